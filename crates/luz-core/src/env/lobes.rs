//! Fitted lobes: the specular IBL method `fitted_lobes` (issue 37). The split sum reads the
//! prefiltered cube once, along one direction, at the material's own roughness: the cube holds
//! the lobe `D(h)(d·l)` of `n = v = d`, which is neither the shape of the real lobe (`D G₂/(4 n·v)`
//! over `n·l > 0`: G₁ instead of the cosine, stretched and cut by the horizon at grazing views)
//! nor its width. This method reads the same cube twice — along directions `d₁`, `d₂` in the
//! plane of `n` and `v` at roughnesses `r₁`, `r₂` — and mixes the two with weight `w₂`; the five
//! numbers come from a table over (n·v, roughness) fitted here so that the mix of the two
//! prefilter kernels is as close as possible (L1 over the sphere) to the real lobe normalised to
//! 1. The split sum's second factor (`F0 A + B`) is unchanged.
//!
//! The table: [`LOBES_SIZE`]² entries (view `cos θ_v = 1 − (t/(N−1))²`, roughness `a/(N−1)`),
//! [`LOBE_ENTRY`] f32 each: `[φ₁, r₁, φ₂, r₂, w₂]` with `φ` a direction's angle from `n`, away
//! from `v` (the mirror direction is at φ = θ_v), the lobe farther from `n` first. The lobe is GGX with separable Smith G₁(l) G₁(v), no Fresnel.
//! [`LOBES_FILE`] holds it (little-endian); `cargo run --release -p luz-core --example
//! ibl_lobe_table` regenerates it and `lobe_table_refits` checks entries against a fresh fit.

use std::f64::consts::PI;

use glam::{DVec3, Vec3};

use super::equirect::Equirect;
use super::reference::prefiltered_reference;
use crate::brdf::{split_sum_lut_reference, Geometry};

/// Entries per side of the shipped table.
pub const LOBES_SIZE: usize = 32;
/// Where the generator writes the table, relative to the luz-core crate.
pub const LOBES_FILE: &str = "data/ibl_lobes_32x32.bin";
/// Samples per strategy of the fitting error.
const FIT_SAMPLES: u32 = 256;

static SHIPPED: &[u8] = include_bytes!("../../data/ibl_lobes_32x32.bin");

fn d_ggx(c: f64, a: f64) -> f64 {
    let a2 = a * a;
    let t = c * c * (a2 - 1.0) + 1.0;
    a2 / (PI * t * t)
}

fn g1(c: f64, a: f64) -> f64 {
    if c <= 0.0 {
        return 0.0;
    }
    2.0 * c / (c + (a * a + (1.0 - a * a) * c * c).sqrt())
}

fn radical(i: u32) -> f64 {
    f64::from(i.reverse_bits()) / 4_294_967_296.0
}

/// A GGX half vector around +z.
fn sample_h(u1: f64, u2: f64, a: f64) -> DVec3 {
    let phi = 2.0 * PI * u1;
    let c2 = (1.0 - u2) / (1.0 + (a * a - 1.0) * u2);
    let s = (1.0 - c2).max(0.0).sqrt();
    DVec3::new(s * phi.cos(), s * phi.sin(), c2.sqrt())
}

/// `l` given in the frame whose z is `d` (any tangents), in world space.
fn around(d: DVec3, l: DVec3) -> DVec3 {
    let t = if d.z.abs() < 0.999 {
        DVec3::Z.cross(d).normalize()
    } else {
        DVec3::X.cross(d).normalize()
    };
    t * l.x + d.cross(t) * l.y + d * l.z
}

/// The prefilter's kernel around `d` (what one texel of the prefiltered cube integrates):
/// `D(h)(d·l)⁺ / Z`, `h = normalize(d + l)`, normalised to 1 over the sphere.
struct Kernel {
    d: DVec3,
    a: f64,
    z: f64,
    w: f64,
}

impl Kernel {
    fn new(d: DVec3, a: f64, w: f64) -> Self {
        // Z = ∫ D(h)(d·l)⁺ dl = 2π ∫₀^{π/4} D(θ)(2c² − 1) 4c sin θ dθ (dl = 4 (d·h) dh).
        let n = 512;
        let dt = PI / 4.0 / f64::from(n);
        let z: f64 = (0..n)
            .map(|i| {
                let th = (f64::from(i) + 0.5) * dt;
                let c = th.cos();
                d_ggx(c, a) * (2.0 * c * c - 1.0) * 4.0 * c * th.sin()
            })
            .sum::<f64>()
            * 2.0
            * PI
            * dt;
        Kernel { d, a, z, w }
    }

