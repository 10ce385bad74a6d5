//! Looking at the shadow maps (issue 15's debug view of each map): every layer read back after a
//! frame holds exactly the casters' geometry seen from its light, at the distances the geometry
//! gives, and `luz render --shadow-maps DIR` writes one picture per light.

mod common;

use common::*;
use glam::{Vec3, Vec4};
use luz::headless::Headless;
use luz::render::shadow::MapLayer;

const SPHERE_C: Vec3 = Vec3::new(0.2, 1.2, -0.1);
const SPHERE_R: f32 = 0.7;

/// A floor (hides nothing from above, so no map draws it) and a floating sphere, lit by a
/// directional light (three cascades), a spot (one map) and a point light (six cube faces); no
/// slope bias, so the maps hold the geometry's own depth.
fn scene() -> String {
    let (c, r) = (SPHERE_C, SPHERE_R);
    format!(
        r#"{{
        "camera": {{"position": [0.5, 4.0, 5.0], "target": [0.2, 0.5, 0], "fov_y_deg": 50, "near": 0.1, "far": 40}},
        "output": {{"width": 160, "height": 120, "msaa": 1}},
        "lights": [
            {{"type": "directional", "direction": [0.4, -1.0, 0.3], "intensity": 2.0, "shadow": {{"resolution": 256, "cascades": 3, "slope_bias": 0}}}},
            {{"type": "spot", "position": [1.0, 4.0, 0.5], "target": [0.2, 0, -0.1], "umbra_deg": 35, "inner_deg": 25, "intensity": 40.0, "shadow": {{"resolution": 256, "slope_bias": 0}}}},
            {{"type": "point", "position": [-1.5, 1.5, 1.2], "intensity": 15.0, "shadow": {{"resolution": 128, "slope_bias": 0}}}}
        ],
        "materials": {{"m": {{"model": "lambert", "albedo": [0.8, 0.8, 0.8]}}}},
        "objects": [
            {{"mesh": {{"type": "plane", "size": [16, 16]}}, "material": "m"}},
            {{"mesh": {{"type": "sphere", "radius": {r}, "segments": 256, "rings": 128}}, "material": "m", "position": [{}, {}, {}]}}
        ]
    }}"#,
        c.x, c.y, c.z
    )
}

/// The world-space ray through texel (x, y) of a layer: two points of the texel's line of sight
/// (reversed depth: 1 at the near plane), from the layer's own matrix.
fn texel_ray(m: &MapLayer, x: u32, y: u32) -> (Vec3, Vec3) {
    let res = m.resolution as f32;
    let ndc = |v: u32| 2.0 * (v as f32 + 0.5) / res - 1.0;
    let inv = m.view_proj.inverse();
    let at = |z: f32| {
        let p = inv * Vec4::new(ndc(x), ndc(y), z, 1.0);
        p.truncate() / p.w
    };
    let (a, b) = (at(1.0), at(0.5));
    (a, (b - a).normalize())
}

/// Nearest hit of the ray (origin `o`, unit `d`, forward only) with the sphere, and the ray's
/// closest approach to its centre.
fn hit(o: Vec3, d: Vec3) -> (Option<Vec3>, f32) {
    let oc = o - SPHERE_C;
    let b = oc.dot(d);
    if b > 0.0 {
        // The centre is behind the origin (a cube face looking away): the origin is nearest.
        return (None, oc.length());
    }
    let q = (oc.length_squared() - b * b).max(0.0);
    let disc = SPHERE_R * SPHERE_R - q;
    let t = (disc >= 0.0).then(|| -b - disc.sqrt());
    (t.map(|t| o + t * d), q.sqrt())
}

