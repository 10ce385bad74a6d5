//! Indexed triangle meshes: the built-in primitives, normal generation and helpers.
//!
//! Conventions: right-handed, y up, counter-clockwise front faces seen from outside, unit normals.
//! UVs have u to the right and v downwards (v = 0 at the top of a texture image), so an OBJ's
//! `vt` is flipped on load.

use std::collections::HashMap;

use glam::{Vec2, Vec3, Vec4};

/// Most segments (around) for spheres, cones and cylinders.
pub const MAX_SEGMENTS: u32 = 4096;
/// Most rings (top to bottom) for spheres.
pub const MAX_RINGS: u32 = 4096;
/// Most recursive subdivisions of an icosphere (8 gives 1 310 720 triangles).
pub const MAX_ICOSPHERE_SUBDIVISIONS: u32 = 8;
/// Most quads along each side of a plane.
pub const MAX_PLANE_SUBDIVISIONS: u32 = 4096;
/// Most triangles one built-in primitive may have (2^24 = 16 777 216).
pub const MAX_PRIMITIVE_TRIANGLES: u64 = 1 << 24;

/// One interleaved vertex as a GPU vertex buffer wants it (32 bytes).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
}

/// Indexed triangle mesh, counter-clockwise front faces seen from outside, right-handed, y up.
///
/// `normals` has one unit normal per position. `uvs` is either empty (the mesh has no texture
/// coordinates) or has one entry per position. `indices.len()` is a multiple of 3. `colors`
/// (linear RGBA vertex colours, glTF's COLOR_0) and `tangents` (xyz + handedness w, glTF's
/// TANGENT) are empty or one per position; without them the colour is white and tangents are
/// computed (MikkTSpace).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub uvs: Vec<Vec2>,
    pub indices: Vec<u32>,
    pub colors: Vec<Vec4>,
    pub tangents: Vec<Vec4>,
    /// For a mesh placed by a glTF node (its transform baked into the vertices above): the same
    /// primitive before that transform, shared by every node that places it, and the transform.
    /// Automatic LOD keys and simplifies this one ([`super::lod::chain_for`]), so that a mesh
    /// placed by many nodes has one cache entry, not one per node (issue 38). None when the mesh
    /// is its own local form (OBJ, primitives, a glTF node with the identity transform) or its
    /// glTF mesh is named by one node only.
    pub placed: Option<std::sync::Arc<Placed>>,
}

/// A mesh's form before the transform that placed it ([`Mesh::placed`]): `local` has the same
/// vertex count, order and indices (winding already swapped for a mirroring transform) and
/// `transform` maps it to the placed mesh's positions.
#[derive(Debug, Clone, PartialEq)]
pub struct Placed {
    pub local: std::sync::Arc<Mesh>,
    pub transform: glam::Mat4,
}

impl Mesh {
    /// UV sphere centred at the origin: `segments` around (clamped to 3..=4096), `rings` from
    /// pole to pole (clamped to 2..=4096). Analytic normals; u goes around (+x towards −z), v from
    /// the top (v = 0 at +y). The seam and the poles have duplicated vertices.
    pub fn sphere(radius: f32, segments: u32, rings: u32) -> Mesh {
        let segments = segments.clamp(3, MAX_SEGMENTS);
        let rings = rings.clamp(2, MAX_RINGS);
        let (s, r) = (segments as usize, rings as usize);
        let mut m = Mesh::with_capacity((s + 1) * (r + 1), 6 * s * (r - 1));
        for i in 0..=rings {
            let v = i as f64 / rings as f64;
            let theta = std::f64::consts::PI * v;
            for j in 0..=segments {
                let u = j as f64 / segments as f64;
                // Exact seam: the last column is the first one again.
                let phi = if j == segments {
                    0.0
                } else {
                    std::f64::consts::TAU * u
                };
                let n = Vec3::new(
                    (theta.sin() * phi.cos()) as f32,
                    theta.cos() as f32,
                    (-theta.sin() * phi.sin()) as f32,
                );
                // Exact poles and seam, so the mesh is watertight.
                let n = match i {
                    0 => Vec3::Y,
                    _ if i == rings => Vec3::NEG_Y,
                    _ => n.normalize(),
                };
                m.positions.push(n * radius);
                m.normals.push(n);
                m.uvs.push(Vec2::new(u as f32, v as f32));
            }
        }
        let row = segments + 1;
        for i in 0..rings {
            for j in 0..segments {
                let a = i * row + j;
                let b = (i + 1) * row + j;
                let c = b + 1;
                let d = a + 1;
                if i != rings - 1 {
                    m.indices.extend_from_slice(&[a, b, c]);
                }
                if i != 0 {
                    m.indices.extend_from_slice(&[a, c, d]);
                }
            }
        }
        m
    }

