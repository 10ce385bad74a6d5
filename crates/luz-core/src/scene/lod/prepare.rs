//! What the simplifier is given (issue 38): the mesh's triangles on its vertices welded where they
//! are exact copies, without degenerate triangles, with the triangles around a vertex of too high
//! a valence set aside, so that its time stays in proportion to the mesh whatever the mesh.
//!
//! - **Welding.** Exported glTF often stores each triangle's corners as their own vertices (no
//!   shared vertex at all: `color_teapot_spheres.gltf`'s spheres and teapot), so that meshopt sees
//!   every vertex as a seam of several copies and can collapse none. Vertices whose position,
//!   normal, UV and colour are bitwise equal are one vertex to the simplifier (meshopt's
//!   `generate_vertex_remap`); vertices that differ in an attribute stay apart, so the seams the
//!   file has are kept.
//! - **Degenerate triangles** (two corners at one position, or an area below [`AREA_EPSILON`] of
//!   the longest edge's square) are dropped: they draw nothing, and a fan of them around one vertex
//!   made meshopt's edge lookups quadratic in its valence (0.8, 1.9 and 6.1 s for 10k, 20k and
//!   40k such triangles).
//! - **Valence.** The triangles at a position used by more than [`MAX_VALENCE`] triangles (a long
//!   polygon triangulated as a fan) are set aside: every level keeps them as they are, and meshopt
//!   sees their other corners as a locked border.

use glam::{Vec2, Vec3};

use crate::scene::Mesh;

/// Triangles around one position beyond which they are set aside (kept whole in every level).
/// A UV sphere's pole has as many as it has segments; 256 leaves meshopt's per-vertex edge lookups
/// bounded (quadratic in the valence) while real models are simplified as before.
pub const MAX_VALENCE: usize = 256;
/// A triangle whose area (|cross product|) is below this times its longest edge's square is
/// degenerate (its smallest angle is below about 10⁻⁸ rad).
pub const AREA_EPSILON: f64 = 1e-8;

/// The simplifier's input for one mesh: `mesh` holds the welded vertices (positions, normals,
/// UVs when the mesh has them) and the triangles to simplify; `origin` gives, per welded vertex,
/// the mesh vertex it stands for; `set_aside` holds the triangles kept as they are in every level
/// (into the mesh's own vertices); `uv_seam` marks the welded vertices that share their position
/// with another of other UVs (protected when the simplifier may cross other seams), and
/// `has_seams` says whether some position has several welded vertices.
pub(super) struct Prepared {
    pub mesh: Mesh,
    pub origin: Vec<u32>,
    pub set_aside: Vec<u32>,
    pub uv_seam: Vec<bool>,
    pub has_seams: bool,
}

/// The vertex attributes compared when welding: position, normal, UV, colour.
#[derive(Clone, Copy, Default)]
#[repr(C)]
struct Packed([f32; 12]);

pub(super) fn prepare(mesh: &Mesh) -> Prepared {
    let n = mesh.positions.len();
    let uv = mesh.uvs.len() == n;
    let color = mesh.colors.len() == n;
    let packed: Vec<Packed> = (0..n)
        .map(|i| {
            let mut p = [0.0f32; 12];
            p[..3].copy_from_slice(&mesh.positions[i].to_array());
            p[3..6].copy_from_slice(&mesh.normals[i].to_array());
            if uv {
                p[6..8].copy_from_slice(&mesh.uvs[i].to_array());
            }
            if color {
                p[8..].copy_from_slice(&mesh.colors[i].to_array());
            }
            Packed(p)
        })
        .collect();
    let (unique, remap) = meshopt::generate_vertex_remap(&packed, Some(&mesh.indices));
    // Nothing to weld (every referenced vertex is its own): the mesh as it is, so meshes that
    // simplified before get the same chains.
    let referenced = {
        let mut seen = vec![false; n];
        mesh.indices.iter().for_each(|&i| seen[i as usize] = true);
        seen.iter().filter(|&&s| s).count()
    };
    let (origin, indices): (Vec<u32>, Vec<u32>) = if unique == referenced {
        ((0..n as u32).collect(), mesh.indices.clone())
    } else {
        let mut origin = vec![u32::MAX; unique];
        for (v, &r) in remap.iter().enumerate() {
            if r != u32::MAX && origin[r as usize] == u32::MAX {
                origin[r as usize] = v as u32;
            }
        }
        let indices = meshopt::remap_index_buffer(Some(&mesh.indices), n, &remap);
        (origin, indices)
    };
    let pick = |v: &[Vec3]| origin.iter().map(|&o| v[o as usize]).collect::<Vec<Vec3>>();
    let (positions, normals) = (pick(&mesh.positions), pick(&mesh.normals));
    let uvs: Vec<Vec2> = if uv {
        origin.iter().map(|&o| mesh.uvs[o as usize]).collect()
    } else {
        Vec::new()
    };
    // One id per position (meshopt's position remap: the first vertex at that position).
    let at = meshopt::generate_position_remap_decoder(
        &positions.iter().map(|p| p.to_array()).collect::<Vec<_>>(),
    );
    let mut kept = Vec::with_capacity(indices.len());
    let mut valence = vec![0u32; positions.len()];
    for t in indices.chunks_exact(3) {
        let p = [at[t[0] as usize], at[t[1] as usize], at[t[2] as usize]];
        if p[0] == p[1] || p[1] == p[2] || p[0] == p[2] || zero_area(&positions, t) {
            continue;
        }
        p.iter().for_each(|&p| valence[p as usize] += 1);
        kept.extend_from_slice(t);
    }
    let mut simplified = Vec::with_capacity(kept.len());
    let mut set_aside = Vec::new();
    for t in kept.chunks_exact(3) {
        if t.iter()
            .any(|&v| valence[at[v as usize] as usize] as usize > MAX_VALENCE)
        {
            set_aside.extend(t.iter().map(|&v| origin[v as usize]));
        } else {
            simplified.extend_from_slice(t);
        }
    }
    // Seams: several vertices at one position; a UV seam when their UVs differ.
    let mut has_seams = false;
    let mut seam_uv = vec![false; positions.len()];
    for (v, &a) in at.iter().enumerate() {
        if a as usize != v {
            has_seams = true;
            if uv && uvs[v] != uvs[a as usize] {
                seam_uv[a as usize] = true;
            }
        }
    }
    let uv_seam = at.iter().map(|&a| seam_uv[a as usize]).collect();
    Prepared {
        mesh: Mesh {
            positions,
            normals,
            uvs,
            indices: simplified,
            ..Mesh::default()
        },
        origin,
        set_aside,
        uv_seam,
        has_seams,
    }
}

/// Whether triangle `t` has (almost) no area: |cross| below [`AREA_EPSILON`] times its longest
/// edge's square (in f64, so that rounding does not decide).
fn zero_area(positions: &[Vec3], t: &[u32]) -> bool {
    let p = |k: usize| positions[t[k] as usize].as_dvec3();
    let (a, b, c) = (p(0), p(1), p(2));
    let longest = (b - a)
        .length_squared()
        .max((c - b).length_squared())
        .max((a - c).length_squared());
    (b - a).cross(c - a).length() <= AREA_EPSILON * longest
}
