//! What the forward pass refreshes per frame and slot besides the frame data: the shadow maps'
//! fit and casters, and the light clusters.

use super::draws::{self, Caster, Placed};
use super::{clusters, ForwardPass, TermsKey};
use crate::render::shadow;
use crate::scene::Scene;
use crate::vk::VkError;

impl ForwardPass {
    /// Refits the shadow maps of slot `slot` to `scene`'s camera and objects (the draw list's
    /// items `placed` this frame): the casters and receivers, and each layer's view.
    pub(super) fn update_shadows(
        &mut self,
        slot: usize,
        scene: &Scene,
        aspect: f32,
        placed: &[Placed],
    ) -> Result<(), VkError> {
        if !self.shadows.active() {
            return Ok(());
        }
        let mut casters = Vec::new();
        let mut receivers = Vec::new();
        let mut draw_receivers = Vec::with_capacity(self.draws.len());
        for (i, (it, p)) in self.list.items.iter().zip(placed).enumerate() {
            let obj = &scene.objects[it.object];
            let shape = &self.list.shapes[it.shape];
            let receiver = obj.shadow.receive.then(|| {
                receivers.push(shadow::Receiver {
                    sphere: p.sphere,
                    corners: shadow::box_corners(p.model, shape.bounds),
                    tight: p.tight,
                    convex: convex(&obj.desc, it.cull && self.opaque(i)),
                });
                receivers.len() - 1
            });
            draw_receivers.push(receiver);
            if obj.shadow.cast {
                casters.push(Caster {
                    item: i,
                    scale: p.scale,
                    model: p.model,
                    sphere: p.sphere,
                    tight: p.tight,
                    plane: shape.plane.map(|(q, n)| shadow::world_plane(p.model, q, n)),
                    receiver,
                    alpha: scene
                        .materials
                        .get(it.material)
                        .and_then(|m| m.textures.alpha_mode.shadow_cutoff())
                        .map(|cutoff| (it.material, cutoff)),
                });
            }
        }
        self.shadows
            .update(slot, scene, aspect, (&self.list, &casters), &receivers)?;
        let view_proj = crate::render::gpu::projection(&scene.camera, aspect) * scene.camera.view();
        self.receive_slots(slot, &draw_receivers, view_proj);
        Ok(())
    }

    /// Whether item `i` draws opaque (neither alpha-tested nor blended).
    fn opaque(&self, i: usize) -> bool {
        self.draws[i].variant.alpha == super::AlphaKey::Opaque
    }

    /// Marks, in each forward draw's variant, the fixed shadow slots whose light cannot darken
    /// it (`SHADOW_FIXED_SKIP`; every slot for an object that receives no shadow), so that its
    /// pipeline compiles no lookup for them: lavapipe runs a lookup even where an `if` masks
    /// every pixel off (docs/shadows.md#cost). Draws that could be instances of one draw
    /// (same mesh, material, culling and variant but for these marks) share the union of
    /// their lights, so that instancing still joins them. A flat draw (a floor, a wall) of at
    /// most [`draws::split::SPLIT_TRIANGLES`] triangles lit per pixel also gets the screen rectangle
    /// (`view_proj`) of the part of its box that shadows can reach (`shadow_area`): it
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
                    draws::split::ndc_rect(b, view_proj).map(|r| {
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
        let items = &self.list.items;
        let group = |(d, it): (&super::Draw, &draws::Item)| {
            (it.shape, it.material, it.cull, d.variant.unshadowed())
        };
        let mut lights: std::collections::HashMap<_, u32> = std::collections::HashMap::new();
        for ((d, it), r) in self.draws.iter().zip(items).zip(&reached) {
            *lights.entry(group((d, it))).or_default() |= r.lights;
        }
        for ((d, it), r) in self.draws.iter_mut().zip(items).zip(&reached) {
            if d.variant.terms == TermsKey::Generic {
                continue;
            }
            let bits = if self.instancing {
                lights.get(&group((d, it))).copied().unwrap_or(r.lights)
            } else {
                r.lights
            };
            d.variant = d.variant.receiving(bits);
            let phong = d.variant.shading == super::ShadingKey::Phong;
            let split = draws::split::splits(&self.list.shapes[it.shape], phong);
            d.shadow_area = match r.area {
                Some(area) if split && d.variant.unshadowed() != d.variant => {
                    draws::split::ndc_rect(area, view_proj)
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
        let c = clusters::build(
            &grid,
            scene.camera.view(),
            &scene.lights,
            &scene.area_lights,
        );
        self.slots[slot].write_clusters((&self.ctx, &self.set_layout), slot, &c)?;
        self.cluster_stats = Some(c.stats);
        Ok(())
    }
}

/// Whether an object cannot shadow itself beyond its terminator (where n·l ≤ 0 leaves it
/// unlit anyway): a plane, or a closed convex primitive drawn opaque with its back faces culled
/// (`culled_opaque`, so that no inside can be seen through it or from within).
fn convex(desc: &crate::scene::MeshDesc, culled_opaque: bool) -> bool {
    use crate::scene::MeshDesc as M;
    match desc {
        M::Plane { .. } => true,
        M::Sphere { .. }
        | M::Icosphere { .. }
        | M::Cube { .. }
        | M::Cone { .. }
        | M::Cylinder { .. } => culled_opaque,
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
