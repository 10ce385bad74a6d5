//! The lab in the viewer window (issue 20), under Xvfb on lavapipe with validation on, driven by
//! scripted actions and checked on screenshots (swapchain images, UI included):
//!
//! * `--compare`: a red and a blue version of one scene in split mode show red left of the
//!   divider and blue right of it, wherever the divider is put; toggle mode shows one side whole.
//! * difference mode of identical inputs is one colour (the palette's zero); of different inputs
//!   it is not that colour.
//! * the error view against the CPU reference: uniform for a Lambert plane (the GPU renders it
//!   exactly), not uniform for a coarsely tessellated sphere.

mod common;

use std::path::{Path, PathBuf};

use common::{luz, luz_in_window, scratch};

/// The window (and scene) size: wide enough for the compact profiler and the status line to
/// take one line each.
const W: u32 = 480;
const H: u32 = 300;

fn rgb(path: &Path) -> image::RgbImage {
    image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgb8()
}

/// A Lambert plane filling the view, lit by one directional light (constant radiance).
fn plane_scene(dir: &Path, name: &str, albedo: [f32; 3]) -> PathBuf {
    let path = dir.join(format!("{name}.json"));
    std::fs::write(
        &path,
        format!(
            r#"{{
  "description": "viewer lab test: a Lambert plane filling the view",
  "camera": {{"position": [0, 6, 0.001], "target": [0, 0, 0], "up": [0, 0, -1], "fov_y_deg": 50, "near": 0.1, "far": 100}},
  "output": {{"width": {W}, "height": {H}, "background": [0, 0, 0], "tonemap": "khronos_neutral"}},
  "ambient": [0, 0, 0],
  "lights": [{{"type": "directional", "direction": [0.3, -1, 0.2], "intensity": 1.0}}],
  "materials": {{"m": {{"model": "lambert", "albedo": {albedo:?}}}}},
  "objects": [{{"mesh": {{"type": "plane", "size": [40, 40]}}, "material": "m"}}]
}}"#
        ),
    )
    .unwrap();
    path
}

/// Runs `luz view SCENE [--compare B]` in a `w × h` window for `frames` frames with `script`,
/// checks it succeeded with validation silent; returns stdout and stderr.
fn view(
    scene: &Path,
    compare: Option<&Path>,
    (w, h): (u32, u32),
    frames: u32,
    script: &str,
) -> Option<String> {
    let (w, h, frames) = (w.to_string(), h.to_string(), frames.to_string());
    let mut args = vec!["view", scene.to_str().unwrap()];
    if let Some(b) = compare {
        args.extend(["--compare", b.to_str().unwrap()]);
    }
    args.extend([
        "--width", &w, "--height", &h, "--frames", &frames, "--script", script,
    ]);
    let (code, out, err) = luz_in_window(&args)?;
    assert_eq!(code, 0, "luz view failed\nstdout: {out}\nstderr: {err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        err.contains("validation: 0 errors, 0 warnings"),
        "validation must be silent: {err}"
    );
    Some(format!("{out}\n{err}"))
}

/// Pixels of rows 90..250 (below the compact profiler, up to three lines, and its shadow; above
/// the status line) in columns `x0..x1`.
fn region(img: &image::RgbImage, (x0, x1): (u32, u32)) -> Vec<[u8; 3]> {
    rows(img, (x0, x1), (90, 250))
}

/// Pixels of rows 90..185: clear of the compact profiler and the map legend (bottom right, about
/// 80 px tall) and of their popup shadows.
fn map_region(img: &image::RgbImage) -> Vec<[u8; 3]> {
    rows(img, (0, W), (90, 185))
}

fn rows(img: &image::RgbImage, (x0, x1): (u32, u32), (y0, y1): (u32, u32)) -> Vec<[u8; 3]> {
    let mut out = Vec::new();
    for y in y0..y1 {
        for x in x0..x1 {
            out.push(img.get_pixel(x, y).0);
        }
    }
    out
}

fn all(px: &[[u8; 3]], f: impl Fn([u8; 3]) -> bool) -> bool {
    px.iter().all(|&p| f(p))
}

fn red(p: [u8; 3]) -> bool {
    p[0] > 100 && p[2] < 40
}

fn blue(p: [u8; 3]) -> bool {
    p[2] > 100 && p[0] < 40
}

