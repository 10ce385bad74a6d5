//! Which flat casters the maps can leave out: a plane hides a point from a light only when the
//! two lie strictly on opposite sides of it.

use glam::{Mat4, Vec3};

use super::fit::Sphere;
use crate::scene::{Light, LightKind};

/// Something the maps are looked up for: its world bounding sphere (the maps' fit) and the
/// corners of its world bounding box.
#[derive(Debug, Clone, Copy)]
pub struct Receiver {
    pub sphere: Sphere,
    pub corners: [Vec3; 8],
}

/// The eight corners of object-space bounds `(lo, hi)` under `model`.
pub fn box_corners(model: Mat4, (lo, hi): (Vec3, Vec3)) -> [Vec3; 8] {
    std::array::from_fn(|k| {
        let pick = |bit: usize, a: f32, b: f32| if k & bit == 0 { a } else { b };
        model.transform_point3(Vec3::new(
            pick(1, lo.x, hi.x),
            pick(2, lo.y, hi.y),
            pick(4, lo.z, hi.z),
        ))
    })
}

/// An object-space plane (point, unit normal) under `model`, in world space.
pub fn world_plane(model: Mat4, point: Vec3, normal: Vec3) -> (Vec3, Vec3) {
    let n = model.inverse().transpose().transform_vector3(normal);
    (model.transform_point3(point), n.normalize_or(normal))
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
