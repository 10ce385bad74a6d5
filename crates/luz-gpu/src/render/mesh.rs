//! Turning scene meshes into vertex streams for each shading frequency.

use glam::{Vec2, Vec3};

use super::gpu::Vertex;
use crate::scene::Mesh;

/// Vertex and index data ready for upload. `centroids` is present for flat shading only;
/// `colors` (linear RGBA, vertex buffer binding 2) for smooth meshes with vertex colours.
pub struct MeshData {
    pub vertices: Vec<Vertex>,
    pub centroids: Option<Vec<[f32; 3]>>,
    pub colors: Option<Vec<[f32; 4]>>,
    pub indices: Vec<u32>,
}

/// Per-vertex tangents (xyz unit, w = ±1 handedness) for normal mapping and anisotropic BRDFs.
///
/// **Convention (glTF's).** T points along +u; the bitangent B = w · (N × T) points *up the
/// image*, towards decreasing v (luz's v runs down an image, like glTF's). So a tangent-space
/// normal map in the glTF / OpenGL "green up" convention is applied as
/// n = normalize(x·T + y·B + z·N) with (x, y, z) = 2·texel − 1. On the built-in plane (u along
/// +x, v along +z, normal +y) T = +x and w = +1.
///
/// **With UVs** (one per position): MikkTSpace (`bevy_mikktspace`, byte-compatible with the
/// reference C implementation that Blender, xNormal and Substance bake with), fed v-up
/// coordinates (u, 1 − v) so that its bitangent is the one above. MikkTSpace works per face
/// corner; an indexed vertex shared by several triangles gets the same tangent at each of its
/// corners unless MikkTSpace split it (a vertex on a UV mirror seam used with both
/// orientations). Such a vertex — the index buffer cannot be changed here — takes the
/// normalised sum of its corners' tangents, orthogonalised against its normal, and the sign of
/// the majority of its corners (+1 on a tie). Corners of degenerate triangles that MikkTSpace
/// leaves without a tangent, and vertices no triangle uses, fall back as below.
///
/// **Very large meshes** (more than [`MIKKTSPACE_MAX_TRIANGLES`] triangles): MikkTSpace costs
/// about 2 µs per triangle on one core and grows faster than linearly (1 M triangles: 2 s;
/// 4 M: 13 s) with a large working set, so high-poly meshes — which rarely carry normal maps —
/// use the per-vertex sum of the triangles' UV gradients instead (same convention; the same
/// directions as MikkTSpace on smooth, seamless UV layouts, up to its angle weighting).
///
/// **Without UVs** (or where the above finds nothing): any unit vector perpendicular to the
/// normal, w = +1.
///
/// Deterministic: identical inputs give bit-identical outputs.
pub fn tangents(
    positions: &[Vec3],
    normals: &[Vec3],
    uvs: &[Vec2],
    indices: &[u32],
) -> Vec<[f32; 4]> {
    let n = positions.len();
    let normal = |i: usize| {
        normals
            .get(i)
            .copied()
            .unwrap_or(Vec3::Y)
            .normalize_or(Vec3::Y)
    };
    // Per vertex: sum of corner tangents, and the balance of corner signs.
    let mut sum = vec![Vec3::ZERO; n];
    let mut sign = vec![0i32; n];
    if uvs.len() == n && n > 0 && indices.len() / 3 > MIKKTSPACE_MAX_TRIANGLES {
        gradient_tangents(positions, normals, uvs, indices, &mut sum, &mut sign);
    } else if uvs.len() == n && n > 0 {
        let mut geometry = MikkMesh {
            positions,
            normals,
            uvs,
            indices,
            corners: vec![None; indices.len() / 3 * 3],
        };
        // Only fails on meshes with no triangles, which leave every corner `None`.
        let _ = bevy_mikktspace::generate_tangents(&mut geometry);
        for (c, t) in geometry.corners.iter().enumerate() {
            if let Some(t) = t {
                let v = indices[c] as usize;
                sum[v] += Vec3::from_slice(&t[..3]);
                sign[v] += if t[3] < 0.0 { -1 } else { 1 };
            }
        }
    }
    (0..n)
        .map(|i| {
            let nrm = normal(i);
            let t = sum[i] - nrm * nrm.dot(sum[i]);
            let (t, w) = if t.length_squared() > 1e-20 {
                (t.normalize(), if sign[i] < 0 { -1.0 } else { 1.0 })
            } else {
                (nrm.any_orthonormal_vector(), 1.0)
            };
            [t.x, t.y, t.z, w]
        })
        .collect()
}

