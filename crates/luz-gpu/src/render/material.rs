//! Per-material GPU data (descriptor set 2 of the forward pass): the texture maps of the
//! metallic-roughness workflow (uploaded with their CPU-built mip chains), one sampler per map,
//! and a small uniform block (emissive factor, normal scale, occlusion strength, which maps exist).
//! Materials without maps bind 1×1 neutral textures, so every pipeline sees the same layout.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::scene::{Filter, Scene, TextureSlot, Wrap};
use crate::texture::{ColorSpace, TexFormat, TextureData};
use crate::vk::cmd::CommandPool;
use crate::vk::image::{ImageDesc, Sampler};
use crate::vk::pipeline::{DescriptorPool, DescriptorSetLayout};
use crate::vk::{Buffer, Context, Image, SetWrites, VkError};

pub const SET_MATERIAL: u32 = crate::glsl::include_bindings::SET_MATERIAL as u32;
/// Bindings 0..22: one combined image sampler per [`TextureSlot::ALL`] entry, in that order.
pub const SLOT_COUNT: usize = 22;

/// Bit i set when `textures` has map `TextureSlot::ALL[i]` (the shader's `MAPS`/`present`).
pub fn map_bits(textures: &crate::scene::MaterialTextures) -> u32 {
    TextureSlot::ALL
        .iter()
        .take(SLOT_COUNT)
        .enumerate()
        .filter(|(_, s)| textures.get(**s).is_some())
        .fold(0, |bits, (i, _)| bits | 1 << i)
}
/// The binding of `MaterialExtra` (after the maps, whose bindings are their `MAP_*` slots).
pub const BINDING_EXTRA: u32 = crate::glsl::include_bindings::BINDING_MATERIAL_EXTRA as u32;

/// `MaterialExtra` (std140) in `shaders_glsl/include/bindings.glsl`.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable, Debug, Default)]
pub struct MaterialExtra {
    /// Emitted radiance factor (rgb).
    pub emissive: [f32; 4],
    /// normal_scale, occlusion_strength, alpha factor, alpha cutoff (MASK; 0 otherwise).
    pub params: [f32; 4],
    /// x: bit i set when map `TextureSlot::ALL[i]` is present.
    pub present: [u32; 4],
    /// Glass ([`MaterialExtra::glass`]): thickness (mesh units), dispersion; the iridescence
    /// thickness map's minimum (nm), –.
    pub volume: [f32; 4],
    /// The volume's attenuation coefficient σ per unit length (rgb); the clear coat normal
    /// map's scale (with maps).
    pub attenuation: [f32; 4],
    /// `diffuseTransmissionColorFactor` (rgb), –.
    pub diffuse_transmission: [f32; 4],
}

impl MaterialExtra {
    /// The block of a material without maps (`present` 0): emission, normal scale, occlusion
    /// strength, as [`MaterialSets::new`] writes it.
    pub fn without_maps(m: &crate::scene::NamedMaterial) -> Self {
        let t = &m.textures;
        Self {
            emissive: t.emissive_factor.extend(0.0).to_array(),
            params: Self::params(t),
            present: [0; 4],
            ..Self::default()
        }
        .glass(&m.material)
    }

    /// With the glass parameters of `model` (zero for a material that transmits nothing; σ
    /// finite: a channel that lets nothing through gets a large coefficient instead of ∞), and
    /// the iridescence thickness map's minimum (`volume.z`, nm: the thickness at texel 0).
    pub fn glass(self, model: &crate::brdf::Model) -> Self {
        let crate::brdf::Model::MetalRough(p) = model.sanitized() else {
            return self;
        };
        let t = p.transmission;
        let sigma = t.sigma().min(glam::Vec3::splat(1e30));
        Self {
            volume: [t.thickness, t.dispersion, p.iridescence_thickness_min, 0.0],
            attenuation: sigma.extend(0.0).to_array(),
            diffuse_transmission: t.diffuse_color.extend(0.0).to_array(),
            ..self
        }
    }

    /// `params`: normal scale, occlusion strength, alpha factor and alpha cutoff of `t`.
    pub fn params(t: &crate::scene::MaterialTextures) -> [f32; 4] {
        let cutoff = match t.alpha_mode {
            crate::scene::AlphaMode::Mask { cutoff } => cutoff,
            _ => 0.0,
        };
        [t.normal_scale, t.occlusion_strength, t.alpha, cutoff]
    }
}

