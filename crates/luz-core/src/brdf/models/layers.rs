//! The layers the ratified glTF PBR extensions put on the metallic-roughness model (issue 34),
//! mirrored function for function in `shaders_glsl/brdf/models.glsl`.
//!
//! KHR_materials_clearcoat: a clear dielectric coat (ior 1.5, so F0 = 0.04) over the base, with its
//! own roughness. The extension's layering is
//! `f = f_base · (1 − clearcoat · Fc) + clearcoat · f_coat`, where `f_coat = D G F / (4 (n·l)(n·v))`
//! is a microfacet lobe of width `clearcoat_roughness²` with Schlick's F (F0 0.04) at `v·h`, and
//! `Fc` is Schlick's F at the coat normal and the view, `F0 + (1 − F0)(1 − n·v)^5`. The coat takes
//! the material's distribution and geometry terms (glTF's are GGX and the height-correlated
//! Smith term, the extension's own), so its energy compensation reads the material's split-sum
//! table.
//!
//! With energy compensation on (the environment's `energy_compensation`), `Fc` is replaced by
//! the coat's compensated directional albedo `E_ms(n·v)` and the coat lobe gets the same
//! multi-scatter factor as the base's specular ([`crate::brdf::energy_scale`] with F0 0.04): the
//! base then receives exactly what the coat does not reflect, so a white furnace stays 1 whatever
//! the coat (the extension's `Fc` equals the coat's albedo only for a smooth coat).

use glam::Vec3;

use super::{MetalRoughParams, Terms};
use crate::brdf::{clamp_cos, mix, safe_normalize, schlick_weight, ALPHA_MIN};

/// F0 of the clear coat (ior 1.5), as KHR_materials_clearcoat fixes it.
pub const CLEARCOAT_F0: f32 = 0.04;

/// What the coat takes from the base and gives its own lobe at one view.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClearcoatEnergy {
    /// The coat's reflectance at the view: the base is weighted by `1 − clearcoat · albedo`.
    pub albedo: f32,
    /// Multiplies the coat's lobe (1 without energy compensation).
    pub specular: f32,
}

impl ClearcoatEnergy {
    /// The extension's own: Schlick's Fresnel of F0 0.04 at `n_v`, the lobe unscaled.
    pub fn schlick(n_v: f32) -> Self {
        Self {
            albedo: CLEARCOAT_F0 + (1.0 - CLEARCOAT_F0) * schlick_weight(n_v),
            specular: 1.0,
        }
    }
}

/// The energy-compensated coat of `p` at `n_v`: its directional albedo `E_ms` from the split-sum
/// table and the multi-scatter factor of its lobe.
pub fn clearcoat_energy(p: &MetalRoughParams, n_v: f32) -> ClearcoatEnergy {
    let e = crate::brdf::energy_scale(
        p.geometry,
        Vec3::splat(CLEARCOAT_F0),
        n_v,
        p.clearcoat_roughness,
    );
    ClearcoatEnergy {
        albedo: 1.0 - e.diffuse.x,
        specular: e.specular.x,
    }
}

/// The coat's lobe `D G F / (4 (n·l)(n·v))` for unit `n` (the coat normal), `l` and `v` with
/// `n·l > 0` and `n·v > 0`; sanitised parameters.
pub fn clearcoat_specular(p: &MetalRoughParams, n: Vec3, l: Vec3, v: Vec3) -> f32 {
    let n_l = clamp_cos(n.dot(l));
    let n_v = clamp_cos(n.dot(v));
    let r = p.clearcoat_roughness;
    let a = (r * r).max(ALPHA_MIN);
    let h = safe_normalize(l + v);
    let n_h = n.dot(h);
    let sin2_h = n.cross(h).length_squared();
    let v_h = v.dot(h);
    let d = p.distribution.eval(n_h, sin2_h, a);
    let g = p.geometry.eval(n_h, n_v, n_l, v_h, a, r);
    let f = CLEARCOAT_F0 + (1.0 - CLEARCOAT_F0) * schlick_weight(v_h);
    f * (d * g / (4.0 * n_l * n_v))
}

