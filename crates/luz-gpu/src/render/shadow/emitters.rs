//! Visible area-light emitters as shadow casters (issue 36, docs/area-lights.md#shadows): the
//! reference stops the shadow rays of every light with a `shadow` at a visible emitter, from
//! either side, except the light's own rays at its own emitter. The maps draw each visible
//! emitter into every layer of every shadowed light but its own, with the casters' depth-only
//! pipeline (`shadow.vert`: reversed depth, the light's slope bias, no culling, so both sides
//! block). The shapes are the camera's (`emitter.vert`): one static buffer holds a unit rect, a
//! 48-triangle disk fan, a 48 × 24 sphere and a 48-quad open tube side (round polygons scaled to
//! the round shape's area), and each draw's matrix places its light's shape: the layer's
//! view-projection times the emitter's model matrix, so a moved or resized emitter changes the
//! draw and its layers are drawn again ([`super::ShadowMaps::add_pass`]'s cache compares draws).
//! The buffer exists only for scenes with a visible area light and a shadowed light.

use std::sync::Arc;

use ash::vk;
use glam::{Mat4, Vec3};

use super::fit::Sphere;
use crate::render::gpu::Vertex;
use crate::render::MeshRef;
use crate::scene::{AreaLight, AreaShape, Scene};
use crate::vk::{Buffer, Context, VkError};

/// Segments of a round shape's polygon and stacks of a sphere's (`emitter.vert`'s
/// `EMITTER_SEGMENTS`, `EMITTER_STACKS`).
const SEGMENTS: u32 = 48;
const STACKS: u32 = 24;

/// An emitter drawn into one layer: the layer's view-projection times the emitter's model
/// matrix, and its unit shape's index range (first, count) in the buffer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct EmitterDraw {
    pub clip: Mat4,
    pub range: (u32, u32),
}

/// A visible emitter placed in the world.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Emitter {
    /// Index among the scene's area lights.
    pub area: usize,
    pub model: Mat4,
    pub range: (u32, u32),
    /// Holds the drawn polygon (the maps' fit and the receiver test count it as a caster).
    pub sphere: Sphere,
}

/// The unit shapes' vertices and indices, and each shape's index range (rect, disk, sphere,
/// tube). Unit frames: a rect's corners (±1, ±1, 0); a disk's fan of radius s in z = 0; a
/// sphere of radius s; a tube side of radius s from z = −1 to 1; s = √(θ / sin θ), θ = 2π / 48.
pub(super) fn unit_shapes() -> (Vec<Vertex>, Vec<u32>, [(u32, u32); 4]) {
    let seg = 2.0 * std::f32::consts::PI / SEGMENTS as f32;
    let s = (seg / seg.sin()).sqrt();
    let mut v: Vec<Vertex> = Vec::new();
    let mut idx: Vec<u32> = Vec::new();
    let vertex = |p: Vec3| Vertex {
        position: p.to_array(),
        ..Default::default()
    };
    let mut ranges = [(0, 0); 4];
    // Rect.
    let first = idx.len() as u32;
    let base = v.len() as u32;
    for (x, y) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
        v.push(vertex(Vec3::new(x, y, 0.0)));
    }
    idx.extend([0, 1, 2, 0, 2, 3].map(|i| base + i));
    ranges[0] = (first, idx.len() as u32 - first);
    // Disk: centre, then the rim.
    let first = idx.len() as u32;
    let base = v.len() as u32;
    v.push(vertex(Vec3::ZERO));
    for k in 0..SEGMENTS {
        let phi = seg * k as f32;
        v.push(vertex(Vec3::new(phi.cos() * s, phi.sin() * s, 0.0)));
    }
    for k in 0..SEGMENTS {
        idx.extend([base, base + 1 + k, base + 1 + (k + 1) % SEGMENTS]);
    }
    ranges[1] = (first, idx.len() as u32 - first);
    // Sphere: (STACKS + 1) rings of SEGMENTS + 1 vertices (pole to pole).
    let first = idx.len() as u32;
    let base = v.len() as u32;
    for i in 0..=STACKS {
        let theta = std::f32::consts::PI * i as f32 / STACKS as f32;
        for k in 0..=SEGMENTS {
            let phi = seg * k as f32;
            let m = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            v.push(vertex(m * s));
        }
    }
    let ring = SEGMENTS + 1;
    for i in 0..STACKS {
        for k in 0..SEGMENTS {
            let a = base + i * ring + k;
            idx.extend([a, a + 1, a + ring + 1, a, a + ring + 1, a + ring]);
        }
    }
    ranges[2] = (first, idx.len() as u32 - first);
    // Tube side: two rings.
    let first = idx.len() as u32;
    let base = v.len() as u32;
    for z in [-1.0, 1.0] {
        for k in 0..SEGMENTS {
            let phi = seg * k as f32;
            v.push(vertex(Vec3::new(phi.cos() * s, phi.sin() * s, z)));
        }
    }
    for k in 0..SEGMENTS {
        let (a, b) = (base + k, base + (k + 1) % SEGMENTS);
        idx.extend([a, b, b + SEGMENTS, a, b + SEGMENTS, a + SEGMENTS]);
    }
    ranges[3] = (first, idx.len() as u32 - first);
    (v, idx, ranges)
}

