//! The environment's descriptor set (set 1 of the forward pass): the four images and the uniforms.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::render::gpu::glsl::include_ibl as glsl_ibl;
use crate::render::gpu::SET_ENV;
use crate::vk::image::Sampler;
use crate::vk::pipeline::{DescriptorPool, DescriptorSetLayout};
use crate::vk::{Buffer, Context, Image, SetWrites, VkError};

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
        let [env, irradiance, prefiltered, lut] = images;
        let mut ubo = Buffer::new(
            ctx,
            "environment uniforms",
            std::mem::size_of::<EnvData>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        ubo.write(0, bytemuck::bytes_of(ubo_data))?;
        let set_layout = crate::render::sets::scene_interface()?.set_layout(ctx, SET_ENV)?;
        let set_pool = DescriptorPool::for_sets(ctx, "environment pool", &[(&set_layout, 1)])?;
        let set = set_pool.allocate(&set_layout)?;
        let sampled = |view| Bind::Sampled(view, sampler.raw);
        write_set(
            ctx,
            (&set_layout, set),
            &[
                sampled(env.view),
                sampled(irradiance.view),
                sampled(prefiltered.view),
                sampled(lut.view),
            ],
        )?;
        // SAFETY: `set` was just allocated and is unused; `ubo` is a live uniform buffer, kept as
        // long as the set.
        unsafe {
            SetWrites::new(&set_layout, set)
                .buffer(BINDING_ENV_DATA, ubo.raw)
                .apply(ctx)
        }?;
        Ok(Self {
            set,
            set_layout,
            pool: set_pool,
            ubo,
        })
    }
}
