//! The viewer's frame-time target (`luz view --target-ms`) in a real window under Xvfb on
//! lavapipe, validation and sync validation on: 24 bunnies at 320×180 (the shared Stanford
//! bunny; skipped visibly without ../shared). With the camera turning and a target no frame can
//! meet, the mesh LOD budget rises above the scene's and the triangles drawn drop; with the target
//! off, or with it on and the camera still (the picture at rest), every measured frame draws what
//! `luz render` draws for the same view, and a screenshot taken while turning is the exact picture.

mod common;

use std::path::Path;

use common::{assert_ran_clean, luz, luz_in_window_with, scratch, shared_dir};

/// 24 bunnies in 4 rows from 4 to 14.5 units in front of the camera, budget 0.2 px; no floor, so
/// `luz render`'s LOD summary counts every triangle drawn.
fn scene_text(bunny: &Path) -> String {
    let objects: Vec<String> = (0..24)
        .map(|i| {
            let (row, col) = (i / 6, i % 6);
            format!(
                r#"{{"mesh": {{"type": "obj", "path": {:?}}}, "material": "m",
                    "position": [{}, -0.33, {}], "rotation_deg": [0, {}, 0], "scale": [10, 10, 10]}}"#,
                bunny.to_str().unwrap(),
                (col as f32 - 2.5) * 1.8,
                2.0 - 3.5 * row as f32,
                (i * 47) % 360
            )
        })
        .collect();
    format!(
        r#"{{
        "description": "viewer_lod test: 24 bunnies",
        "camera": {{"position": [0, 1.6, 6], "target": [0, 0.5, -10], "up": [0, 1, 0], "fov_y_deg": 50, "near": 0.1, "far": 200}},
        "output": {{"width": 320, "height": 180, "msaa": 1, "tessellation_error_px": 0.2}},
        "lights": [{{"type": "directional", "direction": [-0.4, -1, -0.5], "intensity": 2.5}}],
        "ambient": [0.05, 0.05, 0.05],
        "materials": {{"m": {{"model": "lambert", "albedo": [0.7, 0.5, 0.4]}}}},
        "objects": [{}]
    }}"#,
        objects.join(",")
    )
}

/// `luz view --bench` with `extra` options; its JSON report.
fn bench(dir: &Path, scene: &Path, name: &str, extra: &[&str]) -> Option<serde_json::Value> {
    let json = dir.join(format!("{name}.json"));
    let mut args = vec![
        "view",
        scene.to_str().unwrap(),
        "--bench",
        "--frames",
        "16",
        "--warmup",
        "5",
        "--json",
        json.to_str().unwrap(),
    ];
    args.extend(extra);
    let (code, out, err) = luz_in_window_with(&args, &[("LUZ_SYNC_VALIDATION", "1")])?;
    assert_ran_clean(code, &out, &err);
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    println!(
        "{name}: budget {} px, triangles drawn {}, frame ms {}",
        v["lod_budget_px"], v["triangles_drawn_per_frame"], v["frame_ms"]
    );
    Some(v)
}

fn num(v: &serde_json::Value, path: &[&str]) -> f64 {
    let mut x = v;
    for p in path {
        x = &x[p];
    }
    x.as_f64()
        .unwrap_or_else(|| panic!("no number at {path:?} in {v}"))
}

/// `luz render --verbose`'s "N of M triangles drawn" of the LOD summary.
fn rendered_triangles(dir: &Path, scene: &Path) -> f64 {
    let (code, out, err) = luz(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        dir.join("render.png").to_str().unwrap(),
        "--verbose",
    ]);
    assert_eq!(code, 0, "{err}");
    let line = out
        .lines()
        .find(|l| l.starts_with("automatic LOD (budget 0.2 px)"))
        .unwrap_or_else(|| panic!("no LOD summary in {out}"));
    let before = line
        .split(" triangles drawn")
        .next()
        .unwrap()
        .rsplit(", ")
        .next()
        .unwrap();
    let drawn = before.split(" of ").next().unwrap();
    drawn
        .parse()
        .unwrap_or_else(|_| panic!("{drawn:?} in {line:?}"))
}

