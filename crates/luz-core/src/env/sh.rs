//! Order-2 (9-coefficient) real spherical harmonics and Ramamoorthi–Hanrahan irradiance.
//!
//! # Basis (order and constants; the GLSL uses the same)
//!
//! For a unit direction `d = (x, y, z)` in luz's world axes (+y up; no axis swap: the irradiance
//! convolution is rotation invariant per band, so any orthonormal real basis works):
//!
//! | i | l, m | Y_i(d) | constant |
//! |---|---|---|---|
//! | 0 | 0, 0 | `C0` | `C0 = 1/(2√π) = 0.282095` |
//! | 1 | 1, −1 | `C1 · y` | `C1 = √3/(2√π) = 0.488603` |
//! | 2 | 1, 0 | `C1 · z` | |
//! | 3 | 1, 1 | `C1 · x` | |
//! | 4 | 2, −2 | `C2 · x y` | `C2 = √15/(2√π) = 1.092548` |
//! | 5 | 2, −1 | `C2 · y z` | |
//! | 6 | 2, 0 | `C3 · (3 z² − 1)` | `C3 = √5/(4√π) = 0.315392` |
//! | 7 | 2, 1 | `C2 · x z` | |
//! | 8 | 2, 2 | `C4 · (x² − y²)` | `C4 = √15/(4√π) = 0.546274` |
//!
//! Projection: `L_i = ∫ L(ω) Y_i(ω) dω`. Irradiance (Ramamoorthi & Hanrahan 2001):
//! `E(n) = Σ_i Â_l(i) L_i Y_i(n)` with `Â_0 = π`, `Â_1 = 2π/3`, `Â_2 = π/4`; a uniform radiance L
//! gives `E = π L`. [`sh9_irradiance_coeffs`] folds the `Â_l` into the coefficients, so the GPU
//! evaluates `E(n) = Σ_i c_i Y_i(n)` (9 `vec3`s) with `n` in environment space.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::equirect::Equirect;

/// `1/(2√π)`.
pub const SH_C0: f32 = 0.282_094_8;
/// `√3/(2√π)`.
pub const SH_C1: f32 = 0.488_602_5;
/// `√15/(2√π)`.
pub const SH_C2: f32 = 1.092_548_4;
/// `√5/(4√π)`.
pub const SH_C3: f32 = 0.315_391_57;
/// `√15/(4√π)`.
pub const SH_C4: f32 = 0.546_274_2;
/// The cosine-lobe convolution factors `Â_l` per coefficient: π, 2π/3 (×3), π/4 (×5).
pub const SH_IRRADIANCE_FACTORS: [f32; 9] = [
    std::f32::consts::PI,
    2.0 * std::f32::consts::PI / 3.0,
    2.0 * std::f32::consts::PI / 3.0,
    2.0 * std::f32::consts::PI / 3.0,
    std::f32::consts::FRAC_PI_4,
    std::f32::consts::FRAC_PI_4,
    std::f32::consts::FRAC_PI_4,
    std::f32::consts::FRAC_PI_4,
    std::f32::consts::FRAC_PI_4,
];

/// The 9 basis functions at the unit direction `d` (order and constants in the module docs).
pub fn sh9_basis(d: Vec3) -> [f32; 9] {
    let (x, y, z) = (d.x, d.y, d.z);
    [
        SH_C0,
        SH_C1 * y,
        SH_C1 * z,
        SH_C1 * x,
        SH_C2 * x * y,
        SH_C2 * y * z,
        SH_C3 * (3.0 * z * z - 1.0),
        SH_C2 * x * z,
        SH_C4 * (x * x - y * y),
    ]
}

/// `Σ_i c_i Y_i(d)`.
pub fn sh9_eval(coeffs: &[Vec3; 9], d: Vec3) -> Vec3 {
    sh9_basis(d).iter().zip(coeffs).map(|(y, c)| *c * *y).sum()
}

