//! The equirectangular (latitude-longitude) image and its mapping to directions.
//!
//! # The mapping (mirrored by the GLSL)
//!
//! World space is right-handed with +y up. For a unit direction `d = (x, y, z)`:
//!
//! ```text
//! u = 0.5 + atan2(d.x, −d.z) / (2π)          ∈ [0, 1]
//! v = acos(clamp(d.y, −1, 1)) / π            ∈ [0, 1]
//! ```
//!
//! and back, with `φ = 2π (u − 0.5)`, `θ = π v`:
//!
//! ```text
//! d = (sin θ · sin φ,  cos θ,  −sin θ · cos φ)
//! ```
//!
//! So `v = 0` (row 0, the top of the image) is +y, `v = 1` is −y; the centre of the image
//! (`u = 0.5`, `v = 0.5`) is −z, the direction a default camera (at +z, looking at the origin)
//! looks at; `u = 0.75` is +x, `u = 0.25` is −x, and the left/right edges (`u = 0` / `u = 1`)
//! are +z, behind that camera. Seen from inside the sphere the image is not mirrored: moving
//! right in the image turns right. GLSL's `atan(y, x)` has the same range as Rust's `atan2`, so
//! `u = 0.5 + atan(d.x, -d.z) * (0.5 / PI)` is the exact twin (no `fract` needed).
//!
//! Texel `(i, j)` (column, row) covers `u ∈ [i/W, (i+1)/W]`, `v ∈ [j/H, (j+1)/H]`; its centre is
//! at `((i + 0.5)/W, (j + 0.5)/H)` and its solid angle is `(2π/W) · (cos θ_top − cos θ_bottom)`.
//! Bilinear lookups ([`Equirect::sample`]) are those of a Vulkan sampler with linear filtering,
//! `REPEAT` in u and `CLAMP_TO_EDGE` in v.
//!
//! # Rotation
//!
//! An environment's `rotation_deg` (θ, about +y, right-handed) is *not* baked into the image:
//! the radiance arriving from world direction `d` is `L_env(world_to_env(d, θ))` with
//! `world_to_env(d, θ) = R_y(−θ) d`. In texture space that is exactly `u_env = u_world + θ/360`
//! (v unchanged), so the GPU may either rotate the direction or offset u (with `REPEAT`).

use glam::{DVec3, Mat3, Vec2, Vec3};
use rayon::prelude::*;

use crate::brdf::PI;

/// Largest value a texel may hold: the largest finite IEEE half float, so that an RGBA16F copy
/// of the image stays finite.
pub const TEXEL_MAX: f32 = 65504.0;

/// A linear-radiance equirectangular image (see the module documentation for the mapping),
/// row-major, row 0 at the top (+y). Alpha is 1.
#[derive(Clone, PartialEq)]
pub struct Equirect {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<[f32; 4]>,
}

impl std::fmt::Debug for Equirect {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Equirect")
            .field("width", &self.width)
            .field("height", &self.height)
            .field("texels", &format_args!("[{} texels]", self.texels.len()))
            .finish()
    }
}

/// The (u, v) texture coordinates of the unit direction `d` (see the module documentation):
/// `u = 0.5 + atan2(d.x, −d.z)/(2π)`, `v = acos(d.y)/π`. Both in [0, 1].
pub fn dir_to_uv(d: Vec3) -> Vec2 {
    let u = 0.5 + d.x.atan2(-d.z) * (0.5 / PI);
    let v = d.y.clamp(-1.0, 1.0).acos() * (1.0 / PI);
    Vec2::new(u, v)
}

/// The unit direction of texture coordinates `uv`: `φ = 2π(u − 0.5)`, `θ = πv`,
/// `d = (sin θ sin φ, cos θ, −sin θ cos φ)`. Inverse of [`dir_to_uv`].
pub fn uv_to_dir(uv: Vec2) -> Vec3 {
    let phi = 2.0 * PI * (uv.x - 0.5);
    let theta = PI * uv.y;
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    Vec3::new(st * sp, ct, -st * cp)
}

