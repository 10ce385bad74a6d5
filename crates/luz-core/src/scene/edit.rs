//! The viewer's edit rules, without egui: what a change to a light, a material or the fog does to
//! the rest of the scene so that it stays valid by the decoder's rules (`decode*.rs`,
//! `docs/scene-format.md`). The panels (`window::ui`) call these; they are unit-tested here.

use glam::{DVec3, Vec3};

use crate::brdf::{metal_preset, CookTorranceParams, Fresnel, ModelKind, SpecularSource};
use crate::scene::{
    slots_for_model, Falloff, Light, LightKind, Material, MaterialTextures, Shadow, ShadowMethod,
};

/// Unit vector of `v` (in f64, like the decoder); `None` for a zero or non-finite vector.
pub fn unit_vec(v: Vec3) -> Option<Vec3> {
    let d = DVec3::new(f64::from(v.x), f64::from(v.y), f64::from(v.z));
    let len = d.length();
    (len > 1e-12 && len.is_finite()).then(|| (d / len).as_vec3())
}

/// Smallest separation kept between the fog's z_a and z_b.
pub fn fog_gap(z: f32) -> f32 {
    (z.abs() * 1e-3).max(1e-3)
}

/// A new light of `kind` with sensible defaults, placed for a scene whose objects span `bounds`.
pub fn default_light(kind: LightKind, bounds: Option<(Vec3, Vec3)>) -> Light {
    let (lo, hi) = bounds.unwrap_or((Vec3::splat(-1.0), Vec3::splat(1.0)));
    let centre = (lo + hi) * 0.5;
    let size = (hi - lo).length().max(1.0);
    let above = centre + Vec3::new(0.0, size, 0.0);
    let base = Light {
        kind,
        direction: Vec3::NEG_Y,
        position: above,
        color: Vec3::ONE,
        intensity: 1.0,
        falloff: Falloff::InverseSquare,
        umbra_deg: 180.0,
        inner_deg: None,
        exponent: 0.0,
        range: None,
        shadow: None,
        radius: 0.0,
        angular_radius_deg: 0.0,
    };
    match kind {
        LightKind::Directional => Light {
            direction: Vec3::new(-0.4, -1.0, -0.5).normalize(),
            position: Vec3::ZERO,
            falloff: Falloff::None,
            ..base
        },
        // About irradiance 1 at the scene's centre.
        LightKind::Point => Light {
            position: centre + Vec3::new(0.5, 1.0, 0.5) * size * 0.7,
            intensity: size * size,
            ..base
        },
        LightKind::Spot => Light {
            intensity: 2.0 * size * size,
            umbra_deg: 30.0,
            inner_deg: Some(20.0),
            ..base
        },
    }
}

/// How [`light_field`] places its lights over the scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LightField {
    /// A square grid, row by row.
    Grid,
    /// Uniformly at random (a fixed seed: the same field every time).
    Random,
}

impl LightField {
    pub fn name(self) -> &'static str {
        match self {
            LightField::Grid => "grid",
            LightField::Random => "random",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        [LightField::Grid, LightField::Random]
            .into_iter()
            .find(|f| f.name().eq_ignore_ascii_case(name))
    }
}

/// The most lights one `add_lights` (or the panel's "Add many") adds.
pub const MAX_ADDED_LIGHTS: u32 = 65_536;

