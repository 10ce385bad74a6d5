//! Command pools and small recording helpers (synchronization2 barriers).

use std::sync::Arc;

use ash::vk;

use super::{Context, VkError};

/// A command pool owning its command buffers.
pub struct CommandPool {
    pub raw: vk::CommandPool,
    ctx: Arc<Context>,
}

impl CommandPool {
    pub fn new(ctx: &Arc<Context>, name: &str) -> Result<Self, VkError> {
        let info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(ctx.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: `info` is a local that outlives the call; `ctx.queue_family` is the family the
        // device's queue was created from.
        let raw = unsafe { ctx.device.create_command_pool(&info, None) }?;
        ctx.set_name(raw, name);
        Ok(Self {
            raw,
            ctx: ctx.clone(),
        })
    }

    pub fn allocate(&self, count: u32) -> Result<Vec<vk::CommandBuffer>, VkError> {
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.raw)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(count);
        // SAFETY: `info` is a local naming `self.raw`, a live pool of this device. The pool is
        // externally synchronised: luz records and submits on one thread only (its rayon work is
        // CPU-only), so no other call uses this pool concurrently.
        Ok(unsafe { self.ctx.device.allocate_command_buffers(&info) }?)
    }

    /// Records with `f` into a fresh command buffer, submits it and waits.
    pub fn one_shot(
        &self,
        f: impl FnOnce(vk::CommandBuffer) -> Result<(), VkError>,
    ) -> Result<(), VkError> {
        let cmd = self.allocate(1)?[0];
        let d = &self.ctx.device;
        let result = (|| {
            // SAFETY: `cmd` was just allocated from `self.raw`, so it is in the initial state, not
            // recording or pending (VUID-vkBeginCommandBuffer-commandBuffer-00049); the begin info
            // is a temporary that outlives the call. Pool access is single-threaded (see
            // `allocate`).
            unsafe {
                d.begin_command_buffer(
                    cmd,
                    &vk::CommandBufferBeginInfo::default()
                        .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
                )
            }?;
            f(cmd)?;
            // SAFETY: `cmd` is in the recording state: it began above and `f` only records into
            // it (it does not own it and never ends or submits it).
            unsafe { d.end_command_buffer(cmd) }?;
            self.ctx.submit_and_wait(cmd)
        })();
        // SAFETY: `cmd` was allocated from `self.raw` and is not pending
        // (VUID-vkFreeCommandBuffers-pCommandBuffers-00047): it was never submitted (an earlier
        // step failed), or the submission failed, or `submit_and_wait` waited for its fence. It is
        // not used after this.
        unsafe { d.free_command_buffers(self.raw, &[cmd]) };
        result
    }
}

impl Drop for CommandPool {
    fn drop(&mut self) {
        // SAFETY: `self.raw` was created from `self.ctx.device` (alive through `self.ctx`) and is
        // destroyed only here. The idle wait first makes sure no command buffer allocated from it
        // is pending (VUID-vkDestroyCommandPool-commandPool-00041). Waiting idle also needs the
        // queue externally synchronised, which holds because all submissions come from the same
        // single thread that drops the pool.
        unsafe {
            // Buffers from this pool may still be executing if a frame was abandoned on error.
            let _ = self.ctx.device.device_wait_idle();
            self.ctx.device.destroy_command_pool(self.raw, None);
        }
    }
}

/// A layout transition with explicit stages and accesses (synchronization2).
#[derive(Clone, Copy)]
pub struct Transition {
    pub image: vk::Image,
    pub range: vk::ImageSubresourceRange,
    pub from: (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2),
    pub to: (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2),
}