    /// Icosphere centred at the origin: an icosahedron whose triangles are split in four
    /// `subdivisions` times (clamped to 0..=8) and pushed onto the sphere. Analytic normals;
    /// spherical UVs as for [`Mesh::sphere`] (with a visible seam: vertices are not duplicated).
    pub fn icosphere(radius: f32, subdivisions: u32) -> Mesh {
        let subdivisions = subdivisions.min(MAX_ICOSPHERE_SUBDIVISIONS);
        let t = (1.0 + 5.0f32.sqrt()) / 2.0;
        let mut dirs: Vec<Vec3> = [
            [-1.0, t, 0.0],
            [1.0, t, 0.0],
            [-1.0, -t, 0.0],
            [1.0, -t, 0.0],
            [0.0, -1.0, t],
            [0.0, 1.0, t],
            [0.0, -1.0, -t],
            [0.0, 1.0, -t],
            [t, 0.0, -1.0],
            [t, 0.0, 1.0],
            [-t, 0.0, -1.0],
            [-t, 0.0, 1.0],
        ]
        .iter()
        .map(|p| Vec3::from_array(*p).normalize())
        .collect();
        let mut faces: Vec<[u32; 3]> = vec![
            [0, 11, 5],
            [0, 5, 1],
            [0, 1, 7],
            [0, 7, 10],
            [0, 10, 11],
            [1, 5, 9],
            [5, 11, 4],
            [11, 10, 2],
            [10, 7, 6],
            [7, 1, 8],
            [3, 9, 4],
            [3, 4, 2],
            [3, 2, 6],
            [3, 6, 8],
            [3, 8, 9],
            [4, 9, 5],
            [2, 4, 11],
            [6, 2, 10],
            [8, 6, 7],
            [9, 8, 1],
        ];
        // Make every face wind counter-clockwise seen from outside, whatever the table says.
        for f in &mut faces {
            let [a, b, c] = f.map(|i| dirs[i as usize]);
            if (b - a).cross(c - a).dot(a + b + c) < 0.0 {
                f.swap(1, 2);
            }
        }
        for _ in 0..subdivisions {
            let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
            let mut next = Vec::with_capacity(faces.len() * 4);
            let mut mid = |a: u32, b: u32, dirs: &mut Vec<Vec3>| -> u32 {
                let key = (a.min(b), a.max(b));
                *midpoints.entry(key).or_insert_with(|| {
                    let p = (dirs[a as usize] + dirs[b as usize]).normalize();
                    dirs.push(p);
                    (dirs.len() - 1) as u32
                })
            };
            for &[a, b, c] in &faces {
                let ab = mid(a, b, &mut dirs);
                let bc = mid(b, c, &mut dirs);
                let ca = mid(c, a, &mut dirs);
                next.extend_from_slice(&[[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
            }
            faces = next;
        }
        Mesh {
            positions: dirs.iter().map(|d| *d * radius).collect(),
            uvs: dirs.iter().map(|d| spherical_uv(*d)).collect(),
            normals: dirs,
            indices: faces.into_iter().flatten().collect(),
            ..Mesh::default()
        }
    }

    /// Plane in y = 0 centred at the origin, `size` = [extent along x, extent along z], split
    /// into `subdivisions` × `subdivisions` quads (clamped to 1..=4096). Normal +y; u along +x,
    /// v along +z.
    pub fn plane(size: [f32; 2], subdivisions: u32) -> Mesh {
        let n = subdivisions.clamp(1, MAX_PLANE_SUBDIVISIONS);
        let verts = (n as usize + 1) * (n as usize + 1);
        let mut m = Mesh::with_capacity(verts, 6 * n as usize * n as usize);
        for i in 0..=n {
            let v = i as f32 / n as f32;
            for j in 0..=n {
                let u = j as f32 / n as f32;
                m.positions
                    .push(Vec3::new((u - 0.5) * size[0], 0.0, (v - 0.5) * size[1]));
                m.normals.push(Vec3::Y);
                m.uvs.push(Vec2::new(u, v));
            }
        }
        let row = n + 1;
        for i in 0..n {
            for j in 0..n {
                let a = i * row + j; // (x0, z0)
                let b = a + row; // (x0, z1)
                let c = b + 1; // (x1, z1)
                let d = a + 1; // (x1, z0)
                m.indices.extend_from_slice(&[a, b, c, a, c, d]);
            }
        }
        m
    }

    /// Axis-aligned cube centred at the origin with edge length `size`: 24 vertices (hard edges),
    /// one face normal per side, each face mapped to the full [0, 1]² UV square.
    pub fn cube(size: f32) -> Mesh {
        let h = size * 0.5;
        let mut m = Mesh::with_capacity(24, 36);
        // (normal, u axis, v axis) with u × v = normal.
        let faces = [
            (Vec3::X, Vec3::NEG_Z, Vec3::Y),
            (Vec3::NEG_X, Vec3::Z, Vec3::Y),
            (Vec3::Y, Vec3::X, Vec3::NEG_Z),
            (Vec3::NEG_Y, Vec3::X, Vec3::Z),
            (Vec3::Z, Vec3::X, Vec3::Y),
            (Vec3::NEG_Z, Vec3::NEG_X, Vec3::Y),
        ];
        for (n, u, v) in faces {
            let c = n * h;
            m.quad(
                [
                    c - u * h - v * h,
                    c + u * h - v * h,
                    c + u * h + v * h,
                    c - u * h + v * h,
                ],
                n,
            );
        }
        m
    }

    /// Cone centred at the origin, axis +y: base disc of `radius` at y = −height/2, apex at
    /// y = +height/2, `segments` around (clamped to 3..=4096). Smooth side, hard edge and a
    /// flat cap at the base.
    pub fn cone(radius: f32, height: f32, segments: u32) -> Mesh {
        let s = segments.clamp(3, MAX_SEGMENTS);
        let h = height * 0.5;
        let mut m = Mesh::with_capacity(4 * s as usize + 3, 6 * s as usize);
        let side_normal = |phi: f64| {
            Vec3::new(
                (f64::from(height) * phi.cos()) as f32,
                radius,
                (-f64::from(height) * phi.sin()) as f32,
            )
            .normalize_or(Vec3::Y)
        };
        // Side: base ring (s + 1, seam duplicated) then one apex vertex per segment.
        for j in 0..=s {
            let u = j as f64 / s as f64;
            let phi = std::f64::consts::TAU * u;
            m.positions.push(ring_point(radius, phi, -h));
            m.normals.push(side_normal(phi));
            m.uvs.push(Vec2::new(u as f32, 1.0));
        }
        let apex0 = s + 1;
        for j in 0..s {
            let u = (j as f64 + 0.5) / s as f64;
            m.positions.push(Vec3::new(0.0, h, 0.0));
            m.normals.push(side_normal(std::f64::consts::TAU * u));
            m.uvs.push(Vec2::new(u as f32, 0.0));
        }
        for j in 0..s {
            m.indices.extend_from_slice(&[j, j + 1, apex0 + j]);
        }
        m.disc(radius, -h, s, false);
        m
    }

    /// Cylinder centred at the origin, axis +y, from y = −height/2 to +height/2, `segments`
    /// around (clamped to 3..=4096). Smooth side, hard edges and flat caps at both ends.
    pub fn cylinder(radius: f32, height: f32, segments: u32) -> Mesh {
        let s = segments.clamp(3, MAX_SEGMENTS);
        let h = height * 0.5;
        let mut m = Mesh::with_capacity(4 * s as usize + 6, 12 * s as usize);
        for (y, v) in [(-h, 1.0), (h, 0.0)] {
            for j in 0..=s {
                let u = j as f64 / s as f64;
                let phi = std::f64::consts::TAU * u;
                let p = ring_point(radius, phi, y);
                m.positions.push(p);
                m.normals
                    .push(Vec3::new(p.x, 0.0, p.z).normalize_or(Vec3::X));
                m.uvs.push(Vec2::new(u as f32, v));
            }
        }
        let top = s + 1;
        for j in 0..s {
            let (a, b) = (j, j + 1);
            let (c, d) = (top + j + 1, top + j);
            m.indices.extend_from_slice(&[a, b, c, a, c, d]);
        }
        m.disc(radius, h, s, true);
        m.disc(radius, -h, s, false);
        m
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// Axis-aligned bounding box (min, max); (0, 0) for an empty mesh.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        bounds_of(&self.positions)
    }

    /// The plane every vertex lies in, as (a point on it, unit normal), or `None` when the mesh is
    /// not flat (a vertex farther than 1e-5 of the mesh's extent from the plane of its largest
    /// triangle) or has no triangle of non-zero area. One pass over the triangles and one over
    /// the vertices. The shadow passes use it: a flat caster cannot shadow a receiver on the same
    /// side of its plane as the light (`render::shadow`).
    pub fn flat_plane(&self) -> Option<(Vec3, Vec3)> {
        let mut best = (0.0f32, Vec3::ZERO, Vec3::ZERO);
        for t in self.indices.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| self.positions.get(i as usize).copied());
            let (Some(a), Some(b), Some(c)) = (a, b, c) else {
                return None;
            };
            let n = (b - a).cross(c - a);
            let area2 = n.length_squared();
            if area2 > best.0 {
                best = (area2, a, n);
            }
        }
        let (area2, point, n) = best;
        if !(area2 > 0.0 && area2.is_finite()) {
            return None;
        }
        let normal = n.normalize();
        let (lo, hi) = self.bounds();
        let tolerance = 1e-5 * (hi - lo).length().max(f32::MIN_POSITIVE);
        self.positions
            .iter()
            .all(|p| normal.dot(*p - point).abs() <= tolerance)
            .then_some((point, normal))
    }

    /// Recomputes `normals` per vertex index: the angle-weighted average of the normals of the
    /// triangles that use the vertex (Thürmer & Wüthrich). Vertices that are split (same position,
    /// different index) keep separate normals, so hard edges stay hard. Vertices used by no
    /// non-degenerate triangle get +y.
    pub fn compute_normals(&mut self) {
        let n = self.positions.len();
        self.normals = self.accumulate_normals(n, |i| i as usize);
    }

    /// Like [`Mesh::compute_normals`], but vertices with bit-identical positions share one normal
    /// (so UV seams of an OBJ do not show as shading seams). Used for OBJ files without normals.
    pub fn compute_smooth_normals(&mut self) {
        let mut ids: HashMap<[u32; 3], usize> = HashMap::new();
        let key_of: Vec<usize> = self
            .positions
            .iter()
            .map(|p| {
                // +0.0 and −0.0 are the same point.
                let k = (*p + Vec3::ZERO).to_array().map(f32::to_bits);
                let next = ids.len();
                *ids.entry(k).or_insert(next)
            })
            .collect();
        let welded = self.accumulate_normals(ids.len(), |i| key_of[i as usize]);
        self.normals = key_of.iter().map(|&k| welded[k]).collect();
    }

    fn accumulate_normals(&self, keys: usize, key: impl Fn(u32) -> usize) -> Vec<Vec3> {
        let mut acc = vec![Vec3::ZERO; keys];
        let count = self.positions.len();
        for t in self.indices.chunks_exact(3) {
            if t.iter().any(|&i| i as usize >= count) {
                continue;
            }
            let p = [0, 1, 2].map(|k| self.positions[t[k] as usize]);
            let Some(face) = (p[1] - p[0]).cross(p[2] - p[0]).try_normalize() else {
                continue;
            };
            for k in 0..3 {
                let e1 = p[(k + 1) % 3] - p[k];
                let e2 = p[(k + 2) % 3] - p[k];
                let angle = e1.cross(e2).length().atan2(e1.dot(e2));
                if angle.is_finite() {
                    acc[key(t[k])] += face * angle;
                }
            }
        }
        acc.into_iter().map(|n| n.normalize_or(Vec3::Y)).collect()
    }

    /// A copy with every triangle's vertices split and given the triangle's face normal: what
    /// flat shading needs when the renderer takes the normal from a vertex attribute.
    pub fn to_flat(&self) -> Mesh {
        let mut m = Mesh::with_capacity(self.indices.len(), self.indices.len());
        let n = self.positions.len();
        let has_uvs = self.uvs.len() == n && !self.uvs.is_empty();
        let has_colors = self.colors.len() == n && n > 0;
        let has_tangents = self.tangents.len() == n && n > 0;
        for t in self.indices.chunks_exact(3) {
            if t.iter().any(|&i| i as usize >= self.positions.len()) {
                continue;
            }
            let p = [0, 1, 2].map(|k| self.positions[t[k] as usize]);
            let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or(Vec3::Y);
            for k in 0..3 {
                m.indices.push(m.positions.len() as u32);
                m.positions.push(p[k]);
                m.normals.push(n);
                if has_uvs {
                    m.uvs.push(self.uvs[t[k] as usize]);
                }
                if has_colors {
                    m.colors.push(self.colors[t[k] as usize]);
                }
                if has_tangents {
                    m.tangents.push(self.tangents[t[k] as usize]);
                }
            }
        }
        m
    }

    /// Interleaved vertices for a GPU vertex buffer (UV (0, 0) when the mesh has none).
    pub fn vertices(&self) -> Vec<Vertex> {
        (0..self.positions.len())
            .map(|i| Vertex {
                position: self.positions[i].to_array(),
                normal: self.normals.get(i).copied().unwrap_or(Vec3::Y).to_array(),
                uv: self.uvs.get(i).copied().unwrap_or(Vec2::ZERO).to_array(),
            })
            .collect()
    }

    /// Checks the invariants: index count a multiple of 3, indices in range, one unit normal per
    /// position, UVs empty or one per position, every number finite.
    pub fn validate(&self) -> Result<(), String> {
        let n = self.positions.len();
        if !self.indices.len().is_multiple_of(3) {
            return Err(format!(
                "index count {} is not a multiple of 3",
                self.indices.len()
            ));
        }
        if let Some((k, i)) = self
            .indices
            .iter()
            .enumerate()
            .find(|(_, &i)| i as usize >= n)
        {
            return Err(format!("index {k} is {i}, but there are only {n} vertices"));
        }
        if self.normals.len() != n {
            return Err(format!("{} normals for {n} positions", self.normals.len()));
        }
        if !self.uvs.is_empty() && self.uvs.len() != n {
            return Err(format!("{} UVs for {n} positions", self.uvs.len()));
        }
        if let Some(i) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(format!("position {i} is not finite: {}", self.positions[i]));
        }
        if let Some(i) = self
            .normals
            .iter()
            .position(|v| !v.is_finite() || (v.length() - 1.0).abs() > 1e-3)
        {
            return Err(format!(
                "normal {i} is not a unit vector: {}",
                self.normals[i]
            ));
        }
        if let Some(i) = self.uvs.iter().position(|v| !v.is_finite()) {
            return Err(format!("UV {i} is not finite: {}", self.uvs[i]));
        }
        Ok(())
    }

