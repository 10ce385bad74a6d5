//! The environment's descriptor set (set 1 of the forward pass): the four images and the uniforms.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::render::gpu::glsl::include_ibl as glsl_ibl;
use crate::vk::image::Sampler;
use crate::vk::pipeline::{DescriptorPool, DescriptorSetLayout};
use crate::vk::{Buffer, Context, Image, VkError};

use super::bake::{write_set, Bind};
use super::EnvData;

/// The environment set's bindings (`shaders_glsl/include/ibl.glsl`): the environment cube, the
/// irradiance cube, the prefiltered cube and the LUT are 0..4 in that order, then the uniforms.
const BINDING_ENV_DATA: u32 = glsl_ibl::BINDING_ENV_DATA as u32;
const _: () = assert!(
    glsl_ibl::BINDING_ENV_CUBE == 0
        && glsl_ibl::BINDING_IRRADIANCE_CUBE == 1
        && glsl_ibl::BINDING_PREFILTERED_CUBE == 2
        && glsl_ibl::BINDING_BRDF_LUT == 3
        && glsl_ibl::BINDING_ENV_DATA == 4
);

/// The set, its layout and pool, and the uniform buffer it binds.
pub(super) struct EnvSet {
    pub set: vk::DescriptorSet,
    pub set_layout: DescriptorSetLayout,
    pub pool: DescriptorPool,
    pub ubo: Buffer,
}

impl EnvSet {
    /// Binds `images` (environment, irradiance, prefiltered, LUT, each with `sampler`) and
    /// uniforms holding `ubo_data`.
    pub fn new(
        ctx: &Arc<Context>,
        ubo_data: &EnvData,
        images: [&Image; 4],
        sampler: &Sampler,
    ) -> Result<Self, VkError> {
        let d = &ctx.device;
        let [env, irradiance, prefiltered, lut] = images;
        let mut ubo = Buffer::new(
            ctx,
            "environment uniforms",
            std::mem::size_of::<EnvData>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        ubo.write(0, bytemuck::bytes_of(ubo_data))?;
        let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
        // Bindings 0..4 (BINDING_ENV_CUBE … BINDING_BRDF_LUT) in the order of the writes below.
        let mut bindings: Vec<_> = (0..BINDING_ENV_DATA)
            .map(|i| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(i)
                    .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                    .descriptor_count(1)
                    .stage_flags(stages)
            })
            .collect();
        bindings.push(
            vk::DescriptorSetLayoutBinding::default()
                .binding(BINDING_ENV_DATA)
                .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
                .descriptor_count(1)
                .stage_flags(stages),
        );
        let set_layout = DescriptorSetLayout::new(ctx, "environment set layout", &bindings)?;
        let set_pool = DescriptorPool::new(
            ctx,
            "environment pool",
            1,
            &[
                vk::DescriptorPoolSize {
                    ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                    descriptor_count: 4,
                },
                vk::DescriptorPoolSize {
                    ty: vk::DescriptorType::UNIFORM_BUFFER,
                    descriptor_count: 1,
                },
            ],
        )?;
        let set = set_pool.allocate(&set_layout)?;
        write_set(
            ctx,
            set,
            &[
                Bind::Sampled(env.view, sampler.raw),
                Bind::Sampled(irradiance.view, sampler.raw),
                Bind::Sampled(prefiltered.view, sampler.raw),
                Bind::Sampled(lut.view, sampler.raw),
            ],
        );
        let ubo_info = [vk::DescriptorBufferInfo {
            buffer: ubo.raw,
            offset: 0,
            range: vk::WHOLE_SIZE,
        }];
        let write = vk::WriteDescriptorSet::default()
            .dst_set(set)
            .dst_binding(BINDING_ENV_DATA)
            .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
            .buffer_info(&ubo_info);
        // SAFETY: `set` was just allocated and is unused; `ubo` is a live uniform buffer and `ubo_info`
        // outlives the call.
        unsafe { d.update_descriptor_sets(&[write], &[]) };
        Ok(Self {
            set,
            set_layout,
            pool: set_pool,
            ubo,
        })
    }
}
