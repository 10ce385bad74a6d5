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

/// The fit's coefficients of [`SHEEN_ALBEDO_GLSL`]: `c[a · SHEEN_FIT_S + b]` multiplies
/// `u^a t^b` ([`sheen_fit_variables`]).
pub fn sheen_albedo_fit() -> &'static [f32] {
    static FIT: std::sync::OnceLock<Vec<f32>> = std::sync::OnceLock::new();
    FIT.get_or_init(|| {
        let body = SHEEN_ALBEDO_GLSL
            .split_once("float[](")
            .and_then(|(_, rest)| rest.split_once(')'))
            .map(|(numbers, _)| numbers)
            .unwrap_or("");
        let c: Vec<f32> = body
            .split(',')
            .filter_map(|s| s.trim().parse().ok())
            .collect();
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
