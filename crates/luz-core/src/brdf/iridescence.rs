//! KHR_materials_iridescence: the Fresnel reflectance of a thin dielectric film over the base
//! (Belcour & Barla 2017, "A Practical Extension to Microfacet Theory for the Modeling of Varying
//! Iridescence"), as the extension specifies it: Airy summation of the film's first two orders,
//! integrated against the CIE XYZ sensitivities by the paper's Gaussian fit, then to linear
//! Rec. 709. The GLSL mirror is `iridescence_fresnel` in `shaders_glsl/brdf/terms.glsl`, same names,
//! same order of operations.
//!
//! `F = mix(F_base(v·h), iridescence_fresnel(1, η_film, v·h, d, F0), factor)` replaces the
//! material's Fresnel term. The film's index fades to the outside's as its thickness goes to 0
//! (the extension's smoothstep over 0–0.03 nm), and a thickness of 0 turns the film off (as the
//! extension's sample renderer does: Schlick's first interface does not vanish at grazing).

use glam::{Mat3, Vec3};

/// CIE XYZ → linear Rec. 709 (sRGB primaries, D65), column-major like GLSL's `mat3`.
const XYZ_TO_REC709: Mat3 = Mat3::from_cols_array(&[
    3.240_454_2,
    -0.969_266,
    0.055_643_4,
    -1.537_138_5,
    1.876_010_8,
    -0.204_025_9,
    -0.498_531_4,
    0.041_556,
    1.057_225_2,
]);

fn sq(x: f32) -> f32 {
    x * x
}

/// Schlick's F for a scalar F0 at `cos θ` (F90 = 1).
fn schlick1(f0: f32, c: f32) -> f32 {
    f0 + (1.0 - f0) * super::terms::schlick_weight(c)
}

/// The reflectance at normal incidence between indices `eta_t` and `eta_i`.
fn ior_to_f0(eta_t: f32, eta_i: f32) -> f32 {
    sq((eta_t - eta_i) / (eta_t + eta_i))
}

/// The index of a dielectric whose F0 against air is `f0` (clamped below 1).
fn f0_to_ior(f0: f32) -> f32 {
    let s = f0.clamp(0.0, 0.9999).sqrt();
    (1.0 + s) / (1.0 - s)
}

/// The film's spectral sensitivity at optical path differences `opd` and `2 opd` (nm) with
/// phases `shift` and `2 shift`, in linear Rec. 709: Belcour & Barla's Gaussian fit of the CIE
/// XYZ matching functions, the Airy sum's first and second orders. The second order's arguments
/// are twice the first's, so its cosines and Gaussians come from the first's
/// (`cos 2x = 2 cos² x − 1`, `exp(−4y) = exp(−y)⁴`): four cosines and four exponentials for
/// both instead of eight and eight.
pub fn eval_sensitivity2(opd: f32, shift: Vec3) -> (Vec3, Vec3) {
    let phase = 2.0 * std::f32::consts::PI * opd * 1.0e-9;
    let val = Vec3::new(5.4856e-13, 4.4201e-13, 5.2481e-13);
    let pos = Vec3::new(1.6810e+06, 1.7953e+06, 2.2084e+06);
    let var = Vec3::new(4.3278e+09, 9.3046e+09, 6.6121e+09);
    let two_pi = 2.0 * std::f32::consts::PI;
    let (mut xyz1, mut xyz2) = (Vec3::ZERO, Vec3::ZERO);
    let doubled = |c: f32, e: f32| (2.0 * c * c - 1.0, sq(sq(e)));
    for i in 0..3 {
        let k = val[i] * (two_pi * var[i]).sqrt();
        let c = (pos[i] * phase + shift[i]).cos();
        let e = (-sq(phase) * var[i]).exp();
        let (c2, e2) = doubled(c, e);
        xyz1[i] = k * c * e;
        xyz2[i] = k * c2 * e2;
    }
    let k = 9.7470e-14 * (two_pi * 4.5282e+09f32).sqrt();
    let c = (2.2399e+06 * phase + shift.x).cos();
    let e = (-4.5282e+09 * sq(phase)).exp();
    let (c2, e2) = doubled(c, e);
    xyz1.x += k * c * e;
    xyz2.x += k * c2 * e2;
    (
        XYZ_TO_REC709 * (xyz1 / 1.0685e-7),
        XYZ_TO_REC709 * (xyz2 / 1.0685e-7),
    )
}