/// The base's terms `t` under the coat of `p`: diffuse and specular weighted by
/// `1 − clearcoat · e.albedo`, plus `clearcoat · e.specular · f_coat · cosines` in the
/// specular, `f_coat` at the coat's normal `n` and `cosines` = (n_coat·l)/(n·l), which turns
/// the caller's cosine into the coat's (1 when the coat's normal is the base's; 0 below it).
pub fn clearcoat_layer(
    t: Terms,
    p: &MetalRoughParams,
    (n, cosines): (Vec3, f32),
    l: Vec3,
    v: Vec3,
    e: ClearcoatEnergy,
) -> Terms {
    let keep = 1.0 - p.clearcoat * e.albedo;
    let coat = if cosines > 0.0 {
        p.clearcoat * e.specular * clearcoat_specular(p, n, l, v) * cosines
    } else {
        0.0
    };
    Terms {
        diffuse: t.diffuse * keep,
        specular: t.specular * keep + Vec3::splat(coat),
        ..t
    }
}

// ---------------------------------------------------------------------------------------------
// KHR_materials_sheen
// ---------------------------------------------------------------------------------------------
// The extension's sheen lobe: `f_sheen = sheenColor · D_Charlie · V_sheen` (Estevez & Kulla 2017's
// Charlie distribution at `α = sheenRoughness²`, the specification's visibility term, Neubelt &
// Pettineo's denominator with Estevez & Kulla's Λ fit), layered over the base as
// `f = f_base · (1 − max(sheenColor) · E_sheen(n·v)) + f_sheen`, with `E_sheen` the lobe's own
// directional albedo (white sheen colour). `E_sheen` is a fit ([`SHEEN_ALBEDO_GLSL`]:
// exp of a polynomial in √(n·v) and ln(sheen roughness), 8 × 7 coefficients) to the integral
// ([`sheen_albedo_integrated`]) that this module computes; the CPU and the GLSL evaluate the
// same coefficients the same way, so they scale by the same numbers and a white furnace stays 1 (the lobe's albedo is what the base
// loses). The sheen is part of `Terms::diffuse` (a broad lobe, like Principled's sheen).

/// The smallest sheen roughness (the specification's sample code clamps at 1e-6, which raises
/// a float to the power 5·10¹¹). Below 0.07 the lobe lives within a few degrees of grazing and
/// its albedo changes faster than a 32-node table could follow (0.17 between nodes with 0.01);
/// at 0.07 it looks the same at every view but grazing.
pub const SHEEN_ROUGHNESS_MIN: f32 = 0.07;

/// The GLSL file holding the fit of the sheen albedo (`shaders_glsl/brdf/sheen_albedo.glsl`),
/// read by the CPU too: one source of the coefficients.
pub const SHEEN_ALBEDO_GLSL: &str =
    include_str!("../../../../../shaders_glsl/brdf/sheen_albedo.glsl");

/// Coefficients of the fit per axis: polynomial degree + 1 in √(n·v) and in ln(roughness).
pub const SHEEN_FIT_X: usize = crate::glsl::brdf_sheen_albedo::SHEEN_FIT_X as usize;
pub const SHEEN_FIT_S: usize = crate::glsl::brdf_sheen_albedo::SHEEN_FIT_S as usize;

/// The sheen's `α = max(sheenRoughness, SHEEN_ROUGHNESS_MIN)²`.
pub fn sheen_alpha(sheen_roughness: f32) -> f32 {
    let r = sheen_roughness.max(SHEEN_ROUGHNESS_MIN);
    r * r
}

/// The Charlie distribution `(2 + 1/α) sin(θh)^(1/α) / (2π)`, `sin2_h = |n × h|²`.
pub fn d_charlie(alpha: f32, sin2_h: f32) -> f32 {
    let inv_r = 1.0 / alpha;
    (2.0 + inv_r) * sin2_h.max(0.0).powf(0.5 * inv_r) * (0.5 * crate::brdf::INV_PI)
}

/// The specification's fit `L(x) = a / (1 + b x^c) + d x + e`, its coefficients interpolated by
/// `(1 − α)²`.
fn sheen_l(x: f32, alpha: f32) -> f32 {
    let t = (1.0 - alpha) * (1.0 - alpha);
    let a = mix(21.5473, 25.3245, t);
    let b = mix(3.82987, 3.32435, t);
    let c = mix(0.19823, 0.16801, t);
    let d = mix(-1.97760, -1.27393, t);
    let e = mix(-4.32054, -4.85967, t);
    a / (1.0 + b * x.powf(c)) + d * x + e
}

/// The sheen's Λ: `exp(L(cos θ))` below cos θ = 0.5, `exp(2 L(0.5) − L(1 − cos θ))` above.
pub fn lambda_sheen(cos_theta: f32, alpha: f32) -> f32 {
    if cos_theta.abs() < 0.5 {
        sheen_l(cos_theta, alpha).exp()
    } else {
        (2.0 * sheen_l(0.5, alpha) - sheen_l(1.0 - cos_theta, alpha)).exp()
    }
}

