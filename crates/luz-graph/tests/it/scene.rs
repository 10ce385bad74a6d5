//! luz's forward frame: shadow -> forward -> saturate -> display -> readback, with the exact
//! barriers of each pass.

use ash::vk;
use ash::vk::Handle;
use luz_graph::*;
use vk::AccessFlags2 as A;
use vk::ImageLayout as L;
use vk::PipelineStageFlags2 as S;

use crate::common::*;

pub struct Scene {
    pub shadow: ImageHandle,
    pub hdr: ImageHandle,
    pub depth: ImageHandle,
    pub swapchain: ImageHandle,
    pub readback: BufferHandle,
}

pub const TESTS: S =
    S::from_raw(S::EARLY_FRAGMENT_TESTS.as_raw() | S::LATE_FRAGMENT_TESTS.as_raw());
pub const DS_RW: A = A::from_raw(
    A::DEPTH_STENCIL_ATTACHMENT_READ.as_raw() | A::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw(),
);

/// Declares the frame (with no-op closures).
pub fn declare(g: &mut FrameGraph<'_>) -> Scene {
    let shadow = g.import_image(
        "shadow maps",
        imported(
            100,
            ImageDesc::depth(1024, 1024, vk::Format::D32_SFLOAT).layers(4),
        )
        .before(ImageStateBefore::Keep(Access::FragmentSampled)),
    );
    let hdr = g.create_image(
        "hdr color",
        ImageDesc::color(64, 48, vk::Format::R32G32B32A32_SFLOAT),
    );
    let depth = g.create_image("depth", ImageDesc::depth(64, 48, vk::Format::D32_SFLOAT));
    let swapchain = g.import_image(
        "swapchain",
        imported(200, ImageDesc::color(64, 48, vk::Format::B8G8R8A8_SRGB))
            .before(ImageStateBefore::Discard(Access::ColorAttachmentWrite))
            .after(Access::Present),
    );
    let readback = g.import_buffer(
        "readback",
        vk::Buffer::from_raw(300),
        64 * 48 * 16,
        Some(Access::HostRead),
    );
    g.buffer_after(readback, Access::HostRead);

    g.pass("shadow")
        .write_range(
            shadow,
            SubresourceRange::layers(0, 2),
            Access::DepthAttachmentWrite,
        )
        .record(|_| Ok(()));
    g.pass("forward")
        .read(shadow, Access::FragmentSampled)
        .write(hdr, Access::ColorAttachmentWrite)
        .write(depth, Access::DepthAttachmentWrite)
        .record(|_| Ok(()));
    g.pass("saturate")
        .read_write(hdr, Access::ComputeStorageReadWrite)
        .record(|_| Ok(()));
    g.pass("display")
        .read(hdr, Access::FragmentSampled)
        .write(swapchain, Access::ColorAttachmentWrite)
        .record(|_| Ok(()));
    g.pass("readback")
        .read(hdr, Access::TransferSrc)
        .write(readback, Access::TransferDst)
        .side_effect()
        .record(|_| Ok(()));
    Scene {
        shadow,
        hdr,
        depth,
        swapchain,
        readback,
    }
}

#[allow(clippy::too_many_arguments)]
fn bi(
    name: &str,
    handle: impl Into<Resource>,
    old: L,
    new: L,
    src: (S, A),
    dst: (S, A),
    range: Option<SubresourceRange>,
    pool: bool,
) -> BarrierInfo {
    BarrierInfo {
        resource: name.to_string(),
        handle: handle.into(),
        old_layout: old,
        new_layout: new,
        scopes: MemoryBarrier {
            src_stages: src.0,
            src_access: src.1,
            dst_stages: dst.0,
            dst_access: dst.1,
        },
        range,
        after_pool_use: pool,
    }
}

