//! Execution through the fake recorder: declared-access checks, culled closures, timer scopes,
//! intra-pass barriers, errors.

use std::cell::Cell;

use ash::vk;
use ash::vk::Handle;
use luz_graph::*;
use vk::AccessFlags2 as A;
use vk::ImageLayout as L;
use vk::PipelineStageFlags2 as S;

use crate::common::*;

#[test]
fn undeclared_access_is_refused() {
    let log = log();
    let mut pool = TransientPool::new();
    let mut factory = FakeFactory::default();
    let mut g = FrameGraph::new();
    let a = g.create_image("a", color(16));
    let b = g.create_image("b", color(16));
    let buf = g.import_buffer("buf", vk::Buffer::null(), 16, None);
    g.pass("make b").write(b, Access::ColorAttachmentWrite);
    g.pass("sneaky")
        .write(a, Access::ColorAttachmentWrite)
        .side_effect()
        .record(move |rc| {
            // Declared: fine.
            let img = rc.image(a)?;
            assert_eq!(
                img.extent,
                vk::Extent2D {
                    width: 16,
                    height: 16
                }
            );
            assert_eq!(img.range.level_count, 1);
            // Not declared: refused, even if the closure swallows the error.
            assert!(matches!(rc.buffer(buf), Err(GraphError::Undeclared { .. })));
            let _ = rc.image(b);
            Ok(())
        });
    g.pass("uses b")
        .read(b, Access::FragmentSampled)
        .side_effect();
    let (r, _) = run(g, &mut pool, &mut factory, &log);
    match r {
        Err(GraphError::Undeclared { pass, resource }) => {
            assert_eq!(pass, "sneaky");
            assert_eq!(resource, "buf");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn undeclared_error_propagates_with_question_mark() {
    let log = log();
    let mut pool = TransientPool::new();
    let mut factory = FakeFactory::default();
    let mut g = FrameGraph::new();
    let a = g.create_image("a", color(16));
    let other = g.create_image("other", color(16));
    g.pass("p")
        .write(a, Access::ColorAttachmentWrite)
        .side_effect()
        .record(move |rc| {
            rc.barrier(other, Access::ColorAttachmentWrite, Access::FragmentSampled)?;
            Ok(())
        });
    g.pass("q")
        .write(other, Access::ColorAttachmentWrite)
        .side_effect();
    let (r, rec) = run(g, &mut pool, &mut factory, &log);
    let e = r.unwrap_err();
    assert!(
        matches!(&e, GraphError::Undeclared { pass: "p", resource } if resource == "other"),
        "{e:?}"
    );
    // Only the graph's own barrier for "a" was recorded, not the refused one.
    assert_eq!(rec.batches.len(), 1);
}

#[test]
fn culled_closures_never_run_and_timers_wrap_live_passes() {
    let log = log();
    let mut pool = TransientPool::new();
    let mut factory = FakeFactory::default();
    let culled_ran = Cell::new(false);
    let mut g = FrameGraph::new();
    let x = g.create_image("x", color(16));
    let unused = g.create_image("unused", color(16));
    let l = log.clone();
    g.pass("produce")
        .write(x, Access::ComputeStorageWrite)
        .record(move |_| {
            l.borrow_mut().push("record produce".into());
            Ok(())
        });
    g.pass("debug view")
        .read(x, Access::FragmentSampled)
        .write(unused, Access::ColorAttachmentWrite)
        .record(|_| {
            culled_ran.set(true);
            Ok(())
        });
    let l = log.clone();
    g.pass("consume")
        .read(x, Access::ComputeStorageRead)
        .side_effect()
        .record(move |_| {
            l.borrow_mut().push("record consume".into());
            Ok(())
        });
    let compiled = g.compile().unwrap();
    let mut rec = FakeRecorder::new(&log);
    let mut timer = FakeTimer {
        log: log.clone(),
        next: 0,
    };
    let report = compiled
        .execute_with(&mut rec, cmd(), &mut pool, &mut factory, Some(&mut timer))
        .unwrap();
    assert!(!culled_ran.get());
    assert_eq!(report.recorded, ["produce", "consume"]);
    assert_eq!(report.culled, ["debug view"]);
    assert_eq!(report.barrier_calls, 2);
    assert_eq!(
        report.images_created, 1,
        "the culled pass's transient is not allocated"
    );
    assert_eq!(
        *log.borrow(),
        [
            "begin produce",
            "barrier 1i 0b 0m",
            "record produce",
            "end Some(0)",
            "begin consume",
            "barrier 1i 0b 0m",
            "record consume",
            "end Some(1)",
        ]
    );
}

#[test]
fn intra_pass_barriers_use_the_declared_range() {
    let log = log();
    let mut pool = TransientPool::new();
    let mut factory = FakeFactory::default();
    let mut g = FrameGraph::new();
    let x = g.import_image(
        "levels",
        imported(50, color(16).mips(4)).before(ImageStateBefore::Keep(Access::ComputeSampled)),
    );
    g.pass("reduce")
        .read_write_range(
            x,
            SubresourceRange::new(1, 2, 0, 1),
            Access::ComputeStorageReadWrite,
        )
        .side_effect()
        .record(move |rc| {
            rc.barrier(x, Access::ComputeStorageWrite, Access::ComputeStorageRead)?;
            rc.memory_barrier(Access::ComputeStorageWrite, Access::ComputeStorageRead);
            let _ = rc.device();
            Ok(())
        });
    let (r, rec) = run(g, &mut pool, &mut factory, &log);
    r.unwrap();
    assert_eq!(rec.batches.len(), 3);
    let graph_barrier = image_barrier(&rec.batches[0], vk::Image::from_raw(50));
    assert_eq!(
        (graph_barrier.old_layout, graph_barrier.new_layout),
        (L::SHADER_READ_ONLY_OPTIMAL, L::GENERAL)
    );
    assert_eq!(graph_barrier.range, SubresourceRange::new(1, 2, 0, 1));
    let own = image_barrier(&rec.batches[1], vk::Image::from_raw(50));
    assert_eq!(
        own,
        ImageBarrier {
            image: vk::Image::from_raw(50),
            aspect: vk::ImageAspectFlags::COLOR,
            range: SubresourceRange::new(1, 2, 0, 1),
            old_layout: L::GENERAL,
            new_layout: L::GENERAL,
            scopes: MemoryBarrier {
                src_stages: S::COMPUTE_SHADER,
                src_access: A::SHADER_STORAGE_WRITE,
                dst_stages: S::COMPUTE_SHADER,
                dst_access: A::SHADER_STORAGE_READ,
            },
        }
    );
    assert_eq!(
        rec.batches[2].memory,
        [MemoryBarrier {
            src_stages: S::COMPUTE_SHADER,
            src_access: A::SHADER_STORAGE_WRITE,
            dst_stages: S::COMPUTE_SHADER,
            dst_access: A::SHADER_STORAGE_READ,
        }]
    );
}

#[derive(Debug)]
struct LuzError(&'static str);

impl std::fmt::Display for LuzError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.0)
    }
}

impl std::error::Error for LuzError {}

#[test]
fn pass_errors_propagate_and_later_passes_do_not_run() {
    let log = log();
    let mut pool = TransientPool::new();
    let mut factory = FakeFactory::default();
    let later = Cell::new(false);
    let state = String::from("borrowed caller state");
    let mut g = FrameGraph::new();
    let x = g.create_image("x", color(16));
    g.pass("fails")
        .write(x, Access::ColorAttachmentWrite)
        .side_effect()
        .record(|_| {
            assert_eq!(state.len(), 21);
            Err(Box::new(LuzError("pipeline missing")))
        });
    g.pass("after").side_effect().record(|_| {
        later.set(true);
        Ok(())
    });
    let (r, _) = run(g, &mut pool, &mut factory, &log);
    match r {
        Err(GraphError::Pass { pass, source }) => {
            assert_eq!(pass, "fails");
            assert_eq!(
                source.downcast_ref::<LuzError>().unwrap().0,
                "pipeline missing"
            );
        }
        other => panic!("{other:?}"),
    }
    assert!(!later.get());
}