/// Meshes with more triangles than this get UV-gradient tangents instead of MikkTSpace's
/// (see [`tangents`]): 2^19, about one second of MikkTSpace.
pub const MIKKTSPACE_MAX_TRIANGLES: usize = 1 << 19;

/// The fast path of [`tangents`]: per vertex, the sum of its triangles' UV-gradient tangents
/// (∂P/∂u), and the handedness balance of their ∂P/∂v' (v' = 1 − v, up the image).
fn gradient_tangents(
    positions: &[Vec3],
    normals: &[Vec3],
    uvs: &[Vec2],
    indices: &[u32],
    sum: &mut [Vec3],
    sign: &mut [i32],
) {
    let n = positions.len();
    let mut bit = vec![Vec3::ZERO; n];
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [t[0] as usize, t[1] as usize, t[2] as usize];
        if a >= n || b >= n || c >= n {
            continue;
        }
        let e1 = positions[b] - positions[a];
        let e2 = positions[c] - positions[a];
        let d1 = Vec2::new(uvs[b].x - uvs[a].x, uvs[a].y - uvs[b].y);
        let d2 = Vec2::new(uvs[c].x - uvs[a].x, uvs[a].y - uvs[c].y);
        let det = d1.x * d2.y - d2.x * d1.y;
        if det.abs() < 1e-12 {
            continue;
        }
        let r = 1.0 / det;
        let t_dir = (e1 * d2.y - e2 * d1.y) * r;
        let b_dir = (e2 * d1.x - e1 * d2.x) * r;
        for i in [a, b, c] {
            sum[i] += t_dir;
            bit[i] += b_dir;
        }
    }
    for i in 0..n {
        let nrm = normals.get(i).copied().unwrap_or(Vec3::Y);
        sign[i] = if nrm.cross(sum[i]).dot(bit[i]) < 0.0 {
            -1
        } else {
            1
        };
    }
}

/// An indexed triangle mesh as MikkTSpace sees it, collecting one tangent per face corner.
struct MikkMesh<'a> {
    positions: &'a [Vec3],
    normals: &'a [Vec3],
    uvs: &'a [Vec2],
    indices: &'a [u32],
    corners: Vec<Option<[f32; 4]>>,
}

impl MikkMesh<'_> {
    fn vertex(&self, face: usize, vert: usize) -> usize {
        self.indices[face * 3 + vert] as usize
    }
}

impl bevy_mikktspace::Geometry for MikkMesh<'_> {
    fn num_faces(&self) -> usize {
        self.indices.len() / 3
    }

    fn num_vertices_of_face(&self, face: usize) -> usize {
        // Triangles with an index out of range are skipped (MikkTSpace ignores faces that are
        // neither triangles nor quads).
        let n = self.positions.len();
        if (0..3).all(|k| self.vertex(face, k) < n) {
            3
        } else {
            0
        }
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.positions[self.vertex(face, vert)].to_array()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.normals
            .get(self.vertex(face, vert))
            .copied()
            .unwrap_or(Vec3::Y)
            .normalize_or(Vec3::Y)
            .to_array()
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        let uv = self.uvs[self.vertex(face, vert)];
        [uv.x, 1.0 - uv.y]
    }

    fn set_tangent(
        &mut self,
        tangent_space: Option<bevy_mikktspace::TangentSpace>,
        face: usize,
        vert: usize,
    ) {
        if let Some(slot) = self.corners.get_mut(face * 3 + vert) {
            *slot = tangent_space.map(|t| t.tangent_encoded());
        }
    }
}

