//! The built-in environments: a sky with a sun, and a studio with four soft area-like lights.
//! Both are rendered into equirectangular images in environment space (before `rotation_deg`)
//! and are finite, non-negative and below the half-float maximum for every valid input.

use glam::{Vec2, Vec3};

use super::equirect::{dir_to_uv, uv_to_dir, Equirect};
use crate::brdf::PI;

/// Default size of the sky image (2:1).
pub const SKY_WIDTH: u32 = 1024;
/// Default size of the studio image (2:1).
pub const STUDIO_WIDTH: u32 = 512;

/// Angular radius of the sun disc, degrees (the real sun's is 0.27°; 1° keeps the disc a few
/// texels wide in a 1024×512 image, so it survives filtering without aliasing).
pub const SUN_RADIUS_DEG: f32 = 1.0;
/// Colour of the sun: its irradiance is `sun_intensity · SUN_COLOR` per channel.
pub const SUN_COLOR: Vec3 = Vec3::new(1.0, 0.96, 0.9);
/// Sky radiance straight up.
pub const SKY_ZENITH: Vec3 = Vec3::new(0.10, 0.22, 0.50);
/// Sky radiance at the horizon.
pub const SKY_HORIZON: Vec3 = Vec3::new(0.55, 0.62, 0.72);
/// Diffuse albedo of the ground (lit by the sky and the sun, seen below the horizon).
pub const GROUND_ALBEDO: Vec3 = Vec3::new(0.30, 0.27, 0.24);
/// Fraction of the sun's irradiance added as a Gaussian glow around the disc.
pub const SUN_GLOW_FRACTION: f32 = 0.05;
/// Standard deviation of the glow, degrees.
pub const SUN_GLOW_SIGMA_DEG: f32 = 5.0;

/// `smoothstep(e0, e1, x)` as GLSL.
fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Half-width of the horizon blend, in units of `d.y` (≈ 1.1°).
const HORIZON_BLEND: f32 = 0.02;

/// The sky without the sun disc (gradient, glow and ground), for the environment-space unit
/// direction `d` and the unit direction *towards* the sun `to_sun`.
pub(super) fn sky_background(d: Vec3, to_sun: Vec3, sun_intensity: f32) -> Vec3 {
    let e_sun = SUN_COLOR * sun_intensity;
    let sky = |y: f32| SKY_HORIZON.lerp(SKY_ZENITH, y.clamp(0.0, 1.0).powf(0.4));
    // Glow: a Gaussian of the angle to the sun, normalised (small-angle) so that it adds
    // SUN_GLOW_FRACTION of the sun's irradiance.
    let sigma = SUN_GLOW_SIGMA_DEG.to_radians();
    let gamma = d.dot(to_sun).clamp(-1.0, 1.0).acos();
    let glow = e_sun
        * (SUN_GLOW_FRACTION * (-(gamma * gamma) / (2.0 * sigma * sigma)).exp()
            / (2.0 * PI * sigma * sigma));
    // Ground: Lambertian, lit by the sun and (roughly) by the average sky.
    let e_ground = e_sun * to_sun.y.max(0.0) + PI * 0.5 * (SKY_HORIZON + SKY_ZENITH);
    let ground = GROUND_ALBEDO * e_ground / PI;
    let above = sky(d.y) + glow;
    let t = smoothstep(-HORIZON_BLEND, HORIZON_BLEND, d.y);
    ground.lerp(above, t)
}

