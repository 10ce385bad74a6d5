//! The individual terms (MODELS.md §3, §4, §6): normal distributions D, masking-shadowing G,
//! Fresnel F and diffuse lobes. One function per term, named as in `MODELS.md`, mirrored in
//! `shaders_glsl/brdf/terms.glsl` with the same names, operation order, clamps and epsilons.
//!
//! Every function returns a finite, non-negative value for any finite input.

use glam::Vec3;

/// π.
pub const PI: f32 = std::f32::consts::PI;
/// 1/π.
pub const INV_PI: f32 = std::f32::consts::FRAC_1_PI;
/// Smallest width a normal distribution is evaluated with (`α` of GGX/GTR1/GTR2, `α_x`, `α_y`,
/// Beckmann `m`). Roughness 0 would be a delta (0/0 in the seed's Beckmann shader); at
/// `α = 1e-3` the GGX peak is `1/(π α²) ≈ 3.2e5`, comfortably finite in `f32`. Disney's
/// Principled uses the same floor (`max(.001, …)`).
pub const ALPHA_MIN: f32 = 1e-3;
/// Floor for cosines that are divided by (`n·l`, `n·v`, `n·h`, `v·h`), applied *after* the
/// "`≤ 0` gives 0" test. Only directions within 0.006° of the horizon are affected.
pub const COS_EPS: f32 = 1e-4;
/// A vector whose squared length is at most this is treated as the zero vector.
pub const LEN2_EPS: f32 = 1e-12;
/// Largest refractive index η and extinction κ the Fresnel terms use (inputs are clamped to it).
/// Beyond ≈ 1.8e19 their squares overflow `f32` (Inf/Inf = NaN); at 1e9 every square stays below
/// 1e18, and the dip of r∥ near cos θ ≈ 1/η lies below cos θ = 1e-9, so for cos θ ≥ 1e-4 the clamp
/// moves F by less than 1e-4 from its η → ∞ limit of 1.
pub const IOR_MAX: f32 = 1e9;

/// GLSL `clamp(x, 0, 1)`.
#[inline]
pub fn saturate(x: f32) -> f32 {
    x.clamp(0.0, 1.0)
}

/// GLSL `mix(x, y, a) = x·(1 − a) + y·a`, written exactly as the GLSL specification defines it.
#[inline]
pub fn mix(x: f32, y: f32, a: f32) -> f32 {
    x * (1.0 - a) + y * a
}

/// `mix` for colours with a scalar weight.
#[inline]
pub fn mix3(x: Vec3, y: Vec3, a: f32) -> Vec3 {
    x * (1.0 - a) + y * a
}

/// `v / |v|`, or the zero vector when `|v|² ≤ LEN2_EPS`.
#[inline]
pub fn safe_normalize(v: Vec3) -> Vec3 {
    let len2 = v.dot(v);
    if len2 > LEN2_EPS {
        v * (1.0 / len2.sqrt())
    } else {
        Vec3::ZERO
    }
}

/// Clamps a cosine that is already known to be positive into `[COS_EPS, 1]`.
#[inline]
pub fn clamp_cos(c: f32) -> f32 {
    c.clamp(COS_EPS, 1.0)
}

/// Schlick's weight `(1 − clamp(u, 0, 1))^5`, computed as `m²·m²·m` like Disney's `SchlickFresnel`.
#[inline]
pub fn schlick_weight(u: f32) -> f32 {
    let m = saturate(1.0 - u);
    let m2 = m * m;
    m2 * m2 * m
}

/// An orthonormal tangent frame `(x, y)` around the unit normal `n`.
///
/// `x` is the given tangent made orthogonal to `n` (Gram-Schmidt); when it is zero or parallel to
/// `n` the bitangent is used instead (`x = y' × n`); when both are degenerate a frame is built
/// from `n` alone ([`any_tangent`]). `y = n × x`. The sign of `y` never matters to the BRDFs
/// (they only use `(h·y)²`, `(l·y)²`, `(v·y)²`).
pub fn tangent_frame(n: Vec3, x: Vec3, y: Vec3) -> (Vec3, Vec3) {
    let mut t = safe_normalize(x - n * n.dot(x));
    if t == Vec3::ZERO {
        let b = safe_normalize(y - n * n.dot(y));
        t = if b == Vec3::ZERO {
            any_tangent(n)
        } else {
            safe_normalize(b.cross(n))
        };
    }
    (t, n.cross(t))
}

