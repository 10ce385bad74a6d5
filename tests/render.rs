//! Foundation tests on lavapipe with validation on: golden image of the default scene, determinism,
//! and the Lambert analytic oracle.

mod common;

use common::*;

/// The embedded default scene against its golden, at a reduced size to keep the suite quick.
#[test]
fn default_scene_golden() {
    let mut scene = luz::scene::default_scene();
    scene.output.width = 640;
    scene.output.height = 360;
    // The case file (`luz golden tests/golden`) loads the same scene from its file.
    assert_same_scene(&golden_scene("default_640x360"), &scene);
    let img = render(&scene);
    // Lit spheres: the image is not black and has no NaN.
    let lum: f64 = img
        .pixels
        .iter()
        .map(|p| (p[0] + p[1] + p[2]) as f64 / 3.0)
        .sum::<f64>()
        / img.pixels.len() as f64;
    assert!(lum > 0.05, "default scene is nearly black (mean {lum})");
    check_golden("default_640x360", &scene, &img, Tolerance::default());
}

/// The same scene rendered twice gives identical bytes.
#[test]
fn determinism() {
    let mut scene = luz::scene::default_scene();
    scene.output.width = 320;
    scene.output.height = 180;
    let a = render(&scene);
    let b = render(&scene);
    let bytes = |i: &luz::imageio::LinearImage| -> Vec<u8> {
        i.pixels
            .iter()
            .flat_map(|p| p.iter().flat_map(|c| c.to_le_bytes()))
            .collect()
    };
    assert!(bytes(&a) == bytes(&b), "two renders of one scene differ");
}

/// A plane under one directional light with a Lambert material: every pixel equals
/// albedo/π · E · cosθ to 1e-4 relative.
#[test]
fn lambert_plane_oracle() {
    let dir = glam::Vec3::new(-0.3, -1.0, -0.2).normalize();
    let json = format!(
        r#"{{
        "camera": {{"position": [0, 2, 0], "target": [0, 0, 0], "up": [0, 0, -1], "fov_y_deg": 60, "near": 0.1, "far": 10}},
        "output": {{"width": 64, "height": 48, "background": [0, 0, 0]}},
        "ambient": [0, 0, 0],
        "lights": [{{"type": "directional", "direction": [{}, {}, {}], "color": [1, 1, 1], "intensity": 2.5}}],
        "materials": {{"m": {{"model": "lambert", "albedo": [0.8, 0.5, 0.2]}}}},
        "objects": [{{"mesh": {{"type": "plane", "size": [20, 20]}}, "material": "m"}}]
    }}"#,
        dir.x, dir.y, dir.z
    );
    let scene = parse(&json);
    let img = render(&scene);
    let cos = -dir.y;
    let albedo = [0.8f32, 0.5, 0.2];
    let mut worst = 0.0f32;
    for p in &img.pixels {
        for c in 0..3 {
            let expected = albedo[c] / std::f32::consts::PI * 2.5 * cos;
            let rel = (p[c] - expected).abs() / expected;
            worst = worst.max(rel);
        }
    }
    assert!(worst <= 1e-4, "worst relative error {worst} > 1e-4");
}

/// Frustum culling (issue 17): objects wholly outside the view (behind the camera, beyond the
/// far plane, off to a side) are not drawn, and the image is exactly the one without them, on
/// the forward and the deferred path; an object that only pokes into the view is drawn.
#[test]
fn frustum_culling_changes_no_pixel() {
    let objects_in = r#"
        {"mesh": {"type": "sphere", "segments": 24, "rings": 12}, "material": "m", "position": [0, 0.5, 0]},
        {"mesh": {"type": "cube", "size": 1}, "material": "m", "position": [1.5, 0.5, -1], "rotation_deg": [0, 30, 0]},
        {"mesh": {"type": "sphere", "radius": 2, "segments": 24, "rings": 12}, "material": "m", "position": [5.2, 0.5, 0]}"#;
    let objects_out = r#",
        {"mesh": {"type": "sphere", "segments": 24, "rings": 12}, "material": "m", "position": [0, 1, 9]},
        {"mesh": {"type": "cube", "size": 1}, "material": "m", "position": [0, 0, -80]},
        {"mesh": {"type": "cone", "radius": 0.5, "height": 1}, "material": "m", "position": [30, 0, 0]}"#;
    let scene = |objects: &str, (model, msaa): (&str, u32)| {
        parse(&format!(
            r#"{{
            "camera": {{"position": [0, 1.5, 5], "target": [0, 0.5, 0], "up": [0, 1, 0], "fov_y_deg": 50, "near": 0.1, "far": 40}},
            "output": {{"width": 160, "height": 90, "msaa": {msaa}}},
            "lights": [{{"type": "point", "position": [2, 4, 3], "intensity": 30}}],
            "materials": {{"m": {model}}},
            "objects": [{objects}]
        }}"#
        ))
    };
    let ctx = gpu();
    // One sample: the deferred path; MSAA 4x: the forward path.
    for model in [
        (r#"{"model": "phong", "kd": 0.7}"#, 1),
        (
            r#"{"model": "metal_rough", "base_color": [0.8, 0.5, 0.3], "metallic": 0.5, "roughness": 0.4}"#,
            4,
        ),
    ] {
        let all = scene(&format!("{objects_in}{objects_out}"), model);
        let visible_only = scene(objects_in, model);
        let mut r = luz::headless::Headless::new(&ctx, &all).unwrap();
        r.render().unwrap();
        let path = if model.1 == 1 { "deferred" } else { "forward" };
        assert_eq!(r.render_path(), path, "{model:?}");
        assert_eq!(
            r.drawn_objects(),
            (3, 6),
            "{model:?}: the three outside are culled"
        );
        let with = r.image().unwrap();
        let without = render_on(&ctx, &visible_only);
        let differ = with
            .pixels
            .iter()
            .zip(&without.pixels)
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(differ, 0, "{model:?}: {differ} pixels differ");
    }
    assert_no_validation_messages(&ctx);
}
