//! Low-discrepancy points and hemisphere / lobe sampling (MODELS.md §7), shared by the albedo
//! integrator here and by the CPU IBL reference. Directions are in a local frame with the normal
//! along +z unless said otherwise. `shaders_glsl/brdf/sampling.glsl` mirrors the first four.

use glam::Vec3;

use super::terms::{any_tangent, ALPHA_MIN, PI};

/// Van der Corput radical inverse of `i` in base 2 by integer bit reversal, as an `f32` in
/// `[0, 1)` with 24 significant bits (`(reverse_bits(i) >> 8) · 2⁻²⁴`, exact in `f32`).
pub fn radical_inverse_vdc(i: u32) -> f32 {
    (i.reverse_bits() >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// Hammersley point `i` of `n`: `(i/n, radical_inverse(i))`.
pub fn hammersley(i: u32, n: u32) -> (f32, f32) {
    (i as f32 / n.max(1) as f32, radical_inverse_vdc(i))
}

/// Cosine-weighted direction on the +z hemisphere (pdf `cosθ/π`).
pub fn sample_cosine_hemisphere(u1: f32, u2: f32) -> Vec3 {
    let r = u1.clamp(0.0, 1.0).sqrt();
    let phi = 2.0 * PI * u2;
    Vec3::new(
        r * phi.cos(),
        r * phi.sin(),
        (1.0 - u1).clamp(0.0, 1.0).sqrt(),
    )
}

/// Uniform direction on the +z hemisphere (pdf `1/(2π)`).
pub fn sample_uniform_hemisphere(u1: f32, u2: f32) -> Vec3 {
    let z = u1.clamp(0.0, 1.0);
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u2;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// GGX half vector as MODELS.md §7 writes it: `φ = 2π ξ1`,
/// `cosθ_h = sqrt((1 − ξ2)/(1 + (α² − 1) ξ2))`; pdf of h is `D(h)(n·h)`. `α` (= roughness²)
/// is clamped to [`ALPHA_MIN`] like [`super::d_ggx`].
pub fn importance_sample_ggx(xi1: f32, xi2: f32, alpha: f32) -> Vec3 {
    let a = alpha.max(ALPHA_MIN);
    let phi = 2.0 * PI * xi1;
    let den = 1.0 + (a * a - 1.0) * xi2;
    let cos_t = ((1.0 - xi2) / den).clamp(0.0, 1.0).sqrt();
    // sin² = α² ξ2 / den, not 1 − cos²: exact near the peak of a narrow lobe.
    let sin_t = (a * a * xi2 / den).clamp(0.0, 1.0).sqrt();
    Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t)
}

/// Anisotropic GGX (GTR2) half vector by stretching the slopes of the `α = 1` distribution
/// (`tan²θ = u1/(1 − u1)`, `φ = 2π u2`) by `(α_x, α_y)`; pdf of h is
/// `D_GTR2aniso(h)(n·h)` with x along +x and y along +y. Widths clamped to [`ALPHA_MIN`].
pub fn sample_ggx_aniso_h(u1: f32, u2: f32, ax: f32, ay: f32) -> Vec3 {
    let ax = ax.max(ALPHA_MIN);
    let ay = ay.max(ALPHA_MIN);
    let u1 = u1.clamp(0.0, 1.0 - 1e-7);
    let tan_t = (u1 / (1.0 - u1)).sqrt();
    let phi = 2.0 * PI * u2;
    let sx = ax * tan_t * phi.cos();
    let sy = ay * tan_t * phi.sin();
    let len = (sx * sx + sy * sy + 1.0).sqrt();
    Vec3::new(-sx / len, -sy / len, 1.0 / len)
}

/// Beckmann half vector: `tan²θ = −m² ln(1 − u1)`, `φ = 2π u2`; pdf of h `D(h)(n·h)`.
pub fn sample_beckmann_h(u1: f32, u2: f32, m: f32) -> Vec3 {
    let m = m.max(ALPHA_MIN);
    let tan2 = -m * m * (1.0 - u1.clamp(0.0, 1.0 - 1e-7)).ln();
    let cos_t = 1.0 / (1.0 + tan2).sqrt();
    let sin_t = tan2.sqrt() * cos_t;
    let phi = 2.0 * PI * u2;
    Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t)
}

/// GTR1 half vector (Burley 2012, appendix B): `cos²θ = (1 − α^(2(1 − u1)))/(1 − α²)`;
/// pdf of h `D(h)(n·h)`. Cosine-distributed h when `α ≥ 1`.
pub fn sample_gtr1_h(u1: f32, u2: f32, alpha: f32) -> Vec3 {
    let a = alpha.max(ALPHA_MIN);
    let a2 = a * a;
    // sin²θ = (α^(2(1 − u1)) − α²)/(1 − α²), computed directly (exact near the peak).
    let sin2 = if a2 >= 1.0 {
        u1
    } else {
        (a2.powf(1.0 - u1) - a2) / (1.0 - a2)
    };
    let sin2 = sin2.clamp(0.0, 1.0);
    let cos_t = (1.0 - sin2).sqrt();
    let sin_t = sin2.sqrt();
    let phi = 2.0 * PI * u2;
    Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t)
}

/// Power-cosine lobe around +z: `cosθ = u1^(1/(e + 1))`; pdf `(e + 1)/(2π) cos^e θ`.
pub fn sample_power_cosine(u1: f32, u2: f32, exponent: f32) -> Vec3 {
    let k = 1.0 / (exponent.max(0.0) + 1.0);
    let ln_u = u1.clamp(1e-30, 1.0).ln();
    let cos_t = (ln_u * k).exp();
    // sin² = 1 − u^(2k) = −expm1(2k ln u), exact for large exponents.
    let sin_t = (-(2.0 * k * ln_u).exp_m1()).clamp(0.0, 1.0).sqrt();
    let phi = 2.0 * PI * u2;
    Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t)
}

/// An orthonormal basis `(t, b)` around the unit vector `n`, so that `(t, b, n)` is right-handed.
pub fn ortho_basis(n: Vec3) -> (Vec3, Vec3) {
    let t = any_tangent(n);
    (t, n.cross(t))
}
