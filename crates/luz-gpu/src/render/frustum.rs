//! Frustum culling per object: a draw whose bounding sphere lies wholly outside the camera's view
//! volume is not recorded. Conservative (a sphere that touches the volume is drawn), so the image
//! is the same as drawing everything.

use glam::{Mat4, Vec3, Vec4};

/// The six planes (xyz: inward unit normal, w: offset) of the view volume of `view_proj`, for
/// Vulkan's clip space: −w ≤ x ≤ w, −w ≤ y ≤ w, 0 ≤ z ≤ w (Gribb and Hartmann's extraction).
pub fn planes(view_proj: Mat4) -> [Vec4; 6] {
    let r = [
        view_proj.row(0),
        view_proj.row(1),
        view_proj.row(2),
        view_proj.row(3),
    ];
    [
        r[3] + r[0],
        r[3] - r[0],
        r[3] + r[1],
        r[3] - r[1],
        r[2],
        r[3] - r[2],
    ]
    .map(|p| {
        let len = p.truncate().length();
        if len > 0.0 && len.is_finite() {
            p / len
        } else {
            // A degenerate plane culls nothing.
            Vec4::new(0.0, 0.0, 0.0, 1.0)
        }
    })
}

/// An object-space bounding sphere (centre of the box, half its diagonal) of `lo..hi`.
pub fn sphere((lo, hi): (Vec3, Vec3)) -> (Vec3, f32) {
    ((lo + hi) * 0.5, (hi - lo).length() * 0.5)
}

/// Whether the object-space sphere `(centre, radius)` under `model` may be seen: false only when
/// it lies wholly outside one plane. Non-finite data is always seen.
pub fn visible(planes: &[Vec4; 6], model: Mat4, (centre, radius): (Vec3, f32)) -> bool {
    let c = model.transform_point3(centre);
    let scale = max_scale(model);
    // A little margin for rounding: culling must never drop a covered pixel.
    let r = radius * scale * (1.0 + 1e-4) + 1e-6;
    if !(c.is_finite() && r.is_finite()) {
        return true;
    }
    planes.iter().all(|p| p.truncate().dot(c) + p.w >= -r)
}

/// The largest length of `model`'s axes: how much it may stretch an object-space distance.
pub fn max_scale(model: Mat4) -> f32 {
    model
        .x_axis
        .truncate()
        .length()
        .max(model.y_axis.truncate().length())
        .max(model.z_axis.truncate().length())
}

/// Whether the world-space sphere `(centre, radius)` may meet the volume of `planes` (as
/// [`visible`], without a model matrix).
pub fn sphere_visible(planes: &[Vec4; 6], centre: Vec3, radius: f32) -> bool {
    visible(planes, Mat4::IDENTITY, (centre, radius))
}

/// A world-space bounding sphere.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
}

/// The eight corners of object-space bounds under a model matrix (the scene's own, shared).
pub use crate::scene::box_corners;

/// An object-space plane (point, unit normal) under `model`, in world space.
pub fn world_plane(model: Mat4, point: Vec3, normal: Vec3) -> (Vec3, Vec3) {
    let n = model.inverse().transpose().transform_vector3(normal);
    (model.transform_point3(point), n.normalize_or(normal))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Mat4 {
        let proj = Mat4::perspective_rh(60f32.to_radians(), 16.0 / 9.0, 0.1, 50.0);
        proj * Mat4::look_at_rh(Vec3::new(0.0, 1.0, 5.0), Vec3::ZERO, Vec3::Y)
    }

    /// Spheres in front are seen, behind the camera, beyond the far plane or far to a side are
    /// not; a sphere that only pokes into the view is seen; scale counts.
    #[test]
    fn culls_only_what_is_outside() {
        let p = planes(camera());
        let unit = (Vec3::ZERO, 1.0);
        let at = |x: f32, y: f32, z: f32| Mat4::from_translation(Vec3::new(x, y, z));
        assert!(visible(&p, at(0.0, 0.0, 0.0), unit));
        assert!(!visible(&p, at(0.0, 1.0, 9.0), unit), "behind the camera");
        assert!(!visible(&p, at(0.0, 0.0, -60.0), unit), "beyond far");
        assert!(!visible(&p, at(40.0, 0.0, 0.0), unit), "far right");
        assert!(visible(&p, at(0.0, 1.0, 5.5), unit), "around the camera");
        assert!(
            visible(
                &p,
                at(40.0, 0.0, 0.0) * Mat4::from_scale(Vec3::splat(40.0)),
                unit
            ),
            "scaled into view"
        );
        assert!(visible(&p, Mat4::from_translation(Vec3::NAN), unit));
        // Every point a sampled sphere covers on screen belongs to a visible sphere.
        let vp = camera();
        let mut culled = 0;
        for k in 0..2000 {
            let a = k as f32 * 0.37;
            let c = Vec3::new(
                a.sin() * 30.0,
                (a * 1.3).cos() * 12.0,
                (a * 0.7).sin() * 40.0 - 10.0,
            );
            let r = 0.5 + (k % 7) as f32;
            let m = at(c.x, c.y, c.z);
            if visible(&p, m, (Vec3::ZERO, r)) {
                continue;
            }
            culled += 1;
            for s in 0..64 {
                let t = s as f32 * 2.399;
                let z = 1.0 - 2.0 * (s as f32 + 0.5) / 64.0;
                let d = Vec3::new(
                    (1.0 - z * z).sqrt() * t.cos(),
                    z,
                    (1.0 - z * z).sqrt() * t.sin(),
                );
                let q = vp * (c + d * r).extend(1.0);
                let inside = q.x.abs() <= q.w && q.y.abs() <= q.w && q.z >= 0.0 && q.z <= q.w;
                assert!(
                    !inside,
                    "a culled sphere at {c} (r {r}) has a point in view"
                );
            }
        }
        assert!(culled > 500, "only {culled} of 2000 spheres culled");
    }
}
