//! The slides' figures (assets/scenes/classic/) against goldens, saturation policies, and Gouraud
//! missing a highlight that Phong shading catches.

mod common;

use common::*;
use glam::Vec3;
use luz::imageio::LinearImage;

fn classic_scene(name: &str) -> luz::scene::Scene {
    luz::scene::load(
        &root()
            .join("assets/scenes/classic")
            .join(format!("{name}.json")),
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

fn golden(name: &str) {
    // The scene through its case file, as `luz golden tests/golden` renders it.
    let scene = golden_scene(&format!("classic_{name}"));
    assert_same_scene(&scene, &classic_scene(name));
    let img = render(&scene);
    check_golden(
        &format!("classic_{name}"),
        &scene,
        &img,
        Tolerance::default(),
    );
}

#[test]
fn classic_01_ambient() {
    golden("01_ambient");
}
#[test]
fn classic_02_diffuse_ka() {
    golden("02_diffuse_ka");
}
#[test]
fn classic_03_diffuse_kd() {
    golden("03_diffuse_kd");
}
#[test]
fn classic_04_specular_n() {
    golden("04_specular_n");
}
#[test]
fn classic_05_specular_ks() {
    golden("05_specular_ks");
}
#[test]
fn classic_06_colour() {
    golden("06_colour");
}
#[test]
fn classic_07_multiple_lights() {
    golden("07_multiple_lights");
}
#[test]
fn classic_08_depth_cue_off() {
    golden("08_depth_cue_off");
}
#[test]
fn classic_09_depth_cue_on() {
    golden("09_depth_cue_on");
}

/// Every figure of the slides has a golden test above.
#[test]
fn every_classic_scene_has_a_golden_test() {
    let src = std::fs::read_to_string(root().join("tests/classic_scenes.rs")).unwrap();
    for e in std::fs::read_dir(root().join("assets/scenes/classic")).unwrap() {
        let p = e.unwrap().path();
        let stem = p.file_stem().unwrap().to_string_lossy().into_owned();
        assert!(
            src.contains(&format!("golden(\"{stem}\")")),
            "{stem} has no golden test"
        );
    }
}

/// The ambient-only figure is I_a k_a O_d exactly: 0.4, 0.8 and 0.6 at the sphere centres.
#[test]
fn ambient_figure_values() {
    let scene = classic_scene("01_ambient");
    let img = render(&scene);
    let row = img.height / 2;
    let mut seen = Vec::new();
    for x in 0..img.width {
        let v = img.pixels[(row * img.width + x) as usize][0];
        if v > 0.0 && !seen.iter().any(|s: &f32| (s - v).abs() < 1e-6) {
            seen.push(v);
        }
    }
    for k in [0.4f32, 0.8, 0.6] {
        assert!(
            seen.iter().any(|s| (s - k).abs() < 1e-6),
            "no pixel equals I_a k_a = {k}; values on the middle row: {seen:?}"
        );
    }
}

/// Depth cueing darkens the far sphere towards black and leaves the near one brighter.
#[test]
fn depth_cue_changes_far_more_than_near() {
    let off = render(&classic_scene("08_depth_cue_off"));
    let on = render(&classic_scene("09_depth_cue_on"));
    let mean = |img: &LinearImage, x0: u32, x1: u32| -> f32 {
        let mut s = 0.0;
        let mut n = 0;
        for y in 0..img.height {
            for x in x0..x1 {
                let p = img.pixels[(y * img.width + x) as usize];
                if p[0] + p[1] + p[2] > 0.0 {
                    s += p[0] + p[1] + p[2];
                    n += 1;
                }
            }
        }
        s / n.max(1) as f32
    };
    let w = off.width;
    let (near_off, near_on) = (mean(&off, 0, w / 3), mean(&on, 0, w / 3));
    let (far_off, far_on) = (mean(&off, 2 * w / 3, w), mean(&on, 2 * w / 3, w));
    let near_ratio = near_on / near_off;
    let far_ratio = far_on / far_off;
    assert!(
        far_ratio < near_ratio - 0.2,
        "fog: near keeps {near_ratio:.3} of its brightness, far {far_ratio:.3}"
    );
}

fn bright_scene(saturation: &str) -> luz::scene::Scene {
    parse(&format!(
        r#"{{
        "camera": {{"position": [0, 0, 4], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 40, "near": 0.1, "far": 10}},
        "output": {{"width": 96, "height": 64}},
        "ambient": [0.1, 0.1, 0.1],
        "lights": [{{"type": "point", "position": [2, 2, 3], "color": [1, 0.5, 0.25], "intensity": 3, "falloff": "none"}}],
        "materials": {{"m": {{"model": "phong", "ka": 1, "kd": 0.9, "ks": 0.8, "shininess": 10, "diffuse_color": [1, 1, 1], "specular_color": [1, 1, 1]}}}},
        "objects": [{{"mesh": {{"type": "sphere", "radius": 1, "segments": 48, "rings": 24}}, "material": "m"}}],
        "saturation": "{saturation}"
    }}"#
    ))
}

