//! Area lights in the reference (issue 36): the light's direct contribution at a surface point
//! by multiple importance sampling (balance heuristic) of the emitter (uniform on the area of a
//! rect, disk or tube; uniform in the solid angle of a sphere) and of the BRDF's lobes, with a
//! shadow ray per sample for lights with a shadow.

use std::f32::consts::PI;

use glam::{DVec3, Vec2, Vec3};

use super::{cmj, concentric_disc, hash, orthonormal_basis, Surface};
use crate::brdf::{sampling_lobes, Lobe};
use crate::scene::{range_window, AreaLight, AreaShape};

/// A direction towards the emitter: unit `dir`, the distance to the emitting point and the
/// solid-angle density with which the emitter's sampling gives it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Towards {
    pub dir: Vec3,
    pub dist: f32,
    pub pdf: f32,
}

/// Cosine of the emitted direction `-dir` with the emitter's normal `m` at the hit, or 0 when
/// that side does not emit.
fn emitting_cos(light: &AreaLight, m: Vec3, dir: Vec3) -> f32 {
    let c = -dir.dot(m);
    if light.two_sided || !light.shape.is_flat() {
        c.abs()
    } else {
        c.max(0.0)
    }
}

/// The emitter point of unit-square sample `u` with its outward normal and the area density.
fn sample_surface(light: &AreaLight, u: Vec2) -> (Vec3, Vec3, f32) {
    let (c, n) = (light.position, light.direction);
    match light.shape {
        AreaShape::Rect { .. } => {
            let (ex, ey) = light.rect_axes().unwrap_or_default();
            let q = c + ex * (2.0 * u.x - 1.0) + ey * (2.0 * u.y - 1.0);
            (q, n, 1.0 / light.area())
        }
        AreaShape::Disk { radius } => {
            let (a, b) = orthonormal_basis(n);
            let d = concentric_disc(u) * radius;
            (c + a * d.x + b * d.y, n, 1.0 / light.area())
        }
        AreaShape::Tube { length, radius } => {
            let (a, b) = orthonormal_basis(n);
            let phi = 2.0 * PI * u.y;
            let m = a * phi.cos() + b * phi.sin();
            let q = c + n * (length * (u.x - 0.5)) + m * radius;
            (q, m, 1.0 / light.area())
        }
        // Spheres are sampled in solid angle (`sample`); this uniform form is unused.
        AreaShape::Sphere { radius } => {
            let z = 1.0 - 2.0 * u.x;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = 2.0 * PI * u.y;
            let m = Vec3::new(r * phi.cos(), r * phi.sin(), z);
            (c + m * radius, m, 1.0 / light.area())
        }
    }
}

/// The cone of a sphere seen from `p`: (unit axis towards the centre, distance, 1 − cos θ_max),
/// in f64: for a 0.5 mm sphere at 1 m, 1 − cos θ_max is 1.25e-7, below f32's spacing at 1 (the
/// reference's tiny-sphere row was 33 % off in f32); `None` from inside it.
fn sphere_cone(light: &AreaLight, radius: f32, p: Vec3) -> Option<(DVec3, f64, f64)> {
    let to_c = light.position.as_dvec3() - p.as_dvec3();
    let d = to_c.length();
    let r = f64::from(radius);
    (d > r * (1.0 + 1e-5)).then(|| {
        let sin2 = (r / d) * (r / d);
        (to_c / d, d, sin2 / (1.0 + (1.0 - sin2).max(0.0).sqrt()))
    })
}