    fn eval(&self, l: DVec3) -> f64 {
        let c = self.d.dot(l);
        if c <= 0.0 {
            return 0.0;
        }
        d_ggx((self.d + l).normalize().dot(self.d), self.a) * c / self.z
    }

    /// Density of [`Self::sample`]: `D(h)/4`.
    fn pdf(&self, l: DVec3) -> f64 {
        d_ggx((self.d + l).normalize().dot(self.d), self.a) / 4.0
    }

    fn sample(&self, u1: f64, u2: f64) -> DVec3 {
        let h = around(self.d, sample_h(u1, u2, self.a));
        h * (2.0 * h.dot(self.d)) - self.d
    }
}

/// The real lobe at `n = +z`, `v = (sin θ_v, 0, cos θ_v)`: `D G₁(l) G₁(v) / (4 n·v)` over
/// `n·l > 0`, normalised to 1.
struct Lobe {
    v: DVec3,
    a: f64,
    norm: f64,
}

impl Lobe {
    fn new(n_v: f64, a: f64) -> Self {
        let v = DVec3::new((1.0 - n_v * n_v).max(0.0).sqrt(), 0.0, n_v);
        let mut lobe = Lobe { v, a, norm: 1.0 };
        let n = 8192;
        let sum: f64 = (0..n)
            .map(|i| {
                let l = lobe.sample((f64::from(i) + 0.5) / f64::from(n), radical(i));
                let p = lobe.pdf(l);
                if p > 0.0 {
                    lobe.eval(l) / p
                } else {
                    0.0
                }
            })
            .sum();
        lobe.norm = sum / f64::from(n);
        lobe
    }

    fn eval(&self, l: DVec3) -> f64 {
        if l.z <= 0.0 {
            return 0.0;
        }
        let h = (self.v + l).normalize();
        d_ggx(h.z, self.a) * g1(l.z, self.a) * g1(self.v.z, self.a) / (4.0 * self.v.z) / self.norm
    }

    /// Density of [`Self::sample`] (GGX normals reflected about v).
    fn pdf(&self, l: DVec3) -> f64 {
        let h = (self.v + l).normalize();
        let v_h = self.v.dot(h);
        if v_h <= 0.0 || h.z <= 0.0 {
            return 0.0;
        }
        d_ggx(h.z, self.a) * h.z / (4.0 * v_h)
    }

    fn sample(&self, u1: f64, u2: f64) -> DVec3 {
        let h = sample_h(u1, u2, self.a);
        h * (2.0 * h.dot(self.v)) - self.v
    }
}

/// The fit's free parameters: `[φ₁, ln α₁, φ₂, ln α₂, logit w₂]`.
type Params = [f64; 5];

/// Values per entry of the table: `[φ₁, r₁, φ₂, r₂, w₂]`.
pub const LOBE_ENTRY: usize = 5;

/// A direction in the plane of n (+z) and v (+x side), at angle φ from n away from v.
fn plane_dir(phi: f64) -> DVec3 {
    DVec3::new(-phi.sin(), 0.0, phi.cos())
}

fn kernels(p: &Params) -> [Kernel; 2] {
    let w2 = 1.0 / (1.0 + (-p[4]).exp());
    let a1 = p[1].exp().clamp(1e-3, 1.0);
    let a2 = p[3].exp().clamp(1e-3, 1.0);
    [
        Kernel::new(plane_dir(p[0]), a1, 1.0 - w2),
        Kernel::new(plane_dir(p[2]), a2, w2),
    ]
}

/// The same two lobes with the one farther from n first (φ₁ ≥ φ₂), so that neighbouring
/// entries, fitted from different starts, name their lobes alike and interpolate.
fn canonical(p: Params) -> Params {
    if p[0] >= p[2] {
        p
    } else {
        [p[2], p[3], p[0], p[1], -p[4]]
    }
}