/// A unit vector orthogonal to the unit vector `n` (Duff et al. 2017, "Building an Orthonormal
/// Basis, Revisited"); `(1, 0, 0)` for the zero vector.
pub fn any_tangent(n: Vec3) -> Vec3 {
    if n == Vec3::ZERO {
        return Vec3::X;
    }
    let sign = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x)
}

// ---------------------------------------------------------------------------------------------
// D: normal distribution functions (MODELS.md §4)
// ---------------------------------------------------------------------------------------------

/// `sin²θ_h = 1 − (n·h)²` from `n·h` alone, as `(1 − c)(1 + c)`. Near the peak of a narrow lobe
/// `n·h` itself has too few bits (`f32` spacing below 1 is 6e-8, so `1 − c²` moves in steps of
/// 1.2e-7 against `α² = 1e-6` at the floor): the models pass `|n × h|²` to the `*_sin2` forms
/// instead, which is exact to a few ulps at any angle (the trick Filament uses for half floats).
#[inline]
pub fn sin2_from_cos(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    (1.0 - c) * (1.0 + c)
}

/// Beckmann: `exp((c² − 1)/(m² c²)) / (π m² c⁴)`, `c = n·h`; 0 for `c ≤ 0`.
/// `m` is clamped to [`ALPHA_MIN`], `c` to `[COS_EPS, 1]` (the exponential is already 0 there
/// for any `m ≤ 1000`, so the clamp only prevents `0/0`).
pub fn d_beckmann(n_h: f32, m: f32) -> f32 {
    d_beckmann_sin2(n_h, sin2_from_cos(n_h), m)
}

/// [`d_beckmann`] with `sin²θ_h` given (`|n × h|²`): `exp(−s²/(m² c²)) / (π m² c⁴)`.
pub fn d_beckmann_sin2(n_h: f32, sin2_h: f32, m: f32) -> f32 {
    if n_h <= 0.0 {
        return 0.0;
    }
    let m = m.max(ALPHA_MIN);
    let c = clamp_cos(n_h);
    let s2 = saturate(sin2_h);
    let c2 = c * c;
    let m2 = m * m;
    (-s2 / (m2 * c2)).exp() / (PI * m2 * c2 * c2)
}

/// GGX / Trowbridge-Reitz (GTR2): `α² / (π ((n·h)²(α² − 1) + 1)²)`; 0 for `n·h ≤ 0`.
/// `α` is clamped to [`ALPHA_MIN`].
pub fn d_ggx(n_h: f32, alpha: f32) -> f32 {
    d_ggx_sin2(n_h, sin2_from_cos(n_h), alpha)
}

/// [`d_ggx`] with `sin²θ_h` given (`|n × h|²`): `α² / (π (α² c² + s²)²)`
/// (`c²(α² − 1) + 1 = α² c² + s²`).
pub fn d_ggx_sin2(n_h: f32, sin2_h: f32, alpha: f32) -> f32 {
    let Some((a2, t)) = gtr_terms(n_h, sin2_h, alpha) else {
        return 0.0;
    };
    a2 / (PI * t * t)
}

/// What GGX and GTR1 share: `(α², α² c² + s²)` with `α` clamped to [`ALPHA_MIN`] and `c = n·h`
/// to `[COS_EPS, 1]`; `None` for `n·h ≤ 0` (where both are 0).
fn gtr_terms(n_h: f32, sin2_h: f32, alpha: f32) -> Option<(f32, f32)> {
    if n_h <= 0.0 {
        return None;
    }
    let a = alpha.max(ALPHA_MIN);
    let a2 = a * a;
    let c = clamp_cos(n_h);
    Some((a2, a2 * c * c + saturate(sin2_h)))
}