/// The procedural sky at `width × width/2`: a gradient from [`SKY_HORIZON`] to [`SKY_ZENITH`]
/// (`mix(horizon, zenith, y^0.4)`), a Gaussian glow around the sun, a Lambertian ground of albedo
/// [`GROUND_ALBEDO`] below the horizon (blended over ±1.1°), and a sun disc of angular radius
/// [`SUN_RADIUS_DEG`] whose constant radiance is set so that the disc's irradiance on a surface
/// facing it, integrated over the image's texels, is exactly `sun_intensity · SUN_COLOR`
/// (≈ 3135 · sun_intensity · SUN_COLOR for the 1° disc: below 60000 for `sun_intensity ≤ 50`
/// without `intensity`). `sun_direction` is the way the light travels (the sun is at
/// `−sun_direction`).
pub fn sky(width: u32, sun_direction: Vec3, sun_intensity: f32) -> Equirect {
    let width = width.max(4) & !1;
    let height = width / 2;
    let to_sun = (-sun_direction).try_normalize().unwrap_or(Vec3::Y);
    let sun_intensity = sun_intensity.max(0.0);
    let mut eq = Equirect::from_fn(width, height, 2, |d| {
        sky_background(d, to_sun, sun_intensity)
    });
    if sun_intensity > 0.0 {
        draw_sun(&mut eq, to_sun, sun_intensity);
    }
    eq
}

/// Replaces the texels under the sun disc by `coverage · L_sun + (1 − coverage) · sky`, with
/// `L_sun` chosen so that `Σ coverage · Ω_texel · L_sun = sun_intensity · SUN_COLOR`.
fn draw_sun(eq: &mut Equirect, to_sun: Vec3, sun_intensity: f32) {
    const SS: u32 = 16;
    let radius = SUN_RADIUS_DEG.to_radians();
    let cos_r = radius.cos();
    let (w, h) = (eq.width, eq.height);
    // Rows whose latitude band can touch the disc (a texel's diagonal of margin).
    let theta_sun = to_sun.y.clamp(-1.0, 1.0).acos();
    let margin = radius + 2.0 * PI / h as f32;
    let j0 = (((theta_sun - margin) / PI * h as f32).floor().max(0.0)) as u32;
    let j1 = (((theta_sun + margin) / PI * h as f32).ceil() as u32).min(h);
    // A texel spans at most π/h in each direction (w = 2h): 1.5 π/h bounds its half diagonal.
    let texel_half_diag = (PI / h as f32) * 1.5;
    let mut covered: Vec<(usize, f32)> = Vec::new();
    let mut solid = 0.0f64;
    for j in j0..j1 {
        let omega = eq.texel_solid_angle(j);
        for i in 0..w {
            let c = eq.texel_dir(i, j);
            // Cheap rejection: the texel centre is far from the disc.
            if c.dot(to_sun).clamp(-1.0, 1.0).acos() > radius + texel_half_diag {
                continue;
            }
            let mut inside = 0.0f32;
            let mut total = 0.0f32;
            for sj in 0..SS {
                let v = (j as f32 + (sj as f32 + 0.5) / SS as f32) / h as f32;
                let weight = (PI * v).sin().max(1e-9);
                for si in 0..SS {
                    let u = (i as f32 + (si as f32 + 0.5) / SS as f32) / w as f32;
                    if uv_to_dir(Vec2::new(u, v)).dot(to_sun) >= cos_r {
                        inside += weight;
                    }
                    total += weight;
                }
            }
            let coverage = inside / total;
            if coverage > 0.0 {
                covered.push(((j * w + i) as usize, coverage));
                solid += f64::from(coverage) * omega;
            }
        }
    }
    if solid <= 0.0 {
        // A disc smaller than the sub-samples (cannot happen at the supported sizes): put the
        // sun's energy into the one texel that holds its centre.
        let uv = dir_to_uv(to_sun);
        let i = ((uv.x * w as f32) as u32).min(w - 1);
        let j = ((uv.y * h as f32) as u32).min(h - 1);
        covered = vec![((j * w + i) as usize, 1.0)];
        solid = eq.texel_solid_angle(j);
    }
    let l_sun = SUN_COLOR * (sun_intensity / solid as f32);
    for (k, coverage) in covered {
        let t = &mut eq.texels[k];
        let bg = Vec3::new(t[0], t[1], t[2]);
        let c = bg * (1.0 - coverage) + l_sun * coverage;
        *t = [c.x, c.y, c.z, 1.0];
    }
}

