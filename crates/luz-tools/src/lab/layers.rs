//! The lab's `layers` group (issue 34): the scene with each glTF layer luz models on metal_rough
//! turned off in turn — clear coat, sheen, anisotropy, iridescence, the specular F90 — each GPU
//! time beside its error against the reference, which keeps every layer. A layer's row is what
//! it costs against what leaving it out gets wrong; the scene as written is the cost and error
//! of drawing them all. One row is a method instead: the thin film at the view, once per pixel
//! (`iridescence_at_view`). Empty when no material has a layer.

use glam::Vec3;

use crate::brdf::{has_iridescence, MetalRoughParams, Model};
use crate::scene::Scene;

use super::Variant;

/// The layers: a label and the parameters without the layer (`None`: the material has none).
type Off = fn(&MetalRoughParams) -> Option<MetalRoughParams>;

const LAYERS: [(&str, Off); 6] = [
    ("no clearcoat", |p| {
        (p.clearcoat > 0.0).then_some(MetalRoughParams {
            clearcoat: 0.0,
            ..*p
        })
    }),
    ("no sheen", |p| {
        (p.sheen_color != Vec3::ZERO).then_some(MetalRoughParams {
            sheen_color: Vec3::ZERO,
            ..*p
        })
    }),
    ("no anisotropy", |p| {
        (p.anisotropy_strength > 0.0).then_some(MetalRoughParams {
            anisotropy_strength: 0.0,
            ..*p
        })
    }),
    ("no iridescence", |p| {
        has_iridescence(p).then_some(MetalRoughParams {
            iridescence: 0.0,
            ..*p
        })
    }),
    // Not a layer off but the film's cheaper form: its Fresnel at n·v once per pixel, against
    // the reference's per light at v·h.
    ("iridescence at the view", |p| {
        has_iridescence(p).then_some(MetalRoughParams {
            iridescence_at_view: true,
            ..*p
        })
    }),
    ("F90 1 (no specular F90)", |p| {
        (p.dielectric_f90 < 1.0).then_some(MetalRoughParams {
            dielectric_f90: 1.0,
            ..*p
        })
    }),
];

/// The group's variants for `scene`, one per layer some material has, in [`LAYERS`] order.
pub fn variants(scene: &Scene) -> Vec<Variant> {
    LAYERS
        .iter()
        .filter_map(|(label, off)| {
            let mut s = scene.clone();
            let mut changed = false;
            for m in &mut s.materials {
                if let Model::MetalRough(p) = &mut m.material {
                    if let Some(q) = off(&p.sanitized()) {
                        *p = q;
                        changed = true;
                    }
                }
            }
            changed.then(|| Variant {
                group: "layers",
                label: label.to_string(),
                scene: s,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// docs/lab/layers.json has every layer: six variants, each the scene with exactly that
    /// layer off (or the film at the view) on the materials that have it (and nothing else
    /// changed); a scene without layers has none.
    #[test]
    fn one_variant_per_layer_present() {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/lab/layers.json");
        let scene = crate::scene::load(&path).unwrap();
        let v = variants(&scene);
        let labels: Vec<&str> = v.iter().map(|v| v.label.as_str()).collect();
        assert_eq!(labels, LAYERS.map(|(l, _)| l).to_vec());
        for (variant, (_, off)) in v.iter().zip(LAYERS) {
            let mut changed = 0;
            for (a, b) in scene.materials.iter().zip(&variant.scene.materials) {
                let (Model::MetalRough(p), Model::MetalRough(q)) = (&a.material, &b.material)
                else {
                    panic!("metal_rough only");
                };
                match off(&p.sanitized()) {
                    Some(want) => {
                        assert_eq!(*q, want);
                        changed += 1;
                    }
                    None => assert_eq!(q, p),
                }
            }
            assert_eq!(changed, 1, "{}: one material has each layer", variant.label);
        }
        let mut plain = scene.clone();
        for m in &mut plain.materials {
            m.material = Model::MetalRough(MetalRoughParams::default());
        }
        assert!(variants(&plain).is_empty());
    }
}
