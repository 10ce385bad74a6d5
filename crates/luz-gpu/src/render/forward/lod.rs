//! The per-frame LOD choice of the forward pass ([`crate::scene::lod`]): a level per draw and
//! slot, what it draws and why.

use super::{frustum, ForwardPass};
use crate::scene::Scene;

impl ForwardPass {
    /// Per draw: the coarsest LOD level of its mesh whose error, projected at the object's
    /// distance from `scene`'s camera onto the output height, stays within the budget
    /// ([`crate::scene::lod::choose`]).
    /// The levels are chosen for the target's height (the viewer's window) or the scene's, at
    /// the budget asked for ([`ForwardPass::set_lod_budget`]) or the scene's.
    pub(super) fn lod_levels(&mut self, scene: &Scene) -> Vec<u8> {
        self.lod_height = self.target_height.unwrap_or(scene.output.height);
        self.lod_budget = self
            .lod_override
            .unwrap_or(scene.output.tessellation_error_px);
        let f = crate::scene::lod::focal_px(&scene.camera, self.lod_height);
        self.draws
            .iter()
            .map(|d| {
                let levels = &self.meshes[d.mesh].levels;
                if levels.len() < 2 {
                    return 0;
                }
                let model = scene.objects[d.object].transform.matrix();
                let (c, r) = self.meshes[d.mesh].sphere;
                let scale = frustum::max_scale(model);
                let distance = crate::scene::lod::camera_distance(
                    &scene.camera,
                    model.transform_point3(c),
                    r * scale,
                );
                crate::scene::lod::choose(levels, scale, f, distance, self.lod_budget) as u8
            })
            .collect()
    }

    /// The LOD level each simplified mesh's object draws with slot `slot`'s camera, and why
    /// (`luz render`, the viewer); objects whose mesh has no simplified level are left out.
    pub fn lod_choices(&self, slot: usize, scene: &Scene) -> Vec<crate::scene::lod::LodChoice> {
        let s = &self.slots[slot.min(self.slots.len() - 1)];
        // Drawn: the slot's draw order (frustum-culled draws are not in it).
        let mut shown = vec![false; self.draws.len()];
        for &i in &s.order {
            shown[i] = true;
        }
        let f = crate::scene::lod::focal_px(&scene.camera, self.lod_height);
        self.draws
            .iter()
            .enumerate()
            .filter(|(_, d)| self.meshes[d.mesh].levels.len() > 1)
            .map(|(i, d)| {
                let m = &self.meshes[d.mesh];
                let level = s.levels.get(i).copied().unwrap_or(0) as usize;
                let model = scene.objects[d.object].transform.matrix();
                let scale = frustum::max_scale(model);
                let distance = crate::scene::lod::camera_distance(
                    &scene.camera,
                    model.transform_point3(m.sphere.0),
                    m.sphere.1 * scale,
                );
                crate::scene::lod::LodChoice {
                    object: d.object,
                    level,
                    levels: m.levels.len(),
                    triangles: m.levels[level].triangles(),
                    full_triangles: m.levels[0].triangles(),
                    error_px: crate::scene::lod::projected_error_px(
                        m.levels[level].error,
                        scale,
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
        self.draws
            .iter()
            .any(|d| self.meshes[d.mesh].levels.len() > 1)
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
        // Drawn: the slot's draw order (frustum-culled draws are not in it).
        let mut shown = vec![false; self.draws.len()];
        for &i in &s.order {
            shown[i] = true;
        }
        self.draws
            .iter()
            .enumerate()
            .filter(|&(i, _)| shown[i])
            .map(|(i, d)| {
                let level = s.levels.get(i).copied().unwrap_or(0) as usize;
                self.meshes[d.mesh].levels[level].triangles()
            })
            .sum()
    }
}
