//! Random numbers and sample sets of the reference renderer: a counter-based hash (so every
//! pixel's samples depend only on the seed and the pixel, whatever the thread schedule),
//! correlated multi-jittered pixel samples (Kensler 2013) and an importance-sampling
//! distribution over an environment image.

use glam::{Vec2, Vec3};

use crate::env::{dir_to_uv, env_to_world, uv_to_dir, world_to_env, Equirect};

/// SplitMix64's finaliser: a good 64-bit mix.
pub fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A hash of several words.
pub fn hash(words: &[u64]) -> u64 {
    words.iter().fold(0x9e37_79b9_7f4a_7c15, |h, &w| {
        mix64(h ^ w.wrapping_mul(0x9e37_79b9_7f4a_7c15))
    })
}

/// A float in [0, 1) from the high 24 bits of `h`.
pub fn unit_float(h: u64) -> f32 {
    (h >> 40) as f32 * (1.0 / 16_777_216.0)
}

/// Kensler's hashed permutation of `i` in `[0, l)`.
fn permute(mut i: u32, l: u32, p: u32) -> u32 {
    if l <= 1 {
        return 0;
    }
    let mut w = l - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    loop {
        i ^= p;
        i = i.wrapping_mul(0xe170_893d);
        i ^= p >> 16;
        i ^= (i & w) >> 4;
        i ^= p >> 8;
        i = i.wrapping_mul(0x0929_eb3f);
        i ^= p >> 23;
        i ^= (i & w) >> 1;
        i = i.wrapping_mul(1 | (p >> 27));
        i = i.wrapping_mul(0x6935_fa69);
        i ^= (i & w) >> 11;
        i = i.wrapping_mul(0x74dc_b303);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0x9e50_1cc3);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0xc860_a3df);
        i &= w;
        i ^= i >> 5;
        if i < l {
            break;
        }
    }
    (i.wrapping_add(p)) % l
}

/// Kensler's hashed float in [0, 1).
fn rand_float(mut i: u32, p: u32) -> f32 {
    i ^= p;
    i ^= i >> 17;
    i ^= i >> 10;
    i = i.wrapping_mul(0xb365_34e5);
    i ^= i >> 12;
    i ^= i >> 21;
    i = i.wrapping_mul(0x93fc_4795);
    i ^= 0xdf6e_307f;
    i ^= i >> 17;
    i = i.wrapping_mul(1 | (p >> 18));
    ((i >> 8) as f32 * (1.0 / 16_777_216.0)).min(1.0 - f32::EPSILON)
}

/// Sample `s` of `n` correlated multi-jittered points in [0, 1)² (Kensler, "Correlated
/// Multi-Jittered Sampling", 2013) for pattern `p`: stratified in 2D on a near-square grid and
/// in each 1D projection, for any `n`; each point is uniformly distributed on its own, so the
/// pixel average is unbiased.
pub fn cmj(s: u32, n: u32, p: u32) -> Vec2 {
    let n = n.max(1);
    let m = ((n as f64).sqrt() as u32).max(1);
    let rows = n.div_ceil(m);
    let s = permute(s, n, p.wrapping_mul(0x5163_3e2d));
    let sx = permute(s % m, m, p.wrapping_mul(0x68bc_21eb));
    let sy = permute(s / m, rows, p.wrapping_mul(0x02e5_be93));
    let jx = rand_float(s, p.wrapping_mul(0x967a_889b));
    let jy = rand_float(s, p.wrapping_mul(0x368c_c8b7));
    let x = (sx as f32 + (sy as f32 + jx) / rows as f32) / m as f32;
    let y = (s as f32 + jy) / n as f32;
    Vec2::new(x.min(1.0 - f32::EPSILON), y.min(1.0 - f32::EPSILON))
}