/// The specification's visibility `clamp(1 / ((1 + Λ(n·v) + Λ(n·l)) · 4 (n·l)(n·v)), 0, 1)`.
pub fn v_sheen(n_l: f32, n_v: f32, alpha: f32) -> f32 {
    let denom = (1.0 + lambda_sheen(n_v, alpha) + lambda_sheen(n_l, alpha)) * (4.0 * n_v * n_l);
    (1.0 / denom).clamp(0.0, 1.0)
}

// The GPU's Λ_sheen: a polynomial fit of the specification's `L` (so of `ln Λ`), which the
// lighting shaders evaluate per light instead of `L`'s power, division and exponential
// (docs/brdf.md, "`BrdfParams`", the sheen). [`lambda_sheen`] above stays the reference;
// these mirror the GLSL's `sheen_lambda_fit` and `lambda_sheen_of`
// (shaders_glsl/brdf/models.glsl), and `brdf::tests::sheen_lambda_fit_is_lambda` bounds their
// error.

/// The GLSL file holding the fit of Λ_sheen (`shaders_glsl/brdf/sheen_lambda.glsl`), read by
/// the CPU too: one source of the coefficients.
pub const SHEEN_LAMBDA_GLSL: &str =
    include_str!("../../../../../shaders_glsl/brdf/sheen_lambda.glsl");

/// The fit's degree in its variable `q` (polynomial in `w^(1/8)`, mapped onto [−1, 1]).
pub const SHEEN_LAMBDA_DEGREE: usize = 6;
/// The degree of each of its coefficients in `s = 2 (1 − α)² − 1`.
pub const SHEEN_LAMBDA_DEGREE_S: usize = 3;
/// The smallest `w = min(cos θ, 1 − cos θ)` the fit covers: the renderer's cosines are clamped
/// to [`crate::brdf::COS_EPS`] already.
pub const SHEEN_LAMBDA_W_MIN: f32 = crate::brdf::COS_EPS;

/// The fit's constants: `q = w^(1/8) · q_scale + q_offset` (−1 at [`SHEEN_LAMBDA_W_MIN`], 1 at
/// w = 0.5), and `c[(SHEEN_LAMBDA_DEGREE_S + 1) · j + k]` multiplying `q^j s^k` in `log2 Λ`.
#[derive(Debug, Clone, PartialEq)]
pub struct SheenLambdaConstants {
    pub q_scale: f32,
    pub q_offset: f32,
    pub c: Vec<f32>,
}

/// The fit at one α (what the GLSL's `SheenFit` holds, once per pixel): the coefficients of
/// `log2 Λ` in `q`, and its value at w = 0.5 (q = 1: their sum).
/// (The Rust one carries the constants' `q` mapping too, which the GLSL's are defines.)
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SheenFit {
    pub c: [f32; SHEEN_LAMBDA_DEGREE + 1],
    pub l_half: f32,
    pub q_scale: f32,
    pub q_offset: f32,
}

/// The fit's `q` range for `w` in [[`SHEEN_LAMBDA_W_MIN`], 0.5].
fn sheen_lambda_q_range() -> (f64, f64) {
    ((SHEEN_LAMBDA_W_MIN as f64).powf(0.125), 0.5f64.powf(0.125))
}

/// The specification's `L(w)` at `t = (1 − α)²`, in f64 (what [`sheen_l`] computes).
fn sheen_l_f64(w: f64, t: f64) -> f64 {
    let m = |a: f64, b: f64| a + (b - a) * t;
    let (a, b, c) = (
        m(21.5473, 25.3245),
        m(3.82987, 3.32435),
        m(0.19823, 0.16801),
    );
    let (d, e) = (m(-1.97760, -1.27393), m(-4.32054, -4.85967));
    a / (1.0 + b * w.powf(c)) + d * w + e
}

/// The `n` Chebyshev nodes on [−1, 1].
fn chebyshev_nodes(n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| (std::f64::consts::PI * (k as f64 + 0.5) / n as f64).cos())
        .collect()
}