pub fn transition(device: &ash::Device, cmd: vk::CommandBuffer, transitions: &[Transition]) {
    let barriers: Vec<vk::ImageMemoryBarrier2> = transitions
        .iter()
        .map(|t| {
            vk::ImageMemoryBarrier2::default()
                .image(t.image)
                .subresource_range(t.range)
                .old_layout(t.from.0)
                .src_stage_mask(t.from.1)
                .src_access_mask(t.from.2)
                .new_layout(t.to.0)
                .dst_stage_mask(t.to.1)
                .dst_access_mask(t.to.2)
                .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        })
        .collect();
    let dep = vk::DependencyInfo::default().image_memory_barriers(&barriers);
    // SAFETY: `dep` and `barriers` are locals that outlive the call. The caller passes `cmd` in the
    // recording state, from a pool used only on this thread, and images and states that are valid
    // for it (the contract of this function; the synchronization2 feature is enabled by
    // `Context::new`).
    unsafe { device.cmd_pipeline_barrier2(cmd, &dep) };
}

/// Records `record` with `range` of `image` in the state `during`: a transition from `before`
/// into it first, and one from it to `after` once `record` has run.
pub fn between_transitions(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    (image, range): (vk::Image, vk::ImageSubresourceRange),
    [before, during, after]: [ImageState; 3],
    record: impl FnOnce(),
) {
    let step = |from, to| Transition {
        image,
        range,
        from,
        to,
    };
    transition(device, cmd, &[step(before, during)]);
    record();
    transition(device, cmd, &[step(during, after)]);
}

/// A global memory barrier between two stage/access pairs.
pub fn memory_barrier(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    src: (vk::PipelineStageFlags2, vk::AccessFlags2),
    dst: (vk::PipelineStageFlags2, vk::AccessFlags2),
) {
    let b = [vk::MemoryBarrier2::default()
        .src_stage_mask(src.0)
        .src_access_mask(src.1)
        .dst_stage_mask(dst.0)
        .dst_access_mask(dst.1)];
    let dep = vk::DependencyInfo::default().memory_barriers(&b);
    // SAFETY: `dep` and `b` are locals that outlive the call; the caller passes `cmd` in the
    // recording state, from a pool used only on this thread (the contract of this function).
    unsafe { device.cmd_pipeline_barrier2(cmd, &dep) };
}

/// Makes transfer writes (copies into host-visible buffers) visible to host reads after the
/// submission's fence.
pub fn copy_to_host_barrier(device: &ash::Device, cmd: vk::CommandBuffer) {
    memory_barrier(
        device,
        cmd,
        (
            vk::PipelineStageFlags2::COPY,
            vk::AccessFlags2::TRANSFER_WRITE,
        ),
        (vk::PipelineStageFlags2::HOST, vk::AccessFlags2::HOST_READ),
    );
}

/// Copies the colour of mip 0, layer 0 of `image` (in `layout`) over `extent` into `buffer`,
/// tightly packed.
pub fn copy_image_to_buffer(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    layout: vk::ImageLayout,
    buffer: &super::Buffer,
    extent: vk::Extent2D,
) {
    let region = vk::BufferImageCopy {
        buffer_offset: 0,
        buffer_row_length: 0,
        buffer_image_height: 0,
        image_subresource: vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        },
        image_offset: vk::Offset3D::default(),
        image_extent: vk::Extent3D {
            width: extent.width,
            height: extent.height,
            depth: 1,
        },
    };
    // SAFETY: the region is a local that outlives the call. The caller passes `cmd` in the
    // recording state outside a render pass, `image` (TRANSFER_SRC, at least `extent`, in `layout`)
    // and a TRANSFER_DST `buffer` large enough for the tightly packed pixels, and keeps both alive
    // until the submission completes (the contract of this function).
    unsafe { d.cmd_copy_image_to_buffer(cmd, image, layout, buffer.raw, &[region]) };
}

/// Where an image stands between commands: layout, and the stages and accesses that use it there.
pub type ImageState = (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2);

