//! The renderer answers what an edit costs (issue 33, part 2): for each kind of edit the viewer
//! offers, `Headless::apply` gets the expected answer from the shape the passes were built for
//! (`render::world::Change`: in place, new pipelines, a rebuild, with or without the
//! environment), and the next picture equals, bit for bit, a fresh renderer's picture of the
//! edited scene. The edits run one after another on one renderer, as in the viewer, so a stale
//! shadow map, pipeline or buffer left by any of them shows. Validation on, zero messages.

mod common;

use common::*;

use glam::Vec3;
use luz::brdf::Fresnel;
use luz::headless::{Headless, RenderOptions};
use luz::render::ibl::IblSettings;
use luz::render::world::Change;
use luz::scene::edit::{
    default_light, edit_shadow, set_light_kind, set_material_model, ShadowEdit,
};
use luz::scene::{LightKind, Material, Saturation, Scene, Shading};

const SCENE: &str = r#"{
  "camera": {"position": [0, 1.4, 4], "target": [0, 0.4, 0], "up": [0, 1, 0], "fov_y_deg": 45},
  "output": {"width": 96, "height": 64, "msaa": 1},
  "ambient": [0.03, 0.03, 0.03],
  "lights": [
    {"type": "directional", "direction": [-0.4, -1, -0.5], "intensity": 2, "shadow": true},
    {"type": "point", "position": [1.5, 2, 1.5], "intensity": 6}
  ],
  "environment": {"procedural": "studio", "intensity": 0.5, "show_background": false},
  "materials": {
    "floor": {"model": "lambert", "albedo": [0.6, 0.6, 0.6]},
    "ct": {"model": "cook_torrance", "color": [0.9, 0.4, 0.2], "kd": 0.6, "roughness": 0.3},
    "mr": {"model": "metal_rough", "base_color": [0.8, 0.7, 0.3], "metallic": 1, "roughness": 0.4},
    "chalk": {"model": "phong", "kd": 0.7, "ks": 0.2, "shininess": 20, "diffuse_color": [0.7, 0.7, 0.8]}
  },
  "objects": [
    {"name": "floor", "mesh": {"type": "plane", "size": [6, 6]}, "material": "floor"},
    {"name": "ball", "mesh": {"type": "sphere", "radius": 0.5}, "material": "ct", "position": [-0.7, 0.5, 0]},
    {"name": "ico", "mesh": {"type": "icosphere", "radius": 0.45}, "material": "mr", "position": [0.7, 0.45, 0]},
    {"name": "box", "mesh": {"type": "cube", "size": 0.5}, "material": "chalk", "position": [0, 0.25, -1]}
  ]
}"#;

fn options(cache: &std::path::Path) -> RenderOptions {
    RenderOptions {
        ibl: IblSettings::fast(),
        cache_dir: Some(cache.to_path_buf()),
        ..RenderOptions::default()
    }
}

fn material(scene: &mut Scene, name: &str) -> usize {
    scene.materials.iter().position(|m| m.name == name).unwrap()
}

