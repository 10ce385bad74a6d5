//! Saturation of the classic model on the GPU: per-channel clamp, or whole-image normalisation by the
//! largest channel value (a reduction with shared memory and one atomic per workgroup).

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::scene::{Saturation, Scene};
use crate::vk::cmd::{memory_barrier, transition, Transition};
use crate::vk::pipeline::{DescriptorPool, DescriptorSetLayout, Pipeline, PipelineLayout};
use crate::vk::shaders::ShaderModule;
use crate::vk::{Buffer, Context, Image, VkError};

/// Bindings of `saturate.comp` (its `BINDING_*`).
const BINDING_HDR: u32 = crate::glsl::saturate_comp::BINDING_HDR as u32;
const BINDING_REDUCTION: u32 = crate::glsl::saturate_comp::BINDING_REDUCTION as u32;

type Access = (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2);

pub struct SaturatePass {
    mode: Saturation,
    pipelines: Vec<Pipeline>,
    reduction: Buffer,
    set: vk::DescriptorSet,
    _pool: DescriptorPool,
    layout: PipelineLayout,
    _set_layout: DescriptorSetLayout,
    groups: (u32, u32),
    image: vk::Image,
    range: vk::ImageSubresourceRange,
    ctx: Arc<Context>,
}

impl SaturatePass {
    /// The pass the scene asks for, or None (no saturation: no pipeline is built).
    pub fn for_scene(
        ctx: &Arc<Context>,
        scene: &Scene,
        target: &Image,
    ) -> Result<Option<Self>, VkError> {
        let mode = scene.saturation;
        let kernels: &[&str] = match mode {
            Saturation::None => return Ok(None),
            Saturation::Clamp => &["saturate.comp:clamp"],
            Saturation::Normalize => &["saturate.comp:reduce", "saturate.comp:normalize"],
        };
        let bindings = [
            vk::DescriptorSetLayoutBinding::default()
                .binding(BINDING_HDR)
                .descriptor_type(vk::DescriptorType::STORAGE_IMAGE)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::COMPUTE),
            vk::DescriptorSetLayoutBinding::default()
                .binding(BINDING_REDUCTION)
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::COMPUTE),
        ];
        let set_layout = DescriptorSetLayout::new(ctx, "saturate set layout", &bindings)?;
        let layout = PipelineLayout::new(ctx, "saturate layout", &[&set_layout], &[])?;
        let pool = DescriptorPool::new(
            ctx,
            "saturate pool",
            1,
            &[
                vk::DescriptorPoolSize {
                    ty: vk::DescriptorType::STORAGE_IMAGE,
                    descriptor_count: 1,
                },
                vk::DescriptorPoolSize {
                    ty: vk::DescriptorType::STORAGE_BUFFER,
                    descriptor_count: 1,
                },
            ],
        )?;
        let set = pool.allocate(&set_layout)?;
        let reduction = Buffer::new(
            ctx,
            "saturation max",
            4,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        let image_info = [vk::DescriptorImageInfo {
            sampler: vk::Sampler::null(),
            image_view: target.view,
            image_layout: vk::ImageLayout::GENERAL,
        }];
        let buffer_info = [vk::DescriptorBufferInfo {
            buffer: reduction.raw,
            offset: 0,
            range: vk::WHOLE_SIZE,
        }];
        let writes = [
            vk::WriteDescriptorSet::default()
                .dst_set(set)
                .dst_binding(BINDING_HDR)
                .descriptor_type(vk::DescriptorType::STORAGE_IMAGE)
                .image_info(&image_info),
            vk::WriteDescriptorSet::default()
                .dst_set(set)
                .dst_binding(BINDING_REDUCTION)
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                .buffer_info(&buffer_info),
        ];
        // SAFETY: `writes` and the infos they point to outlive the call. `set` was just allocated
        // and no command buffer has used it; the bindings match `set_layout` (STORAGE_IMAGE 0,
        // STORAGE_BUFFER 1). `target.view` is a live view of a colour target with STORAGE usage,
        // and `reduction` a STORAGE_BUFFER that the pass keeps as long as the set.
        unsafe { ctx.device.update_descriptor_sets(&writes, &[]) };
        let pipelines = kernels
            .iter()
            .map(|k| {
                let module = ShaderModule::new(ctx, k)?;
                Pipeline::compute(ctx, &layout, k, &module, &[])
            })
            .collect::<Result<Vec<_>, _>>()?;
        let e = target.extent();
        Ok(Some(Self {
            mode,
            pipelines,
            reduction,
            set,
            _pool: pool,
            layout,
            _set_layout: set_layout,
            groups: (e.width.div_ceil(16), e.height.div_ceil(16)),
            image: target.raw,
            range: target.subresource_range(),
            ctx: ctx.clone(),
        }))
    }

    pub fn name(&self) -> &'static str {
        match self.mode {
            Saturation::Clamp => "saturate[clamp]",
            _ => "saturate[normalize]",
        }
    }

    /// Records the pass on the target, which was last accessed as `from`; returns its new state.
    pub fn record(&self, cmd: vk::CommandBuffer, from: Access) -> Access {
        let d = &self.ctx.device;
        let general = (
            vk::ImageLayout::GENERAL,
            vk::PipelineStageFlags2::COMPUTE_SHADER,
            vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE,
        );
        transition(
            d,
            cmd,
            &[Transition {
                image: self.image,
                range: self.range,
                from,
                to: general,
            }],
        );
        // SAFETY: `reduction` has TRANSFER_DST usage and is filled whole; each pipeline was built
        // with `self.layout`, whose set 0 `self.set` matches; the barriers order the fill before
        // the reduction and each kernel before the next. The transition above puts the target in
        // GENERAL for the storage accesses. The caller's part: `cmd` is recording outside a render
        // pass, and `from` is the target's actual state.
        unsafe {
            if self.mode == Saturation::Normalize {
                // Fill is a transfer command: validation layers place it in COPY or CLEAR
                // depending on their version, so wait on every transfer stage.
                d.cmd_fill_buffer(cmd, self.reduction.raw, 0, vk::WHOLE_SIZE, 0);
                memory_barrier(
                    d,
                    cmd,
                    (
                        vk::PipelineStageFlags2::ALL_TRANSFER,
                        vk::AccessFlags2::TRANSFER_WRITE,
                    ),
                    (
                        vk::PipelineStageFlags2::COMPUTE_SHADER,
                        vk::AccessFlags2::SHADER_STORAGE_READ
                            | vk::AccessFlags2::SHADER_STORAGE_WRITE,
                    ),
                );
            }
            d.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                self.layout.raw,
                0,
                &[self.set],
                &[],
            );
            for (i, p) in self.pipelines.iter().enumerate() {
                if i > 0 {
                    memory_barrier(
                        d,
                        cmd,
                        (
                            vk::PipelineStageFlags2::COMPUTE_SHADER,
                            vk::AccessFlags2::SHADER_STORAGE_WRITE,
                        ),
                        (
                            vk::PipelineStageFlags2::COMPUTE_SHADER,
                            vk::AccessFlags2::SHADER_STORAGE_READ
                                | vk::AccessFlags2::SHADER_STORAGE_WRITE,
                        ),
                    );
                }
                d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, p.raw);
                d.cmd_dispatch(cmd, self.groups.0, self.groups.1, 1);
            }
        }
        (
            vk::ImageLayout::GENERAL,
            vk::PipelineStageFlags2::COMPUTE_SHADER,
            vk::AccessFlags2::SHADER_STORAGE_WRITE,
        )
    }
}