#[test]
fn forward_frame_barriers_are_exact() {
    let mut g = FrameGraph::new();
    let s = declare(&mut g);
    let compiled = g.compile().unwrap();
    let plan = compiled.plan();
    assert_eq!(
        plan.live_passes(),
        ["shadow", "forward", "saturate", "display", "readback"]
    );
    let whole = Some(SubresourceRange::whole(1, 1));
    let none = (S::NONE, A::NONE);

    // shadow: layers 0-1 of the kept shadow array from sampled to depth attachment (WAR on the
    // previous frame's fragment sampling; contents kept, so not from UNDEFINED).
    assert_eq!(
        plan.pass("shadow").unwrap().barriers,
        [bi(
            "shadow maps",
            s.shadow,
            L::SHADER_READ_ONLY_OPTIMAL,
            L::DEPTH_ATTACHMENT_OPTIMAL,
            (S::FRAGMENT_SHADER, A::NONE),
            (TESTS, DS_RW),
            Some(SubresourceRange::layers(0, 2)),
            false,
        )]
    );

    // forward: layers 0-1 back to sampled (RAW on depth writes); layers 2-3 need nothing; hdr and
    // depth start from UNDEFINED after their pooled image's previous use.
    assert_eq!(
        plan.pass("forward").unwrap().barriers,
        [
            bi(
                "shadow maps",
                s.shadow,
                L::DEPTH_ATTACHMENT_OPTIMAL,
                L::SHADER_READ_ONLY_OPTIMAL,
                (TESTS, A::DEPTH_STENCIL_ATTACHMENT_WRITE),
                (S::FRAGMENT_SHADER, A::SHADER_SAMPLED_READ),
                Some(SubresourceRange::layers(0, 2)),
                false,
            ),
            bi(
                "hdr color",
                s.hdr,
                L::UNDEFINED,
                L::COLOR_ATTACHMENT_OPTIMAL,
                none,
                (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
                whole,
                true,
            ),
            bi(
                "depth",
                s.depth,
                L::UNDEFINED,
                L::DEPTH_ATTACHMENT_OPTIMAL,
                none,
                (TESTS, DS_RW),
                whole,
                true,
            ),
        ]
    );

    assert_eq!(
        plan.pass("saturate").unwrap().barriers,
        [bi(
            "hdr color",
            s.hdr,
            L::COLOR_ATTACHMENT_OPTIMAL,
            L::GENERAL,
            (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
            (
                S::COMPUTE_SHADER,
                A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE
            ),
            whole,
            false,
        )]
    );

    assert_eq!(
        plan.pass("display").unwrap().barriers,
        [
            bi(
                "hdr color",
                s.hdr,
                L::GENERAL,
                L::SHADER_READ_ONLY_OPTIMAL,
                (S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE),
                (S::FRAGMENT_SHADER, A::SHADER_SAMPLED_READ),
                whole,
                false,
            ),
            bi(
                "swapchain",
                s.swapchain,
                L::UNDEFINED,
                L::COLOR_ATTACHMENT_OPTIMAL,
                (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
                (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
                whole,
                false,
            ),
        ]
    );

    // readback: hdr to TRANSFER_SRC after the fragment reads; the buffer waits for the host's
    // read of the previous contents (WAR).
    assert_eq!(
        plan.pass("readback").unwrap().barriers,
        [
            bi(
                "hdr color",
                s.hdr,
                L::SHADER_READ_ONLY_OPTIMAL,
                L::TRANSFER_SRC_OPTIMAL,
                (S::FRAGMENT_SHADER, A::NONE),
                (S::COPY, A::TRANSFER_READ),
                whole,
                false,
            ),
            bi(
                "readback",
                s.readback,
                L::UNDEFINED,
                L::UNDEFINED,
                (S::HOST, A::NONE),
                (S::COPY, A::TRANSFER_WRITE),
                None,
                false,
            ),
        ]
    );

    assert_eq!(
        plan.final_barriers,
        [
            bi(
                "swapchain",
                s.swapchain,
                L::COLOR_ATTACHMENT_OPTIMAL,
                L::PRESENT_SRC_KHR,
                (S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
                none,
                whole,
                false,
            ),
            bi(
                "readback",
                s.readback,
                L::UNDEFINED,
                L::UNDEFINED,
                (S::COPY, A::TRANSFER_WRITE),
                (S::HOST, A::HOST_READ),
                None,
                false,
            ),
        ]
    );

    // What the shadow maps' next import starts from: layers 0-1 and 2-3 all end sampled.
    assert_eq!(
        plan.end_state(s.shadow),
        Some(ImageStateBefore::Keep(Access::Custom {
            name: "last use",
            layout: L::SHADER_READ_ONLY_OPTIMAL,
            stages: S::FRAGMENT_SHADER,
            access: A::NONE,
            writes: false,
        }))
    );
    assert_eq!(plan.end_state(s.hdr), None);

    // The transients' usage was completed from their accesses.
    let hdr = &plan.images[s.hdr.index()];
    assert_eq!(
        hdr.desc.usage,
        vk::ImageUsageFlags::COLOR_ATTACHMENT
            | vk::ImageUsageFlags::STORAGE
            | vk::ImageUsageFlags::SAMPLED
            | vk::ImageUsageFlags::TRANSFER_SRC
    );
    assert_eq!(hdr.lifetime, Some((1, 4)));
    assert_eq!(hdr.final_scope, (S::COPY, A::NONE));
    let depth = &plan.images[s.depth.index()];
    assert_eq!(
        depth.final_scope,
        (TESTS, A::DEPTH_STENCIL_ATTACHMENT_WRITE)
    );
}

#[test]
fn transient_first_use_waits_for_previous_frame() {
    let log = log();
    let mut pool = TransientPool::new();
    let mut factory = FakeFactory::default();

    let mut g = FrameGraph::new();
    let s = declare(&mut g);
    let (r, rec1) = run(g, &mut pool, &mut factory, &log);
    let r = r.unwrap();
    assert_eq!(r.images_created, 2);
    assert_eq!(factory.created.len(), 2);
    // Frame 1: a new image has no previous use.
    let hdr_image = pool
        .images()
        .find(|(d, _)| d.format == vk::Format::R32G32B32A32_SFLOAT)
        .map(|(_, i)| vk::Image::from_raw(i.id))
        .unwrap();
    let b = image_barrier(&rec1.batches[1], hdr_image);
    assert_eq!(
        (b.old_layout, b.scopes.src_stages, b.scopes.src_access),
        (L::UNDEFINED, S::NONE, A::NONE)
    );

    // Frame 2: same images, first barrier waits for frame 1's last uses.
    let mut g = FrameGraph::new();
    let s2 = declare(&mut g);
    assert_eq!(s2.hdr, s.hdr);
    let (r, rec2) = run(g, &mut pool, &mut factory, &log);
    let r = r.unwrap();
    assert_eq!((r.images_created, r.images_reused), (0, 2));
    assert_eq!(factory.created.len(), 2);
    let forward = &rec2.batches[1];
    let b = image_barrier(forward, hdr_image);
    assert_eq!(b.old_layout, L::UNDEFINED);
    assert_eq!(b.new_layout, L::COLOR_ATTACHMENT_OPTIMAL);
    assert_eq!(
        (b.scopes.src_stages, b.scopes.src_access),
        (S::COPY, A::NONE)
    );
    let depth_image = pool
        .images()
        .find(|(d, _)| d.format == vk::Format::D32_SFLOAT)
        .map(|(_, i)| vk::Image::from_raw(i.id))
        .unwrap();
    let b = image_barrier(forward, depth_image);
    assert_eq!(b.old_layout, L::UNDEFINED);
    assert_eq!(
        (b.scopes.src_stages, b.scopes.src_access),
        (TESTS, A::DEPTH_STENCIL_ATTACHMENT_WRITE)
    );
    // Imported images keep their handles and absolute ranges.
    let b = image_barrier(&rec2.batches[0], vk::Image::from_raw(100));
    assert_eq!(b.range, SubresourceRange::layers(0, 2));
    assert_eq!(b.aspect, vk::ImageAspectFlags::DEPTH);
}

#[test]
fn kept_import_is_never_transitioned_from_undefined() {
    let mut g = FrameGraph::new();
    let s = declare(&mut g);
    let ibl = g.import_image(
        "ibl cube",
        imported(400, color(32).layers(6).mips(3))
            .before(ImageStateBefore::Keep(Access::FragmentSampled)),
    );
    let out = g.create_image("out", color(8));
    g.pass("sample ibl")
        .read(ibl, Access::FragmentSampled)
        .write(out, Access::ColorAttachmentWrite)
        .side_effect();
    g.pass("rebake")
        .write(ibl, Access::ComputeStorageWrite)
        .side_effect();
    let plan = g.compile().unwrap().plan().clone();
    // Sampling in the kept layout needs nothing.
    assert!(plan
        .pass("sample ibl")
        .unwrap()
        .barriers
        .iter()
        .all(|b| b.handle != Resource::Image(ibl)));
    // Rewriting it waits for the sampling and keeps the layout chain.
    let b = &plan.pass("rebake").unwrap().barriers;
    assert_eq!(b.len(), 1);
    assert_eq!(b[0].old_layout, L::SHADER_READ_ONLY_OPTIMAL);
    assert_eq!(b[0].new_layout, L::GENERAL);
    assert_eq!(b[0].scopes.src_stages, S::FRAGMENT_SHADER);
    assert_eq!(b[0].range, Some(SubresourceRange::new(0, 3, 0, 6)));
    for p in &plan.passes {
        for b in &p.barriers {
            if b.handle == Resource::Image(s.shadow) || b.handle == Resource::Image(ibl) {
                assert_ne!(b.old_layout, L::UNDEFINED, "{b:?}");
            }
        }
    }
}