/// ∫ |lobe − Σ w_k kernel_k| over the sphere: balance-heuristic estimate over `n` Hammersley
/// samples of each of the three densities.
fn l1_distance(lobe: &Lobe, ks: &[Kernel; 2], n: u32) -> f64 {
    let pdf = |l: DVec3| lobe.pdf(l) + ks[0].pdf(l) + ks[1].pdf(l);
    let g = |l: DVec3| (lobe.eval(l) - ks.iter().map(|k| k.w * k.eval(l)).sum::<f64>()).abs();
    let mut sum = 0.0;
    for i in 0..n {
        let (u1, u2) = ((f64::from(i) + 0.5) / f64::from(n), radical(i));
        for l in [
            lobe.sample(u1, u2),
            ks[0].sample(u1, u2),
            ks[1].sample(u1, u2),
        ] {
            let p = pdf(l);
            if p > 0.0 {
                sum += g(l) / p;
            }
        }
    }
    sum / f64::from(n)
}

fn nelder_mead(f: &dyn Fn(&Params) -> f64, start: Params, delta: f64, iters: usize) -> Params {
    const N: usize = 5;
    let mut pts = [start; N + 1];
    for (i, p) in pts.iter_mut().skip(1).enumerate() {
        p[i] += delta;
    }
    let mut vals = pts.map(|p| f(&p));
    for _ in 0..iters {
        let mut idx = [0, 1, 2, 3, 4, 5];
        idx.sort_by(|&a, &b| vals[a].total_cmp(&vals[b]));
        pts = idx.map(|i| pts[i]);
        vals = idx.map(|i| vals[i]);
        let c: Params =
            std::array::from_fn(|k| pts[..N].iter().map(|p| p[k]).sum::<f64>() / N as f64);
        let towards = |t: f64| -> Params { std::array::from_fn(|k| c[k] + t * (pts[N][k] - c[k])) };
        let r = towards(-1.0);
        let fr = f(&r);
        if fr < vals[0] {
            let e = towards(-2.0);
            let fe = f(&e);
            (pts[N], vals[N]) = if fe < fr { (e, fe) } else { (r, fr) };
        } else if fr < vals[N - 1] {
            (pts[N], vals[N]) = (r, fr);
        } else {
            let cc = towards(0.5);
            let fc = f(&cc);
            if fc < vals[N] {
                (pts[N], vals[N]) = (cc, fc);
            } else {
                for i in 1..=N {
                    pts[i] = std::array::from_fn(|k| pts[0][k] + 0.5 * (pts[i][k] - pts[0][k]));
                    vals[i] = f(&pts[i]);
                }
            }
        }
    }
    let best = (0..=N)
        .min_by(|&a, &b| vals[a].total_cmp(&vals[b]))
        .unwrap_or(0);
    pts[best]
}

/// `cos θ_v` and roughness of entry `(t, a)`.
pub fn lobe_entry_coords(t: usize, a: usize) -> (f64, f64) {
    let x = t as f64 / (LOBES_SIZE - 1) as f64;
    ((1.0 - x * x).max(0.02), a as f64 / (LOBES_SIZE - 1) as f64)
}

/// The start of a row's first entry (n = v): both kernels along n, the second wider and weak.
fn row_start(roughness: f64) -> Params {
    // Inside the clamp of α ≤ 1 (a simplex started on the clamp would not move).
    let alpha = (roughness * roughness).clamp(1e-3, 0.8);
    [0.0, alpha.ln(), 0.0, (2.0 * alpha).min(0.8).ln(), -2.0]
}

fn to_entry(p: &Params) -> [f32; LOBE_ENTRY] {
    let [k1, k2] = kernels(p);
    [
        p[0] as f32,
        k1.a.sqrt() as f32,
        p[2] as f32,
        k2.a.sqrt() as f32,
        k2.w as f32,
    ]
}

/// Fits entry `(t, a)` from `start`; returns the parameters and the entry.
fn fit(t: usize, a: usize, start: Params) -> (Params, [f32; LOBE_ENTRY]) {
    let (n_v, roughness) = lobe_entry_coords(t, a);
    if a == 0 {
        // A mirror: the mirror direction at roughness 0.
        let th = n_v.acos();
        let p = [th, (1e-3f64).ln(), th, (1e-3f64).ln(), -30.0];
        return (p, [th as f32, 0.0, th as f32, 0.0, 0.0]);
    }
    let alpha = roughness * roughness;
    let lobe = Lobe::new(n_v, alpha);
    let f = |p: &Params| l1_distance(&lobe, &kernels(p), FIT_SAMPLES);
    // Two starts, the better kept: the previous entry's fit, and two lobes spread along the
    // lobe's stretch around Frostbite's dominant direction (from the first a simplex tends to
    // stay with one lobe on n).
    let th = n_v.acos();
    let dominant = th * (1.0 - alpha) * ((1.0 - alpha).sqrt() + alpha);
    let a0 = alpha.clamp(1e-3, 0.8).ln();
    let spread = [1.15 * dominant, a0 - 0.3, 0.8 * dominant, a0 - 0.3, 0.0];
    let run = |start: Params| {
        let p = nelder_mead(&f, start, 0.1, 600);
        let p = canonical(nelder_mead(&f, p, 0.03, 400));
        (f(&p), p)
    };
    let (e1, p1) = run(start);
    let p = if t == 0 {
        p1
    } else {
        let (e2, p2) = run(spread);
        if e2 < e1 {
            p2
        } else {
            p1
        }
    };
    (p, to_entry(&p))
}

