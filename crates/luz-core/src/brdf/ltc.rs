//! Linearly transformed cosines (Heitz, Dupuy, Hill, Neubelt 2016) for the GGX lobe: the fitter
//! and the table shipped with luz (issue 36, area lights).
//!
//! For each view angle θ_v and roughness, the cosine-weighted GGX lobe with height-correlated Smith
//! masking and no Fresnel, `D G₂ / (4 n·v)`, is approximated by a clamped cosine `D_o(ω_o) =
//! max(ω_o.z, 0)/π` seen through a 3×3 matrix M: `D(ω) = D_o(M⁻¹ω/|M⁻¹ω|) · |∂ω_o/∂ω|`. M has the
//! paper's four-parameter form for isotropic GGX, `[[a, 0, b], [0, c, 0], [d, 0, 1]]` up to scale,
//! written as `M = R_y(θ) · [[m11, 0, m13], [0, m22, 0], [0, 0, 1]]`: a frame (X, Y, Z) turned by
//! θ about y (Z = (sin θ, 0, cos θ), X in the plane of the view) times an upper-triangular
//! matrix. The four parameters (m11, m22, m13, θ) are found by Nelder–Mead (restarted once),
//! minimising the paper's error (the sum over samples of both lobes of `|f_GGX − f_LTC|³ /
//! (pdf_GGX + pdf_LTC)`; [`FIT_POWER`]), each entry started from its neighbour's fit (the paper's
//! public fitting code does the same; this is luz's own code).
//!
//! The table: [`LTC_SIZE`]² entries, row = θ index `t`, column = roughness index `a`; the entry's
//! view has `cos θ_v = 1 − (t/(N−1))²` (the shader looks it up at `sqrt(1 − n·v)`), perceptual
//! roughness `a/(N−1)` (α = roughness², at least [`super::ALPHA_MIN`]). Each entry is 8 f32:
//! M⁻¹'s (0,0), (2,0), (0,2), (2,2) elements divided by its (1,1) element (the other elements are
//! 0; scale does not change the integral), then the lobe's norm (its directional albedo without
//! Fresnel), the Schlick weight `∫ f cos (1 − v·h)⁵`, and two zeros.
//! [`LTC_FILE`] holds it (little-endian); `cargo run --release -p luz-core --example ltc_table`
//! regenerates it and `ltc_table_refits` checks entries against a fresh fit.

use std::f64::consts::PI;

/// Entries per side of the shipped table.
pub const LTC_SIZE: usize = 64;
/// Stratified samples per axis of each lobe in the fitting error (the paper's 32).
pub const LTC_FIT_SAMPLES: usize = 32;
/// The power of the lobes' difference the fit minimises (3: the paper's error, 1: L1).
const FIT_POWER: i32 = 3;

/// Samples per axis for entry row t: more at grazing views (θ_v > 60°), where the lobe is
/// narrow in one direction and long-tailed in the other.
fn fit_samples(t: usize) -> usize {
    if t >= 45 {
        2 * LTC_FIT_SAMPLES
    } else {
        LTC_FIT_SAMPLES
    }
}
/// f32 values per entry.
pub const LTC_ENTRY: usize = 8;
/// Where the generator writes the table, relative to the luz-core crate.
pub const LTC_FILE: &str = "data/ltc_ggx_64x64.bin";

static SHIPPED: &[u8] = include_bytes!("../../data/ltc_ggx_64x64.bin");

type M3 = [[f64; 3]; 3];

fn mul(a: &M3, b: &M3) -> M3 {
    let mut c = [[0.0; 3]; 3];
    for (i, row) in c.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    c
}

fn apply(m: &M3, v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

fn det(m: &M3) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

fn inverse(m: &M3) -> M3 {
    let d = det(m);
    let c =
        |r0: usize, c0: usize, r1: usize, c1: usize| m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0];
    [
        [c(1, 1, 2, 2) / d, -c(0, 1, 2, 2) / d, c(0, 1, 1, 2) / d],
        [-c(1, 0, 2, 2) / d, c(0, 0, 2, 2) / d, -c(0, 0, 1, 2) / d],
        [c(1, 0, 2, 1) / d, -c(0, 0, 2, 1) / d, c(0, 0, 1, 1) / d],
    ]
}