#[test]
fn every_map_layer_holds_the_casters_seen_from_its_light() {
    let ctx = gpu_with(true);
    let scene = parse(&scene());
    let mut r = Headless::new(&ctx, &scene).expect("renderer");
    r.render().expect("frame");
    let layers = r.shadow_map_layers().expect("read the maps");
    // 3 cascades + 1 spot map + 6 cube faces.
    let per_light: Vec<usize> = (0..3)
        .map(|i| layers.iter().filter(|l| l.light == i).count())
        .collect();
    assert_eq!(per_light, [3, 1, 6]);
    for m in &layers {
        let (mut drawn, mut inside, mut outside, mut wrong) = (0, 0, 0, Vec::new());
        let mut worst = 0.0f32;
        for y in 0..m.resolution {
            for x in 0..m.resolution {
                let (o, d) = texel_ray(m, x, y);
                let (h, closest) = hit(o, d);
                let stored = m.distance[(y * m.resolution + x) as usize];
                drawn += usize::from(stored.is_some());
                // The tessellated sphere's silhouette differs from the exact one by far under 1 %
                // of its radius: judge texels clearly inside or outside it.
                if closest < 0.98 * SPHERE_R {
                    inside += 1;
                    let expected = (h.unwrap() - m.origin).dot(m.axis);
                    match stored {
                        // Distances where the surface faces the ray within 64° (towards the rim
                        // a facet's sagitta grows as 1 / cos along the ray).
                        Some(s) if closest < 0.9 * SPHERE_R => {
                            worst = worst.max((s - expected).abs() / (1.0 + 2.0 * expected))
                        }
                        Some(_) => {}
                        None => wrong.push((x, y, "empty inside the sphere")),
                    }
                } else if closest > 1.02 * SPHERE_R {
                    outside += 1;
                    if stored.is_some() {
                        wrong.push((x, y, "drawn outside the sphere"));
                    }
                }
            }
        }
        let what = format!("light {} layer {} ({}²)", m.light, m.index, m.resolution);
        assert!(
            wrong.is_empty(),
            "{what}: {} texel(s) wrong, first {:?}",
            wrong.len(),
            &wrong[..wrong.len().min(5)]
        );
        // Distances along the axis within 3 mm + 0.6 % (a sphere of 0.7 m in 256 × 128 facets,
        // whose sagitta is 0.05 mm; lavapipe interpolates a perspective map's depth, near / d,
        // to about 0.35 % of d: measured at 256² and 1024² alike).
        assert!(
            worst < 0.003,
            "{what}: a distance off by {worst} (3 mm + 0.6 % units)"
        );
        assert!(outside > 0, "{what}: no texel outside the sphere to judge");
        assert!(drawn >= inside, "{what}: {drawn} drawn, {inside} inside");
        println!("{what}: {drawn} drawn, {inside} clearly inside, worst distance error {worst:.5} (3 mm + 0.6 % units)");
    }
    // The sphere is seen by the spot and by the point light's faces that face it.
    for light in [1, 2] {
        assert!(
            layers
                .iter()
                .any(|l| l.light == light && l.distance.iter().any(Option::is_some)),
            "light {light}: the sphere is in none of its maps"
        );
    }
    assert_no_validation_messages(&ctx);
}

