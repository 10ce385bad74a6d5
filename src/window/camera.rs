//! The viewer's orbit camera: yaw and pitch about the scene camera's up axis around a target,
//! a distance, and panning of the target. Converts to and from [`crate::scene::Camera`].

use glam::Vec3;

use crate::scene::{Camera, Projection};

/// Pitch stays this far (degrees) from the poles, where yaw is undefined.
const MAX_PITCH_DEG: f32 = 89.0;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitCamera {
    pub target: Vec3,
    pub distance: f32,
    /// Degrees about `up`, measured from `e1` towards `e2` (see [`OrbitCamera::basis`]).
    pub yaw_deg: f32,
    /// Degrees above the plane perpendicular to `up`.
    pub pitch_deg: f32,
    pub up: Vec3,
    pub fov_y_deg: f32,
    pub near: f32,
    pub far: f32,
    /// Perspective, or orthographic with its half view height (which zoom and framing change,
    /// as the distance in perspective).
    pub projection: Projection,
}

impl OrbitCamera {
    /// The orbit that reproduces `camera` exactly (up to rounding).
    pub fn from_camera(camera: &Camera) -> Self {
        let up = camera.up.normalize();
        let (e1, e2) = Self::basis(up);
        let offset = camera.position - camera.target;
        let distance = offset.length().max(1e-4);
        let o = offset / distance;
        let pitch = o.dot(up).clamp(-1.0, 1.0).asin().to_degrees();
        let yaw = o.dot(e2).atan2(o.dot(e1)).to_degrees();
        Self {
            target: camera.target,
            distance,
            yaw_deg: yaw,
            pitch_deg: pitch.clamp(-MAX_PITCH_DEG, MAX_PITCH_DEG),
            up,
            fov_y_deg: camera.fov_y_deg,
            near: camera.near,
            far: camera.far,
            projection: camera.projection,
        }
    }

    /// Two unit vectors perpendicular to `up` and to each other (right-handed with `up`).
    fn basis(up: Vec3) -> (Vec3, Vec3) {
        let helper = if up.x.abs() < 0.9 { Vec3::X } else { Vec3::Z };
        let e1 = (helper - up * helper.dot(up)).normalize();
        let e2 = e1.cross(up);
        (e1, e2)
    }

    pub fn position(&self) -> Vec3 {
        let (e1, e2) = Self::basis(self.up);
        let (sy, cy) = self.yaw_deg.to_radians().sin_cos();
        let (sp, cp) = self.pitch_deg.to_radians().sin_cos();
        self.target + self.distance * (cp * cy * e1 + sp * self.up + cp * sy * e2)
    }

    pub fn to_camera(&self) -> Camera {
        Camera {
            position: self.position(),
            target: self.target,
            up: self.up,
            fov_y_deg: self.fov_y_deg,
            near: self.near,
            far: self.far,
            projection: self.projection,
        }
    }

    /// Rotates by `dx`, `dy` degrees (yaw, pitch); pitch stops short of the poles.
    pub fn orbit(&mut self, dx_deg: f32, dy_deg: f32) {
        self.yaw_deg = (self.yaw_deg + dx_deg).rem_euclid(360.0);
        self.pitch_deg = (self.pitch_deg + dy_deg).clamp(-MAX_PITCH_DEG, MAX_PITCH_DEG);
    }

    /// Moves the target in the view plane by fractions of the view height at the target's depth
    /// (a drag of the whole window height moves the scene by one view height).
    pub fn pan(&mut self, dx: f32, dy: f32) {
        let forward = (self.target - self.position()).normalize();
        let right = forward.cross(self.up).normalize();
        let up = right.cross(forward);
        let view_height = 2.0 * self.to_camera().half_extent(self.distance, 1.0).1;
        self.target += (-dx * right + dy * up) * view_height;
    }

    /// Multiplies the distance (orthographic: the half view height) by 0.9^steps (positive steps
    /// zoom in).
    pub fn zoom(&mut self, steps: f32) {
        if let Projection::Orthographic { half_height } = &mut self.projection {
            *half_height = (*half_height * 0.9f32.powf(steps)).clamp(1e-6, 1e9);
            return;
        }
        self.distance = (self.distance * 0.9f32.powf(steps)).clamp(1e-3, 1e6);
        self.far = self.far.max(self.distance * 4.0);
    }