/// The film whatever the angle and the base: the outside's index, the film's index `eta2` (it
/// fades to the outside's as the film thins), the first interface's F0, the film's own phase
/// `phi21` and the path difference per unit refracted cosine. A material's film, made once per
/// pixel; [`film_at`] adds the angle.
#[derive(Debug, Clone, Copy)]
pub struct Film {
    outside_ior: f32,
    eta2: f32,
    r12_f0: f32,
    phi21: f32,
    /// The phase 2π · (2 η₂ d cos θ₂) · 10⁻⁹ per unit cos θ₂.
    phase_per_cos2: f32,
}

/// The film of index `film_ior` and thickness `thickness_nm` seen from a medium of index
/// `outside_ior`. The film's index fades to the outside's as it thins.
pub fn film_of(outside_ior: f32, film_ior: f32, thickness_nm: f32) -> Film {
    let t = (thickness_nm / 0.03).clamp(0.0, 1.0);
    let eta2 = outside_ior + (film_ior - outside_ior) * (t * t * (3.0 - 2.0 * t));
    Film {
        outside_ior,
        eta2,
        r12_f0: ior_to_f0(eta2, outside_ior),
        phi21: if eta2 < outside_ior {
            0.0
        } else {
            std::f32::consts::PI
        },
        phase_per_cos2: 2.0 * std::f32::consts::PI * (2.0 * eta2 * thickness_nm) * 1.0e-9,
    }
}

/// What a base of normal-incidence reflectance `base_f0` gives under `film` whatever the angle:
/// the second interface's F0 per channel, and the sign the base's phase (π when its index is
/// below the film's) gives the first order's cosine. Made once per pixel per base.
#[derive(Debug, Clone, Copy)]
pub struct FilmBase {
    r23_f0: Vec3,
    sign: Vec3,
}

/// [`FilmBase`] of `base_f0` under `film`.
pub fn film_base(film: &Film, base_f0: Vec3) -> FilmBase {
    let mut r23_f0 = Vec3::ZERO;
    let mut sign = Vec3::ONE;
    for i in 0..3 {
        let base_ior = f0_to_ior(base_f0[i]);
        r23_f0[i] = ior_to_f0(base_ior, film.eta2);
        if base_ior < film.eta2 {
            sign[i] = -1.0;
        }
    }
    FilmBase { r23_f0, sign }
}

/// What the film gives at one angle whatever the base under it: the first interface's
/// reflectance `r12` and transmission `t121`, the film's refracted cosine `cos2`, and the
/// sensitivity fit's cosines and Gaussians at the film's path difference and its own phase
/// `phi21` (per XYZ component, and the X component's extra lobe). A base only adds a phase of π
/// per channel, which flips a first-order cosine's sign and leaves the second order's
/// (`cos(2x + 2π) = cos 2x`): two bases (metallic between 0 and 1) share one evaluation of the
/// transcendentals. `None` under total internal reflection.
#[derive(Debug, Clone, Copy)]
pub struct FilmAt {
    r12: f32,
    t121: f32,
    cos2: f32,
    /// cos(pos · phase + φ21) per XYZ component, and the X lobe's.
    c: Vec3,
    cx: f32,
    /// exp(−phase² var) per XYZ component, and the X lobe's.
    e: Vec3,
    ex: f32,
}

/// `film` at `cos_theta1` (v·h).
pub fn film_at(film: &Film, cos_theta1: f32) -> Option<FilmAt> {
    let c1 = cos_theta1.clamp(0.0, 1.0);
    let sin2_theta2 = sq(film.outside_ior / film.eta2) * (1.0 - sq(c1));
    let cos2_theta2 = 1.0 - sin2_theta2;
    if cos2_theta2 < 0.0 {
        return None;
    }
    let cos2 = cos2_theta2.sqrt();
    let r12 = schlick1(film.r12_f0, c1);
    let phi21 = film.phi21;
    let phase = film.phase_per_cos2 * cos2;
    let pos = Vec3::new(1.6810e+06, 1.7953e+06, 2.2084e+06);
    let var = Vec3::new(4.3278e+09, 9.3046e+09, 6.6121e+09);
    let mut c = Vec3::ZERO;
    let mut e = Vec3::ZERO;
    for i in 0..3 {
        c[i] = (pos[i] * phase + phi21).cos();
        e[i] = (-sq(phase) * var[i]).exp();
    }
    Some(FilmAt {
        r12,
        t121: 1.0 - r12,
        cos2,
        c,
        cx: (2.2399e+06 * phase + phi21).cos(),
        e,
        ex: (-4.5282e+09 * sq(phase)).exp(),
    })
}