/// One row of the table (fixed roughness index `a`), each entry started from the previous one
/// (the first from [`row_start`]).
fn fit_row(a: usize) -> Vec<(Params, [f32; LOBE_ENTRY])> {
    let (_, roughness) = lobe_entry_coords(0, a);
    let mut start = row_start(roughness);
    (0..LOBES_SIZE)
        .map(|t| {
            let r = fit(t, a, start);
            start = r.0;
            r
        })
        .collect()
}

/// The whole table in file order (row = roughness index, column = view index), as bytes.
pub fn generate_lobe_table() -> Vec<u8> {
    use rayon::prelude::*;
    let rows: Vec<Vec<(Params, [f32; LOBE_ENTRY])>> =
        (0..LOBES_SIZE).into_par_iter().map(fit_row).collect();
    rows.iter()
        .flatten()
        .flat_map(|(_, e)| e.iter().flat_map(|v| v.to_le_bytes()))
        .collect()
}

/// The shipped table, `LOBES_SIZE² × [φ₁, r₁, φ₂, r₂, w₂]`, row = roughness index (decoded once).
pub fn lobe_table() -> &'static [[f32; LOBE_ENTRY]] {
    static TABLE: std::sync::OnceLock<Vec<[f32; LOBE_ENTRY]>> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        SHIPPED
            .chunks_exact(4 * LOBE_ENTRY)
            .map(|b| {
                std::array::from_fn(|k| f32::from_le_bytes(b[4 * k..4 * k + 4].try_into().unwrap()))
            })
            .collect()
    })
}

/// The table's four values at `(n·v, roughness)`, bilinear between entries (the table's own
/// coordinates: `t = (N − 1) sqrt(1 − n·v)`).
pub fn lobes_at(n_v: f32, roughness: f32) -> [f32; LOBE_ENTRY] {
    lobes_in(lobe_table(), n_v, roughness)
}

fn lobes_in(table: &[[f32; LOBE_ENTRY]], n_v: f32, roughness: f32) -> [f32; LOBE_ENTRY] {
    let last = (LOBES_SIZE - 1) as f32;
    let x = (1.0 - n_v.clamp(0.0, 1.0)).sqrt() * last;
    let y = roughness.clamp(0.0, 1.0) * last;
    let (x0, y0) = (
        (x.floor() as usize).min(LOBES_SIZE - 2),
        (y.floor() as usize).min(LOBES_SIZE - 2),
    );
    let (fx, fy) = (x - x0 as f32, y - y0 as f32);
    let at = |t: usize, a: usize| table[a * LOBES_SIZE + t];
    std::array::from_fn(|k| {
        let top = at(x0, y0)[k] * (1.0 - fx) + at(x0 + 1, y0)[k] * fx;
        let bottom = at(x0, y0 + 1)[k] * (1.0 - fx) + at(x0 + 1, y0 + 1)[k] * fx;
        top * (1.0 - fy) + bottom * fy
    })
}

/// The table resampled at a LUT's texel centres (`size`², column = n·v `(i + 0.5)/size`, row =
/// roughness `(j + 0.5)/size`), as the GPU stores it beside the split-sum LUT: two RGBA layers,
/// `(φ₁, r₁, φ₂, r₂)` then `(w₂, 0, 0, 0)`.
pub fn lobe_layers(size: u32) -> [Vec<[f32; 4]>; 2] {
    let table = lobe_table();
    let c = |i: u32| (i as f32 + 0.5) / size as f32;
    let entries: Vec<[f32; LOBE_ENTRY]> = (0..size)
        .flat_map(|j| (0..size).map(move |i| (i, j)))
        .map(|(i, j)| lobes_in(table, c(i), c(j)))
        .collect();
    [
        entries.iter().map(|e| [e[0], e[1], e[2], e[3]]).collect(),
        entries.iter().map(|e| [e[4], 0.0, 0.0, 0.0]).collect(),
    ]
}

