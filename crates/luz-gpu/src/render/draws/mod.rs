//! One draw list for every pass: the scene's drawn objects once ([`Item`]: mesh, object,
//! material, face culling, blending), the CPU side of their meshes ([`Shape`]: bounds and LOD
//! levels), and per view the commands to record, sorted by a packed key ([`key`]).
//!
//! Each frame the items are placed once ([`DrawList::place`]: model matrix, world spheres), and
//! every view is built from that: the camera's colour view ([`DrawList::color_view`], which the
//! forward pass and the deferred path's G-buffer record) culls by the camera's frustum, picks
//! each item's LOD level for the camera and sorts opaque draws by pipeline, material, culling,
//! mesh and level, blended ones back to front; each shadow layer's depth view
//! ([`DrawList::layer_view`]) culls the casters by the layer's volume, picks their level for the
//! layer's texels and sorts them front to back, opaque casters before alpha-tested ones. The
//! instanced runs ([`runs`]) and the receiver splits ([`split`]) are read off the views. All of
//! it is CPU data: built and tested without a device; the passes only record.

use std::sync::Arc;

use glam::{Mat4, Vec3};

use crate::render::frustum::{self, Sphere};
use crate::scene::lod::LodLevel;
use crate::scene::{Camera, Scene};

pub mod key;
pub mod split;
#[cfg(test)]
mod tests;

pub use key::Key;

/// The CPU side of a mesh the passes draw (its buffers belong to the pass that uploads them).
#[derive(Debug, Clone)]
pub struct Shape {
    /// Object-space bounding sphere (culling, LOD distances).
    pub sphere: (Vec3, f32),
    /// The bounds' centre and the farthest vertex from it (where shadows can fall).
    pub tight: (Vec3, f32),
    /// Object-space bounds (the shadow passes' receivers).
    pub bounds: (Vec3, Vec3),
    /// Object-space plane of a flat mesh (point, unit normal): `scene::Mesh::flat_plane`.
    pub plane: Option<(Vec3, Vec3)>,
    /// Ranges of the mesh's indices from full detail (level 0) to the coarsest
    /// ([`crate::scene::lod`]); one level for meshes that are not simplified.
    pub levels: Arc<[LodLevel]>,
}

/// One drawn object, as every pass sees it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Item {
    /// Index into [`DrawList::shapes`] (and the pass's mesh buffers).
    pub shape: usize,
    /// Index into the scene's objects.
    pub object: usize,
    pub material: usize,
    /// Back faces are culled.
    pub cull: bool,
    /// Blended: drawn back to front after the opaque draws and the skybox.
    pub blend: bool,
    /// Transmissive (glass, issue 35): drawn front to back after the opaque draws and the
    /// skybox, reading a copy of them, before the blended draws.
    pub transmit: bool,
}

/// The scene's drawn objects and their meshes' bounds and levels.
#[derive(Debug, Clone, Default)]
pub struct DrawList {
    pub shapes: Vec<Shape>,
    pub items: Vec<Item>,
}

/// An item placed for one frame: its model matrix, the matrix's largest scale, and its shape's
/// spheres in the world.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placed {
    pub model: Mat4,
    pub scale: f32,
    pub sphere: Sphere,
    pub tight: Sphere,
}

/// The camera a colour view is built for: its view volume (`view_proj`), and the LOD choice's
/// focal length in pixels and error budget ([`crate::scene::lod::choose`]).
#[derive(Debug, Clone, Copy)]
pub struct Eye<'a> {
    pub camera: &'a Camera,
    pub view_proj: Mat4,
    pub focal_px: f32,
    pub budget: f32,
}

/// A depth-only view (one shadow layer): its projection, and what its LOD choice needs (the
/// texel size, absolute or per metre from `origin` when `perspective`), and its view axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DepthEye {
    pub view_proj: Mat4,
    pub texel: f32,
    pub perspective: bool,
    pub origin: Vec3,
    pub axis: Vec3,
}

/// An item drawn into the shadow maps this frame, with what the maps' fit and culling need.
#[derive(Debug, Clone)]
pub struct Caster {
    /// Index into [`DrawList::items`].
    pub item: usize,
    /// The model matrix's largest scale factor (object-space errors to the world).
    pub scale: f32,
    pub model: Mat4,
    pub sphere: Sphere,
    /// A bounding sphere as tight as the mesh's box allows (where its shadows can fall).
    pub tight: Sphere,
    /// World plane (point, unit normal) when the mesh is flat (`shadow::cull::hides_nothing`).
    pub plane: Option<(Vec3, Vec3)>,
    /// Its own index among the receivers, when it receives too.
    pub receiver: Option<usize>,
    /// For an alpha-tested caster (a MASK or BLEND material): its material (the index of its
    /// set in the forward pass's material sets) and the alpha below which it casts nothing
    /// ([`crate::scene::AlphaMode::shadow_cutoff`]). `None`: opaque, the vertex-only pipeline.
    pub alpha: Option<(usize, f32)>,
}

/// One caster drawn into one depth view.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DepthDraw {
    pub key: Key,
    /// Index of the mesh (shape) drawn.
    pub mesh: usize,
    /// The LOD level's index range: first, count.
    pub range: (u32, u32),
    pub clip: Mat4,
    /// [`Caster::alpha`].
    pub alpha: Option<(usize, f32)>,
}