/// The polynomial through `values` at [`chebyshev_nodes`] (as many), as monomial coefficients.
fn chebyshev_monomial(values: &[f64]) -> Vec<f64> {
    let n = values.len();
    let mut cheb: Vec<f64> = (0..n)
        .map(|j| {
            2.0 / n as f64
                * (0..n)
                    .map(|k| {
                        values[k]
                            * (std::f64::consts::PI * j as f64 * (k as f64 + 0.5) / n as f64).cos()
                    })
                    .sum::<f64>()
        })
        .collect();
    cheb[0] *= 0.5;
    // T_j in monomials: T_0 = 1, T_1 = x, T_j = 2x T_(j−1) − T_(j−2).
    let mut t: Vec<Vec<f64>> = vec![vec![1.0], vec![0.0, 1.0]];
    for j in 2..n {
        let mut next = vec![0.0; j + 1];
        for (k, v) in t[j - 1].iter().enumerate() {
            next[k + 1] += 2.0 * v;
        }
        for (k, v) in t[j - 2].iter().enumerate() {
            next[k] -= v;
        }
        t.push(next);
    }
    let mut mono = vec![0.0; n];
    for (j, c) in cheb.iter().enumerate() {
        for (k, v) in t[j].iter().enumerate() {
            mono[k] += c * v;
        }
    }
    mono
}

/// Fits `log2 Λ = L(w) / ln 2` below cos θ = 0.5: Chebyshev interpolation in `q` (7 nodes) and,
/// for each of its coefficients, in `s` (4 nodes over α from 1 to 0), from the specification's
/// `L` in f64. `brdf::tests::sheen_lambda_fit_is_lambda` bounds the error of the result.
pub fn fit_sheen_lambda() -> SheenLambdaConstants {
    let (ql, qh) = sheen_lambda_q_range();
    let (nq, ns) = (SHEEN_LAMBDA_DEGREE + 1, SHEEN_LAMBDA_DEGREE_S + 1);
    // At each of s's nodes, the coefficients in q; then each coefficient interpolated in s.
    let in_q: Vec<Vec<f64>> = chebyshev_nodes(ns)
        .iter()
        .map(|&s| {
            let values: Vec<f64> = chebyshev_nodes(nq)
                .iter()
                .map(|&x| {
                    let q = 0.5 * (ql + qh) + 0.5 * (qh - ql) * x;
                    sheen_l_f64(q.powi(8), 0.5 * (s + 1.0)) * std::f64::consts::LOG2_E
                })
                .collect();
            chebyshev_monomial(&values)
        })
        .collect();
    let mut c = Vec::with_capacity(nq * ns);
    for j in 0..nq {
        let values: Vec<f64> = in_q.iter().map(|row| row[j]).collect();
        c.extend(chebyshev_monomial(&values).iter().map(|&v| v as f32));
    }
    SheenLambdaConstants {
        q_scale: (2.0 / (qh - ql)) as f32,
        q_offset: (-(qh + ql) / (qh - ql)) as f32,
        c,
    }
}

/// The GLSL source of the fit `f` (what `shaders_glsl/brdf/sheen_lambda.glsl` holds:
/// `cargo run --release -p luz-core --example sheen_lambda_fit` writes it from
/// [`fit_sheen_lambda`]). Literal indices only (glslang folds them to constants).
pub fn sheen_lambda_glsl_source(f: &SheenLambdaConstants) -> String {
    let ns = SHEEN_LAMBDA_DEGREE_S + 1;
    let mut s = String::from(
        "// KHR_materials_sheen's Λ(cos θ) as the GPU evaluates it: log2 Λ = P(q) below cos θ = 0.5, 2 P(1) − P(q)\n\
         // above, q = w^(1/8) · SHEEN_LAMBDA_Q_SCALE + SHEEN_LAMBDA_Q_OFFSET, w = min(cos θ, 1 − cos θ) clamped to\n\
         // [SHEEN_LAMBDA_W_MIN, 0.5]; P's coefficient of q^j is Σ SHEEN_LAMBDA_FIT[4 j + k] s^k, s = 2 (1 − α)² − 1.\n\
         // A fit of the specification's L (brdf::fit_sheen_lambda; its error: brdf::tests::sheen_lambda_fit_is_lambda).\n\
         // Generated by brdf::models::layers::sheen_lambda_glsl_source (cargo run --release -p luz-core\n\
         // --example sheen_lambda_fit); the CPU reads the constants from this file.\n\
         #ifndef LUZ_SHEEN_LAMBDA_GLSL\n#define LUZ_SHEEN_LAMBDA_GLSL\n",
    );
    s += &format!("#define SHEEN_LAMBDA_W_MIN {:?}\n", SHEEN_LAMBDA_W_MIN);
    s += &format!("#define SHEEN_LAMBDA_Q_SCALE {:?}\n", f.q_scale);
    s += &format!("#define SHEEN_LAMBDA_Q_OFFSET {:?}\n", f.q_offset);
    s += &format!("const float SHEEN_LAMBDA_FIT[{}] = float[](\n", f.c.len());
    let rows: Vec<String> =
        f.c.chunks(ns)
            .map(|row| {
                let r: Vec<String> = row.iter().map(|v| format!("{v:?}")).collect();
                format!("    {}", r.join(", "))
            })
            .collect();
    s += &rows.join(",\n");
    s += "\n);\n#endif\n";
    s
}