/// A direction from `p` towards the emitter for the unit-square sample `u`.
pub(super) fn sample(light: &AreaLight, p: Vec3, u: Vec2) -> Option<Towards> {
    if let AreaShape::Sphere { radius } = light.shape {
        let (w, _, omc) = sphere_cone(light, radius, p)?;
        // 1 − cos θ and sin θ without cancellation (f64 throughout: see `sphere_cone`).
        let one_minus = f64::from(u.x) * omc;
        let sin_t = (one_minus * (2.0 - one_minus)).max(0.0).sqrt();
        let phi = 2.0 * std::f64::consts::PI * f64::from(u.y);
        let (a, b) = orthonormal_basis(w.as_vec3());
        let (a, b) = (a.as_dvec3(), b.as_dvec3());
        let dir = (a * (sin_t * phi.cos()) + b * (sin_t * phi.sin()) + w * (1.0 - one_minus))
            .normalize()
            .as_vec3();
        let dist = intersect(light, p, dir)?.0;
        return Some(Towards {
            dir,
            dist,
            pdf: (1.0 / (2.0 * std::f64::consts::PI * omc)) as f32,
        });
    }
    let (q, m, pdf_area) = sample_surface(light, u);
    let to_q = q - p;
    let dist = to_q.length();
    let dir = to_q / dist;
    let cos_l = emitting_cos(light, m, dir);
    // A tube's side hides itself: a point behind the near side (outside it, its far half) is
    // not seen from `p`, though its inner face turns towards p. Only the first surface the ray
    // meets emits towards p, as `intersect` (the BRDF's samples) has it; counting the far half
    // too doubled a tube's light seen from outside (the lab's `area` group, issue 36).
    if matches!(light.shape, AreaShape::Tube { .. }) && !tube_point_seen(light, p, dir, dist) {
        return None;
    }
    (dist > 0.0 && cos_l > 0.0).then(|| Towards {
        dir,
        dist,
        pdf: pdf_area * dist * dist / cos_l,
    })
}

/// Where the ray from `p` along unit `dir` first meets the emitter's emitting side: the distance
/// and the solid-angle density with which [`sample`] would give that direction.
pub(super) fn intersect(light: &AreaLight, p: Vec3, dir: Vec3) -> Option<(f32, f32)> {
    let (c, n) = (light.position, light.direction);
    let area_pdf = |t: f32, m: Vec3| {
        let cos_l = emitting_cos(light, m, dir);
        (t > 0.0 && cos_l > 0.0).then(|| (t, t * t / (cos_l * light.area())))
    };
    match light.shape {
        AreaShape::Rect { .. } | AreaShape::Disk { .. } => {
            let dn = dir.dot(n);
            if dn == 0.0 {
                return None;
            }
            let t = (c - p).dot(n) / dn;
            let q = p + dir * t - c;
            let inside = match light.shape {
                AreaShape::Disk { radius } => q.length_squared() <= radius * radius,
                _ => {
                    let (ex, ey) = light.rect_axes()?;
                    q.dot(ex).abs() <= ex.length_squared() && q.dot(ey).abs() <= ey.length_squared()
                }
            };
            if inside {
                area_pdf(t, n)
            } else {
                None
            }
        }
        AreaShape::Sphere { radius } => {
            // f64, and the discriminant as r² − (the ray's distance from the centre)², which
            // keeps its precision for a 0.5 mm sphere at 1 m (b² − |oc|² + r² loses it in f32).
            let (_, _, omc) = sphere_cone(light, radius, p)?;
            let (oc, d) = (p.as_dvec3() - c.as_dvec3(), dir.as_dvec3());
            let b = oc.dot(d);
            let r = f64::from(radius);
            let disc = r * r - (oc - d * b).length_squared();
            let t = -b - disc.max(0.0).sqrt();
            (disc >= 0.0 && t > 0.0)
                .then(|| (t as f32, (1.0 / (2.0 * std::f64::consts::PI * omc)) as f32))
        }
        AreaShape::Tube { length, radius } => {
            // The side of the cylinder: solve |(p + t dir − c)⊥n|² = r² for the nearest t > 0
            // whose point lies within the length; in f64, with the discriminant as
            // a·r² − |o⊥ × d⊥|² (Lagrange's identity: b² − a·(|o⊥|² − r²) without its
            // cancellation, which lost a 1 mm tube at 1 m in f32).
            let (oc, d, n) = (p.as_dvec3() - c.as_dvec3(), dir.as_dvec3(), n.as_dvec3());
            let (o_p, d_p) = (oc - n * oc.dot(n), d - n * d.dot(n));
            let a = d_p.length_squared();
            let b = o_p.dot(d_p);
            let r = f64::from(radius);
            let disc = a * r * r - o_p.cross(d_p).length_squared();
            if a == 0.0 || disc < 0.0 {
                return None;
            }
            let s = disc.sqrt();
            [(-b - s) / a, (-b + s) / a].into_iter().find_map(|t| {
                let q = oc + d * t;
                let along = q.dot(n);
                if t <= 0.0 || along.abs() > 0.5 * f64::from(length) {
                    return None;
                }
                area_pdf(t as f32, ((q - n * along) / r).as_vec3())
            })
        }
    }
}