/// GTR1 (Disney clearcoat): `(α² − 1) / (π ln(α²) (1 + (α² − 1)(n·h)²))`, `1/π` when `α² ≥ 1`;
/// 0 for `n·h ≤ 0`. `α` is clamped to [`ALPHA_MIN`].
pub fn d_gtr1(n_h: f32, alpha: f32) -> f32 {
    d_gtr1_sin2(n_h, sin2_from_cos(n_h), alpha)
}

/// [`d_gtr1`] with `sin²θ_h` given (`|n × h|²`): `(α² − 1) / (π ln(α²) (α² c² + s²))`.
pub fn d_gtr1_sin2(n_h: f32, sin2_h: f32, alpha: f32) -> f32 {
    let Some((a2, t)) = gtr_terms(n_h, sin2_h, alpha) else {
        return 0.0;
    };
    if a2 >= 1.0 {
        return INV_PI;
    }
    (a2 - 1.0) / (PI * a2.ln() * t)
}

/// Anisotropic GTR2: `1 / (π α_x α_y ((h·x/α_x)² + (h·y/α_y)² + (n·h)²)²)`; 0 for `n·h ≤ 0`.
/// `α_x`, `α_y` are clamped to [`ALPHA_MIN`], `n·h` to `[COS_EPS, 1]`.
pub fn d_gtr2_aniso(n_h: f32, h_x: f32, h_y: f32, ax: f32, ay: f32) -> f32 {
    if n_h <= 0.0 {
        return 0.0;
    }
    let ax = ax.max(ALPHA_MIN);
    let ay = ay.max(ALPHA_MIN);
    let c = clamp_cos(n_h);
    let sx = h_x / ax;
    let sy = h_y / ay;
    let t = sx * sx + sy * sy + c * c;
    1.0 / (PI * ax * ay * t * t)
}

// ---------------------------------------------------------------------------------------------
// G: masking-shadowing (MODELS.md §4)
// ---------------------------------------------------------------------------------------------

/// Cook-Torrance: `min(1, 2(n·h)(n·v)/(v·h), 2(n·h)(n·l)/(v·h))`; 0 when a cosine is `≤ 0`.
/// `v·h` is clamped to at least [`COS_EPS`].
pub fn g_cook_torrance(n_h: f32, n_v: f32, n_l: f32, v_h: f32) -> f32 {
    if n_h <= 0.0 || n_v <= 0.0 || n_l <= 0.0 {
        return 0.0;
    }
    let vh = v_h.max(COS_EPS);
    let g_v = 2.0 * n_h * n_v / vh;
    let g_l = 2.0 * n_h * n_l / vh;
    g_v.min(g_l).min(1.0)
}

/// Smith GGX, one direction: `2(n·v) / ((n·v) + sqrt(α² + (1 − α²)(n·v)²))`; 0 for `n·v ≤ 0`.
pub fn g1_smith_ggx(n_v: f32, alpha: f32) -> f32 {
    if n_v <= 0.0 {
        return 0.0;
    }
    let c = clamp_cos(n_v);
    let a2 = alpha * alpha;
    2.0 * c / (c + (a2 + (1.0 - a2) * c * c).sqrt())
}

/// Smith GGX, separable: `G1(l) · G1(v)`.
pub fn g_smith_ggx_separable(n_l: f32, n_v: f32, alpha: f32) -> f32 {
    g1_smith_ggx(n_l, alpha) * g1_smith_ggx(n_v, alpha)
}

/// Smith GGX, height-correlated (Heitz 2014): `1 / (1 + Λ(l) + Λ(v))` with
/// `Λ = (−1 + sqrt(1 + α² tan²θ))/2`, evaluated in the division-free form
/// `2 (n·l)(n·v) / ((n·l) sqrt((n·v)²(1 − α²) + α²) + (n·v) sqrt((n·l)²(1 − α²) + α²))`.
pub fn g_smith_ggx_correlated(n_l: f32, n_v: f32, alpha: f32) -> f32 {
    if n_l <= 0.0 || n_v <= 0.0 {
        return 0.0;
    }
    let cl = clamp_cos(n_l);
    let cv = clamp_cos(n_v);
    let a2 = alpha * alpha;
    let lambda_v = cl * (cv * cv * (1.0 - a2) + a2).sqrt();
    let lambda_l = cv * (cl * cl * (1.0 - a2) + a2).sqrt();
    2.0 * cl * cv / (lambda_v + lambda_l)
}

