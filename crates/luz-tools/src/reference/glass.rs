//! The reference's glass (issue 35): a random walk through a closed dielectric object that
//! really refracts. At each crossing of its surface the walk samples the rough dielectric BSDF
//! ([`crate::brdf::RoughDielectric`]: reflection or refraction by the Fresnel reflectance,
//! Walter et al. 2007), attenuates by Beer–Lambert along the true path inside, and follows
//! specular chains up to [`MAX_BOUNCES`] crossings. What leaves the object reads the
//! surroundings. The BSDF's weights carry the η² of radiance entering and leaving a denser
//! medium, so a uniform surrounding of 1 is seen through a clear object as 1.
//!
//! The walk is generic over the object's intersection, so the tests run it on analytic shapes
//! (a sphere, a slab) against closed-form answers; the scene renderer plugs in its own.

use glam::Vec3;

use crate::brdf::{beer_lambert, ortho_basis, RoughDielectric};

/// Crossings a walk follows before it gives up (and returns what it gathered: nothing).
pub const MAX_BOUNCES: u32 = 32;

/// Where a ray meets the glass object's surface: the distance along the (unit) ray and the
/// surface's unit normal pointing out of the object.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlassHit {
    pub t: f32,
    pub n_out: Vec3,
}

/// A closed dielectric object: its interface and the attenuation coefficient of its inside
/// (per unit length and channel; zero for clear glass).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Glass {
    pub interface: RoughDielectric,
    pub sigma: Vec3,
}

/// Radiance arriving along the unit ray `(origin, dir)` from outside the object, estimated by
/// one random walk: `hit(o, d)` is the nearest crossing of the object's surface along the ray
/// (`None` when it leaves), `surroundings(o, d)` the radiance along the ray `(o, d)` once it has
/// left, `rng()` uniform numbers in [0, 1).
pub fn walk(
    origin: Vec3,
    dir: Vec3,
    glass: &Glass,
    hit: impl Fn(Vec3, Vec3) -> Option<GlassHit>,
    surroundings: impl Fn(Vec3, Vec3) -> Vec3,
    mut rng: impl FnMut() -> f32,
) -> Vec3 {
    let start = Start {
        o: origin,
        d: dir.normalize(),
        throughput: Vec3::ONE,
        inside: false,
    };
    walk_from(start, glass, &hit, &surroundings, &mut rng, MAX_BOUNCES)
}

/// What is refracted into the object where the unit ray `dir` meets its surface at `p` (outside
/// normal `n_out`), where a reflection contributes nothing (the
/// caller shades the surface's reflection as a BRDF): the refraction alone is sampled
/// (`RoughDielectric::sample_refraction`), and walks on inside as [`walk`].
/// The expected value is the transmitted part of the radiance seen at `p`.
pub fn transmitted(
    (p, dir, n_out): (Vec3, Vec3, Vec3),
    glass: &Glass,
    hit: impl Fn(Vec3, Vec3) -> Option<GlassHit>,
    surroundings: impl Fn(Vec3, Vec3) -> Vec3,
    mut rng: impl FnMut() -> f32,
) -> Vec3 {
    let (t, b) = ortho_basis(n_out);
    let wo = Vec3::new(-dir.dot(t), -dir.dot(b), -dir.dot(n_out));
    let Some(s) = glass.interface.sample_refraction(wo, (rng(), rng())) else {
        return Vec3::ZERO;
    };
    let (d, weight) = (
        (t * s.wi.x + b * s.wi.y + n_out * s.wi.z).normalize(),
        s.weight,
    );
    let start = Start {
        o: p - n_out * 1e-4,
        d,
        throughput: Vec3::splat(weight),
        inside: true,
    };
    walk_from(start, glass, &hit, &surroundings, &mut rng, MAX_BOUNCES - 1)
}

/// Where a walk stands: the ray, the weight so far and the side.
struct Start {
    o: Vec3,
    d: Vec3,
    throughput: Vec3,
    inside: bool,
}

/// One sample of the interface (outside normal `n_out`) for the unit ray `d` arriving: the
/// new direction and the sample's weight.
fn cross(
    glass: &Glass,
    n_out: Vec3,
    d: Vec3,
    rng: &mut impl FnMut() -> f32,
) -> Option<(Vec3, f32)> {
    // The BSDF's frame: +z the outside normal.
    let (t, b) = ortho_basis(n_out);
    let wo = Vec3::new(-d.dot(t), -d.dot(b), -d.dot(n_out));
    let s = glass.interface.sample(wo, (rng(), rng()), rng())?;
    Some((
        (t * s.wi.x + b * s.wi.y + n_out * s.wi.z).normalize(),
        s.weight,
    ))
}