/// `n` coloured inverse-square point lights with a range, spread over the horizontal extent of
/// `bounds` (the objects' box; a 2 m square without) a little above its bottom: the viewer's bulk
/// add, for many-light scenes. With spacing s between neighbours (grid: the extent over ⌈√n⌉; the
/// same mean spacing at random), each has intensity s² / 2 (irradiance 0.5 at distance s) and
/// range 2 s, so a point is lit by about a dozen lights.
pub fn light_field(field: LightField, n: usize, bounds: Option<(Vec3, Vec3)>) -> Vec<Light> {
    let (lo, hi) = bounds.unwrap_or((Vec3::splat(-1.0), Vec3::splat(1.0)));
    let (lo, hi) = if lo.is_finite() && hi.is_finite() {
        (lo, hi)
    } else {
        (Vec3::splat(-1.0), Vec3::splat(1.0))
    };
    let size = (hi - lo).max(Vec3::splat(1e-3));
    let side = (n as f64).sqrt().ceil().max(1.0) as usize;
    let spacing = (size.x.max(size.z) / side as f32).max(1e-3);
    let y = lo.y + 0.1 * size.y + 0.25 * spacing;
    let mut seed = 0x1ce_5eedu64;
    let mut rand = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 40) as f32 / (1u64 << 24) as f32
    };
    (0..n)
        .map(|k| {
            let (u, v) = match field {
                LightField::Grid => (
                    ((k % side) as f32 + 0.5) / side as f32,
                    ((k / side) as f32 + 0.5) / side as f32,
                ),
                LightField::Random => (rand(), rand()),
            };
            // Hues around the colour wheel (golden-ratio steps), saturated but light.
            let h = (k as f32 * 0.618_034).fract() * 6.0;
            let c = |o: f32| (((h + o) % 6.0 - 3.0).abs() - 1.0).clamp(0.0, 1.0);
            let color = Vec3::new(c(0.0), c(4.0), c(2.0)) * 0.7 + 0.3;
            Light {
                kind: LightKind::Point,
                direction: Vec3::NEG_Y,
                position: Vec3::new(lo.x + u * size.x, y, lo.z + v * size.z),
                color,
                intensity: 0.5 * spacing * spacing,
                falloff: Falloff::InverseSquare,
                umbra_deg: 180.0,
                inner_deg: None,
                exponent: 0.0,
                range: Some(2.0 * spacing),
                shadow: None,
                radius: 0.0,
                angular_radius_deg: 0.0,
            }
        })
        .collect()
}

/// Changes a light's kind, keeping what carries over and resetting what the new kind fixes
/// (the decoder's values: point lights point down, non-spots have umbra 180°, no inner cone and
/// exponent 0, directional lights have no falloff and no range).
pub fn set_light_kind(light: &mut Light, kind: LightKind) {
    if light.kind == kind {
        return;
    }
    let from = light.kind;
    light.kind = kind;
    match kind {
        LightKind::Directional => {
            light.falloff = Falloff::None;
            light.range = None;
            light.umbra_deg = 180.0;
            light.inner_deg = None;
            light.exponent = 0.0;
            if from == LightKind::Point {
                light.direction = Vec3::new(-0.4, -1.0, -0.5).normalize();
            }
        }
        LightKind::Point => {
            light.direction = Vec3::NEG_Y;
            light.umbra_deg = 180.0;
            light.inner_deg = None;
            light.exponent = 0.0;
            if from == LightKind::Directional {
                light.falloff = Falloff::InverseSquare;
            }
        }
        LightKind::Spot => {
            light.umbra_deg = 30.0;
            light.inner_deg = None;
            light.exponent = 0.0;
            if from == LightKind::Directional {
                light.falloff = Falloff::InverseSquare;
            }
        }
    }
}

/// The map resolutions the lights panel offers (texels per side).
pub const SHADOW_RESOLUTIONS: [u32; 6] = [256, 512, 1024, 2048, 4096, 8192];

/// One change to a light's shadow, as the lights panel's Shadow rows make it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ShadowEdit {
    /// The Shadow checkbox off: no shadow.
    Off,
    /// The Shadow checkbox on: the light kind's defaults ([`Shadow::default_for`]).
    On,
    /// The Method row (turning the shadow on first when it is off).
    Method(ShadowMethod),
    /// The Resolution row: one of [`SHADOW_RESOLUTIONS`].
    Resolution(u32),
}

/// Whether PCSS can be used: it needs the light's radius or angular radius.
pub fn has_size(light: &Light) -> bool {
    light.radius > 0.0 || light.angular_radius_deg > 0.0
}

