//! The split sum's BRDF table (MODELS.md §7, Karis 2013): the directional albedo of the GGX
//! lobe, `E(n·v, roughness) = F0 · A + B` for Schlick's Fresnel. The environment's split sum reads
//! it (`env`, the GPU's `brdf_lut`), and so does energy compensation ([`super::energy`]), which
//! is why it lives with the BRDFs.

use glam::Vec3;
use rayon::prelude::*;

use super::{
    g_schlick_ggx, hammersley, k_ibl, sample_ggx_vndf_aniso, Geometry, ALPHA_MIN, COS_EPS,
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

/// Point `i` of `n` for the split-sum table: `((i + ½)/n, radical_inverse(i))`, the Hammersley
/// point moved to the middle of its stratum (`hammersley` starts at 0, which biased a
/// 1024-sample entry by 0.16 % at roughness 1).
pub fn lut_point(i: u32, n: u32) -> (f32, f32) {
    let (_, u2) = hammersley(i, n);
    ((i as f32 + 0.5) / n.max(1) as f32, u2)
}

/// The table coordinate of texel `i` of `size` along either axis: `i/(size − 1)`, so that the
/// first and last texels hold `n·v` (or roughness) 0 and 1 exactly. The lookups map `x` to
/// `(x (size − 1) + ½)/size` ([`lut_uv`]). Until 2026-11-29 texel `i` held `(i + ½)/size` and a
/// lookup at roughness 1 or `n·v` 1 read the value half a texel inside: 0.30848 for a white
/// metal of roughness 1 seen from the normal, where the integral is 0.30685.
pub fn lut_node(i: u32, size: u32) -> f32 {
    i as f32 / size.saturating_sub(1).max(1) as f32
}

/// The texture coordinate at which a table of `size` texels per side ([`lut_node`]) holds `x`.
pub fn lut_uv(x: f32, size: u32) -> f32 {
    let n = size.max(1) as f32;
    (x * (n - 1.0) + 0.5) / n
}

/// The split-sum table entry `(A, B)` at `(n·v, roughness)` (MODELS.md §7, Karis 2013):
/// with `v = (sqrt(1 − n_v²), 0, n_v)`, `n = +z`, h a visible normal of the GGX lobe at
/// `α = roughness²` seen from v ([`sample_ggx_vndf_aniso`] with `α_x = α_y`, Heitz 2018) on
/// point `i` of `samples` ([`lut_point`]), `l = 2(v·h)h − v`, and for samples with `n·l > 0` and
/// `v·h > 0` the weight `w = G/G1(v)` (the visible normals' pdf cancels D, so `w ≤ 1` for the
/// Smith terms; `G` from [`g_ibl`], `G1` the GGX Smith masking of the sampled lobe),
/// `Fc = (1 − v·h)^5`, `A = (1/N) Σ (1 − Fc) w`, `B = (1/N) Σ Fc w`. The specular reflectance
/// is then `F0 · A + B`. `n·v` is clamped to at least `COS_EPS`.
///
/// Until 2026-11-29 the half vectors were drawn from `D(h)(n·h)` (Karis' `G (v·h)/((n·h)(n·v))`
/// weight): at 1024 samples that table read 0.9094 for a white metal of roughness 0.5 seen at
/// 85° where the integral is 0.9007, and energy compensation inherited the 1 % (issue 34's
/// furnace). Visible normals on midpoint points make the same 1024 samples agree with 2¹⁸ to
/// 3e-4 (0.90102 against 0.90075 there; 0.30685 at roughness 1 seen from the normal).
pub fn split_sum_lut_reference(
    n_v: f32,
    roughness: f32,
    geometry: Geometry,
    samples: u32,
) -> (f32, f32) {
    let [a, b, _, _] = split_sum_lut_moments(n_v, roughness, geometry, samples);
    (a, b)
}

/// [`split_sum_lut_reference`]'s `(A, B)` and the lobe's `v·h` under the same weight: its mean
/// `μ = Σ w v·h / Σ w` and standard deviation `σ`. A Fresnel that is not Schlick's (the
/// iridescent film's) is integrated over the lobe from them ([`super::iridescence_f0_lobe`]):
/// Schlick's curve through it at the mean Schlick angle, corrected by the difference at `μ ± σ`.
pub fn split_sum_lut_moments(
    n_v: f32,
    roughness: f32,
    geometry: Geometry,
    samples: u32,
) -> [f32; 4] {
    let n_v = n_v.clamp(COS_EPS, 1.0);
    let roughness = roughness.clamp(0.0, 1.0);
    let v = Vec3::new((1.0 - n_v * n_v).max(0.0).sqrt(), 0.0, n_v);
    let alpha = (roughness * roughness).max(ALPHA_MIN);
    let g1 = 2.0 * n_v / (n_v + Vec3::new(alpha * v.x, 0.0, n_v).length());
    let samples = samples.max(1);
    let (mut a, mut b, mut m1, mut m2) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for i in 0..samples {
        let (xi1, xi2) = lut_point(i, samples);
        let h = sample_ggx_vndf_aniso(v, alpha, alpha, xi1, xi2);
        let v_h = v.dot(h);
        let l = h * (2.0 * v_h) - v;
        let (n_l, n_h) = (l.z, h.z);
        if n_l <= 0.0 || v_h <= 0.0 || n_h <= 0.0 {
            continue;
        }
        let g = g_ibl(geometry, n_h, n_v, n_l, v_h, roughness);
        let w = f64::from(g / g1);
        let fc = f64::from((1.0 - v_h).clamp(0.0, 1.0).powi(5));
        a += (1.0 - fc) * w;
        b += fc * w;
        // About n·v, as the GPU kernel sums them (in f32 a narrow lobe's variance cancels).
        let d = f64::from(v_h) - f64::from(n_v);
        m1 += d * w;
        m2 += d * d * w;
    }
    let n = f64::from(samples);
    let e = a + b;
    let (mu, sd) = if e > 0.0 {
        let d = m1 / e;
        (f64::from(n_v) + d, (m2 / e - d * d).max(0.0).sqrt())
    } else {
        (1.0, 0.0)
    };
    [(a / n) as f32, (b / n) as f32, mu as f32, sd as f32]
}

/// The whole split-sum table, `size × size` entries `[A, B, μ, σ]`
/// ([`split_sum_lut_moments`]), row-major: column `i` is `n·v = lut_node(i)`, row `j` is
/// `roughness = lut_node(j)` (read at [`lut_uv`]).
pub fn split_sum_lut_table(size: u32, samples: u32, geometry: Geometry) -> Vec<[f32; 4]> {
    let size = size.max(1);
    (0..size * size)
        .into_par_iter()
        .map(|k| {
            let (i, j) = (k % size, k / size);
            let (n_v, r) = (lut_node(i, size), lut_node(j, size));
            split_sum_lut_moments(n_v, r, geometry, samples)
        })
        .collect()
}
