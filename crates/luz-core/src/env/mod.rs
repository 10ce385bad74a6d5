//! Image-based lighting on the CPU (no Vulkan): environment images, spherical harmonics and
//! reference integrals (MODELS.md §7).
//!
//! * [`load_equirect`] turns a scene's [`Environment`] into an [`Equirect`]: a linear-radiance
//!   latitude-longitude image in *environment space*. `intensity` is applied here;
//!   `rotation_deg` is not (it is a lookup-time rotation, [`world_to_env`]).
//! * The mapping between directions and texture coordinates ([`dir_to_uv`], [`uv_to_dir`]) is
//!   documented in `equirect.rs` and mirrored by the GLSL.
//! * [`sh9_project`], [`sh9_irradiance`], [`sh9_irradiance_coeffs`]: 9-coefficient irradiance
//!   (basis order and constants in `sh.rs`).
//! * Reference integrals for tests: [`irradiance_reference`], [`irradiance_quadrature`],
//!   [`split_sum_lut_reference`], [`prefiltered_reference`], [`specular_ibl_reference`],
//!   [`diffuse_ibl_reference`].
//! * [`fitted_lobes_specular`] and its table ([`lobe_table`]): the `fitted_lobes` specular
//!   method (two prefiltered lookups fitted to the real lobe, `lobes.rs`).
//! * [`cache_key`]: a stable key for precomputed data on disk.

mod cache;
mod equirect;
mod lobes;
mod procedural;
mod reference;
mod sh;

#[cfg(test)]
mod tests;

use std::path::PathBuf;

pub use cache::{cache_key, fnv1a64, Fnv1a, CACHE_VERSION};
pub use equirect::{
    dir_to_uv, env_rotation, env_to_world, uv_to_dir, world_to_env, Equirect, TEXEL_MAX,
};
pub use lobes::{
    fitted_lobes_specular, generate_lobe_table, lobe_direction, lobe_entry_coords, lobe_fit_error,
    lobe_layers, lobe_table, lobes_at, prefilter_level_roughness, prefiltered_lod,
    refit_lobe_entry, LOBES_FILE, LOBES_SIZE, LOBE_ENTRY,
};
pub use procedural::{
    sky, studio, GROUND_ALBEDO, SKY_HORIZON, SKY_WIDTH, SKY_ZENITH, STUDIO_FLOOR, STUDIO_WALL,
    STUDIO_WIDTH, SUN_COLOR, SUN_GLOW_FRACTION, SUN_GLOW_SIGMA_DEG, SUN_RADIUS_DEG,
};
pub use reference::{
    diffuse_ibl_reference, irradiance_quadrature, irradiance_reference, prefiltered_reference,
    specular_dominant_direction, specular_ibl_reference, split_sum_specular,
};
// The split-sum table is the BRDF's directional albedo: it lives in `brdf` (energy compensation
// reads it too); these names stay where users found them.
pub use crate::brdf::{
    g_ibl, generate_shipped_lut, shipped_lut, shipped_lut_bytes, split_sum_lut_reference,
    split_sum_lut_table, SHIPPED_LUT_FILE, SHIPPED_LUT_GEOMETRY, SHIPPED_LUT_SAMPLES,
    SHIPPED_LUT_SIZE,
};
pub use sh::{
    sh9_basis, sh9_eval, sh9_irradiance, sh9_irradiance_coeffs, sh9_project, SH_C0, SH_C1, SH_C2,
    SH_C3, SH_C4, SH_IRRADIANCE_FACTORS,
};

use crate::imageio::{self, ImageError};
use crate::scene::{EnvSource, Environment};

/// Size of the image of a uniform environment (any size would do: it is constant).
pub const UNIFORM_SIZE: (u32, u32) = (8, 4);
/// Smallest `max_dimension` [`load_equirect`] accepts.
pub const MIN_DIMENSION: u32 = 8;

/// Why an environment image could not be built. Every message names the file when there is one.
#[derive(Debug, thiserror::Error)]
pub enum EnvError {
    /// The `.hdr` / `.exr` file is missing, unreadable, corrupt or too large.
    // The message already ends with the I/O reason: no `source`, or `{e:#}` (anyhow's chain)
    // would print the reason twice ("cannot write x.png: Is a directory: Is a directory").
    #[error("{0}")]
    Image(ImageError),
    /// The file is not 2:1 (an equirectangular image spans 360° × 180°).
    #[error(
        "{}: not an equirectangular (latitude-longitude) image: {width}×{height}; expected width = 2 × height",
        .path.display()
    )]
    NotEquirect {
        path: PathBuf,
        width: u32,
        height: u32,
    },
    /// The caller's size limit is too small to be useful.
    #[error("environment size limit {0} is below the minimum of {MIN_DIMENSION} pixels")]
    LimitTooSmall(u32),
}

impl From<ImageError> for EnvError {
    fn from(e: ImageError) -> Self {
        EnvError::Image(e)
    }
}