    fn with_capacity(vertices: usize, indices: usize) -> Mesh {
        Mesh {
            positions: Vec::with_capacity(vertices),
            normals: Vec::with_capacity(vertices),
            uvs: Vec::with_capacity(vertices),
            indices: Vec::with_capacity(indices),
            ..Mesh::default()
        }
    }

    /// Appends a flat quad p0 p1 p2 p3 (counter-clockwise around `n`), UVs (0,1) (1,1) (1,0) (0,0).
    fn quad(&mut self, p: [Vec3; 4], n: Vec3) {
        let base = self.positions.len() as u32;
        let uv = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]];
        for k in 0..4 {
            self.positions.push(p[k]);
            self.normals.push(n);
            self.uvs.push(Vec2::from_array(uv[k]));
        }
        self.indices
            .extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
    }

    /// Appends a flat disc of `radius` in the plane y, facing +y (`up`) or −y.
    fn disc(&mut self, radius: f32, y: f32, segments: u32, up: bool) {
        let base = self.positions.len() as u32;
        let n = if up { Vec3::Y } else { Vec3::NEG_Y };
        self.positions.push(Vec3::new(0.0, y, 0.0));
        self.normals.push(n);
        self.uvs.push(Vec2::splat(0.5));
        for j in 0..=segments {
            let phi = std::f64::consts::TAU * j as f64 / segments as f64;
            self.positions.push(ring_point(radius, phi, y));
            self.normals.push(n);
            // Seen from outside, +x is to the right; v points towards +z on the top cap and
            // towards −z on the bottom cap (ring points have z = −r·sin φ).
            let (sin, cos) = (phi.sin() as f32, phi.cos() as f32);
            let v = if up { 0.5 - 0.5 * sin } else { 0.5 + 0.5 * sin };
            self.uvs.push(Vec2::new(0.5 + 0.5 * cos, v));
        }
        for j in 0..segments {
            let (a, b) = (base + 1 + j, base + 2 + j);
            if up {
                self.indices.extend_from_slice(&[base, a, b]);
            } else {
                self.indices.extend_from_slice(&[base, b, a]);
            }
        }
    }
}