/// Copies `regions` of `image` (kept in `state`) to the host in one submission and waits: the
/// image goes to TRANSFER_SRC and back to `state`, and the first `total` bytes of the tightly
/// packed copy are returned. `name` labels the staging buffer.
pub fn read_to_host(
    ctx: &Arc<Context>,
    pool: &CommandPool,
    image: &super::Image,
    state: ImageState,
    (regions, total): (&[vk::BufferImageCopy], u64),
    name: &str,
) -> Result<Vec<u8>, VkError> {
    let buf = super::Buffer::new(
        ctx,
        name,
        total,
        vk::BufferUsageFlags::TRANSFER_DST,
        gpu_allocator::MemoryLocation::GpuToCpu,
    )?;
    let d = &ctx.device;
    let src = (
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        vk::PipelineStageFlags2::COPY,
        vk::AccessFlags2::TRANSFER_READ,
    );
    let (raw, range) = (image.raw, image.subresource_range());
    pool.one_shot(|cmd| {
        between_transitions(d, cmd, (raw, range), [state, src, state], || {
            // SAFETY: the image is in TRANSFER_SRC_OPTIMAL (transitioned before this runs), `buf`
            // is a live TRANSFER_DST buffer of `total` bytes, which the caller's regions fit
            // tightly packed, and the command buffer is recording outside a render pass.
            unsafe {
                d.cmd_copy_image_to_buffer(
                    cmd,
                    raw,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    buf.raw,
                    regions,
                )
            };
        });
        copy_to_host_barrier(d, cmd);
        Ok(())
    })?;
    Ok(buf.mapped()?[..total as usize].to_vec())
}

/// Sets the dynamic viewport to the whole of `extent` (depth 0..1) and the scissor to `scissor`.
///
/// # Safety
/// `cmd` must be recording, with a pipeline whose viewport and scissor are dynamic (or about to
/// be bound).
pub unsafe fn set_viewport(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    extent: vk::Extent2D,
    scissor: vk::Rect2D,
) {
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: extent.width as f32,
        height: extent.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    // SAFETY: the caller's contract; the arrays are locals that outlive the calls.
    unsafe {
        device.cmd_set_viewport(cmd, 0, &[viewport]);
        device.cmd_set_scissor(cmd, 0, &[scissor]);
    }
}

/// How a rendering attachment starts.
#[derive(Clone, Copy)]
pub enum Load {
    /// Cleared to a value.
    Clear(vk::ClearValue),
    /// What the image holds.
    Keep,
    /// Undefined (every pixel read is written first, or nothing is read).
    DontCare,
}

impl Load {
    /// Depth cleared to `depth` (stencil 0).
    pub fn depth(depth: f32) -> Self {
        Load::Clear(vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue { depth, stencil: 0 },
        })
    }
}

/// A dynamic-rendering attachment of `view` in `layout` that starts as `load` says and is
/// stored (`store`) or not.
pub fn attachment(
    view: vk::ImageView,
    layout: vk::ImageLayout,
    load: Load,
    store: bool,
) -> vk::RenderingAttachmentInfo<'static> {
    let a = vk::RenderingAttachmentInfo::default()
        .image_view(view)
        .image_layout(layout)
        .store_op(if store {
            vk::AttachmentStoreOp::STORE
        } else {
            vk::AttachmentStoreOp::DONT_CARE
        });
    match load {
        Load::Clear(value) => a.load_op(vk::AttachmentLoadOp::CLEAR).clear_value(value),
        Load::Keep => a.load_op(vk::AttachmentLoadOp::LOAD),
        Load::DontCare => a.load_op(vk::AttachmentLoadOp::DONT_CARE),
    }
}

/// [`attachment`] for a colour view in COLOR_ATTACHMENT_OPTIMAL.
pub fn color_attachment(
    view: vk::ImageView,
    load: Load,
    store: bool,
) -> vk::RenderingAttachmentInfo<'static> {
    attachment(view, vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL, load, store)
}

/// [`attachment`] for a depth view in DEPTH_ATTACHMENT_OPTIMAL.
pub fn depth_attachment(
    view: vk::ImageView,
    load: Load,
    store: bool,
) -> vk::RenderingAttachmentInfo<'static> {
    attachment(view, vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL, load, store)
}

/// One layer of rendering over `area` into `colors` and `depth`.
pub fn rendering_info<'a>(
    area: vk::Rect2D,
    colors: &'a [vk::RenderingAttachmentInfo<'a>],
    depth: Option<&'a vk::RenderingAttachmentInfo<'a>>,
) -> vk::RenderingInfo<'a> {
    let info = vk::RenderingInfo::default()
        .render_area(area)
        .layer_count(1)
        .color_attachments(colors);
    match depth {
        Some(d) => info.depth_attachment(d),
        None => info,
    }
}