    /// Looks at the centre of `bounds` from the current direction, at the distance where the
    /// bounding sphere fills the vertical field of view (with a 10 % margin; orthographic: the
    /// half view height is the radius plus 10 %, the distance as in perspective).
    pub fn frame(&mut self, bounds: (Vec3, Vec3)) {
        let (lo, hi) = bounds;
        let centre = (lo + hi) * 0.5;
        let radius = ((hi - lo).length() * 0.5).max(1e-3);
        let half = (self.fov_y_deg.to_radians() * 0.5).max(1e-3);
        self.target = centre;
        self.distance = 1.1 * radius / half.sin();
        if let Projection::Orthographic { half_height } = &mut self.projection {
            *half_height = 1.1 * radius;
        }
        self.far = self.far.max(self.distance + 2.0 * radius);
        self.near = self
            .near
            .min((self.distance - radius).max(self.distance * 1e-3));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera {
            position: Vec3::new(3.0, 2.0, 5.0),
            target: Vec3::new(0.0, 0.5, 0.0),
            up: Vec3::Y,
            fov_y_deg: 45.0,
            near: 0.1,
            far: 100.0,
            projection: Projection::Perspective,
        }
    }

    #[test]
    fn round_trips_a_scene_camera() {
        let c = camera();
        let o = OrbitCamera::from_camera(&c);
        let back = o.to_camera();
        assert!((back.position - c.position).length() < 1e-5, "{back:?}");
        assert_eq!(back.target, c.target);
        // A z-up camera too.
        let z = Camera {
            up: Vec3::Z,
            position: Vec3::new(1.0, -4.0, 2.0),
            ..c
        };
        let back = OrbitCamera::from_camera(&z).to_camera();
        assert!((back.position - z.position).length() < 1e-5, "{back:?}");
    }

    #[test]
    fn orbit_keeps_distance_and_full_turn_returns() {
        let mut o = OrbitCamera::from_camera(&camera());
        let start = o.position();
        let d = o.distance;
        o.orbit(90.0, 0.0);
        assert!(((o.position() - o.target).length() - d).abs() < 1e-4);
        assert!((o.position() - start).length() > 1.0);
        o.orbit(270.0, 0.0);
        assert!((o.position() - start).length() < 1e-4);
        o.orbit(0.0, 500.0);
        assert_eq!(o.pitch_deg, MAX_PITCH_DEG);
        assert!(o.position().is_finite());
    }

    #[test]
    fn pan_moves_target_sideways_and_zoom_scales_distance() {
        let mut o = OrbitCamera::from_camera(&camera());
        let before = o;
        o.pan(0.5, 0.0);
        let moved = o.target - before.target;
        let forward = (before.target - before.position()).normalize();
        assert!(
            moved.dot(forward).abs() < 1e-5,
            "pan stays in the view plane"
        );
        assert!(moved.length() > 0.1);
        o.zoom(1.0);
        assert!((o.distance - before.distance * 0.9).abs() < 1e-5);
    }

    #[test]
    fn frame_all_sees_the_whole_box() {
        let mut o = OrbitCamera::from_camera(&camera());
        let bounds = (Vec3::splat(-10.0), Vec3::splat(10.0));
        o.frame(bounds);
        let r = Vec3::splat(20.0).length() * 0.5;
        let half = (o.fov_y_deg.to_radians() * 0.5).sin();
        assert!(o.distance * half >= r, "sphere inside the view cone");
        assert!(o.far >= o.distance + r);
        assert_eq!(o.target, Vec3::ZERO);
    }

    /// An orthographic orbit: zoom scales the half view height (not the distance), framing fits
    /// the bounding sphere into it, panning by a whole view height moves the target by 2 · half
    /// height, and the camera converts back orthographic.
    #[test]
    fn orthographic_zoom_frame_and_pan() {
        let c = Camera {
            projection: Projection::Orthographic { half_height: 2.0 },
            ..camera()
        };
        let mut o = OrbitCamera::from_camera(&c);
        let d = o.distance;
        o.zoom(2.0);
        assert_eq!(o.distance, d);
        let h = o.to_camera().ortho_half_height().unwrap();
        assert!((h - 2.0 * 0.81).abs() < 1e-5, "{h}");
        o.frame((Vec3::splat(-1.0), Vec3::splat(1.0)));
        let r = 3f32.sqrt();
        assert!((o.to_camera().ortho_half_height().unwrap() - 1.1 * r).abs() < 1e-5);
        let before = o.target;
        o.pan(0.0, 1.0);
        let moved = (o.target - before).length();
        assert!((moved - 2.2 * r).abs() < 1e-4, "{moved}");
    }
}