/// Smith Beckmann, one direction, by Walter et al. 2007's rational approximation (eq. 27):
/// `a = (n·v)/(m sqrt(1 − (n·v)²))`, `G1 = (3.535 a + 2.181 a²)/(1 + 2.276 a + 2.577 a²)` for
/// `a < 1.6`, else 1; 0 for `n·v ≤ 0`. `m` is the Beckmann width (clamped to [`ALPHA_MIN`]).
/// Within 0.35 % of the exact `2/(1 + erf(a) + e^{−a²}/(a√π))` (Mitsuba's form is this one).
pub fn g1_smith_beckmann(n_v: f32, m: f32) -> f32 {
    if n_v <= 0.0 {
        return 0.0;
    }
    let c = clamp_cos(n_v);
    let sin = (1.0 - c * c).max(0.0).sqrt();
    if sin <= 0.0 {
        return 1.0;
    }
    let a = c / (m.max(ALPHA_MIN) * sin);
    if a >= 1.6 {
        return 1.0;
    }
    (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a)
}

/// Smith Beckmann, separable: `G1(l) · G1(v)` ([`g1_smith_beckmann`]), the masking-shadowing that
/// belongs to the Beckmann distribution (the Smith GGX forms with the Beckmann width differ from it
/// by up to 14 % in G1 at n·v = 0.3).
pub fn g_smith_beckmann(n_l: f32, n_v: f32, m: f32) -> f32 {
    g1_smith_beckmann(n_l, m) * g1_smith_beckmann(n_v, m)
}

/// Schlick-GGX (UE4): `G1(v) = (n·v) / ((n·v)(1 − k) + k)`, `G = G1(l) G1(v)`.
/// Use [`k_punctual`] for lights and [`k_ibl`] for image-based lighting.
pub fn g_schlick_ggx(n_l: f32, n_v: f32, k: f32) -> f32 {
    if n_l <= 0.0 || n_v <= 0.0 {
        return 0.0;
    }
    let k = k.max(0.0);
    let cl = clamp_cos(n_l);
    let cv = clamp_cos(n_v);
    let gl = cl / (cl * (1.0 - k) + k);
    let gv = cv / (cv * (1.0 - k) + k);
    gl * gv
}

/// Schlick-GGX `k` for punctual lights: `(roughness + 1)² / 8`.
pub fn k_punctual(roughness: f32) -> f32 {
    let r1 = roughness + 1.0;
    r1 * r1 / 8.0
}

/// Schlick-GGX `k` for image-based lighting: `roughness² / 2`.
pub fn k_ibl(roughness: f32) -> f32 {
    roughness * roughness / 2.0
}

/// Smith GGX, height-correlated and anisotropic (Heitz 2014; KHR_materials_anisotropy's
/// `V_GGX_anisotropic` × 4 (n·l)(n·v)):
/// `2 (n·l)(n·v) / ((n·l) |(α_t t·v, α_b b·v, n·v)| + (n·v) |(α_t t·l, α_b b·l, n·l)|)`, with
/// `t`, `b` the anisotropy direction and its bitangent. Equal to [`g_smith_ggx_correlated`] when
/// `α_t = α_b`. 0 for `n·l ≤ 0` or `n·v ≤ 0`; the widths are clamped to [`ALPHA_MIN`].
#[allow(clippy::too_many_arguments)]
pub fn g_smith_ggx_correlated_aniso(
    n_l: f32,
    n_v: f32,
    t_l: f32,
    b_l: f32,
    t_v: f32,
    b_v: f32,
    at: f32,
    ab: f32,
) -> f32 {
    if n_l <= 0.0 || n_v <= 0.0 {
        return 0.0;
    }
    let at = at.max(ALPHA_MIN);
    let ab = ab.max(ALPHA_MIN);
    let cl = clamp_cos(n_l);
    let cv = clamp_cos(n_v);
    let lambda_v = cl * Vec3::new(at * t_v, ab * b_v, cv).length();
    let lambda_l = cv * Vec3::new(at * t_l, ab * b_l, cl).length();
    2.0 * cl * cv / (lambda_v + lambda_l)
}

