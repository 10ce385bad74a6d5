//! Orthographic cameras (issue 16): the GPU (forward and deferred paths) against the CPU
//! reference's parallel rays, the analytic size of a sphere's silhouette at any distance, shadow
//! cascades fitted to the orthographic view box, clustered lights, the environment background,
//! and bad camera fields.

mod common;

use glam::Vec3;
use luz::headless::{Headless, RenderOptions};
use luz::imageio::LinearImage;
use luz::reference::{render_reference, ReferenceOptions};
use luz::render::forward::RenderPath;
use luz::scene::Scene;

use common::*;

fn reference(scene: &Scene) -> LinearImage {
    render_reference(scene, &ReferenceOptions::default(), None).unwrap_or_else(|e| panic!("{e:#}"))
}

/// Renders `scene` with `options` on `ctx`: the image, the render path's name and whether the
/// light loop was clustered.
fn render_with(
    ctx: &std::sync::Arc<luz::vk::Context>,
    scene: &Scene,
    options: &RenderOptions,
) -> (LinearImage, &'static str, bool) {
    let mut r = Headless::with_options(ctx, scene, options).expect("renderer");
    let name = r.render_path();
    r.render().expect("frame");
    let clustered = r.cluster_stats().is_some();
    (r.image().expect("readback"), name, clustered)
}

fn rgb(p: [f32; 4]) -> Vec3 {
    Vec3::new(p[0], p[1], p[2])
}

/// Pixels that are not the background colour.
fn mask(img: &LinearImage, background: Vec3) -> Vec<bool> {
    img.pixels.iter().map(|p| rgb(*p) != background).collect()
}

/// Mean relative error per channel over the pixels both images cover, over all of them and over
/// those away from a silhouette (no uncovered 4-neighbour), with the largest of the latter.
fn shading_error(a: &LinearImage, b: &LinearImage, background: Vec3) -> (f64, f64, f64) {
    let (ma, mb) = (mask(a, background), mask(b, background));
    let (w, h) = (a.width as i64, a.height as i64);
    let interior = |i: usize| {
        let (x, y) = (i as i64 % w, i as i64 / w);
        [(-1, 0), (1, 0), (0, -1), (0, 1)].iter().all(|(dx, dy)| {
            let (nx, ny) = (x + dx, y + dy);
            nx >= 0
                && ny >= 0
                && nx < w
                && ny < h
                && ma[(ny * w + nx) as usize]
                && mb[(ny * w + nx) as usize]
        })
    };
    let (mut all, mut n_all, mut inner, mut n_inner, mut worst) =
        (0.0, 0usize, 0.0, 0usize, 0.0f64);
    for i in 0..ma.len() {
        if !(ma[i] && mb[i]) {
            continue;
        }
        for c in 0..3 {
            let (g, r) = (f64::from(a.pixels[i][c]), f64::from(b.pixels[i][c]));
            let e = (g - r).abs() / r.abs().max(1e-3);
            all += e;
            n_all += 1;
            if interior(i) {
                inner += e;
                n_inner += 1;
                worst = worst.max(e);
            }
        }
    }
    (
        all / n_all.max(1) as f64,
        inner / n_inner.max(1) as f64,
        worst,
    )
}