/// Whether the emitter point at `dist` along `dir` from `p` is the first surface of the tube
/// that the ray meets (a tube's side hides its far half from outside; through an open end the
/// inner face is seen). The nearest hit must be that point, within a thousandth of the radius
/// (plus f32's rounding of the point): a tolerance relative to the distance (0.1 % of it)
/// cannot tell the halves of a 1 mm tube apart at 1 m, and kept samples of the far half near
/// the silhouette of a 5 mm one at 1.5 m.
fn tube_point_seen(light: &AreaLight, p: Vec3, dir: Vec3, dist: f32) -> bool {
    let AreaShape::Tube { radius, .. } = light.shape else {
        return true;
    };
    let tolerance = 1e-3 * radius + 1e-6 * dist;
    intersect(light, p, dir).is_some_and(|(t, _)| t >= dist - tolerance)
}

/// The light's reflected radiance towards `v` at `p` on surface `s`: `samples` directions from
/// the emitter and `samples` from each of the BRDF's lobes, combined by the balance heuristic
/// (at the default 1024 a Lambert plane is within 0.5 % of the exact irradiance: the tests). `blocked(p, dir,
/// dist)` tells whether a shadow caster lies between `p` and the emitter point.
pub(super) fn area_light_radiance(
    light: &AreaLight,
    s: &Surface,
    (p, v): (Vec3, Vec3),
    key: [u64; 3],
    samples: u32,
    blocked: &dyn Fn(Vec3, f32) -> bool,
) -> Vec3 {
    let (n, x) = (s.n, s.x);
    let y = n.cross(x);
    let local = |d: Vec3| Vec3::new(d.dot(x), d.dot(y), d.dot(n));
    let v_local = local(v);
    let lobes: Vec<Lobe> = std::iter::once(Lobe::Cosine)
        .chain(
            sampling_lobes(&s.model)
                .into_iter()
                .filter(|l| *l != Lobe::Cosine),
        )
        .collect();
    // One strategy more than the lobes: the emitter itself (index `lobes.len()`).
    let count = lobes.len() + 1;
    let per = samples.max(1);
    let radiance = light.radiance() * range_window((light.position - p).length(), light.range);
    if radiance == Vec3::ZERO {
        return Vec3::ZERO;
    }
    let mut sum = DVec3::ZERO;
    for k in 0..count {
        let pattern = hash(&[key[0], key[1], key[2], 0xa4ea_0000 + k as u64]) as u32;
        for j in 0..per {
            let u = cmj(j, per, pattern);
            // The direction, its distance to the emitter and the emitter's density for it.
            let hit = match lobes.get(k) {
                None => sample(light, p, u).map(|t| (t.dir, t.dist, t.pdf)),
                Some(lobe) => lobe
                    .sample(v_local, u.x, u.y)
                    .try_normalize()
                    .map(|l| x * l.x + y * l.y + n * l.z)
                    .and_then(|dir| intersect(light, p, dir).map(|(t, pdf)| (dir, t, pdf))),
            };
            let Some((dir, dist, light_pdf)) = hit else {
                continue;
            };
            let l_local = local(dir);
            if l_local.z <= 0.0 || blocked(dir, dist) {
                continue;
            }
            let f = crate::brdf::radiance(&s.model, n, dir, v, x, s.y, radiance);
            let pdf_sum: f32 =
                light_pdf + lobes.iter().map(|lb| lb.pdf(v_local, l_local)).sum::<f32>();
            let denom = pdf_sum * per as f32;
            if f != Vec3::ZERO && denom > 0.0 && denom.is_finite() {
                sum += (f / denom).as_dvec3();
            }
        }
    }
    sum.as_vec3()
}