/// The constants of [`SHEEN_LAMBDA_GLSL`].
pub fn sheen_lambda_constants() -> &'static SheenLambdaConstants {
    static FIT: std::sync::OnceLock<SheenLambdaConstants> = std::sync::OnceLock::new();
    FIT.get_or_init(|| {
        let define = |name: &str| -> f32 {
            SHEEN_LAMBDA_GLSL
                .lines()
                .find_map(|l| l.strip_prefix(&format!("#define {name} ")))
                .and_then(|v| v.trim().parse().ok())
                .unwrap_or(f32::NAN)
        };
        let c = glsl_float_array(SHEEN_LAMBDA_GLSL);
        assert_eq!(
            c.len(),
            (SHEEN_LAMBDA_DEGREE + 1) * (SHEEN_LAMBDA_DEGREE_S + 1),
            "sheen_lambda.glsl"
        );
        SheenLambdaConstants {
            q_scale: define("SHEEN_LAMBDA_Q_SCALE"),
            q_offset: define("SHEEN_LAMBDA_Q_OFFSET"),
            c,
        }
    })
}

/// The fit at `alpha` (the GLSL's `sheen_lambda_fit`, once per pixel): each coefficient's cubic
/// in `s = 2 (1 − α)² − 1` by Horner, and their sum.
pub fn sheen_lambda_fit(alpha: f32) -> SheenFit {
    sheen_lambda_fit_of(alpha, sheen_lambda_constants())
}

/// [`sheen_lambda_fit`] with the constants `k` (a new fit's, before it is written).
pub fn sheen_lambda_fit_of(alpha: f32, k: &SheenLambdaConstants) -> SheenFit {
    let s = 2.0 * (1.0 - alpha) * (1.0 - alpha) - 1.0;
    let mut c = [0.0f32; SHEEN_LAMBDA_DEGREE + 1];
    for (j, cj) in c.iter_mut().enumerate() {
        let row = &k.c[j * 4..j * 4 + 4];
        *cj = ((row[3] * s + row[2]) * s + row[1]) * s + row[0];
    }
    let l_half = c[0] + c[1] + c[2] + c[3] + c[4] + c[5] + c[6];
    SheenFit {
        c,
        l_half,
        q_scale: k.q_scale,
        q_offset: k.q_offset,
    }
}

/// Λ_sheen at `cos_theta` in [0, 1] from the fit `f` (the GLSL's `lambda_sheen_of`): `2^P(q)`
/// below 0.5, `2^(2 P(1) − P(q))` above; [`lambda_sheen`] is what it approximates.
pub fn lambda_sheen_of(cos_theta: f32, f: &SheenFit) -> f32 {
    let low = cos_theta < 0.5;
    let w = cos_theta
        .min(1.0 - cos_theta)
        .clamp(SHEEN_LAMBDA_W_MIN, 0.5);
    let q = w.sqrt().sqrt().sqrt() * f.q_scale + f.q_offset;
    let c = &f.c;
    let p = (((((c[6] * q + c[5]) * q + c[4]) * q + c[3]) * q + c[2]) * q + c[1]) * q + c[0];
    (if low { p } else { 2.0 * f.l_half - p }).exp2()
}

/// The largest errors of the fit `k` against the specification's Λ ([`lambda_sheen`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SheenLambdaError {
    /// Relative error of Λ where Λ ≥ 1e-3 (below, Λ changes `1 + Λ(n·v) + Λ(n·l)` by less).
    pub lambda: f32,
    /// Relative error of the visibility [`v_sheen`] with Λ from the fit (so of the lobe
    /// `D · V` and of `D · V · n·l`: D and n·l are the same either way).
    pub visibility: f32,
    /// Where the visibility's is largest: (α, n·l, n·v).
    pub at: (f32, f32, f32),
}

