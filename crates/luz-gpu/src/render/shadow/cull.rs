//! Which flat casters the maps can leave out (a plane hides a point from a light only when the
//! two lie strictly on opposite sides of it), and which receivers no caster can darken (their
//! pipelines then leave that light's lookup out).

use glam::{Mat4, Vec3};

use super::fit::Sphere;
pub use crate::render::frustum::{box_corners, world_plane};
use crate::scene::{Light, LightKind};

/// Something the maps are looked up for: its world bounding sphere (the maps' fit) and the
/// corners of its world bounding box.
#[derive(Debug, Clone, Copy)]
pub struct Receiver {
    pub sphere: Sphere,
    pub corners: [Vec3; 8],
    /// A bounding sphere as tight as the mesh's box allows (where shadows can fall).
    pub tight: Sphere,
    /// Convex or flat (a closed sphere, box, cone or cylinder, a plane): it cannot shadow
    /// itself beyond its terminator, where n·l ≤ 0 leaves it unlit anyway.
    pub convex: bool,
}

/// How far a light's looked-up shadow can reach past a caster's outline on a receiver, in the
/// light's map texels: the filter's reach plus the normal and depth offsets the lookup applies
/// (shadows.glsl: shadow_lookup), and one texel to spare.
pub fn reach_texels(s: &crate::scene::Shadow) -> f32 {
    let widen = match s.method {
        crate::scene::ShadowMethod::Pcf => (0.5 * (s.pcf_kernel as f32 - 1.0)).max(1.0),
        _ => 1.0,
    };
    super::fit::margin_texels(s) + (s.normal_bias.abs() + s.bias.abs()) * widen + 1.0
}

/// An axis-aligned world box (min, max corners).
pub type Aabb = (Vec3, Vec3);

/// The world box of a receiver's box corners.
pub fn receiver_box(r: &Receiver) -> Aabb {
    r.corners
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &q| {
            (lo.min(q), hi.max(q))
        })
}

/// The part of receiver `r`'s box that a caster may darken through `light`'s maps (`None`:
/// nothing). A flat caster (`plane`) reaches the whole box when some corner lies on the far side
/// of its plane from the light, or within the margin of it. Any other caster reaches where its
/// bounding sphere, grown by the margin, sweeps away from the light (a cylinder for a
/// directional light, a widening cone for a point or spot light) inside the box. The margin
/// (world units) is `texel` × the light's `reach` in texels ([`reach_texels`]), times the
/// distance to the light's far side of the receiver for perspective maps (`texel` per metre).
pub fn shadow_box(
    (caster, plane): (Sphere, Option<(Vec3, Vec3)>),
    r: &Receiver,
    light: &Light,
    (texel, perspective): (f32, bool),
    reach: f32,
) -> Option<Aabb> {
    let bounds = receiver_box(r);
    // Perspective texels grow with the distance from the light: at the receiver's far side for
    // a flat caster, along the cone below.
    let far = (light.position - r.tight.center).length() + r.tight.radius;
    let margin = texel * reach * if perspective { far } else { 1.0 };
    if let Some((point, normal)) = plane {
        let side = match light.kind {
            LightKind::Directional => -normal.dot(light.direction),
            _ => normal.dot(light.position - point),
        };
        let reaches = side.abs() > 1e-6 * (1.0 + point.abs().max_element())
            && r.corners
                .iter()
                .any(|q| side.signum() * normal.dot(*q - point) < margin);
        return reaches.then_some(bounds);
    }
    // First whether the caster comes near the receiver's shadow volume at all: the receiver's
    // sphere swept towards a directional light (exactly), or the capsule from it to a point or
    // spot light (which holds the volume), grown by the caster's sphere and the margin.
    let v = caster.center - r.tight.center;
    let towards = match light.kind {
        LightKind::Directional => -light.direction,
        _ => light.position - r.tight.center,
    };
    let t = match light.kind {
        LightKind::Directional => v.dot(towards).max(0.0),
        _ => (v.dot(towards) / towards.length_squared().max(f32::MIN_POSITIVE)).clamp(0.0, 1.0),
    };
    if (v - t * towards).length() > r.tight.radius + caster.radius + margin {
        return None;
    }
    // Balls of centre o + u·e and radius ρ0 + u·ρ1 for u in [u_min, ∞): the caster's shadow,
    // grown by the margin (for a perspective map, texel × reach × the distance from the light,
    // at most u·(|e| + caster radius) at the ball of parameter u).
    let (o, e, rho, u_min) = match light.kind {
        LightKind::Directional => (
            caster.center,
            light.direction,
            (caster.radius + margin, 0.0),
            0.0,
        ),
        _ => {
            let e = caster.center - light.position;
            let grow = if perspective {
                texel * reach * (e.length() + caster.radius)
            } else {
                margin
            };
            if e.length() <= caster.radius + grow {
                return Some(bounds);
            }
            (light.position, e, (0.0, caster.radius + grow), 1.0)
        }
    };
    // Per axis, the u where the ball overlaps the box's slab: o + u·e ± (ρ0 + u·ρ1) within
    // [lo, hi], two half-lines a·u ≤ b.
    let (mut u0, mut u1): (f32, f32) = (u_min, f32::INFINITY);
    for i in 0..3 {
        for (a, b) in [
            (e[i] - rho.1, bounds.1[i] - o[i] + rho.0),
            (-e[i] - rho.1, o[i] - bounds.0[i] + rho.0),
        ] {
            if a > 0.0 {
                u1 = u1.min(b / a);
            } else if a < 0.0 {
                u0 = u0.max(b / a);
            } else if b < 0.0 {
                return None;
            }
        }
    }
    if u0.is_nan() || u1.is_nan() || u0 > u1 {
        return None;
    }
    if !u1.is_finite() {
        return Some(bounds);
    }
    let ball = |u: f32| (o + u * e, rho.0 + u * rho.1);
    let ((c0, r0), (c1, r1)) = (ball(u0), ball(u1));
    let lo = (c0 - Vec3::splat(r0))
        .min(c1 - Vec3::splat(r1))
        .max(bounds.0);
    let hi = (c0 + Vec3::splat(r0))
        .max(c1 + Vec3::splat(r1))
        .min(bounds.1);
    (lo.cmple(hi).all()).then_some((lo, hi))
}