fn normalize(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|x| x / l)
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The GGX lobe of the fit, in the shading frame (n = z): `f · cos` without Fresnel and the pdf
/// of sampling it by the distribution of normals.
struct Ggx {
    alpha: f64,
    v: [f64; 3],
}

impl Ggx {
    fn lambda(&self, cos: f64) -> f64 {
        let c2 = cos * cos;
        let t2 = (1.0 - c2).max(0.0) / c2.max(1e-12);
        0.5 * (-1.0 + (1.0 + self.alpha * self.alpha * t2).sqrt())
    }

    /// (f·cos, pdf) for the direction `l`.
    fn eval(&self, l: [f64; 3]) -> (f64, f64) {
        let v = self.v;
        if l[2] <= 0.0 {
            return (0.0, 0.0);
        }
        let h = normalize([l[0] + v[0], l[1] + v[1], l[2] + v[2]]);
        let a2 = self.alpha * self.alpha;
        let c2 = h[2] * h[2];
        let d = a2 / (PI * (c2 * (a2 - 1.0) + 1.0).powi(2));
        let g2 = 1.0 / (1.0 + self.lambda(v[2]) + self.lambda(l[2]));
        let f_cos = d * g2 / (4.0 * v[2]);
        let pdf = d * h[2] / (4.0 * dot(v, h).max(1e-12));
        (f_cos, pdf)
    }

    /// A direction from the distribution of normals (the reflection about a GGX normal).
    fn sample(&self, u1: f64, u2: f64) -> [f64; 3] {
        let phi = 2.0 * PI * u1;
        let t = self.alpha * (u2 / (1.0 - u2)).sqrt();
        let ct = 1.0 / (1.0 + t * t).sqrt();
        let st = t * ct;
        let h = [st * phi.cos(), st * phi.sin(), ct];
        let vh = dot(self.v, h);
        [0, 1, 2].map(|i| 2.0 * vh * h[i] - self.v[i])
    }
}

/// The rotation about y whose Z column is (sin θ, 0, cos θ) and X column (cos θ, 0, −sin θ).
fn frame(theta: f64) -> M3 {
    let (s, c) = theta.sin_cos();
    [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]
}

/// An LTC: the matrix M from the four parameters (m11, m22, m13, θ).
#[derive(Clone, Copy)]
struct Ltc {
    magnitude: f64,
    m: M3,
    inv: M3,
    det: f64,
}

impl Ltc {
    fn new([m11, m22, m13, theta]: [f64; 4], magnitude: f64) -> Self {
        let a = [[m11, 0.0, m13], [0.0, m22, 0.0], [0.0, 0.0, 1.0]];
        let m = mul(&frame(theta), &a);
        Self {
            magnitude,
            m,
            inv: inverse(&m),
            det: det(&m).abs(),
        }
    }

    /// (value, pdf) of the transformed cosine (value = magnitude · pdf).
    fn eval(&self, l: [f64; 3]) -> (f64, f64) {
        let lo = normalize(apply(&self.inv, l));
        let lt = apply(&self.m, lo);
        let len = dot(lt, lt).sqrt();
        let jacobian = self.det / (len * len * len);
        let pdf = lo[2].max(0.0) / PI / jacobian;
        (self.magnitude * pdf, pdf)
    }

    fn sample(&self, u1: f64, u2: f64) -> [f64; 3] {
        let theta = u1.sqrt().acos();
        let phi = 2.0 * PI * u2;
        normalize(apply(
            &self.m,
            [
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            ],
        ))
    }
}

/// The fitting error of `ltc` against `brdf` over `n`² stratified samples of each lobe, both
/// lobes' samples weighted by the balance heuristic (1 / (pdf_GGX + pdf_LTC)): the sum of
/// `|f_GGX − f_LTC|^FIT_POWER`, i.e. an estimate of ∫ |f_GGX − f_LTC|^FIT_POWER.
fn error(ltc: &Ltc, brdf: &Ggx, n: usize) -> f64 {
    let mut sum = 0.0;
    for j in 0..n {
        for i in 0..n {
            let u1 = (i as f64 + 0.5) / n as f64;
            let u2 = (j as f64 + 0.5) / n as f64;
            for l in [ltc.sample(u1, u2), brdf.sample(u1, u2)] {
                let (fb, pb) = brdf.eval(l);
                let (fl, pl) = ltc.eval(l);
                let e = (fb - fl).abs();
                if pb + pl > 0.0 {
                    sum += e.powi(FIT_POWER) / (pb + pl);
                }
            }
        }
    }
    sum / (n * n) as f64
}