/// What [`load_equirect`] did besides building the image (for logs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LoadReport {
    /// Size of the file's image before any downsampling (0×0 for built-in sources).
    pub source_size: (u32, u32),
    /// The downsampling factor applied to fit `max_dimension` (1: none).
    pub downsampled_by: u32,
    /// Texels whose value was changed to be finite, ≥ 0 and ≤ [`TEXEL_MAX`].
    pub sanitized_texels: u64,
}

/// Builds the environment's equirectangular image (environment space, `intensity` applied,
/// `rotation_deg` *not* applied), at most `max_dimension` texels wide and high (e.g. the
/// device's `maxImageDimension2D`):
///
/// * `hdr`: the file through [`imageio::load_radiance`] (`.hdr` or `.exr`); it must be 2:1
///   (±1 %). A file larger than `max_dimension` is halved (solid-angle-weighted 2×2 averages)
///   until it fits.
/// * `uniform`: an 8×4 constant image.
/// * `procedural` sky: [`sky`] at 1024×512; studio: [`studio`] at 512×256 (smaller when
///   `max_dimension` is).
///
/// Texels are then multiplied by `intensity` and made finite, non-negative and at most
/// [`TEXEL_MAX`] (the half-float maximum): NaN and negatives → 0, larger values and +Inf →
/// [`TEXEL_MAX`].
pub fn load_equirect(env: &Environment, max_dimension: u32) -> Result<Equirect, EnvError> {
    load_equirect_with_report(env, max_dimension).map(|(eq, _)| eq)
}

/// [`load_equirect`], also saying what was done to the image.
pub fn load_equirect_with_report(
    env: &Environment,
    max_dimension: u32,
) -> Result<(Equirect, LoadReport), EnvError> {
    let mut report = start_report(max_dimension)?;
    let fit = |w: u32| w.min(max_dimension);
    let eq = match &env.source {
        EnvSource::Hdr(path) => {
            let img = imageio::load_radiance(path)?;
            fit_radiance(img, path, max_dimension, &mut report)?
        }
        EnvSource::Uniform(c) => Equirect::filled(UNIFORM_SIZE.0, UNIFORM_SIZE.1, *c),
        EnvSource::Sky {
            sun_direction,
            sun_intensity,
        } => sky(fit(SKY_WIDTH), *sun_direction, *sun_intensity),
        EnvSource::Studio => studio(fit(STUDIO_WIDTH)),
    };
    finish(eq, env.intensity, report)
}

/// The report a load starts with (nothing done yet), once `max_dimension` is known to be usable.
fn start_report(max_dimension: u32) -> Result<LoadReport, EnvError> {
    if max_dimension < MIN_DIMENSION {
        return Err(EnvError::LimitTooSmall(max_dimension));
    }
    Ok(LoadReport {
        downsampled_by: 1,
        ..LoadReport::default()
    })
}

/// [`load_equirect_with_report`] for an `hdr` environment whose file is already in memory:
/// `name` gives the format (`.hdr` or `.exr`, by extension) and names it in errors; `limits`
/// are the decoder's size limits ([`imageio::SizeLimits::DEFAULT`] for files).
pub fn load_equirect_bytes(
    bytes: &[u8],
    name: &std::path::Path,
    intensity: f32,
    max_dimension: u32,
    limits: &imageio::SizeLimits,
) -> Result<(Equirect, LoadReport), EnvError> {
    let mut report = start_report(max_dimension)?;
    let img = imageio::load_radiance_bytes(bytes, name, limits)?;
    let eq = fit_radiance(img, name, max_dimension, &mut report)?;
    finish(eq, intensity, report)
}

/// Checks that a decoded environment file is 2:1, sanitises it and halves it until it fits
/// `max_dimension`.
fn fit_radiance(
    img: imageio::LinearImage,
    path: &std::path::Path,
    max_dimension: u32,
    report: &mut LoadReport,
) -> Result<Equirect, EnvError> {
    let (w, h) = (img.width, img.height);
    report.source_size = (w, h);
    let ratio = f64::from(w) / f64::from(h);
    if (ratio - 2.0).abs() > 0.02 {
        return Err(EnvError::NotEquirect {
            path: path.to_path_buf(),
            width: w,
            height: h,
        });
    }
    let mut eq = Equirect {
        width: w,
        height: h,
        texels: img.pixels,
    };
    // Sanitise before averaging so one NaN cannot spread over a block.
    report.sanitized_texels = eq.sanitize();
    let mut k = 1;
    while eq.width.div_ceil(k) > max_dimension || eq.height.div_ceil(k) > max_dimension {
        k *= 2;
    }
    if k > 1 {
        eq = eq.downsample(k);
        report.downsampled_by = k;
    }
    Ok(eq)
}

/// Applies the intensity and makes every texel finite, non-negative and at most [`TEXEL_MAX`].
fn finish(
    mut eq: Equirect,
    intensity: f32,
    mut report: LoadReport,
) -> Result<(Equirect, LoadReport), EnvError> {
    if intensity != 1.0 {
        eq.scale(intensity);
    }
    report.sanitized_texels += eq.sanitize();
    Ok((eq, report))
}
