//! What the forward pass refreshes per frame and slot besides the frame data: the shadow maps'
//! fit and casters, and the light clusters.

use super::{clusters, frustum, Draw, ForwardPass, TermsKey};
use crate::render::shadow;
use crate::scene::Scene;
use crate::vk::VkError;

impl ForwardPass {
    /// Refits the shadow maps of slot `slot` to `scene`'s camera and objects.
    pub(super) fn update_shadows(
        &mut self,
        slot: usize,
        scene: &Scene,
        aspect: f32,
    ) -> Result<(), VkError> {
        if !self.shadows.active() {
            return Ok(());
        }
        let world = |d: &Draw| {
            let model = scene.objects[d.object].transform.matrix();
            let (c, r) = self.meshes[d.mesh].sphere;
            let sphere = shadow::Sphere {
                center: model.transform_point3(c),
                radius: r * frustum::max_scale(model),
            };
            (model, sphere)
        };
        let mut casters = Vec::new();
        let mut receivers = Vec::new();
        let mut draw_receivers = Vec::with_capacity(self.draws.len());
        for d in &self.draws {
            let obj = &scene.objects[d.object];
            let (model, sphere) = world(d);
            let mesh = &self.meshes[d.mesh];
            let tight = shadow::Sphere {
                center: model.transform_point3(mesh.tight.0),
                radius: mesh.tight.1 * frustum::max_scale(model),
            };
            let receiver = obj.shadow.receive.then(|| {
                receivers.push(shadow::Receiver {
                    sphere,
                    corners: shadow::box_corners(model, mesh.bounds),
                    tight,
                    convex: convex(&obj.desc, d),
                });
                receivers.len() - 1
            });
            draw_receivers.push(receiver);
            if obj.shadow.cast {
                casters.push(shadow::Caster {
                    mesh: d.mesh,
                    levels: mesh.levels.clone(),
                    scale: frustum::max_scale(model),
                    model,
                    sphere,
                    tight,
                    plane: mesh.plane.map(|(p, n)| shadow::world_plane(model, p, n)),
                    receiver,
                    alpha: scene
                        .materials
                        .get(d.material)
                        .and_then(|m| m.textures.alpha_mode.shadow_cutoff())
                        .map(|cutoff| (d.material, cutoff)),
                });
            }
        }
        self.shadows
            .update(slot, scene, aspect, &casters, &receivers)?;
        let view_proj = crate::render::gpu::projection(&scene.camera, aspect) * scene.camera.view();
        self.receive_slots(slot, &draw_receivers, view_proj);
        Ok(())
    }

    /// Marks, in each forward draw's variant, the fixed shadow slots whose light cannot darken
    /// it (`SHADOW_FIXED_SKIP`; every slot for an object that receives no shadow), so that its
    /// pipeline compiles no lookup for them: lavapipe runs a lookup even where an `if` masks
    /// every pixel off (docs/shadows.md#cost). Draws that could be instances of one draw
    /// (same mesh, material, culling and variant but for these marks) share the union of
    /// their lights, so that instancing still joins them. A flat draw (a floor, a wall) of at
    /// most [`SPLIT_TRIANGLES`] triangles lit per pixel also gets the screen rectangle
    /// (`view_proj`) of the part of its box that shadows can reach ([`Draw::shadow_area`]): it
    /// is drawn unshadowed around it. `draw_receivers`: each draw's receiver index in the last
    /// update of slot `slot`. Pipelines for new combinations are built by the next
    /// [`ForwardPass::prepare`]; the deferred path and generic pipelines keep theirs.
    fn receive_slots(
        &mut self,
        slot: usize,
        draw_receivers: &[Option<usize>],
        view_proj: glam::Mat4,
    ) {
        if !self.receivers_culled {
            return;
        }
        let receives = self.shadows.receives(slot);
        let reached: Vec<shadow::Reached> = draw_receivers
            .iter()
            .map(|r| r.and_then(|r| receives.get(r)).copied().unwrap_or_default())
            .collect();
        if let Some(def) = &mut self.deferred {
            // One lighting pass for every pixel: the union of the lights, inside the union of
            // the receivers' rectangles (anywhere when one has a corner behind the eye).
            let lights = reached.iter().fold(0, |m, r| m | r.lights);
            let area = reached.iter().filter_map(|r| r.area).try_fold(
                [
                    f32::INFINITY,
                    f32::INFINITY,
                    f32::NEG_INFINITY,
                    f32::NEG_INFINITY,
                ],
                |u, b| {
                    ndc_rect(b, view_proj).map(|r| {
                        [
                            u[0].min(r[0]),
                            u[1].min(r[1]),
                            u[2].max(r[2]),
                            u[3].max(r[3]),
                        ]
                    })
                },
            );
            def.set_receivers(lights, area);
            return;
        }
        // The union of the lights over each group of would-be instances.
        let group = |d: &Draw| (d.mesh, d.material, d.cull, d.variant.unshadowed());
        let mut lights: std::collections::HashMap<_, u32> = std::collections::HashMap::new();
        for (d, r) in self.draws.iter().zip(&reached) {
            *lights.entry(group(d)).or_default() |= r.lights;
        }
        for (d, r) in self.draws.iter_mut().zip(&reached) {
            if d.variant.terms == TermsKey::Generic {
                continue;
            }
            let bits = if self.instancing {
                lights.get(&group(d)).copied().unwrap_or(r.lights)
            } else {
                r.lights
            };
            d.variant = d.variant.receiving(bits);
            // Flat and Gouraud light in the vertex stage: a triangle across the rectangle's edge
            // carries its vertices' shadows beyond it, so they are not split.
            let mesh = &self.meshes[d.mesh];
            let split = mesh.plane.is_some()
                && mesh.levels[0].index_count / 3 <= SPLIT_TRIANGLES
                && d.variant.shading == super::ShadingKey::Phong;
            d.shadow_area = match r.area {
                Some(area) if split && d.variant.unshadowed() != d.variant => {
                    ndc_rect(area, view_proj)
                }
                _ => None,
            };
        }
    }