/// The film's Fresnel reflectance over `base` (`None`, total internal reflection: 1). Never
/// negative (the extension clamps out-of-gamut colours).
pub fn film_over(film: Option<&FilmAt>, base: &FilmBase) -> Vec3 {
    let Some(f) = film else {
        return Vec3::ONE;
    };
    let val = Vec3::new(5.4856e-13, 4.4201e-13, 5.2481e-13);
    let var = Vec3::new(4.3278e+09, 9.3046e+09, 6.6121e+09);
    let two_pi = 2.0 * std::f32::consts::PI;
    let w = super::terms::schlick_weight(f.cos2);
    let r23 = base.r23_f0 + (Vec3::ONE - base.r23_f0) * w;
    let (mut xyz1, mut xyz2) = (Vec3::ZERO, Vec3::ZERO);
    for i in 0..3 {
        let k = val[i] * (two_pi * var[i]).sqrt();
        xyz1[i] = k * base.sign[i] * f.c[i] * f.e[i];
        xyz2[i] = k * (2.0 * f.c[i] * f.c[i] - 1.0) * sq(sq(f.e[i]));
    }
    let kx = 9.7470e-14 * (two_pi * 4.5282e+09f32).sqrt();
    xyz1.x += kx * base.sign.x * f.cx * f.ex;
    xyz2.x += kx * (2.0 * f.cx * f.cx - 1.0) * sq(sq(f.ex));
    let s1 = XYZ_TO_REC709 * (xyz1 / 1.0685e-7);
    let s2 = XYZ_TO_REC709 * (xyz2 / 1.0685e-7);
    let r123 = (f.r12 * r23).clamp(Vec3::splat(1e-5), Vec3::splat(0.9999));
    let sqrt_r123 = Vec3::new(r123.x.sqrt(), r123.y.sqrt(), r123.z.sqrt());
    let rs = sq(f.t121) * r23 / (Vec3::ONE - r123);
    // m = 0 (the DC term), then the pairs of Diracs m = 1, 2.
    let k1 = (rs - Vec3::splat(f.t121)) * sqrt_r123;
    let k2 = k1 * sqrt_r123;
    (Vec3::splat(f.r12) + rs + 2.0 * (k1 * s1 + k2 * s2)).max(Vec3::ZERO)
}