/// The tangent of one flat-shaded triangle with face normal `normal`: the UV gradient along +u
/// (with the handedness convention of [`tangents`]) when the triangle has usable UVs, else its
/// first edge (w = +1).
fn face_tangent(p: [Vec3; 3], uv: Option<[Vec2; 3]>, normal: Vec3) -> [f32; 4] {
    let along = |e: Vec3| {
        let e = e - normal * normal.dot(e);
        (e.length_squared() > 1e-20).then(|| e.normalize())
    };
    if let Some(uv) = uv {
        let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
        // v-up coordinates, as in `tangents`.
        let d1 = Vec2::new(uv[1].x - uv[0].x, uv[0].y - uv[1].y);
        let d2 = Vec2::new(uv[2].x - uv[0].x, uv[0].y - uv[2].y);
        let det = d1.x * d2.y - d2.x * d1.y;
        if det.abs() > 1e-12 {
            let t = (e1 * d2.y - e2 * d1.y) / det;
            let b = (e2 * d1.x - e1 * d2.x) / det;
            if let Some(t) = along(t) {
                let w = if normal.cross(t).dot(b) < 0.0 {
                    -1.0
                } else {
                    1.0
                };
                return [t.x, t.y, t.z, w];
            }
        }
    }
    let t = along((p[1] - p[0]).normalize_or_zero()).unwrap_or(normal.any_orthonormal_vector());
    [t.x, t.y, t.z, 1.0]
}

/// The mesh's own tangents (a glTF file's TANGENT) when it has one per position, else
/// [`tangents`].
pub fn mesh_tangents(mesh: &Mesh) -> Vec<[f32; 4]> {
    if !mesh.tangents.is_empty() && mesh.tangents.len() == mesh.positions.len() {
        return mesh.tangents.iter().map(|t| t.to_array()).collect();
    }
    tangents(&mesh.positions, &mesh.normals, &mesh.uvs, &mesh.indices)
}

/// Smooth (Gouraud and Phong shading): the mesh as it is, with its vertex normals (and colours).
pub fn smooth(mesh: &Mesh) -> MeshData {
    let tangents = mesh_tangents(mesh);
    let n = mesh.positions.len();
    let colors = (n > 0 && mesh.colors.len() == n)
        .then(|| mesh.colors.iter().map(|c| c.to_array()).collect());
    let vertices = mesh
        .positions
        .iter()
        .enumerate()
        .map(|(i, p)| Vertex {
            position: p.to_array(),
            normal: mesh.normals.get(i).copied().unwrap_or(Vec3::Y).to_array(),
            uv: mesh.uvs.get(i).copied().unwrap_or(Vec2::ZERO).to_array(),
            tangent: tangents[i],
        })
        .collect();
    MeshData {
        vertices,
        centroids: None,
        colors,
        indices: mesh.indices.clone(),
    }
}

/// The size of the draw [`smooth`] or [`flat`] makes of a mesh, known before building it, to be
/// checked against the device ([`crate::vk::Limits::check_mesh`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DrawSize {
    pub vertices: usize,
    pub indices: usize,
    /// The largest index value (0 without indices).
    pub max_index: u64,
}

/// The size of `mesh` drawn smooth (its own vertices and indices) or flat (three vertices per
/// triangle, indexed 0, 1, 2, …; an upper bound: triangles with an index out of range are
/// dropped).
pub fn draw_size(mesh: &Mesh, flat: bool) -> DrawSize {
    if flat {
        let corners = mesh.indices.len() / 3 * 3;
        DrawSize {
            vertices: corners,
            indices: corners,
            max_index: (corners as u64).saturating_sub(1),
        }
    } else {
        DrawSize {
            vertices: mesh.positions.len(),
            indices: mesh.indices.len(),
            max_index: mesh.indices.iter().copied().max().map_or(0, u64::from),
        }
    }
}

