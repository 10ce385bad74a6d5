//! Barrier derivation for each hazard, culling, and declaration errors.

use ash::vk;
use luz_graph::*;
use vk::AccessFlags2 as A;
use vk::ImageLayout as L;
use vk::PipelineStageFlags2 as S;

use crate::common::*;

/// The (old, new, src, dst) of a pass's barriers.
fn summary(plan: &Plan, pass: &str) -> Vec<(L, L, S, A, S, A)> {
    plan.pass(pass)
        .unwrap()
        .barriers
        .iter()
        .map(|b| {
            (
                b.old_layout,
                b.new_layout,
                b.scopes.src_stages,
                b.scopes.src_access,
                b.scopes.dst_stages,
                b.scopes.dst_access,
            )
        })
        .collect()
}

#[test]
fn read_after_read_needs_no_barrier() {
    let mut g = FrameGraph::new();
    let x = g.create_image("x", color(16));
    g.pass("write").write(x, Access::ComputeStorageWrite);
    g.pass("read 1")
        .read(x, Access::FragmentSampled)
        .side_effect();
    g.pass("read 2")
        .read(x, Access::FragmentSampled)
        .side_effect();
    // A different stage in the same layout still needs the write made visible to it.
    g.pass("read 3")
        .read(x, Access::ComputeSampled)
        .side_effect();
    g.pass("read 4")
        .read(x, Access::FragmentSampled)
        .side_effect();
    let c = g.compile().unwrap();
    let p = c.plan();
    assert_eq!(
        summary(p, "read 1"),
        [(
            L::GENERAL,
            L::SHADER_READ_ONLY_OPTIMAL,
            S::COMPUTE_SHADER,
            A::SHADER_STORAGE_WRITE,
            S::FRAGMENT_SHADER,
            A::SHADER_SAMPLED_READ
        )]
    );
    assert_eq!(summary(p, "read 2"), []);
    assert_eq!(
        summary(p, "read 3"),
        [(
            L::SHADER_READ_ONLY_OPTIMAL,
            L::SHADER_READ_ONLY_OPTIMAL,
            S::FRAGMENT_SHADER,
            A::NONE,
            S::COMPUTE_SHADER,
            A::SHADER_SAMPLED_READ
        )]
    );
    assert_eq!(summary(p, "read 4"), []);
}

#[test]
fn write_after_read_waits_for_every_reader() {
    let mut g = FrameGraph::new();
    let x = g.create_image("x", color(16));
    g.pass("write").write(x, Access::ComputeStorageWrite);
    g.pass("compute read")
        .read(x, Access::ComputeStorageRead)
        .side_effect();
    g.pass("fragment read")
        .read(x, Access::FragmentStorageRead)
        .side_effect();
    g.pass("rewrite").write(x, Access::ComputeStorageWrite);
    g.pass("final read")
        .read(x, Access::ComputeStorageRead)
        .side_effect();
    let c = g.compile().unwrap();
    let p = c.plan();
    assert_eq!(
        summary(p, "compute read"),
        [(
            L::GENERAL,
            L::GENERAL,
            S::COMPUTE_SHADER,
            A::SHADER_STORAGE_WRITE,
            S::COMPUTE_SHADER,
            A::SHADER_STORAGE_READ
        )]
    );
    assert_eq!(
        summary(p, "fragment read"),
        [(
            L::GENERAL,
            L::GENERAL,
            S::COMPUTE_SHADER,
            A::SHADER_STORAGE_WRITE,
            S::FRAGMENT_SHADER,
            A::SHADER_STORAGE_READ
        )]
    );
    assert_eq!(
        summary(p, "rewrite"),
        [(
            L::GENERAL,
            L::GENERAL,
            S::COMPUTE_SHADER | S::FRAGMENT_SHADER,
            A::SHADER_STORAGE_WRITE,
            S::COMPUTE_SHADER,
            A::SHADER_STORAGE_WRITE
        )]
    );
}

#[test]
fn write_after_write_and_same_stage_layout_change() {
    let mut g = FrameGraph::new();
    let x = g.create_image("x", color(16));
    let y = g.create_image("y", color(16));
    g.pass("clear").write(x, Access::ColorAttachmentWrite);
    g.pass("blend")
        .read_write(x, Access::ColorAttachmentReadWrite)
        .side_effect();
    g.pass("compute").write(y, Access::ComputeStorageWrite);
    g.pass("sample")
        .read(y, Access::ComputeSampled)
        .side_effect();
    let c = g.compile().unwrap();
    let p = c.plan();
    assert_eq!(
        summary(p, "blend"),
        [(
            L::COLOR_ATTACHMENT_OPTIMAL,
            L::COLOR_ATTACHMENT_OPTIMAL,
            S::COLOR_ATTACHMENT_OUTPUT,
            A::COLOR_ATTACHMENT_WRITE,
            S::COLOR_ATTACHMENT_OUTPUT,
            A::COLOR_ATTACHMENT_READ | A::COLOR_ATTACHMENT_WRITE
        )]
    );
    assert_eq!(
        summary(p, "sample"),
        [(
            L::GENERAL,
            L::SHADER_READ_ONLY_OPTIMAL,
            S::COMPUTE_SHADER,
            A::SHADER_STORAGE_WRITE,
            S::COMPUTE_SHADER,
            A::SHADER_SAMPLED_READ
        )]
    );
}