/// `R_y(θ)`: environment space → world space for an environment rotated by `rotation_deg`
/// about +y (right-handed: positive angles turn +z towards +x).
pub fn env_rotation(rotation_deg: f32) -> Mat3 {
    Mat3::from_rotation_y(rotation_deg.to_radians())
}

/// The environment-space direction for world direction `d`: `R_y(−θ) d`. Every function of this
/// module that takes a direction takes it in environment space.
pub fn world_to_env(d: Vec3, rotation_deg: f32) -> Vec3 {
    env_rotation(-rotation_deg) * d
}

/// The world direction of environment-space direction `d`: `R_y(θ) d`.
pub fn env_to_world(d: Vec3, rotation_deg: f32) -> Vec3 {
    env_rotation(rotation_deg) * d
}

impl Equirect {
    /// A `width × height` image of constant radiance `rgb`.
    pub fn filled(width: u32, height: u32, rgb: Vec3) -> Self {
        Equirect {
            width,
            height,
            texels: vec![[rgb.x, rgb.y, rgb.z, 1.0]; width as usize * height as usize],
        }
    }

    /// Renders `radiance(direction)` into a `width × height` image, averaging `ss × ss`
    /// stratified directions per texel (uniform in (u, v) within the texel, each weighted by its
    /// `sin θ`, so the texel holds its solid-angle average).
    pub fn from_fn(
        width: u32,
        height: u32,
        ss: u32,
        radiance: impl Fn(Vec3) -> Vec3 + Sync,
    ) -> Self {
        let ss = ss.max(1);
        let w = width as usize;
        let mut texels = vec![[0.0f32; 4]; w * height as usize];
        texels.par_chunks_mut(w).enumerate().for_each(|(j, row)| {
            for (i, t) in row.iter_mut().enumerate() {
                let mut sum = DVec3::ZERO;
                let mut wsum = 0.0f64;
                for sj in 0..ss {
                    let v = (j as f32 + (sj as f32 + 0.5) / ss as f32) / height as f32;
                    let weight = f64::from((PI * v).sin()).max(1e-9);
                    for si in 0..ss {
                        let u = (i as f32 + (si as f32 + 0.5) / ss as f32) / width as f32;
                        sum += radiance(uv_to_dir(Vec2::new(u, v))).as_dvec3() * weight;
                        wsum += weight;
                    }
                }
                let c = (sum / wsum).as_vec3();
                *t = [c.x, c.y, c.z, 1.0];
            }
        });
        Equirect {
            width,
            height,
            texels,
        }
    }

    /// Texel `(i, j)` (column, row) as RGB. Panics when out of range.
    pub fn texel(&self, i: u32, j: u32) -> Vec3 {
        let t = self.texels[j as usize * self.width as usize + i as usize];
        Vec3::new(t[0], t[1], t[2])
    }

    /// The direction through the centre of texel `(i, j)`.
    pub fn texel_dir(&self, i: u32, j: u32) -> Vec3 {
        uv_to_dir(Vec2::new(
            (i as f32 + 0.5) / self.width as f32,
            (j as f32 + 0.5) / self.height as f32,
        ))
    }

    /// The exact solid angle of a texel of row `j`: `(2π/W)(cos θ_top − cos θ_bottom)`.
    pub fn texel_solid_angle(&self, j: u32) -> f64 {
        let h = f64::from(self.height);
        let t0 = std::f64::consts::PI * f64::from(j) / h;
        let t1 = std::f64::consts::PI * f64::from(j + 1) / h;
        2.0 * std::f64::consts::PI / f64::from(self.width) * (t0.cos() - t1.cos())
    }

    /// The radiance of the texel that contains direction `d` (no filtering).
    pub fn lookup_nearest(&self, d: Vec3) -> Vec3 {
        let uv = dir_to_uv(d);
        let i = ((uv.x * self.width as f32).floor() as i64).rem_euclid(i64::from(self.width));
        let j = ((uv.y * self.height as f32).floor() as i64).clamp(0, i64::from(self.height) - 1);
        self.texel(i as u32, j as u32)
    }

