//! Saturation of the classic model on the GPU: per-channel clamp, or whole-image normalisation by the
//! largest channel value (a reduction with shared memory and one atomic per workgroup).

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use luz_graph::{Access, FrameGraph, ImageHandle};

use crate::render::frame::TRANSFER_FILL;

use crate::scene::{Saturation, Scene};
use crate::vk::pipeline::Pipeline;
use crate::vk::shaders::ShaderModule;
use crate::vk::{Buffer, Context, PushSet, VkError};

/// Bindings of `saturate.comp` (its `BINDING_*`).
const BINDING_HDR: u32 = crate::glsl::saturate_comp::BINDING_HDR as u32;
const BINDING_REDUCTION: u32 = crate::glsl::saturate_comp::BINDING_REDUCTION as u32;

pub struct SaturatePass {
    mode: Saturation,
    pipelines: Vec<Pipeline>,
    reduction: Buffer,
    /// The kernels' layout; the image (a transient of the frame graph) and the reduction buffer
    /// are pushed at record time.
    push: PushSet,
    ctx: Arc<Context>,
}

impl SaturatePass {
    /// The pass the scene asks for, or None (no saturation: no pipeline is built).
    pub fn for_scene(ctx: &Arc<Context>, scene: &Scene) -> Result<Option<Self>, VkError> {
        let mode = scene.saturation;
        let kernels: &[&str] = match mode {
            Saturation::None => return Ok(None),
            Saturation::Clamp => &["saturate.comp:clamp"],
            Saturation::Normalize => &["saturate.comp:reduce", "saturate.comp:normalize"],
        };
        let push = PushSet::new(ctx, "saturate", kernels)?;
        let reduction = Buffer::new(
            ctx,
            "saturation max",
            4,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        let pipelines = kernels
            .iter()
            .map(|k| {
                let module = ShaderModule::new(ctx, k)?;
                Pipeline::compute(ctx, &push.layout, k, &module, &[])
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Some(Self {
            mode,
            pipelines,
            reduction,
            push,
            ctx: ctx.clone(),
        }))
    }

    pub fn name(&self) -> &'static str {
        match self.mode {
            Saturation::Clamp => "saturate[clamp]",
            _ => "saturate[normalize]",
        }
    }

    /// Declares the pass (named `name`, [`SaturatePass::name`] for the main scene) on `color`
    /// (an RGBA32F image), read and written in place by the compute kernels.
    pub fn add_pass<'a>(&'a self, g: &mut FrameGraph<'a>, color: ImageHandle, name: &'static str) {
        g.pass(name)
            .read_write(color, Access::ComputeStorageReadWrite)
            .record(move |rc| {
                let image = rc.image(color)?;
                let groups = (
                    image.extent.width.div_ceil(16),
                    image.extent.height.div_ceil(16),
                );
                let mut writes =
                    self.push
                        .writes()
                        .view(BINDING_HDR, image.view, vk::ImageLayout::GENERAL);
                if self.mode == Saturation::Normalize {
                    writes = writes.buffer(BINDING_REDUCTION, self.reduction.raw);
                }
                let d = &self.ctx.device;
                let cmd = rc.cmd();
                if self.mode == Saturation::Normalize {
                    // SAFETY: `reduction` has TRANSFER_DST usage and is filled whole; `cmd` is
                    // recording outside a render pass (the graph records passes one by one).
                    unsafe { d.cmd_fill_buffer(cmd, self.reduction.raw, 0, vk::WHOLE_SIZE, 0) };
                    // Fill is a transfer command: validation layers place it in COPY or CLEAR
                    // depending on their version, so wait on every transfer stage.
                    rc.memory_barrier(TRANSFER_FILL, Access::ComputeStorageReadWrite);
                }
                // SAFETY: `cmd` is recording; the view is the graph's image for this frame (live
                // until the frame completes, in GENERAL when the kernels run) and the reduction
                // buffer the pass's own, both with STORAGE usage.
                unsafe {
                    self.push
                        .push(cmd, vk::PipelineBindPoint::COMPUTE, writes)?
                };
                for (i, p) in self.pipelines.iter().enumerate() {
                    if i > 0 {
                        // The image and the reduction buffer: every kernel reads the last's writes.
                        rc.memory_barrier(
                            Access::ComputeStorageReadWrite,
                            Access::ComputeStorageReadWrite,
                        );
                    }
                    // SAFETY: each pipeline was built with `self.push.layout`; the graph put the
                    // image (a live STORAGE view while the frame runs) in GENERAL for the storage
                    // accesses, the reduction buffer is the pass's own, and the barriers above
                    // order each kernel after the one before.
                    unsafe {
                        d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, p.raw);
                        d.cmd_dispatch(cmd, groups.0, groups.1, 1);
                    }
                }
                Ok(())
            });
    }
}
