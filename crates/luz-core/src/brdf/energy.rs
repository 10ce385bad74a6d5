//! Energy compensation of the metal-rough model (the environment's `energy_compensation`): the
//! GGX lobe loses the energy of its multiple scattering, most at high roughness, and the diffuse
//! under it was not weighted by what the specular already reflects, so a white dielectric in a
//! white furnace returned 1.04 at the centre and 1.14 at the rim (issue 34).
//!
//! With `E(μ) = A + B` and `E_ss(μ) = F0·A + B` from the split-sum table ([`split_sum_ab`], the
//! same table the GPU's `brdf_lut` holds):
//! * the specular lobe is scaled by `1 + F0 (1 − E)/E` (Fdez-Agüera 2019, as Filament and
//!   three.js do), so that it reflects `E_ms = E_ss (1 + F0 (1 − E)/E)` (1 for a white metal);
//! * the diffuse is scaled by `1 − E_ms(μ_v)`, what the specular leaves of the light that reaches
//!   it (as the KHR layering does for its layers), so that a white dielectric reflects 1.
//!
//! `shaders_glsl/include/ibl.glsl` (`energy_scale`) mirrors [`energy_scale`] and applies it to
//! every light and to the environment.

use std::sync::OnceLock;

use glam::Vec3;

use super::{shipped_lut, split_sum_lut_table, Geometry, COS_EPS};
use super::{SHIPPED_LUT_SAMPLES, SHIPPED_LUT_SIZE};

/// Size and samples of the tables computed for the geometry terms that do not ship one (the
/// GPU's `fast` quality uses the same).
const COMPUTED_SIZE: u32 = 128;
const COMPUTED_SAMPLES: u32 = 512;

struct Table {
    size: u32,
    entries: Vec<[f32; 4]>,
}

fn table(geometry: Geometry) -> &'static Table {
    static TABLES: [OnceLock<Table>; Geometry::ALL.len()] =
        [const { OnceLock::new() }; Geometry::ALL.len()];
    let slot = Geometry::ALL
        .iter()
        .position(|g| *g == geometry)
        .expect("every geometry is in ALL");
    TABLES[slot].get_or_init(|| {
        match shipped_lut(SHIPPED_LUT_SIZE, SHIPPED_LUT_SAMPLES, geometry as i32) {
            Some(entries) => Table {
                size: SHIPPED_LUT_SIZE,
                entries,
            },
            None => Table {
                size: COMPUTED_SIZE,
                entries: split_sum_lut_table(COMPUTED_SIZE, COMPUTED_SAMPLES, geometry),
            },
        }
    })
}

/// The split-sum table's `(A, B)` at `(n·v, roughness)`, bilinear between its nodes (texel `i`
/// holds [`super::lut_node`]`(i)`, 0 and 1 included) and clamped at the edges, as the GPU's
/// sampler reads `brdf_lut` at [`super::lut_uv`]. The shipped table (512², 1024 samples) for
/// the correlated Smith term, a 128² table of 512 samples (computed once per process) for the
/// others.
pub fn split_sum_ab(geometry: Geometry, n_v: f32, roughness: f32) -> (f32, f32) {
    let [a, b, _, _] = split_sum_lobe(geometry, n_v, roughness);
    (a, b)
}

/// The whole entry `[A, B, μ, σ]` ([`super::split_sum_lut_moments`]) at `(n·v, roughness)`, read
/// as [`split_sum_ab`] reads `(A, B)`.
pub fn split_sum_lobe(geometry: Geometry, n_v: f32, roughness: f32) -> [f32; 4] {
    // Geometry terms that share a table (Beckmann's Smith term reads the separable GGX one) share
    // its computation too.
    let t = table(geometry.for_split_sum());
    let size = t.size as usize;
    let coord = |x: f32| {
        let x = if x.is_finite() {
            x.clamp(0.0, 1.0)
        } else {
            1.0
        };
        let p = (x * (size - 1) as f32).clamp(0.0, (size - 1) as f32);
        let i = (p.floor() as usize).min(size - 1);
        (i, (i + 1).min(size - 1), p - i as f32)
    };
    let (i0, i1, fx) = coord(n_v);
    let (j0, j1, fy) = coord(roughness);
    let at = |i: usize, j: usize| t.entries[j * size + i];
    let lerp = |a: [f32; 4], b: [f32; 4], f: f32| std::array::from_fn(|k| a[k] + (b[k] - a[k]) * f);
    lerp(
        lerp(at(i0, j0), at(i1, j0), fx),
        lerp(at(i0, j1), at(i1, j1), fx),
        fy,
    )
}

/// What energy compensation multiplies the metal-rough terms by at a view with cosine `n_v`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnergyScale {
    /// `1 + F0 (1 − E)/E`, on the specular lobe.
    pub specular: Vec3,
    /// `1 − E_ms`, on the diffuse lobe (clamped to ≥ 0).
    pub diffuse: Vec3,
}

impl EnergyScale {
    /// No compensation.
    pub const NONE: EnergyScale = EnergyScale {
        specular: Vec3::ONE,
        diffuse: Vec3::ONE,
    };
}

/// [`EnergyScale`] of a GGX lobe of reflectance `f0` and perceptual `roughness` seen at `n_v`
/// (clamped to `[COS_EPS, 1]`, as the GPU's `clamp(n·v, 1e-4, 1)`).
pub fn energy_scale(geometry: Geometry, f0: Vec3, n_v: f32, roughness: f32) -> EnergyScale {
    energy_scale_f90(geometry, f0, 1.0, n_v, roughness)
}

/// [`energy_scale`] of a lobe whose Fresnel reaches `f90` at grazing (KHR_materials_specular):
/// its single-scattering albedo is `F0·A + F90·B`.
pub fn energy_scale_f90(
    geometry: Geometry,
    f0: Vec3,
    f90: f32,
    n_v: f32,
    roughness: f32,
) -> EnergyScale {
    let (a, b) = split_sum_ab(geometry, n_v.clamp(COS_EPS, 1.0), roughness);
    energy_scale_ab(f0, f90, a, b)
}

/// [`energy_scale_f90`] from a lobe's split sum `(A, B)` (the isotropic table's, or the
/// anisotropic lobe's, [`super::aniso_split_sum_ab`]).
pub fn energy_scale_ab(f0: Vec3, f90: f32, a: f32, b: f32) -> EnergyScale {
    let e = (a + b).max(1e-4);
    let specular = Vec3::ONE + f0.max(Vec3::ZERO) * ((1.0 - e) / e);
    let e_ms = (f0 * a + Vec3::splat(f90 * b)) * specular;
    EnergyScale {
        specular,
        diffuse: (Vec3::ONE - e_ms).max(Vec3::ZERO),
    }
}
