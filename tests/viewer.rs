//! The interactive viewer in a real window: `luz view` under Xvfb on lavapipe, driven by a script
//! (a resize and a UI change), with validation on. The screenshot (swapchain image, UI included)
//! is checked against a headless render of the same scene after the same change: the scene must
//! be there pixel for pixel (±2 levels) where no panel covers it, and the panels must be there.

mod common;

use std::path::Path;

use common::{assert_ran_clean, luz, luz_in_window, root, scratch, shared_dir};

fn rgb(path: &Path) -> image::RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
}

fn max_diff(a: &image::Rgb<u8>, b: &image::Rgb<u8>) -> u8 {
    (0..3).map(|i| a[i].abs_diff(b[i])).max().unwrap()
}

/// Share of the pixels in columns `x0..x1` and rows `0..y1` whose channels are all within `tol`
/// of `reference`.
fn matching(
    shot: &image::RgbImage,
    reference: &image::RgbImage,
    (x0, x1): (u32, u32),
    y1: u32,
    tol: u8,
) -> f64 {
    let mut ok = 0u64;
    let mut n = 0u64;
    for y in 0..y1 {
        for x in x0..x1 {
            n += 1;
            if max_diff(shot.get_pixel(x, y), reference.get_pixel(x, y)) <= tol {
                ok += 1;
            }
        }
    }
    ok as f64 / n as f64
}

