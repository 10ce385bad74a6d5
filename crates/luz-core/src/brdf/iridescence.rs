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

/// The film's spectral sensitivity at optical path difference `opd` (nm) and phase `shift`,
/// in linear Rec. 709: Belcour & Barla's Gaussian fit of the CIE XYZ matching functions.
pub fn eval_sensitivity(opd: f32, shift: Vec3) -> Vec3 {
    let phase = 2.0 * std::f32::consts::PI * opd * 1.0e-9;
    let val = Vec3::new(5.4856e-13, 4.4201e-13, 5.2481e-13);
    let pos = Vec3::new(1.6810e+06, 1.7953e+06, 2.2084e+06);
    let var = Vec3::new(4.3278e+09, 9.3046e+09, 6.6121e+09);
    let two_pi = 2.0 * std::f32::consts::PI;
    let mut xyz = Vec3::ZERO;
    for i in 0..3 {
        xyz[i] = val[i]
            * (two_pi * var[i]).sqrt()
            * (pos[i] * phase + shift[i]).cos()
            * (-sq(phase) * var[i]).exp();
    }
    xyz.x += 9.7470e-14
        * (two_pi * 4.5282e+09f32).sqrt()
        * (2.2399e+06 * phase + shift.x).cos()
        * (-4.5282e+09 * sq(phase)).exp();
    XYZ_TO_REC709 * (xyz / 1.0685e-7)
}

/// The thin film's Fresnel reflectance (RGB) seen from a medium of index `outside_ior` at
/// `cos_theta1` (v·h), for a film of index `film_ior` and thickness `thickness_nm` over a base
/// of normal-incidence reflectance `base_f0`. 1 under total internal reflection in the film;
/// never negative (out-of-gamut colours are clamped, as the extension does).
pub fn iridescence_fresnel(
    outside_ior: f32,
    film_ior: f32,
    cos_theta1: f32,
    thickness_nm: f32,
    base_f0: Vec3,
) -> Vec3 {
    let c1 = cos_theta1.clamp(0.0, 1.0);
    // The film's index fades to the outside's as it thins (no film: the base alone).
    let t = (thickness_nm / 0.03).clamp(0.0, 1.0);
    let eta2 = outside_ior + (film_ior - outside_ior) * (t * t * (3.0 - 2.0 * t));
    let sin2_theta2 = sq(outside_ior / eta2) * (1.0 - sq(c1));
    let cos2_theta2 = 1.0 - sin2_theta2;
    if cos2_theta2 < 0.0 {
        return Vec3::ONE;
    }
    let c2 = cos2_theta2.sqrt();
    // First interface (outside → film).
    let r12 = schlick1(ior_to_f0(eta2, outside_ior), c1);
    let t121 = 1.0 - r12;
    let phi12 = if eta2 < outside_ior {
        std::f32::consts::PI
    } else {
        0.0
    };
    let phi21 = std::f32::consts::PI - phi12;
    // Second interface (film → base), per channel.
    let mut r23 = Vec3::ZERO;
    let mut phi23 = Vec3::ZERO;
    for i in 0..3 {
        let base_ior = f0_to_ior(base_f0[i]);
        r23[i] = schlick1(ior_to_f0(base_ior, eta2), c2);
        if base_ior < eta2 {
            phi23[i] = std::f32::consts::PI;
        }
    }
    // Phase shift and the compound terms.
    let opd = 2.0 * eta2 * thickness_nm * c2;
    let phi = Vec3::splat(phi21) + phi23;
    let r123 = (r12 * r23).clamp(Vec3::splat(1e-5), Vec3::splat(0.9999));
    let sqrt_r123 = Vec3::new(r123.x.sqrt(), r123.y.sqrt(), r123.z.sqrt());
    let rs = sq(t121) * r23 / (Vec3::ONE - r123);
    // m = 0 (the DC term), then the pairs of Diracs m = 1, 2.
    let mut i = Vec3::splat(r12) + rs;
    let mut cm = rs - Vec3::splat(t121);
    for m in 1..=2 {
        cm *= sqrt_r123;
        let sm = 2.0 * eval_sensitivity(m as f32 * opd, m as f32 * phi);
        i += cm * sm;
    }
    i.max(Vec3::ZERO)
}

#[cfg(test)]
mod tests {
    use super::*;

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
