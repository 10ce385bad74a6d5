//! The per-frame LOD choice of the forward pass ([`crate::scene::lod`]): a level per draw and
//! slot, what it draws and why.

use super::draws::{ColorView, Eye, Placed};
use super::{ForwardPass, VariantKey};
use crate::scene::Scene;

impl ForwardPass {
    /// The draw list's colour view of `scene`'s camera at `aspect` (items `placed`): frustum
    /// culling, a LOD level per item and the recording order. The levels are the coarsest whose
    /// error, projected at the object's distance from the camera onto the output height, stays
    /// within the budget ([`crate::scene::lod::choose`]): for the target's height (the viewer's
    /// window) or the scene's, at the budget asked for ([`ForwardPass::set_lod_budget`]) or the
    /// scene's.
    pub(super) fn color_view(
        &mut self,
        scene: &Scene,
        aspect: f32,
        placed: &[Placed],
    ) -> ColorView {
        self.lod_height = self.target_height.unwrap_or(scene.output.height);
        self.lod_budget = self
            .lod_override
            .unwrap_or(scene.output.tessellation_error_px);
        let eye = Eye {
            camera: &scene.camera,
            view_proj: scene.camera.projection(aspect) * scene.camera.view(),
            focal_px: crate::scene::lod::focal_px(&scene.camera, self.lod_height),
            budget: self.lod_budget,
        };
        // Pipelines grouped in variant order: each draw's rank among the variants in use.
        let mut variants: Vec<VariantKey> = self.draws.iter().map(|d| d.variant).collect();
        variants.sort_unstable();
        variants.dedup();
        let ranks: Vec<u32> = self
            .draws
            .iter()
            .map(|d| variants.binary_search(&d.variant).unwrap_or(0) as u32)
            .collect();
        self.list.color_view(placed, &eye, &ranks)
    }

    /// The LOD level each simplified mesh's object draws with slot `slot`'s camera, and why
    /// (`luz render`, the viewer); objects whose mesh has no simplified level are left out.
    pub fn lod_choices(&self, slot: usize, scene: &Scene) -> Vec<crate::scene::lod::LodChoice> {
        let s = &self.slots[slot.min(self.slots.len() - 1)];
        // Drawn: the slot's draw order (frustum-culled draws are not in it).
        let mut shown = vec![false; self.draws.len()];
        for &i in &s.view.order {
            shown[i] = true;
        }
        let f = crate::scene::lod::focal_px(&scene.camera, self.lod_height);
        let placed = self.list.place(scene);
        self.list
            .items
            .iter()
            .enumerate()
            .filter(|(_, it)| self.list.shapes[it.shape].levels.len() > 1)
            .map(|(i, it)| {
                let levels = &self.list.shapes[it.shape].levels;
                let level = s.view.levels.get(i).copied().unwrap_or(0) as usize;
                let p = &placed[i];
                let distance = crate::scene::lod::camera_distance(
                    &scene.camera,
                    p.sphere.center,
                    p.sphere.radius,
                );
                crate::scene::lod::LodChoice {
                    object: it.object,
                    level,
                    levels: levels.len(),
                    triangles: levels[level].triangles(),
                    full_triangles: levels[0].triangles(),
                    error_px: crate::scene::lod::projected_error_px(
                        levels[level].error,
                        p.scale,
                        f,
                        distance,
                    ),
                    visible: shown[i],
                }
            })
            .collect()
    }

    /// The budget (px) the next [`ForwardPass::update`] or [`ForwardPass::update_camera`]
    /// chooses mesh LOD levels with; `None`: the scene's `output.tessellation_error_px` (what
    /// `luz render`, `bench` and `lab` always use). The viewer's frame-time target sets it while
    /// the view changes. Only the meshes' levels follow it (they are chosen per frame):
    /// primitives keep the tessellation they were built with, shadow casters the scene's budget.
    pub fn set_lod_budget(&mut self, budget: Option<f32>) {
        self.lod_override = budget.filter(|b| b.is_finite() && *b >= 0.0);
    }

    /// The budget (px) of the last LOD choice.
    pub fn lod_budget(&self) -> f32 {
        self.lod_budget
    }

    /// Whether any drawn mesh has simplified levels (a budget changes what is drawn).
    pub fn has_lod_levels(&self) -> bool {
        self.list
            .items
            .iter()
            .any(|it| self.list.shapes[it.shape].levels.len() > 1)
    }

    /// What building the LOD chains did: chains built, read from the disk cache, failed.
    pub fn lod_stats(&self) -> &crate::scene::lod::ChainStats {
        &self.lod_stats
    }

    /// Triangles drawn into slot `slot`'s shadow maps, every layer: casters at the levels the
    /// layers' projections pick.
    pub fn shadow_triangles_drawn(&self, slot: usize) -> u64 {
        self.shadows.triangles_drawn(slot)
    }

    /// Triangles recorded for slot `slot`'s camera: the drawn objects at their LOD levels.
    pub fn triangles_drawn(&self, slot: usize) -> u64 {
        let s = &self.slots[slot.min(self.slots.len() - 1)];
        self.list.triangles(&s.view.order, &s.view.levels)
    }
}
