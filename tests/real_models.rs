//! The real OBJ files in ../shared/models (Stanford bunny, Utah teapot, Suzanne, Spot, cow) load
//! through a scene and render on lavapipe with every shading frequency: lit, finite, validation
//! clean. Skips visibly when ../shared is absent (a fresh clone of luz alone).

mod common;

use common::*;

#[test]
fn real_models_render() {
    let Some(models) = shared_dir("models") else {
        return;
    };
    let ctx = gpu();
    for file in [
        "stanford-bunny.obj",
        "teapot.obj",
        "suzanne.obj",
        "spot.obj",
        "cow.obj",
    ] {
        for shading in ["flat", "gouraud", "phong"] {
            let json = format!(
                r#"{{
                "camera": {{"position": [0, 0.5, 4], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 40, "near": 0.05, "far": 50}},
                "output": {{"width": 160, "height": 120}},
                "ambient": [0.1, 0.1, 0.1],
                "lights": [{{"type": "directional", "direction": [-0.4, -0.7, -0.6], "color": [1, 1, 1], "intensity": 2}}],
                "materials": {{"m": {{"model": "metal_rough", "base_color": [0.8, 0.6, 0.4], "metallic": 0, "roughness": 0.5}}}},
                "objects": [{{"mesh": {{"type": "obj", "path": "{}"}}, "material": "m", "shading": "{shading}"}}]
            }}"#,
                models.join(file).display()
            );
            let mut scene = parse(&json);
            // Frame the model: centre it and scale it to a 2-unit box.
            let (lo, hi) = scene.bounds().expect("the model has vertices");
            let scale = 2.0 / (hi - lo).max_element();
            for o in &mut scene.objects {
                o.transform.scale = glam::Vec3::splat(scale);
                o.transform.position = -(lo + hi) * 0.5 * scale;
            }
            let img = render_on(&ctx, &scene);
            assert_eq!(nan_count(&img), 0, "{file} {shading}: NaN/Inf");
            let lit = img
                .pixels
                .iter()
                .filter(|p| p[0] + p[1] + p[2] > 0.05)
                .count();
            assert!(
                lit > 300,
                "{file} {shading}: only {lit} lit pixels (scale/placement or loading is wrong)"
            );
        }
    }
    assert_no_validation_messages(&ctx);
}

/// A model file is a scene (issue 16): `scene::load` of a bare OBJ gives the model, the default
/// rig and a camera that frames it. Rendered against the same scene without the model, the model
/// covers a sensible share of the image, inside it, and is shaded (not one flat colour).
#[test]
fn model_files_open_as_scenes() {
    let Some(models) = shared_dir("models") else {
        return;
    };
    let ctx = gpu();
    for file in ["stanford-bunny.obj", "spot.obj", "teapot.obj"] {
        let mut scene = luz::scene::load(&models.join(file)).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(scene.objects.len(), 1, "{file}");
        assert!(
            scene.environment.is_some() && !scene.lights.is_empty(),
            "{file}: the rig"
        );
        scene.override_size(Some(240), Some(135));
        let render = |s: &luz::scene::Scene| {
            let mut r = luz::headless::Headless::with_options(
                &ctx,
                s,
                &luz::headless::RenderOptions {
                    ibl: luz::render::ibl::IblSettings::fast(),
                    ..Default::default()
                },
            )
            .unwrap_or_else(|e| panic!("{file}: {e}"));
            r.render().unwrap();
            r.image().unwrap()
        };
        let with = render(&scene);
        let mut empty = scene.clone();
        empty.objects.clear();
        let without = render(&empty);
        assert_eq!(nan_count(&with), 0, "{file}: NaN/Inf");
        let (w, h) = (with.width as usize, with.height as usize);
        let (mut covered, mut lo, mut hi) = (Vec::new(), (w, h), (0, 0));
        for (i, (a, b)) in with.pixels.iter().zip(&without.pixels).enumerate() {
            if (0..3).any(|c| (a[c] - b[c]).abs() > 1e-3) {
                let (x, y) = (i % w, i / w);
                covered.push(a[0] + a[1] + a[2]);
                lo = (lo.0.min(x), lo.1.min(y));
                hi = (hi.0.max(x), hi.1.max(y));
            }
        }
        let share = covered.len() as f32 / (w * h) as f32;
        assert!(
            (0.05..0.8).contains(&share),
            "{file}: the model covers {share} of the image"
        );
        assert!(
            lo.0 > 0 && lo.1 > 0 && hi.0 < w - 1 && hi.1 < h - 1,
            "{file}: cut by the frame"
        );
        assert!(
            (hi.1 - lo.1) as f32 > 0.3 * h as f32 || (hi.0 - lo.0) as f32 > 0.3 * w as f32,
            "{file}: framed too small ({lo:?} to {hi:?})"
        );
        covered.sort_by(f32::total_cmp);
        let (dark, bright) = (covered[covered.len() / 10], covered[covered.len() * 9 / 10]);
        assert!(
            bright > 1.5 * dark,
            "{file}: flat shading? 10th/90th percentiles {dark} / {bright}"
        );
    }
    assert_no_validation_messages(&ctx);
}
