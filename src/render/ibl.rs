//! Image-based lighting precomputation on the GPU (MODELS.md §7): the environment as a cube with a
//! full mip chain (for PDF-based LOD), a cosine-convolved irradiance cube, a GGX-prefiltered cube
//! (one roughness per mip) and the split-sum BRDF LUT (one layer per geometry term a material uses).
//! The 9 spherical-harmonic irradiance coefficients come from the CPU (`crate::env`).

use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use glam::Vec3;
use gpu_allocator::MemoryLocation;

use crate::vk::cmd::{memory_barrier, transition, CommandPool, Transition};
use crate::vk::image::{ImageDesc, Sampler};
use crate::vk::pipeline::{DescriptorPool, DescriptorSetLayout, Pipeline, PipelineLayout};
use crate::vk::shaders::ShaderModule;
use crate::vk::{Buffer, Context, Image, VkError};

use super::gpu::glsl::include_ibl as glsl_ibl;

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

pub const CUBE_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;
pub const LUT_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;

/// Sizes and sample counts of the precomputed data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IblSettings {
    /// Level-0 face size of the environment cube (full mip chain below it).
    pub env_size: u32,
    pub irradiance_size: u32,
    pub irradiance_samples: u32,
    pub prefilter_size: u32,
    pub prefilter_mips: u32,
    pub prefilter_samples: u32,
    pub lut_size: u32,
    pub lut_samples: u32,
}

impl Default for IblSettings {
    /// The sizes of the well-known Vulkan PBR sample luz compares itself with: 64² irradiance,
    /// 512² prefiltered cube with 10 mips, 512² LUT at 1024 samples.
    fn default() -> Self {
        Self {
            env_size: 512,
            irradiance_size: 64,
            irradiance_samples: 256,
            prefilter_size: 512,
            prefilter_mips: 10,
            prefilter_samples: 64,
            lut_size: 512,
            lut_samples: 1024,
        }
    }
}

impl IblSettings {
    /// Small sizes for tests and previews: 128² cubes, 128² LUT at 512 samples.
    pub fn fast() -> Self {
        Self {
            env_size: 128,
            irradiance_size: 32,
            irradiance_samples: 128,
            prefilter_size: 128,
            prefilter_mips: 8,
            prefilter_samples: 32,
            lut_size: 128,
            lut_samples: 512,
        }
    }

    /// A string naming every setting (part of the cache key).
    pub fn describe(&self) -> String {
        format!(
            "env{} irr{}x{} pre{}x{}m{} lut{}x{}",
            self.env_size,
            self.irradiance_size,
            self.irradiance_samples,
            self.prefilter_size,
            self.prefilter_samples,
            self.prefilter_mips,
            self.lut_size,
            self.lut_samples
        )
    }
}

/// `EnvData` (std140) in `shaders_glsl/include/ibl.glsl`.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable, Debug)]
pub struct EnvData {
    /// Irradiance SH coefficients (RGB in xyz), already convolved: E(n) = Σ c_i Y_i(n).
    pub sh: [[f32; 4]; 9],
    /// cos θ, sin θ of the environment rotation about +y, environment cube size, its mip count.
    pub rotation: [f32; 4],
    /// Prefiltered cube mip count, samples for importance sampling, 0, 0.
    pub params: [f32; 4],
}

/// Linear radiance in an equirectangular layout (row 0 = +y), as `crate::env` produces it.
pub struct EquirectView<'a> {
    pub width: u32,
    pub height: u32,
    pub texels: &'a [[f32; 4]],
}

/// What the precomputation starts from.
pub struct IblInputs<'a> {
    pub equirect: EquirectView<'a>,
    /// Convolved irradiance SH coefficients (`crate::env::sh9_irradiance_coeffs`).
    pub sh_irradiance: [Vec3; 9],
    /// Rotation of the environment about +y.
    pub rotation_deg: f32,
    /// The geometry selectors (BRDF_G_*) the scene's materials use: one LUT layer each.
    pub lut_geometries: &'a [i32],
    /// Where to keep precomputed data between runs, and this environment's key there
    /// (`crate::env::cache_key`); None computes everything every time.
    pub cache: Option<(&'a std::path::Path, String)>,
}

