//! Area lights (issue 36) as Mitsuba 3 shapes with an `area` emitter: rect → `rectangle`, disk →
//! `disk`, sphere → `sphere`, tube → `cylinder` (open, as luz's tube emits from its side).

use glam::{Mat4, Vec3};

use super::{matrix, v3, Writer};
use crate::scene::{AreaLight, AreaShape, Scene};

/// The shape's `to_world`: Mitsuba's unit rectangle and disk lie in z = 0 facing +z; `(a, b)`
/// are the half-extent (or radius) vectors with a × b along `direction`.
fn flat_to_world(l: &AreaLight, a: Vec3, b: Vec3) -> Mat4 {
    Mat4::from_cols(
        a.extend(0.0),
        b.extend(0.0),
        l.direction.extend(0.0),
        l.position.extend(1.0),
    )
}

impl Writer {
    /// The scene's area lights; `lights[i]` counts them after the punctual ones, as the scene
    /// encoder writes them.
    pub(super) fn area_lights(&mut self, scene: &Scene) {
        for (k, l) in scene.area_lights.iter().enumerate() {
            let i = scene.lights.len() + k;
            match l.shape {
                AreaShape::Rect { .. } => {
                    let (ex, ey) = l.rect_axes().unwrap_or_default();
                    self.flat_shape("rectangle", flat_to_world(l, ex, ey));
                }
                AreaShape::Disk { radius } => {
                    let a = if l.direction.x.abs() < 0.9 {
                        Vec3::X
                    } else {
                        Vec3::Y
                    };
                    let a = (a - l.direction * l.direction.dot(a)).normalize();
                    let b = l.direction.cross(a);
                    self.flat_shape("disk", flat_to_world(l, a * radius, b * radius));
                }
                AreaShape::Sphere { radius } => {
                    self.line(1, "<shape type=\"sphere\">");
                    self.line(
                        2,
                        &format!("<point name=\"center\" value=\"{}\"/>", v3(l.position)),
                    );
                    self.param(2, "float", "radius", radius);
                }
                AreaShape::Tube { length, radius } => {
                    let half = l.direction * (0.5 * length);
                    self.line(1, "<shape type=\"cylinder\">");
                    self.line(
                        2,
                        &format!("<point name=\"p0\" value=\"{}\"/>", v3(l.position - half)),
                    );
                    self.line(
                        2,
                        &format!("<point name=\"p1\" value=\"{}\"/>", v3(l.position + half)),
                    );
                    self.param(2, "float", "radius", radius);
                }
            }
            self.line(2, "<emitter type=\"area\">");
            self.line(
                3,
                &format!("<rgb name=\"radiance\" value=\"{}\"/>", v3(l.radiance())),
            );
            self.line(2, "</emitter>");
            self.line(1, "</shape>");
            if l.two_sided {
                self.note(format!(
                    "lights[{i}]: two_sided (Mitsuba's area emitter emits on one side)"
                ));
            }
            if !l.visible {
                self.note(format!(
                    "lights[{i}]: visible false (Mitsuba's emitters are seen and block light)"
                ));
            }
            if l.range.is_some() {
                self.note(format!(
                    "lights[{i}]: the range window (Mitsuba's lights reach everywhere)"
                ));
            }
            if l.shadow.is_none() {
                self.note(format!("lights[{i}]: no shadow (Mitsuba always shadows)"));
            }
        }
    }

    fn flat_shape(&mut self, kind: &str, to_world: Mat4) {
        self.line(1, &format!("<shape type=\"{kind}\">"));
        self.line(
            2,
            &format!(
                "<transform name=\"to_world\"><matrix value=\"{}\"/></transform>",
                matrix(to_world)
            ),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Mitsuba's rectangle spans [−1, 1]² in z = 0 facing +z: its corners and normal through the
    /// matrix are the rect's, and a × b faces the way the light travels.
    #[test]
    fn rect_to_world_maps_the_unit_square_onto_the_rect() {
        let text = r#"{"lights": [{"type": "rect", "position": [1, 2, 3], "direction": [0, -1, 0], "up": [0, 0, 1], "size": [4, 2]}]}"#;
        let scene = crate::scene::parse(text, std::path::Path::new("a.json")).unwrap();
        let l = &scene.area_lights[0];
        let (ex, ey) = l.rect_axes().unwrap();
        let m = flat_to_world(l, ex, ey);
        let corner = m.transform_point3(Vec3::new(1.0, 1.0, 0.0));
        assert!(
            (corner - Vec3::new(1.0 + 2.0, 2.0, 3.0 + 1.0)).length() < 1e-6,
            "{corner}"
        );
        let normal = m.transform_vector3(Vec3::Z);
        assert!((normal - Vec3::NEG_Y).length() < 1e-6);
        assert!(ex.cross(ey).dot(l.direction) > 0.0);
    }
}