/// A piecewise-constant density over an environment image, proportional to each texel's
/// luminance times sin θ (its solid angle), for importance sampling the environment. Directions
/// are drawn uniformly in (u, v) inside the chosen texel; the solid-angle density of a direction
/// is `p(u, v) / (2π² sin θ)`.
pub struct EnvDistribution {
    width: usize,
    height: usize,
    /// Marginal CDF over rows (height + 1 entries, 0 … 1).
    rows: Vec<f32>,
    /// Per-row conditional CDFs (height × (width + 1)).
    cols: Vec<f32>,
    /// Density of each texel over the unit square (mean 1).
    density: Vec<f32>,
    rotation_deg: f32,
}

impl EnvDistribution {
    /// `None` when the image is constant (then the BRDF's own sampling is already perfect for
    /// the radiance) or black.
    pub fn new(eq: &Equirect, rotation_deg: f32) -> Option<Self> {
        let (w, h) = (eq.width as usize, eq.height as usize);
        let first = eq.texels.first()?;
        if eq
            .texels
            .iter()
            .all(|t| t[0] == first[0] && t[1] == first[1] && t[2] == first[2])
        {
            return None;
        }
        let lum: Vec<f64> = eq
            .texels
            .iter()
            .map(|t| {
                (0.2126 * f64::from(t[0]) + 0.7152 * f64::from(t[1]) + 0.0722 * f64::from(t[2]))
                    .max(0.0)
            })
            .collect();
        // A bilinear lookup inside texel (i, j) mixes its 3×3 neighbourhood: weigh each texel by
        // the brightest of them, so a small bright source (the sky's sun) has a high density
        // wherever the lookup sees it (no fireflies from its filtered edge).
        let mut weights = vec![0.0f64; w * h];
        for j in 0..h {
            let theta = std::f64::consts::PI * (j as f64 + 0.5) / h as f64;
            let s = theta.sin();
            for i in 0..w {
                let mut m = 0.0f64;
                for dj in [-1i64, 0, 1] {
                    let jj = (j as i64 + dj).clamp(0, h as i64 - 1) as usize;
                    for di in [-1i64, 0, 1] {
                        let ii = (i as i64 + di).rem_euclid(w as i64) as usize;
                        m = m.max(lum[jj * w + ii]);
                    }
                }
                weights[j * w + i] = m * s;
            }
        }
        let total: f64 = weights.iter().sum();
        if total.is_nan() || total <= 0.0 || !total.is_finite() {
            return None;
        }
        let mut rows = Vec::with_capacity(h + 1);
        let mut cols = Vec::with_capacity(h * (w + 1));
        rows.push(0.0f32);
        let mut acc = 0.0f64;
        for j in 0..h {
            let row = &weights[j * w..(j + 1) * w];
            let row_sum: f64 = row.iter().sum();
            let mut c = 0.0f64;
            cols.push(0.0f32);
            for &x in row {
                c += x;
                cols.push(if row_sum > 0.0 {
                    (c / row_sum) as f32
                } else {
                    0.0
                });
            }
            if row_sum > 0.0 {
                *cols.last_mut().expect("pushed") = 1.0;
            }
            acc += row_sum;
            rows.push((acc / total) as f32);
        }
        *rows.last_mut().expect("pushed") = 1.0;
        let scale = (w * h) as f64 / total;
        let density = weights.iter().map(|x| (x * scale) as f32).collect();
        Some(EnvDistribution {
            width: w,
            height: h,
            rows,
            cols,
            density,
            rotation_deg,
        })
    }

    /// A world direction drawn from `(u1, u2) ∈ [0, 1)²`, with its solid-angle density.
    pub fn sample(&self, u1: f32, u2: f32) -> Option<(Vec3, f32)> {
        let (j, fv) = pick(&self.rows, u2)?;
        let row = &self.cols[j * (self.width + 1)..(j + 1) * (self.width + 1)];
        let (i, fu) = pick(row, u1)?;
        let uv = Vec2::new(
            (i as f32 + fu) / self.width as f32,
            (j as f32 + fv) / self.height as f32,
        );
        let d_env = uv_to_dir(uv);
        let pdf = self.pdf_env(d_env);
        (pdf > 0.0).then(|| (env_to_world(d_env, self.rotation_deg), pdf))
    }

