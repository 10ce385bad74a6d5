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