/// One edit of each kind the viewer's panels and script offer, the answer it must get, and a
/// name for the messages.
type Edit = (&'static str, fn(&mut Scene), Change);

const IN_PLACE: Change = Change::InPlace;
const PIPELINES: Change = Change::RebuildPipelines;
const REBUILD: Change = Change::Rebuild { environment: false };
const REBUILD_ENV: Change = Change::Rebuild { environment: true };

fn edits() -> Vec<Edit> {
    vec![
        (
            "camera orbit",
            |s| s.camera.position = Vec3::new(2.5, 2.0, 3.0),
            IN_PLACE,
        ),
        (
            "light colour and intensity",
            |s| {
                s.lights[1].color = Vec3::new(1.0, 0.5, 0.3);
                s.lights[1].intensity = 9.0;
            },
            IN_PLACE,
        ),
        (
            "point light moved",
            |s| s.lights[1].position = Vec3::new(-1.5, 1.5, 1.0),
            IN_PLACE,
        ),
        (
            "sun turned (its shadow follows)",
            |s| s.lights[0].direction = Vec3::new(0.5, -1.0, -0.3).normalize(),
            IN_PLACE,
        ),
        (
            "material value",
            |s| {
                let i = material(s, "mr");
                if let Material::MetalRough(p) = &mut s.materials[i].material {
                    p.roughness = 0.8;
                    p.base_color = Vec3::new(0.3, 0.5, 0.9);
                }
            },
            IN_PLACE,
        ),
        (
            "object moved",
            |s| s.objects[2].transform.position = Vec3::new(0.9, 0.7, 0.3),
            IN_PLACE,
        ),
        (
            "ambient, background and exposure",
            |s| {
                s.ambient = Vec3::splat(0.1);
                s.output.background = Vec3::new(0.1, 0.2, 0.3);
                s.output.exposure = 0.5;
            },
            IN_PLACE,
        ),
        (
            "shading phong to flat",
            |s| s.objects[1].shading = Shading::Flat,
            PIPELINES,
        ),
        (
            "object given another material",
            |s| s.objects[2].material = material(s, "chalk"),
            PIPELINES,
        ),
        (
            "material model changed",
            |s| {
                let i = material(s, "chalk");
                let m = &mut s.materials[i];
                set_material_model(&mut m.material, &mut m.textures, "oren_nayar");
            },
            PIPELINES,
        ),
        (
            "Fresnel term selected",
            |s| {
                let i = material(s, "ct");
                if let Material::CookTorrance(p) = &mut s.materials[i].material {
                    p.fresnel = Fresnel::SchlickSg;
                }
            },
            PIPELINES,
        ),
        (
            "point light made a spot",
            |s| set_light_kind(&mut s.lights[1], LightKind::Spot),
            PIPELINES,
        ),
        (
            "fog on",
            |s| {
                s.fog = Some(luz::scene::Fog {
                    z_a: 2.0,
                    z_b: 9.0,
                    s_a: 0.0,
                    s_b: 1.0,
                    color: Vec3::new(0.5, 0.5, 0.6),
                })
            },
            PIPELINES,
        ),
        (
            "fog distance",
            |s| s.fog.as_mut().unwrap().z_b = 6.0,
            IN_PLACE,
        ),
        (
            "saturation mode (over a brighter sun)",
            |s| {
                s.saturation = Saturation::Normalize;
                s.lights[0].intensity = 8.0;
            },
            PIPELINES,
        ),
        (
            "shadow resolution",
            |s| {
                edit_shadow(&mut s.lights[0], ShadowEdit::Resolution(512)).unwrap();
            },
            REBUILD,
        ),
        (
            "light added",
            |s| {
                s.lights.push(default_light(
                    LightKind::Point,
                    Some((Vec3::splat(-1.0), Vec3::ONE)),
                ))
            },
            REBUILD,
        ),
        ("msaa 1 to 4", |s| s.output.msaa = 4, REBUILD),
        (
            "environment intensity",
            |s| s.environment.as_mut().unwrap().intensity = 1.0,
            REBUILD_ENV,
        ),
        ("environment removed", |s| s.environment = None, REBUILD_ENV),
    ]
}

#[test]
fn each_edit_gets_its_answer_and_the_picture_of_a_fresh_render() {
    let dir = scratch("world-edits");
    let opts = options(&dir);
    let mut scene = luz::scene::parse(SCENE, &dir.join("world.json")).expect("scene");
    let ctx = gpu();
    let mut renderer = Headless::with_options(&ctx, &scene, &opts).unwrap();
    renderer.render().unwrap();
    let mut seen = std::collections::BTreeSet::new();
    for (name, edit, expected) in edits() {
        let before = renderer.image().unwrap();
        edit(&mut scene);
        let change = renderer
            .apply(&scene)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(change, expected, "{name}");
        seen.insert(format!("{change:?}"));
        renderer.render().unwrap();
        let edited = renderer.image().unwrap();
        let mut fresh = Headless::with_options(&ctx, &scene, &opts).unwrap();
        fresh.render().unwrap();
        let want = fresh.image().unwrap();
        let differing = edited
            .pixels
            .iter()
            .zip(&want.pixels)
            .filter(|(a, b)| a.map(f32::to_bits) != b.map(f32::to_bits))
            .count();
        assert_eq!(
            differing, 0,
            "{name} ({change:?}): {differing} pixels differ from a fresh render"
        );
        // The edit shows: the picture moved.
        let moved = edited
            .pixels
            .iter()
            .zip(&before.pixels)
            .filter(|(a, b)| a != b)
            .count();
        assert!(moved > 0, "{name}: the picture did not change");
    }
    assert_eq!(seen.len(), 4, "every answer was given: {seen:?}");
    assert_no_validation_messages(&ctx);
}

/// An edit the passes cannot take in place is refused by `update_scene` with a message naming
/// what changed, and the renderer keeps drawing the scene it was built for; `apply` of a new
/// output size is refused the same way.
#[test]
fn update_refuses_a_shape_change_and_apply_refuses_a_new_size() {
    let dir = scratch("world-refused");
    let opts = options(&dir);
    let scene = luz::scene::parse(SCENE, &dir.join("world.json")).expect("scene");
    let ctx = gpu();
    let mut renderer = Headless::with_options(&ctx, &scene, &opts).unwrap();
    renderer.render().unwrap();
    let first = renderer.image().unwrap();
    let mut more = scene.clone();
    more.lights.push(default_light(
        LightKind::Point,
        Some((Vec3::splat(-1.0), Vec3::ONE)),
    ));
    let e = renderer.update_scene(&more).unwrap_err().to_string();
    assert!(e.contains("2 lights → 3"), "{e}");
    assert!(e.contains("Rebuild"), "{e}");
    let mut bigger = scene.clone();
    bigger.output.width = 128;
    let e = renderer.apply(&bigger).unwrap_err().to_string();
    assert!(
        e.contains("output size 128×64 differs from the renderer's 96×64"),
        "{e}"
    );
    renderer.render().unwrap();
    assert_eq!(renderer.image().unwrap().pixels, first.pixels);
    assert_no_validation_messages(&ctx);
}
