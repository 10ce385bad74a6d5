//! The split sum's BRDF table (MODELS.md §7, Karis 2013): the directional albedo of the GGX
//! lobe, `E(n·v, roughness) = F0 · A + B` for Schlick's Fresnel. The environment's split sum reads
//! it (`env`, the GPU's `brdf_lut`), and so does energy compensation ([`super::energy`]), which
//! is why it lives with the BRDFs.

use glam::Vec3;
use rayon::prelude::*;

use super::{
    g_schlick_ggx, hammersley, importance_sample_ggx, k_ibl, Geometry, ALPHA_MIN, COS_EPS,
};

/// The masking-shadowing G of the selector for image-based lighting: Schlick-GGX with
/// [`k_ibl`] (`roughness²/2`) instead of `k_punctual`; the other selectors as for lights, with
/// `α = roughness²` (at least `ALPHA_MIN`); Beckmann's Smith term as the separable Smith GGX
/// ([`Geometry::for_split_sum`]).
pub fn g_ibl(geometry: Geometry, n_h: f32, n_v: f32, n_l: f32, v_h: f32, roughness: f32) -> f32 {
    match geometry.for_split_sum() {
        Geometry::SchlickGgx => g_schlick_ggx(n_l, n_v, k_ibl(roughness)),
        g => g.eval(
            n_h,
            n_v,
            n_l,
            v_h,
            (roughness * roughness).max(ALPHA_MIN),
            roughness,
        ),
    }
}

/// The split-sum table entry `(A, B)` at `(n·v, roughness)` (MODELS.md §7, Karis 2013):
/// with `v = (sqrt(1 − n_v²), 0, n_v)`, `n = +z`, h from [`importance_sample_ggx`] at
/// `α = roughness²` on Hammersley point `i` of `samples` (`ξ1 = i/N` → φ, `ξ2` = radical
/// inverse → θ), `l = 2(v·h)h − v`, and for samples with `n·l > 0` and `v·h > 0`:
/// `G_vis = G (v·h)/((n·h)(n·v))` ([`g_ibl`]), `Fc = (1 − v·h)^5`,
/// `A = (1/N) Σ (1 − Fc) G_vis`, `B = (1/N) Σ Fc G_vis`. The specular reflectance is then
/// `F0 · A + B`. `n·v` is clamped to at least `COS_EPS`.
pub fn split_sum_lut_reference(
    n_v: f32,
    roughness: f32,
    geometry: Geometry,
    samples: u32,
) -> (f32, f32) {
    let n_v = n_v.clamp(COS_EPS, 1.0);
    let roughness = roughness.clamp(0.0, 1.0);
    let v = Vec3::new((1.0 - n_v * n_v).max(0.0).sqrt(), 0.0, n_v);
    let alpha = roughness * roughness;
    let samples = samples.max(1);
    let (mut a, mut b) = (0.0f64, 0.0f64);
    for i in 0..samples {
        let (xi1, xi2) = hammersley(i, samples);
        let h = importance_sample_ggx(xi1, xi2, alpha);
        let v_h = v.dot(h);
        let l = h * (2.0 * v_h) - v;
        let (n_l, n_h) = (l.z, h.z);
        if n_l <= 0.0 || v_h <= 0.0 || n_h <= 0.0 {
            continue;
        }
        let g = g_ibl(geometry, n_h, n_v, n_l, v_h, roughness);
        let g_vis = f64::from(g * v_h / (n_h * n_v));
        let fc = f64::from((1.0 - v_h).clamp(0.0, 1.0).powi(5));
        a += (1.0 - fc) * g_vis;
        b += fc * g_vis;
    }
    let n = f64::from(samples);
    ((a / n) as f32, (b / n) as f32)
}

/// The whole split-sum table, `size × size` entries `[A, B]`, row-major: column `i` is
/// `n·v = (i + 0.5)/size`, row `j` is `roughness = (j + 0.5)/size` (texel centres of a texture
/// sampled with `(n·v, roughness)` as `(u, v)`).
pub fn split_sum_lut_table(size: u32, samples: u32, geometry: Geometry) -> Vec<[f32; 2]> {
    let size = size.max(1);
    (0..size * size)
        .into_par_iter()
        .map(|k| {
            let (i, j) = (k % size, k / size);
            let n_v = (i as f32 + 0.5) / size as f32;
            let r = (j as f32 + 0.5) / size as f32;
            let (a, b) = split_sum_lut_reference(n_v, r, geometry, samples);
            [a, b]
        })
        .collect()
}