/// Timings of the precomputation, per stage, in milliseconds of wall time.
#[derive(Debug, Clone, Default)]
pub struct IblTimes {
    pub stages: Vec<(&'static str, f64)>,
}

impl IblTimes {
    pub fn total(&self) -> f64 {
        self.stages.iter().map(|(_, t)| t).sum()
    }
}

/// The environment's GPU data and the descriptor set (set 1 of the forward pass) that binds it.
pub struct Ibl {
    pub set: vk::DescriptorSet,
    pub set_layout: DescriptorSetLayout,
    _pool: DescriptorPool,
    _ubo: Buffer,
    /// Geometry selector (BRDF_G_*) of each LUT layer.
    lut_layers: Vec<i32>,
    pub times: IblTimes,
    _lut: Image,
    _prefiltered: Image,
    _irradiance: Image,
    _env: Image,
    _sampler: Sampler,
}

struct Kernel {
    pipeline: Pipeline,
    layout: PipelineLayout,
    set_layout: DescriptorSetLayout,
}

impl Kernel {
    fn new(
        ctx: &Arc<Context>,
        key: &str,
        bindings: &[vk::DescriptorType],
        push_size: u32,
    ) -> Result<Self, VkError> {
        let b: Vec<_> = bindings
            .iter()
            .enumerate()
            .map(|(i, t)| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(i as u32)
                    .descriptor_type(*t)
                    .descriptor_count(1)
                    .stage_flags(vk::ShaderStageFlags::COMPUTE)
            })
            .collect();
        let set_layout = DescriptorSetLayout::new(ctx, &format!("{key} set layout"), &b)?;
        let push = [vk::PushConstantRange {
            stage_flags: vk::ShaderStageFlags::COMPUTE,
            offset: 0,
            size: push_size,
        }];
        let layout = PipelineLayout::new(ctx, &format!("{key} layout"), &[&set_layout], &push)?;
        let module = ShaderModule::new(ctx, key)?;
        let pipeline = Pipeline::compute(ctx, &layout, key, &module, &[])?;
        Ok(Self {
            pipeline,
            layout,
            set_layout,
        })
    }
}

/// Descriptor writes for one dispatch: (binding, image view + layout + sampler) pairs.
enum Bind {
    Sampled(vk::ImageView, vk::Sampler),
    Storage(vk::ImageView),
}

fn write_set(ctx: &Context, set: vk::DescriptorSet, binds: &[Bind]) {
    let infos: Vec<[vk::DescriptorImageInfo; 1]> = binds
        .iter()
        .map(|b| match b {
            Bind::Sampled(view, sampler) => [vk::DescriptorImageInfo {
                sampler: *sampler,
                image_view: *view,
                image_layout: vk::ImageLayout::GENERAL,
            }],
            Bind::Storage(view) => [vk::DescriptorImageInfo {
                sampler: vk::Sampler::null(),
                image_view: *view,
                image_layout: vk::ImageLayout::GENERAL,
            }],
        })
        .collect();
    let writes: Vec<_> = binds
        .iter()
        .zip(&infos)
        .enumerate()
        .map(|(i, (b, info))| {
            vk::WriteDescriptorSet::default()
                .dst_set(set)
                .dst_binding(i as u32)
                .descriptor_type(match b {
                    Bind::Sampled(..) => vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                    Bind::Storage(..) => vk::DescriptorType::STORAGE_IMAGE,
                })
                .image_info(info)
        })
        .collect();
    unsafe { ctx.device.update_descriptor_sets(&writes, &[]) };
}

fn mip_count(size: u32) -> u32 {
    32 - size.max(1).leading_zeros()
}

const COMPUTE_RW: (vk::PipelineStageFlags2, vk::AccessFlags2) = (
    vk::PipelineStageFlags2::COMPUTE_SHADER,
    vk::AccessFlags2::from_raw(
        vk::AccessFlags2::SHADER_STORAGE_WRITE.as_raw()
            | vk::AccessFlags2::SHADER_STORAGE_READ.as_raw()
            | vk::AccessFlags2::SHADER_SAMPLED_READ.as_raw(),
    ),
);