/// The palette's zero (black; (0, 0, 12) on screen after egui's colour handling).
fn dark(p: [u8; 3]) -> bool {
    p.iter().map(|&c| u32::from(c)).sum::<u32>() < 40
}

/// The per-channel spread (max − min) over `px`.
fn spread(px: &[[u8; 3]]) -> u8 {
    (0..3)
        .map(|c| {
            let hi = px.iter().map(|p| p[c]).max().unwrap();
            let lo = px.iter().map(|p| p[c]).min().unwrap();
            hi - lo
        })
        .max()
        .unwrap()
}

#[test]
fn split_shows_a_left_and_b_right_and_toggle_shows_one_side() {
    let dir = scratch("lab_split");
    let a = plane_scene(&dir, "red", [0.8, 0.05, 0.05]);
    let b = plane_scene(&dir, "blue", [0.05, 0.05, 0.8]);
    let shot = |n: &str| dir.join(format!("{n}.png"));
    let script = format!(
        "1:panels=off;4:screenshot={};5:compare_split=0.25;8:screenshot={};9:compare_mode=toggle;\
         12:screenshot={};13:compare_flip;16:screenshot={}",
        shot("half").display(),
        shot("quarter").display(),
        shot("toggle_a").display(),
        shot("toggle_b").display(),
    );
    let Some(_) = view(&a, Some(&b), (W, H), 20, &script) else {
        return;
    };
    // Divider at the middle (x = 240): red left, blue right (the line and its handle excluded).
    let half = rgb(&shot("half"));
    assert_eq!(half.dimensions(), (W, H));
    assert!(
        all(&region(&half, (0, 230)), red),
        "left of the divider is A (red)"
    );
    assert!(
        all(&region(&half, (250, W)), blue),
        "right of the divider is B (blue)"
    );
    // Divider at a quarter (x = 120): the middle is now B.
    let quarter = rgb(&shot("quarter"));
    assert!(all(&region(&quarter, (0, 110)), red));
    assert!(
        all(&region(&quarter, (130, W)), blue),
        "compare_split moved the divider"
    );
    // Toggle: A whole, then (compare_flip, the B key) B whole.
    assert!(all(&region(&rgb(&shot("toggle_a")), (0, W)), red));
    assert!(all(&region(&rgb(&shot("toggle_b")), (0, W)), blue));
}

/// A figure of the viewer's exit line `A/B maps: … difference maps … last: mean M p99 P max X
/// scale S above F` for `kind` (`difference` or `flip`).
fn map_figure(log: &str, kind: &str, name: &str) -> f64 {
    let line = log
        .lines()
        .find(|l| l.contains("A/B maps:"))
        .unwrap_or_else(|| panic!("no A/B maps line: {log}"));
    let part = line
        .split(';')
        .find(|p| p.contains(&format!(" {kind} maps")))
        .unwrap_or_else(|| panic!("no {kind} maps in {line}"));
    let rest = part
        .split(&format!(" {name} "))
        .nth(1)
        .unwrap_or_else(|| panic!("no {name} in {part}"));
    rest.split(' ').next().unwrap().parse().unwrap()
}

#[test]
fn difference_and_flip_maps_on_the_gpu_follow_every_frame() {
    let dir = scratch("lab_difference");
    let a = plane_scene(&dir, "red", [0.8, 0.05, 0.05]);
    let b = plane_scene(&dir, "blue", [0.05, 0.05, 0.8]);
    let mut images = Vec::new();
    let mut logs = Vec::new();
    for (other, name) in [(&a, "same"), (&b, "different")] {
        let shot = |m: &str| dir.join(format!("{name}_{m}.png"));
        let script = format!(
            "1:panels=off;2:compare_mode=difference;8:screenshot={};9:compare_mode=flip;\
             14:screenshot={}",
            shot("difference").display(),
            shot("flip").display()
        );
        let Some(log) = view(&a, Some(other), (W, H), 16, &script) else {
            return;
        };
        images.push((rgb(&shot("difference")), rgb(&shot("flip"))));
        logs.push(log);
    }
    // Identical inputs: every pixel of both maps is the palette's zero, and the figures are 0.
    for img in [&images[0].0, &images[0].1] {
        let same = map_region(img);
        assert!(spread(&same) == 0, "map of identical inputs is not uniform");
        assert!(all(&same, dark), "{:?}", same[0]);
    }
    for kind in ["difference", "flip"] {
        assert_eq!(map_figure(&logs[0], kind, "max"), 0.0, "{}", logs[0]);
    }
    // Red against blue: max_c |A − B| = 0.75 / π · cos θ (Lambert, irradiance 1 at cos θ =
    // 1/|(0.3, −1, 0.2)|) at every pixel; the colour bar's top is that value, so the map is the
    // palette's top colour everywhere.
    let expected = 0.75 / std::f64::consts::PI / (0.3f64 * 0.3 + 1.0 + 0.2 * 0.2).sqrt();
    for name in ["max", "mean", "p99", "scale"] {
        let v = map_figure(&logs[1], "difference", name);
        assert!(
            (v - expected).abs() < 1e-5 * expected,
            "{name} {v} vs {expected}: {}",
            logs[1]
        );
    }
    let top = luz::compare::palette()[255];
    let different = map_region(&images[1].0);
    assert!(
        all(&different, |p| p == top),
        "the difference of red and blue is the top colour {top:?}: {:?}",
        different[0]
    );
    // FLIP of red against blue: uniform and far from zero.
    let flip = map_region(&images[1].1);
    assert!(spread(&flip) == 0, "FLIP of two uniform images is uniform");
    assert!(map_figure(&logs[1], "flip", "mean") > 0.3, "{}", logs[1]);
}

