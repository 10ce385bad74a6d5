//! Automatic LOD of meshes (issue 17) on lavapipe with validation on: the chain of a real model
//! built once however many objects use it, the levels chosen by distance and budget, the image
//! against full detail (FLIP), and budget 0 drawing every mesh whole.

mod common;

use common::*;

use luz::headless::{Headless, RenderOptions};
use luz::imageio::{FileFormat, LoadedImage};
use luz::scene::Scene;

/// `count` bunnies (the shared Stanford bunny, 69,451 triangles) in rows from 2 to ~60 units
/// away, some behind the camera, at `budget` px.
fn bunnies(count: usize, budget: f32) -> Option<Scene> {
    shared_dir("models/stanford-bunny.obj")?;
    let mut objects = Vec::new();
    for i in 0..count {
        let (row, col) = (i / 6, i % 6);
        objects.push(format!(
            r#"{{"mesh": {{"type": "obj", "path": "../../shared/models/stanford-bunny.obj"}}, "material": "m",
                "position": [{}, -0.33, {}], "rotation_deg": [0, {}, 0], "scale": [10, 10, 10]}}"#,
            (col as f32 - 2.5) * 1.8,
            4.0 - 3.5 * row as f32,
            (i * 47) % 360
        ));
    }
    let text = format!(
        r#"{{
        "camera": {{"position": [0, 1.6, 6], "target": [0, 0.5, -10], "up": [0, 1, 0], "fov_y_deg": 50, "near": 0.1, "far": 200}},
        "output": {{"width": 320, "height": 180, "msaa": 1, "tessellation_error_px": {budget}}},
        "lights": [{{"type": "directional", "direction": [-0.4, -1, -0.5], "intensity": 2.5}}],
        "ambient": [0.05, 0.05, 0.05],
        "materials": {{"m": {{"model": "lambert", "albedo": [0.7, 0.5, 0.4]}}}},
        "objects": [{}]
    }}"#,
        objects.join(",")
    );
    Some(luz::scene::parse(&text, &root().join("tests/lod.json")).expect("scene"))
}

fn mean_flip(scene: &Scene, a: &luz::imageio::LinearImage, b: &luz::imageio::LinearImage) -> f32 {
    let load = |img| {
        LoadedImage::from_linear(
            img,
            FileFormat::Png,
            scene.output.exposure,
            scene.output.tonemap,
        )
    };
    luz::diff::compare(&load(a), &load(b), &Default::default())
        .expect("same size")
        .flip_mean
}

/// Mean FLIP between the automatic levels and full detail, at the default budget and a loose one.
const MAX_FLIP_DEFAULT_BUDGET: f32 = 0.01;

#[test]
fn one_chain_per_mesh_levels_by_distance_and_flip_against_full_detail() {
    let Some(full_scene) = bunnies(48, 0.0) else {
        return;
    };
    let ctx = gpu();
    let options = RenderOptions::default();
    let mut full = Headless::with_options(&ctx, &full_scene, &options).unwrap();
    // 48 objects, one mesh: one chain (no cache: built here).
    assert_eq!(
        full.lod_stats(),
        luz::scene::lod::ChainStats {
            built: 1,
            loaded: 0,
            failed: 0
        }
    );
    // Budget 0: every object at level 0, every triangle of the objects in view drawn.
    let choices = full.lod_choices(&full_scene);
    assert_eq!(choices.len(), 48);
    assert!(
        choices.iter().all(|c| c.level == 0 && c.levels >= 5),
        "{choices:?}"
    );
    let in_view = choices.iter().filter(|c| c.visible).count() as u64;
    assert!((12..48).contains(&in_view), "{in_view} in view");
    assert_eq!(full.triangles_drawn(), in_view * 69_451);
    full.render().unwrap();
    let full_image = full.image().unwrap();

    let auto_scene = bunnies(48, luz::scene::DEFAULT_TESSELLATION_ERROR_PX).unwrap();
    let mut auto = Headless::with_options(&ctx, &auto_scene, &options).unwrap();
    let choices = auto.lod_choices(&auto_scene);
    // Farther rows, coarser levels (never finer); the nearest row is finer than the farthest.
    let level = |row: usize| choices[row * 6 + 2].level;
    for row in 2..7 {
        assert!(level(row + 1) >= level(row), "{choices:?}");
    }
    assert!(level(7) > level(2), "{choices:?}");
    for c in &choices {
        assert!(
            c.error_px <= luz::scene::DEFAULT_TESSELLATION_ERROR_PX,
            "{c:?}"
        );
    }
    let drawn = auto.triangles_drawn();
    assert!(drawn < full.triangles_drawn() / 2, "{drawn} triangles");
    auto.render().unwrap();
    let flip = mean_flip(&auto_scene, &full_image, &auto.image().unwrap());
    eprintln!(
        "default budget: {drawn} of {} triangles, mean FLIP {flip:.5} against full detail",
        full.triangles_drawn()
    );
    assert!(flip <= MAX_FLIP_DEFAULT_BUDGET, "mean FLIP {flip}");
    assert_no_validation_messages(&ctx);
}
