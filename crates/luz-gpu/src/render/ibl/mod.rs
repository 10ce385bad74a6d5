//! Image-based lighting precomputation on the GPU (MODELS.md §7): the environment as a cube with a
//! full mip chain (for PDF-based LOD), a cosine-convolved irradiance cube, a GGX-prefiltered cube
//! (one roughness per mip) and the split-sum BRDF LUT (one layer per geometry term a material uses).
//! The 9 spherical-harmonic irradiance coefficients come from the CPU (`crate::env`).

mod bake;
mod cache;
mod set;
pub mod shipped;

pub use cache::default_cache_dir;

use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use glam::Vec3;

use crate::vk::cmd::CommandPool;
use crate::vk::image::{ImageDesc, Sampler};
use crate::vk::pipeline::{DescriptorPool, DescriptorSetLayout};
use crate::vk::{Buffer, Context, Image, VkError};

use bake::{mip_count, Baker, Equirect};
use cache::{
    blobs_of, read_blob, read_blobs, read_image, write_blob, write_file, write_image,
    write_lut_layer,
};
use set::EnvSet;

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
    /// Use the data shipped with luz where it applies: the BRDF table when the LUT's size,
    /// samples and geometry term are the shipped ones (`crate::env::shipped_lut`), and the
    /// default scene's environment at the default sizes in place of a missing cache entry
    /// ([`shipped`]). False computes everything on the GPU (tests compare the two).
    pub shipped: bool,
}