/// Whether a flat caster (world plane `(point, normal)`) can shadow none of `receivers` (but the
/// one at index `own`) under `light`: a plane hides a point from the light only when the two lie
/// strictly on opposite sides of it, so a plane with every receiver's bounding box on the
/// light's side (or the light in the plane) is left out of the maps. This is what keeps a floor
/// under the objects out of every cascade and cube face, exactly.
pub fn hides_nothing(
    (point, normal): (Vec3, Vec3),
    light: &Light,
    receivers: &[Receiver],
    own: Option<usize>,
) -> bool {
    let side = match light.kind {
        LightKind::Directional => -normal.dot(light.direction),
        _ => normal.dot(light.position - point),
    };
    let scale = 1.0 + point.abs().max_element();
    if side.abs() <= 1e-6 * scale {
        return true;
    }
    let sign = side.signum();
    receivers.iter().enumerate().all(|(k, r)| {
        let tolerance = 1e-5 * (scale + r.sphere.radius);
        Some(k) == own
            || r.corners
                .iter()
                .all(|q| sign * normal.dot(*q - point) >= -tolerance)
    })
}

/// Receiver × caster pairs tested per light and frame at most; beyond, every receiver is
/// taken as reached (whole) by every light.
const RECEIVER_PAIRS: usize = 250_000;

/// Where a receiver may be darkened: bit k of `lights` when map k may darken it, and the
/// part of its world box where (`None` with no bit set).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Reached {
    pub lights: u32,
    pub area: Option<Aabb>,
}