/// Norm, Schlick weight and average direction (y = 0) of the lobe, by its own samples.
fn lobe_terms(brdf: &Ggx) -> (f64, f64, [f64; 3]) {
    let n = LTC_FIT_SAMPLES;
    let (mut norm, mut fresnel, mut dir) = (0.0, 0.0, [0.0; 3]);
    for j in 0..n {
        for i in 0..n {
            let l = brdf.sample((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
            let (f, pdf) = brdf.eval(l);
            if pdf <= 0.0 {
                continue;
            }
            let w = f / pdf;
            let h = normalize([l[0] + brdf.v[0], l[1] + brdf.v[1], l[2] + brdf.v[2]]);
            norm += w;
            fresnel += w * (1.0 - dot(brdf.v, h).max(0.0)).powi(5);
            dir = [0, 1, 2].map(|k| dir[k] + w * l[k]);
        }
    }
    let count = (n * n) as f64;
    dir[1] = 0.0;
    (norm / count, fresnel / count, normalize(dir))
}

/// Nelder–Mead minimisation of `f` from `start` with an initial step `delta`.
fn nelder_mead<const N: usize>(
    f: &dyn Fn([f64; N]) -> f64,
    start: [f64; N],
    delta: f64,
    iters: usize,
) -> [f64; N] {
    let mut s: Vec<([f64; N], f64)> = (0..=N)
        .map(|k| {
            let mut p = start;
            if k > 0 {
                p[k - 1] += delta;
            }
            (p, f(p))
        })
        .collect();
    let lerp = |a: [f64; N], b: [f64; N], t: f64| -> [f64; N] {
        std::array::from_fn(|i| a[i] + t * (b[i] - a[i]))
    };
    for _ in 0..iters {
        s.sort_by(|a, b| a.1.total_cmp(&b.1));
        if (s[N].1 - s[0].1).abs() <= 1e-5 * (s[0].1.abs() + s[N].1.abs()) + 1e-30 {
            break;
        }
        let c: [f64; N] =
            std::array::from_fn(|i| s[..N].iter().map(|p| p.0[i]).sum::<f64>() / N as f64);
        let worst = s[N];
        let r = lerp(c, worst.0, -1.0);
        let fr = f(r);
        if fr < s[0].1 {
            let e = lerp(c, worst.0, -2.0);
            let fe = f(e);
            s[N] = if fe < fr { (e, fe) } else { (r, fr) };
        } else if fr < s[N - 1].1 {
            s[N] = (r, fr);
        } else {
            let k = if fr < worst.1 {
                lerp(c, r, 0.5)
            } else {
                lerp(c, worst.0, 0.5)
            };
            let fk = f(k);
            if fk < worst.1.min(fr) {
                s[N] = (k, fk);
            } else {
                let best = s[0].0;
                for p in s.iter_mut().skip(1) {
                    p.0 = lerp(best, p.0, 0.5);
                    p.1 = f(p.0);
                }
            }
        }
    }
    s.sort_by(|a, b| a.1.total_cmp(&b.1));
    s[0].0
}

/// The view and α of entry (t, a).
fn entry_setup(t: usize, a: usize) -> (Ggx, f64) {
    let n = (LTC_SIZE - 1) as f64;
    let x = t as f64 / n;
    let ct = (1.0 - x * x).max(1e-4);
    let st = (1.0 - ct * ct).sqrt();
    let r = a as f64 / n;
    let alpha = (r * r).max(super::ALPHA_MIN as f64);
    (
        Ggx {
            alpha,
            v: [st, 0.0, ct],
        },
        r,
    )
}

/// One fitted entry: the parameters (m11, m22, m13, θ) and the table's 8 values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LtcEntry {
    pub params: [f64; 4],
    pub values: [f32; LTC_ENTRY],
}

/// The start of the fit at normal incidence from the roughest entry.
const START: [f64; 4] = [1.0, 1.0, 0.0, 0.0];

/// Fits entry (t, a) starting from `start` (m11, m22, m13, θ).
pub fn fit_entry(t: usize, a: usize, start: [f64; 4]) -> LtcEntry {
    let (brdf, _) = entry_setup(t, a);
    let (norm, fresnel, _) = lobe_terms(&brdf);
    let n = fit_samples(t);
    let best = if t == 0 {
        // Normal incidence: the lobe is isotropic, M = m·I in the normal's frame.
        let cost = |p: [f64; 1]| {
            let m = p[0].abs().max(1e-7);
            error(&Ltc::new([m, m, 0.0, 0.0], norm), &brdf, n)
        };
        let m = nelder_mead(&cost, [start[0]], 0.05, 200)[0].abs().max(1e-7);
        [m, m, 0.0, 0.0]
    } else {
        let params_of = |p: [f64; 4]| [p[0].abs().max(1e-7), p[1].abs().max(1e-7), p[2], p[3]];
        let cost = |p: [f64; 4]| error(&Ltc::new(params_of(p), norm), &brdf, n);
        // Restarted once from its result: Nelder–Mead's simplex can collapse in the valley
        // before the minimum.
        let p = nelder_mead(&cost, start, 0.05, 400);
        params_of(nelder_mead(&cost, p, 0.02, 400))
    };
    let inv = Ltc::new(best, norm).inv;
    let s = inv[1][1];
    LtcEntry {
        params: best,
        values: [
            (inv[0][0] / s) as f32,
            (inv[2][0] / s) as f32,
            (inv[0][2] / s) as f32,
            (inv[2][2] / s) as f32,
            norm as f32,
            fresnel as f32,
            0.0,
            0.0,
        ],
    }
}

/// The whole table, fitted as the shipped one was: column t = 0 from the roughest entry down
/// (each started from the rougher one's fit), then each roughness's row from t = 0 up (each
/// started from the previous view's fit). Entries in row-major order (t, a).
pub fn fit_table() -> Vec<LtcEntry> {
    let n = LTC_SIZE;
    let mut first = vec![START; n];
    let mut start = START;
    let mut col0 = Vec::with_capacity(n);
    for a in (0..n).rev() {
        let e = fit_entry(0, a, start);
        start = e.params;
        first[a] = e.params;
        col0.push((a, e));
    }
    use rayon::prelude::*;
    let rows: Vec<Vec<LtcEntry>> = (0..n)
        .into_par_iter()
        .map(|a| {
            let mut row = Vec::with_capacity(n);
            let e0 = col0.iter().find(|(k, _)| *k == a).expect("column 0").1;
            row.push(e0);
            let mut p = first[a];
            for t in 1..n {
                let e = fit_entry(t, a, p);
                p = e.params;
                row.push(e);
            }
            row
        })
        .collect();
    let mut out = Vec::with_capacity(n * n);
    for t in 0..n {
        for row in &rows {
            out.push(row[t]);
        }
    }
    out
}

/// The bytes of the table, fitted now (what the generator writes).
pub fn generate_ltc_table() -> Vec<u8> {
    fit_table()
        .iter()
        .flat_map(|e| e.values.iter().flat_map(|v| v.to_le_bytes()))
        .collect()
}

/// The shipped table's entries (8 f32 each, row-major (t, a)).
pub fn ltc_table() -> Vec<f32> {
    SHIPPED
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().expect("4 bytes")))
        .collect()
}

