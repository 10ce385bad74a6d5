//! Panel tests: drawing without input edits nothing, every model draws, the profiler, the keys.

use super::*;
use crate::profiler::FrameSample;
use egui::Rect;
use std::path::Path;

fn profiler() -> Profiler {
    let mut p = Profiler::new(120);
    for i in 0..200 {
        p.push(FrameSample {
            frame_ms: if i % 50 == 49 {
                40.0
            } else {
                16.0 + (i % 3) as f64
            },
            cpu_ms: 2.0,
            gpu_ms: vec![("forward", 5.0), ("tonemap", 0.4)],
        });
    }
    p
}

/// Runs a few frames of `draw` without input; returns every action.
fn run(scene: &mut Scene, settings: &mut ViewSettings) -> Vec<UiAction> {
    let ctx = egui::Context::default();
    let mut state = UiState {
        expand_all: true,
        ..Default::default()
    };
    let profiler = profiler();
    let mut all = Vec::new();
    for _ in 0..3 {
        let input = egui::RawInput {
            screen_rect: Some(Rect::from_min_size(Pos2::ZERO, Vec2::new(1280.0, 720.0))),
            ..Default::default()
        };
        let _ = ctx.run_ui(input, |ui| {
            all.extend(draw(ui, scene, settings, &profiler, &mut state));
        });
    }
    all
}

#[test]
fn draws_without_input_and_edits_nothing() {
    let ibl = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/ibl/seed001_grid_sky.json");
    let scenes = [
        crate::scene::default_scene(),
        crate::scene::parse(crate::scene::DEFAULT_SCENE_JSON, Path::new("default.json"))
            .expect("default scene"),
        crate::scene::load(&ibl).expect("ibl scene"),
    ];
    for mut scene in scenes {
        let before_lights = scene.lights.clone();
        let before_materials = scene.materials.clone();
        let before_env = scene.environment.clone();
        for (panels, help) in [(true, false), (true, true), (false, true), (false, false)] {
            let mut settings = ViewSettings {
                show_panels: panels,
                show_help: help,
                ..Default::default()
            };
            let actions = run(&mut scene, &mut settings);
            assert!(actions.is_empty(), "{actions:?}");
            assert_eq!(settings.show_help, help);
        }
        assert_eq!(scene.lights, before_lights);
        assert_eq!(scene.materials, before_materials);
        assert_eq!(scene.environment, before_env);
    }
}

#[test]
fn every_material_model_draws() {
    let mut scene = crate::scene::default_scene();
    for model in crate::brdf::ModelKind::ALL.map(|k| k.name()) {
        let m = &mut scene.materials[0];
        set_material_model(&mut m.material, &mut m.textures, model);
        assert_eq!(m.material.name(), model);
        let mut settings = ViewSettings::default();
        assert!(run(&mut scene, &mut settings).is_empty());
    }
    // Every light kind and environment source.
    for kind in [LightKind::Directional, LightKind::Point, LightKind::Spot] {
        scene.lights.push(default_light(kind, scene.bounds()));
    }
    for source in [
        EnvSource::Studio,
        EnvSource::Uniform(Vec3::ONE),
        EnvSource::Sky {
            sun_direction: DEFAULT_SUN_DIRECTION.normalize(),
            sun_intensity: 3.0,
        },
    ] {
        let mut env = Environment::new(source);
        env.specular_method = SpecularMethod::Importance;
        scene.environment = Some(env);
        let mut settings = ViewSettings::default();
        assert!(run(&mut scene, &mut settings).is_empty());
    }
}

#[test]
fn keys_are_listed() {
    assert!(KEYS.iter().any(|(k, _)| *k == "Esc"));
    // The lab's keys (issue 20): L opens the lab panel, B switches sides in toggle mode.
    assert!(KEYS.iter().any(|(k, _)| *k == "L") && KEYS.iter().any(|(k, _)| *k == "B"));
    assert_eq!(KEYS.len(), 13);
}