pub struct MaterialSets {
    pub set_layout: DescriptorSetLayout,
    /// One descriptor set per scene material, by material index.
    pub sets: Vec<vk::DescriptorSet>,
    /// Texture maps uploaded (not counting the neutral defaults).
    pub texture_count: usize,
    _pool: DescriptorPool,
    _extra: Buffer,
    _images: Vec<Image>,
    _samplers: Vec<Sampler>,
}

fn vk_format(f: TexFormat) -> vk::Format {
    match f {
        TexFormat::Rgba8Srgb => vk::Format::R8G8B8A8_SRGB,
        TexFormat::Rgba8Unorm => vk::Format::R8G8B8A8_UNORM,
        TexFormat::Rgba16F => vk::Format::R16G16B16A16_SFLOAT,
        TexFormat::Rgba32F => vk::Format::R32G32B32A32_SFLOAT,
    }
}

fn wrap(w: Wrap) -> vk::SamplerAddressMode {
    match w {
        Wrap::Repeat => vk::SamplerAddressMode::REPEAT,
        Wrap::Clamp => vk::SamplerAddressMode::CLAMP_TO_EDGE,
        Wrap::Mirror => vk::SamplerAddressMode::MIRRORED_REPEAT,
    }
}

fn filter(f: Filter) -> vk::Filter {
    match f {
        Filter::Nearest => vk::Filter::NEAREST,
        Filter::Linear => vk::Filter::LINEAR,
    }
}

/// Uploads a texture with all its mip levels and leaves it in SHADER_READ_ONLY_OPTIMAL.
fn upload(
    ctx: &Arc<Context>,
    pool: &CommandPool,
    name: &str,
    data: &TextureData,
) -> Result<Image, VkError> {
    let levels = data.mips.len().max(1) as u32;
    let image = Image::new(
        ctx,
        name,
        ImageDesc::texture(data.width, data.height, vk_format(data.format), levels, 1),
    )?;
    let mut regions = Vec::with_capacity(data.mips.len());
    let mut offset = 0u64;
    for level in 0..data.mips.len() {
        let (w, h) = data.level_extent(level);
        regions.push(crate::vk::image::color_region(level as u32, offset, (w, h)));
        offset += data.mips[level].len() as u64;
    }
    let bytes = data.mips.concat();
    crate::vk::image::upload(
        ctx,
        pool,
        &image,
        &bytes,
        &regions,
        image.subresource_range(),
        (
            vk::ImageLayout::UNDEFINED,
            vk::PipelineStageFlags2::TOP_OF_PIPE,
            vk::AccessFlags2::NONE,
        ),
        (
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            vk::PipelineStageFlags2::VERTEX_SHADER | vk::PipelineStageFlags2::FRAGMENT_SHADER,
            vk::AccessFlags2::SHADER_SAMPLED_READ,
        ),
    )?;
    Ok(image)
}

fn neutral(texel: [u8; 4]) -> TextureData {
    TextureData {
        width: 1,
        height: 1,
        format: TexFormat::Rgba8Unorm,
        mips: vec![texel.to_vec()],
    }
}

