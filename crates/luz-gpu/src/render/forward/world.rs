//! What the renderer holds of a scene, and what an edit costs it.
//!
//! The passes are built for a scene's *shape*: which mesh each object draws and with which
//! shading and material variant, how many lights of which kinds, each light's shadow maps, the
//! fog, the saturation mode, the sample count, the environment and the debug view. Everything
//! else — the camera, transforms, light colours and positions, material values, exposure,
//! background, fog distances — is per-frame data written in place.
//!
//! [`Shape::of`] is the one place those render-internal keys are worked out from a scene. The
//! forward pass keeps the shape it was built for ([`crate::render::forward::ForwardPass::shape`]);
//! [`Shape::change_to`] answers what a changed scene costs ([`Change`]). The viewer asks it after
//! every edit; [`crate::headless::Headless::apply`] asks it and acts on the answer.

use super::variant::{material_key, DebugView, TermsKey};
use crate::scene::{Environment, Saturation, Scene, Shading, ShadowMethod};

/// What a changed scene costs the renderer, cheapest first.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Change {
    /// Per-frame data only: written into this frame's slot, nothing is rebuilt.
    InPlace,
    /// The same meshes, lights, shadow maps, targets and environment, but other pipeline
    /// variants or descriptor contents: a material's model or terms, its maps, an object's
    /// shading or material, the kinds of lights, the fog or saturation mode, the debug view.
    RebuildPipelines,
    /// Objects, meshes, the number of lights, shadow maps or the sample count changed (and, with
    /// `environment`, the environment's image-based lighting must be computed again).
    Rebuild { environment: bool },
}

/// Per object: the mesh's identity, its shading, its material index, that material's variant
/// key (model, BRDF terms) and map bits.
type ObjectShape = (
    usize,
    Shading,
    usize,
    (crate::brdf::ModelKind, TermsKey),
    u32,
);

/// The part of a scene the passes are built for (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct Shape {
    objects: Vec<ObjectShape>,
    lights: usize,
    /// Per area light: what its emitter draws (the shape's vertex count) and whether the camera
    /// sees it (the emitter pass's draw list).
    area_lights: Vec<(u32, bool)>,
    light_kinds: u32,
    /// Per light: the shadow's method, resolution and layers.
    shadows: Vec<Option<(ShadowMethod, u32, u32)>>,
    /// The forward pass's fixed shadow slots (the PCF kernel is one of their fields).
    shadow_slots: [u32; 4],
    fog: bool,
    saturation: Saturation,
    msaa: u32,
    debug: DebugView,
    environment: Option<Environment>,
}

impl Shape {
    /// The shape of `scene` drawn with debug view `debug`.
    pub fn of(scene: &Scene, debug: DebugView) -> Self {
        Self {
            objects: scene
                .objects
                .iter()
                .map(|o| {
                    let m = &scene.materials[o.material];
                    (
                        std::sync::Arc::as_ptr(&o.mesh) as usize,
                        o.shading,
                        o.material,
                        material_key(&m.material),
                        crate::render::material::map_bits(&m.textures),
                    )
                })
                .collect(),
            lights: scene.lights.len(),
            area_lights: scene
                .area_lights
                .iter()
                .map(|l| (super::emitter::vertex_count(&l.shape), l.visible))
                .collect(),
            light_kinds: crate::render::gpu::scene_light_kinds(scene),
            shadows: crate::render::shadow::shadow_lights(scene)
                .iter()
                .map(crate::render::shadow::structure_of)
                .collect(),
            shadow_slots: crate::render::shadow::fixed_slots(&scene.lights),
            fog: scene.fog.is_some(),
            saturation: scene.saturation,
            msaa: scene.output.msaa,
            debug,
            environment: scene.environment.clone(),
        }
    }

    /// What drawing `scene` with debug view `debug` costs passes built for `self`.
    pub fn change_to(&self, scene: &Scene, debug: DebugView) -> Change {
        self.change(&Self::of(scene, debug))
    }

    /// What going from `self` to `new` costs.
    pub fn change(&self, new: &Shape) -> Change {
        if self == new {
            return Change::InPlace;
        }
        let environment = self.environment != new.environment;
        let meshes = |s: &Shape| s.objects.iter().map(|o| o.0).collect::<Vec<_>>();
        if environment
            || meshes(self) != meshes(new)
            || self.lights != new.lights
            || self.area_lights != new.area_lights
            || self.shadows != new.shadows
            || self.msaa != new.msaa
        {
            return Change::Rebuild { environment };
        }
        Change::RebuildPipelines
    }

    /// One line naming what differs from `new` (for errors: "2 lights → 3 lights").
    pub fn describe_change(&self, new: &Shape) -> String {
        let mut parts = Vec::new();
        if self.objects.len() != new.objects.len() {
            parts.push(format!(
                "{} objects → {}",
                self.objects.len(),
                new.objects.len()
            ));
        } else if self.objects != new.objects {
            let n = self
                .objects
                .iter()
                .zip(&new.objects)
                .filter(|(a, b)| a != b)
                .count();
            parts.push(format!("{n} object(s)' mesh, shading or material variant"));
        }
        if self.lights != new.lights {
            parts.push(format!("{} lights → {}", self.lights, new.lights));
        } else if self.area_lights.len() != new.area_lights.len() {
            parts.push(format!(
                "{} area lights → {}",
                self.area_lights.len(),
                new.area_lights.len()
            ));
        } else if self.area_lights != new.area_lights {
            parts.push("an area light's shape or visibility".into());
        } else if self.light_kinds != new.light_kinds {
            parts.push("the kinds of lights".into());
        }
        if self.shadows != new.shadows || self.shadow_slots != new.shadow_slots {
            parts.push("shadow settings".into());
        }
        if self.fog != new.fog {
            parts.push("fog on/off".into());
        }
        if self.saturation != new.saturation {
            parts.push("the saturation mode".into());
        }
        if self.msaa != new.msaa {
            parts.push(format!("msaa {} → {}", self.msaa, new.msaa));
        }
        if self.debug != new.debug {
            parts.push("the debug view".into());
        }
        if self.environment != new.environment {
            parts.push("the environment".into());
        }
        parts.join(", ")
    }
}