#[test]
fn mip_chain_tracks_each_mip() {
    // The IBL bake: one pass per mip reads the mip above and writes its own; the cube is
    // imported and left sampled.
    let mut g = FrameGraph::new();
    let cube = g.import_image(
        "prefiltered",
        imported(7, color(64).layers(6).mips(3)).after(Access::FragmentSampled),
    );
    g.pass("mip 0").write_range(
        cube,
        SubresourceRange::new(0, 1, 0, 6),
        Access::ComputeStorageWrite,
    );
    for (name, m) in [("mip 1", 1), ("mip 2", 2)] {
        g.pass(name)
            .read_range(
                cube,
                SubresourceRange::new(m - 1, 1, 0, 6),
                Access::ComputeSampled,
            )
            .write_range(
                cube,
                SubresourceRange::new(m, 1, 0, 6),
                Access::ComputeStorageWrite,
            );
    }
    let c = g.compile().unwrap();
    let p = c.plan();
    assert_eq!(p.live_passes(), ["mip 0", "mip 1", "mip 2"]);
    let b = &p.pass("mip 1").unwrap().barriers;
    assert_eq!(b.len(), 2);
    assert_eq!(b[0].range, Some(SubresourceRange::new(0, 1, 0, 6)));
    assert_eq!(
        (b[0].old_layout, b[0].new_layout),
        (L::GENERAL, L::SHADER_READ_ONLY_OPTIMAL)
    );
    assert_eq!(b[1].range, Some(SubresourceRange::new(1, 1, 0, 6)));
    assert_eq!(
        (b[1].old_layout, b[1].new_layout),
        (L::UNDEFINED, L::GENERAL)
    );
    // At the end: mips 0-1 (already sampled by compute) made visible to fragment sampling, mip 2
    // transitioned from storage.
    let f = &p.final_barriers;
    assert_eq!(f.len(), 2);
    assert_eq!(f[0].range, Some(SubresourceRange::new(0, 2, 0, 6)));
    assert_eq!(
        (
            f[0].old_layout,
            f[0].scopes.src_stages,
            f[0].scopes.src_access
        ),
        (L::SHADER_READ_ONLY_OPTIMAL, S::COMPUTE_SHADER, A::NONE)
    );
    assert_eq!(f[1].range, Some(SubresourceRange::new(2, 1, 0, 6)));
    assert_eq!(
        (f[1].old_layout, f[1].new_layout, f[1].scopes.src_access),
        (
            L::GENERAL,
            L::SHADER_READ_ONLY_OPTIMAL,
            A::SHADER_STORAGE_WRITE
        )
    );
}

#[test]
fn unread_passes_are_culled_transitively() {
    let mut g = FrameGraph::new();
    let a = g.create_image("a", color(16));
    let b = g.create_image("b", color(16));
    let c = g.create_image("c", color(16));
    let kept = g.create_image("kept", color(16));
    g.pass("make a").write(a, Access::ColorAttachmentWrite);
    g.pass("a to b")
        .read(a, Access::FragmentSampled)
        .write(b, Access::ColorAttachmentWrite);
    g.pass("b to c")
        .read(b, Access::FragmentSampled)
        .write(c, Access::ColorAttachmentWrite);
    g.pass("make kept").write(kept, Access::ComputeStorageWrite);
    // Overwritten before anyone reads it: the earlier write is dead.
    g.pass("dead write")
        .write(kept, Access::ComputeStorageWrite);
    g.pass("rewrite kept")
        .write(kept, Access::ComputeStorageWrite);
    g.pass("use kept")
        .read(kept, Access::ComputeStorageRead)
        .side_effect();
    let compiled = g.compile().unwrap();
    let p = compiled.plan();
    assert_eq!(p.live_passes(), ["rewrite kept", "use kept"]);
    assert_eq!(
        p.culled_passes(),
        ["make a", "a to b", "b to c", "make kept", "dead write"]
    );
    assert!(p.pass("make a").unwrap().barriers.is_empty());
    assert_eq!(p.images[a.index()].lifetime, None);
}

#[test]
fn present_and_readback_keep_their_producers() {
    let mut g = FrameGraph::new();
    let hdr = g.create_image("hdr", color(16));
    let swap = g.import_image("swapchain", imported(9, color(16)).after(Access::Present));
    let buf = g.import_buffer("readback", vk::Buffer::null(), 1024, None);
    g.buffer_after(buf, Access::HostRead);
    let ui_only = g.create_image("ui", color(16));
    g.pass("draw").write(hdr, Access::ColorAttachmentWrite);
    g.pass("to swapchain")
        .read(hdr, Access::FragmentSampled)
        .write(swap, Access::ColorAttachmentWrite);
    g.pass("copy").write(buf, Access::TransferDst);
    g.pass("ui").write(ui_only, Access::ColorAttachmentWrite);
    g.pass("ui side effect")
        .write(ui_only, Access::ColorAttachmentWrite)
        .side_effect();
    let c = g.compile().unwrap();
    assert_eq!(
        c.plan().live_passes(),
        ["draw", "to swapchain", "copy", "ui side effect"]
    );
}

