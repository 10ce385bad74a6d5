//! `EXT_lights_area` (the draft Babylon.js's loader reads; the older `KHR_lights_area` proposal
//! is closed): rect and disk lights at nodes. An untransformed light faces −Z; a rect's `size`
//! runs along local Y and `size · aspect` along X; a disk's `size` is its diameter; both scale by
//! the largest component of the node's world scale. `intensity` is the surface's luminance in
//! nits, which luz takes as its radiance L, as it takes KHR_lights_punctual's units as they are.

use glam::{Mat4, Vec3};
use serde_json::Value;

use super::{Builder, GltfError};
use crate::scene::{AreaLight, AreaMethod, AreaShape};

const EXT: &str = "EXT_lights_area";

/// The largest length of the upper 3×3's columns: the node's world scale as the extension
/// applies it (uniform and positive).
pub fn max_scale(m: Mat4) -> f32 {
    m.x_axis
        .truncate()
        .length()
        .max(m.y_axis.truncate().length())
        .max(m.z_axis.truncate().length())
}

impl Builder<'_> {
    /// The area light node `node` (index `i`) carries, if any, placed by `world`.
    pub(super) fn area_light(&mut self, node: &gltf::Node, world: Mat4) -> Result<(), GltfError> {
        let Some(reference) = node.extension_value(EXT) else {
            return Ok(());
        };
        let at_node = format!("nodes[{}].extensions.{EXT}.light", node.index());
        let lights = self
            .doc
            .extension_value(EXT)
            .and_then(|e| e.get("lights"))
            .and_then(Value::as_array);
        let count = lights.map_or(0, |l| l.len());
        let li = match reference.get("light").and_then(Value::as_u64) {
            Some(li) if (li as usize) < count => li as usize,
            Some(li) => {
                return Err(GltfError::at(
                    self.path,
                    at_node,
                    format!("light {li} does not exist (extensions.{EXT}.lights has {count})"),
                ))
            }
            None => return Err(GltfError::at(self.path, at_node, "expected a light index")),
        };
        let l = &lights.expect("counted above")[li];
        let at = |field: &str, reason: String| {
            GltfError::at(
                self.path,
                format!("extensions.{EXT}.lights[{li}].{field}"),
                reason,
            )
        };
        let number = |v: Option<&Value>, field: &str, default: f64| -> Result<f32, GltfError> {
            let x = match v {
                None => default,
                Some(v) => v
                    .as_f64()
                    .ok_or_else(|| at(field, format!("expected a number, got {v}")))?,
            };
            if x > 0.0 && x.is_finite() && x < f64::from(f32::MAX) {
                Ok(x as f32)
            } else {
                Err(at(field, format!("must be positive, got {x}")))
            }
        };
        let color = match l.get("color") {
            None => Vec3::ONE,
            Some(v) => {
                let c: Option<Vec<f32>> = v.as_array().filter(|a| a.len() == 3).map(|a| {
                    a.iter()
                        .filter_map(|x| x.as_f64().map(|x| x as f32))
                        .collect()
                });
                match c {
                    Some(c) if c.len() == 3 && c.iter().all(|x| x.is_finite() && *x >= 0.0) => {
                        Vec3::from_slice(&c)
                    }
                    _ => {
                        return Err(at(
                            "color",
                            format!("expected 3 finite numbers ≥ 0, got {v}"),
                        ))
                    }
                }
            }
        };
        let intensity = number(l.get("intensity"), "intensity", 1000.0)?;
        let scale = max_scale(world);
        let size = number(l.get("size"), "size", 1.0)? * scale;
        let shape = match l.get("type").and_then(Value::as_str) {
            Some("rect") => {
                let aspect = number(
                    l.get("rect").and_then(|r| r.get("aspect")),
                    "rect.aspect",
                    1.0,
                )?;
                let up = world
                    .transform_vector3(Vec3::Y)
                    .try_normalize()
                    .unwrap_or(Vec3::Y);
                AreaShape::Rect {
                    up,
                    width: size * aspect,
                    height: size,
                }
            }
            Some("disk") => AreaShape::Disk { radius: 0.5 * size },
            other => {
                return Err(at(
                    "type",
                    format!(
                        "expected \"rect\" or \"disk\", got {}",
                        other.map_or("nothing".into(), |s| format!("\"{s}\""))
                    ),
                ))
            }
        };
        let direction = world
            .transform_vector3(Vec3::NEG_Z)
            .try_normalize()
            .unwrap_or(Vec3::NEG_Z);
        if let AreaShape::Rect { up, .. } = shape {
            if up.cross(direction).length_squared() < 1e-8 {
                return Err(at(
                    "type",
                    format!(
                        "node {}'s transform makes the rect degenerate",
                        node.index()
                    ),
                ));
            }
        }
        self.out.area_lights.push(AreaLight {
            shape,
            position: world.transform_point3(Vec3::ZERO),
            direction,
            color,
            intensity,
            shadow: None,
            two_sided: false,
            visible: true,
            method: AreaMethod::Ltc,
            range: None,
        });
        Ok(())
    }
}