/// Disney's anisotropic Smith GGX in visibility form (the `1/(4 (n·l)(n·v))` is inside):
/// `Vis(c, a, b) = 1 / (c + sqrt((a α_x)² + (b α_y)² + c²))`, `c = n·v`, `a = v·x`, `b = v·y`.
/// 0 for `n·v ≤ 0`. `G1 = 2 (n·v) · Vis`.
pub fn vis_smith_ggx_aniso(n_v: f32, v_x: f32, v_y: f32, ax: f32, ay: f32) -> f32 {
    if n_v <= 0.0 {
        return 0.0;
    }
    let c = clamp_cos(n_v);
    let sx = v_x * ax;
    let sy = v_y * ay;
    1.0 / (c + (sx * sx + sy * sy + c * c).sqrt())
}

/// Disney's isotropic Smith GGX in visibility form (clearcoat, `α_g = 0.25`):
/// `VisIso(c, g) = 1 / (c + sqrt(g² + c² − g²c²))`; 0 for `c ≤ 0`.
pub fn vis_smith_ggx_iso(n_v: f32, alpha_g: f32) -> f32 {
    if n_v <= 0.0 {
        return 0.0;
    }
    let c = clamp_cos(n_v);
    let a = alpha_g * alpha_g;
    let b = c * c;
    1.0 / (c + (a + b - a * b).sqrt())
}

// ---------------------------------------------------------------------------------------------
// F: Fresnel (MODELS.md §3)
// ---------------------------------------------------------------------------------------------

/// Schlick: `F0 + (1 − F0)(1 − v·h)^5`, with `1 − v·h` clamped to `[0, 1]`.
pub fn f_schlick(f0: Vec3, v_h: f32) -> Vec3 {
    let w = schlick_weight(v_h);
    f0 + (Vec3::ONE - f0) * w
}

/// UE4's spherical-Gaussian Schlick: `F0 + (1 − F0) · 2^((−5.55473 c − 6.98316) c)`,
/// `c = clamp(v·h, 0, 1)`.
pub fn f_schlick_sg(f0: Vec3, v_h: f32) -> Vec3 {
    let c = saturate(v_h);
    let w = ((-5.55473 * c - 6.98316) * c).exp2();
    f0 + (Vec3::ONE - f0) * w
}

/// Exact unpolarised Fresnel reflectance of a dielectric interface, `eta = η_t / η_i`,
/// `cos_i` the cosine of the incidence angle (clamped to `[0, 1]`). Compact form:
/// `g = sqrt(η² + c² − 1)`, `F = ½ (g − c)²/(g + c)² · (1 + (c(g + c) − 1)²/(c(g − c) + 1)²)`;
/// total internal reflection (`η² + c² − 1 < 0`) gives 1. `eta` is clamped to `[1e-4, IOR_MAX]`;
/// `g²` is summed as `(η − 1)(η + 1) + c²`, exact at η = 1 (index matching gives F = 0 at every
/// angle; `η² + c² − 1` cancelled to F ≈ 1e-4 at grazing incidence).
pub fn f_dielectric(cos_i: f32, eta: f32) -> f32 {
    let c = saturate(cos_i);
    let eta = eta.clamp(1e-4, IOR_MAX);
    let g2 = (eta - 1.0) * (eta + 1.0) + c * c;
    if g2 < 0.0 {
        return 1.0;
    }
    let g = g2.sqrt();
    let a = g - c;
    let b = g + c;
    if b <= 1e-6 {
        // g = c = 0: grazing incidence on η = 1, the limit is 1.
        return 1.0;
    }
    let p = c * b - 1.0;
    let q = c * a + 1.0;
    (0.5 * (a * a) / (b * b) * (1.0 + (p * p) / (q * q))).min(1.0)
}

