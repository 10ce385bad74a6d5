//! The transient pool: reuse across frames, aliasing within a frame, release of unused images.

use ash::vk;
use luz_graph::*;
use vk::AccessFlags2 as A;
use vk::ImageLayout as L;
use vk::PipelineStageFlags2 as S;

use crate::common::*;

#[test]
fn non_overlapping_transients_share_an_image() {
    let log = log();
    let mut pool = TransientPool::new();
    let mut factory = FakeFactory::default();
    let mut g = FrameGraph::new();
    // The graph adds the usage each access needs; equal usage makes equal descriptions.
    let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT
        | vk::ImageUsageFlags::SAMPLED
        | vk::ImageUsageFlags::STORAGE;
    let a = g.create_image("a", color(32).usage(usage));
    let b = g.create_image("b", color(32).usage(usage));
    g.pass("write a").write(a, Access::ColorAttachmentWrite);
    g.pass("read a")
        .read(a, Access::FragmentSampled)
        .side_effect();
    g.pass("write b").write(b, Access::ComputeStorageWrite);
    g.pass("read b")
        .read(b, Access::ComputeStorageRead)
        .side_effect();
    let (r, rec) = run(g, &mut pool, &mut factory, &log);
    let r = r.unwrap();
    assert_eq!((r.images_created, r.images_reused), (1, 1));
    assert_eq!(pool.len(), 1);
    // b's first barrier waits for a's last use (fragment sampling) on the shared image.
    let shared = rec.batches[0].images[0].image;
    let first_b = image_barrier(&rec.batches[2], shared);
    assert_eq!(first_b.old_layout, L::UNDEFINED);
    assert_eq!(first_b.new_layout, L::GENERAL);
    assert_eq!(
        (first_b.scopes.src_stages, first_b.scopes.src_access),
        (S::FRAGMENT_SHADER, A::NONE)
    );
}

#[test]
fn overlapping_transients_get_their_own_images() {
    let log = log();
    let mut pool = TransientPool::new();
    let mut factory = FakeFactory::default();
    let mut g = FrameGraph::new();
    let a = g.create_image("a", color(32));
    let b = g.create_image("b", color(32));
    let c = g.create_image("c", color(64));
    g.pass("write a").write(a, Access::ColorAttachmentWrite);
    g.pass("write b").write(b, Access::ColorAttachmentWrite);
    g.pass("write c").write(c, Access::ColorAttachmentWrite);
    g.pass("read all")
        .read(a, Access::FragmentSampled)
        .read(b, Access::FragmentSampled)
        .read(c, Access::FragmentSampled)
        .side_effect();
    let (r, _) = run(g, &mut pool, &mut factory, &log);
    assert_eq!(r.unwrap().images_created, 3);
    assert_eq!(pool.len(), 3);
}

#[test]
fn unused_images_are_released() {
    let log = log();
    let mut pool = TransientPool::with_max_unused(2);
    let mut factory = FakeFactory::default();
    let frame = |pool: &mut TransientPool<FakeFactory>, factory: &mut FakeFactory, size: u32| {
        let mut g = FrameGraph::new();
        let x = g.create_image("x", color(size));
        g.pass("w").write(x, Access::ColorAttachmentWrite);
        g.pass("r").read(x, Access::FragmentSampled).side_effect();
        run(g, pool, factory, &log).0.unwrap()
    };
    assert_eq!(frame(&mut pool, &mut factory, 8).images_created, 1);
    assert_eq!(frame(&mut pool, &mut factory, 8).images_reused, 1);
    // The size changes (a resize): the old image idles, then goes.
    let r = frame(&mut pool, &mut factory, 16);
    assert_eq!((r.images_created, r.images_released), (1, 0));
    assert_eq!(pool.len(), 2);
    let r = frame(&mut pool, &mut factory, 16);
    assert_eq!(r.images_released, 1);
    assert_eq!(pool.len(), 1);
    assert_eq!(pool.images().next().unwrap().0.width, 16);
    assert_eq!(pool.generation(), 4);
}

#[test]
fn one_pool_serves_several_graphs() {
    // A bake graph then a frame graph: the second graph's first use waits for the first's last.
    let log = log();
    let mut pool = TransientPool::new();
    let mut factory = FakeFactory::default();
    let mut g = FrameGraph::new();
    let both = vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::COLOR_ATTACHMENT;
    let x = g.create_image("scratch", color(8).usage(both));
    g.pass("bake")
        .write(x, Access::ComputeStorageWrite)
        .side_effect();
    run(g, &mut pool, &mut factory, &log).0.unwrap();
    let mut g = FrameGraph::new();
    let y = g.create_image("target", color(8).usage(both));
    g.pass("draw")
        .write(y, Access::ColorAttachmentWrite)
        .side_effect();
    let (r, rec) = run(g, &mut pool, &mut factory, &log);
    assert_eq!(r.unwrap().images_reused, 1);
    let b = rec.batches[0].images[0];
    assert_eq!(
        (b.scopes.src_stages, b.scopes.src_access),
        (S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE)
    );
}