/// Adds what `light`'s map `k` (fit `fit`) may darken of each receiver to `reached`: the parts
/// of its box a caster of `drawn` reaches ([`shadow_box`]). A convex receiver is not its
/// own caster: beyond its terminator n·l ≤ 0 leaves it unlit without a lookup; any other is
/// reached whole by itself.
pub(super) fn receiving(
    reached: &mut [Reached],
    k: usize,
    (light, shadow, fit): (&Light, &crate::scene::Shadow, &super::fit::LightFit),
    view: Mat4,
    (drawn, receivers): (&[&super::Caster], &[Receiver]),
) {
    let perspective = fit.layers.first().is_some_and(|l| l.perspective);
    let reach = reach_texels(shadow);
    let all = k >= 32 || receivers.len().saturating_mul(drawn.len()) > RECEIVER_PAIRS;
    for (ri, (r, out)) in receivers.iter().zip(reached.iter_mut()).enumerate() {
        // The largest texel of the layers the receiver is looked up in: the cascades its view
        // depth range overlaps (the camera's near plane starts the first), every cube face.
        let depth = -view.transform_point3(r.sphere.center).z;
        let (zmin, zmax) = (depth - r.sphere.radius, depth + r.sphere.radius);
        let texel = fit
            .layers
            .iter()
            .enumerate()
            .filter(|&(c, _)| {
                let split = |i: usize| fit.splits.get(i).copied();
                let start = c
                    .checked_sub(1)
                    .and_then(split)
                    .unwrap_or(f32::NEG_INFINITY);
                let end = if c + 1 == fit.layers.len() {
                    f32::INFINITY
                } else {
                    split(c).unwrap_or(f32::INFINITY)
                };
                perspective || (zmax >= start && zmin <= end)
            })
            .map(|(_, l)| l.texel)
            .fold(0.0f32, f32::max);
        let area = if all {
            Some(receiver_box(r))
        } else {
            drawn.iter().fold(None, |acc: Option<Aabb>, c| {
                let b = if c.receiver == Some(ri) {
                    (!r.convex).then(|| receiver_box(r))
                } else {
                    shadow_box((c.tight, c.plane), r, light, (texel, perspective), reach)
                };
                union(acc, b)
            })
        };
        if area.is_some() {
            out.lights |= 1u32.checked_shl(k as u32).unwrap_or(0);
            out.area = union(out.area, area);
        }
    }
}