    /// What the receiver test left out of the draws' pipelines ([`ForwardPass::receive_slots`]).
    pub fn shadow_receivers(&self) -> ReceiverStats {
        let mut stats = ReceiverStats::default();
        let mut count = |v: &super::VariantKey, area: bool| {
            for code in v.shadow_slots.iter().filter(|&&c| c != 0) {
                stats.pairs += 1;
                stats.skipped += usize::from(code & shadow::FIXED_SKIP != 0);
            }
            stats.split += usize::from(area);
        };
        match &self.deferred {
            Some(def) => {
                let (v, area) = def.receivers();
                count(&v, area.is_some());
            }
            None => self
                .draws
                .iter()
                .for_each(|d| count(&d.variant, d.shadow_area.is_some())),
        }
        stats.deferred = self.deferred.is_some();
        stats
    }

    /// Assigns the scene's lights to the clusters of its camera at `aspect` and writes them into
    /// slot `slot` (nothing when the light loop is plain).
    pub(super) fn write_clusters(
        &mut self,
        slot: usize,
        scene: &Scene,
        aspect: f32,
    ) -> Result<(), VkError> {
        if !self.clustered {
            return Ok(());
        }
        let grid = clusters::Grid::of(scene, aspect);
        let c = clusters::build(&grid, scene.camera.view(), &scene.lights);
        self.slots[slot].write_clusters((&self.ctx, &self.set_layout), slot, &c)?;
        self.cluster_stats = Some(c.stats);
        Ok(())
    }
}

/// Whether an object cannot shadow itself beyond its terminator (where n·l ≤ 0 leaves it
/// unlit anyway): a plane, or a closed convex primitive drawn opaque with its back faces culled
/// (so that no inside can be seen through it or from within).
fn convex(desc: &crate::scene::MeshDesc, d: &Draw) -> bool {
    use crate::scene::MeshDesc as M;
    match desc {
        M::Plane { .. } => true,
        M::Sphere { .. }
        | M::Icosphere { .. }
        | M::Cube { .. }
        | M::Cone { .. }
        | M::Cylinder { .. } => d.cull && d.variant.alpha == super::AlphaKey::Opaque,
        _ => false,
    }
}

/// What the receiver test did to a forward pass's draws ([`ForwardPass::shadow_receivers`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ReceiverStats {
    /// (draw, shadowed light) pairs with a specialised lookup (the fixed slots).
    pub pairs: usize,
    /// Of those, the pairs compiled without the lookup: nothing can darken the draw there.
    pub skipped: usize,
    /// Draws recorded with lookups inside the screen rectangle shadows can reach only.
    pub split: usize,
    /// The deferred path: one lighting pass, whose fixed slots `pairs` and `skipped` count and
    /// which `split` (0 or 1) limits to the rectangle.
    pub deferred: bool,
}

/// Flat draws of at most this many triangles are split where shadows can fall on them
/// ([`ForwardPass::receive_slots`]): each part runs the vertex stage again, which a floor of a
/// few hundred triangles repays many times over in fragments that skip the lookups, a mesh of
/// millions would not.
pub(super) const SPLIT_TRIANGLES: u32 = 4096;

/// The NDC rectangle (x0, y0, x1, y1) that world box `(lo, hi)` covers under `view_proj`
/// (empty when it is off screen); `None` when a corner is behind the eye (the whole screen).
fn ndc_rect((lo, hi): (glam::Vec3, glam::Vec3), view_proj: glam::Mat4) -> Option<[f32; 4]> {
    let mut r = [
        f32::INFINITY,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NEG_INFINITY,
    ];
    for p in shadow::box_corners(glam::Mat4::IDENTITY, (lo, hi)) {
        let c = view_proj * p.extend(1.0);
        if c.w.is_nan() || c.w <= 1e-6 {
            return None;
        }
        let (x, y) = (c.x / c.w, c.y / c.w);
        r = [r[0].min(x), r[1].min(y), r[2].max(x), r[3].max(y)];
    }
    Some([r[0].max(-1.0), r[1].max(-1.0), r[2].min(1.0), r[3].min(1.0)])
}