#[test]
fn the_target_raises_the_budget_while_moving_and_the_scene_budget_holds_at_rest() {
    let Some(bunny) = shared_dir("models/stanford-bunny.obj") else {
        return;
    };
    let dir = scratch("viewer-lod");
    let scene = dir.join("bunnies.json");
    std::fs::write(&scene, scene_text(&bunny)).unwrap();

    // Turning, a target of 1 ms (no frame meets it): the budget climbs to the ceiling.
    let (shot_tight, shot_off) = (dir.join("tight.png"), dir.join("off.png"));
    let tight_args = [
        "--turntable",
        "1",
        "--target-ms",
        "1",
        "--screenshot",
        shot_tight.to_str().unwrap(),
    ];
    let Some(tight) = bench(&dir, &scene, "tight", &tight_args) else {
        return;
    };
    assert_eq!(num(&tight, &["lod_target_ms"]), 1.0);
    assert_eq!(num(&tight, &["scene_lod_budget_px"]) as f32, 0.2);
    assert_eq!(num(&tight, &["adaptive_frames"]), num(&tight, &["frames"]));
    assert!(num(&tight, &["lod_budget_px", "min"]) > 0.2, "{tight}");
    assert_eq!(
        num(&tight, &["lod_budget_px", "max"]) as f32,
        luz::window::lod_target::MAX_BUDGET_PX,
        "{tight}"
    );
    // The same turn with the target off: the scene's budget, more triangles in every frame.
    let off_args = [
        "--turntable",
        "1",
        "--target-ms",
        "off",
        "--screenshot",
        shot_off.to_str().unwrap(),
    ];
    let Some(off) = bench(&dir, &scene, "off", &off_args) else {
        return;
    };
    assert!(off["lod_target_ms"].is_null(), "{off}");
    assert_eq!(num(&off, &["adaptive_frames"]), 0.0);
    assert_eq!(num(&off, &["lod_budget_px", "max"]) as f32, 0.2);
    assert_eq!(num(&off, &["lod_budget_px", "min"]) as f32, 0.2);
    let (tight_max, off_min) = (
        num(&tight, &["triangles_drawn_per_frame", "max"]),
        num(&off, &["triangles_drawn_per_frame", "min"]),
    );
    assert!(
        tight_max * 2.0 < off_min,
        "{tight_max} triangles at most with the target, {off_min} at least without"
    );

    // The screenshot frame (one more turn after the last) draws at the scene's budget even while
    // turning: the same picture as with the target off, below the compact profiler's figures (the
    // top 100 rows: its box, frame and shadow grow with the figures, which wrap onto more lines
    // on a busy machine — under a CPU-bound neighbour 64 rows let 650 pixels of the box through,
    // 76 rows 152; the bunnies' bodies fill the rows below). A PNG: the viewer's EXR
    // screenshot copies the float image in GENERAL layout, a validation performance warning.
    let (a, b) = (
        image::open(&shot_tight).unwrap().to_rgb8(),
        image::open(&shot_off).unwrap().to_rgb8(),
    );
    assert_eq!(a.dimensions(), (320, 180));
    let differing = a
        .enumerate_pixels()
        .filter(|&(x, y, p)| y >= 100 && (0..3).any(|i| p[i].abs_diff(b.get_pixel(x, y)[i]) > 1))
        .count();
    assert_eq!(differing, 0, "the screenshot is not the exact picture");

    // The camera still: with the target off, and with it on (at rest after 3 frames, before the
    // 5 warm-up frames end), every measured frame draws what `luz render` draws.
    let rendered = rendered_triangles(&dir, &scene);
    for (name, target) in [("still-off", "off"), ("still-on", "1")] {
        let Some(v) = bench(&dir, &scene, name, &["--target-ms", target]) else {
            return;
        };
        assert_eq!(num(&v, &["adaptive_frames"]), 0.0, "{name}: {v}");
        assert_eq!(num(&v, &["lod_budget_px", "max"]) as f32, 0.2, "{name}");
        for q in ["min", "max"] {
            assert_eq!(
                num(&v, &["triangles_drawn_per_frame", q]),
                rendered,
                "{name}: {v}"
            );
        }
    }
    println!("luz render draws {rendered} triangles");
}

#[test]
fn bad_target_values_are_clear_errors() {
    for (flag, bad, message) in [
        (
            "--target-ms",
            "-5",
            "expected a frame time in milliseconds >= 0, or off, got \"-5\"",
        ),
        (
            "--target-ms",
            "fast",
            "expected a frame time in milliseconds >= 0, or off, got \"fast\"",
        ),
        (
            "--turntable",
            "nan",
            "expected a number of degrees, got \"nan\"",
        ),
    ] {
        let arg = format!("{flag}={bad}");
        let (code, _, err) = luz(&["view", &arg]);
        assert_eq!(code, 2, "{err}");
        assert!(err.contains(flag) && err.contains(message), "{err}");
    }
}
