//! Turning scene meshes into vertex streams for each shading frequency.

use glam::{Vec2, Vec3};

use super::gpu::Vertex;
use crate::scene::Mesh;

/// Vertex and index data ready for upload. `centroids` is present for flat shading only.
pub struct MeshData {
    pub vertices: Vec<Vertex>,
    pub centroids: Option<Vec<[f32; 3]>>,
    pub indices: Vec<u32>,
}

/// Per-vertex tangents from UV gradients (accumulated per triangle, then Gram-Schmidt against the
/// normal); where UVs are missing or degenerate, any unit vector perpendicular to the normal.
pub fn tangents(
    positions: &[Vec3],
    normals: &[Vec3],
    uvs: &[Vec2],
    indices: &[u32],
) -> Vec<[f32; 4]> {
    let n = positions.len();
    let mut tan = vec![Vec3::ZERO; n];
    let mut bit = vec![Vec3::ZERO; n];
    if uvs.len() == n {
        for t in indices.chunks_exact(3) {
            let [a, b, c] = [t[0] as usize, t[1] as usize, t[2] as usize];
            if a >= n || b >= n || c >= n {
                continue;
            }
            let e1 = positions[b] - positions[a];
            let e2 = positions[c] - positions[a];
            let d1 = uvs[b] - uvs[a];
            let d2 = uvs[c] - uvs[a];
            let det = d1.x * d2.y - d2.x * d1.y;
            if det.abs() < 1e-12 {
                continue;
            }
            let r = 1.0 / det;
            let t_dir = (e1 * d2.y - e2 * d1.y) * r;
            let b_dir = (e2 * d1.x - e1 * d2.x) * r;
            for &i in &[a, b, c] {
                tan[i] += t_dir;
                bit[i] += b_dir;
            }
        }
    }
    (0..n)
        .map(|i| {
            let nrm = normals
                .get(i)
                .copied()
                .unwrap_or(Vec3::Y)
                .normalize_or(Vec3::Y);
            let t = tan[i] - nrm * nrm.dot(tan[i]);
            let t = if t.length_squared() > 1e-20 {
                t.normalize()
            } else {
                nrm.any_orthonormal_vector()
            };
            let w = if nrm.cross(t).dot(bit[i]) < 0.0 {
                -1.0
            } else {
                1.0
            };
            [t.x, t.y, t.z, w]
        })
        .collect()
}

/// Smooth (Gouraud and Phong shading): the mesh as it is, with its vertex normals.
pub fn smooth(mesh: &Mesh) -> MeshData {
    let tangents = tangents(&mesh.positions, &mesh.normals, &mesh.uvs, &mesh.indices);
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
        indices: mesh.indices.clone(),
    }
}

/// Flat shading: every triangle gets its own three vertices carrying the face normal and the
/// triangle's centroid, so lighting is evaluated once per polygon.
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
        let tangent = {
            let e = (p[1] - p[0]).normalize_or_zero();
            let e = e - normal * normal.dot(e);
            let e = if e.length_squared() > 1e-20 {
                e.normalize()
            } else {
                normal.any_orthonormal_vector()
            };
            [e.x, e.y, e.z, 1.0]
        };
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
    let indices = (0..vertices.len() as u32).collect();
    MeshData {
        vertices,
        centroids: Some(centroids),
        indices,
    }
}