#[test]
fn error_view_shows_each_side_against_its_reference() {
    let dir = scratch("lab_error_sides");
    let plane = plane_scene(&dir, "plane", [0.7, 0.7, 0.7]);
    let sphere = coarse_sphere(&dir);
    let shot = dir.join("sides.png");
    let script = format!(
        "1:panels=off;2:error_view=on;118:screenshot={}",
        shot.display()
    );
    let Some(log) = view(&plane, Some(&sphere), (W, H), 120, &script) else {
        return;
    };
    let line = |side: &str| {
        log.lines()
            .find(|l| l.contains(&format!("error view{side}: reference")))
            .unwrap_or_else(|| panic!("{side:?} reference finished within 120 frames: {log}"))
            .to_string()
    };
    let (a, b) = (line(""), line(" B"));
    eprintln!("{a}\n{b}");
    assert!(mean_relative(&a) < 1e-4, "{a}");
    assert!(mean_relative(&b) > 0.01, "{b}");
    // Split mode (the default): A's map left of the divider (uniform zero), B's right of it.
    // Columns left of x = 150 only: the colour bar's box starts at x ≈ 160 and grows upwards
    // into these rows when its B line wraps (a longer max figure).
    let img = rgb(&shot);
    let left = rows(&img, (0, 150), (90, 185));
    assert!(spread(&left) <= 1 && all(&left, dark), "{:?}", left[0]);
    let right = rows(&img, (250, W), (90, 185));
    assert!(spread(&right) > 150, "B's error map is not uniform");
}

#[test]
fn error_view_is_uniform_for_a_lambert_plane_and_not_for_a_coarse_sphere() {
    let dir = scratch("lab_error");
    let plane = plane_scene(&dir, "plane", [0.7, 0.7, 0.7]);
    let sphere = coarse_sphere(&dir);
    let mut results = Vec::new();
    for scene in [&plane, &sphere] {
        let shot = scene.with_extension("png");
        let script = format!(
            "1:panels=off;2:error_view=on;118:screenshot={}",
            shot.display()
        );
        let Some(log) = view(scene, None, (W, H), 120, &script) else {
            return;
        };
        let line = log
            .lines()
            .find(|l| l.contains("error view: reference"))
            .unwrap_or_else(|| panic!("the reference finished within 120 frames: {log}"))
            .to_string();
        results.push((rgb(&shot), line));
    }
    let (plane_img, plane_line) = &results[0];
    let (sphere_img, sphere_line) = &results[1];
    eprintln!("{plane_line}\n{sphere_line}");
    // The plane: the map is one colour, the palette's zero (the relative error rounds to 0).
    let p = map_region(plane_img);
    assert!(spread(&p) <= 1, "plane error map not uniform: {plane_line}");
    assert!(all(&p, dark), "{:?}", p[0]);
    assert!(mean_relative(plane_line) < 1e-4, "{plane_line}");
    // The sphere: facets and silhouette differ from the exact sphere; dark and bright pixels.
    let s = map_region(sphere_img);
    assert!(
        spread(&s) > 150,
        "sphere error map looks uniform: {sphere_line}"
    );
    let bright = s
        .iter()
        .filter(|c| c.iter().map(|&v| u32::from(v)).sum::<u32>() > 300);
    assert!(bright.count() > 200, "{sphere_line}");
    assert!(mean_relative(sphere_line) > 0.01, "{sphere_line}");
}