    /// Bilinear radiance in direction `d`, as a Vulkan linear sampler with `REPEAT` in u and
    /// `CLAMP_TO_EDGE` in v reads it: `s = u W − 0.5`, `t = v H − 0.5`.
    pub fn sample(&self, d: Vec3) -> Vec3 {
        let uv = dir_to_uv(d);
        let s = uv.x * self.width as f32 - 0.5;
        let t = uv.y * self.height as f32 - 0.5;
        let (s0, t0) = (s.floor(), t.floor());
        let (fs, ft) = (s - s0, t - t0);
        let w = i64::from(self.width);
        let h = i64::from(self.height);
        let x0 = (s0 as i64).rem_euclid(w) as u32;
        let x1 = (s0 as i64 + 1).rem_euclid(w) as u32;
        let y0 = (t0 as i64).clamp(0, h - 1) as u32;
        let y1 = (t0 as i64 + 1).clamp(0, h - 1) as u32;
        let top = self.texel(x0, y0) * (1.0 - fs) + self.texel(x1, y0) * fs;
        let bottom = self.texel(x0, y1) * (1.0 - fs) + self.texel(x1, y1) * fs;
        top * (1.0 - ft) + bottom * ft
    }

    /// Multiplies every texel's RGB by `k`.
    pub fn scale(&mut self, k: f32) {
        for t in &mut self.texels {
            for c in &mut t[..3] {
                *c *= k;
            }
        }
    }

    /// Makes every texel finite, non-negative and at most [`TEXEL_MAX`]: NaN and negative
    /// channels become 0, +Inf and larger values [`TEXEL_MAX`]; alpha becomes 1. Returns the
    /// number of texels changed.
    pub fn sanitize(&mut self) -> u64 {
        let mut changed = 0;
        for t in &mut self.texels {
            let before = *t;
            for c in &mut t[..3] {
                *c = if c.is_nan() {
                    0.0
                } else {
                    c.clamp(0.0, TEXEL_MAX)
                };
            }
            t[3] = 1.0;
            if before[..3] != t[..3] {
                changed += 1;
            }
        }
        changed
    }

    /// The largest channel value of any texel.
    pub fn max_value(&self) -> f32 {
        self.texels
            .iter()
            .flat_map(|t| t[..3].iter().copied())
            .fold(0.0, f32::max)
    }

    /// Whether every channel of every texel is finite and ≥ 0.
    pub fn is_finite_non_negative(&self) -> bool {
        self.texels
            .iter()
            .all(|t| t.iter().all(|c| c.is_finite() && *c >= 0.0))
    }

    /// `∫ L dω` over the sphere (per channel), summing texels times their solid angles.
    pub fn integral(&self) -> Vec3 {
        (0..self.height)
            .into_par_iter()
            .map(|j| {
                let w = self.texel_solid_angle(j);
                (0..self.width)
                    .map(|i| self.texel(i, j).as_dvec3())
                    .sum::<DVec3>()
                    * w
            })
            .sum::<DVec3>()
            .as_vec3()
    }

    /// Halves the resolution by a factor `k` (a power of two) in both directions, averaging
    /// `k × k` blocks weighted by solid angle (so `∫ L dω` is kept). Rows and columns that do not
    /// fill a block are dropped (none when both sizes are multiples of `k`).
    pub fn downsample(&self, k: u32) -> Equirect {
        let k = k.max(1);
        let (w, h) = ((self.width / k).max(1), (self.height / k).max(1));
        let mut texels = vec![[0.0f32; 4]; w as usize * h as usize];
        texels
            .par_chunks_mut(w as usize)
            .enumerate()
            .for_each(|(j, row)| {
                for (i, t) in row.iter_mut().enumerate() {
                    let mut sum = DVec3::ZERO;
                    let mut wsum = 0.0;
                    for sj in 0..k {
                        let y = (j as u32 * k + sj).min(self.height - 1);
                        let weight = self.texel_solid_angle(y);
                        for si in 0..k {
                            let x = (i as u32 * k + si).min(self.width - 1);
                            sum += self.texel(x, y).as_dvec3() * weight;
                            wsum += weight;
                        }
                    }
                    let c = (sum / wsum.max(1e-300)).as_vec3();
                    *t = [c.x, c.y, c.z, 1.0];
                }
            });
        Equirect {
            width: w,
            height: h,
            texels,
        }
    }
}