/// The fit's errors over α = r² for sheen roughness r from [`SHEEN_ROUGHNESS_MIN`] to 1 (48
/// values, so α from 0.0049 to 1) and cosines from [`crate::brdf::COS_EPS`] to 1 (120 for the
/// view, 480 for the light; geometric towards both ends, where Λ's fit bends most).
pub fn sheen_lambda_fit_error(k: &SheenLambdaConstants) -> SheenLambdaError {
    let cosines = |n: usize| -> Vec<f32> {
        let w0 = SHEEN_LAMBDA_W_MIN as f64;
        let mut c: Vec<f32> = (0..n / 2)
            .map(|i| w0 * (0.5 / w0).powf(i as f64 / (n / 2 - 1) as f64))
            .flat_map(|w| [w as f32, (1.0 - w) as f32])
            .collect();
        c.push(1.0);
        c
    };
    let (lights, views) = (cosines(480), cosines(120));
    let mut e = SheenLambdaError {
        lambda: 0.0,
        visibility: 0.0,
        at: (0.0, 0.0, 0.0),
    };
    for i in 0..48 {
        let r = SHEEN_ROUGHNESS_MIN + (1.0 - SHEEN_ROUGHNESS_MIN) * i as f32 / 47.0;
        let alpha = sheen_alpha(r);
        let f = sheen_lambda_fit_of(alpha, k);
        let exact: Vec<f32> = lights.iter().map(|&c| lambda_sheen(c, alpha)).collect();
        let fit: Vec<f32> = lights.iter().map(|&c| lambda_sheen_of(c, &f)).collect();
        for (x, y) in exact.iter().zip(&fit) {
            if *x >= 1e-3 {
                e.lambda = e.lambda.max((y - x).abs() / x);
            }
        }
        for &n_v in &views {
            let (lv, lv_fit) = (lambda_sheen(n_v, alpha), lambda_sheen_of(n_v, &f));
            for (j, &n_l) in lights.iter().enumerate() {
                let v =
                    |a: f32, b: f32| (1.0 / ((1.0 + a + b) * (4.0 * n_v * n_l))).clamp(0.0, 1.0);
                let (x, y) = (v(lv, exact[j]), v(lv_fit, fit[j]));
                let d = (y - x).abs() / x;
                if d > e.visibility {
                    e.visibility = d;
                    e.at = (alpha, n_l, n_v);
                }
            }
        }
    }
    e
}

/// The white sheen lobe `D_Charlie · V_sheen` for unit `n`, `l` and `v` with `n·l > 0` and
/// `n·v > 0`, at sheen roughness `r`.
pub fn sheen_specular(r: f32, n: Vec3, l: Vec3, v: Vec3) -> f32 {
    let alpha = sheen_alpha(r);
    let h = safe_normalize(l + v);
    let sin2_h = n.cross(h).length_squared();
    d_charlie(alpha, sin2_h) * v_sheen(clamp_cos(n.dot(l)), clamp_cos(n.dot(v)), alpha)
}

/// The white sheen lobe's directional albedo `∫ D V (n·l) dl` at `n_v` and sheen roughness `r`,
/// by a midpoint rule over the hemisphere (what the table holds at its nodes).
pub fn sheen_albedo_integrated(n_v: f32, r: f32) -> f32 {
    let (nt, np) = (256, 128);
    let n_v = clamp_cos(n_v);
    let v = Vec3::new((1.0 - n_v * n_v).max(0.0).sqrt(), 0.0, n_v);
    let mut sum = 0.0f64;
    let (dt, dp) = (
        std::f32::consts::FRAC_PI_2 / nt as f32,
        std::f32::consts::PI / np as f32,
    );
    for i in 0..nt {
        let t = (i as f32 + 0.5) * dt;
        let (st, ct) = t.sin_cos();
        for j in 0..np {
            // φ over [0, π], doubled: the lobe is symmetric about the plane of incidence.
            let p = (j as f32 + 0.5) * dp;
            let l = Vec3::new(st * p.cos(), st * p.sin(), ct);
            let f = sheen_specular(r, Vec3::Z, l, v);
            sum += (f * ct * st * dt * dp * 2.0) as f64;
        }
    }
    sum as f32
}

/// The numbers of the first `const float NAME[N] = float[](…)` in a generated GLSL file (the fits'
/// coefficients, which the CPU reads from the same file as the shaders).
fn glsl_float_array(source: &str) -> Vec<f32> {
    source
        .split_once("float[](")
        .and_then(|(_, rest)| rest.split_once(')'))
        .map(|(numbers, _)| numbers)
        .unwrap_or("")
        .split(',')
        .filter_map(|s| s.trim().parse().ok())
        .collect()
}

/// The fit's coefficients of [`SHEEN_ALBEDO_GLSL`]: `c[a · SHEEN_FIT_S + b]` multiplies
/// `u^a t^b` ([`sheen_fit_variables`]).
pub fn sheen_albedo_fit() -> &'static [f32] {
    static FIT: std::sync::OnceLock<Vec<f32>> = std::sync::OnceLock::new();
    FIT.get_or_init(|| {
        let c = glsl_float_array(SHEEN_ALBEDO_GLSL);
        assert_eq!(c.len(), SHEEN_FIT_X * SHEEN_FIT_S, "sheen_albedo.glsl");
        c
    })
}

