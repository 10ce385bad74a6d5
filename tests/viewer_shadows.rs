//! The lights panel's Shadow rows in a real window (issue 15): `luz view` under Xvfb on lavapipe,
//! with validation and synchronization validation on, driven by the script actions that take the
//! panel's path (`light_shadow=N:off|on|hard|pcf|pcss`, `light_shadow_resolution=N:TEXELS`, both
//! through `scene::edit::edit_shadow`, then the viewer's rebuild when the shadow's structure
//! changed). Each edit is checked on the frame the window shows: against the analytic radiance of
//! the floor (lit and in the umbra), against a headless `luz render` of the same scene with the
//! same edit written in its JSON, and, for the resolution, on the shadow map read back after the
//! rebuild.
//!
//! The scene: a Lambert floor (albedo 0.8) seen straight from above, a 1 m cube floating 1 m above
//! it, ambient 0.1 and a sun of intensity 2 along (0.6, −1, 0) (cos θ = 1/√1.36 on the floor),
//! with a 3° angular radius (for PCSS); no tone map, exposure 0. The floor is then
//! 0.8·0.1 = 0.08 in the umbra (sRGB 80) and 0.08 + 0.8/π·2·cos θ = 0.5167 where lit (sRGB 190).
//! The camera (10 m up over z = −1.2 m, looking down, 40° vertical field, 320×240) puts 33
//! pixels on a metre of floor: the cube's umbra (x from 0.7 to 1.6 m, z within ±0.4 m, outside
//! the cube's own footprint) covers the pixels 190..206 × 152..168, and the floor at x ≈ −3 m
//! (pixels 60..76) is lit whatever the shadow.

mod common;

use std::path::Path;

use common::{assert_ran_clean, luz, luz_in_window_with, scratch};

const SCENE: &str = r#"{
  "camera": {"position": [0, 10, -1.2], "target": [0, 0, -1.2], "up": [0, 0, -1], "fov_y_deg": 40, "near": 0.5, "far": 30},
  "output": {"width": 320, "height": 240, "background": [0, 0, 0], "msaa": 1, "tonemap": "none", "exposure": 0},
  "ambient": [0.1, 0.1, 0.1],
  "lights": [{"type": "directional", "direction": [0.6, -1, 0], "intensity": 2.0, "angular_radius_deg": 3.0, "shadow": true}],
  "materials": {"m": {"model": "lambert", "albedo": [0.8, 0.8, 0.8]}},
  "objects": [
    {"mesh": {"type": "plane", "size": [12, 12]}, "material": "m"},
    {"mesh": {"type": "cube", "size": 1}, "material": "m", "position": [0, 1.5, 0]}
  ]
}"#;

/// sRGB levels of the floor: in the umbra (0.08) and lit (0.5167), see the module comment.
const UMBRA: f64 = 80.0;
const LIT: f64 = 190.0;

/// Pixel windows (x0..x1, y0..y1): in the cube's umbra, and on floor lit whatever the shadow.
const SHADOWED: (u32, u32, u32, u32) = (190, 206, 152, 168);
const OPEN: (u32, u32, u32, u32) = (60, 76, 152, 168);

fn rgb(path: &Path) -> image::RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
}

/// The mean green level and the largest deviation from `expected` over a window.
fn window(
    img: &image::RgbImage,
    (x0, x1, y0, y1): (u32, u32, u32, u32),
    expected: f64,
) -> (f64, f64) {
    let mut sum = 0.0;
    let mut worst = 0.0f64;
    for y in y0..y1 {
        for x in x0..x1 {
            let g = f64::from(img.get_pixel(x, y)[1]);
            sum += g;
            worst = worst.max((g - expected).abs());
        }
    }
    (sum / f64::from((x1 - x0) * (y1 - y0)), worst)
}

/// The rows compared: below the frame-time overlay the viewer keeps at the top right without
/// panels (2–3 lines of text and a drop shadow, to row 95 at this width), above the status bar
/// a screenshot leaves at the bottom ("wrote PATH", from row 190). The cube and its shadow lie
/// between (rows 139–181).
const ROWS: (u32, u32) = (120, 184);