/// A coarsely tessellated (8 × 4), flat-shaded Lambert sphere.
fn coarse_sphere(dir: &Path) -> PathBuf {
    let sphere = dir.join("sphere.json");
    std::fs::write(
        &sphere,
        format!(
            r#"{{
  "description": "viewer lab test: a coarsely tessellated Lambert sphere, flat shaded",
  "camera": {{"position": [0, 0, 4], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 45, "near": 0.1, "far": 100}},
  "output": {{"width": {W}, "height": {H}, "background": [0, 0, 0], "tonemap": "khronos_neutral"}},
  "ambient": [0, 0, 0],
  "lights": [{{"type": "directional", "direction": [0.3, -0.5, -1], "intensity": 1.0}}],
  "materials": {{"m": {{"model": "lambert", "albedo": [0.7, 0.7, 0.7]}}}},
  "objects": [{{"mesh": {{"type": "sphere", "radius": 1, "segments": 8, "rings": 4}}, "material": "m", "shading": "flat"}}]
}}"#
        ),
    )
    .unwrap();
    sphere
}

/// The mean relative error of the viewer's "error view: reference …" log line.
fn mean_relative(line: &str) -> f64 {
    let rest = line
        .split("relative error mean ")
        .nth(1)
        .unwrap_or_else(|| panic!("no mean in {line}"));
    let token = rest.split([' ', ';']).next().unwrap();
    token
        .parse()
        .unwrap_or_else(|_| panic!("{token:?} in {line}"))
}