/// (a) Two spheres and a cube (metal_rough: one variant, so Auto takes the deferred path) under a
/// directional and a point light,
/// seen by an orthographic camera: the GPU's forward and deferred paths cover the pixels the
/// reference's parallel rays hit and shade them alike, within the tolerances of the perspective
/// test (`tests/reference.rs`, `lit_sphere_matches_the_gpu`). The specular highlights depend on
/// the view vector, which is the same (−forward) at every pixel.
#[test]
fn orthographic_scene_matches_the_reference() {
    let background = Vec3::new(0.2, 0.3, 0.4);
    let scene = parse(
        r#"{
        "camera": {"position": [0.3, 1.2, 4], "target": [0, 0.2, 0], "projection": "orthographic", "ortho_half_height": 1.3, "near": 0.5, "far": 20},
        "output": {"width": 96, "height": 54, "msaa": 1, "background": [0.2, 0.3, 0.4]},
        "ambient": [0.05, 0.05, 0.05],
        "lights": [
            {"type": "directional", "direction": [-0.4, -1, -0.5], "intensity": 1.5},
            {"type": "point", "position": [2, 2, 2], "intensity": 8}
        ],
        "materials": {
            "plastic": {"model": "metal_rough", "base_color": [0.8, 0.2, 0.1], "metallic": 0, "roughness": 0.35},
            "gold": {"model": "metal_rough", "base_color": [1.0, 0.78, 0.34], "metallic": 1, "roughness": 0.3},
            "blue": {"model": "metal_rough", "base_color": [0.2, 0.5, 0.8], "metallic": 0, "roughness": 0.5}
        },
        "objects": [
            {"mesh": {"type": "sphere", "radius": 0.6, "segments": 256, "rings": 128}, "material": "plastic", "position": [-1.3, 0.5, 0]},
            {"mesh": {"type": "sphere", "radius": 0.5, "segments": 256, "rings": 128}, "material": "gold", "position": [0, 0.2, -3]},
            {"mesh": {"type": "cube", "size": 0.6}, "material": "blue", "position": [1.3, -0.3, 0.3], "rotation_deg": [0, 30, 0]}
        ]
    }"#,
    );
    let ctx = gpu();
    let cpu = reference(&scene);
    assert_eq!(nan_count(&cpu), 0);
    let mc = mask(&cpu, background);
    let covered = mc.iter().filter(|&&m| m).count();
    assert!(covered > 800, "the objects are in view ({covered} px)");
    let mut paths = Vec::new();
    for render_path in [RenderPath::Forward, RenderPath::Auto] {
        let options = RenderOptions {
            render_path,
            ..Default::default()
        };
        let (img, name, _) = render_with(&ctx, &scene, &options);
        paths.push(name);
        assert_eq!(nan_count(&img), 0);
        let mg = mask(&img, background);
        let differ = mg.iter().zip(&mc).filter(|(a, b)| a != b).count();
        let (mean_all, mean_inner, worst) = shading_error(&img, &cpu, background);
        eprintln!(
            "{name}: coverage differs at {differ} of {covered} px; mean relative error {mean_all:.2e}, \
             away from silhouettes {mean_inner:.2e} (max {worst:.2e})"
        );
        assert!(
            differ <= 6,
            "{name}: {differ} pixels covered by one renderer only"
        );
        assert!(mean_all < 3e-3, "{name}: mean relative error {mean_all}");
        assert!(
            mean_inner < 2e-4,
            "{name}: mean relative error away from silhouettes {mean_inner}"
        );
        // Measured on lavapipe (2026-11-25): coverage identical, mean 1.65e-4 over all and
        // 1.25e-4 away from silhouettes (the perspective test's bounds: 3e-3 and 2e-4), max
        // 3.7e-3 (its bound 3e-3; here the 0.5 m gold sphere's sharper lobe on tessellated
        // normals).
        assert!(
            worst < 5e-3,
            "{name}: max relative error away from silhouettes {worst}"
        );
    }
    assert_eq!(paths, ["forward", "deferred"], "both paths are tested");
    assert_no_validation_messages(&ctx);
}

/// Radius in pixels of the covered pixels in columns `cols` (from their area, π R²).
fn radius_px(m: &[bool], width: u32, cols: std::ops::Range<u32>) -> f64 {
    let n = m
        .iter()
        .enumerate()
        .filter(|(i, &on)| on && cols.contains(&(*i as u32 % width)))
        .count();
    (n as f64 / std::f64::consts::PI).sqrt()
}

