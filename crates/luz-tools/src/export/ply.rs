//! Binary little-endian PLY of a [`Mesh`]: positions, normals and (when the mesh has them) UVs,
//! triangles as `uchar`-counted `int` lists. Written by hand: the format is a short text header
//! and packed floats, and Mitsuba's PLY reader expects exactly these property names.

use std::io::Write;

use crate::scene::Mesh;

/// The PLY bytes of `mesh` in its own (object) space.
pub fn ply_bytes(mesh: &Mesh) -> Vec<u8> {
    let uvs = !mesh.uvs.is_empty() && mesh.uvs.len() == mesh.positions.len();
    let normals = mesh.normals.len() == mesh.positions.len();
    let tris = mesh.indices.len() / 3;
    let mut out = Vec::with_capacity(256 + mesh.positions.len() * 32 + tris * 13);
    let mut header =
        String::from("ply\nformat binary_little_endian 1.0\ncomment written by luz export\n");
    header += &format!("element vertex {}\n", mesh.positions.len());
    header += "property float x\nproperty float y\nproperty float z\n";
    if normals {
        header += "property float nx\nproperty float ny\nproperty float nz\n";
    }
    if uvs {
        header += "property float u\nproperty float v\n";
    }
    header += &format!("element face {tris}\nproperty list uchar int vertex_indices\nend_header\n");
    out.extend_from_slice(header.as_bytes());
    for (i, p) in mesh.positions.iter().enumerate() {
        let mut put = |x: f32| out.extend_from_slice(&x.to_le_bytes());
        put(p.x);
        put(p.y);
        put(p.z);
        if normals {
            let n = mesh.normals[i];
            put(n.x);
            put(n.y);
            put(n.z);
        }
        if uvs {
            let t = mesh.uvs[i];
            put(t.x);
            put(t.y);
        }
    }
    for t in mesh.indices.chunks_exact(3) {
        out.push(3);
        for &i in t {
            // Indices fit 32-bit signed: meshes are limited to 2^24 triangles per primitive and
            // loaders refuse more than i32::MAX vertices in practice; clamp rather than wrap.
            let _ = out.write_all(&(i.min(i32::MAX as u32) as i32).to_le_bytes());
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_and_size_match_the_mesh() {
        let m = Mesh::cube(1.0);
        let b = ply_bytes(&m);
        let text_end = b.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
        let header = std::str::from_utf8(&b[..text_end]).unwrap();
        assert!(header.contains(&format!("element vertex {}", m.positions.len())));
        assert!(header.contains("property float u"));
        let per_vertex = 8 * 4;
        let tris = m.indices.len() / 3;
        assert_eq!(
            b.len() - text_end,
            m.positions.len() * per_vertex + tris * 13
        );
    }
}
