//! Lookups only where shadows can fall (issue 15's cost): an object no caster can darken from a
//! light gets a pipeline without that light's lookup, and a small receiver (a floor) has its
//! lookups only inside the screen rectangle its possible shadows cover. The images must not
//! change: each scene here is rendered with the receiver test on and off
//! (`--no-shadow-receivers`) and compared, and a renderer whose objects move into another's
//! shadow switches pipelines and matches a fresh renderer.

mod common;

use common::*;
use glam::Vec3;
use luz::headless::Headless;

/// Renders `scene` (a path) to PNG with the receiver test on (two frames) and off; the `--verbose`
/// report of the run with it on.
fn on_and_off(scene: &str, name: &str) -> (Vec<u8>, Vec<u8>, String) {
    let dir = scratch(name);
    let png = |tag: &str| dir.join(format!("{tag}.png"));
    // Two frames: a one-frame render does not cull (its compile cost exceeds the frame's saving).
    let on = run(&mut luz_command([
        "render",
        scene,
        "--verbose",
        "--frames",
        "2",
        "-o",
        png("on").to_str().unwrap(),
    ]));
    assert_ran_clean(on.code, &on.stdout, &on.stderr);
    let off = run(&mut luz_command([
        "render",
        scene,
        "--no-shadow-receivers",
        "--verbose",
        "-o",
        png("off").to_str().unwrap(),
    ]));
    assert_ran_clean(off.code, &off.stdout, &off.stderr);
    assert!(
        off.stdout
            .contains("shadow receivers: not culled (--no-shadow-receivers;"),
        "{}",
        off.stdout
    );
    // Each image says how it was made.
    for (tag, want) in [("on", "on"), ("off", "off")] {
        let p = luz::imageio::provenance::read(&png(tag)).expect("provenance");
        assert_eq!(p.get("luz.shadow_receivers"), Some(want), "{tag}");
        assert_eq!(p.get("luz.instancing"), Some("on"), "{tag}");
    }
    let decode = |p: std::path::PathBuf| image::open(p).expect("png").to_rgba8().into_raw();
    (decode(png("on")), decode(png("off")), on.stdout)
}

/// The largest difference of two images' 8-bit codes, and the pixels that differ at all.
fn differences(a: &[u8], b: &[u8]) -> (u8, usize) {
    assert_eq!(a.len(), b.len());
    let max = a
        .iter()
        .zip(b)
        .map(|(x, y)| x.abs_diff(*y))
        .max()
        .unwrap_or(0);
    let pixels = a.chunks(4).zip(b.chunks(4)).filter(|(x, y)| x != y).count();
    (max, pixels)
}

/// The built-in scene: the floor keeps both lights' lookups inside its shadow rectangle only;
/// no sphere can be darkened by the sun (the others stand beside it, the floor below), the
/// gold one (nearest the lamp) by neither light: 5 of the 10 (object, light) lookups are
/// compiled out, and the image is the same to the last code value.
#[test]
fn the_built_in_scene_is_unchanged_with_fewer_lookups() {
    let scene = root().join("assets/scenes/default.json");
    let (on, off, report) = on_and_off(scene.to_str().unwrap(), "receivers_default");
    assert!(
        report.contains("shadow receivers: 5 of 10 (object, shadowed light) lookups compiled out")
            && report.contains("1 object(s) with lookups only inside"),
        "{report}"
    );
    assert_eq!(differences(&on, &off), (0, 0));
}

/// The shipped shadow scenes (contact and grazing shadows on the deferred path, whose one
/// lighting pass gets the lookups inside the rectangle of every receiver's shadows only;
/// alpha-tested casters on the forward path): the same image either way.
#[test]
fn the_shadow_scenes_are_unchanged() {
    for (name, says) in [
        (
            "contact_grazing",
            "shadow receivers (deferred lighting pass): 0 of 2 shadowed lights' lookups compiled \
             out (no caster can darken any object); lookups only inside the screen rectangle",
        ),
        ("alpha_casters", "4 object(s) with lookups only inside"),
    ] {
        let scene = root().join(format!("assets/scenes/shadows/{name}.json"));
        let (on, off, report) = on_and_off(scene.to_str().unwrap(), &format!("receivers_{name}"));
        assert!(report.contains(says), "{name}: {report}");
        assert_eq!(differences(&on, &off), (0, 0), "{name}");
    }
}