impl DrawList {
    /// Every item placed by its object's transform in `scene`.
    pub fn place(&self, scene: &Scene) -> Vec<Placed> {
        self.items
            .iter()
            .map(|it| {
                let model = scene.objects[it.object].transform.matrix();
                let shape = &self.shapes[it.shape];
                let scale = frustum::max_scale(model);
                let world = |(c, r): (Vec3, f32)| Sphere {
                    center: model.transform_point3(c),
                    radius: r * scale,
                };
                Placed {
                    model,
                    scale,
                    sphere: world(shape.sphere),
                    tight: world(shape.tight),
                }
            })
            .collect()
    }

    /// The LOD level item `i` (placed at `p`) draws with for `eye`: the coarsest whose error,
    /// projected at its distance from the camera, stays within the budget.
    pub fn camera_level(&self, i: usize, p: &Placed, eye: &Eye) -> u8 {
        let levels = &self.shapes[self.items[i].shape].levels;
        if levels.len() < 2 {
            return 0;
        }
        let distance =
            crate::scene::lod::camera_distance(eye.camera, p.sphere.center, p.sphere.radius);
        crate::scene::lod::choose(levels, p.scale, eye.focal_px, distance, eye.budget) as u8
    }

    /// The colour view of `eye`: the items whose sphere meets its view volume, each at its LOD
    /// level, sorted by [`key::opaque`] (`pipelines`: each item's pipeline rank) and
    /// [`key::blended`]; ties keep the items' order.
    pub fn color_view(&self, placed: &[Placed], eye: &Eye, pipelines: &[u32]) -> ColorView {
        let planes = frustum::planes(eye.view_proj);
        let view = eye.camera.view();
        let levels: Vec<u8> = placed
            .iter()
            .enumerate()
            .map(|(i, p)| self.camera_level(i, p, eye))
            .collect();
        let mut commands: Vec<(Key, usize)> = self
            .items
            .iter()
            .zip(placed)
            .enumerate()
            .filter(|(_, (_, p))| {
                frustum::sphere_visible(&planes, p.sphere.center, p.sphere.radius)
            })
            .map(|(i, (it, p))| {
                let key = if it.blend {
                    key::blended(-view.transform_point3(p.sphere.center).z)
                } else if it.transmit {
                    key::transmissive(-view.transform_point3(p.sphere.center).z)
                } else {
                    let pipeline = pipelines.get(i).copied().unwrap_or(0);
                    key::opaque(pipeline, it.material, it.cull, it.shape, levels[i])
                };
                (key, i)
            })
            .collect();
        commands.sort_by_key(|c| c.0);
        ColorView {
            order: commands.iter().map(|c| c.1).collect(),
            keys: commands.iter().map(|c| c.0).collect(),
            levels,
        }
    }

    /// The draws of depth view `eye`: the casters whose sphere meets its volume, each at the
    /// level [`layer_level`] picks at `budget` texels, sorted by [`key::depth`].
    pub fn layer_view(&self, casters: &[&Caster], eye: &DepthEye, budget: f32) -> Vec<DepthDraw> {
        let planes = frustum::planes(eye.view_proj);
        let mut draws: Vec<DepthDraw> = casters
            .iter()
            .filter(|c| frustum::sphere_visible(&planes, c.sphere.center, c.sphere.radius))
            .map(|c| {
                let shape = self.items[c.item].shape;
                let levels = &self.shapes[shape].levels;
                let l = levels[layer_level(levels, c.scale, c.sphere, eye, budget)];
                let depth = (c.sphere.center - eye.origin).dot(eye.axis);
                DepthDraw {
                    key: key::depth(c.alpha.map(|a| a.0), depth),
                    mesh: shape,
                    range: (l.first_index, l.index_count),
                    clip: eye.view_proj * c.model,
                    alpha: c.alpha,
                }
            })
            .collect();
        draws.sort_by_key(|d| d.key);
        draws
    }

    /// Triangles of the items of `order` at their `levels` (by item).
    pub fn triangles(&self, order: &[usize], levels: &[u8]) -> u64 {
        order
            .iter()
            .map(|&i| {
                let level = levels.get(i).copied().unwrap_or(0) as usize;
                self.shapes[self.items[i].shape].levels[level].triangles()
            })
            .sum()
    }
}

/// The level of `levels` (object-space errors, × `scale`) a caster whose bounding sphere is
/// `sphere` draws into depth view `eye` at `budget` texels ([`crate::scene::lod::choose`]): the
/// error over the view's texel size, absolute (orthographic) or at the sphere's nearest distance
/// from the light (perspective).
pub fn layer_level(
    levels: &[LodLevel],
    scale: f32,
    sphere: Sphere,
    eye: &DepthEye,
    budget: f32,
) -> usize {
    let distance = if eye.perspective {
        crate::scene::lod::sphere_distance(eye.origin, sphere.center, sphere.radius)
    } else {
        1.0
    };
    crate::scene::lod::choose(levels, scale, 1.0 / eye.texel, distance, budget)
}

/// The instanced draws of `order`: runs `(start, count)` of it whose entries `same(first, entry)`
/// says one draw can record (entries are item indices), one run per entry when `instancing` is
/// off.
pub fn runs(
    order: &[usize],
    instancing: bool,
    same: impl Fn(usize, usize) -> bool,
) -> Vec<(usize, usize)> {
    let mut runs: Vec<(usize, usize)> = Vec::new();
    for (k, &i) in order.iter().enumerate() {
        match runs.last_mut() {
            Some((start, count)) if instancing && same(order[*start], i) => *count += 1,
            _ => runs.push((k, 1)),
        }
    }
    runs
}

/// A colour view: the visible items in recording `order` (opaque ones, transmissive ones, then
/// blended ones) with
/// their `keys`, and every item's LOD level (culled items too).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ColorView {
    pub order: Vec<usize>,
    pub keys: Vec<Key>,
    pub levels: Vec<u8>,
}