/// Projects the environment onto the 9 basis functions: `L_i = ∫ L(ω) Y_i(ω) dω`, treating each
/// texel as constant radiance over its exact footprint (`u`, `v` rectangle) and integrating
/// `Y_i · sin θ dθ dφ` over that footprint in closed form (so an 8×4 uniform image projects
/// exactly; at ordinary resolutions this equals the texel-centre sum to O(texel²)).
pub fn sh9_project(eq: &Equirect) -> [Vec3; 9] {
    let (w, h) = (eq.width as usize, eq.height as usize);
    let pi = std::f64::consts::PI;
    // Per column: ∫ over φ of 1, sin φ, cos φ, sin²φ, cos²φ, sin φ cos φ.
    let cols: Vec<[f64; 6]> = (0..w)
        .map(|i| {
            let p0 = 2.0 * pi * (i as f64 / w as f64 - 0.5);
            let p1 = 2.0 * pi * ((i + 1) as f64 / w as f64 - 0.5);
            let prim = |p: f64| {
                let (s, c) = p.sin_cos();
                let s2 = (2.0 * p).sin();
                [
                    p,
                    -c,
                    s,
                    p / 2.0 - s2 / 4.0,
                    p / 2.0 + s2 / 4.0,
                    s * s / 2.0,
                ]
            };
            let (a, b) = (prim(p0), prim(p1));
            std::array::from_fn(|k| b[k] - a[k])
        })
        .collect();
    let sum: [DVec3; 9] = (0..h)
        .into_par_iter()
        .map(|j| {
            // Per row, in c = cos θ (dω = dc dφ): ∫ of 1, c, s, c s, s², c² with s = sin θ,
            // from the bottom edge (smaller c) to the top edge.
            let c_top = (pi * j as f64 / h as f64).cos();
            let c_bot = (pi * (j + 1) as f64 / h as f64).cos();
            let prim = |c: f64| {
                let s = (1.0 - c * c).max(0.0).sqrt();
                [
                    c,
                    c * c / 2.0,
                    (c * s + c.clamp(-1.0, 1.0).asin()) / 2.0,
                    -s * s * s / 3.0,
                    c - c * c * c / 3.0,
                    c * c * c / 3.0,
                ]
            };
            let (a, b) = (prim(c_bot), prim(c_top));
            let g: [f64; 6] = std::array::from_fn(|k| b[k] - a[k]);
            // Row sums of radiance times each φ integral.
            let mut r = [DVec3::ZERO; 6];
            for (i, col) in cols.iter().enumerate() {
                let l = eq.texel(i as u32, j as u32).as_dvec3();
                for k in 0..6 {
                    r[k] += l * col[k];
                }
            }
            let [g1, gc, gs, gcs, gs2, gc2] = g;
            let [r1, rsin, rcos, rsin2, rcos2, rsincos] = r;
            // x = s sin φ, y = c, z = −s cos φ.
            [
                r1 * g1 * f64::from(SH_C0),
                r1 * gc * f64::from(SH_C1),
                -rcos * gs * f64::from(SH_C1),
                rsin * gs * f64::from(SH_C1),
                rsin * gcs * f64::from(SH_C2),
                -rcos * gcs * f64::from(SH_C2),
                (rcos2 * (3.0 * gs2) - r1 * g1) * f64::from(SH_C3),
                -rsincos * gs2 * f64::from(SH_C2),
                (rsin2 * gs2 - r1 * gc2) * f64::from(SH_C4),
            ]
        })
        .reduce(
            || [DVec3::ZERO; 9],
            |a, b| std::array::from_fn(|k| a[k] + b[k]),
        );
    sum.map(|c| c.as_vec3())
}

/// The coefficients with the cosine-lobe convolution folded in: `c_i = Â_l(i) · L_i`, so that
/// `E(n) = Σ_i c_i Y_i(n)` ([`sh9_eval`]). These are what the GPU receives.
pub fn sh9_irradiance_coeffs(sh: &[Vec3; 9]) -> [Vec3; 9] {
    std::array::from_fn(|i| sh[i] * SH_IRRADIANCE_FACTORS[i])
}

/// Irradiance `E(n)` on a surface with unit normal `n` (environment space) from the projected
/// radiance `sh` ([`sh9_project`]). Ringing can make it slightly negative opposite a strong
/// light; it is returned unclamped (clamp at use if needed).
pub fn sh9_irradiance(sh: &[Vec3; 9], n: Vec3) -> Vec3 {
    sh9_eval(&sh9_irradiance_coeffs(sh), n)
}