/// Two spheres side by side under a sun from the side and a lamp above, on a floor (MSAA: the
/// forward path; the deferred one lights every pixel in one pass and keeps its lookups): at first
/// neither sphere can shade the other from the sun; moved into a row along the sun's direction,
/// the far one can. The renderer updated in place must switch that sphere to a pipeline with the
/// lookup (built when the frame is prepared) and give exactly a fresh renderer's image.
#[test]
fn objects_moving_into_a_shadow_get_their_lookups_back() {
    let json = r#"{
        "camera": {"position": [0, 3, 7], "target": [0, 0.6, 0], "fov_y_deg": 45, "near": 0.1, "far": 50},
        "output": {"width": 160, "height": 90, "msaa": 4},
        "lights": [
            {"type": "directional", "direction": [1, -0.35, 0], "intensity": 2.0, "shadow": true},
            {"type": "point", "position": [0, 4, 1], "intensity": 20.0, "shadow": true}
        ],
        "materials": {"m": {"model": "lambert", "albedo": [0.8, 0.8, 0.8]}},
        "objects": [
            {"mesh": {"type": "plane", "size": [20, 20]}, "material": "m"},
            {"mesh": {"type": "sphere", "radius": 0.6}, "material": "m", "position": [-1.5, 0.6, -1.5]},
            {"mesh": {"type": "sphere", "radius": 0.6}, "material": "m", "position": [1.5, 0.6, 1.5]}
        ]
    }"#;
    let ctx = gpu_with(true);
    let mut scene = parse(json);
    let mut r = Headless::new(&ctx, &scene).expect("renderer");
    r.render().expect("frame");
    let before = r.shadow_receivers();
    // Neither sphere can shade the other from either light (3.2 m apart, the lamp above
    // between them): only the floor keeps lookups, inside its shadows' rectangle.
    assert_eq!(
        before,
        luz::render::forward::ReceiverStats {
            pairs: 6,
            skipped: 4,
            split: 1,
            deferred: false,
        }
    );
    assert_eq!(
        r.image().expect("readback").pixels,
        render_on(&ctx, &scene).pixels
    );

    // In a row along the sun's travel: the first sphere can shade the second.
    scene.objects[1].transform.position = Vec3::new(-1.5, 0.6, 0.0);
    scene.objects[2].transform.position = Vec3::new(0.3, 0.6, 0.0);
    r.update_scene(&scene).expect("update");
    r.render().expect("frame");
    let after = r.shadow_receivers();
    assert!(after.skipped < before.skipped, "{before:?} → {after:?}");
    let moved = r.image().expect("readback");
    let fresh = render_on(&ctx, &scene);
    assert_eq!(
        moved.pixels, fresh.pixels,
        "moved in place against a fresh renderer"
    );
    assert_no_validation_messages(&ctx);
    // And the moved scene is the same with every lookup everywhere.
    let moved_json = json
        .replace("[-1.5, 0.6, -1.5]", "[-1.5, 0.6, 0.0]")
        .replace("[1.5, 0.6, 1.5]", "[0.3, 0.6, 0.0]");
    let dir = scratch("receivers_moved");
    let file = dir.join("moved.json");
    std::fs::write(&file, moved_json).expect("write scene");
    let (on, off, report) = on_and_off(file.to_str().unwrap(), "receivers_moved_images");
    // The second sphere may be darkened by the first from the sun; the first shares its
    // pipeline (one instanced draw), so both keep the sun's lookup; neither needs the lamp's.
    assert!(
        report.contains("2 of 6 (object, shadowed light)"),
        "{report}"
    );
    assert_eq!(differences(&on, &off), (0, 0));
}