/// Clamp is min(I, 1) per channel; normalize divides the whole image by its largest channel value.
#[test]
fn saturation_clamp_and_normalize() {
    let raw = render(&bright_scene("none"));
    let max = raw
        .pixels
        .iter()
        .flat_map(|p| p[..3].iter().copied())
        .fold(0.0f32, f32::max);
    assert!(max > 2.0, "the test scene must exceed 1 (max {max})");
    let clamped = render(&bright_scene("clamp"));
    let normalized = render(&bright_scene("normalize"));
    for ((r, c), n) in raw
        .pixels
        .iter()
        .zip(&clamped.pixels)
        .zip(&normalized.pixels)
    {
        for k in 0..3 {
            assert_eq!(c[k], r[k].min(1.0), "clamp");
            let want = r[k] / max;
            assert!(
                (n[k] - want).abs() <= 1e-6 * want.max(1e-3) + 1e-7,
                "normalize: {} vs {want}",
                n[k]
            );
        }
    }
    let nmax = normalized
        .pixels
        .iter()
        .flat_map(|p| p[..3].iter().copied())
        .fold(0.0f32, f32::max);
    assert!((nmax - 1.0).abs() < 1e-6, "normalized maximum {nmax}");
}

/// A coarse sphere with a sharp Blinn-Phong highlight placed inside a polygon: Phong shading
/// (per fragment) reaches the analytic peak, Gouraud (per vertex) misses most of it.
#[test]
fn gouraud_misses_highlight_phong_catches() {
    let cam = Vec3::new(0.0, 0.0, 5.0);
    let light_dir = Vec3::new(-0.25, -0.2, -1.0).normalize();
    let shininess = 300.0f32;
    let scene_for = |shading: &str| {
        parse(&format!(
            r#"{{
            "camera": {{"position": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 30, "near": 0.1, "far": 20}},
            "output": {{"width": 200, "height": 200}},
            "ambient": [0, 0, 0],
            "lights": [{{"type": "directional", "direction": [{}, {}, {}], "color": [1, 1, 1], "intensity": 1}}],
            "materials": {{"m": {{"model": "blinn_phong", "ka": 0, "kd": 0.2, "ks": 1, "shininess": {shininess}, "diffuse_color": [1, 1, 1], "specular_color": [1, 1, 1]}}}},
            "objects": [{{"mesh": {{"type": "sphere", "radius": 1, "segments": 10, "rings": 5}}, "material": "m", "shading": "{shading}"}}]
        }}"#,
            light_dir.x, light_dir.y, light_dir.z
        ))
    };
    // Analytic peak over the true sphere, sampled densely.
    let l = -light_dir;
    let mut analytic = 0.0f32;
    for i in 0..400 {
        for j in 0..400 {
            let theta = std::f32::consts::PI * (i as f32 + 0.5) / 400.0;
            let phi = 2.0 * std::f32::consts::PI * (j as f32 + 0.5) / 400.0;
            let n = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            let v = (cam - n).normalize();
            if n.dot(v) <= 0.0 || n.dot(l) <= 0.0 {
                continue;
            }
            let h = (l + v).normalize();
            analytic = analytic.max(0.2 * n.dot(l) + n.dot(h).max(0.0).powf(shininess));
        }
    }
    let peak = |img: &LinearImage| img.pixels.iter().map(|p| p[0]).fold(0.0f32, f32::max);
    let phong = peak(&render(&scene_for("phong")));
    let gouraud = peak(&render(&scene_for("gouraud")));
    let flat = peak(&render(&scene_for("flat")));
    eprintln!(
        "highlight peak: analytic {analytic:.4}, Phong shading {phong:.4}, Gouraud {gouraud:.4}, flat {flat:.4}"
    );
    assert!(
        (phong - analytic).abs() < 0.03 * analytic,
        "Phong shading peak {phong} vs analytic {analytic}"
    );
    assert!(
        gouraud < 0.6 * analytic,
        "Gouraud should miss the highlight: peak {gouraud} vs analytic {analytic}"
    );
}