/// One soft area-like light of the studio, seen from the origin.
struct Panel {
    /// Unit direction towards the panel's centre.
    centre: Vec3,
    /// Half-size in gnomonic (tangent-plane) units: `tan` of the half angles.
    half: Vec2,
    /// `true`: a disc of radius `half.x`; `false`: a rectangle.
    disc: bool,
    radiance: Vec3,
}

/// Width of the soft edge of the studio's panels, in tangent-plane units (≈ 3°).
const PANEL_SOFT: f32 = 0.05;

impl Panel {
    fn new(centre: Vec3, half_deg: (f32, f32), disc: bool, radiance: Vec3) -> Self {
        Panel {
            centre: centre.normalize(),
            half: Vec2::new(half_deg.0.to_radians().tan(), half_deg.1.to_radians().tan()),
            disc,
            radiance,
        }
    }

    fn eval(&self, d: Vec3) -> Vec3 {
        let c = d.dot(self.centre);
        if c <= 0.1 {
            return Vec3::ZERO;
        }
        // Tangent frame with t horizontal (b up), except for panels straight above or below.
        let t = Vec3::Y
            .cross(self.centre)
            .try_normalize()
            .unwrap_or(Vec3::X);
        let b = self.centre.cross(t);
        let p = Vec2::new(d.dot(t), d.dot(b)) / c;
        let edge = |a: f32, half: f32| 1.0 - smoothstep(half - PANEL_SOFT, half + PANEL_SOFT, a);
        let mask = if self.disc {
            edge(p.length(), self.half.x)
        } else {
            edge(p.x.abs(), self.half.x) * edge(p.y.abs(), self.half.y)
        };
        self.radiance * mask
    }
}

/// Studio walls above the horizon.
pub const STUDIO_WALL: Vec3 = Vec3::splat(0.05);
/// Studio floor below the horizon.
pub const STUDIO_FLOOR: Vec3 = Vec3::splat(0.025);

fn studio_panels() -> [Panel; 4] {
    [
        // Key: a large warm softbox front-left and above (50° × 36°).
        Panel::new(
            Vec3::new(-0.6, 0.5, 0.62),
            (25.0, 18.0),
            false,
            Vec3::new(1.0, 0.95, 0.88) * 4.0,
        ),
        // Fill: a dim cool disc front-right, low (44° across).
        Panel::new(
            Vec3::new(0.8, 0.15, 0.55),
            (22.0, 22.0),
            true,
            Vec3::new(0.85, 0.92, 1.0) * 0.9,
        ),
        // Rim: a tall narrow strip behind and to the right (14° × 60°).
        Panel::new(
            Vec3::new(0.35, 0.3, -0.88),
            (7.0, 30.0),
            false,
            Vec3::splat(6.0),
        ),
        // Top: a disc overhead (36° across).
        Panel::new(Vec3::Y, (18.0, 18.0), true, Vec3::splat(2.5)),
    ]
}

/// The procedural studio at `width × width/2`: walls of radiance [`STUDIO_WALL`] above the
/// horizon, a floor of [`STUDIO_FLOOR`] below (blended over ±1.1°), and four soft-edged
/// area-like lights (in environment space, "front" = +z, where a default camera stands):
/// a key softbox front-left-above (50° × 36°, radiance 4 warm), a fill disc front-right (44°,
/// 0.9 cool), a rim strip behind-right (14° × 60°, 6) and a top disc (36°, 2.5).
pub fn studio(width: u32) -> Equirect {
    let width = width.max(4) & !1;
    let panels = studio_panels();
    Equirect::from_fn(width, width / 2, 3, |d| {
        let bg = STUDIO_FLOOR.lerp(STUDIO_WALL, smoothstep(-HORIZON_BLEND, HORIZON_BLEND, d.y));
        panels.iter().fold(bg, |acc, p| acc + p.eval(d))
    })
}
