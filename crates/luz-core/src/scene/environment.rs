//! The scene's `environment` block: image-based lighting settings (plain data; decoded in
//! `decode/environment.rs`, turned into an image by `crate::env`).

use std::path::PathBuf;

use glam::Vec3;

/// Image-based lighting: where the environment's radiance comes from and how the renderer
/// integrates it. `crate::env` turns it into an equirectangular image ([`crate::env::Equirect`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Environment {
    pub source: EnvSource,
    /// Multiplies the source's radiance (applied when the image is built). ≥ 0, default 1.
    pub intensity: f32,
    /// Rotation of the environment about +y in degrees (right-handed: positive turns +z towards
    /// +x). Not baked into the image: applied at lookup (`crate::env::world_to_env`). Default 0.
    pub rotation_deg: f32,
    /// How the specular part of image-based lighting is integrated. Default split sum.
    pub specular_method: SpecularMethod,
    /// Samples per pixel of [`SpecularMethod::Importance`], 1..=1024. Default 64.
    pub samples: u32,
    /// How diffuse irradiance is represented. Default 9 SH coefficients.
    pub diffuse_method: DiffuseMethod,
    /// Multiple-scattering energy compensation of the specular lobe. Default false.
    pub energy_compensation: bool,
    /// Importance sampling reads a mip level chosen from the sample's PDF (filtered importance
    /// sampling) instead of the full-resolution image. Default true.
    pub mip_filtered_samples: bool,
    /// Draw the environment as the background (skybox) instead of `output.background`.
    /// Default true.
    pub show_background: bool,
}

impl Environment {
    /// Every setting at its default, for the given source.
    pub fn new(source: EnvSource) -> Self {
        Environment {
            source,
            intensity: 1.0,
            rotation_deg: 0.0,
            specular_method: SpecularMethod::FittedLobes,
            samples: DEFAULT_ENV_SAMPLES,
            diffuse_method: DiffuseMethod::Sh9,
            energy_compensation: false,
            mip_filtered_samples: true,
            show_background: true,
        }
    }
}

/// Default `samples` of an environment.
pub const DEFAULT_ENV_SAMPLES: u32 = 64;
/// Largest `samples` of an environment.
pub const MAX_ENV_SAMPLES: u32 = 1024;
/// Largest `sun_intensity` of the procedural sky: keeps the sun disc's radiance below the largest
/// half float (see `crate::env::SUN_RADIUS_DEG`).
pub const MAX_SUN_INTENSITY: f32 = 50.0;

/// Where an environment's radiance comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum EnvSource {
    /// An equirectangular (latitude-longitude) image, Radiance `.hdr` or OpenEXR `.exr`, linear
    /// radiance. Resolved against the scene file's folder; its existence and header are checked
    /// when the scene loads, its pixels are read by `crate::env::load_equirect`.
    Hdr(PathBuf),
    /// The same radiance from every direction (linear RGB, ≥ 0): furnace tests.
    Uniform(Vec3),
    /// The procedural sky: a gradient sky, a ground and a sun disc (`crate::env` documents the
    /// numbers).
    Sky {
        /// Unit vector, the way sunlight travels (like a directional light's `direction`); the
        /// sun is seen in the direction `−sun_direction`, never below the horizon
        /// (`sun_direction.y ≤ 0`).
        sun_direction: Vec3,
        /// Irradiance of the sun disc on a surface facing it, in [0, 50]; the disc is white-ish
        /// (`crate::env::SUN_COLOR`).
        sun_intensity: f32,
    },
    /// The procedural studio: a dark grey room with four soft area-like lights (key, fill, rim,
    /// top).
    Studio,
}

impl EnvSource {
    /// The source's name as in the scene format: "hdr", "uniform", "sky", "studio".
    pub fn kind_name(&self) -> &'static str {
        match self {
            EnvSource::Hdr(_) => "hdr",
            EnvSource::Uniform(_) => "uniform",
            EnvSource::Sky { .. } => "sky",
            EnvSource::Studio => "studio",
        }
    }
}

/// Default sun direction of the procedural sky (the way the light travels, normalised on use):
/// the sun stands about 50° high, to the right of and behind a camera looking down −z.
pub const DEFAULT_SUN_DIRECTION: Vec3 = Vec3::new(-0.4, -0.75, -0.5);
/// Default sun irradiance of the procedural sky.
pub const DEFAULT_SUN_INTENSITY: f32 = 3.0;

/// Specular image-based lighting.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum SpecularMethod {
    /// Importance-sampled GGX with `samples` samples per pixel (MODELS.md §7).
    Importance,
    /// Karis's split sum: prefiltered environment × (F0·A + B) from a 2D table.
    SplitSum,
    /// Two lookups of the same prefiltered environment (along two directions in the plane of the
    /// normal and the view), at roughnesses and with a weight from a table fitted to
    /// the real lobe (`crate::env::fitted_lobes_specular`), × (F0·A + B). The default since
    /// issue 37: 1.7–5.6× closer to Mitsuba than the split sum on gold spheres (docs/accuracy.md).
    #[default]
    FittedLobes,
}

crate::brdf::selector_names!(SpecularMethod {
    Importance => "importance",
    SplitSum => "split_sum",
    FittedLobes => "fitted_lobes",
});

/// Diffuse image-based lighting.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum DiffuseMethod {
    /// Irradiance from 9 spherical-harmonic coefficients (`crate::env::sh9_irradiance`).
    #[default]
    Sh9,
    /// Irradiance from a cosine-convolved cubemap.
    Cubemap,
}

crate::brdf::selector_names!(DiffuseMethod { Sh9 => "sh9", Cubemap => "cubemap" });
