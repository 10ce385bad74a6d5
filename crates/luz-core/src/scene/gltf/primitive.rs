//! One glTF mesh primitive → a luz [`Mesh`] in the coordinates of the scene (the node's world
//! transform baked in).

use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use gltf::mesh::{Mode, Semantic};

use super::accessor;
use crate::scene::Mesh;

/// How a primitive's UVs are chosen: the set its material's maps read and the material's
/// KHR_texture_transform (offset, rotation, scale), baked into the mesh's UVs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UvChoice {
    pub set: u32,
    pub offset: Vec2,
    pub rotation: f32,
    pub scale: Vec2,
}

impl Default for UvChoice {
    fn default() -> Self {
        UvChoice {
            set: 0,
            offset: Vec2::ZERO,
            rotation: 0.0,
            scale: Vec2::ONE,
        }
    }
}

impl UvChoice {
    /// KHR_texture_transform: uv' = T · R · S · uv, R = [[cos, −sin], [sin, cos]] (the
    /// extension's matrix, column-major `mat3(cos, sin, 0, −sin, cos, 0, 0, 0, 1)`).
    pub fn apply(&self, uv: Vec2) -> Vec2 {
        let s = uv * self.scale;
        let (sin, cos) = self.rotation.sin_cos();
        Vec2::new(cos * s.x - sin * s.y, sin * s.x + cos * s.y) + self.offset
    }

    fn is_identity(&self) -> bool {
        self.offset == Vec2::ZERO && self.rotation == 0.0 && self.scale == Vec2::ONE
    }
}

/// What a primitive turned into.
pub enum Built {
    Mesh(Mesh),
    /// Points or lines: not drawn (the mode's name).
    NotTriangles(&'static str),
    /// No POSITION attribute: nothing to draw.
    NoPositions,
}

/// Builds primitive `p` of a mesh with world transform `world`. `where_` names the primitive in
/// errors (`meshes[2].primitives[0]`).
pub fn build(
    p: &gltf::Primitive,
    buffers: &[Vec<u8>],
    world: Mat4,
    uv: UvChoice,
    where_: &str,
) -> Result<Built, String> {
    let mode = p.mode();
    let name = match mode {
        Mode::Points => Some("POINTS"),
        Mode::Lines => Some("LINES"),
        Mode::LineLoop => Some("LINE_LOOP"),
        Mode::LineStrip => Some("LINE_STRIP"),
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan => None,
    };
    if let Some(n) = name {
        return Ok(Built::NotTriangles(n));
    }
    let at = |what: &str, e: String| format!("{where_}.{what}: {e}");
    let Some(pos_acc) = p.get(&Semantic::Positions) else {
        return Ok(Built::NoPositions);
    };
    let pos = accessor::floats(&pos_acc, buffers).map_err(|e| at("attributes.POSITION", e))?;
    if pos.components != 3 {
        return Err(at(
            "attributes.POSITION",
            format!("must be VEC3, has {} components", pos.components),
        ));
    }
    let n = pos.len();
    let positions: Vec<Vec3> = (0..n).map(|i| Vec3::from_array(pos.get(i, 0.0))).collect();
    if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
        return Err(at(
            "attributes.POSITION",
            format!("element {i} is not finite: {}", positions[i]),
        ));
    }
    let attr = |semantic: Semantic, what: &str, kind: &str, counts: &[usize]| {
        per_vertex(p, buffers, semantic, n, (kind, counts)).map_err(|e| at(what, e))
    };
    let normals = attr(Semantic::Normals, "attributes.NORMAL", "VEC3", &[3])?.map(|f| {
        (0..n)
            .map(|i| Vec3::from_array(f.get(i, 0.0)))
            .collect::<Vec<_>>()
    });
    let what = format!("attributes.TEXCOORD_{}", uv.set);
    let uvs = match attr(Semantic::TexCoords(uv.set), &what, "VEC2", &[2])? {
        None => Vec::new(),
        Some(f) => (0..n)
            .map(|i| {
                let t = Vec2::from_array(f.get(i, 0.0));
                let t = if uv.is_identity() { t } else { uv.apply(t) };
                if t.is_finite() {
                    t
                } else {
                    Vec2::ZERO
                }
            })
            .collect(),
    };
    // COLOR_0: VEC3 or VEC4 (alpha 1), float or normalised u8/u16; linear, multiplies the
    // base colour.
    let colors = match attr(
        Semantic::Colors(0),
        "attributes.COLOR_0",
        "VEC3 or VEC4",
        &[3, 4],
    )? {
        None => Vec::new(),
        Some(f) => (0..n)
            .map(|i| {
                let c = Vec4::from_array(f.get(i, 1.0));
                if c.is_finite() {
                    c.clamp(Vec4::ZERO, Vec4::ONE)
                } else {
                    Vec4::ONE
                }
            })
            .collect(),
    };
    let tangents = attr(Semantic::Tangents, "attributes.TANGENT", "VEC4", &[4])?.map(|f| {
        (0..n)
            .map(|i| Vec4::from_array(f.get(i, 1.0)))
            .collect::<Vec<_>>()
    });
    let raw = match p.indices() {
        Some(a) => accessor::indices(&a, buffers, n).map_err(|e| at("indices", e))?,
        None => (0..n as u32).collect(),
    };
    let mut indices = triangles(mode, &raw);
    // A mirroring transform turns counter-clockwise into clockwise: swap to keep the front.
    let linear = Mat3::from_mat4(world);
    if linear.determinant() < 0.0 {
        for t in indices.chunks_exact_mut(3) {
            t.swap(1, 2);
        }
    }
    let mut mesh = Mesh {
        positions: positions
            .iter()
            .map(|p| world.transform_point3(*p))
            .collect(),
        normals: Vec::new(),
        uvs,
        indices,
        colors,
        ..Mesh::default()
    };
    if let Some(i) = mesh.positions.iter().position(|p| !p.is_finite()) {
        return Err(format!(
            "{where_}: vertex {i} is not finite after the node transforms: {}",
            mesh.positions[i]
        ));
    }
    let file_normals = normals.is_some();
    match normals {
        Some(ns) => {
            let nm = linear.inverse().transpose();
            let nm = if nm.is_finite() { nm } else { Mat3::IDENTITY };
            mesh.normals = ns
                .iter()
                .map(|v| (nm * *v).try_normalize())
                .collect::<Option<Vec<_>>>()
                .unwrap_or_default();
            if mesh.normals.len() != n {
                // A zero or non-finite normal: smooth normals from the triangles for the mesh.
                mesh.compute_normals();
            }
        }
        // glTF: without normals, flat shading (and the file's tangents, which go with the
        // normals, are not used: the spec asks for both or computed ones).
        None => mesh = mesh.to_flat(),
    }
    if let (Some(ts), true) = (tangents, file_normals) {
        mesh.tangents = file_tangents(&ts, linear);
    }
    Ok(Built::Mesh(mesh))
}

