//! Buffers with their memory, freed on drop.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::{Context, VkError};

/// A buffer and its allocation. Host-visible buffers are persistently mapped.
pub struct Buffer {
    pub raw: vk::Buffer,
    pub size: u64,
    allocation: Option<Allocation>,
    ctx: Arc<Context>,
}

impl Buffer {
    pub fn new(
        ctx: &Arc<Context>,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<Self, VkError> {
        let size = size.max(4);
        let limits = ctx.limits();
        limits.check_buffer(name, size)?;
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: `info` is a local that outlives the call; its size is non-zero (at least 4) and
        // within maxBufferSize (`check_buffer` above); the device is alive while `ctx` is.
        let raw = unsafe { ctx.device.create_buffer(&info, None) }?;
        // SAFETY: `raw` was just created from `ctx.device`.
        let requirements = unsafe { ctx.device.get_buffer_memory_requirements(raw) };
        if let Err(e) = limits.check_allocation(name, requirements.size) {
            // SAFETY: `raw` was created above, never bound or used by any command, and is not used
            // after this.
            unsafe { ctx.device.destroy_buffer(raw, None) };
            return Err(e);
        }
        let allocation = ctx.allocator().allocate(&AllocationCreateDesc {
            name,
            requirements,
            location,
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        });
        let allocation = match allocation {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: as above: `raw` is unbound, unused by any command, and dropped here.
                unsafe { ctx.device.destroy_buffer(raw, None) };
                return Err(e.into());
            }
        };
        // SAFETY: `raw` is a new buffer with no memory bound yet (VUID-vkBindBufferMemory-buffer-07459);
        // `allocation` came from this device's allocator for `requirements`, so its memory type,
        // offset alignment and size fit the buffer.
        if let Err(e) = unsafe {
            ctx.device
                .bind_buffer_memory(raw, allocation.memory(), allocation.offset())
        } {
            let _ = ctx.allocator().free(allocation);
            // SAFETY: `raw` is unused by any command (the bind failed, nothing recorded it) and is
            // not used after this.
            unsafe { ctx.device.destroy_buffer(raw, None) };
            return Err(e.into());
        }
        ctx.set_name(raw, name);
        Ok(Self {
            raw,
            size,
            allocation: Some(allocation),
            ctx: ctx.clone(),
        })
    }

    /// A host-visible buffer filled with `data`.
    pub fn with_data<T: bytemuck::Pod>(
        ctx: &Arc<Context>,
        name: &str,
        data: &[T],
        usage: vk::BufferUsageFlags,
    ) -> Result<Self, VkError> {
        let bytes = bytemuck::cast_slice::<T, u8>(data);
        let mut b = Self::new(
            ctx,
            name,
            bytes.len() as u64,
            usage,
            MemoryLocation::CpuToGpu,
        )?;
        b.write(0, bytes)?;
        Ok(b)
    }

    /// Copies bytes into a mapped buffer at `offset`.
    pub fn write(&mut self, offset: u64, bytes: &[u8]) -> Result<(), VkError> {
        let slice = self
            .allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .ok_or_else(|| VkError::Setup("buffer is not host-visible".into()))?;
        let start = offset as usize;
        let end = start
            .checked_add(bytes.len())
            .filter(|&e| e <= slice.len())
            .ok_or_else(|| VkError::Setup("write past the end of a buffer".into()))?;
        slice[start..end].copy_from_slice(bytes);
        Ok(())
    }

    /// The mapped bytes of a host-visible buffer.
    pub fn mapped(&self) -> Result<&[u8], VkError> {
        self.allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .ok_or_else(|| VkError::Setup("buffer is not host-visible".into()))
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: `self.raw` was created from `self.ctx.device`, which `self.ctx` keeps alive, and is
        // destroyed only here. No submitted command still uses it (VUID-vkDestroyBuffer-buffer-00922):
        // luz drops GPU resources only after their work finished — one-shot submissions are waited
        // for (`Context::submit_and_wait`), and the owners of per-frame work (`Headless`, the
        // viewer) wait on their frame fences or `device_wait_idle` before dropping what they
        // recorded. The memory is freed after the buffer is gone.
        unsafe { self.ctx.device.destroy_buffer(self.raw, None) };
        if let Some(a) = self.allocation.take() {
            let _ = self.ctx.allocator().free(a);
        }
    }
}

/// Collects host-to-device copies and submits them in one command buffer.
pub struct Uploader {
    ctx: Arc<Context>,
    pending: Vec<(Buffer, vk::Buffer, u64)>,
}

impl Uploader {
    pub fn new(ctx: &Arc<Context>) -> Self {
        Self {
            ctx: ctx.clone(),
            pending: Vec::new(),
        }
    }

    /// A device-local buffer that will hold `bytes` once [`Uploader::flush`] has run. Keep the
    /// returned buffer alive until `flush` has returned: the copy into it is recorded there.
    pub fn buffer(
        &mut self,
        name: &str,
        bytes: &[u8],
        usage: vk::BufferUsageFlags,
    ) -> Result<Buffer, VkError> {
        let size = bytes.len().max(4) as u64;
        let dst = Buffer::new(
            &self.ctx,
            name,
            size,
            usage | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        let mut staging = Buffer::new(
            &self.ctx,
            &format!("{name} staging"),
            size,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        staging.write(0, bytes)?;
        self.pending.push((staging, dst.raw, size));
        Ok(dst)
    }

    /// Records and submits every copy, waits, and frees the staging buffers.
    pub fn flush(&mut self, pool: &super::cmd::CommandPool) -> Result<(), VkError> {
        if self.pending.is_empty() {
            return Ok(());
        }
        let pending = std::mem::take(&mut self.pending);
        let d = self.ctx.device.clone();
        pool.one_shot(|cmd| {
            for (src, dst, size) in &pending {
                let region = [vk::BufferCopy {
                    src_offset: 0,
                    dst_offset: 0,
                    size: *size,
                }];
                // SAFETY: `one_shot` hands over `cmd` in the recording state, outside any render
                // pass. `src` (TRANSFER_SRC staging) lives in `pending` until `one_shot` has waited
                // for the copy. `*dst` was created with TRANSFER_DST by `buffer`; that it is still
                // alive is the caller's part of `Uploader`'s contract (the returned `Buffer` is kept
                // until `flush` returns — the forward pass stores it in its meshes first). Both hold
                // `size` bytes, so the region is in bounds.
                unsafe { d.cmd_copy_buffer(cmd, src.raw, *dst, &region) };
            }
            super::cmd::memory_barrier(
                &d,
                cmd,
                (
                    vk::PipelineStageFlags2::TRANSFER,
                    vk::AccessFlags2::TRANSFER_WRITE,
                ),
                (
                    vk::PipelineStageFlags2::ALL_COMMANDS,
                    vk::AccessFlags2::MEMORY_READ,
                ),
            );
            Ok(())
        })
    }
}