/// Resets `cmd` and begins it for one submission.
///
/// # Safety
/// `cmd` must come from a pool created with RESET_COMMAND_BUFFER and must not be pending (its
/// last submission's fence was waited for).
pub unsafe fn restart(device: &ash::Device, cmd: vk::CommandBuffer) -> Result<(), vk::Result> {
    // SAFETY: the caller's contract.
    unsafe {
        device.reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty())?;
        device.begin_command_buffer(
            cmd,
            &vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
        )
    }
}

/// Fills `image`'s mips 1..`levels` (layer 0, colour) by halving blits from mip 0, each level
/// from the one above with a linear filter. Every level is in TRANSFER_DST_OPTIMAL before (mip
/// 0 written by a transfer) and after: the barriers between the levels stay inside, so a frame
/// graph sees one transfer write of the whole image.
pub fn blit_mip_chain(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    extent: vk::Extent2D,
    levels: u32,
) {
    let dst = (
        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        vk::PipelineStageFlags2::ALL_TRANSFER,
        vk::AccessFlags2::TRANSFER_WRITE,
    );
    let src = (
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        vk::PipelineStageFlags2::ALL_TRANSFER,
        vk::AccessFlags2::TRANSFER_READ,
    );
    let range = |base, count| vk::ImageSubresourceRange {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        base_mip_level: base,
        level_count: count,
        base_array_layer: 0,
        layer_count: 1,
    };
    let size = |level: u32| {
        [
            (extent.width >> level).max(1) as i32,
            (extent.height >> level).max(1) as i32,
        ]
    };
    if levels < 2 {
        return;
    }
    // The frame graph's barrier before this pass made the image TRANSFER_DST for the COPY stage:
    // chain the blits' stage (BLIT) to it for the levels they write.
    transition(
        d,
        cmd,
        &[Transition {
            image,
            range: range(1, levels - 1),
            from: dst,
            to: dst,
        }],
    );
    for level in 1..levels {
        let step = |from, to| Transition {
            image,
            range: range(level - 1, 1),
            from,
            to,
        };
        transition(d, cmd, &[step(dst, src)]);
        let layers = |mip| vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: mip,
            base_array_layer: 0,
            layer_count: 1,
        };
        let corner = |[x, y]: [i32; 2]| vk::Offset3D { x, y, z: 1 };
        let blit = vk::ImageBlit2::default()
            .src_subresource(layers(level - 1))
            .src_offsets([vk::Offset3D::default(), corner(size(level - 1))])
            .dst_subresource(layers(level))
            .dst_offsets([vk::Offset3D::default(), corner(size(level))]);
        let regions = [blit];
        let info = vk::BlitImageInfo2::default()
            .src_image(image)
            .src_image_layout(vk::ImageLayout::TRANSFER_SRC_OPTIMAL)
            .dst_image(image)
            .dst_image_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
            .regions(&regions)
            .filter(vk::Filter::LINEAR);
        // SAFETY: `info` and `regions` are locals that outlive the call; the caller passes `cmd`
        // recording outside a render pass and a live single-layer colour image of `levels` mips
        // of `extent`, usable as TRANSFER_SRC and TRANSFER_DST with a format that supports linear
        // blits; level − 1 was just moved to TRANSFER_SRC and level is TRANSFER_DST.
        unsafe { d.cmd_blit_image2(cmd, &info) };
    }
    // Every level back to TRANSFER_DST, the blits' writes made available to the transfer stages
    // (COPY among them), which the graph's next barrier waits for.
    transition(
        d,
        cmd,
        &[
            Transition {
                image,
                range: range(0, levels - 1),
                from: src,
                to: dst,
            },
            Transition {
                image,
                range: range(levels - 1, 1),
                from: dst,
                to: dst,
            },
        ],
    );
}