/// (a) An orthographic view of a sphere of radius r shows a disc of r / half_height · height / 2
/// pixels radius at any distance: two equal spheres 3 and 33 units from the camera (a perspective
/// camera would show them 11 times apart in size) both measure 0.5 / 2 · 200 / 2 = 25 px, on the
/// GPU and in the reference.
#[test]
fn sphere_silhouette_size_does_not_depend_on_distance() {
    let scene = parse(
        r#"{
        "camera": {"position": [0, 0, 5], "target": [0, 0, 0], "projection": "orthographic", "ortho_half_height": 2, "near": 0.1, "far": 100},
        "output": {"width": 400, "height": 200, "msaa": 1, "background": [0, 0, 0]},
        "ambient": [1, 1, 1],
        "materials": {"m": {"model": "lambert", "albedo": [0.5, 0.5, 0.5]}},
        "objects": [
            {"mesh": {"type": "sphere", "radius": 0.5, "segments": 512, "rings": 256}, "material": "m", "position": [-2, 0, 2]},
            {"mesh": {"type": "sphere", "radius": 0.5, "segments": 512, "rings": 256}, "material": "m", "position": [2, 0, -28]}
        ]
    }"#,
    );
    let expected = 0.5 / 2.0 * 200.0 / 2.0;
    let gpu_img = render(&scene);
    let cpu = reference(&scene);
    for (name, img) in [("GPU", &gpu_img), ("reference", &cpu)] {
        let m = mask(img, Vec3::ZERO);
        for (which, cols) in [("near", 0..200), ("far", 200..400)] {
            let r = radius_px(&m, 400, cols);
            eprintln!("{name}, {which} sphere: {r:.3} px (expected {expected})");
            assert!(
                (r - expected).abs() < 0.25,
                "{name}, {which} sphere: radius {r} px, expected {expected}"
            );
        }
    }
    // Perspective at the same place: the far sphere is much smaller.
    let mut persp = scene.clone();
    persp.camera.projection = luz::scene::Projection::Perspective;
    let m = mask(&render(&persp), Vec3::ZERO);
    assert!(radius_px(&m, 400, 200..400) < 0.2 * radius_px(&m, 400, 0..200));
}

/// The share of `floor` pixels (by index) whose luminance is below `dark`.
fn shadowed(img: &LinearImage, floor: &[usize], dark: f32) -> Vec<bool> {
    floor
        .iter()
        .map(|&i| {
            let p = img.pixels[i];
            0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2] < dark
        })
        .collect()
}