/// The roughness the prefiltered cube holds at `level` of `mips`: `level / (mips − 1)`, 0 (the
/// mirror) at level 0. Linear in roughness, not in α: each level has half the previous one's
/// resolution, and the widest lobes need the most texels across them that the chain can give
/// (a logarithmic α scale, tried for the fitted lobes, put α 0.16 on a 16² face and measured
/// 3.6 / 4.1 / 1.9 % against Mitsuba at α 0.1 / 0.3 / 0.6 instead of 3.3 / 3.1 / 1.8 %).
/// The shaders' `prefiltered_lod` is its inverse.
pub fn prefilter_level_roughness(level: u32, mips: u32) -> f32 {
    if mips <= 1 {
        return 0.0;
    }
    level.min(mips - 1) as f32 / (mips - 1) as f32
}

/// The mip level (fractional) holding `roughness` in a prefiltered cube of `mips` levels: the
/// inverse of [`prefilter_level_roughness`], as the shaders' `prefiltered_lod`.
pub fn prefiltered_lod(roughness: f32, mips: u32) -> f32 {
    roughness * mips.saturating_sub(1) as f32
}

/// A lobe's direction at `n`, `v` (unit, `n·v > 0`): `d = cos φ n − sin φ t` with `t` the unit
/// part of `v` across `n` (any when `v = n`).
pub fn lobe_direction(n: Vec3, v: Vec3, phi1: f32) -> Vec3 {
    let t = (v - n * n.dot(v)).try_normalize().unwrap_or(Vec3::ZERO);
    (n * phi1.cos() - t * phi1.sin())
        .try_normalize()
        .unwrap_or(n)
}

/// The method's estimate with the table and an exact prefilter (`samples` per lookup, as
/// [`prefiltered_reference`]): `((1 − w₂) pre(d₁, r₁) + w₂ pre(d₂, r₂)) · (F0 A + B)`, `(A, B)`
/// at `(n·v, roughness)` for `geometry`. 0 when `n·v ≤ 0`.
pub fn fitted_lobes_specular(
    eq: &Equirect,
    f0: Vec3,
    roughness: f32,
    geometry: Geometry,
    n: Vec3,
    v: Vec3,
    samples: u32,
) -> Vec3 {
    let Some((n, v, n_v)) = super::reference::unit_view(n, v) else {
        return Vec3::ZERO;
    };
    let [phi1, r1, phi2, r2, w2] = lobes_at(n_v, roughness);
    let pre = prefiltered_reference(eq, lobe_direction(n, v, phi1), r1, samples) * (1.0 - w2)
        + prefiltered_reference(eq, lobe_direction(n, v, phi2), r2, samples) * w2;
    let (a, b) = split_sum_lut_reference(n_v, roughness, geometry, samples);
    pre * (f0 * a + Vec3::splat(b))
}

/// The fit's L1 distance at entry `(t, a)` for the shipped values and for the split sum's own
/// single lookup (Frostbite's dominant direction at the material's roughness), both over `n`
/// samples per density: how much closer the table is to the real lobe.
pub fn lobe_fit_error(t: usize, a: usize, n: u32) -> (f64, f64) {
    let (n_v, roughness) = lobe_entry_coords(t, a);
    let alpha = (roughness * roughness).max(1e-3);
    let lobe = Lobe::new(n_v, alpha);
    let e = lobe_table()[a * LOBES_SIZE + t];
    let e = e.map(f64::from);
    let fitted = [
        Kernel::new(plane_dir(e[0]), (e[1] * e[1]).max(1e-3), 1.0 - e[4]),
        Kernel::new(plane_dir(e[2]), (e[3] * e[3]).max(1e-3), e[4]),
    ];
    let th = n_v.acos();
    let s = (1.0 - alpha) * ((1.0 - alpha).sqrt() + alpha);
    let r = DVec3::new(-th.sin(), 0.0, th.cos());
    let d = DVec3::Z.lerp(r, s).normalize();
    let single = [
        Kernel::new(d, alpha, 1.0),
        Kernel::new(DVec3::Z, alpha, 0.0),
    ];
    (
        l1_distance(&lobe, &fitted, n),
        l1_distance(&lobe, &single, n),
    )
}