impl MaterialSets {
    /// Uploads every map the scene's materials name, decoded by `prepared` (a map it lacks, or
    /// decoded under another size limit, is loaded here; warnings such as downscaled textures
    /// go to `warn`).
    pub fn new(
        ctx: &Arc<Context>,
        pool: &CommandPool,
        (scene, prepared): (&Scene, &crate::prepare::PreparedScene),
        warn: &mut dyn FnMut(String),
    ) -> Result<Self, VkError> {
        let set_layout = crate::render::sets::scene_interface()?.set_layout(ctx, SET_MATERIAL)?;
        let n = scene.materials.len().max(1) as u32;
        let desc_pool = DescriptorPool::for_sets(ctx, "material pool", &[(&set_layout, n)])?;

        let limits = &ctx.info.limits;
        // The limits in force (tests tighten them to reach the downscale path).
        let max_dim = ctx.limits().max_image_dimension_2d;
        let anisotropy_supported = ctx.info.sampler_anisotropy;
        let mut images = Vec::new();
        let mut samplers = Vec::new();
        // Neutral defaults: white (multiplies by 1), a flat normal.
        images.push(upload(ctx, pool, "neutral white", &neutral([255; 4]))?);
        images.push(upload(
            ctx,
            pool,
            "neutral normal",
            &neutral([128, 128, 255, 255]),
        )?);
        samplers.push(Sampler::linear(
            ctx,
            "neutral sampler",
            vk::SamplerAddressMode::REPEAT,
        )?);
        let (white, flat, neutral_sampler) = (images[0].view, images[1].view, samplers[0].raw);

        let align = limits.min_uniform_buffer_offset_alignment.max(16);
        let stride = (std::mem::size_of::<MaterialExtra>() as u64).div_ceil(align) * align;
        let mut extra = Buffer::new(
            ctx,
            "material extras",
            stride * n as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        let mut sets = Vec::with_capacity(n as usize);
        let mut texture_count = 0;
        for (mi, m) in scene.materials.iter().enumerate() {
            let t = &m.textures;
            let mut views = [(white, neutral_sampler); SLOT_COUNT];
            views[TextureSlot::ALL
                .iter()
                .position(|s| *s == TextureSlot::Normal)
                .unwrap_or(0)] = (flat, neutral_sampler);
            let mut present = 0u32;
            for (i, slot) in TextureSlot::ALL.iter().enumerate().take(SLOT_COUNT) {
                let Some(r) = t.get(*slot) else { continue };
                let loaded;
                let data = match prepared
                    .texture(r, *slot)
                    .filter(|_| prepared.max_texture_dimension() == max_dim)
                {
                    Some(d) => d.as_ref(),
                    None => {
                        let space = ColorSpace::for_slot(*slot);
                        loaded = crate::texture::load_texture(r, space, max_dim, warn)
                            .map_err(|e| VkError::Setup(format!("material \"{}\": {e}", m.name)))?;
                        &loaded
                    }
                };
                let image = upload(ctx, pool, &format!("{} {:?} map", m.name, slot), data)?;
                let s = &r.sampler;
                let mut info = vk::SamplerCreateInfo::default()
                    .mag_filter(filter(s.mag))
                    .min_filter(filter(s.min))
                    .mipmap_mode(if s.min == Filter::Linear {
                        vk::SamplerMipmapMode::LINEAR
                    } else {
                        vk::SamplerMipmapMode::NEAREST
                    })
                    .address_mode_u(wrap(s.wrap_u))
                    .address_mode_v(wrap(s.wrap_v))
                    .address_mode_w(vk::SamplerAddressMode::REPEAT)
                    .max_lod(vk::LOD_CLAMP_NONE);
                if let Some(a) =
                    s.anisotropy_for(anisotropy_supported, limits.max_sampler_anisotropy)
                {
                    info = info.anisotropy_enable(true).max_anisotropy(a);
                }
                let sampler = Sampler::new(ctx, &format!("{} {:?} sampler", m.name, slot), &info)?;
                views[i] = (image.view, sampler.raw);
                present |= 1 << i;
                images.push(image);
                samplers.push(sampler);
                texture_count += 1;
            }
            let data = MaterialExtra {
                emissive: t.emissive_factor.extend(0.0).to_array(),
                params: MaterialExtra::params(t),
                present: [present, 0, 0, 0],
                ..MaterialExtra::default()
            }
            .glass(&m.material);
            let data = MaterialExtra {
                attenuation: [
                    data.attenuation[0],
                    data.attenuation[1],
                    data.attenuation[2],
                    t.clearcoat_normal_scale,
                ],
                ..data
            };
            extra.write(stride * mi as u64, bytemuck::bytes_of(&data))?;
            let set = desc_pool.allocate(&set_layout)?;
            let layout = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
            let writes = views
                .iter()
                .enumerate()
                .fold(
                    SetWrites::new(&set_layout, set),
                    |w, (i, (view, sampler))| w.image(i as u32, *view, layout, *sampler),
                )
                .buffer_range(
                    BINDING_EXTRA,
                    extra.raw,
                    stride * mi as u64,
                    std::mem::size_of::<MaterialExtra>() as u64,
                );
            // SAFETY: `set` was just allocated and no command buffer has used it. Every view and
            // sampler is alive — owned by `images` and `samplers`, which the returned struct
            // keeps — and the uniform range lies inside `extra` at an offset aligned to
            // minUniformBufferOffsetAlignment (`stride`).
            unsafe { writes.apply(ctx) }?;
            sets.push(set);
        }
        Ok(Self {
            set_layout,
            sets,
            texture_count,
            _pool: desc_pool,
            _extra: extra,
            _images: images,
            _samplers: samplers,
        })
    }
}