/// Fresnel reflectance of a conductor with complex index `η + iκ`, one channel
/// (MODELS.md §3, the formula PBRT 2nd ed. uses; exact at normal incidence). `eta` is clamped to
/// `[0, IOR_MAX]`, `|k|` to at most `IOR_MAX`.
pub fn f_conductor_1(cos_i: f32, eta: f32, k: f32) -> f32 {
    let c = saturate(cos_i);
    let eta = eta.clamp(0.0, IOR_MAX);
    let k = k.abs().min(IOR_MAX);
    let c2 = c * c;
    let t0 = eta * eta + k * k;
    let t1 = 2.0 * eta * c;
    let r_perp = (t0 - t1 + c2) / (t0 + t1 + c2).max(1e-12);
    let r_par = (t0 * c2 - t1 + 1.0) / (t0 * c2 + t1 + 1.0);
    (0.5 * (r_perp + r_par)).clamp(0.0, 1.0)
}

/// Exact Fresnel reflectance of a conductor with complex index `η + iκ`, one channel (the
/// complex-index Fresnel equations for unpolarised light, as PBRT-v3's `FrConductor` and
/// Mitsuba 3's `fresnel_conductor` evaluate them; the outer medium has index 1):
/// `a² + b² = sqrt((η² − κ² − sin²θ)² + 4η²κ²)`, `a = sqrt((a² + b² + η² − κ² − sin²θ)/2)`,
/// `Rs = (a² + b² + cos²θ − 2a cosθ)/(a² + b² + cos²θ + 2a cosθ)`,
/// `Rp = Rs (cos²θ (a² + b²) + sin⁴θ − 2a cosθ sin²θ)/(cos²θ (a² + b²) + sin⁴θ + 2a cosθ sin²θ)`,
/// `F = (Rs + Rp)/2`. [`f_conductor_1`] is the usual approximation (up to 0.94 % off for gold).
/// `eta` is clamped to `[0, IOR_MAX]`, `|k|` to at most `IOR_MAX`.
pub fn f_conductor_exact_1(cos_i: f32, eta: f32, k: f32) -> f32 {
    let c = saturate(cos_i);
    let eta = eta.clamp(0.0, IOR_MAX);
    let k = k.abs().min(IOR_MAX);
    let c2 = c * c;
    let s2 = (1.0 - c2).max(0.0);
    let t0 = eta * eta - k * k - s2;
    let a2pb2 = (t0 * t0 + 4.0 * eta * eta * k * k).max(0.0).sqrt();
    let a = (0.5 * (a2pb2 + t0)).max(0.0).sqrt();
    let t1 = a2pb2 + c2;
    let t2 = 2.0 * c * a;
    let rs = (t1 - t2) / (t1 + t2).max(1e-12);
    let t3 = c2 * a2pb2 + s2 * s2;
    let t4 = t2 * s2;
    let rp = rs * (t3 - t4) / (t3 + t4).max(1e-12);
    (0.5 * (rs + rp)).clamp(0.0, 1.0)
}

/// [`f_conductor_exact_1`] per RGB channel.
pub fn f_conductor_exact(cos_i: f32, eta: Vec3, k: Vec3) -> Vec3 {
    Vec3::new(
        f_conductor_exact_1(cos_i, eta.x, k.x),
        f_conductor_exact_1(cos_i, eta.y, k.y),
        f_conductor_exact_1(cos_i, eta.z, k.z),
    )
}

/// Conductor Fresnel per RGB channel: `(r⊥² + r∥²)/2` with complex index `η + iκ`.
pub fn f_conductor(cos_i: f32, eta: Vec3, k: Vec3) -> Vec3 {
    Vec3::new(
        f_conductor_1(cos_i, eta.x, k.x),
        f_conductor_1(cos_i, eta.y, k.y),
        f_conductor_1(cos_i, eta.z, k.z),
    )
}

// ---------------------------------------------------------------------------------------------
// Diffuse (MODELS.md §5, §6)
// ---------------------------------------------------------------------------------------------

/// Lambert: `albedo / π`.
pub fn diffuse_lambert(albedo: Vec3) -> Vec3 {
    albedo * INV_PI
}

/// Disney's diffuse factor `Fd = mix(1, Fd90, FL) · mix(1, Fd90, FV)`,
/// `Fd90 = 0.5 + 2 · roughness · (l·h)²`, `FL = (1 − n·l)^5`, `FV = (1 − n·v)^5`.
pub fn fd_burley(n_l: f32, n_v: f32, l_h: f32, roughness: f32) -> f32 {
    let fl = schlick_weight(n_l);
    let fv = schlick_weight(n_v);
    let fd90 = 0.5 + 2.0 * l_h * l_h * roughness;
    mix(1.0, fd90, fl) * mix(1.0, fd90, fv)
}