fn union(a: Option<Aabb>, b: Option<Aabb>) -> Option<Aabb> {
    match (a, b) {
        (Some(a), Some(b)) => Some((a.0.min(b.0), a.1.max(b.1))),
        (a, None) => a,
        (None, b) => b,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn light(kind: LightKind, position: Vec3, direction: Vec3) -> Light {
        super::super::fit::tests::light(kind, position, direction, 30.0)
    }

    fn ball(center: Vec3, radius: f32) -> Receiver {
        Receiver {
            sphere: Sphere { center, radius },
            corners: box_corners(
                Mat4::from_translation(center),
                (Vec3::splat(-radius), Vec3::splat(radius)),
            ),
            tight: Sphere { center, radius },
            convex: true,
        }
    }

    /// The default scene's case: a floor (y = 0) under spheres resting on it, lit from above by
    /// a sun and a point light: the floor hides nothing. A sphere sinking below the floor, or a
    /// light below it, makes the floor a caster again; a light in the floor's plane sees nothing
    /// through it. The floor's own bounds (it receives too) never count.
    #[test]
    fn a_floor_under_the_objects_hides_nothing() {
        let floor = (Vec3::ZERO, Vec3::Y);
        let sun = light(
            LightKind::Directional,
            Vec3::ZERO,
            Vec3::new(0.3, -1.0, 0.2).normalize(),
        );
        let lamp = light(LightKind::Point, Vec3::new(1.0, 3.0, 0.0), Vec3::NEG_Y);
        let floor_box = Receiver {
            sphere: Sphere {
                center: Vec3::ZERO,
                radius: 20.0,
            },
            corners: box_corners(
                Mat4::IDENTITY,
                (Vec3::new(-20.0, 0.0, -20.0), Vec3::new(20.0, 0.0, 20.0)),
            ),
            tight: Sphere {
                center: Vec3::ZERO,
                radius: 20.0,
            },
            convex: true,
        };
        let resting = [
            floor_box,
            ball(Vec3::new(-1.0, 0.6, 0.0), 0.6),
            ball(Vec3::new(1.0, 0.6, 0.0), 0.6),
        ];
        assert!(hides_nothing(floor, &sun, &resting, Some(0)));
        assert!(hides_nothing(floor, &lamp, &resting, Some(0)));
        // Without excluding itself, the floor's own box lies in its plane: still nothing hidden.
        assert!(hides_nothing(floor, &sun, &resting, None));
        let sunk = [floor_box, ball(Vec3::new(0.0, 0.5, 0.0), 0.6)];
        assert!(!hides_nothing(floor, &sun, &sunk, Some(0)));
        let below = light(LightKind::Spot, Vec3::new(0.0, -2.0, 0.0), Vec3::Y);
        assert!(!hides_nothing(floor, &below, &resting, Some(0)));
        let grazing = light(LightKind::Directional, Vec3::ZERO, Vec3::X);
        assert!(hides_nothing(floor, &grazing, &sunk, Some(0)));
        let in_plane = light(LightKind::Point, Vec3::new(5.0, 0.0, 0.0), Vec3::NEG_X);
        assert!(hides_nothing(floor, &in_plane, &sunk, Some(0)));
    }

    /// `shadow_box` never misses a shadow: for random receivers (boxes), casters (balls) and
    /// lights (directional, or a point outside the caster), every sample of the receiver box
    /// whose path to the light crosses the caster's ball lies in the box returned. It is not
    /// the trivial answer either: casters far off give `None`, and most answers are smaller
    /// than the receiver's box.
    #[test]
    fn shadow_boxes_hold_every_shadowed_point() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 40) as f32 / (1u64 << 24) as f32
        };
        let (mut none, mut smaller, mut shadowed_cases) = (0, 0, 0);
        for case in 0..400 {
            let v = |next: &mut dyn FnMut() -> f32, s: f32| {
                Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5) * s
            };
            let (lo, size) = (
                v(&mut next, 6.0),
                v(&mut next, 4.0).abs() + Vec3::splat(0.2),
            );
            let hi = lo + size;
            let r = Receiver {
                sphere: Sphere {
                    center: (lo + hi) * 0.5,
                    radius: size.length() * 0.5,
                },
                corners: box_corners(Mat4::IDENTITY, (lo, hi)),
                tight: Sphere {
                    center: (lo + hi) * 0.5,
                    radius: size.length() * 0.5,
                },
                convex: true,
            };
            let caster = Sphere {
                center: (lo + hi) * 0.5 + v(&mut next, 6.0),
                radius: 0.2 + next(),
            };
            let l = if case % 2 == 0 {
                light(
                    LightKind::Directional,
                    Vec3::ZERO,
                    v(&mut next, 2.0).normalize_or(Vec3::NEG_Y),
                )
            } else {
                let mut p = v(&mut next, 12.0);
                while (p - caster.center).length() < caster.radius * 1.5 {
                    p = v(&mut next, 12.0);
                }
                light(LightKind::Point, p, Vec3::NEG_Y)
            };
            let got = shadow_box((caster, None), &r, &l, (0.0, false), 0.0);
            let bounds = receiver_box(&r);
            let mut any = false;
            for k in 0..2000 {
                let t = Vec3::new(next(), next(), next());
                let p = lo + size * t;
                // The path from p towards the light, and whether it crosses the ball.
                let (dir, len) = match l.kind {
                    LightKind::Directional => (-l.direction, f32::INFINITY),
                    _ => ((l.position - p).normalize(), (l.position - p).length()),
                };
                let oc = caster.center - p;
                let along = oc.dot(dir).clamp(0.0, len);
                let crosses = (oc - along * dir).length() < caster.radius;
                if crosses {
                    any = true;
                    let (a, b) = got.unwrap_or_else(|| panic!("case {case}: {p} shadowed, no box"));
                    let eps = 1e-3 * (1.0 + p.abs().max_element());
                    assert!(
                        p.cmpge(a - Vec3::splat(eps)).all() && p.cmple(b + Vec3::splat(eps)).all(),
                        "case {case} sample {k}: {p} outside {a}..{b}"
                    );
                }
            }
            shadowed_cases += usize::from(any);
            none += usize::from(got.is_none());
            smaller += usize::from(got.is_some_and(|b| b != bounds));
        }
        assert!(shadowed_cases > 40, "{shadowed_cases} cases with a shadow");
        assert!(none > 100, "{none} cases without a box");
        assert!(smaller > 20, "{smaller} boxes smaller than the receiver's");
    }

    /// A plane under a scale, rotation and translation keeps a unit normal perpendicular to its
    /// transformed points, and box corners are the transformed corners.
    #[test]
    fn world_planes_and_corners_follow_the_model() {
        let model = Mat4::from_scale_rotation_translation(
            Vec3::new(2.0, 0.5, 3.0),
            glam::Quat::from_rotation_z(0.4),
            Vec3::new(1.0, 2.0, 3.0),
        );
        let (p, n) = world_plane(model, Vec3::ZERO, Vec3::Y);
        assert!((n.length() - 1.0).abs() < 1e-5);
        for q in [Vec3::X, Vec3::Z, Vec3::new(-2.0, 0.0, 5.0)] {
            let w = model.transform_point3(q);
            assert!(n.dot(w - p).abs() < 1e-4, "{q}: {}", n.dot(w - p));
        }
        let c = box_corners(model, (Vec3::ZERO, Vec3::ONE));
        assert_eq!(c[0], model.transform_point3(Vec3::ZERO));
        assert_eq!(c[7], model.transform_point3(Vec3::ONE));
    }
}
