//! The lab's `glass` group (issue 35): the scene under every way the GPU can draw its
//! transmissive materials (`output.refraction`: screen-space refraction at three mip policies,
//! every surface thin-walled, and none — drawn opaque), each GPU time beside its error against
//! the reference's true refraction. Empty when no material transmits.

use crate::brdf::Model;
use crate::scene::{Refraction, Scene};

use super::Variant;

/// The group's variants for `scene`, in [`Refraction::ALL`] order.
pub fn variants(scene: &Scene) -> Vec<Variant> {
    let transmits = scene
        .materials
        .iter()
        .any(|m| matches!(&m.material, Model::MetalRough(p) if p.transmission.factor > 0.0));
    if !transmits {
        return Vec::new();
    }
    Refraction::ALL
        .into_iter()
        .map(|r| {
            let mut s = scene.clone();
            s.output.refraction = r;
            Variant {
                group: "glass",
                label: format!("refraction {}", r.name()),
                scene: s,
            }
        })
        .collect()
}