#[test]
fn render_writes_one_picture_per_shadowed_light() {
    let dir = scratch("shadow_maps_cli");
    let scene_path = dir.join("scene.json");
    std::fs::write(&scene_path, scene()).unwrap();
    let out = dir.join("maps");
    let image = dir.join("frame.png");
    let (code, stdout, stderr) = luz(&[
        "render",
        scene_path.to_str().unwrap(),
        "-o",
        image.to_str().unwrap(),
        "--shadow-maps",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    for (light, w, h) in [(0, 3 * 256, 256), (1, 256, 256), (2, 6 * 128, 128)] {
        let path = out.join(format!("light{light}.png"));
        assert!(
            stdout.contains(&format!("shadow maps of light {light}: {}", path.display())),
            "{stdout}"
        );
        let img = image::open(&path).expect("map picture").to_rgba8();
        assert_eq!(img.dimensions(), (w, h), "{}", path.display());
        // Nothing drawn in a corner of the first layer; some texel white (the nearest one).
        assert_eq!(
            img.get_pixel(0, 0).0,
            luz::render::shadow::view::EMPTY_TEXEL
        );
        assert!(img.pixels().any(|p| p.0 == [255, 255, 255, 255]));
    }
    // A file where the folder should be: the option and the path named, exit 1.
    let (code, _, stderr) = luz(&[
        "render",
        scene_path.to_str().unwrap(),
        "-o",
        image.to_str().unwrap(),
        "--shadow-maps",
        image.to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{stderr}");
    assert!(
        stderr.contains(&format!("--shadow-maps {}", image.display())),
        "{stderr}"
    );
}

#[test]
fn the_viewer_window_shows_the_same_maps() {
    let dir = scratch("shadow_maps_viewer");
    // A spot's map does not depend on the window's size (a cascade would), and the sphere's
    // facets are fixed: the viewer and `luz render` draw the same map.
    let scene_text = scene().replace(r#""cascades": 3, "#, "").replace(
        r#""width": 160, "height": 120"#,
        r#""width": 960, "height": 720"#,
    );
    let scene_path = dir.join("scene.json");
    std::fs::write(&scene_path, scene_text).unwrap();
    let saved = dir.join("viewer_light1.png");
    let shot = dir.join("window.png");
    let script = format!(
        "3:shadow_map=1;4:shadow_map_save={};8:screenshot={}",
        saved.display(),
        shot.display()
    );
    let Some((code, out, err)) = luz_in_window(&[
        "view",
        scene_path.to_str().unwrap(),
        "--frames",
        "10",
        "--script",
        &script,
    ]) else {
        return;
    };
    assert_eq!(code, 0, "{out}\n{err}");
    let maps = dir.join("maps");
    let (code, stdout, stderr) = luz(&[
        "render",
        scene_path.to_str().unwrap(),
        "-o",
        dir.join("frame.png").to_str().unwrap(),
        "--shadow-maps",
        maps.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    let viewer = image::open(&saved).expect("viewer's picture").to_rgba8();
    let render = image::open(maps.join("light1.png"))
        .expect("render's picture")
        .to_rgba8();
    assert_eq!(viewer.dimensions(), render.dimensions());
    let differing = viewer
        .pixels()
        .zip(render.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(
        differing, 0,
        "viewer and luz render disagree on {differing} texels"
    );
    // The window shows the picture: a large area of the empty-texel colour (the scene has
    // no such colour; egui's colour path shows (16, 24, 64) as (24, 30, 66): within 10 codes),
    // and the nearest texels' white.
    let window = image::open(&shot).expect("screenshot").to_rgb8();
    let [er, eg, eb, _] = luz::render::shadow::view::EMPTY_TEXEL;
    let near = |p: &image::Rgb<u8>, c: [u8; 3], tol: u8| {
        p.0.iter().zip(c).all(|(a, b)| a.abs_diff(b) <= tol)
    };
    let empty = window
        .pixels()
        .filter(|p| near(p, [er, eg, eb], 10))
        .count();
    // The 256² picture shown 256 pixels wide: ~60,000 empty texels around the sphere's disc.
    assert!(
        empty > 40_000,
        "{empty} pixels of the empty-texel colour in the window"
    );
    assert!(window.pixels().any(|p| near(p, [255, 255, 255], 3)));
}

/// Map reuse: a frame draws only the layers whose record or casters changed since the image last
/// held them. A static scene draws its maps once; moving the camera redraws the sun's cascades
/// (fitted to the view) and keeps the spot's and the point light's seven layers; moving the
/// sphere redraws every layer that sees it. After each change the image is exactly the one a
/// fresh renderer makes of the changed scene (no stale map), with zero validation messages.
#[test]
fn unchanged_map_layers_are_reused_and_changed_ones_redrawn() {
    let ctx = gpu_with(true);
    let mut scene = parse(&scene());
    let mut r = Headless::new(&ctx, &scene).expect("renderer");
    r.render().expect("frame");
    let first = r.image().expect("readback");
    // 3 cascades + 1 spot map + 6 cube faces, every one drawn in the first frame.
    assert_eq!(r.shadow_frames_drawn_reused(), (1, 0, 10));
    r.render().expect("frame");
    assert_eq!(r.shadow_frames_drawn_reused(), (1, 1, 10));
    assert_eq!(r.image().expect("readback").pixels, first.pixels);

    // The camera moves: the cascades follow the view, the other lights' layers stay.
    scene.camera.position = Vec3::new(-2.0, 3.5, 4.5);
    r.update_scene(&scene).expect("update");
    r.render().expect("frame");
    assert_eq!(r.shadow_frames_drawn_reused(), (2, 1, 13));
    let fresh = render_on(&ctx, &scene);
    assert_eq!(
        r.image().expect("readback").pixels,
        fresh.pixels,
        "camera moved"
    );
    assert_ne!(fresh.pixels, first.pixels);

    // The sphere moves: every layer that saw it or sees it now is drawn again.
    let sphere = scene.objects.len() - 1;
    scene.objects[sphere].transform.position += Vec3::new(0.6, 0.2, -0.4);
    r.update_scene(&scene).expect("update");
    r.render().expect("frame");
    let (frames, reused, layers) = r.shadow_frames_drawn_reused();
    assert_eq!((frames, reused), (3, 1));
    assert!(layers > 13 + 4, "{layers} layers drawn in all");
    let fresh = render_on(&ctx, &scene);
    assert_eq!(
        r.image().expect("readback").pixels,
        fresh.pixels,
        "sphere moved"
    );
    assert_no_validation_messages(&ctx);
}
