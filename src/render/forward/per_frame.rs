//! What the forward pass refreshes per frame and slot besides the frame data: the shadow maps'
//! fit and casters, and the light clusters.

use super::{clusters, frustum, Draw, ForwardPass};
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
        for d in &self.draws {
            let obj = &scene.objects[d.object];
            let (model, sphere) = world(d);
            let mesh = &self.meshes[d.mesh];
            let receiver = obj.shadow.receive.then(|| {
                receivers.push(shadow::Receiver {
                    sphere,
                    corners: shadow::box_corners(model, mesh.bounds),
                });
                receivers.len() - 1
            });
            if obj.shadow.cast {
                casters.push(shadow::Caster {
                    mesh: d.mesh,
                    levels: mesh.levels.clone(),
                    scale: frustum::max_scale(model),
                    model,
                    sphere,
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
            .update(slot, scene, aspect, &casters, &receivers)
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
        self.slots[slot].write_clusters(&self.ctx, slot, &c)?;
        self.cluster_stats = Some(c.stats);
        Ok(())
    }
}