#[test]
fn a_missing_compare_file_is_a_clear_error() {
    let dir = scratch("lab_missing");
    let missing = dir.join("nothing_here.json");
    let (code, _, err) = luz(&["view", "--compare", missing.to_str().unwrap()]);
    assert_ne!(code, 0);
    assert!(err.contains("nothing_here.json"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn lobe_plots_appear_in_the_lab_panel() {
    let dir = scratch("lab_plots");
    let plane = plane_scene(&dir, "plane", [0.7, 0.7, 0.7]);
    let mut white = Vec::new();
    // The lab panel opened by a lab action, without and with the lobe plots (white charts).
    for (action, name) in [("error_view=off", "without"), ("lobe_plots=on", "with")] {
        let shot = dir.join(format!("{name}.png"));
        let script = format!("2:{action};40:screenshot={}", shot.display());
        let Some(_) = view(&plane, None, (900, 700), 42, &script) else {
            return;
        };
        let img = rgb(&shot);
        let n = rows(&img, (650, 900), (0, 700))
            .iter()
            .filter(|p| p.iter().all(|&c| c >= 245))
            .count();
        white.push(n);
    }
    eprintln!(
        "white pixels in the lab panel: without plots {}, with {}",
        white[0], white[1]
    );
    assert!(white[0] < 2_000, "{white:?}");
    assert!(white[1] > 20_000, "the three charts are drawn: {white:?}");
}

#[test]
fn a_parameter_changed_on_b_shows_right_of_the_divider_only() {
    let dir = scratch("lab_edit_b");
    let a = plane_scene(&dir, "red", [0.8, 0.05, 0.05]);
    let shot = dir.join("shot.png");
    // B = a copy of A, then B's exposure 3 EV down (the scene panels edit B).
    let script = format!(
        "1:panels=off;2:compare_duplicate;3:compare_edit=b;4:exposure=-3;8:screenshot={}",
        shot.display()
    );
    let Some(_) = view(&a, None, (W, H), 10, &script) else {
        return;
    };
    let img = rgb(&shot);
    let mean_red = |x0, x1| {
        let px = region(&img, (x0, x1));
        px.iter().map(|p| f64::from(p[0])).sum::<f64>() / px.len() as f64
    };
    let (left, right) = (mean_red(0, 230), mean_red(250, W));
    eprintln!("red level: A {left:.1}, B {right:.1}");
    assert!(left > 100.0, "A keeps its exposure: {left}");
    assert!(right < 0.6 * left, "B is 3 EV darker: {right} vs {left}");
}

/// A 173 × 101 HDR test image: gradients, a disc with a hard edge, fine stripes and values above
/// 1 (the tone map's shoulder); `shift` moves the disc and tints the stripes.
fn pattern(shift: f32) -> luz::imageio::LinearImage {
    let (w, h) = (173u32, 101u32);
    let mut pixels = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let (u, v) = (x as f32 / w as f32, y as f32 / h as f32);
            let mut c = [0.05 + 2.5 * u * u, 0.2 * v, 0.6 * (1.0 - u), 1.0];
            let (dx, dy) = (x as f32 - 60.0 - shift, y as f32 - 50.0);
            if dx * dx + dy * dy < 900.0 {
                c = [4.0, 1.5 + 0.1 * shift, 0.3, 1.0];
            }
            if x > 120 && (x / 2) % 2 == 0 {
                c[1] += 0.5 + 0.05 * shift;
            }
            pixels.push(c);
        }
    }
    luz::imageio::LinearImage {
        width: w,
        height: h,
        pixels,
    }
}

/// The GPU maps the viewer draws every frame in `difference` and `flip` modes against the CPU
/// code (`compare::difference_map`, nv-flip through `compare::flip_map`), headless.
#[test]
fn gpu_maps_match_the_cpu_maps() {
    use luz::color::Tonemap;
    use luz::render::compare::{compare_images, CompareKind};
    let ctx = common::gpu();
    let pool = luz::vk::cmd::CommandPool::new(&ctx, "compare test").unwrap();
    let (a, b) = (pattern(0.0), pattern(3.0));
    let (w, h) = (a.width, a.height);
    let display = (0.5, Tonemap::KhronosNeutral);
    // Identical inputs: exactly zero everywhere, in both kinds, and a zero scale.
    for kind in [CompareKind::Difference, CompareKind::Flip] {
        let (map, s) = compare_images(&ctx, &pool, (&a, &a), kind, display).unwrap();
        assert!(map.values.iter().all(|&v| v == 0.0), "{kind:?}: {s:?}");
        assert_eq!((s.stats.max, s.stats.mean, s.stats.above), (0.0, 0.0, 0.0));
    }
    // Difference: the CPU formula bit for bit (one subtraction and a max per pixel).
    let (map, s) = compare_images(&ctx, &pool, (&a, &b), CompareKind::Difference, display).unwrap();
    let cpu = luz::compare::difference_map(&a.pixels, &b.pixels, w, h);
    assert_eq!(map.values, cpu.values);
    let exact = luz::compare::MapStats::of(&cpu.values);
    assert_eq!(s.stats.max, exact.max);
    assert!(
        (s.stats.mean - exact.mean).abs() <= 1e-5 * exact.mean,
        "{s:?} {exact:?}"
    );
    assert_eq!(s.stats.above, exact.above);
    // p99 within its 1/6-octave bin, and the colour bar's top is it.
    assert!(s.stats.p99 >= exact.p99 && s.stats.p99 <= exact.p99 * 2f32.powf(1.0 / 6.0) * 1.0001);
    assert_eq!(s.scale, s.stats.p99);
    // FLIP: nv-flip's C++ on the CPU against the GLSL port, per pixel.
    let (map, s) = compare_images(&ctx, &pool, (&a, &b), CompareKind::Flip, display).unwrap();
    let cpu = luz::compare::flip_map(&a.pixels, &b.pixels, (w, h), display);
    let diffs: Vec<f32> = map
        .values
        .iter()
        .zip(&cpu.values)
        .map(|(g, c)| (g - c).abs())
        .collect();
    let max_diff = diffs.iter().copied().fold(0.0f32, f32::max);
    let mean_diff = diffs.iter().sum::<f32>() / diffs.len() as f32;
    let cpu_stats = luz::compare::MapStats::of(&cpu.values);
    eprintln!(
        "FLIP GPU vs CPU: max |Δ| {max_diff:.2e}, mean |Δ| {mean_diff:.2e}; mean GPU {:.5} CPU {:.5}",
        s.stats.mean, cpu_stats.mean
    );
    assert!(cpu_stats.mean > 0.05, "the pattern differs: {cpu_stats:?}");
    assert!(max_diff < 2e-4, "max |GPU − CPU| FLIP {max_diff}");
    assert!(mean_diff < 1e-5, "mean |GPU − CPU| FLIP {mean_diff}");
    assert!((s.stats.mean - cpu_stats.mean).abs() < 1e-4);
    assert_eq!(s.scale, 1.0);
    common::assert_no_validation_messages(&ctx);
}
