//! Instancing (issue 17) on lavapipe with validation on: objects sharing mesh, LOD level,
//! pipeline and material are one instanced draw, and the image is the same, bit for bit, as one
//! draw per object (`Switches::instancing` off, `--no-instancing`), on the forward path (flat,
//! Gouraud and Phong shading, a shadowed sun, meshes with and without LOD chains) and on the
//! deferred path. The switch is a render option, so both renders run in one process.

mod common;

use common::*;

use luz::headless::{Headless, RenderOptions};
use luz::render::forward::RenderPath;
use luz::scene::Scene;

/// 30 bunnies (the shared Stanford bunny) in rows from 2 to ~40 units away, the materials `a`, `b`,
/// `c` in turn, then 8 spheres of material `a`; `shading(i)`: bunny `i`'s shading frequency.
fn scene(shading: impl Fn(usize) -> &'static str, shadow: bool) -> Option<Scene> {
    shared_dir("models/stanford-bunny.obj")?;
    let mut objects = Vec::new();
    for i in 0..30 {
        let (row, col) = (i / 6, i % 6);
        objects.push(format!(
            r#"{{"mesh": {{"type": "obj", "path": "../../shared/models/stanford-bunny.obj"}},
                "material": "{}", "shading": "{}",
                "position": [{}, -0.33, {}], "rotation_deg": [0, {}, 0], "scale": [10, 10, 10]}}"#,
            ["a", "b", "c"][i % 3],
            shading(i),
            (col as f32 - 2.5) * 1.8,
            4.0 - 8.0 * row as f32,
            (i * 47) % 360
        ));
    }
    for i in 0..8 {
        objects.push(format!(
            r#"{{"mesh": {{"type": "sphere", "radius": 0.4}}, "material": "a",
                "position": [{}, 1.5, -3]}}"#,
            i as f32 - 3.5
        ));
    }
    let text = format!(
        r#"{{
        "camera": {{"position": [0, 1.6, 6], "target": [0, 0.5, -10], "up": [0, 1, 0], "fov_y_deg": 50, "near": 0.1, "far": 200}},
        "output": {{"width": 320, "height": 180, "msaa": 1}},
        "lights": [{{"type": "directional", "direction": [-0.4, -1, -0.5], "intensity": 2.5, "shadow": {shadow}}}],
        "ambient": [0.05, 0.05, 0.05],
        "materials": {{
            "a": {{"model": "lambert", "albedo": [0.7, 0.5, 0.4]}},
            "b": {{"model": "lambert", "albedo": [0.3, 0.6, 0.4]}},
            "c": {{"model": "lambert", "albedo": [0.8, 0.7, 0.3]}}
        }},
        "objects": [{}]
    }}"#,
        objects.join(",")
    );
    Some(luz::scene::parse(&text, &root().join("tests/instancing.json")).expect("scene"))
}

/// Renders `scene` on `path` with instancing on or off: the image, the render path taken, the
/// draw calls and the objects drawn.
fn render(
    ctx: &std::sync::Arc<luz::vk::Context>,
    scene: &Scene,
    path: RenderPath,
    instancing: bool,
) -> (luz::imageio::LinearImage, &'static str, (usize, usize)) {
    let options = RenderOptions {
        render_path: path,
        switches: luz::render::forward::Switches {
            instancing,
            ..Default::default()
        },
        ..RenderOptions::default()
    };
    let mut r = Headless::with_options(ctx, scene, &options).unwrap();
    r.render().unwrap();
    (r.image().unwrap(), r.render_path(), r.draw_calls())
}

#[test]
fn instanced_draws_give_the_same_image_with_fewer_draw_calls() {
    let shadings = |i: usize| ["phong", "phong", "phong", "flat", "gouraud"][i / 6];
    let Some(mixed) = scene(shadings, true) else {
        return;
    };
    let phong = scene(|_| "phong", false).unwrap();
    let ctx = gpu();
    for (name, scene, path, taken) in [
        (
            "mixed shading, shadowed",
            &mixed,
            RenderPath::Forward,
            "forward",
        ),
        ("Phong", &phong, RenderPath::Forward, "forward"),
        ("Phong", &phong, RenderPath::Auto, "deferred"),
    ] {
        let (single, p1, (calls_off, objects_off)) = render(&ctx, scene, path, false);
        let (instanced, p2, (calls_on, objects_on)) = render(&ctx, scene, path, true);
        assert_eq!((p1, p2), (taken, taken), "{name}");
        eprintln!(
            "{name}, {taken}: {objects_on} objects, {calls_off} draw calls without instancing, \
             {calls_on} with"
        );
        // Without instancing one draw per object in view; with it, one per (shading, material,
        // mesh, level): far fewer.
        assert_eq!(objects_on, objects_off, "{name}");
        assert_eq!(calls_off, objects_off, "{name}");
        assert!(objects_off >= 20, "{name}: {objects_off} objects in view");
        assert!(
            calls_on * 2 <= calls_off,
            "{name}: {calls_on} of {calls_off}"
        );
        let differing = single
            .pixels
            .iter()
            .zip(&instanced.pixels)
            .filter(|(a, b)| a.map(f32::to_bits) != b.map(f32::to_bits))
            .count();
        assert_eq!(differing, 0, "{name}, {taken}: pixels differ");
        // Not a blank image: the objects are there.
        let background = single.pixels[0];
        let covered = single.pixels.iter().filter(|p| **p != background).count();
        assert!(
            covered > single.pixels.len() / 10,
            "{name}: {covered} pixels"
        );
    }
    assert_no_validation_messages(&ctx);
}