/// Applies `edit` to `light`'s shadow; true when something changed. A method or resolution the
/// panel does not offer is an error (the light is left as it was): PCSS on a light without a
/// size, a resolution not in [`SHADOW_RESOLUTIONS`], a resolution for a light without a shadow.
pub fn edit_shadow(light: &mut Light, edit: ShadowEdit) -> Result<bool, String> {
    let before = light.shadow;
    match edit {
        ShadowEdit::Off => light.shadow = None,
        ShadowEdit::On => {
            if light.shadow.is_none() {
                light.shadow = Some(Shadow::default_for(light.kind));
            }
        }
        ShadowEdit::Method(m) => {
            if m == ShadowMethod::Pcss && !has_size(light) {
                return Err(
                    "pcss needs the light's size (a radius, or an angular radius for a \
                     directional light)"
                        .into(),
                );
            }
            light
                .shadow
                .get_or_insert_with(|| Shadow::default_for(light.kind))
                .method = m;
        }
        ShadowEdit::Resolution(r) => {
            if !SHADOW_RESOLUTIONS.contains(&r) {
                return Err(format!(
                    "resolution {r}: expected one of {}",
                    SHADOW_RESOLUTIONS.map(|r| r.to_string()).join(", ")
                ));
            }
            let Some(s) = &mut light.shadow else {
                return Err("the light casts no shadow (turn it on first)".into());
            };
            s.resolution = r;
        }
    }
    Ok(light.shadow != before)
}

/// After the light's size changed: PCSS without a size is not a valid scene, so it falls back
/// to PCF. True when it did.
pub fn fix_shadow_method(light: &mut Light) -> bool {
    let sized = has_size(light);
    match &mut light.shadow {
        Some(s) if s.method == ShadowMethod::Pcss && !sized => {
            s.method = ShadowMethod::Pcf;
            true
        }
        _ => false,
    }
}

/// The material `model` (a scene-format model name) with its defaults, as the decoder makes it
/// when a material gives only its model. Unknown names give the classic Phong.
pub fn default_material(model: &str) -> Material {
    Material::default_of(ModelKind::from_name(model).unwrap_or(ModelKind::Phong))
}

/// Switches a material to another model: Phong ↔ Blinn-Phong only flips `blinn`; any other
/// switch replaces the material with the model's defaults. Texture maps the new model does not
/// take are dropped (the decoder rejects them).
pub fn set_material_model(material: &mut Material, textures: &mut MaterialTextures, model: &str) {
    if material.name() == model {
        return;
    }
    let phong_pair = matches!(model, "phong" | "blinn_phong");
    match material {
        Material::Phong(crate::brdf::PhongParams { blinn, .. }) if phong_pair => {
            *blinn = model == "blinn_phong"
        }
        _ => *material = default_material(model),
    }
    let takes = slots_for_model(material.kind());
    for slot in crate::scene::TextureSlot::ALL {
        if !takes.contains(&slot) {
            *textures.get_mut(slot) = None;
        }
    }
    if textures.occlusion.is_none() && textures.orm.is_none() {
        textures.occlusion_strength = 1.0;
    }
    if textures.normal.is_none() {
        textures.normal_scale = 1.0;
    }
}

