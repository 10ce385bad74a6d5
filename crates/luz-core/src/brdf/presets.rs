//! Fresnel inputs: dielectrics from an index of refraction, metals from measured complex indices.

use glam::Vec3;
use serde::{Deserialize, Serialize};

/// A complex index of refraction `η + iκ` per RGB channel (R ≈ 650 nm, G ≈ 550 nm, B ≈ 450 nm).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ComplexIor {
    /// Real part η (refractive index).
    pub eta: Vec3,
    /// Imaginary part κ (extinction coefficient).
    pub k: Vec3,
}

impl ComplexIor {
    /// Reflectance at normal incidence: `((η − 1)² + κ²) / ((η + 1)² + κ²)` per channel, with η
    /// clamped to `[0, IOR_MAX]` and `|κ|` to at most `IOR_MAX` as [`super::f_conductor_1`] does
    /// (larger values overflowed to Inf/Inf = NaN).
    pub fn f0(&self) -> Vec3 {
        let one = Vec3::ONE;
        let max = Vec3::splat(super::terms::IOR_MAX);
        let eta = self.eta.clamp(Vec3::ZERO, max);
        let k = self.k.abs().min(max);
        let num = (eta - one) * (eta - one) + k * k;
        let den = (eta + one) * (eta + one) + k * k;
        num / den.max(Vec3::splat(1e-12))
    }
}

/// Reflectance at normal incidence of a dielectric in air: `((η − 1)/(η + 1))²`
/// (`η ≤ 0` is treated as 1e-4).
pub fn f0_from_ior(eta: f32) -> f32 {
    let eta = eta.max(1e-4);
    let r = (eta - 1.0) / (eta + 1.0);
    r * r
}

/// The index `η ≥ 1` of the dielectric whose [`f0_from_ior`] is `f0`: `(1 + √F0)/(1 − √F0)`.
/// `f0` is clamped to `[0, 0.99]` (η ≤ 399).
pub fn ior_from_f0(f0: f32) -> f32 {
    let s = f0.clamp(0.0, 0.99).sqrt();
    (1.0 + s) / (1.0 - s)
}

/// Names accepted by [`metal_preset`] (aliases: "aluminum", and chemical symbols "au", "ag", …).
pub const METAL_NAMES: [&str; 9] = [
    "gold",
    "silver",
    "copper",
    "aluminium",
    "iron",
    "chromium",
    "titanium",
    "nickel",
    "platinum",
];

/// Measured complex indices of refraction of metals at R = 650 nm, G = 550 nm, B = 450 nm,
/// linearly interpolated in wavelength between the tabulated points of these
/// refractiveindex.info data sets (room temperature):
///
/// | metal | data set |
/// |---|---|
/// | gold, silver, copper | P. B. Johnson, R. W. Christy, "Optical constants of the noble metals", Phys. Rev. B 6, 4370 (1972) |
/// | iron, chromium, titanium, nickel | P. B. Johnson, R. W. Christy, "Optical constants of transition metals: Ti, V, Cr, Mn, Fe, Co, Ni, and Pd", Phys. Rev. B 9, 5056 (1974) |
/// | aluminium | A. D. Rakić, "Algorithm for the determination of intrinsic optical constants of metal films: application to aluminum", Appl. Opt. 34, 4755 (1995) |
/// | platinum | A. D. Rakić, A. B. Djurišić, J. M. Elazar, M. L. Majewski, "Optical properties of metallic films for vertical-cavity optoelectronic devices", Appl. Opt. 37, 5271 (1998), Lorentz-Drude fit |
///
/// Single wavelengths, not spectra integrated against the RGB primaries: good enough for the
/// characteristic colours (gold F0 ≈ (0.96, 0.79, 0.41), copper ≈ (0.94, 0.62, 0.54)).
/// Names are case-insensitive; "aluminum" and the chemical symbols are accepted.
pub fn metal_preset(name: &str) -> Option<ComplexIor> {
    let (eta, k) = match name.trim().to_ascii_lowercase().as_str() {
        "gold" | "au" => ([0.1556, 0.4241, 1.3831], [3.6024, 2.4721, 1.9155]),
        "silver" | "ag" => ([0.0522, 0.0596, 0.0400], [4.4094, 3.5974, 2.6484]),
        "copper" | "cu" => ([0.2378, 1.0066, 1.2404], [3.6264, 2.5823, 2.3929]),
        "aluminium" | "aluminum" | "al" => ([1.5580, 1.0152, 0.6332], [7.7124, 6.6273, 5.4544]),
        "iron" | "fe" => ([2.9114, 2.9497, 2.5845], [3.0893, 2.9318, 2.7670]),
        "chromium" | "cr" => ([3.1071, 3.1812, 2.3230], [3.3314, 3.3291, 3.1350]),
        "titanium" | "ti" => ([2.7407, 2.5418, 2.2670], [3.8143, 3.4345, 3.0385]),
        "nickel" | "ni" => ([1.9900, 1.9212, 1.7290], [4.2086, 3.6158, 2.9435]),
        "platinum" | "pt" => ([2.3699, 2.0908, 1.8511], [4.2536, 3.7036, 3.1398]),
        _ => return None,
    };
    Some(ComplexIor {
        eta: Vec3::from_array(eta),
        k: Vec3::from_array(k),
    })
}

/// Names accepted by [`dielectric_ior`].
pub const DIELECTRIC_NAMES: [&str; 8] = [
    "water",
    "fused_silica",
    "pmma",
    "glass",
    "polycarbonate",
    "polystyrene",
    "sapphire",
    "diamond",
];

/// Refractive index at the sodium D line (589 nm) of a few common dielectrics
/// (refractiveindex.info: water 20 °C, fused silica Malitson 1965, PMMA, BK7 crown glass,
/// polycarbonate, polystyrene, sapphire ordinary ray, diamond). Case-insensitive.
pub fn dielectric_ior(name: &str) -> Option<f32> {
    Some(match name.trim().to_ascii_lowercase().as_str() {
        "water" => 1.333,
        "fused_silica" => 1.458,
        "pmma" | "acrylic" => 1.491,
        "glass" | "bk7" => 1.517,
        "polycarbonate" => 1.585,
        "polystyrene" => 1.590,
        "sapphire" => 1.768,
        "diamond" => 2.417,
        _ => return None,
    })
}