#[test]
fn reading_a_transient_before_any_write_is_an_error() {
    let mut g = FrameGraph::new();
    let x = g.create_image("lonely", color(16));
    g.pass("early reader")
        .read(x, Access::FragmentSampled)
        .side_effect();
    g.pass("late writer").write(x, Access::ColorAttachmentWrite);
    let e = g.compile().err().expect("an error");
    assert!(
        matches!(&e, GraphError::ReadBeforeWrite { pass: "early reader", resource } if resource == "lonely"),
        "{e:?}"
    );
    let msg = e.to_string();
    assert!(
        msg.contains("early reader") && msg.contains("lonely"),
        "{msg}"
    );

    // Part of an image: mip 1 is read but only mip 0 was written.
    let mut g = FrameGraph::new();
    let m = g.create_image("mips", color(16).mips(2));
    g.pass("w")
        .write_range(m, SubresourceRange::mip(0), Access::ComputeStorageWrite);
    g.pass("r")
        .read_range(m, SubresourceRange::mip(1), Access::ComputeSampled)
        .side_effect();
    assert!(matches!(
        g.compile(),
        Err(GraphError::ReadBeforeWrite { pass: "r", .. })
    ));

    // Imported without kept contents: same.
    let mut g = FrameGraph::new();
    let i = g.import_image(
        "swap",
        imported(1, color(4)).before(ImageStateBefore::Discard(Access::Present)),
    );
    g.pass("blend")
        .read_write(i, Access::ColorAttachmentReadWrite)
        .side_effect();
    assert!(matches!(
        g.compile(),
        Err(GraphError::ReadBeforeWrite { pass: "blend", .. })
    ));
}

#[test]
fn malformed_declarations_are_errors() {
    let mut g = FrameGraph::new();
    let x = g.create_image("x", color(16));
    g.pass("bad")
        .read(x, Access::ComputeStorageWrite)
        .side_effect();
    assert!(matches!(
        g.compile(),
        Err(GraphError::InvalidUse { pass: "bad", .. })
    ));

    let mut g = FrameGraph::new();
    let x = g.create_image("x", color(16));
    g.pass("bad")
        .write(x, Access::FragmentSampled)
        .side_effect();
    assert!(matches!(g.compile(), Err(GraphError::InvalidUse { .. })));

    let mut g = FrameGraph::new();
    let x = g.create_image("x", color(16));
    g.pass("bad")
        .write(x, Access::ComputeStorageBufferWrite)
        .side_effect();
    assert!(matches!(g.compile(), Err(GraphError::InvalidUse { .. })));

    let mut g = FrameGraph::new();
    let x = g.create_image("x", color(16).layers(2));
    g.pass("bad")
        .write_range(
            x,
            SubresourceRange::layers(1, 2),
            Access::ColorAttachmentWrite,
        )
        .side_effect();
    assert!(matches!(g.compile(), Err(GraphError::InvalidUse { .. })));

    let mut g = FrameGraph::new();
    let x = g.create_image("x", color(16));
    g.pass("w").write(x, Access::ColorAttachmentWrite);
    g.pass("bad")
        .read(x, Access::FragmentSampled)
        .read(x, Access::ComputeStorageRead)
        .side_effect();
    assert!(matches!(
        g.compile(),
        Err(GraphError::ConflictingAccess {
            first: "FragmentSampled",
            second: "ComputeStorageRead",
            ..
        })
    ));

    // A handle from another graph.
    let mut other = FrameGraph::new();
    other.create_image("a", color(1));
    let foreign = other.create_image("b", color(1));
    let mut g = FrameGraph::new();
    g.pass("bad")
        .write(foreign, Access::ColorAttachmentWrite)
        .side_effect();
    assert!(matches!(g.compile(), Err(GraphError::InvalidHandle { .. })));
}

#[test]
fn same_layout_uses_in_one_pass_merge() {
    let mut g = FrameGraph::new();
    let x = g.create_image("x", color(16));
    g.pass("w").write(x, Access::ComputeStorageWrite);
    g.pass("both")
        .read(x, Access::FragmentSampled)
        .read(x, Access::ComputeSampled)
        .side_effect();
    let c = g.compile().unwrap();
    assert_eq!(
        summary(c.plan(), "both"),
        [(
            L::GENERAL,
            L::SHADER_READ_ONLY_OPTIMAL,
            S::COMPUTE_SHADER,
            A::SHADER_STORAGE_WRITE,
            S::FRAGMENT_SHADER | S::COMPUTE_SHADER,
            A::SHADER_SAMPLED_READ
        )]
    );
}