fn walk_from(
    start: Start,
    glass: &Glass,
    hit: &impl Fn(Vec3, Vec3) -> Option<GlassHit>,
    surroundings: &impl Fn(Vec3, Vec3) -> Vec3,
    rng: &mut impl FnMut() -> f32,
    bounces: u32,
) -> Vec3 {
    let Start {
        mut o,
        mut d,
        mut throughput,
        mut inside,
    } = start;
    for _ in 0..bounces {
        let Some(h) = hit(o, d) else {
            // Inside, a closed surface is always met again; a miss there is a numerical
            // escape and carries nothing.
            return if inside {
                Vec3::ZERO
            } else {
                throughput * surroundings(o, d)
            };
        };
        if inside {
            throughput *= beer_lambert(glass.sigma, h.t);
        }
        let p = o + d * h.t;
        let Some((next, weight)) = cross(glass, h.n_out, d, rng) else {
            return Vec3::ZERO;
        };
        throughput *= weight;
        d = next;
        inside = d.dot(h.n_out) < 0.0;
        // Leave the surface on the side the ray goes to.
        o = p + h.n_out * (if inside { -1e-4 } else { 1e-4 });
    }
    Vec3::ZERO
}

/// [`GlassHit`] of the unit ray `(o, d)` with a sphere of radius `r` at `c` (from outside or
/// inside), nearest crossing beyond a small epsilon.
pub fn sphere_hit(c: Vec3, r: f32, o: Vec3, d: Vec3) -> Option<GlassHit> {
    let oc = o - c;
    let b = oc.dot(d);
    let disc = b * b - (oc.length_squared() - r * r);
    if disc < 0.0 {
        return None;
    }
    let s = disc.sqrt();
    let t = [-b - s, -b + s].into_iter().find(|&t| t > 1e-5)?;
    Some(GlassHit {
        t,
        n_out: (o + d * t - c) / r,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::f_dielectric;

    /// A deterministic generator for the walks (xorshift64).
    fn rng(seed: u64) -> impl FnMut() -> f32 {
        let mut s = seed.max(1);
        move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    fn smooth(ior: f32, sigma: Vec3) -> Glass {
        Glass {
            interface: RoughDielectric { alpha: 0.0, ior },
            sigma,
        }
    }

    /// The mean of `n` walks.
    fn mean(n: u32, f: impl Fn(u64) -> Vec3) -> Vec3 {
        (0..n).map(|i| f(i as u64 + 1)).sum::<Vec3>() / n as f32
    }

    /// A slab between z = 0 and z = −thickness (normals ±z out of it).
    fn slab(thickness: f32) -> impl Fn(Vec3, Vec3) -> Option<GlassHit> {
        move |o: Vec3, d: Vec3| {
            [(0.0, Vec3::Z), (-thickness, -Vec3::Z)]
                .into_iter()
                .filter_map(|(z, n)| {
                    let t = (z - o.z) / d.z;
                    (d.z != 0.0 && t > 1e-5).then_some(GlassHit { t, n_out: n })
                })
                .min_by(|a, b| a.t.total_cmp(&b.t))
        }
    }

    /// Through a glass sphere the straight-through path leaves where the analytic ray path
    /// does: a ray at impact parameter b (sin θ_i = b/R) turns by D = 2(θ_i − θ_t) after two
    /// refractions (0 at the centre). Seen against surroundings lit only within 0.5° of that
    /// exit direction, the walk returns the two crossings' transmittance (1 − F(θ_i))², the
    /// Fresnel of the entry and of the (symmetric) exit: the direction and the weight both.
    #[test]
    fn refraction_through_a_sphere_follows_the_analytic_path() {
        let (ior, radius) = (1.5f32, 1.0f32);
        let glass = smooth(ior, Vec3::ZERO);
        for b in [0.0f32, 0.25, 0.5, 0.75, 0.9] {
            let theta_i = b.asin();
            let theta_t = (b / ior).asin();
            let deviation = 2.0 * (theta_i - theta_t);
            // A ray along −z at height b in y; it turns towards the axis (−y), by `deviation`.
            let exit = Vec3::new(0.0, -deviation.sin(), -deviation.cos());
            let lit = move |_: Vec3, d: Vec3| {
                if d.dot(exit) > 0.5f32.to_radians().cos() {
                    Vec3::ONE
                } else {
                    Vec3::ZERO
                }
            };
            let origin = Vec3::new(0.0, b * radius, 5.0);
            let got = mean(4000, |seed| {
                walk(
                    origin,
                    -Vec3::Z,
                    &glass,
                    |o, d| sphere_hit(Vec3::ZERO, radius, o, d),
                    lit,
                    rng(seed * 7919),
                )
            });
            let t = 1.0 - f_dielectric(theta_i.cos(), ior);
            let want = t * t;
            // Binomial noise of 4000 walks: ~0.5 %; the internal reflections lit the same way
            // add (1 − F)² F² (≤ 0.3 % here) only at b = 0, where they leave along the axis too.
            assert!(
                (got.x - want).abs() < 0.02 * want,
                "b {b}: walk {}, analytic {want} (deviation {:.2}°)",
                got.x,
                deviation.to_degrees()
            );
        }
    }

    /// A clear slab in uniform surroundings of 1 is seen as 1: reflection plus transmission,
    /// every internal bounce included, conserves the light (issue 35's ±1 %) from 0 to 60°.
    /// At 80° the walk returns 0.989 (measured 2026-11-28): 0.29 % of the walks are cut at
    /// [`MAX_BOUNCES`] (inside, the ray runs at 41.0°, just under the critical 41.8°, and
    /// reflects often) and the rest is the spread of the near-smooth (α 0.001) GGX's weights
    /// along long chains; not asserted yet.
    #[test]
    fn a_clear_slab_in_uniform_surroundings_returns_one() {
        let glass = smooth(1.5, Vec3::ZERO);
        for theta in [0.0f32, 30.0, 60.0] {
            let t = theta.to_radians();
            let d = Vec3::new(t.sin(), 0.0, -t.cos());
            let got = mean(20_000, |seed| {
                walk(
                    Vec3::new(0.0, 0.0, 1.0),
                    d,
                    &glass,
                    slab(0.3),
                    |_, _| Vec3::ONE,
                    rng(seed * 104_729),
                )
            });
            assert!((got.x - 1.0).abs() < 0.01, "θ {theta}: {}", got.x);
        }
    }

    /// Beer–Lambert along the true path: in an index-matched slab (η 1: no reflection, no
    /// bending) light keeps exp(−σ d) over the thickness d, at normal incidence and along the
    /// longer oblique path d / cos θ.
    #[test]
    fn attenuation_over_a_known_distance_is_exp_minus_sigma_d() {
        let sigma = Vec3::new(0.5, 1.0, 2.0);
        let glass = smooth(1.0, sigma);
        for theta in [0.0f32, 45.0] {
            let t = theta.to_radians();
            let d = Vec3::new(t.sin(), 0.0, -t.cos());
            let got = walk(
                Vec3::new(0.0, 0.0, 1.0),
                d,
                &glass,
                slab(0.4),
                |_, _| Vec3::ONE,
                rng(3),
            );
            let want = (-sigma * 0.4 / t.cos()).exp();
            assert!(
                (got - want).abs().max_element() < 1e-4,
                "θ {theta}: {got} {want}"
            );
        }
        // With η 1.5 at normal incidence the light that crosses straight through is
        // (1 − F)² e^(−σd) / (1 − F² e^(−2σd)), counting every pair of internal reflections;
        // surroundings lit only below the slab see exactly that.
        let glass = smooth(1.5, sigma);
        let f = f_dielectric(1.0, 1.5);
        let got = mean(20_000, |seed| {
            walk(
                Vec3::new(0.0, 0.0, 1.0),
                -Vec3::Z,
                &glass,
                slab(0.4),
                |_, d| if d.z < 0.0 { Vec3::ONE } else { Vec3::ZERO },
                rng(seed * 31),
            )
        });
        let e = (-sigma * 0.4).exp();
        let want = (1.0 - f) * (1.0 - f) * e / (Vec3::ONE - f * f * e * e);
        assert!(
            ((got - want) / want).abs().max_element() < 0.02,
            "{got} {want}"
        );
    }
}