/// Makes the Fresnel term and its source agree as the decoder requires: the conductor Fresnel
/// needs a complex index (gold when there is none), the dielectric one a real index (the mean η
/// of a complex one).
pub fn fix_cook_torrance(p: &mut CookTorranceParams) {
    match (p.fresnel, p.specular) {
        (
            Fresnel::Conductor | Fresnel::ConductorExact,
            SpecularSource::Ior(_) | SpecularSource::F0(_),
        ) => {
            if let Some(gold) = metal_preset("gold") {
                p.specular = SpecularSource::Complex(gold);
            }
        }
        (Fresnel::Dielectric, SpecularSource::Complex(c)) => {
            let eta = (c.eta.x + c.eta.y + c.eta.z) / 3.0;
            p.specular = SpecularSource::Ior(if eta.is_finite() && eta > 0.0 {
                eta
            } else {
                1.5
            });
        }
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Shadow rows' rules: on gives the kind's defaults, a method turns the shadow on,
    /// PCSS needs a size, resolutions are the panel's, nothing changes on an error, and PCSS
    /// falls back to PCF when the size goes.
    #[test]
    fn shadow_edits_follow_the_panel() {
        let mut l = default_light(LightKind::Directional, None);
        l.shadow = None;
        assert_eq!(edit_shadow(&mut l, ShadowEdit::Off), Ok(false));
        assert_eq!(edit_shadow(&mut l, ShadowEdit::On), Ok(true));
        assert_eq!(l.shadow, Some(Shadow::default_for(LightKind::Directional)));
        assert_eq!(edit_shadow(&mut l, ShadowEdit::On), Ok(false));
        assert_eq!(edit_shadow(&mut l, ShadowEdit::Off), Ok(true));
        assert_eq!(l.shadow, None);
        assert_eq!(
            edit_shadow(&mut l, ShadowEdit::Method(ShadowMethod::Hard)),
            Ok(true)
        );
        assert_eq!(l.shadow.unwrap().method, ShadowMethod::Hard);
        assert_eq!(l.shadow.unwrap().cascades, 3);
        let e = edit_shadow(&mut l, ShadowEdit::Method(ShadowMethod::Pcss)).unwrap_err();
        assert!(e.contains("pcss needs the light's size"), "{e}");
        assert_eq!(l.shadow.unwrap().method, ShadowMethod::Hard);
        let e = edit_shadow(&mut l, ShadowEdit::Resolution(1000)).unwrap_err();
        assert!(e.contains("expected one of 256, 512"), "{e}");
        assert_eq!(edit_shadow(&mut l, ShadowEdit::Resolution(512)), Ok(true));
        assert_eq!(l.shadow.unwrap().resolution, 512);
        l.angular_radius_deg = 0.5;
        assert_eq!(
            edit_shadow(&mut l, ShadowEdit::Method(ShadowMethod::Pcss)),
            Ok(true)
        );
        assert!(!fix_shadow_method(&mut l));
        l.angular_radius_deg = 0.0;
        assert!(fix_shadow_method(&mut l));
        assert_eq!(l.shadow.unwrap().method, ShadowMethod::Pcf);
        l.shadow = None;
        let e = edit_shadow(&mut l, ShadowEdit::Resolution(512)).unwrap_err();
        assert!(e.contains("casts no shadow"), "{e}");
    }

    /// A field of n lights: n ranged point lights inside the bounds' horizontal extent, above
    /// the bottom; the grid evenly spaced, the random field the same every call; valid lights.
    #[test]
    fn light_fields_cover_the_bounds() {
        let bounds = Some((Vec3::new(-16.0, 0.0, -10.0), Vec3::new(16.0, 2.0, 10.0)));
        for field in [LightField::Grid, LightField::Random] {
            assert_eq!(LightField::from_name(field.name()), Some(field));
            let l = light_field(field, 256, bounds);
            assert_eq!(l.len(), 256);
            assert_eq!(light_field(field, 256, bounds), l, "deterministic");
            for x in &l {
                assert_eq!(x.kind, LightKind::Point);
                let p = x.position;
                assert!(
                    (-16.0..=16.0).contains(&p.x) && (-10.0..=10.0).contains(&p.z),
                    "{p}"
                );
                assert!(p.y > 0.0 && p.y < 2.0, "{p}");
                let r = x.range.unwrap();
                assert!(
                    (r - 4.0).abs() < 1e-5,
                    "spacing 32 / 16 = 2 m, range 4 m: {r}"
                );
                assert!(x.intensity > 0.0 && x.color.min_element() >= 0.3);
            }
            let distinct: std::collections::BTreeSet<(i32, i32)> = l
                .iter()
                .map(|x| ((x.position.x * 100.0) as i32, (x.position.z * 100.0) as i32))
                .collect();
            assert_eq!(distinct.len(), 256);
        }
        assert!(light_field(LightField::Grid, 0, None).is_empty());
        assert_eq!(light_field(LightField::Grid, 5, None).len(), 5);
        assert_eq!(LightField::from_name("spiral"), None);
    }
    use crate::brdf::{MetalRoughParams, PrincipledParams};

    /// The decoder's rules for a light (src/scene/decode.rs `light`).
    fn assert_valid_light(l: &Light) {
        assert!((l.direction.length() - 1.0).abs() < 1e-5, "{l:?}");
        assert!(l.color.min_element() >= 0.0 && l.intensity >= 0.0, "{l:?}");
        match l.kind {
            LightKind::Directional => assert_eq!(l.falloff, Falloff::None),
            LightKind::Point => assert_eq!(l.direction, Vec3::NEG_Y),
            LightKind::Spot => {}
        }
        if l.kind == LightKind::Spot {
            assert!(l.umbra_deg > 0.0 && l.umbra_deg <= 90.0, "{l:?}");
            if let Some(i) = l.inner_deg {
                assert!(i >= 0.0 && i < l.umbra_deg, "{l:?}");
            }
            assert!(l.exponent >= 0.0);
        } else {
            assert_eq!((l.umbra_deg, l.inner_deg, l.exponent), (180.0, None, 0.0));
        }
    }

    #[test]
    fn light_kind_changes_keep_lights_valid() {
        let kinds = [LightKind::Directional, LightKind::Point, LightKind::Spot];
        for from in kinds {
            for to in kinds {
                let mut l = default_light(from, None);
                assert_valid_light(&l);
                set_light_kind(&mut l, to);
                assert_eq!(l.kind, to);
                assert_valid_light(&l);
            }
        }
    }

    #[test]
    fn model_switch_uses_defaults_and_drops_foreign_maps() {
        use crate::scene::{MaterialTextures, TextureRef};
        let mut m = Material::MetalRough(MetalRoughParams {
            roughness: 0.1,
            ..Default::default()
        });
        let mut t = MaterialTextures {
            metallic: Some(TextureRef::new("m.png")),
            normal: Some(TextureRef::new("n.png")),
            ..Default::default()
        };
        set_material_model(&mut m, &mut t, "principled");
        assert_eq!(m, Material::Principled(PrincipledParams::default()));
        assert!(t.metallic.is_some());
        set_material_model(&mut m, &mut t, "lambert");
        assert_eq!(
            m,
            Material::Lambert(crate::brdf::LambertParams {
                albedo: Vec3::splat(0.8)
            })
        );
        assert!(t.metallic.is_none() && t.normal.is_some());
        set_material_model(&mut m, &mut t, "phong");
        assert_eq!(m, Material::default_phong(false));
        if let Material::Phong(crate::brdf::PhongParams { ks, .. }) = &mut m {
            *ks = 0.9;
        }
        // Phong ↔ Blinn-Phong keeps the parameters.
        set_material_model(&mut m, &mut t, "blinn_phong");
        assert!(
            matches!(m, Material::Phong(crate::brdf::PhongParams { blinn: true, ks, .. }) if ks == 0.9)
        );
    }

    #[test]
    fn cook_torrance_fresnel_and_source_agree() {
        let mut p = CookTorranceParams {
            fresnel: Fresnel::Conductor,
            ..Default::default()
        };
        fix_cook_torrance(&mut p);
        assert!(matches!(p.specular, SpecularSource::Complex(_)));
        p.fresnel = Fresnel::Dielectric;
        fix_cook_torrance(&mut p);
        assert!(matches!(p.specular, SpecularSource::Ior(eta) if eta > 0.0));
        p.fresnel = Fresnel::Schlick;
        let before = p;
        fix_cook_torrance(&mut p);
        assert_eq!(p, before);
    }

    #[test]
    fn default_materials_are_the_models_defaults() {
        for kind in ModelKind::ALL {
            let m = default_material(kind.name());
            assert_eq!(m, Material::default_of(kind));
            assert_eq!(m.name(), kind.name());
        }
        // An unknown name: the classic Phong, as the decoder's default.
        assert_eq!(default_material("bogus"), Material::default_phong(false));
    }

    #[test]
    fn unit_vectors_and_fog_gaps() {
        assert_eq!(unit_vec(Vec3::new(0.0, 3.0, 0.0)), Some(Vec3::Y));
        assert_eq!(unit_vec(Vec3::ZERO), None);
        assert_eq!(unit_vec(Vec3::new(f32::NAN, 0.0, 1.0)), None);
        let u = unit_vec(Vec3::new(1.0, 2.0, 2.0)).unwrap();
        assert!((u - Vec3::new(1.0, 2.0, 2.0) / 3.0).length() < 1e-7);
        assert_eq!(fog_gap(0.0), 1e-3);
        assert_eq!(fog_gap(-5000.0), 5.0);
    }
}