/// The fit's variables at `n_v` and sheen roughness `r`, each mapped onto [−1, 1] (which keeps
/// the coefficients small enough for f32): u = 2√(n·v) − 1 and t from
/// s = ln(max(r, SHEEN_ROUGHNESS_MIN)) as 1 − 2 s / ln(SHEEN_ROUGHNESS_MIN).
pub fn sheen_fit_variables(n_v: f32, r: f32) -> (f32, f32) {
    let s = r.clamp(SHEEN_ROUGHNESS_MIN, 1.0).ln();
    (
        2.0 * n_v.clamp(0.0, 1.0).sqrt() - 1.0,
        1.0 - 2.0 * s / SHEEN_ROUGHNESS_MIN.ln(),
    )
}

/// The sheen lobe's directional albedo `E_sheen(n·v)` at sheen roughness `r`:
/// `exp(Σ c_ab u^a t^b)` ([`sheen_fit_variables`]), Horner in t then u (as the GLSL's
/// `sheen_albedo`).
pub fn sheen_albedo(n_v: f32, r: f32) -> f32 {
    let c = sheen_albedo_fit();
    let (x, s) = sheen_fit_variables(n_v, r);
    let mut p = 0.0f32;
    for a in (0..SHEEN_FIT_X).rev() {
        let mut q = 0.0f32;
        for b in (0..SHEEN_FIT_S).rev() {
            q = q * s + c[a * SHEEN_FIT_S + b];
        }
        p = p * x + q;
    }
    p.exp()
}

/// Fits the coefficients of [`sheen_albedo`] to [`sheen_albedo_integrated`] on a 48 × 40 grid
/// (√(n·v) uniform in [0, 1], ln(roughness) uniform in [ln 0.07, 0]): least squares on
/// ln(max(E_sheen, 0.001)) weighted by max(E, 0.003)² (the log error counts as the absolute
/// error; where the albedo is ~0 the fit only has to stay near 0), then 40 Lawson rounds
/// towards the smallest largest error.
pub fn fit_sheen_albedo() -> Vec<f32> {
    let (nx, ns) = (48usize, 40usize);
    let s0 = SHEEN_ROUGHNESS_MIN.ln();
    let mut pts = Vec::with_capacity(nx * ns);
    for j in 0..ns {
        let s = s0 * (1.0 - j as f32 / (ns - 1) as f32);
        for i in 0..nx {
            let x = i as f32 / (nx - 1) as f32;
            let (u, t) = sheen_fit_variables(x * x, s.exp());
            pts.push((
                u as f64,
                t as f64,
                sheen_albedo_integrated(x * x, s.exp()) as f64,
            ));
        }
    }
    let m = SHEEN_FIT_X * SHEEN_FIT_S;
    let basis = |x: f64, s: f64| -> Vec<f64> {
        let mut f = Vec::with_capacity(m);
        for a in 0..SHEEN_FIT_X {
            for b in 0..SHEEN_FIT_S {
                f.push(x.powi(a as i32) * s.powi(b as i32));
            }
        }
        f
    };
    let rows: Vec<Vec<f64>> = pts.iter().map(|&(x, s, _)| basis(x, s)).collect();
    let ys: Vec<f64> = pts.iter().map(|p| p.2.max(1e-3).ln()).collect();
    let mut w: Vec<f64> = pts.iter().map(|p| p.2.max(0.003).powi(2)).collect();
    let mut c = vec![0.0f64; m];
    for _ in 0..40 {
        c = weighted_least_squares(&rows, &ys, &w);
        let err: Vec<f64> = rows
            .iter()
            .zip(&pts)
            .map(|(f, p)| {
                let e: f64 = f.iter().zip(&c).map(|(f, c)| f * c).sum();
                (e.min(5.0).exp() - p.2).abs()
            })
            .collect();
        let worst = err.iter().cloned().fold(1e-12, f64::max);
        for (w, e) in w.iter_mut().zip(&err) {
            *w *= 0.2 + e / worst;
        }
    }
    c.iter().map(|&c| c as f32).collect()
}