/// The model matrix taking `a`'s unit shape to the world, with the frame `emitter.vert` reads
/// from the area buffer (`gpu::gpu_area_light`).
pub(super) fn model(a: &AreaLight) -> Mat4 {
    let g = crate::render::gpu::gpu_area_light(a);
    let (pos, n, ex, ey) = (
        g[0].truncate(),
        g[1].truncate(),
        g[3].truncate(),
        g[4].truncate(),
    );
    let radius = g[4].w;
    let (x, y, z) = match a.shape {
        AreaShape::Rect { .. } | AreaShape::Disk { .. } => (ex, ey, n),
        AreaShape::Sphere { .. } => (Vec3::X * radius, Vec3::Y * radius, Vec3::Z * radius),
        AreaShape::Tube { .. } => {
            // emitter.vert's side frame around the axis.
            let axis = ex.normalize_or(Vec3::Y);
            let t = axis
                .cross(if axis.x.abs() < 0.9 { Vec3::X } else { Vec3::Y })
                .normalize();
            let b = axis.cross(t);
            (t * radius, b * radius, ex)
        }
    };
    Mat4::from_cols(x.extend(0.0), y.extend(0.0), z.extend(0.0), pos.extend(1.0))
}

/// The scene's visible emitters, with `ranges` from [`unit_shapes`].
pub(super) fn visible(scene: &Scene, ranges: &[(u32, u32); 4]) -> Vec<Emitter> {
    scene
        .area_lights
        .iter()
        .enumerate()
        .filter(|(_, a)| a.visible)
        .map(|(k, a)| Emitter {
            area: k,
            model: model(a),
            range: ranges[match a.shape {
                AreaShape::Rect { .. } => 0,
                AreaShape::Disk { .. } => 1,
                AreaShape::Sphere { .. } => 2,
                AreaShape::Tube { .. } => 3,
            }],
            // The round polygons reach s = 1.0007 times the radius.
            sphere: Sphere {
                center: a.position,
                radius: a.bounding_radius() * 1.001,
            },
        })
        .collect()
}

/// The unit shapes in host-visible vertex and index buffers.
pub(super) struct EmitterMesh {
    vertices: Buffer,
    indices: Buffer,
    pub ranges: [(u32, u32); 4],
}

impl EmitterMesh {
    pub fn new(ctx: &Arc<Context>) -> Result<Self, VkError> {
        let (v, idx, ranges) = unit_shapes();
        Ok(Self {
            vertices: Buffer::with_data(
                ctx,
                "shadow emitter vertices",
                &v,
                vk::BufferUsageFlags::VERTEX_BUFFER,
            )?,
            indices: Buffer::with_data(
                ctx,
                "shadow emitter indices",
                &idx,
                vk::BufferUsageFlags::INDEX_BUFFER,
            )?,
            ranges,
        })
    }

    pub fn raw(&self) -> MeshRef {
        MeshRef {
            vertices: self.vertices.raw,
            centroids: None,
            colors: None,
            indices: self.indices.raw,
            index_count: self.ranges[3].0 + self.ranges[3].1,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit shapes have emitter.vert's triangle counts and the round ones the area of
    /// their round shape (a disk's fan π, a tube side 2π · 2, within 0.1 %).
    #[test]
    fn unit_shapes_match_the_camera_s() {
        let (v, idx, ranges) = unit_shapes();
        let tris: Vec<u32> = ranges.iter().map(|r| r.1 / 3).collect();
        assert_eq!(tris, [2, SEGMENTS, 2 * SEGMENTS * STACKS, 2 * SEGMENTS]);
        let area = |(first, count): (u32, u32)| -> f32 {
            idx[first as usize..(first + count) as usize]
                .chunks_exact(3)
                .map(|t| {
                    let p = |i: u32| Vec3::from_array(v[i as usize].position);
                    0.5 * (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0])).length()
                })
                .sum()
        };
        let pi = std::f32::consts::PI;
        assert!((area(ranges[0]) - 4.0).abs() < 1e-5);
        assert!((area(ranges[1]) / pi - 1.0).abs() < 1e-3);
        assert!((area(ranges[3]) / (4.0 * pi) - 1.0).abs() < 1e-3);
    }
}