/// Share of the pixels in [`ROWS`] whose channels are all within `tol` levels of
/// the other image's.
fn matching(a: &image::RgbImage, b: &image::RgbImage, tol: u8) -> f64 {
    assert_eq!(a.dimensions(), b.dimensions());
    let w = a.width();
    let mut ok = 0;
    for y in ROWS.0..ROWS.1 {
        for x in 0..w {
            let (p, q) = (a.get_pixel(x, y), b.get_pixel(x, y));
            ok += (0..3).all(|i| p[i].abs_diff(q[i]) <= tol) as u32;
        }
    }
    f64::from(ok) / f64::from(w * (ROWS.1 - ROWS.0))
}

/// Pixels in [`ROWS`] strictly between the umbra and the lit level (a penumbra, or
/// a filtered edge).
fn between(img: &image::RgbImage) -> usize {
    img.enumerate_pixels()
        .filter(|(_, y, p)| {
            (ROWS.0..ROWS.1).contains(y) && p[1] > UMBRA as u8 + 6 && p[1] < LIT as u8 - 6
        })
        .count()
}

/// `luz render` of `scene_text` (320×240) to `dir/name.png`.
fn headless(dir: &Path, name: &str, scene_text: &str) -> image::RgbImage {
    let scene = dir.join(format!("{name}.json"));
    std::fs::write(&scene, scene_text).unwrap();
    let out = dir.join(format!("{name}_headless.png"));
    let (code, stdout, stderr) = luz(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    rgb(&out)
}

#[test]
fn shadow_rows_turn_off_change_method_and_resolution() {
    let dir = scratch("viewer_shadows");
    let scene = dir.join("scene.json");
    std::fs::write(&scene, SCENE).unwrap();
    let p = |name: &str| dir.join(name).display().to_string();
    let script = [
        "1:panels=off".to_string(),
        format!("4:screenshot={}", p("pcf.png")),
        format!("4:shadow_map_save={}", p("map_1024.png")),
        "6:light_shadow=0:off".into(),
        format!("9:screenshot={}", p("off.png")),
        "11:light_shadow=0:hard".into(),
        format!("14:screenshot={}", p("hard.png")),
        "16:light_shadow_resolution=0:512".into(),
        format!("19:screenshot={}", p("hard_512.png")),
        format!("19:shadow_map_save={}", p("map_512.png")),
        "21:light_shadow=0:pcss".into(),
        format!("24:screenshot={}", p("pcss.png")),
    ]
    .join(";");
    let Some((code, out, err)) = luz_in_window_with(
        &[
            "view",
            scene.to_str().unwrap(),
            "--width",
            "320",
            "--height",
            "240",
            "--frames",
            "26",
            "--script",
            &script,
        ],
        &[("LUZ_SYNC_VALIDATION", "1")],
    ) else {
        return;
    };
    assert_ran_clean(code, &out, &err);

    // Each frame against the floor's analytic levels (±3: the GPU's sRGB encode and dithering
    // of the display pass) …
    let shots: Vec<(&str, image::RgbImage)> = ["pcf", "off", "hard", "hard_512", "pcss"]
        .into_iter()
        .map(|n| (n, rgb(&dir.join(format!("{n}.png")))))
        .collect();
    for (name, img) in &shots {
        assert_eq!(img.dimensions(), (320, 240), "{name}");
        let (lit, worst) = window(img, OPEN, LIT);
        eprintln!("{name}: open floor {lit:.1} (largest deviation from {LIT}: {worst})");
        assert!(worst <= 3.0, "{name}: the open floor is not lit: {lit:.1}");
        let expected = if *name == "off" { LIT } else { UMBRA };
        let (mean, worst) = window(img, SHADOWED, expected);
        eprintln!("{name}: umbra window {mean:.1} (largest deviation from {expected}: {worst})");
        assert!(
            worst <= 3.0,
            "{name}: the umbra window should be {expected} (shadow {}), is {mean:.1} (worst {worst})",
            if *name == "off" { "off" } else { "on" }
        );
    }

    // … and against `luz render` of the scene with the same edit in its JSON: the viewer draws
    // what the scene file would say (≤ 0.1 % of the pixels in [`ROWS`] more than 2 levels off).
    let light = r#""angular_radius_deg": 3.0, "shadow": true"#;
    assert!(SCENE.contains(light));
    let edits = [
        ("pcf", light.to_string()),
        ("off", r#""angular_radius_deg": 3.0"#.to_string()),
        ("hard", light.replace("true", r#"{"method": "hard"}"#)),
        (
            "hard_512",
            light.replace("true", r#"{"method": "hard", "resolution": 512}"#),
        ),
        // The method changes, the resolution set before stays.
        (
            "pcss",
            light.replace("true", r#"{"method": "pcss", "resolution": 512}"#),
        ),
    ];
    let mut previous: Option<image::RgbImage> = None;
    let n = f64::from(320 * (ROWS.1 - ROWS.0));
    for ((name, img), (edit_name, edit)) in shots.iter().zip(&edits) {
        assert_eq!(name, edit_name);
        let reference = headless(&dir, name, &SCENE.replace(light, edit));
        let own = ((1.0 - matching(img, &reference, 2)) * n).round();
        eprintln!("{name}: {own} pixels more than 2 levels from luz render");
        assert!(
            own <= 0.001 * n,
            "{name}: the viewer's frame differs from luz render on {own} pixels"
        );
        // The edit took effect: the render of the state before it differs (on the shadow's
        // edges for the resolution, on the whole umbra when the shadow goes).
        if let Some(before) = &previous {
            let stale = ((1.0 - matching(img, before, 2)) * n).round();
            eprintln!("{name}: {stale} pixels more than 2 levels from the state before");
            assert!(
                stale >= 20.0 && stale > 4.0 * own,
                "{name}: the frame is as close to the state before ({stale} pixels off) as to its own ({own})"
            );
        }
        previous = Some(reference);
    }

    // The rebuild: the map read back after the resolution change has three 512² cascades
    // (before: three 1024² ones), and the method changes show at the edges: hard shadows have
    // no in-between pixels but a few along aliased edges, PCSS's 3° sun softens every edge
    // over several pixels.
    let map = |n: &str| {
        let img = image::open(dir.join(n)).unwrap_or_else(|e| panic!("{n}: {e}"));
        (img.width(), img.height())
    };
    assert_eq!(map("map_1024.png"), (3 * 1024, 1024));
    assert_eq!(map("map_512.png"), (3 * 512, 512));
    let soft = |n: &str| between(&shots.iter().find(|(s, _)| *s == n).unwrap().1);
    let (hard, pcf, pcss) = (soft("hard"), soft("pcf"), soft("pcss"));
    eprintln!("pixels between the umbra and lit levels: hard {hard}, pcf {pcf}, pcss {pcss}");
    assert!(
        pcss > 2 * pcf.max(hard),
        "hard {hard}, pcf {pcf}, pcss {pcss}"
    );
    assert_eq!(soft("off"), 0, "no shadow, no edge");
}

/// An edit the panel does not offer stops the script with the action named, exit 1.
#[test]
fn bad_shadow_edits_are_clear_errors() {
    let dir = scratch("viewer_shadows_bad");
    let scene = dir.join("scene.json");
    // Without the angular radius the panel offers no PCSS.
    std::fs::write(&scene, SCENE.replace(r#""angular_radius_deg": 3.0, "#, "")).unwrap();
    for (script, needle) in [
        (
            "2:light_shadow=0:pcss",
            "script: light_shadow=0:pcss: pcss needs the light's size",
        ),
        (
            "2:light_shadow=1:off",
            "script: light_shadow=1:off: no light 1 (the scene has 1 light(s))",
        ),
        (
            "2:light_shadow_resolution=0:1000",
            "script: light_shadow_resolution=0:1000: resolution 1000: expected one of 256, 512",
        ),
    ] {
        let Some((code, out, err)) = luz_in_window_with(
            &[
                "view",
                scene.to_str().unwrap(),
                "--frames",
                "6",
                "--script",
                script,
            ],
            &[],
        ) else {
            return;
        };
        assert_eq!(code, 1, "{script}\nstdout: {out}\nstderr: {err}");
        assert!(err.contains(needle), "{script}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}