/// Shadow cascades fit the orthographic view box: spheres spread over a wide orthographic view
/// (half height 6, far wider than a 45° frustum's slices near the camera) all cast their shadows
/// on the floor, on the GPU as in the reference (ray-traced shadows), up to a band at the edges.
#[test]
fn directional_shadows_cover_the_orthographic_view() {
    let mut objects =
        vec![r#"{"mesh": {"type": "plane", "size": [40, 40]}, "material": "m"}"#.to_string()];
    for x in [-8.0f32, -4.0, 0.0, 4.0, 8.0] {
        for z in [-5.0f32, 0.0, 5.0] {
            objects.push(format!(
                r#"{{"mesh": {{"type": "sphere", "radius": 0.8}}, "material": "m", "position": [{x}, 1.2, {z}]}}"#
            ));
        }
    }
    let json = format!(
        r#"{{
        "camera": {{"position": [0, 10, 10], "target": [0, 0, 0], "projection": "orthographic", "ortho_half_height": 6, "near": 0.5, "far": 40}},
        "output": {{"width": 160, "height": 120, "msaa": 1, "background": [0, 0, 0]}},
        "ambient": [0.05, 0.05, 0.05],
        "lights": [{{"type": "directional", "direction": [0.3, -1, 0.2], "intensity": 2, "shadow": {{"cascades": 3}}}}],
        "materials": {{"m": {{"model": "lambert", "albedo": [0.8, 0.8, 0.8]}}}},
        "objects": [{}]
    }}"#,
        objects.join(",")
    );
    let scene = parse(&json);
    let gpu_img = render(&scene);
    let cpu = reference(&scene);
    // Floor pixels: the reference's first hit is the plane (y ≈ 0), judged away from a band of
    // 2 px around every change of the reference's shadow state.
    let (w, h) = (160usize, 120usize);
    let mut floor = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let (o, d) = luz::reference::primary_ray(&scene, x as f32 + 0.5, y as f32 + 0.5);
            let t = -o.y / d.y;
            let p = o + d * t;
            let hits_sphere = scene.objects[1..].iter().any(|ob| {
                let c = ob.transform.position;
                let oc = o - c;
                let (a, b, cc) = (d.dot(d), 2.0 * oc.dot(d), oc.dot(oc) - 0.81);
                b * b - 4.0 * a * cc >= 0.0
            });
            if t > 0.0 && p.x.abs() < 19.0 && p.z.abs() < 19.0 && !hits_sphere {
                floor.push(y * w + x);
            }
        }
    }
    let lit_level = 0.5 * 0.8 * 2.0 / std::f32::consts::PI;
    let r = shadowed(&cpu, &floor, lit_level);
    let g = shadowed(&gpu_img, &floor, lit_level);
    let state: std::collections::HashMap<usize, bool> =
        floor.iter().copied().zip(r.iter().copied()).collect();
    let near_edge = |i: usize| {
        let (x, y) = ((i % w) as i64, (i / w) as i64);
        let s = state[&i];
        (-2..=2i64).any(|dy| {
            (-2..=2i64).any(|dx| {
                let (nx, ny) = (x + dx, y + dy);
                nx < 0
                    || ny < 0
                    || nx >= w as i64
                    || ny >= h as i64
                    || state
                        .get(&((ny as usize) * w + nx as usize))
                        .is_none_or(|&o| o != s)
            })
        })
    };
    let in_shadow = r.iter().filter(|&&s| s).count();
    let (mut judged, mut wrong) = (0, 0);
    for (k, &i) in floor.iter().enumerate() {
        if near_edge(i) {
            continue;
        }
        judged += 1;
        if r[k] != g[k] {
            wrong += 1;
        }
    }
    eprintln!(
        "floor: {} px, {in_shadow} in shadow (reference); {wrong} of {judged} judged px disagree",
        floor.len()
    );
    assert!(
        in_shadow > 300,
        "the spheres' shadows are on the floor ({in_shadow} px)"
    );
    // Measured: 0 (2026-11-25). Without cascades fitted to the box (a 45° frustum's slices), the
    // shadows beyond the frustum's slices are missing.
    assert!(
        wrong * 200 <= judged,
        "{wrong} of {judged} floor pixels away from shadow edges disagree with the reference"
    );
}

/// Ranged point lights over a floor seen by an orthographic camera: the clustered light loop (an
/// orthographic grid, tiles in view-space x and y) gives the plain loop's image.
#[test]
fn clustered_lights_under_an_orthographic_camera() {
    let mut lights = Vec::new();
    for i in 0..12 {
        for j in 0..8 {
            lights.push(format!(
                r#"{{"type": "point", "position": [{}, 0.6, {}], "intensity": 2, "range": 2.5}}"#,
                i as f32 * 2.0 - 11.0,
                j as f32 * 2.0 - 7.0
            ));
        }
    }
    let scene = parse(&format!(
        r#"{{
        "camera": {{"position": [0, 12, 9], "target": [0, 0, 0], "projection": "orthographic", "ortho_half_height": 7, "near": 0.5, "far": 60}},
        "output": {{"width": 160, "height": 90, "msaa": 1, "background": [0, 0, 0]}},
        "lights": [{}],
        "materials": {{"m": {{"model": "lambert", "albedo": [0.8, 0.8, 0.8]}}}},
        "objects": [{{"mesh": {{"type": "plane", "size": [30, 30]}}, "material": "m"}},
                    {{"mesh": {{"type": "sphere", "radius": 1}}, "material": "m", "position": [1, 1, 0]}}]
    }}"#,
        lights.join(",")
    ));
    let ctx = gpu();
    let with = |light_loop| RenderOptions {
        light_loop,
        ..Default::default()
    };
    use luz::render::forward::LightLoop;
    let (plain, _, c0) = render_with(&ctx, &scene, &with(LightLoop::Plain));
    let (clustered, _, c1) = render_with(&ctx, &scene, &with(LightLoop::Clustered));
    assert!(!c0 && c1);
    let (mut worst, mut lit) = (0.0f32, 0);
    for (a, b) in plain.pixels.iter().zip(&clustered.pixels) {
        for c in 0..3 {
            worst = worst.max((a[c] - b[c]).abs() / a[c].abs().max(1e-3));
            lit += (a[c] > 1e-3) as usize;
        }
    }
    eprintln!("clustered vs plain: worst relative difference {worst:.2e} over {lit} lit values");
    assert!(lit > 160 * 90, "{lit}");
    assert!(worst <= 1e-5, "worst relative difference {worst}");
    assert_no_validation_messages(&ctx);
}

