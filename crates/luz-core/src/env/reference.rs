//! CPU reference integrals of image-based lighting (MODELS.md §7), for tests and measurements.
//! Directions are unit vectors in environment space (see [`super::world_to_env`]); radiance is
//! read with [`Equirect::sample`] (bilinear, as the GPU's sampler) unless said otherwise.
//! Sample sets are Hammersley points, so every function is deterministic.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use super::equirect::Equirect;
use crate::brdf::{
    eval_terms, hammersley, importance_sample_ggx, integrate_hemisphere, ortho_basis,
    sample_cosine_hemisphere, sampling_lobes, split_sum_lut_reference, Geometry, Model, PI,
};

/// An orthonormal frame `(t, b, n)` around the unit normal `n`.
struct Frame {
    t: Vec3,
    b: Vec3,
    n: Vec3,
}

impl Frame {
    fn new(n: Vec3) -> Self {
        let n = n.try_normalize().unwrap_or(Vec3::Y);
        let (t, b) = ortho_basis(n);
        Frame { t, b, n }
    }

    fn to_world(&self, v: Vec3) -> Vec3 {
        self.t * v.x + self.b * v.y + self.n * v.z
    }

    fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.t), v.dot(self.b), v.dot(self.n))
    }
}

/// Hammersley point `i` of `n` as used by the cosine and albedo integrators:
/// `((i + 0.5)/n, radical_inverse(i))`.
fn point(i: u32, n: u32) -> (f32, f32) {
    let (_, u2) = hammersley(i, n);
    ((i as f32 + 0.5) / n as f32, u2)
}

/// Irradiance `E(n) = ∫ L(ω) max(n·ω, 0) dω` by cosine-weighted Monte Carlo (`samples`
/// Hammersley points, estimator `π · L`, bilinear lookups). Noisy for small bright sources such
/// as the sky's sun: use [`irradiance_quadrature`] there.
pub fn irradiance_reference(eq: &Equirect, n: Vec3, samples: u32) -> Vec3 {
    let frame = Frame::new(n);
    let samples = samples.max(1);
    let sum: DVec3 = (0..samples)
        .into_par_iter()
        .with_min_len(4096)
        .map(|i| {
            let (u1, u2) = point(i, samples);
            eq.sample(frame.to_world(sample_cosine_hemisphere(u1, u2)))
                .as_dvec3()
        })
        .sum();
    (sum * (f64::from(PI) / f64::from(samples))).as_vec3()
}

/// Irradiance `E(n)` by quadrature over every texel: `Σ L_texel · max(n · M_texel, 0)` with
/// `M_texel = ∫_texel ω dω` the texel's exact first moment (closed form). Exact for texels
/// wholly above the surface's horizon, approximate only for the few the horizon cuts;
/// deterministic, and it handles the sun disc of the procedural sky.
pub fn irradiance_quadrature(eq: &Equirect, n: Vec3) -> Vec3 {
    let n = n.try_normalize().unwrap_or(Vec3::Y).as_dvec3();
    let (w, h) = (eq.width as usize, eq.height as usize);
    let pi = std::f64::consts::PI;
    // Per column: ∫ sin φ dφ and ∫ cos φ dφ; per row: ∫ sin θ dc and ∫ c dc (c = cos θ).
    let cols: Vec<(f64, f64)> = (0..w)
        .map(|i| {
            let p0 = 2.0 * pi * (i as f64 / w as f64 - 0.5);
            let p1 = 2.0 * pi * ((i + 1) as f64 / w as f64 - 0.5);
            (p0.cos() - p1.cos(), p1.sin() - p0.sin())
        })
        .collect();
    let dphi = 2.0 * pi / w as f64;
    (0..h)
        .into_par_iter()
        .map(|j| {
            let c_top = (pi * j as f64 / h as f64).cos();
            let c_bot = (pi * (j + 1) as f64 / h as f64).cos();
            let prim_s =
                |c: f64| (c * (1.0 - c * c).max(0.0).sqrt() + c.clamp(-1.0, 1.0).asin()) / 2.0;
            let gs = prim_s(c_top) - prim_s(c_bot);
            let gc = (c_top * c_top - c_bot * c_bot) / 2.0;
            let mut row = DVec3::ZERO;
            for (i, (hsin, hcos)) in cols.iter().enumerate() {
                // x = s sin φ, y = c, z = −s cos φ.
                let m = DVec3::new(gs * hsin, gc * dphi, -gs * hcos);
                let c = n.dot(m);
                if c > 0.0 {
                    row += eq.texel(i as u32, j as u32).as_dvec3() * c;
                }
            }
            row
        })
        .sum::<DVec3>()
        .as_vec3()
}

/// The split sum's first factor: the environment prefiltered with GGX at `roughness` around the
/// unit direction `r`, assuming `n = v = r` and weighting by `n·l` (Karis 2013):
/// `Σ L(l_k)(n·l_k) / Σ (n·l_k)` over GGX-sampled `h_k` (Hammersley, as
/// [`split_sum_lut_reference`]), `l = 2(v·h)h − v`, samples with `n·l ≤ 0` dropped.
pub fn prefiltered_reference(eq: &Equirect, r: Vec3, roughness: f32, samples: u32) -> Vec3 {
    let frame = Frame::new(r);
    let alpha = roughness.clamp(0.0, 1.0).powi(2);
    let samples = samples.max(1);
    let (sum, weight) = (0..samples)
        .into_par_iter()
        .with_min_len(1024)
        .map(|i| {
            let (xi1, xi2) = hammersley(i, samples);
            let h = importance_sample_ggx(xi1, xi2, alpha);
            // v = n = +z locally: l = 2 (n·h) h − n.
            let l = h * (2.0 * h.z) - Vec3::Z;
            if l.z <= 0.0 {
                return (DVec3::ZERO, 0.0);
            }
            let w = f64::from(l.z);
            (eq.sample(frame.to_world(l)).as_dvec3() * w, w)
        })
        .reduce(|| (DVec3::ZERO, 0.0), |a, b| (a.0 + b.0, a.1 + b.1));
    if weight > 0.0 {
        (sum / weight).as_vec3()
    } else {
        Vec3::ZERO
    }
}