/// The thin film's Fresnel reflectance (RGB) seen from a medium of index `outside_ior` at
/// `cos_theta1` (v·h), for a film of index `film_ior` and thickness `thickness_nm` over a base
/// of normal-incidence reflectance `base_f0`: [`film_over`] of [`film_at`] and [`film_base`]
/// of [`film_of`].
pub fn iridescence_fresnel(
    outside_ior: f32,
    film_ior: f32,
    cos_theta1: f32,
    thickness_nm: f32,
    base_f0: Vec3,
) -> Vec3 {
    let film = film_of(outside_ior, film_ior, thickness_nm);
    film_over(
        film_at(&film, cos_theta1).as_ref(),
        &film_base(&film, base_f0),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The doubled second order equals the fit evaluated at twice the path and phase.
    #[test]
    fn second_order_is_the_fit_at_twice_the_path() {
        let direct = |opd: f32, shift: Vec3| {
            let phase = 2.0 * std::f64::consts::PI * opd as f64 * 1.0e-9;
            let val = [5.4856e-13, 4.4201e-13, 5.2481e-13];
            let pos = [1.6810e+06, 1.7953e+06, 2.2084e+06];
            let var = [4.3278e+09, 9.3046e+09, 6.6121e+09];
            let tp = 2.0 * std::f64::consts::PI;
            let mut xyz = [0.0f64; 3];
            for i in 0..3 {
                xyz[i] = val[i]
                    * (tp * var[i]).sqrt()
                    * (pos[i] * phase + shift[i] as f64).cos()
                    * (-phase * phase * var[i]).exp();
            }
            xyz[0] += 9.7470e-14
                * (tp * 4.5282e+09f64).sqrt()
                * (2.2399e+06 * phase + shift.x as f64).cos()
                * (-4.5282e+09 * phase * phase).exp();
            XYZ_TO_REC709 * (Vec3::new(xyz[0] as f32, xyz[1] as f32, xyz[2] as f32) / 1.0685e-7)
        };
        for opd in [0.0, 120.0, 380.0, 777.0, 2400.0] {
            let shift = Vec3::new(std::f32::consts::PI, 0.0, std::f32::consts::PI);
            let (s1, s2) = eval_sensitivity2(opd, shift);
            let (d1, d2) = (direct(opd, shift), direct(2.0 * opd, 2.0 * shift));
            assert!((s1 - d1).abs().max_element() < 1e-4, "{opd}: {s1} {d1}");
            assert!((s2 - d2).abs().max_element() < 1e-4, "{opd}: {s2} {d2}");
        }
    }

    /// The shared-film form equals the extension's code written out (every base's phase in the
    /// sensitivity's argument).
    #[test]
    fn shared_film_is_the_written_out_form() {
        let written = |eta1: f32, eta_f: f32, c1: f32, d: f32, f0: Vec3| {
            let t = (d / 0.03).clamp(0.0, 1.0);
            let eta2 = eta1 + (eta_f - eta1) * (t * t * (3.0 - 2.0 * t));
            let c2sq = 1.0 - sq(eta1 / eta2) * (1.0 - sq(c1));
            if c2sq < 0.0 {
                return Vec3::ONE;
            }
            let c2 = c2sq.sqrt();
            let r12 = schlick1(ior_to_f0(eta2, eta1), c1);
            let t121 = 1.0 - r12;
            let phi12 = if eta2 < eta1 {
                std::f32::consts::PI
            } else {
                0.0
            };
            let phi21 = std::f32::consts::PI - phi12;
            let mut r23 = Vec3::ZERO;
            let mut phi23 = Vec3::ZERO;
            for i in 0..3 {
                let b = f0_to_ior(f0[i]);
                r23[i] = schlick1(ior_to_f0(b, eta2), c2);
                if b < eta2 {
                    phi23[i] = std::f32::consts::PI;
                }
            }
            let opd = 2.0 * eta2 * d * c2;
            let (s1, s2) = eval_sensitivity2(opd, Vec3::splat(phi21) + phi23);
            let r123 = (r12 * r23).clamp(Vec3::splat(1e-5), Vec3::splat(0.9999));
            let sr = Vec3::new(r123.x.sqrt(), r123.y.sqrt(), r123.z.sqrt());
            let rs = sq(t121) * r23 / (Vec3::ONE - r123);
            let k1 = (rs - Vec3::splat(t121)) * sr;
            (Vec3::splat(r12) + rs + 2.0 * (k1 * s1 + k1 * sr * s2)).max(Vec3::ZERO)
        };
        for f0 in [
            Vec3::splat(0.04),
            Vec3::new(0.95, 0.6, 0.2),
            Vec3::new(0.02, 0.5, 0.9),
        ] {
            for (eta_f, d) in [(1.3, 300.0), (1.8, 150.0), (2.5, 900.0), (1.0, 400.0)] {
                for k in 0..=10 {
                    let c = k as f32 / 10.0;
                    let a = iridescence_fresnel(1.0, eta_f, c, d, f0);
                    let b = written(1.0, eta_f, c, d, f0);
                    assert!(
                        (a - b).abs().max_element() < 1e-4,
                        "{f0} {eta_f} {d} {c}: {a} {b}"
                    );
                }
            }
        }
    }

    /// A film of thickness 0 is the base's Schlick Fresnel within 0.02 near normal incidence;
    /// the result is finite and in [0, 1.2] over thicknesses 0–1200 nm and every angle; a film
    /// makes colours (the channels differ) where a bare dielectric does not.
    #[test]
    fn thin_film_limits() {
        let f0 = Vec3::new(0.04, 0.5, 0.95);
        for k in 0..=20 {
            let c = k as f32 / 20.0;
            // Schlick's first interface does not vanish at grazing even between equal indices
            // ((1 − c)⁵), hence the rule that a thickness of 0 turns the film off.
            if c >= 0.8 {
                let bare = iridescence_fresnel(1.0, 1.3, c, 0.0, f0);
                for i in 0..3 {
                    let want = schlick1(f0[i], c);
                    assert!((bare[i] - want).abs() < 0.02, "c {c}: {bare} vs {want}");
                }
            }
            for d in [0.0, 100.0, 400.0, 1200.0] {
                let f = iridescence_fresnel(1.0, 1.3, c, d, f0);
                assert!(
                    f.is_finite() && f.min_element() >= 0.0 && f.max_element() <= 1.2,
                    "{f}"
                );
            }
        }
        let film = iridescence_fresnel(1.0, 1.3, 0.9, 300.0, Vec3::splat(0.04));
        assert!(film.max_element() - film.min_element() > 0.02, "{film}");
    }
}