impl Default for IblSettings {
    /// 64² irradiance, 512² prefiltered cube with 8 mips (down to 4², roughness 1) at 1024
    /// samples per texel, 512² LUT at 1024 samples. The well-known Vulkan PBR sample luz compares
    /// itself with bakes 10 mips at 64 samples; issue 37 measured what that costs in accuracy:
    /// a first version of the fitted lobes against Mitsuba went from 3.8 / 5.7 / 8.9 % (α 0.1 /
    /// 0.3 / 0.6, 10 mips, 64 samples) to 3.3 / 3.0 / 1.4 % (docs/accuracy.md): the last two mips'
    /// 2² and 1² faces cannot hold a wide lobe, and 64 filtered samples blur it wider than the
    /// kernel.
    fn default() -> Self {
        Self {
            env_size: 512,
            irradiance_size: 64,
            irradiance_samples: 256,
            prefilter_size: 512,
            prefilter_mips: 8,
            prefilter_samples: 1024,
            lut_size: 512,
            lut_samples: 1024,
            shipped: true,
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
            prefilter_mips: 6,
            prefilter_samples: 256,
            lut_size: 128,
            lut_samples: 512,
            shipped: true,
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
    /// Prefiltered cube mip count, the fitted lobes' first LUT layer, the anisotropic split
    /// sum's first LUT layer (`brdf::aniso_lut_tiles`), 0.
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
    /// Whether a material has KHR_materials_anisotropy's lobe: the LUT then holds its split
    /// sum in extra layers after the fitted lobes' (`brdf::aniso_lut_layers`).
    pub anisotropy: bool,
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

/// The LUT layers of the anisotropic lobe's split sum: its tiles at `s.lut_size` when `inputs`
/// has anisotropy, else none.
fn aniso_layers(s: &IblSettings, inputs: &IblInputs<'_>) -> u32 {
    if inputs.anisotropy {
        crate::brdf::aniso_lut_tiles(s.lut_size).1 as u32
    } else {
        0
    }
}

/// The four images the precomputation fills, with their mip and layer counts.
struct Images {
    env: Image,
    irradiance: Image,
    prefiltered: Image,
    lut: Image,
    env_mips: u32,
    pre_mips: u32,
    layers: u32,
}

impl Images {
    /// Creates them at `s`'s sizes, one LUT layer per geometry selector (at least one).
    fn new(ctx: &Arc<Context>, s: &IblSettings, inputs: &IblInputs<'_>) -> Result<Self, VkError> {
        let lut_geometries = inputs.lut_geometries;
        let env_mips = mip_count(s.env_size);
        let env = Image::new(
            ctx,
            "environment cube",
            ImageDesc::cube(s.env_size, CUBE_FORMAT, env_mips),
        )?;
        let irradiance = Image::new(
            ctx,
            "irradiance cube",
            ImageDesc::cube(s.irradiance_size, CUBE_FORMAT, 1),
        )?;
        let pre_mips = s.prefilter_mips.clamp(1, mip_count(s.prefilter_size));
        let prefiltered = Image::new(
            ctx,
            "prefiltered cube",
            ImageDesc::cube(s.prefilter_size, CUBE_FORMAT, pre_mips),
        )?;
        // One layer per geometry selector, then the fitted lobes' two (`env::lobe_layers`), then
        // the anisotropic lobe's split sum when a material has one.
        let layers = lut_geometries.len().max(1) as u32 + 2 + aniso_layers(s, inputs);
        let mut lut_desc = ImageDesc::texture(s.lut_size, s.lut_size, LUT_FORMAT, 1, layers);
        lut_desc.usage = vk::ImageUsageFlags::SAMPLED
            | vk::ImageUsageFlags::STORAGE
            | vk::ImageUsageFlags::TRANSFER_SRC
            | vk::ImageUsageFlags::TRANSFER_DST;
        lut_desc.array = true;
        let lut = Image::new(ctx, "brdf lut", lut_desc)?;
        Ok(Self {
            env,
            irradiance,
            prefiltered,
            lut,
            env_mips,
            pre_mips,
            layers,
        })
    }

    /// Stages 1–3: the environment cube with its mips, the irradiance cube and the prefiltered
    /// cube, from `env_file` when it holds them, else computed (and written there).
    #[allow(clippy::too_many_arguments)]
    fn environment(
        &mut self,
        baker: &Baker<'_>,
        eq: &Equirect,
        staging: Buffer,
        sampler: &Sampler,
        rotation: (f32, f32),
        env_file: Option<&std::path::Path>,
        times: &mut IblTimes,
        tick: &mut dyn FnMut(&str),
    ) -> Result<(), VkError> {
        let (ctx, pool) = (baker.ctx, baker.pool);
        let images = [&self.env, &self.irradiance, &self.prefiltered];
        let t = Instant::now();
        let mut from = "environment from cache";
        let cached = env_file.and_then(|f| {
            read_blob(f, &images).or_else(|| {
                from = "environment shipped";
                // The default scene's environment ships with luz: a cache entry filled at once.
                let file = shipped::environment(f, baker.s)?;
                let blobs = blobs_of(&file, &images)?;
                write_file(f, &file);
                Some(blobs)
            })
        });
        if let Some(blobs) = cached {
            for (image, bytes) in [&self.env, &self.irradiance, &self.prefiltered]
                .into_iter()
                .zip(&blobs)
            {
                write_image(ctx, pool, image, bytes)?;
            }
            times.stages.push((from, t.elapsed().as_secs_f64() * 1e3));
            tick("environment (cached)");
        } else {
            // Stage 1: upload, equirect → cube level 0, then the mip chain.
            let t = Instant::now();
            baker.environment_cube(eq, staging, &mut self.env, self.env_mips, rotation)?;
            times
                .stages
                .push(("environment cube + mips", t.elapsed().as_secs_f64() * 1e3));
            tick("environment cube");

            // Stage 2: irradiance cube.
            let t = Instant::now();
            baker.irradiance(&self.env, sampler, &mut self.irradiance)?;
            times
                .stages
                .push(("irradiance cube", t.elapsed().as_secs_f64() * 1e3));
            tick("irradiance");

            // Stage 3: prefiltered cube, one roughness per mip (`env::prefilter_level_roughness`).
            let t = Instant::now();
            baker.prefilter(
                &self.env,
                sampler,
                &mut self.prefiltered,
                self.pre_mips,
                tick,
            )?;
            times
                .stages
                .push(("prefiltered cube", t.elapsed().as_secs_f64() * 1e3));

            if let Some(f) = env_file {
                let blobs = [&self.env, &self.irradiance, &self.prefiltered]
                    .into_iter()
                    .map(|image| read_image(ctx, pool, image))
                    .collect::<Result<Vec<_>, _>>()?;
                write_blob(f, &blobs.iter().map(Vec::as_slice).collect::<Vec<_>>());
            }
        }
        Ok(())
    }

    /// Stage 4: the BRDF LUT, one layer per geometry selector the materials use (correlated Smith
    /// GGX when they name none), each from the cache when it holds it (and written there when
    /// computed). Returns the selectors in layer order.
    fn brdf_lut(
        &self,
        baker: &Baker<'_>,
        inputs: &IblInputs<'_>,
        times: &mut IblTimes,
        tick: &mut dyn FnMut(&str),
    ) -> Result<Vec<i32>, VkError> {
        let (ctx, pool, s) = (baker.ctx, baker.pool, baker.s);
        let lut_geometries = inputs.lut_geometries;
        let lut = &self.lut;
        let t = Instant::now();
        let lut_layers: Vec<i32> = if lut_geometries.is_empty() {
            vec![crate::brdf::Geometry::SmithGgxCorrelated as i32]
        } else {
            lut_geometries.to_vec()
        };
        baker.to_general(lut)?;
        let lut_file = |g: i32| cache::lut_file(inputs, s, g);
        let layer_bytes = (s.lut_size as usize).pow(2) * 16;
        let mut computed = Vec::new();
        for (layer, g) in lut_layers.iter().enumerate() {
            // The default settings' table for the default geometry term ships with luz.
            let shipped = s
                .shipped
                .then(|| crate::env::shipped_lut(s.lut_size, s.lut_samples, *g));
            if let Some(entries) = shipped.flatten() {
                let bytes: Vec<u8> = entries
                    .iter()
                    .flatten()
                    .flat_map(|x| x.to_ne_bytes())
                    .collect();
                write_lut_layer(ctx, pool, lut, layer as u32, &bytes)?;
                tick("brdf lut (shipped)");
                continue;
            }
            let cached = lut_file(*g).and_then(|f| read_blobs(&f, &[layer_bytes as u64]).hit(&f));
            if let Some(bytes) = cached.as_ref().and_then(|blobs| blobs.first()) {
                write_lut_layer(ctx, pool, lut, layer as u32, bytes)?;
                tick("brdf lut (cached)");
                continue;
            }
            computed.push(layer);
            baker.brdf_lut_layer(lut, *g, layer as u32)?;
            tick("brdf lut");
        }
        // The last two layers: the `fitted_lobes` method's table at the LUT's texel centres.
        for (k, layer) in crate::env::lobe_layers(s.lut_size).iter().enumerate() {
            let bytes: Vec<u8> = layer
                .iter()
                .flatten()
                .flat_map(|v| v.to_ne_bytes())
                .collect();
            write_lut_layer(ctx, pool, lut, (lut_layers.len() + k) as u32, &bytes)?;
        }
        // Then the anisotropic lobe's split sum, as tiles (computed once per process).
        if aniso_layers(s, inputs) > 0 {
            for (k, layer) in crate::brdf::aniso_lut_layers(s.lut_size).iter().enumerate() {
                let bytes: Vec<u8> = layer
                    .iter()
                    .flatten()
                    .flat_map(|v| v.to_ne_bytes())
                    .collect();
                write_lut_layer(ctx, pool, lut, (lut_layers.len() + 2 + k) as u32, &bytes)?;
            }
        }
        if !computed.is_empty() && inputs.cache.is_some() {
            let all = read_image(ctx, pool, lut)?;
            for layer in computed {
                if let Some(f) = lut_file(lut_layers[layer]) {
                    let bytes = &all[layer * layer_bytes..(layer + 1) * layer_bytes];
                    write_blob(&f, &[bytes]);
                }
            }
        }
        times
            .stages
            .push(("brdf lut", t.elapsed().as_secs_f64() * 1e3));
        Ok(lut_layers)
    }
}

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
        let mut times = IblTimes::default();
        let s = settings;
        let steps = 4 + s.prefilter_mips as u64 + lut_geometries.len().max(1) as u64;
        let mut step = 0u64;
        let mut tick = |name: &str| {
            step += 1;
            progress(name, step, steps);
        };

        // Upload the equirectangular image.
        let t0 = Instant::now();
        let (eq, staging) = Equirect::upload(ctx, equirect)?;
        let sampler = Sampler::linear(ctx, "ibl sampler", vk::SamplerAddressMode::CLAMP_TO_EDGE)?;
        let mut images = Images::new(ctx, s, inputs)?;
        let dispatches = 2 + images.env_mips + images.pre_mips + images.layers - 2;
        let baker = Baker::new(ctx, pool, s, dispatches)?;
        times
            .stages
            .push(("setup", t0.elapsed().as_secs_f64() * 1e3));

        let (sin, cos) = rotation_deg.to_radians().sin_cos();
        // Stages 1–3 come from the cache when this environment and these settings were seen before.
        let env_file = cache::env_file(inputs, s);
        images.environment(
            &baker,
            &eq,
            staging,
            &sampler,
            (cos, sin),
            env_file.as_deref(),
            &mut times,
            &mut tick,
        )?;
        let lut_layers = images.brdf_lut(&baker, inputs, &mut times, &mut tick)?;

        // The forward pass's set 1.
        let ubo_data = EnvData {
            sh: sh_irradiance.map(|c| [c.x, c.y, c.z, 0.0]),
            rotation: [cos, sin, s.env_size as f32, images.env_mips as f32],
            // The fitted lobes' first layer, the anisotropic split sum's first layer.
            params: [
                images.pre_mips as f32,
                lut_layers.len() as f32,
                lut_layers.len() as f32 + 2.0,
                0.0,
            ],
        };
        let env_set = EnvSet::new(
            ctx,
            &ubo_data,
            [
                &images.env,
                &images.irradiance,
                &images.prefiltered,
                &images.lut,
            ],
            &sampler,
        )?;
        drop(eq);
        let Images {
            env,
            irradiance,
            prefiltered,
            lut,
            ..
        } = images;
        Ok(Self {
            set: env_set.set,
            set_layout: env_set.set_layout,
            _pool: env_set.pool,
            _ubo: env_set.ubo,
            lut_layers,
            times,
            _lut: lut,
            _prefiltered: prefiltered,
            _irradiance: irradiance,
            _env: env,
            _sampler: sampler,
        })
    }
    /// Reads the BRDF LUT back (the geometry layers, then the fitted lobes' layer): per layer, `size`² texels of (A, B, 0, 1), row = roughness index,
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