/// Refits entry `(t, a)` from the start the generator gave it (the previous entry of its row,
/// refitted along the row from the row's start): `(shipped, fresh)`.
pub fn refit_lobe_entry(t: usize, a: usize) -> ([f32; LOBE_ENTRY], [f32; LOBE_ENTRY]) {
    let row = fit_row_until(a, t);
    (lobe_table()[a * LOBES_SIZE + t], row)
}

fn fit_row_until(a: usize, t_end: usize) -> [f32; LOBE_ENTRY] {
    let (_, roughness) = lobe_entry_coords(0, a);
    let mut start = row_start(roughness);
    let mut entry = [0.0; LOBE_ENTRY];
    for t in 0..=t_end {
        let r = fit(t, a, start);
        start = r.0;
        entry = r.1;
    }
    entry
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lobe_table_refits() {
        assert_eq!(SHIPPED.len(), LOBES_SIZE * LOBES_SIZE * LOBE_ENTRY * 4);
        for (t, a) in [(0, 31), (3, 9), (12, 20)] {
            let (shipped, fresh) = refit_lobe_entry(t, a);
            for k in 0..LOBE_ENTRY {
                assert!(
                    (shipped[k] - fresh[k]).abs() <= 1e-3,
                    "entry ({t}, {a}) value {k}: shipped {shipped:?}, fresh {fresh:?}"
                );
            }
        }
    }

    #[test]
    fn fitted_lobes_are_closer_to_the_real_lobe_than_one_lookup() {
        // The table's purpose, entry by entry: its two kernels are nearer (L1 over the sphere)
        // to the real lobe than the split sum's one lookup, from rough to smooth, head-on to
        // grazing.
        for a in [4, 10, 17, 24, 31] {
            for t in [0, 10, 20, 28] {
                let (fitted, single) = lobe_fit_error(t, a, 1024);
                assert!(
                    fitted < single,
                    "entry ({t}, {a}): fitted {fitted:.4} against one lookup {single:.4}"
                );
            }
        }
    }

    #[test]
    fn prefilter_levels_and_lod_are_inverse() {
        for mips in [2u32, 8, 10] {
            assert_eq!(prefilter_level_roughness(0, mips), 0.0);
            assert!((prefilter_level_roughness(mips - 1, mips) - 1.0).abs() < 1e-6);
            for level in 0..mips {
                let r = prefilter_level_roughness(level, mips);
                let lod = prefiltered_lod(r, mips);
                assert!(
                    (lod - level as f32).abs() < 1e-4,
                    "mips {mips} level {level}: {lod}"
                );
            }
        }
    }

    #[test]
    fn fitted_lobes_in_a_uniform_environment_are_the_albedo() {
        // The method's CPU estimate (exact prefilter, no cube) in a uniform environment of 1:
        // both lookups read 1, so it is the split sum's second factor F0 A + B exactly, at every
        // view and roughness (the mix's weights sum to 1).
        let uniform = Equirect::filled(8, 4, Vec3::ONE);
        let base = Vec3::new(0.95, 0.64, 0.54);
        let g = Geometry::SmithGgxCorrelated;
        for roughness in [0.05f32, 0.3, 0.55, 0.8, 1.0] {
            for k in 0..8 {
                let theta = (4.0 + 10.0 * k as f32).to_radians();
                let n = Vec3::new(theta.sin(), 0.3 * theta.sin(), theta.cos());
                let flat = fitted_lobes_specular(&uniform, base, roughness, g, n, Vec3::Z, 1024);
                let (a, b) = split_sum_lut_reference(n.normalize().z, roughness, g, 1024);
                let want = base * a + Vec3::splat(b);
                assert!(
                    (flat - want).abs().max_element() < 1e-4,
                    "roughness {roughness}, θ {theta}: {flat} against {want}"
                );
            }
        }
    }

    #[test]
    fn a_mirror_reads_the_mirror_direction() {
        let n = Vec3::Z;
        let v = Vec3::new(0.6, 0.0, 0.8);
        let [phi1, r1, _, _, w2] = lobes_at(0.8, 0.0);
        assert!(r1 < 1e-6 && w2 < 1e-6, "{r1} {w2}");
        let d = lobe_direction(n, v, phi1);
        let r = n * 2.0 * n.dot(v) - v;
        assert!(
            (d - r).length() < 0.01,
            "{d} against the mirror direction {r}"
        );
    }
}
