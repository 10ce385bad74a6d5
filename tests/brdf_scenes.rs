//! Golden images of the physically based scenes: seed 000's 20-sphere grid and demo01 (Cook-Torrance
//! and Principled), seed 001's metallic × roughness grid, Beckmann vs GGX, separable vs correlated
//! Smith (assets/scenes/brdf/), and the per-model showcase scenes (assets/scenes/models/).

mod common;

use common::*;

fn golden(dir: &str, name: &str, size: Option<(u32, u32)>) {
    let mut scene = luz::scene::load(
        &root()
            .join("assets/scenes")
            .join(dir)
            .join(format!("{name}.json")),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    if let Some((w, h)) = size {
        scene.output.width = w;
        scene.output.height = h;
    }
    // The case file (what `luz golden tests/golden` renders) makes the same scene.
    assert_same_scene(&golden_scene(&format!("{dir}_{name}")), &scene);
    let img = render(&scene);
    check_golden(&format!("{dir}_{name}"), &scene, &img, Tolerance::default());
}

const HALF: Option<(u32, u32)> = Some((640, 360));

#[test]
fn seed000_spheres() {
    golden("brdf", "seed000_spheres", HALF);
}
#[test]
fn seed000_demo01_cook_torrance() {
    golden("brdf", "seed000_demo01_cook_torrance", HALF);
}
#[test]
fn seed000_demo01_principled() {
    golden("brdf", "seed000_demo01_principled", HALF);
}
#[test]
fn seed001_grid() {
    golden("brdf", "seed001_grid", HALF);
}
#[test]
fn beckmann_vs_ggx() {
    golden("brdf", "beckmann_vs_ggx", HALF);
}
#[test]
fn smith_separable_vs_correlated() {
    golden("brdf", "smith_separable_vs_correlated", HALF);
}

#[test]
fn every_model_showcase() {
    for m in [
        "lambert",
        "phong",
        "blinn_phong",
        "cook_torrance",
        "metal_rough",
        "principled",
        "oren_nayar",
    ] {
        golden("models", m, None);
    }
}

/// Every scene in assets/scenes/brdf and assets/scenes/models has a golden above.
#[test]
fn every_scene_has_a_golden() {
    let src = std::fs::read_to_string(root().join("tests/brdf_scenes.rs")).unwrap();
    for dir in ["brdf", "models"] {
        for e in std::fs::read_dir(root().join("assets/scenes").join(dir)).unwrap() {
            let stem = e
                .unwrap()
                .path()
                .file_stem()
                .unwrap()
                .to_string_lossy()
                .into_owned();
            assert!(
                src.contains(&format!("\"{stem}\"")),
                "{dir}/{stem} has no golden test"
            );
        }
    }
}