/// Attribute `semantic` of primitive `p` read as floats, checked to hold one element per position
/// (`n`) with one of `counts` components (`kind` names them in the message); None when absent.
fn per_vertex(
    p: &gltf::Primitive,
    buffers: &[Vec<u8>],
    semantic: Semantic,
    n: usize,
    (kind, counts): (&str, &[usize]),
) -> Result<Option<accessor::Floats>, String> {
    let Some(a) = p.get(&semantic) else {
        return Ok(None);
    };
    let f = accessor::floats(&a, buffers)?;
    if !counts.contains(&f.components) || f.len() != n {
        return Err(format!(
            "must be {kind} with one element per position ({n}), has {} of {} components",
            f.len(),
            f.components
        ));
    }
    Ok(Some(f))
}

/// The file's tangents through the node transform's linear part `linear` (a direction, so `M t`,
/// renormalised), with the handedness flipped by a mirroring transform (the bitangent mirrors
/// with it). Empty when any tangent is zero or not finite (MikkTSpace then computes them all).
fn file_tangents(ts: &[Vec4], linear: Mat3) -> Vec<Vec4> {
    let flip = if linear.determinant() < 0.0 {
        -1.0
    } else {
        1.0
    };
    ts.iter()
        .map(|t| {
            let d = (linear * t.truncate()).try_normalize()?;
            let w = if t.w < 0.0 { -flip } else { flip };
            Some(d.extend(w))
        })
        .collect::<Option<Vec<_>>>()
        .unwrap_or_default()
}

/// Triangle list of a triangles, strip or fan primitive (glTF 2.0 §3.7.2.1: strip triangle i is
/// {i, i + 1 + i%2, i + 2 − i%2}; fan triangle i is {i + 1, i + 2, 0}).
pub fn triangles(mode: Mode, v: &[u32]) -> Vec<u32> {
    match mode {
        Mode::TriangleStrip => {
            let mut out = Vec::with_capacity(v.len().saturating_sub(2) * 3);
            for i in 0..v.len().saturating_sub(2) {
                let odd = i % 2;
                out.extend_from_slice(&[v[i], v[i + 1 + odd], v[i + 2 - odd]]);
            }
            out
        }
        Mode::TriangleFan => {
            let mut out = Vec::with_capacity(v.len().saturating_sub(2) * 3);
            for i in 0..v.len().saturating_sub(2) {
                out.extend_from_slice(&[v[i + 1], v[i + 2], v[0]]);
            }
            out
        }
        _ => {
            let whole = v.len() / 3 * 3;
            v[..whole].to_vec()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_keep_the_winding() {
        assert_eq!(
            triangles(Mode::TriangleStrip, &[0, 1, 2, 3, 4]),
            vec![0, 1, 2, 1, 3, 2, 2, 3, 4]
        );
        assert_eq!(
            triangles(Mode::TriangleFan, &[0, 1, 2, 3]),
            vec![1, 2, 0, 2, 3, 0]
        );
        assert_eq!(triangles(Mode::Triangles, &[0, 1, 2, 3]), vec![0, 1, 2]);
        assert!(triangles(Mode::TriangleStrip, &[0, 1]).is_empty());
    }

    #[test]
    fn texture_transform_matches_the_extension() {
        let t = UvChoice {
            set: 0,
            offset: Vec2::new(0.5, 0.25),
            rotation: std::f32::consts::FRAC_PI_2,
            scale: Vec2::new(2.0, 3.0),
        };
        // S: (2, 0); R (90°): (0, 2); T: (0.5, 2.25).
        let p = t.apply(Vec2::new(1.0, 0.0));
        assert!((p - Vec2::new(0.5, 2.25)).length() < 1e-6, "{p}");
    }
}