impl Ibl {
    /// Precomputes everything for one environment; only the LUT layers the materials use.
    pub fn new(
        ctx: &Arc<Context>,
        pool: &CommandPool,
        inputs: &IblInputs<'_>,
        settings: &IblSettings,
        mut progress: impl FnMut(&str, u64, u64),
    ) -> Result<Self, VkError> {
        let equirect = &inputs.equirect;
        let sh_irradiance = &inputs.sh_irradiance;
        let rotation_deg = inputs.rotation_deg;
        let lut_geometries = inputs.lut_geometries;
        let d = &ctx.device;
        let mut times = IblTimes::default();
        let s = settings;
        let steps = 4 + s.prefilter_mips as u64 + lut_geometries.len().max(1) as u64;
        let mut step = 0u64;
        let mut tick = |name: &str, progress: &mut dyn FnMut(&str, u64, u64)| {
            step += 1;
            progress(name, step, steps);
        };

        // Upload the equirectangular image.
        let t0 = Instant::now();
        let eq = Image::new(
            ctx,
            "equirect",
            ImageDesc::texture(
                equirect.width,
                equirect.height,
                vk::Format::R32G32B32A32_SFLOAT,
                1,
                1,
            ),
        )?;
        let bytes: &[u8] = bytemuck::cast_slice(equirect.texels);
        let mut staging = Buffer::new(
            ctx,
            "equirect staging",
            bytes.len() as u64,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        staging.write(0, bytes)?;
        let sampler_eq = Sampler::linear(ctx, "equirect sampler", vk::SamplerAddressMode::REPEAT)?;
        let sampler = Sampler::linear(ctx, "ibl sampler", vk::SamplerAddressMode::CLAMP_TO_EDGE)?;
        let env_mips = mip_count(s.env_size);
        let mut env = Image::new(
            ctx,
            "environment cube",
            ImageDesc::cube(s.env_size, CUBE_FORMAT, env_mips),
        )?;
        let mut irradiance = Image::new(
            ctx,
            "irradiance cube",
            ImageDesc::cube(s.irradiance_size, CUBE_FORMAT, 1),
        )?;
        let pre_mips = s.prefilter_mips.clamp(1, mip_count(s.prefilter_size));
        let mut prefiltered = Image::new(
            ctx,
            "prefiltered cube",
            ImageDesc::cube(s.prefilter_size, CUBE_FORMAT, pre_mips),
        )?;
        let layers = lut_geometries.len().max(1) as u32;
        let mut lut_desc = ImageDesc::texture(s.lut_size, s.lut_size, LUT_FORMAT, 1, layers);
        lut_desc.usage = vk::ImageUsageFlags::SAMPLED
            | vk::ImageUsageFlags::STORAGE
            | vk::ImageUsageFlags::TRANSFER_SRC
            | vk::ImageUsageFlags::TRANSFER_DST;
        lut_desc.array = true;
        let lut = Image::new(ctx, "brdf lut", lut_desc)?;

        let k_cube = Kernel::new(
            ctx,
            "ibl/equirect_to_cube.comp",
            &[
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                vk::DescriptorType::STORAGE_IMAGE,
            ],
            16,
        )?;
        let k_down = Kernel::new(
            ctx,
            "ibl/cube_downsample.comp",
            &[
                vk::DescriptorType::STORAGE_IMAGE,
                vk::DescriptorType::STORAGE_IMAGE,
            ],
            4,
        )?;
        let k_irr = Kernel::new(
            ctx,
            "ibl/irradiance.comp",
            &[
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                vk::DescriptorType::STORAGE_IMAGE,
            ],
            16,
        )?;
        let k_pre = Kernel::new(
            ctx,
            "ibl/prefilter.comp",
            &[
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                vk::DescriptorType::STORAGE_IMAGE,
            ],
            16,
        )?;
        let k_lut = Kernel::new(
            ctx,
            "ibl/brdf_lut.comp",
            &[vk::DescriptorType::STORAGE_IMAGE],
            16,
        )?;
        let dispatches = 2 + env_mips + pre_mips + layers;
        let work_pool = DescriptorPool::new(
            ctx,
            "ibl work pool",
            dispatches,
            &[
                vk::DescriptorPoolSize {
                    ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                    descriptor_count: dispatches,
                },
                vk::DescriptorPoolSize {
                    ty: vk::DescriptorType::STORAGE_IMAGE,
                    descriptor_count: 2 * dispatches,
                },
            ],
        )?;
        times
            .stages
            .push(("setup", t0.elapsed().as_secs_f64() * 1e3));

        let general = (vk::ImageLayout::GENERAL, COMPUTE_RW.0, COMPUTE_RW.1);
        let undefined = (
            vk::ImageLayout::UNDEFINED,
            vk::PipelineStageFlags2::TOP_OF_PIPE,
            vk::AccessFlags2::NONE,
        );
        let groups = |n: u32| n.div_ceil(8);

        let (sin, cos) = rotation_deg.to_radians().sin_cos();
        // Stages 1–3 come from the cache when this environment and these settings were seen before.
        let env_file = inputs
            .cache
            .as_ref()
            .map(|(dir, key)| dir.join(format!("{key}-{}.ibl", s.describe().replace(' ', "_"))));
        let cached = env_file
            .as_deref()
            .and_then(|f| read_blob(f, &[&env, &irradiance, &prefiltered]));
        if let Some(blobs) = cached {
            let t = Instant::now();
            for (image, bytes) in [&env, &irradiance, &prefiltered].into_iter().zip(&blobs) {
                write_image(ctx, pool, image, bytes)?;
            }
            times
                .stages
                .push(("environment from cache", t.elapsed().as_secs_f64() * 1e3));
            tick("environment (cached)", &mut progress);
        } else {
            // Stage 1: upload, equirect → cube level 0, then the mip chain.
            let t = Instant::now();
            let env_views: Vec<vk::ImageView> = (0..env_mips)
                .map(|m| env.mip_view(m))
                .collect::<Result<_, _>>()?;
            let set = work_pool.allocate(&k_cube.set_layout)?;
            write_set(
                ctx,
                set,
                &[
                    Bind::Sampled(eq.view, sampler_eq.raw),
                    Bind::Storage(env_views[0]),
                ],
            );
            let down_sets: Vec<vk::DescriptorSet> = (1..env_mips)
                .map(|m| {
                    let set = work_pool.allocate(&k_down.set_layout)?;
                    write_set(
                        ctx,
                        set,
                        &[
                            Bind::Storage(env_views[m as usize - 1]),
                            Bind::Storage(env_views[m as usize]),
                        ],
                    );
                    Ok(set)
                })
                .collect::<Result<_, VkError>>()?;
            let eq_raw = eq.raw;
            let eq_range = eq.subresource_range();
            let env_raw = env.raw;
            let env_range = env.subresource_range();
            pool.one_shot(|cmd| {
                transition(
                    d,
                    cmd,
                    &[
                        Transition {
                            image: eq_raw,
                            range: eq_range,
                            from: undefined,
                            to: (
                                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                                vk::PipelineStageFlags2::COPY,
                                vk::AccessFlags2::TRANSFER_WRITE,
                            ),
                        },
                        Transition {
                            image: env_raw,
                            range: env_range,
                            from: undefined,
                            to: general,
                        },
                    ],
                );
                let region = vk::BufferImageCopy {
                    image_subresource: vk::ImageSubresourceLayers {
                        aspect_mask: vk::ImageAspectFlags::COLOR,
                        mip_level: 0,
                        base_array_layer: 0,
                        layer_count: 1,
                    },
                    image_extent: vk::Extent3D {
                        width: equirect.width,
                        height: equirect.height,
                        depth: 1,
                    },
                    ..Default::default()
                };
                unsafe {
                    d.cmd_copy_buffer_to_image(
                        cmd,
                        staging.raw,
                        eq_raw,
                        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                        &[region],
                    )
                };
                transition(
                    d,
                    cmd,
                    &[Transition {
                        image: eq_raw,
                        range: eq_range,
                        from: (
                            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                            vk::PipelineStageFlags2::COPY,
                            vk::AccessFlags2::TRANSFER_WRITE,
                        ),
                        to: general,
                    }],
                );
                let push: [u32; 4] = [cos.to_bits(), sin.to_bits(), s.env_size, 0];
                dispatch(
                    d,
                    cmd,
                    &k_cube,
                    set,
                    bytemuck::bytes_of(&push),
                    groups(s.env_size),
                    groups(s.env_size),
                    6,
                );
                for (i, set) in down_sets.iter().enumerate() {
                    memory_barrier(d, cmd, COMPUTE_RW, COMPUTE_RW);
                    let size = (s.env_size >> (i + 1)).max(1);
                    dispatch(
                        d,
                        cmd,
                        &k_down,
                        *set,
                        bytemuck::bytes_of(&size),
                        groups(size),
                        groups(size),
                        6,
                    );
                }
                Ok(())
            })?;
            drop(staging);
            times
                .stages
                .push(("environment cube + mips", t.elapsed().as_secs_f64() * 1e3));
            tick("environment cube", &mut progress);

            // Stage 2: irradiance cube.
            let t = Instant::now();
            let irr_view = irradiance.mip_view(0)?;
            let set = work_pool.allocate(&k_irr.set_layout)?;
            write_set(
                ctx,
                set,
                &[
                    Bind::Sampled(env.view, sampler.raw),
                    Bind::Storage(irr_view),
                ],
            );
            let irr_raw = irradiance.raw;
            let irr_range = irradiance.subresource_range();
            pool.one_shot(|cmd| {
                transition(
                    d,
                    cmd,
                    &[Transition {
                        image: irr_raw,
                        range: irr_range,
                        from: undefined,
                        to: general,
                    }],
                );
                memory_barrier(d, cmd, COMPUTE_RW, COMPUTE_RW);
                let push: [u32; 4] = [s.irradiance_size, s.irradiance_samples, s.env_size, 0];
                dispatch(
                    d,
                    cmd,
                    &k_irr,
                    set,
                    bytemuck::bytes_of(&push),
                    groups(s.irradiance_size),
                    groups(s.irradiance_size),
                    6,
                );
                Ok(())
            })?;
            times
                .stages
                .push(("irradiance cube", t.elapsed().as_secs_f64() * 1e3));
            tick("irradiance", &mut progress);

            // Stage 3: prefiltered cube, one roughness per mip (roughness = mip / (mips − 1)).
            let t = Instant::now();
            let pre_raw = prefiltered.raw;
            let pre_range = prefiltered.subresource_range();
            pool.one_shot(|cmd| {
                transition(
                    d,
                    cmd,
                    &[Transition {
                        image: pre_raw,
                        range: pre_range,
                        from: undefined,
                        to: general,
                    }],
                );
                Ok(())
            })?;
            for m in 0..pre_mips {
                let view = prefiltered.mip_view(m)?;
                let set = work_pool.allocate(&k_pre.set_layout)?;
                write_set(
                    ctx,
                    set,
                    &[Bind::Sampled(env.view, sampler.raw), Bind::Storage(view)],
                );
                let size = (s.prefilter_size >> m).max(1);
                let roughness = if pre_mips > 1 {
                    m as f32 / (pre_mips - 1) as f32
                } else {
                    0.0
                };
                let push: [u32; 4] = [roughness.to_bits(), size, s.prefilter_samples, s.env_size];
                pool.one_shot(|cmd| {
                    memory_barrier(d, cmd, COMPUTE_RW, COMPUTE_RW);
                    dispatch(
                        d,
                        cmd,
                        &k_pre,
                        set,
                        bytemuck::bytes_of(&push),
                        groups(size),
                        groups(size),
                        6,
                    );
                    Ok(())
                })?;
                tick("prefiltered mip", &mut progress);
            }
            times
                .stages
                .push(("prefiltered cube", t.elapsed().as_secs_f64() * 1e3));

            if let Some(f) = &env_file {
                let blobs = [&env, &irradiance, &prefiltered]
                    .into_iter()
                    .map(|image| read_image(ctx, pool, image))
                    .collect::<Result<Vec<_>, _>>()?;
                write_blob(f, &blobs);
            }
        }

        // Stage 4: BRDF LUT layers.
        let t = Instant::now();
        let lut_raw = lut.raw;
        let lut_range = lut.subresource_range();
        let lut_view = lut.view;
        let lut_layers: Vec<i32> = if lut_geometries.is_empty() {
            vec![crate::brdf::Geometry::SmithGgxCorrelated as i32]
        } else {
            lut_geometries.to_vec()
        };
        pool.one_shot(|cmd| {
            transition(
                d,
                cmd,
                &[Transition {
                    image: lut_raw,
                    range: lut_range,
                    from: undefined,
                    to: general,
                }],
            );
            Ok(())
        })?;
        let lut_file = |g: i32| {
            inputs
                .cache
                .as_ref()
                .map(|(dir, _)| dir.join(format!("lut-{}-{}-g{g}.bin", s.lut_size, s.lut_samples)))
        };
        let layer_bytes = (s.lut_size as usize).pow(2) * 16;
        let mut computed = Vec::new();
        for (layer, g) in lut_layers.iter().enumerate() {
            if let Some(bytes) = lut_file(*g).and_then(|f| std::fs::read(f).ok()) {
                if bytes.len() == layer_bytes {
                    write_lut_layer(ctx, pool, &lut, layer as u32, &bytes)?;
                    tick("brdf lut (cached)", &mut progress);
                    continue;
                }
            }
            computed.push(layer);
            let set = work_pool.allocate(&k_lut.set_layout)?;
            write_set(ctx, set, &[Bind::Storage(lut_view)]);
            let push: [u32; 4] = [s.lut_size, s.lut_samples, *g as u32, layer as u32];
            pool.one_shot(|cmd| {
                memory_barrier(d, cmd, COMPUTE_RW, COMPUTE_RW);
                dispatch(
                    d,
                    cmd,
                    &k_lut,
                    set,
                    bytemuck::bytes_of(&push),
                    groups(s.lut_size),
                    groups(s.lut_size),
                    1,
                );
                memory_barrier(
                    d,
                    cmd,
                    COMPUTE_RW,
                    (
                        vk::PipelineStageFlags2::FRAGMENT_SHADER
                            | vk::PipelineStageFlags2::VERTEX_SHADER,
                        vk::AccessFlags2::SHADER_SAMPLED_READ,
                    ),
                );
                Ok(())
            })?;
            tick("brdf lut", &mut progress);
        }
        if !computed.is_empty() && inputs.cache.is_some() {
            let all = read_image(ctx, pool, &lut)?;
            for layer in computed {
                if let Some(f) = lut_file(lut_layers[layer]) {
                    let bytes = &all[layer * layer_bytes..(layer + 1) * layer_bytes];
                    write_file_atomically(&f, bytes);
                }
            }
        }
        times
            .stages
            .push(("brdf lut", t.elapsed().as_secs_f64() * 1e3));

        // The forward pass's set 1.
        let ubo_data = EnvData {
            sh: sh_irradiance.map(|c| [c.x, c.y, c.z, 0.0]),
            rotation: [cos, sin, s.env_size as f32, env_mips as f32],
            params: [pre_mips as f32, 0.0, 0.0, 0.0],
        };
        let mut ubo = Buffer::new(
            ctx,
            "environment uniforms",
            std::mem::size_of::<EnvData>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        ubo.write(0, bytemuck::bytes_of(&ubo_data))?;
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
        unsafe { d.update_descriptor_sets(&[write], &[]) };
        drop(eq);
        drop(sampler_eq);
        Ok(Self {
            set,
            set_layout,
            _pool: set_pool,
            _ubo: ubo,
            lut_layers,
            times,
            _lut: lut,
            _prefiltered: prefiltered,
            _irradiance: irradiance,
            _env: env,
            _sampler: sampler,
        })
    }

    /// Reads the BRDF LUT back: per layer, `size`² texels of (A, B, 0, 1), row = roughness index,
    /// column = n·v index (texel centres at (i + 0.5)/size).
    pub fn read_lut(
        &self,
        ctx: &Arc<Context>,
        pool: &CommandPool,
    ) -> Result<Vec<Vec<[f32; 4]>>, VkError> {
        let texels = (self._lut.desc.width * self._lut.desc.height) as usize;
        let bytes = read_image(ctx, pool, &self._lut)?;
        let floats: Vec<f32> = bytes
            .chunks_exact(4)
            .map(|c| f32::from_ne_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        Ok(floats
            .chunks_exact(texels * 4)
            .map(|layer| {
                layer
                    .chunks_exact(4)
                    .map(|c| [c[0], c[1], c[2], c[3]])
                    .collect()
            })
            .collect())
    }

    /// The geometry selector of each LUT layer, in layer order.
    pub fn lut_geometries(&self) -> &[i32] {
        &self.lut_layers
    }

    /// The LUT layer holding `geometry`'s A, B (the first layer if that G was not computed).
    pub fn lut_layer(&self, geometry: i32) -> u32 {
        self.lut_layers
            .iter()
            .position(|&g| g == geometry)
            .unwrap_or(0) as u32
    }
}

#[allow(clippy::too_many_arguments)]
fn dispatch(
    d: &ash::Device,
    cmd: vk::CommandBuffer,
    k: &Kernel,
    set: vk::DescriptorSet,
    push: &[u8],
    x: u32,
    y: u32,
    z: u32,
) {
    unsafe {
        d.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, k.pipeline.raw);
        d.cmd_bind_descriptor_sets(
            cmd,
            vk::PipelineBindPoint::COMPUTE,
            k.layout.raw,
            0,
            &[set],
            &[],
        );
        d.cmd_push_constants(cmd, k.layout.raw, vk::ShaderStageFlags::COMPUTE, 0, push);
        d.cmd_dispatch(cmd, x, y, z);
    }
}

/// Bytes of every mip level of `image` (all layers per level, level-major), RGBA16F or RGBA32F.
fn image_bytes(image: &Image) -> Vec<(u32, u64)> {
    let d = image.desc;
    let texel = match d.format {
        vk::Format::R16G16B16A16_SFLOAT => 8u64,
        _ => 16u64,
    };
    (0..d.mip_levels)
        .map(|m| {
            let w = (d.width >> m).max(1) as u64;
            let h = (d.height >> m).max(1) as u64;
            (m, w * h * d.layers as u64 * texel)
        })
        .collect()
}

fn copy_regions(image: &Image) -> (Vec<vk::BufferImageCopy>, u64) {
    let d = image.desc;
    let mut offset = 0u64;
    let regions = image_bytes(image)
        .into_iter()
        .map(|(m, len)| {
            let r = vk::BufferImageCopy {
                buffer_offset: offset,
                image_subresource: vk::ImageSubresourceLayers {
                    aspect_mask: vk::ImageAspectFlags::COLOR,
                    mip_level: m,
                    base_array_layer: 0,
                    layer_count: d.layers,
                },
                image_extent: vk::Extent3D {
                    width: (d.width >> m).max(1),
                    height: (d.height >> m).max(1),
                    depth: 1,
                },
                ..Default::default()
            };
            offset += len;
            r
        })
        .collect();
    (regions, offset)
}

/// Reads every level and layer of an image kept in GENERAL layout.
fn read_image(ctx: &Arc<Context>, pool: &CommandPool, image: &Image) -> Result<Vec<u8>, VkError> {
    let (regions, total) = copy_regions(image);
    let buf = Buffer::new(
        ctx,
        "ibl cache readback",
        total,
        vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuToCpu,
    )?;
    let d = &ctx.device;
    let general = (vk::ImageLayout::GENERAL, COMPUTE_RW.0, COMPUTE_RW.1);
    let src = (
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        vk::PipelineStageFlags2::COPY,
        vk::AccessFlags2::TRANSFER_READ,
    );
    let (raw, range) = (image.raw, image.subresource_range());
    pool.one_shot(|cmd| {
        transition(
            d,
            cmd,
            &[Transition {
                image: raw,
                range,
                from: general,
                to: src,
            }],
        );
        unsafe {
            d.cmd_copy_image_to_buffer(
                cmd,
                raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                buf.raw,
                &regions,
            )
        };
        transition(
            d,
            cmd,
            &[Transition {
                image: raw,
                range,
                from: src,
                to: general,
            }],
        );
        memory_barrier(
            d,
            cmd,
            (
                vk::PipelineStageFlags2::COPY,
                vk::AccessFlags2::TRANSFER_WRITE,
            ),
            (vk::PipelineStageFlags2::HOST, vk::AccessFlags2::HOST_READ),
        );
        Ok(())
    })?;
    Ok(buf.mapped()?[..total as usize].to_vec())
}

/// Fills every level and layer of a fresh image from `bytes` and leaves it in GENERAL layout.
fn write_image(
    ctx: &Arc<Context>,
    pool: &CommandPool,
    image: &Image,
    bytes: &[u8],
) -> Result<(), VkError> {
    let (regions, total) = copy_regions(image);
    upload_regions(
        ctx,
        pool,
        image,
        bytes,
        total,
        &regions,
        vk::ImageLayout::UNDEFINED,
        image.subresource_range(),
    )
}

/// Fills one layer of the LUT (kept in GENERAL layout).
fn write_lut_layer(
    ctx: &Arc<Context>,
    pool: &CommandPool,
    lut: &Image,
    layer: u32,
    bytes: &[u8],
) -> Result<(), VkError> {
    let d = lut.desc;
    let region = vk::BufferImageCopy {
        image_subresource: vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: layer,
            layer_count: 1,
        },
        image_extent: vk::Extent3D {
            width: d.width,
            height: d.height,
            depth: 1,
        },
        ..Default::default()
    };
    let range = vk::ImageSubresourceRange {
        base_array_layer: layer,
        layer_count: 1,
        ..lut.subresource_range()
    };
    upload_regions(
        ctx,
        pool,
        lut,
        bytes,
        bytes.len() as u64,
        &[region],
        vk::ImageLayout::GENERAL,
        range,
    )
}

#[allow(clippy::too_many_arguments)]
fn upload_regions(
    ctx: &Arc<Context>,
    pool: &CommandPool,
    image: &Image,
    bytes: &[u8],
    total: u64,
    regions: &[vk::BufferImageCopy],
    from_layout: vk::ImageLayout,
    range: vk::ImageSubresourceRange,
) -> Result<(), VkError> {
    if bytes.len() as u64 != total {
        return Err(VkError::Setup(format!(
            "cached IBL data has {} bytes, expected {total}",
            bytes.len()
        )));
    }
    let from = if from_layout == vk::ImageLayout::UNDEFINED {
        (
            vk::ImageLayout::UNDEFINED,
            vk::PipelineStageFlags2::TOP_OF_PIPE,
            vk::AccessFlags2::NONE,
        )
    } else {
        (from_layout, COMPUTE_RW.0, COMPUTE_RW.1)
    };
    // GENERAL, visible to the compute kernels and to the forward pass's shaders.
    let to = (
        vk::ImageLayout::GENERAL,
        COMPUTE_RW.0
            | vk::PipelineStageFlags2::FRAGMENT_SHADER
            | vk::PipelineStageFlags2::VERTEX_SHADER,
        COMPUTE_RW.1,
    );
    crate::vk::image::upload(ctx, pool, image, bytes, regions, range, from, to)
}

const BLOB_MAGIC: &[u8; 8] = b"LUZIBL01";

/// The cached images of one environment, if the file exists and every size matches.
fn read_blob(path: &std::path::Path, images: &[&Image]) -> Option<Vec<Vec<u8>>> {
    let data = std::fs::read(path).ok()?;
    let rest = data.strip_prefix(BLOB_MAGIC.as_slice())?;
    let mut out = Vec::new();
    let mut pos = 0usize;
    for image in images {
        let expected: u64 = image_bytes(image).iter().map(|(_, n)| n).sum();
        let len = u64::from_le_bytes(rest.get(pos..pos + 8)?.try_into().ok()?);
        if len != expected {
            return None;
        }
        pos += 8;
        out.push(rest.get(pos..pos + len as usize)?.to_vec());
        pos += len as usize;
    }
    (pos == rest.len()).then_some(out)
}

fn write_blob(path: &std::path::Path, blobs: &[Vec<u8>]) {
    let mut data = BLOB_MAGIC.to_vec();
    for b in blobs {
        data.extend_from_slice(&(b.len() as u64).to_le_bytes());
        data.extend_from_slice(b);
    }
    write_file_atomically(path, &data);
}

/// Best effort: a cache that cannot be written is only slower next time.
fn write_file_atomically(path: &std::path::Path, bytes: &[u8]) {
    if let Some(dir) = path.parent() {
        let _ = std::fs::create_dir_all(dir);
    }
    let tmp = path.with_extension(format!("tmp{}", std::process::id()));
    if std::fs::write(&tmp, bytes).is_ok() && std::fs::rename(&tmp, path).is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
}

/// The directory luz keeps precomputed IBL data in: `$LUZ_CACHE_DIR`, else
/// `$XDG_CACHE_HOME/luz`, else `$HOME/.cache/luz`.
pub fn default_cache_dir() -> Option<std::path::PathBuf> {
    if let Some(d) = std::env::var_os("LUZ_CACHE_DIR") {
        return Some(d.into());
    }
    if let Some(d) = std::env::var_os("XDG_CACHE_HOME") {
        return Some(std::path::PathBuf::from(d).join("luz"));
    }
    std::env::var_os("HOME").map(|h| std::path::PathBuf::from(h).join(".cache/luz"))
}
