//! The lab's `shadows` group: every shadowed light's method × map resolution × (cascades, for
//! directional lights), plus the scene without shadows, so each variant's GPU time (the shadow
//! pass and the frame) sits beside its error against the reference's traced shadows.

use crate::scene::{LightKind, Scene, Shadow, ShadowMethod};

use super::Variant;

/// Map resolutions of the sweep (texels per side of each map, cascade or cube face).
pub const RESOLUTIONS: [u32; 3] = [512, 1024, 2048];
/// Cascade counts of the sweep (directional lights only).
pub const CASCADES: [u32; 3] = [1, 2, 4];

/// Whether a light can take `method`: PCSS needs an emitter size (`radius` or
/// `angular_radius_deg`).
fn supports(kind: LightKind, radius: f32, angular_radius_deg: f32, method: ShadowMethod) -> bool {
    method != ShadowMethod::Pcss
        || match kind {
            LightKind::Directional => angular_radius_deg > 0.0,
            _ => radius > 0.0,
        }
}

/// The variants of the group for `scene`: "no shadows", then method × resolution × cascades
/// applied to every light the scene shadows (its own biases, kernel and split kept; the scene's
/// lights without a shadow stay without). Empty when no light is shadowed. PCSS is left out
/// unless every shadowed light has a size; the cascade axis only when a directional light is
/// shadowed.
pub fn variants(scene: &Scene) -> Vec<Variant> {
    let shadowed: Vec<usize> = (0..scene.lights.len())
        .filter(|&i| scene.lights[i].shadow.is_some())
        .collect();
    if shadowed.is_empty() {
        return Vec::new();
    }
    let mut none = scene.clone();
    for l in &mut none.lights {
        l.shadow = None;
    }
    let mut out = vec![Variant {
        group: "shadows",
        label: "no shadows".into(),
        scene: none,
    }];
    let directional = shadowed
        .iter()
        .any(|&i| scene.lights[i].kind == LightKind::Directional);
    let cascades: &[u32] = if directional { &CASCADES } else { &[1] };
    for method in ShadowMethod::ALL {
        if !shadowed.iter().all(|&i| {
            let l = &scene.lights[i];
            supports(l.kind, l.radius, l.angular_radius_deg, method)
        }) {
            continue;
        }
        for resolution in RESOLUTIONS {
            for &n in cascades {
                let mut s = scene.clone();
                for &i in &shadowed {
                    let l = &mut s.lights[i];
                    let base = l.shadow.unwrap_or_else(|| Shadow::default_for(l.kind));
                    l.shadow = Some(Shadow {
                        method,
                        resolution,
                        cascades: if l.kind == LightKind::Directional {
                            n
                        } else {
                            1
                        },
                        ..base
                    });
                }
                let label = if directional {
                    format!("{} {resolution}, {n} casc.", method.name())
                } else {
                    format!("{} {resolution}", method.name())
                };
                out.push(Variant {
                    group: "shadows",
                    label,
                    scene: s,
                });
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shadow_scene_gets_every_method_resolution_and_cascade_count() {
        let scene = crate::scene::load(
            &std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
                .join("assets/scenes/shadows/contact_grazing.json"),
        )
        .unwrap();
        let v = variants(&scene);
        assert_eq!(v.len(), 1 + 3 * RESOLUTIONS.len() * CASCADES.len());
        assert!(v[0].scene.lights.iter().all(|l| l.shadow.is_none()));
        for x in &v[1..] {
            for l in &x.scene.lights {
                let s = l.shadow.expect("every light shadowed");
                assert!(RESOLUTIONS.contains(&s.resolution));
                if l.kind != LightKind::Directional {
                    assert_eq!(s.cascades, 1, "{}", x.label);
                }
            }
        }
        // A scene without shadowed lights: nothing to sweep.
        let mut plain = scene.clone();
        for l in &mut plain.lights {
            l.shadow = None;
        }
        assert!(variants(&plain).is_empty());
        // Without a size, PCSS is left out.
        let mut unsized_lights = scene.clone();
        for l in &mut unsized_lights.lights {
            l.radius = 0.0;
            l.angular_radius_deg = 0.0;
        }
        assert_eq!(
            variants(&unsized_lights).len(),
            1 + 2 * RESOLUTIONS.len() * CASCADES.len()
        );
    }
}
