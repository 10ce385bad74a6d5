//! GPU timestamps around passes (honouring `timestampValidBits` and `timestampPeriod`).

use std::sync::Arc;

use ash::vk;

use super::{Context, VkError};

/// A query pool holding a begin and end timestamp for up to `capacity` passes per frame.
pub struct GpuTimer {
    pool: vk::QueryPool,
    capacity: u32,
    names: Vec<&'static str>,
    valid_mask: u64,
    period_ns: f64,
    ctx: Arc<Context>,
}

impl GpuTimer {
    pub fn new(ctx: &Arc<Context>, capacity: u32) -> Result<Option<Self>, VkError> {
        let bits = ctx.info.timestamp_valid_bits;
        if bits == 0 || ctx.info.timestamp_period_ns <= 0.0 {
            return Ok(None);
        }
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(capacity * 2);
        // SAFETY: `info` is a local that outlives the call; the device's queue family has
        // timestamp support (`bits` != 0, checked above). Callers pass a non-zero `capacity` (8),
        // so the query count is positive.
        let pool = unsafe { ctx.device.create_query_pool(&info, None) }?;
        ctx.set_name(pool, "luz timestamps");
        Ok(Some(Self {
            pool,
            capacity,
            names: Vec::new(),
            valid_mask: if bits >= 64 {
                u64::MAX
            } else {
                (1u64 << bits) - 1
            },
            period_ns: ctx.info.timestamp_period_ns as f64,
            ctx: ctx.clone(),
        }))
    }

    /// Resets the pool for a new frame; call outside a render pass.
    pub fn reset(&mut self, cmd: vk::CommandBuffer) {
        self.names.clear();
        // SAFETY: `self.pool` is a live pool of this device with `capacity * 2` queries, so the
        // range is in bounds. The caller passes `cmd` in the recording state, outside a render pass
        // (VUID-vkCmdResetQueryPool-renderpass), with no pending submission still using these
        // queries (it waited for the previous frame's fence) — the contract of this method.
        unsafe {
            self.ctx
                .device
                .cmd_reset_query_pool(cmd, self.pool, 0, self.capacity * 2)
        };
    }

    /// Starts timing the pass `name`; returns its slot, or None when the pool is full.
    pub fn begin(&mut self, cmd: vk::CommandBuffer, name: &'static str) -> Option<u32> {
        let slot = self.names.len() as u32;
        if slot >= self.capacity {
            return None;
        }
        self.names.push(name);
        // SAFETY: `slot < capacity` (checked above), so query `slot * 2` exists in `self.pool`; it
        // was reset by `reset` earlier in this frame (`names` counts writes since then). The caller
        // passes `cmd` in the recording state, the one `reset` recorded into.
        unsafe {
            self.ctx.device.cmd_write_timestamp2(
                cmd,
                vk::PipelineStageFlags2::TOP_OF_PIPE,
                self.pool,
                slot * 2,
            )
        };
        Some(slot)
    }

    pub fn end(&mut self, cmd: vk::CommandBuffer, slot: Option<u32>) {
        let Some(slot) = slot else { return };
        // SAFETY: `slot` came from `begin`, so `slot < capacity` and query `slot * 2 + 1` exists and
        // was reset with the others; the caller passes `cmd` in the recording state.
        unsafe {
            self.ctx.device.cmd_write_timestamp2(
                cmd,
                vk::PipelineStageFlags2::BOTTOM_OF_PIPE,
                self.pool,
                slot * 2 + 1,
            )
        };
    }

    /// Milliseconds per pass for the frame last recorded (after its fence has signalled).
    pub fn read(&self) -> Result<Vec<(&'static str, f64)>, VkError> {
        let n = self.names.len();
        if n == 0 {
            return Ok(Vec::new());
        }
        let mut data = vec![0u64; n * 2];
        // SAFETY: `data` holds exactly the 2·n 64-bit results asked for (ash derives the query count
        // and stride from the slice and TYPE_64), and n ≤ capacity, so queries 0..2n exist in
        // `self.pool`. All of them were written by the frame last recorded, which the caller has
        // submitted and waited for, so WAIT returns.
        unsafe {
            self.ctx.device.get_query_pool_results(
                self.pool,
                0,
                &mut data,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }?;
        Ok(self
            .names
            .iter()
            .enumerate()
            .map(|(i, name)| {
                let a = data[2 * i] & self.valid_mask;
                let b = data[2 * i + 1] & self.valid_mask;
                let ticks = b.wrapping_sub(a) & self.valid_mask;
                (*name, ticks as f64 * self.period_ns / 1e6)
            })
            .collect())
    }
}

impl Drop for GpuTimer {
    fn drop(&mut self) {
        // SAFETY: `self.pool` was created from `self.ctx.device` (alive through `self.ctx`) and is
        // destroyed only here; its owner (`Headless`, the viewer) waits for the device to go idle
        // before dropping it, so no submitted command uses it (VUID-vkDestroyQueryPool-queryPool-00793).
        unsafe { self.ctx.device.destroy_query_pool(self.pool, None) };
    }
}