#[test]
fn scripted_resize_and_ui_change_show_in_the_screenshot() {
    let dir = scratch("script");
    let scene_text = std::fs::read_to_string(root().join("assets/scenes/default.json")).unwrap();
    assert!(scene_text.contains("\"exposure\": 0.0"));
    let scene = dir.join("scene.json");
    std::fs::write(&scene, &scene_text).unwrap();
    // The same scene after the scripted UI change, for the headless reference.
    let changed = dir.join("changed.json");
    std::fs::write(
        &changed,
        scene_text.replace("\"exposure\": 0.0", "\"exposure\": 1.0"),
    )
    .unwrap();
    let shot = dir.join("shot.png");
    let Some((code, out, err)) = luz_in_window(&[
        "view",
        scene.to_str().unwrap(),
        "--width",
        "900",
        "--height",
        "560",
        "--frames",
        "30",
        "--script",
        "5:resize=640x400;12:exposure=1",
        "--screenshot",
        shot.to_str().unwrap(),
    ]) else {
        return;
    };
    assert_ran_clean(code, &out, &err);
    let shot_img = rgb(&shot);
    assert_eq!(
        (shot_img.width(), shot_img.height()),
        (640, 400),
        "the scripted resize reached the swapchain"
    );
    // The screenshot's provenance: the device, the scene and its hash, the exposure the script
    // set, the window's size.
    let meta = luz::imageio::provenance::read(&shot).unwrap();
    let get = |k: &str| {
        meta.get(k)
            .unwrap_or_else(|| panic!("no {k} in {meta:?}"))
            .to_string()
    };
    assert!(get("luz.device").contains("llvmpipe"), "{meta:?}");
    assert_eq!(get("luz.scene"), scene.display().to_string());
    assert!(get("luz.scene_hash").starts_with("fnv1a64:"), "{meta:?}");
    assert_eq!(get("luz.size"), "640x400");
    assert_eq!(get("luz.exposure_ev"), "1");
    assert_eq!(get("luz.capture"), "viewer screenshot");

    let reference = dir.join("reference.png");
    let (code, _, err) = luz(&[
        "render",
        changed.to_str().unwrap(),
        "--width",
        "640",
        "--height",
        "400",
        "-o",
        reference.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let reference = rgb(&reference);
    let before = dir.join("before.png");
    let (code, _, err) = luz(&[
        "render",
        scene.to_str().unwrap(),
        "--width",
        "640",
        "--height",
        "400",
        "-o",
        before.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let before = rgb(&before);

    // The scene: the top right of the window is not covered by panels (side panel on the left,
    // profiler at the bottom) and must be the headless render after the change, within 2 levels
    // (GPU tone map vs CPU, both lavapipe).
    let (w, h) = shot_img.dimensions();
    let right = matching(&shot_img, &reference, (w * 2 / 3, w), h / 2, 2);
    eprintln!("top right matching the reference: {:.2} %", right * 100.0);
    assert!(
        right > 0.97,
        "scene region differs from the headless render: {right}"
    );
    // … and not the render before the change (the UI change took effect).
    let unchanged = matching(&shot_img, &before, (w * 2 / 3, w), h / 2, 2);
    assert!(unchanged < 0.5, "exposure change not applied: {unchanged}");
    // The UI: the left panel covers the left part of the window, so most of it differs.
    let left = matching(&shot_img, &reference, (0, w / 4), h, 8);
    eprintln!("left quarter matching the reference: {:.2} %", left * 100.0);
    assert!(left < 0.5, "no panel found in the screenshot: {left}");
}

#[test]
fn bad_script_is_a_clear_error() {
    let (code, _, err) = luz(&["view", "--script", "5:fly=away"]);
    assert_ne!(code, 0);
    assert!(
        err.contains("unknown action") && err.contains("fly"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn resizes_minimise_restore_and_vsync_survive() {
    let script = "2:resize=300x200;4:minimize;6:restore;8:resize=1x1;10:resize=500x300;\
                  12:vsync=off;14:vsync=on;16:panels=off;18:help=on;20:orbit=40,10;22:zoom=2;\
                  24:frame_all;26:reset;28:debug_view=normal;30:tonemap=agx";
    let Some((code, out, err)) = luz_in_window(&["view", "--frames", "36", "--script", script])
    else {
        return;
    };
    assert_eq!(code, 0, "stdout: {out}\nstderr: {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.contains("validation: 0 errors, 0 warnings"), "{err}");
    assert!(
        out.contains("frames: 3"),
        "the frame count is reported: {out}"
    );
}

#[test]
fn opens_models_and_environments_and_saves_the_scene() {
    let (Some(models), Some(envs)) = (shared_dir("models"), shared_dir("environments")) else {
        return;
    };
    let obj = std::fs::read_dir(&models)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| p.extension().is_some_and(|e| e == "obj"))
        .expect("an OBJ in ../shared/models");
    let hdr = std::fs::read_dir(&envs)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| p.extension().is_some_and(|e| e == "hdr" || e == "exr"))
        .expect("an HDR in ../shared/environments");
    let dir = scratch("open");
    let saved = dir.join("saved.json");
    let script = format!(
        "2:open={};4:open={};6:save={};8:open={};10:open={}",
        obj.display(),
        hdr.display(),
        saved.display(),
        saved.display(),
        dir.join("missing.json").display()
    );
    let Some((code, out, err)) = luz_in_window(&[
        "view",
        "--frames",
        "14",
        "--ibl-quality",
        "fast",
        "--script",
        &script,
    ]) else {
        return;
    };
    assert_eq!(code, 0, "stdout: {out}\nstderr: {err}");
    assert!(out.contains("opened model"), "{out}");
    assert!(out.contains("environment"), "{out}");
    assert!(out.contains("saved"), "{out}");
    assert!(
        out.contains(&format!("opened {}", saved.display())),
        "{out}"
    );
    // A file that does not exist is reported and the viewer goes on.
    assert!(err.contains("missing.json"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.contains("validation: 0 errors, 0 warnings"), "{err}");
    // The saved scene is a valid scene with the model and the environment.
    let scene = luz::scene::load(&saved).unwrap();
    assert!(scene.environment.is_some());
    assert!(scene.triangle_count() > 1000);
}

#[test]
fn a_hundred_resizes_then_a_thousand_frames_leave_nothing_behind() {
    // 100 scripted resizes (sizes cycling from 1×1 to 640×400, with minimise/restore and a 0×0
    // request among them), then 1 000 more frames. Validation (object tracking included) and
    // luz's gpu-allocator leak report run at exit: any message fails the test.
    let mut script = String::new();
    let sizes = [
        (320, 180),
        (1, 1),
        (640, 400),
        (0, 0),
        (200, 120),
        (97, 301),
        (480, 270),
    ];
    for i in 0..100u32 {
        let frame = 2 + i * 2;
        let (w, h) = sizes[i as usize % sizes.len()];
        script.push_str(&format!("{frame}:resize={w}x{h};"));
        if i % 25 == 10 {
            script.push_str(&format!("{}:minimize;{}:restore;", frame + 1, frame + 1));
        }
    }
    script.push_str("203:resize=320x180");
    let Some((code, out, err)) = luz_in_window(&[
        "view",
        "--width",
        "320",
        "--height",
        "180",
        "--frames",
        "1205",
        "--no-panels",
        "--script",
        &script,
    ]) else {
        return;
    };
    assert_eq!(code, 0, "stdout: {out}\nstderr: {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        !err.contains("[ERROR") && !err.contains("[WARNING"),
        "validation or leak messages: {err}"
    );
    assert!(err.contains("validation: 0 errors, 0 warnings"), "{err}");
    assert!(out.contains("frames: 1205 shown"), "{out}");
}

/// Bulk add (issue 18): `add_lights=grid:256` adds 256 ranged point lights, the pass is rebuilt
/// (clustered: the scene now has many ranged lights) and the window shows what a headless render
/// of the saved scene shows.
#[test]
fn bulk_added_lights_show_in_the_window() {
    let dir = scratch("bulk_lights");
    let scene = dir.join("plane.json");
    std::fs::write(
        &scene,
        r#"{
        "camera": {"position": [0, 8, 10], "target": [0, 0, -1], "up": [0, 1, 0], "fov_y_deg": 50, "near": 0.1, "far": 100},
        "output": {"width": 320, "height": 180, "background": [0, 0, 0], "tonemap": "khronos_neutral"},
        "ambient": [0.02, 0.02, 0.02],
        "lights": [{"type": "directional", "direction": [0, -1, 0], "intensity": 0.05}],
        "materials": {"m": {"model": "lambert", "albedo": [0.8, 0.8, 0.8]}},
        "objects": [{"mesh": {"type": "plane", "size": [16, 16]}, "material": "m"}]
    }"#,
    )
    .unwrap();
    let saved = dir.join("saved.json");
    let shot = dir.join("shot.png");
    let script = format!(
        "1:panels=off;2:add_lights=grid:256;6:save={}",
        saved.display()
    );
    let Some((code, out, err)) = luz_in_window(&[
        "view",
        scene.to_str().unwrap(),
        "--frames",
        "12",
        "--script",
        &script,
        "--screenshot",
        shot.to_str().unwrap(),
    ]) else {
        return;
    };
    assert_eq!(code, 0, "stdout: {out}\nstderr: {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.contains("validation: 0 errors, 0 warnings"), "{err}");
    let s = luz::scene::load(&saved).unwrap();
    assert_eq!(s.lights.len(), 257);
    assert!(s.lights[1..].iter().all(|l| l.range.is_some()));
    let reference = dir.join("reference.png");
    let (code, rout, err) = luz(&[
        "render",
        saved.to_str().unwrap(),
        "--verbose",
        "-o",
        reference.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(rout.contains("light loop: clustered"), "{rout}");
    let shot = rgb(&shot);
    let reference = rgb(&reference);
    assert_eq!(shot.dimensions(), reference.dimensions());
    // The left third above the bottom quarter: clear of the frame-time overlay (top right) and
    // the "saved" message (bottom left).
    let (w, h) = shot.dimensions();
    let same = matching(&shot, &reference, (0, w / 3), h * 3 / 4, 2);
    assert!(same > 0.97, "window and headless render differ: {same}");
    // The lights made a difference (the plane under the directional light alone is dark).
    let lit = shot
        .pixels()
        .filter(|p| p.0.iter().any(|&c| c > 60))
        .count();
    assert!(lit > (w * h / 4) as usize, "{lit} bright pixels");
}

/// An EXR screenshot of the viewer is the float image `luz render` writes for the same scene at
/// its own size (before tone mapping: the panels are not in it; the embedded scene, 1280×720), with the validation layer silent (the
/// copy reads the image in TRANSFER_SRC_OPTIMAL, not GENERAL) and sync validation on.
#[test]
fn exr_screenshot_is_the_headless_float_image() {
    let dir = scratch("viewer_exr");
    let shot = dir.join("shot.exr");
    let Some((code, out, err)) = common::luz_in_window_with(
        &[
            "view",
            "--frames",
            "4",
            "--screenshot",
            shot.to_str().unwrap(),
        ],
        &[("LUZ_SYNC_VALIDATION", "1")],
    ) else {
        return;
    };
    assert_ran_clean(code, &out, &err);
    let reference = dir.join("reference.exr");
    let (code, _, err) = luz(&["render", "-o", reference.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    // Float images: FLIP after the scene's tone map, and a radiance bound far under one 8-bit step.
    let (code, out, err) = luz(&[
        "diff",
        reference.to_str().unwrap(),
        shot.to_str().unwrap(),
        "--max-flip-mean",
        "0.001",
        "--max-abs",
        "0.001",
        "--max-bad-pixels",
        "0",
    ]);
    assert_eq!(code, 0, "{out}\n{err}");
}
