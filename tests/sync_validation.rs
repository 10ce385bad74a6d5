//! Synchronization validation is really on when asked for: a deliberate write-after-write hazard
//! (two fills of one buffer with no barrier between them) is reported, and the same commands with
//! a barrier are not. `scripts/test.sh` runs every GPU test with `LUZ_SYNC_VALIDATION=1`, so a
//! hazard anywhere in luz fails the test that recorded it.

mod common;

use gpu_allocator::MemoryLocation;
use luz::vk::cmd::CommandPool;
use luz::vk::{Buffer, Context};

use ash::vk;

use common::gpu_with;

fn fill_twice(ctx: &std::sync::Arc<Context>, barrier: bool) {
    let pool = CommandPool::new(ctx, "sync test").unwrap();
    let buffer = Buffer::new(
        ctx,
        "sync test buffer",
        256,
        vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuOnly,
    )
    .unwrap();
    let d = ctx.device.clone();
    pool.one_shot(|cmd| {
        // SAFETY: `cmd` is recording (inside `one_shot`); the buffer is live, has TRANSFER_DST
        // usage and 256 bytes, a multiple of 4 from offset 0.
        unsafe { d.cmd_fill_buffer(cmd, buffer.raw, 0, 256, 1) };
        if barrier {
            luz::vk::cmd::memory_barrier(
                &d,
                cmd,
                (
                    vk::PipelineStageFlags2::ALL_TRANSFER,
                    vk::AccessFlags2::TRANSFER_WRITE,
                ),
                (
                    vk::PipelineStageFlags2::ALL_TRANSFER,
                    vk::AccessFlags2::TRANSFER_WRITE,
                ),
            );
        }
        // SAFETY: as for the first fill; the hazard between the two (without the barrier) is what
        // this test wants the validation layer to report, not undefined behaviour on the host.
        unsafe { d.cmd_fill_buffer(cmd, buffer.raw, 0, 256, 2) };
        Ok(())
    })
    .unwrap();
}

#[test]
fn a_missing_barrier_is_reported_only_with_sync_validation() {
    let ctx = gpu_with(true);
    fill_twice(&ctx, true);
    assert_eq!(
        ctx.validation_log().errors(),
        0,
        "{:?}",
        ctx.validation_log().messages()
    );
    fill_twice(&ctx, false);
    let messages = ctx.validation_log().messages();
    assert!(
        ctx.validation_log().errors() > 0 && messages.iter().any(|m| m.contains("HAZARD")),
        "sync validation did not see the write-after-write hazard: {messages:?}"
    );
    // Without synchronization validation the core layer does not see it.
    let plain = gpu_with(false);
    fill_twice(&plain, false);
    assert_eq!(plain.validation_log().errors(), 0);
}

#[test]
fn a_leaked_allocation_is_reported_when_the_device_goes() {
    let ctx = gpu_with(false);
    let log = ctx.instance.log.clone();
    let leaked = Buffer::new(
        &ctx,
        "deliberately leaked",
        1024,
        vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuOnly,
    )
    .unwrap();
    // The buffer's Arc keeps the context alive: leak it, then drop the last other handle.
    std::mem::forget(leaked);
    let raw = std::sync::Arc::into_raw(ctx);
    // SAFETY: `raw` came from Arc::into_raw just above; the forgotten buffer still holds one count,
    // so take the count down to zero explicitly to run the context's Drop.
    unsafe {
        std::sync::Arc::decrement_strong_count(raw);
        std::sync::Arc::from_raw(raw);
    }
    let messages = log.messages();
    assert!(
        messages
            .iter()
            .any(|m| m.contains("gpu-allocator") && m.contains("deliberately leaked")),
        "{messages:?}"
    );
    // The validation layer's object tracking reports the VkBuffer itself too.
    assert!(log.errors() >= 1);
}