/// The start of a refit of entry (t, a) from the shipped table: the parameters the generator
/// had there are not stored, so they are read back from the neighbour's matrix.
fn shipped_params(table: &[f32], t: usize, a: usize) -> [f64; 4] {
    let e = &table[(t * LTC_SIZE + a) * LTC_ENTRY..][..4];
    let inv = [
        [e[0] as f64, 0.0, e[2] as f64],
        [0.0, 1.0, 0.0],
        [e[1] as f64, 0.0, e[3] as f64],
    ];
    let m = inverse(&inv);
    // M = frame(θ) · A with A = [[m11, 0, m13], [0, m22, 0], [0, 0, 1]] up to scale (a QR
    // decomposition of M's xz block): M's first column is m11 times the frame's X = (cos θ, 0,
    // −sin θ).
    let theta = (-m[2][0]).atan2(m[0][0]);
    let f = frame(theta);
    let ft = [0, 1, 2].map(|i| [0, 1, 2].map(|j| f[j][i]));
    let a_m = mul(&ft, &m);
    let s = a_m[2][2];
    [a_m[0][0] / s, a_m[1][1] / s, a_m[0][2] / s, theta]
}

/// Refits entry (t, a) of the shipped table freshly, started from the shipped neighbour the
/// generator started it from; returns (shipped, refitted) values.
pub fn refit_shipped_entry(t: usize, a: usize) -> ([f32; LTC_ENTRY], [f32; LTC_ENTRY]) {
    let table = ltc_table();
    let start = match (t, a) {
        (0, a) if a + 1 == LTC_SIZE => START,
        (0, a) => shipped_params(&table, 0, a + 1),
        (t, a) => shipped_params(&table, t - 1, a),
    };
    let fresh = fit_entry(t, a, start).values;
    let mut shipped = [0.0; LTC_ENTRY];
    shipped.copy_from_slice(&table[(t * LTC_SIZE + a) * LTC_ENTRY..][..LTC_ENTRY]);
    (shipped, fresh)
}

