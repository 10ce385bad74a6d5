//! Built meshes by description ([`MeshCache`]), shared by the scene decoder and automatic
//! tessellation.

use std::collections::HashMap;
use std::sync::Arc;

use super::mesh::Mesh;
use super::MeshDesc;

/// Built meshes by description, shared between objects with equal descriptions: a hash of the
/// fields picks a short list searched with `==` (one list searched linearly made scenes of many
/// distinct meshes quadratic).
#[derive(Default)]
pub(crate) struct MeshCache {
    by_key: HashMap<[u32; 5], Vec<(MeshDesc, Arc<Mesh>)>>,
}

impl MeshCache {
    /// Equal descriptions have equal keys (−0 counts as 0; a NaN never equals, as with `==`).
    fn key(desc: &MeshDesc) -> [u32; 5] {
        let f = |x: f32| if x == 0.0 { 0 } else { x.to_bits() };
        match *desc {
            MeshDesc::Sphere {
                radius,
                segments,
                rings,
            } => [0, f(radius), segments, rings, 0],
            MeshDesc::Icosphere {
                radius,
                subdivisions,
            } => [1, f(radius), subdivisions, 0, 0],
            MeshDesc::Plane { size, subdivisions } => [2, f(size[0]), f(size[1]), subdivisions, 0],
            MeshDesc::Cube { size } => [3, f(size), 0, 0, 0],
            MeshDesc::Cone {
                radius,
                height,
                segments,
            } => [4, f(radius), f(height), segments, 0],
            MeshDesc::Cylinder {
                radius,
                height,
                segments,
            } => [5, f(radius), f(height), segments, 0],
            MeshDesc::Obj { .. } => [6, 0, 0, 0, 0],
            MeshDesc::Gltf { .. } => [7, 0, 0, 0, 0],
        }
    }

    /// The mesh built for a description equal to `desc`.
    pub(crate) fn get(&self, desc: &MeshDesc) -> Option<&Arc<Mesh>> {
        self.by_key
            .get(&Self::key(desc))?
            .iter()
            .find(|(d, _)| d == desc)
            .map(|(_, m)| m)
    }

    pub(crate) fn insert(&mut self, desc: MeshDesc, mesh: Arc<Mesh>) {
        self.by_key
            .entry(Self::key(&desc))
            .or_default()
            .push((desc, mesh));
    }
}
