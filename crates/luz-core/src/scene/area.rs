//! Area lights (issue 36): rectangles, disks, spheres and tubes that emit a uniform radiance.
//!
//! They are written in the scene's `lights` array beside the punctual lights but kept in their
//! own list ([`super::Scene::area_lights`]): every punctual-light path of the renderer (shadow
//! maps, clustered culling, the GPU light buffer) stays as it is, and area lights are added to
//! each one as it learns them.

use glam::Vec3;

use super::Shadow;

/// The emitting shape of an area light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AreaShape {
    /// A rectangle centred on the light's position, facing `direction`. `height` runs along `up`
    /// (made perpendicular to `direction`), `width` along the third axis
    /// ([`AreaLight::rect_axes`]). `up` is the unit vector as written, not yet made perpendicular.
    Rect { up: Vec3, width: f32, height: f32 },
    /// A disk centred on the position, facing `direction`.
    Disk { radius: f32 },
    /// A sphere centred on the position; it emits from its whole surface.
    Sphere { radius: f32 },
    /// A capsule-less cylinder of `length` along `direction` (the axis), centred on the position,
    /// of `radius`; it emits from its side (representative point treats it as a line of that
    /// radius with spherical caps; LTC as its facing ribbon with flat end disks).
    Tube { length: f32, radius: f32 },
}

impl AreaShape {
    /// The scene format's `type`, and whether the shape is flat (rect and disk emit from one
    /// side, or both with `two_sided`; spheres and tubes all round).
    fn info(&self) -> (&'static str, bool) {
        match self {
            AreaShape::Rect { .. } => ("rect", true),
            AreaShape::Disk { .. } => ("disk", true),
            AreaShape::Sphere { .. } => ("sphere", false),
            AreaShape::Tube { .. } => ("tube", false),
        }
    }

    /// The scene format's `type`.
    pub fn name(&self) -> &'static str {
        self.info().0
    }

    /// Rect and disk emit from one side (or both with `two_sided`); spheres and tubes all round.
    pub fn is_flat(&self) -> bool {
        self.info().1
    }
}

/// The `type` names of the area lights, in the scene format.
pub const AREA_LIGHT_TYPES: [&str; 4] = ["rect", "disk", "sphere", "tube"];

/// How the GPU shades an area light.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum AreaMethod {
    /// Linearly transformed cosines (Heitz et al. 2016).
    Ltc,
    /// Karis 2013's representative point, with its normalisation.
    RepresentativePoint,
    /// `samples` stratified samples of the emitter.
    Sampled { samples: u32 },
}

/// Most samples of the `sampled` method.
pub const MAX_AREA_SAMPLES: u32 = 1024;
/// The `sampled` method's default sample count.
pub const DEFAULT_AREA_SAMPLES: u32 = 16;

impl AreaMethod {
    /// The scene format's `method`.
    pub fn name(&self) -> &'static str {
        match self {
            AreaMethod::Ltc => "ltc",
            AreaMethod::RepresentativePoint => "representative_point",
            AreaMethod::Sampled { .. } => "sampled",
        }
    }
}

/// An area light: every point of its shape emits radiance `color · intensity` (W·m⁻²·sr⁻¹) into
/// the hemisphere around its normal (the emitting side of a rect or disk is the side
/// `direction` points to; `two_sided` emits from both).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AreaLight {
    pub shape: AreaShape,
    /// Centre of the shape.
    pub position: Vec3,
    /// Unit vector: the emitting side's normal for rect and disk, the axis for a tube; (0, −1, 0)
    /// for spheres.
    pub direction: Vec3,
    /// Linear RGB (each channel ≥ 0) and the radiance L (≥ 0): every point emits color ·
    /// intensity, and a surface under a large one-sided rect facing it receives π·L.
    pub color: Vec3,
    pub intensity: f32,
    pub shadow: Option<Shadow>,
    /// `two_sided` (rect and disk): emit from both sides. `visible`: the camera sees the emitter
    /// and it blocks shadow rays; false: rays pass through it.
    pub two_sided: bool,
    pub visible: bool,
    pub method: AreaMethod,
    /// Beyond this distance (m) from the shape's centre the light is cut off, with the same
    /// window as point lights ([`super::range_window`]); `None`: infinite.
    pub range: Option<f32>,
}

impl AreaLight {
    /// The radiance each point emits, per channel.
    pub fn radiance(&self) -> Vec3 {
        self.color * self.intensity
    }

    /// A rect's half-extent vectors (ex along the width, ey along the height): `ey` is `up` made
    /// perpendicular to `direction`, `ex = ey × direction`, so (ex, ey, direction) is a
    /// right-handed frame. `None` for other shapes.
    pub fn rect_axes(&self) -> Option<(Vec3, Vec3)> {
        let AreaShape::Rect { up, width, height } = self.shape else {
            return None;
        };
        let n = self.direction;
        let y = (up - n * up.dot(n)).normalize();
        let x = y.cross(n);
        Some((x * (0.5 * width), y * (0.5 * height)))
    }

    /// The emitting area in m² (one side for rect and disk).
    pub fn area(&self) -> f32 {
        use std::f32::consts::PI;
        match self.shape {
            AreaShape::Rect { width, height, .. } => width * height,
            AreaShape::Disk { radius } => PI * radius * radius,
            AreaShape::Sphere { radius } => 4.0 * PI * radius * radius,
            AreaShape::Tube { length, radius } => 2.0 * PI * radius * length,
        }
    }

    /// The radius of the sphere around `position` that holds the whole shape (for culling and
    /// soft-shadow sizes).
    pub fn bounding_radius(&self) -> f32 {
        match self.shape {
            AreaShape::Rect { width, height, .. } => 0.5 * (width * width + height * height).sqrt(),
            AreaShape::Disk { radius } | AreaShape::Sphere { radius } => radius,
            AreaShape::Tube { length, radius } => 0.5 * length + radius,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(direction: Vec3, up: Vec3) -> AreaLight {
        AreaLight {
            shape: AreaShape::Rect {
                up,
                width: 2.0,
                height: 4.0,
            },
            position: Vec3::ZERO,
            direction,
            color: Vec3::ONE,
            intensity: 1.0,
            two_sided: false,
            visible: true,
            method: AreaMethod::Ltc,
            range: None,
            shadow: None,
        }
    }

    /// `up` is made perpendicular to `direction`; the height runs along it, the width across.
    #[test]
    fn rect_axes_follow_up_and_size() {
        let l = rect(Vec3::NEG_Y, Vec3::new(0.0, 0.6, 0.8));
        let (x, y) = l.rect_axes().unwrap();
        assert!((y - Vec3::new(0.0, 0.0, 2.0)).length() < 1e-6, "{y}");
        assert!((x.length() - 1.0).abs() < 1e-6, "{x}");
        assert!(x.dot(Vec3::NEG_Y).abs() < 1e-6 && x.dot(y).abs() < 1e-6);
        // Right-handed: x × y along the emitting normal.
        assert!(x.cross(y).normalize().dot(l.direction) > 0.999);
        assert_eq!(l.area(), 8.0);
        assert!((l.bounding_radius() - 5f32.sqrt()).abs() < 1e-6);
    }
}