/// Flat shading: every triangle gets its own three vertices carrying the face normal and the
/// triangle's centroid, so lighting is evaluated once per polygon.
///
/// Callers check [`draw_size`] against the device first: a mesh of more than 2^32 / 3 triangles
/// has no 32-bit flat indices (this panics rather than wrap them).
pub fn flat(mesh: &Mesh) -> MeshData {
    let tri_count = mesh.indices.len() / 3;
    let mut vertices = Vec::with_capacity(tri_count * 3);
    let mut centroids = Vec::with_capacity(tri_count * 3);
    let n = mesh.positions.len();
    for t in mesh.indices.chunks_exact(3) {
        if t.iter().any(|&i| i as usize >= n) {
            continue;
        }
        let p = [
            mesh.positions[t[0] as usize],
            mesh.positions[t[1] as usize],
            mesh.positions[t[2] as usize],
        ];
        let face = (p[1] - p[0]).cross(p[2] - p[0]);
        // Degenerate triangles keep the average vertex normal so they never produce NaN.
        let normal = if face.length_squared() > 0.0 {
            face.normalize()
        } else {
            t.iter()
                .map(|&i| mesh.normals.get(i as usize).copied().unwrap_or(Vec3::ZERO))
                .sum::<Vec3>()
                .normalize_or(Vec3::Y)
        };
        let centroid = (p[0] + p[1] + p[2]) / 3.0;
        let uv = (mesh.uvs.len() == n).then(|| {
            [
                mesh.uvs[t[0] as usize],
                mesh.uvs[t[1] as usize],
                mesh.uvs[t[2] as usize],
            ]
        });
        let tangent = face_tangent(p, uv, normal);
        for (k, &i) in t.iter().enumerate() {
            vertices.push(Vertex {
                position: p[k].to_array(),
                normal: normal.to_array(),
                uv: mesh
                    .uvs
                    .get(i as usize)
                    .copied()
                    .unwrap_or(Vec2::ZERO)
                    .to_array(),
                tangent,
            });
            centroids.push(centroid.to_array());
        }
    }
    let count = u32::try_from(vertices.len())
        .expect("flat mesh beyond 32-bit indices (draw_size is checked before building it)");
    let indices = (0..count).collect();
    MeshData {
        vertices,
        centroids: Some(centroids),
        colors: None,
        indices,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t3(t: [f32; 4]) -> Vec3 {
        Vec3::new(t[0], t[1], t[2])
    }

    #[test]
    fn plane_tangents_follow_u_with_positive_handedness() {
        let m = Mesh::plane([2.0, 3.0], 4);
        let t = tangents(&m.positions, &m.normals, &m.uvs, &m.indices);
        assert_eq!(t.len(), m.positions.len());
        for x in &t {
            assert!(t3(*x).abs_diff_eq(Vec3::X, 1e-5), "{x:?}");
            assert_eq!(x[3], 1.0);
            // B = w (N × T) points up the image (towards −v, which is −z on the plane).
            assert!((Vec3::Y.cross(t3(*x)) * x[3]).abs_diff_eq(Vec3::NEG_Z, 1e-5));
        }
        // Mirrored u: the tangent flips, and so does the handedness.
        let uvs: Vec<Vec2> = m.uvs.iter().map(|uv| Vec2::new(1.0 - uv.x, uv.y)).collect();
        for x in tangents(&m.positions, &m.normals, &uvs, &m.indices) {
            assert!(
                t3(x).abs_diff_eq(Vec3::NEG_X, 1e-5) && x[3] == -1.0,
                "{x:?}"
            );
        }
        // Flat shading derives the same frame per triangle.
        for v in flat(&m).vertices {
            assert!(t3(v.tangent).abs_diff_eq(Vec3::X, 1e-5) && v.tangent[3] == 1.0);
        }
    }

    #[test]
    fn sphere_tangents_are_unit_perpendicular_and_deterministic() {
        for m in [
            Mesh::sphere(1.0, 48, 24),
            Mesh::icosphere(2.0, 3),
            Mesh::cube(1.0),
        ] {
            let t = tangents(&m.positions, &m.normals, &m.uvs, &m.indices);
            for (x, n) in t.iter().zip(&m.normals) {
                let v = t3(*x);
                assert!(v.is_finite() && (v.length() - 1.0).abs() < 1e-4, "{x:?}");
                assert!(v.dot(*n).abs() < 1e-4, "{x:?} against {n}");
                assert!(x[3] == 1.0 || x[3] == -1.0);
            }
            let again = tangents(&m.positions, &m.normals, &m.uvs, &m.indices);
            let bits = |t: &[[f32; 4]]| t.iter().flatten().map(|f| f.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&t), bits(&again));
        }
        // On the UV sphere (u grows from +x towards −z), away from the poles T is the direction
        // of increasing u.
        let m = Mesh::sphere(1.0, 48, 24);
        let t = tangents(&m.positions, &m.normals, &m.uvs, &m.indices);
        for (i, x) in t.iter().enumerate() {
            let p = m.positions[i];
            if p.y.abs() > 0.8 {
                continue;
            }
            let east = Vec3::new(p.z, 0.0, -p.x).normalize();
            assert!(t3(*x).dot(east) > 0.99, "{p}: {x:?}");
            assert_eq!(x[3], 1.0, "{p}");
        }
    }

    #[test]
    fn large_meshes_take_the_gradient_path_with_the_same_convention() {
        let m = Mesh::plane([2.0, 2.0], 4);
        let (mut sum, mut sign) = (
            vec![Vec3::ZERO; m.positions.len()],
            vec![0; m.positions.len()],
        );
        gradient_tangents(
            &m.positions,
            &m.normals,
            &m.uvs,
            &m.indices,
            &mut sum,
            &mut sign,
        );
        assert!(sum.iter().all(|t| t.normalize().abs_diff_eq(Vec3::X, 1e-5)));
        assert!(sign.iter().all(|&s| s == 1));
        // A sphere just over the limit: unit, perpendicular, eastwards away from the poles.
        let m = Mesh::sphere(1.0, 1024, 258);
        assert!(m.indices.len() / 3 > MIKKTSPACE_MAX_TRIANGLES);
        let t = tangents(&m.positions, &m.normals, &m.uvs, &m.indices);
        for (i, x) in t.iter().enumerate().step_by(97) {
            let (p, n) = (m.positions[i], m.normals[i]);
            assert!((t3(*x).length() - 1.0).abs() < 1e-4 && t3(*x).dot(n).abs() < 1e-4);
            if p.y.abs() < 0.8 {
                let east = Vec3::new(p.z, 0.0, -p.x).normalize();
                assert!(t3(*x).dot(east) > 0.99 && x[3] == 1.0, "{p}: {x:?}");
            }
        }
    }

    #[test]
    fn draw_sizes_match_the_built_data() {
        let m = Mesh::icosphere(1.0, 2);
        for flat_shading in [false, true] {
            let size = draw_size(&m, flat_shading);
            let data = if flat_shading { flat(&m) } else { smooth(&m) };
            assert_eq!(size.vertices, data.vertices.len());
            assert_eq!(size.indices, data.indices.len());
            let max = data.indices.iter().copied().max().map_or(0, u64::from);
            assert_eq!(size.max_index, max);
        }
        let empty = Mesh {
            indices: Vec::new(),
            ..Mesh::cube(1.0)
        };
        assert_eq!(draw_size(&empty, true).max_index, 0);
        assert_eq!(draw_size(&empty, false).max_index, 0);
    }

    #[test]
    fn without_uvs_any_perpendicular_vector() {
        let m = Mesh::icosphere(1.0, 1);
        let t = tangents(&m.positions, &m.normals, &[], &m.indices);
        for (x, n) in t.iter().zip(&m.normals) {
            assert!((t3(*x).length() - 1.0).abs() < 1e-5 && t3(*x).dot(*n).abs() < 1e-5);
            assert_eq!(x[3], 1.0);
        }
        // Degenerate and broken input never panics.
        let p = [Vec3::ZERO; 3];
        let uv = [Vec2::ZERO; 3];
        assert_eq!(tangents(&p, &[], &uv, &[0, 1, 2]).len(), 3);
        assert_eq!(tangents(&p, &[], &uv, &[0, 1, 7]).len(), 3);
        assert!(tangents(&[], &[], &[], &[]).is_empty());
    }
}