/// Evaluates the shipped LTC of entry (t, a) as a lobe (`f·cos` without Fresnel) in direction `l`
/// of the shading frame whose view is the entry's: for tests against the GGX lobe.
pub fn shipped_lobe(t: usize, a: usize, l: [f64; 3]) -> (f64, f64) {
    let table = ltc_table();
    let e = &table[(t * LTC_SIZE + a) * LTC_ENTRY..][..LTC_ENTRY];
    let inv = [
        [e[0] as f64, 0.0, e[2] as f64],
        [0.0, 1.0, 0.0],
        [e[1] as f64, 0.0, e[3] as f64],
    ];
    let ltc = Ltc {
        magnitude: e[4] as f64,
        m: inverse(&inv),
        inv,
        det: det(&inverse(&inv)).abs(),
    };
    let (brdf, _) = entry_setup(t, a);
    (ltc.eval(l).0, brdf.eval(l).0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shipped table is the generator's output: entries across the table (grazing and
    /// normal views, smooth and rough) refitted freshly from the shipped neighbour the generator
    /// started them from give the shipped matrix within 2 % of its largest element and the same
    /// norm and Schlick weight within 1e-5.
    #[test]
    fn ltc_table_refits() {
        assert_eq!(SHIPPED.len(), LTC_SIZE * LTC_SIZE * LTC_ENTRY * 4);
        for (t, a) in [(0, 63), (0, 20), (10, 40), (32, 32), (50, 10), (63, 60)] {
            let (shipped, fresh) = refit_shipped_entry(t, a);
            let scale = shipped[..4].iter().fold(0f32, |m, v| m.max(v.abs()));
            for k in 0..4 {
                assert!(
                    (shipped[k] - fresh[k]).abs() <= 0.02 * scale,
                    "entry ({t}, {a}) value {k}: shipped {shipped:?}, refitted {fresh:?}; \
                     regenerate with `cargo run --release -p luz-core --example ltc_table`"
                );
            }
            for k in 4..6 {
                assert!(
                    (shipped[k] - fresh[k]).abs() <= 1e-5,
                    "({t}, {a}): {shipped:?} {fresh:?}"
                );
            }
        }
    }

    /// The fitted lobe is close to GGX where it matters: the LTC integrates to the norm (its
    /// magnitude) and the lobes' mean absolute difference, weighted by the GGX lobe, is small at
    /// moderate roughness.
    #[test]
    fn shipped_ltc_is_near_ggx() {
        for (t, a) in [(20, 32), (40, 48)] {
            let n = 64;
            let (mut diff, mut total) = (0.0, 0.0);
            for j in 0..n {
                for i in 0..n {
                    // Uniform hemisphere quadrature.
                    let z = (i as f64 + 0.5) / n as f64;
                    let phi = 2.0 * PI * (j as f64 + 0.5) / n as f64;
                    let s = (1.0 - z * z).sqrt();
                    let (fl, fb) = shipped_lobe(t, a, [s * phi.cos(), s * phi.sin(), z]);
                    diff += (fl - fb).abs();
                    total += fb;
                }
            }
            assert!(
                diff / total < 0.25,
                "({t}, {a}): relative L1 {}",
                diff / total
            );
        }
    }
}