/// The `c` minimising `Σ w (rows · c − y)²`: the normal equations by Gaussian elimination with
/// partial pivoting (f64; a tiny ridge keeps them regular).
fn weighted_least_squares(rows: &[Vec<f64>], ys: &[f64], w: &[f64]) -> Vec<f64> {
    let m = rows[0].len();
    let mut a = vec![vec![0.0f64; m + 1]; m];
    for ((f, &y), &w) in rows.iter().zip(ys).zip(w) {
        for i in 0..m {
            let fi = f[i] * w;
            for k in 0..m {
                a[i][k] += fi * f[k];
            }
            a[i][m] += fi * y;
        }
    }
    for (i, row) in a.iter_mut().enumerate() {
        row[i] += 1e-12;
    }
    for col in 0..m {
        let p = (col..m)
            .max_by(|&i, &k| a[i][col].abs().total_cmp(&a[k][col].abs()))
            .unwrap_or(col);
        a.swap(col, p);
        let pivot = a[col].clone();
        for (r, row) in a.iter_mut().enumerate() {
            if r != col {
                let f = row[col] / pivot[col];
                for k in col..=m {
                    row[k] -= f * pivot[k];
                }
            }
        }
    }
    (0..m).map(|i| a[i][m] / a[i][i]).collect()
}

/// The GLSL source of the fit with coefficients `c` (what `shaders_glsl/brdf/sheen_albedo.glsl`
/// holds: `cargo run --release -p luz-core --example sheen_fit` writes it from
/// [`fit_sheen_albedo`]; `brdf::tests::sheen_albedo_fit_is_the_integral` checks its error). The
/// function indexes the constant array with literal indices only: glslang folds them to
/// constants (a dynamically indexed table made lavapipe ~10× slower).
pub fn sheen_albedo_glsl_source(c: &[f32]) -> String {
    let (nx, ns) = (SHEEN_FIT_X, SHEEN_FIT_S);
    let mut s = String::from(
        "// KHR_materials_sheen's directional albedo E_sheen(n·v, sheenRoughness) of the white sheen lobe\n\
         // (D_Charlie · V_sheen): exp(Σ SHEEN_ALBEDO_FIT[a · SHEEN_FIT_S + b] u^a t^b), u = 2√(n·v) − 1,\n\
         // t = 1 − 2 ln(max(sheenRoughness, SHEEN_ROUGHNESS_MIN)) / ln(SHEEN_ROUGHNESS_MIN), fitted to the\n\
         // lobe's integral by brdf::fit_sheen_albedo (max error: brdf::tests::sheen_albedo_fit_is_the_integral).\n\
         // Generated by brdf::models::layers::sheen_albedo_glsl_source (cargo run --release -p luz-core\n\
         // --example sheen_fit); the CPU reads the coefficients from this file.\n\
         #ifndef LUZ_SHEEN_ALBEDO_GLSL\n#define LUZ_SHEEN_ALBEDO_GLSL\n",
    );
    s += &format!("#define SHEEN_FIT_X {nx}\n#define SHEEN_FIT_S {ns}\n");
    s += &format!("const float SHEEN_ALBEDO_FIT[{}] = float[](\n", nx * ns);
    for a in 0..nx {
        let row: Vec<String> = (0..ns).map(|b| format!("{:?}", c[a * ns + b])).collect();
        s += "    ";
        s += &row.join(", ");
        s += if a + 1 < nx { ",\n" } else { "\n" };
    }
    s += ");\n\n// The fit at (u, t), Horner in t then u (as layers::sheen_albedo).\n";
    s += "float sheen_albedo_fit(float u, float t) {\n    float p = 0.0;\n";
    for a in (0..nx).rev() {
        let mut q = String::from("0.0");
        for b in (0..ns).rev() {
            q = format!("({q} * t + SHEEN_ALBEDO_FIT[{}])", a * ns + b);
        }
        s += &format!("    p = p * u + {q};\n");
    }
    s += "    return exp(p);\n}\n#endif\n";
    s
}

/// The base's terms `t` under the sheen of `p`: weighted by `1 − max(sheenColor) · e_sheen`
/// (`e_sheen`: [`sheen_albedo`] at the view), plus `sheenColor · D V` in the diffuse.
pub fn sheen_layer(
    t: Terms,
    p: &MetalRoughParams,
    n: Vec3,
    l: Vec3,
    v: Vec3,
    e_sheen: f32,
) -> Terms {
    // The lobe's albedo exceeds 1 near grazing for a smooth sheen (1.64 at sheen roughness 0,
    // n·v 0.01: the extension's visibility term is not energy-conserving there); the base then
    // gets nothing rather than a negative share (`luz stability`'s sheen row).
    let keep = (1.0 - p.sheen_color.max_element() * e_sheen).max(0.0);
    let sheen = p.sheen_color * sheen_specular(p.sheen_roughness, n, l, v);
    Terms {
        diffuse: t.diffuse * keep + sheen,
        specular: t.specular * keep,
        ..t
    }
}