/// Frostbite's "dominant direction" of the specular lobe for a prefiltered lookup (Lagarde &
/// de Rousiers 2014, §4.9.3): `normalize(mix(n, r, s))` with `s = (1 − α)(sqrt(1 − α) + α)`,
/// `α = roughness²`. Equal to `r` for a mirror, leaning towards `n` as the lobe widens (the
/// off-specular peak the n = v = r assumption ignores).
pub fn specular_dominant_direction(n: Vec3, r: Vec3, roughness: f32) -> Vec3 {
    let a = roughness.clamp(0.0, 1.0).powi(2);
    let s = (1.0 - a) * ((1.0 - a).sqrt() + a);
    n.lerp(r, s).try_normalize().unwrap_or(n)
}

/// `n` and `v` made unit (a zero `n` is +y, a zero `v` is `n`) and `n·v`, or `None` when the view
/// is below the surface (`n·v ≤ 0`): the start of every specular IBL estimate.
pub(super) fn unit_view(n: Vec3, v: Vec3) -> Option<(Vec3, Vec3, f32)> {
    let n = n.try_normalize().unwrap_or(Vec3::Y);
    let v = v.try_normalize().unwrap_or(n);
    let n_v = n.dot(v);
    (n_v > 0.0).then_some((n, v, n_v))
}

/// The split-sum estimate of the specular radiance with the table computed on the fly:
/// `prefiltered(d, roughness) · (F0 · A + B)` with `(A, B)` at `(n·v, roughness)` for the
/// `geometry` selector and `d = r = 2(n·v)n − v` (MODELS.md §7), or, with `dominant`,
/// [`specular_dominant_direction`]. 0 when `n·v ≤ 0`.
#[allow(clippy::too_many_arguments)]
pub fn split_sum_specular(
    eq: &Equirect,
    f0: Vec3,
    roughness: f32,
    geometry: Geometry,
    n: Vec3,
    v: Vec3,
    dominant: bool,
    samples: u32,
) -> Vec3 {
    let Some((n, v, n_v)) = unit_view(n, v) else {
        return Vec3::ZERO;
    };
    let r = n * (2.0 * n_v) - v;
    let d = if dominant {
        specular_dominant_direction(n, r, roughness)
    } else {
        r
    };
    let (a, b) = split_sum_lut_reference(n_v, roughness, geometry, samples);
    prefiltered_reference(eq, d, roughness, samples) * (f0 * a + Vec3::splat(b))
}

/// `∫ f(l, v) L(l) max(n·l, 0) dl` for the part of the BRDF picked by `part`, by
/// balance-heuristic MIS over the cosine lobe and the model's own lobes
/// (`brdf::integrate_hemisphere`), in the frame `(t, b, n)` of `brdf::ortho_basis(n)` (the
/// tangent of anisotropic Principled).
fn ibl_reference(
    eq: &Equirect,
    model: &Model,
    n: Vec3,
    v: Vec3,
    samples: u32,
    specular: bool,
) -> Vec3 {
    let frame = Frame::new(n);
    let v_local = frame.to_local(v.try_normalize().unwrap_or(frame.n));
    if v_local.z <= 0.0 {
        return Vec3::ZERO;
    }
    let lobes = if specular {
        sampling_lobes(model)
    } else {
        Vec::new()
    };
    integrate_hemisphere(
        |l| {
            let terms = eval_terms(model, Vec3::Z, l, v_local, Vec3::X, Vec3::Y);
            let f = if specular {
                terms.specular
            } else {
                terms.diffuse
            };
            if f == Vec3::ZERO {
                return Vec3::ZERO;
            }
            f * eq.sample(frame.to_world(l))
        },
        v_local,
        &lobes,
        samples.max(1),
    )
}

/// Specular image-based lighting, importance sampled: `∫ f_spec(l, v) L(l) (n·l) dl` with
/// `f_spec` the specular part of `model` (`brdf::Terms::specular`, clearcoat included). Equal to
/// the full estimator of MODELS.md §7 restricted to the specular lobe; the split sum
/// approximates it.
pub fn specular_ibl_reference(
    eq: &Equirect,
    model: &Model,
    n: Vec3,
    v: Vec3,
    samples: u32,
) -> Vec3 {
    ibl_reference(eq, model, n, v, samples, true)
}

/// Diffuse image-based lighting: `∫ f_diff(l, v) L(l) (n·l) dl` with `f_diff` the diffuse part
/// of `model` (`brdf::Terms::diffuse`, sheen included), cosine-sampled. For a Lambertian
/// diffuse this is `c_diff/π · E(n)`.
pub fn diffuse_ibl_reference(eq: &Equirect, model: &Model, n: Vec3, v: Vec3, samples: u32) -> Vec3 {
    ibl_reference(eq, model, n, v, samples, false)
}