    /// The solid-angle density of drawing the world direction `d` (unit).
    pub fn pdf(&self, d: Vec3) -> f32 {
        self.pdf_env(world_to_env(d, self.rotation_deg))
    }

    fn pdf_env(&self, d: Vec3) -> f32 {
        let sin_t = (1.0 - d.y * d.y).max(0.0).sqrt();
        if sin_t <= 1e-7 {
            return 0.0;
        }
        let uv = dir_to_uv(d);
        let i = ((uv.x * self.width as f32) as usize).min(self.width - 1);
        let j = ((uv.y * self.height as f32) as usize).min(self.height - 1);
        let p = self.density[j * self.width + i];
        p / (2.0 * std::f32::consts::PI * std::f32::consts::PI * sin_t)
    }
}

/// Index `k` with `cdf[k] ≤ u < cdf[k + 1]` among the non-empty intervals, and where `u` lies in
/// it (0 … 1).
fn pick(cdf: &[f32], u: f32) -> Option<(usize, f32)> {
    let n = cdf.len().checked_sub(1)?;
    if n == 0 || cdf[n].is_nan() || cdf[n] <= 0.0 {
        return None;
    }
    // First index whose CDF exceeds u, minus one.
    let k = cdf[1..].partition_point(|&c| c <= u).min(n - 1);
    let (a, b) = (cdf[k], cdf[k + 1]);
    if b <= a {
        return None;
    }
    Some((k, ((u - a) / (b - a)).clamp(0.0, 1.0 - f32::EPSILON)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cmj_is_stratified_and_in_range() {
        for n in [1, 2, 3, 4, 7, 16, 33] {
            let pts: Vec<Vec2> = (0..n).map(|s| cmj(s, n, 12345)).collect();
            for p in &pts {
                assert!((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y));
            }
            // One point per 1D stratum in y.
            let mut strata: Vec<u32> = pts.iter().map(|p| (p.y * n as f32) as u32).collect();
            strata.sort();
            assert_eq!(strata, (0..n).collect::<Vec<_>>());
        }
    }

    #[test]
    fn env_distribution_density_integrates_to_one() {
        let eq = Equirect::from_fn(64, 32, 1, |d| {
            Vec3::splat(1.0 + 10.0 * d.x.max(0.0).powi(8))
        });
        let dist = EnvDistribution::new(&eq, 30.0).unwrap();
        // ∫ pdf dω over the sphere by a fine (u, v) grid.
        let n = 400;
        let mut sum = 0.0f64;
        for j in 0..n {
            for i in 0..2 * n {
                let uv = Vec2::new(
                    (i as f32 + 0.5) / (2 * n) as f32,
                    (j as f32 + 0.5) / n as f32,
                );
                let d = env_to_world(uv_to_dir(uv), 30.0);
                let theta = std::f64::consts::PI * f64::from(uv.y);
                let dw = (2.0 * std::f64::consts::PI / (2 * n) as f64)
                    * (std::f64::consts::PI / n as f64)
                    * theta.sin();
                sum += f64::from(dist.pdf(d)) * dw;
            }
        }
        assert!((sum - 1.0).abs() < 1e-3, "{sum}");
        // Sampled directions carry the density pdf() reports.
        for k in 0..100 {
            let (d, p) = dist
                .sample(
                    (k as f32 + 0.5) / 100.0,
                    (((k * 37) % 100) as f32 + 0.5) / 100.0,
                )
                .unwrap();
            assert!(
                (dist.pdf(d) - p).abs() <= 1e-3 * p,
                "{} vs {p}",
                dist.pdf(d)
            );
        }
        assert!(EnvDistribution::new(&Equirect::filled(8, 4, Vec3::ONE), 0.0).is_none());
    }
}