/// Burley (Disney) diffuse: `albedo/π · Fd` (see [`fd_burley`]). Reciprocal.
pub fn diffuse_burley(albedo: Vec3, n_l: f32, n_v: f32, l_h: f32, roughness: f32) -> Vec3 {
    albedo * (INV_PI * fd_burley(n_l, n_v, l_h, roughness))
}

/// Disney's Hanrahan-Krueger subsurface factor
/// `ss = 1.25 (Fss (1/(n·l + n·v) − 0.5) + 0.5)`, `Fss = mix(1, Fss90, FL) · mix(1, Fss90, FV)`,
/// `Fss90 = roughness · (l·h)²`. `n·l`, `n·v` are clamped to `[COS_EPS, 1]`; 0 when either is
/// `≤ 0`.
pub fn ss_hanrahan_krueger(n_l: f32, n_v: f32, l_h: f32, roughness: f32) -> f32 {
    if n_l <= 0.0 || n_v <= 0.0 {
        return 0.0;
    }
    let cl = clamp_cos(n_l);
    let cv = clamp_cos(n_v);
    let fl = schlick_weight(cl);
    let fv = schlick_weight(cv);
    let fss90 = l_h * l_h * roughness;
    let fss = mix(1.0, fss90, fl) * mix(1.0, fss90, fv);
    1.25 * (fss * (1.0 / (cl + cv) - 0.5) + 0.5)
}

/// The subsurface (`ss`) diffuse lobe of Disney's BRDF on its own: `albedo/π · ss`
/// (see [`ss_hanrahan_krueger`]).
pub fn diffuse_hanrahan_krueger_ss(
    albedo: Vec3,
    n_l: f32,
    n_v: f32,
    l_h: f32,
    roughness: f32,
) -> Vec3 {
    albedo * (INV_PI * ss_hanrahan_krueger(n_l, n_v, l_h, roughness))
}

/// Qualitative Oren-Nayar (MODELS.md §6):
/// `ρ/π (A + B max(0, cos(φ_i − φ_o)) sin α tan β)`, `A = 1 − σ²/(2(σ² + 0.33))`,
/// `B = 0.45 σ²/(σ² + 0.09)`, `α = max(θ_i, θ_o)`, `β = min(θ_i, θ_o)`, `σ` in radians.
/// `cos_phi_diff` is `cos(φ_i − φ_o)`; 0 when `n·l ≤ 0` or `n·v ≤ 0`.
pub fn diffuse_oren_nayar(albedo: Vec3, sigma: f32, n_l: f32, n_v: f32, cos_phi_diff: f32) -> Vec3 {
    if n_l <= 0.0 || n_v <= 0.0 {
        return Vec3::ZERO;
    }
    let cl = clamp_cos(n_l);
    let cv = clamp_cos(n_v);
    let s2 = sigma * sigma;
    let a = 1.0 - 0.5 * s2 / (s2 + 0.33);
    let b = 0.45 * s2 / (s2 + 0.09);
    let cos_alpha = cl.min(cv);
    let cos_beta = cl.max(cv);
    let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
    let tan_beta = (1.0 - cos_beta * cos_beta).max(0.0).sqrt() / cos_beta;
    albedo * (INV_PI * (a + b * cos_phi_diff.max(0.0) * sin_alpha * tan_beta))
}

/// `cos(φ_l − φ_v)`: the cosine of the azimuth difference of `l` and `v` around the unit normal
/// `n`; 0 when either lies along `n` (where the Oren-Nayar term it multiplies vanishes anyway).
pub fn cos_phi_diff(n: Vec3, l: Vec3, v: Vec3) -> f32 {
    let lp = l - n * n.dot(l);
    let vp = v - n * n.dot(v);
    let d = lp.dot(lp) * vp.dot(vp);
    if d > LEN2_EPS {
        (lp.dot(vp) / d.sqrt()).clamp(-1.0, 1.0)
    } else {
        0.0
    }
}