/// The background of an orthographic camera is the environment along the view direction (its
/// rays are parallel): one colour over the whole image, the reference's.
#[test]
fn environment_background_is_the_view_direction() {
    let scene = parse(
        r#"{
        "camera": {"position": [0, 1, 5], "target": [0, 1.5, 0], "projection": "orthographic", "ortho_half_height": 3},
        "output": {"width": 64, "height": 48, "msaa": 1},
        "environment": {"procedural": "sky", "rotation_deg": 40},
        "objects": []
    }"#,
    );
    let ctx = gpu();
    let options = RenderOptions {
        ibl: luz::render::ibl::IblSettings::fast(),
        ..Default::default()
    };
    let (img, _, _) = render_with(&ctx, &scene, &options);
    let cpu = reference(&scene);
    let first = rgb(img.pixels[0]);
    assert!(first.min_element() > 0.0, "{first}");
    for p in &img.pixels {
        assert!(
            (rgb(*p) - first).abs().max_element() <= 1e-6 * first.max_element(),
            "{p:?} vs {first}"
        );
    }
    for p in &cpu.pixels {
        assert_eq!(
            rgb(*p),
            rgb(cpu.pixels[0]),
            "the reference's background is uniform too"
        );
    }
    let r = rgb(cpu.pixels[0]);
    let err = ((first - r).abs() / r.max(Vec3::splat(1e-3))).max_element();
    eprintln!("background: GPU {first}, reference {r}, relative difference {err:.2e}");
    assert!(err < 2e-2, "GPU {first} vs reference {r}");
    assert_no_validation_messages(&ctx);
}

/// The scene file round trip: an orthographic camera is written with "projection" and
/// "ortho_half_height" (no fov) and reads back equal; a perspective one is written as before the
/// field existed.
#[test]
fn encoder_round_trip() {
    let scene = parse(
        r#"{"camera": {"position": [1, 2, 3], "target": [0, 0, 0], "projection": "orthographic", "ortho_half_height": 2.5, "near": 0.2, "far": 30}}"#,
    );
    assert_eq!(
        scene.camera.projection,
        luz::scene::Projection::Orthographic { half_height: 2.5 }
    );
    let text = luz::scene::encode(&scene, None).to_text();
    assert!(
        text.contains("\"projection\": \"orthographic\"")
            && text.contains("\"ortho_half_height\": 2.5"),
        "{text}"
    );
    assert!(!text.contains("fov_y_deg"), "{text}");
    let back = parse(&text);
    assert_eq!(back.camera, scene.camera);
    let persp = parse(r#"{"camera": {"position": [1, 2, 3], "fov_y_deg": 30}}"#);
    let text = luz::scene::encode(&persp, None).to_text();
    assert!(
        !text.contains("projection") && !text.contains("ortho_half_height"),
        "{text}"
    );
    assert_eq!(parse(&text).camera, persp.camera);
}