/// Point on a ring of `radius` at height `y`, angle `phi` from +x towards −z (the same direction
/// as u on the sphere).
fn ring_point(radius: f32, phi: f64, y: f32) -> Vec3 {
    // Exact seam: phi = 2π maps to the same point as 0.
    let (s, c) = if phi >= std::f64::consts::TAU {
        (0.0, 1.0)
    } else {
        phi.sin_cos()
    };
    Vec3::new(radius * c as f32, y, -radius * s as f32)
}

/// Spherical UV of a unit direction: u around from +x towards −z, v = 0 at +y.
fn spherical_uv(d: Vec3) -> Vec2 {
    let u = (-d.z).atan2(d.x) / std::f32::consts::TAU;
    let u = if u < 0.0 { u + 1.0 } else { u };
    let v = d.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI;
    Vec2::new(u, v)
}

/// The bounding box `(lo, hi)` of `positions` (zero when there are none).
pub fn bounds_of(positions: &[Vec3]) -> (Vec3, Vec3) {
    if positions.is_empty() {
        return (Vec3::ZERO, Vec3::ZERO);
    }
    positions.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    #[test]
    fn planes_are_found_in_flat_meshes_only() {
        let plane = Mesh::plane([4.0, 2.0], 3);
        let (p, n) = plane.flat_plane().expect("a plane mesh is flat");
        assert!(n.abs().abs_diff_eq(Vec3::Y, 1e-6), "normal {n}");
        assert!(p.y.abs() < 1e-6);
        assert_eq!(Mesh::sphere(1.0, 16, 8).flat_plane(), None);
        assert_eq!(Mesh::cube(1.0).flat_plane(), None);
        // A quad with one corner lifted by 1e-3 of its size is not flat.
        let mut bent = plane.clone();
        bent.positions[0].y += 4e-3;
        assert_eq!(bent.flat_plane(), None);
        // No triangle of non-zero area, or an index past the vertices: no plane.
        let degenerate = Mesh {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0],
            normals: vec![],
            uvs: vec![],
            indices: vec![0, 1, 2],
            ..Mesh::default()
        };
        assert_eq!(degenerate.flat_plane(), None);
        let broken = Mesh {
            indices: vec![0, 1, 7],
            ..degenerate
        };
        assert_eq!(broken.flat_plane(), None);
    }

    /// Every invariant plus: each triangle's geometric normal agrees with its vertex normals,
    /// there are no degenerate triangles, and the surface is closed (every undirected edge,
    /// after welding equal positions, is used by exactly two triangles with opposite directions).
    fn check(m: &Mesh, closed: bool) {
        m.validate().unwrap();
        assert!(m.triangle_count() > 0);
        for t in m.indices.chunks_exact(3) {
            let p = [0, 1, 2].map(|k| m.positions[t[k] as usize]);
            let g = (p[1] - p[0]).cross(p[2] - p[0]);
            assert!(g.length() > 0.0, "degenerate triangle {t:?}");
            let g = g.normalize();
            for &i in t {
                assert!(
                    g.dot(m.normals[i as usize]) > 0.0,
                    "winding disagrees with normal at {t:?}"
                );
            }
        }
        if closed {
            let mut id: HashMap<[u32; 3], u32> = HashMap::new();
            let w: Vec<u32> = m
                .positions
                .iter()
                .map(|p| {
                    let n = id.len() as u32;
                    *id.entry(p.to_array().map(f32::to_bits)).or_insert(n)
                })
                .collect();
            let mut edges: HashMap<(u32, u32), i32> = HashMap::new();
            for t in m.indices.chunks_exact(3) {
                for k in 0..3 {
                    let a = w[t[k] as usize];
                    let b = w[t[(k + 1) % 3] as usize];
                    *edges.entry((a, b)).or_default() += 1;
                }
            }
            for (&(a, b), &c) in &edges {
                assert_eq!(c, 1, "edge {a}->{b} used {c} times");
                assert_eq!(
                    edges.get(&(b, a)),
                    Some(&1),
                    "edge {a}->{b} has no opposite: the mesh is not closed"
                );
            }
        }
    }

    fn check_outward(m: &Mesh, centre: Vec3) {
        for (p, n) in m.positions.iter().zip(&m.normals) {
            let d = *p - centre;
            if d.length() > 1e-6 {
                assert!(n.dot(d) > 0.0, "normal {n} at {p} points inwards");
            }
        }
    }

    #[test]
    fn sphere_is_closed_outward_and_analytic() {
        for (s, r) in [(3, 2), (8, 5), (64, 32)] {
            let m = Mesh::sphere(2.0, s, r);
            check(&m, true);
            check_outward(&m, Vec3::ZERO);
            assert_eq!(m.triangle_count(), 2 * s as usize * (r as usize - 1));
            for (p, n) in m.positions.iter().zip(&m.normals) {
                assert!((p.length() - 2.0).abs() < 1e-5);
                assert!((*p / 2.0 - *n).length() < 1e-5);
            }
        }
        let m = Mesh::sphere(1.0, 16, 8);
        assert_eq!(m.uvs[0].y, 0.0);
        assert_eq!(m.positions[0], Vec3::Y);
        let (lo, hi) = m.bounds();
        assert!((lo - Vec3::splat(-1.0)).max_element() < 1e-6);
        assert!((hi - Vec3::ONE).abs().max_element() < 1e-6);
    }

    #[test]
    fn icosphere_is_closed_and_outward() {
        for s in 0..=3 {
            let m = Mesh::icosphere(0.5, s);
            check(&m, true);
            check_outward(&m, Vec3::ZERO);
            assert_eq!(m.triangle_count(), 20 * 4usize.pow(s));
            assert_eq!(m.positions.len(), 10 * 4usize.pow(s) + 2);
        }
    }

    #[test]
    fn plane_faces_up() {
        let m = Mesh::plane([4.0, 2.0], 3);
        check(&m, false);
        assert_eq!(m.triangle_count(), 18);
        assert!(m.normals.iter().all(|n| *n == Vec3::Y));
        assert_eq!(
            m.bounds(),
            (Vec3::new(-2.0, 0.0, -1.0), Vec3::new(2.0, 0.0, 1.0))
        );
    }

    #[test]
    fn cube_cone_cylinder_are_closed_with_hard_edges() {
        let cube = Mesh::cube(2.0);
        check(&cube, true);
        check_outward(&cube, Vec3::ZERO);
        assert_eq!((cube.positions.len(), cube.triangle_count()), (24, 12));
        assert_eq!(cube.bounds(), (Vec3::splat(-1.0), Vec3::ONE));
        let cone = Mesh::cone(1.0, 2.0, 12);
        check(&cone, true);
        assert_eq!(cone.triangle_count(), 24);
        // A cone's side normal tilts up by atan(r / h).
        let n = cone.normals[0];
        assert!((n - Vec3::new(2.0, 1.0, 0.0).normalize()).length() < 1e-6);
        let cyl = Mesh::cylinder(0.5, 3.0, 7);
        check(&cyl, true);
        check_outward(&cyl, Vec3::ZERO);
        assert_eq!(cyl.triangle_count(), 28);
    }

    #[test]
    fn compute_normals_reproduces_face_normals_of_split_cube() {
        let cube = Mesh::cube(1.0);
        let mut c = cube.clone();
        c.normals.clear();
        c.compute_normals();
        for (a, b) in c.normals.iter().zip(&cube.normals) {
            assert!((*a - *b).length() < 1e-6);
        }
        // Welded: the corners get the symmetric diagonal, thanks to angle weighting.
        c.compute_smooth_normals();
        for (p, n) in c.positions.iter().zip(&c.normals) {
            assert!((*n - p.normalize()).length() < 1e-5, "{p} {n}");
        }
    }

    #[test]
    fn compute_normals_on_tetrahedron() {
        let p = [
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(1.0, -1.0, -1.0),
            Vec3::new(-1.0, 1.0, -1.0),
            Vec3::new(-1.0, -1.0, 1.0),
        ];
        let mut m = Mesh {
            positions: p.to_vec(),
            normals: vec![],
            uvs: vec![],
            indices: vec![0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2],
            ..Mesh::default()
        };
        // Orient outward first (the test data must be right for the check to mean anything).
        for t in m.indices.chunks_exact_mut(3) {
            let [a, b, c] = [0, 1, 2].map(|k| p[t[k] as usize]);
            if (b - a).cross(c - a).dot(a + b + c) < 0.0 {
                t.swap(1, 2);
            }
        }
        m.compute_normals();
        check(&m, true);
        for (p, n) in m.positions.iter().zip(&m.normals) {
            assert!((*n - p.normalize()).length() < 1e-6);
        }
        let flat = m.to_flat();
        check(&flat, true);
        assert_eq!(flat.positions.len(), 12);
    }

    #[test]
    fn degenerate_input_does_not_panic() {
        let mut m = Mesh {
            positions: vec![Vec3::ZERO; 3],
            normals: vec![],
            uvs: vec![],
            indices: vec![0, 1, 2, 0, 1, 7],
            ..Mesh::default()
        };
        m.compute_normals();
        assert_eq!(m.normals, vec![Vec3::Y; 3]);
        assert!(m.validate().is_err());
        let _ = m.to_flat();
        assert_eq!(Mesh::default().bounds(), (Vec3::ZERO, Vec3::ZERO));
        // Out-of-range arguments are clamped.
        assert_eq!(Mesh::sphere(1.0, 0, 0).triangle_count(), 6);
        assert_eq!(
            Mesh::icosphere(1.0, 99).triangle_count(),
            20 * 4usize.pow(8)
        );
    }

    #[test]
    fn interleaved_vertices() {
        let m = Mesh::cube(1.0);
        let v = m.vertices();
        assert_eq!(std::mem::size_of::<Vertex>(), 32);
        assert_eq!(v.len(), 24);
        assert_eq!(bytemuck::cast_slice::<Vertex, u8>(&v).len(), 24 * 32);
    }
}
