//! `luz diff` through the binary: the golden-image tolerances by default (a visibly changed image
//! fails), printed with the result; `none` and `--report-only` turn checks off.

mod common;

use std::path::Path;

use common::{luz, scratch};

/// A 64×48 picture with gradients and a checker, as 8-bit RGB.
fn picture() -> Vec<u8> {
    let (w, h) = (64u32, 48u32);
    let mut rgb = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let c = ((x / 8 + y / 8) % 2) as u8 * 60;
            rgb.extend([(x * 4) as u8, (y * 5) as u8, 40 + c]);
        }
    }
    rgb
}

fn save(path: &Path, rgb: &[u8]) {
    luz::imageio::save_png_rgb8(path, 64, 48, rgb).unwrap();
}

/// The top-left quarter inverted.
fn quarter_inverted(rgb: &[u8]) -> Vec<u8> {
    let mut out = rgb.to_vec();
    for y in 0..24 {
        for x in 0..32 {
            let i = (y * 64 + x) * 3;
            for c in &mut out[i..i + 3] {
                *c = 255 - *c;
            }
        }
    }
    out
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn a_quarter_inverted_fails_by_default_and_the_checks_are_printed() {
    let dir = scratch("quarter");
    let (e, a) = (dir.join("expected.png"), dir.join("actual.png"));
    save(&e, &picture());
    save(&a, &quarter_inverted(&picture()));
    let (code, out, err) = luz(&["diff", s(&e), s(&a)]);
    assert_eq!(code, 1, "{out}\n{err}");
    assert!(
        out.contains(
            "checks   FLIP mean ≤ 0.005, max abs ≤ 8, ≤ 64 pixels beyond 3 \
             (8-bit sRGB code values; the golden-image defaults)"
        ),
        "{out}"
    );
    // 32×24 = 768 inverted pixels; every one differs by far more than 3 steps.
    assert!(out.contains("differ   768 pixels"), "{out}");
    assert!(out.contains("FAIL: FLIP mean"), "{out}");
    assert!(out.contains("FAIL: max abs difference"), "{out}");
    assert!(
        out.contains("FAIL: 768 pixels differ by more than 3"),
        "{out}"
    );
    assert!(!out.contains("PASS"), "{out}");
}

#[test]
fn identical_and_few_lsb_changes_pass_by_default() {
    let dir = scratch("pass");
    let (e, a) = (dir.join("expected.png"), dir.join("actual.png"));
    save(&e, &picture());
    let (code, out, _) = luz(&["diff", s(&e), s(&e)]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("PASS") && out.contains("the golden-image defaults"));
    // Another driver's few LSB: ten pixels off by 5 steps, fifty others by 1.
    let mut near = picture();
    for (i, c) in near.iter_mut().enumerate() {
        if i % 300 == 0 && i < 3000 {
            *c = c.saturating_add(5);
        } else if i % 37 == 1 && i < 37 * 50 {
            *c = c.saturating_add(1);
        }
    }
    save(&a, &near);
    let (code, out, _) = luz(&["diff", s(&e), s(&a)]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("max abs  5 "), "{out}");
    assert!(out.contains("differ   10 pixels"), "{out}");
    // …which a strict limit catches.
    let (code, out, _) = luz(&["diff", s(&e), s(&a), "--max-abs", "4"]);
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains("max abs ≤ 4") && out.contains("as given"),
        "{out}"
    );
}

#[test]
fn none_and_report_only_turn_checks_off() {
    let dir = scratch("off");
    let (e, a) = (dir.join("expected.png"), dir.join("actual.png"));
    save(&e, &picture());
    save(&a, &quarter_inverted(&picture()));
    // One check off: the others still fail.
    let (code, out, _) = luz(&["diff", s(&e), s(&a), "--max-abs", "none"]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("max abs off"), "{out}");
    assert!(!out.contains("FAIL: max abs"), "{out}");
    assert!(out.contains("FAIL: FLIP mean"), "{out}");
    // All three off.
    let (code, out, _) = luz(&[
        "diff",
        s(&e),
        s(&a),
        "--max-abs=none",
        "--max-flip-mean=NONE",
        "--max-bad-pixels=none",
    ]);
    assert_eq!(code, 0, "{out}");
    assert!(
        out.contains("FLIP mean off, max abs off, differing pixels (beyond 3) off"),
        "{out}"
    );
    assert!(out.contains("PASS"), "{out}");
    // Report only: the figures, no verdict against them.
    let (code, out, _) = luz(&["diff", s(&e), s(&a), "--report-only"]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("report only: nothing is checked"), "{out}");
    assert!(out.contains("differ   768 pixels"), "{out}");
    // A bad value names the flag and the way out.
    let (code, _, err) = luz(&["diff", s(&e), s(&a), "--max-bad-pixels", "many"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--max-bad-pixels") && err.contains("none"),
        "{err}"
    );
}

#[test]
fn exr_defaults_are_in_linear_units() {
    let dir = scratch("exr");
    let (e, a) = (dir.join("expected.exr"), dir.join("actual.exr"));
    let mut img = luz::imageio::LinearImage::filled(16, 16, [0.5, 0.25, 0.125, 1.0]);
    luz::imageio::save(&e, &img, 0.0, luz::color::Tonemap::None).unwrap();
    // 0.02 < 8/255 = 0.0314: passes; 0.05 fails on max abs.
    img.pixel_mut(3, 3)[0] += 0.02;
    luz::imageio::save(&a, &img, 0.0, luz::color::Tonemap::None).unwrap();
    let (code, out, _) = luz(&["diff", s(&e), s(&a)]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("max abs ≤ 0.031372"), "{out}");
    img.pixel_mut(3, 3)[0] += 0.03;
    luz::imageio::save(&a, &img, 0.0, luz::color::Tonemap::None).unwrap();
    let (code, out, _) = luz(&["diff", s(&e), s(&a)]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("FAIL: max abs difference"), "{out}");
}

/// A render records where it came from; `luz info` prints it; `luz diff` says where two images'
/// provenance differs.
#[test]
fn provenance_in_renders_info_and_diff() {
    let dir = scratch("provenance");
    let scene = dir.join("tiny.json");
    std::fs::write(
        &scene,
        r#"{"output": {"width": 48, "height": 32, "msaa": 1, "tonemap": "aces", "exposure": 0.5},
            "lights": [{"type": "directional", "direction": [0, -1, -1], "color": [1, 1, 1], "intensity": 2}],
            "materials": {"m": {"model": "lambert", "albedo": [0.5, 0.5, 0.5]}},
            "objects": [{"mesh": {"type": "sphere", "radius": 1}, "material": "m"}]}"#,
    )
    .unwrap();
    let (png, exr) = (dir.join("a.png"), dir.join("a.exr"));
    for out in [&png, &exr] {
        let (code, stdout, err) = luz(&["render", s(&scene), "-o", s(out), "--frames", "3"]);
        assert_eq!(code, 0, "{stdout}\n{err}");
        assert!(err.contains("validation: 0 errors, 0 warnings"), "{err}");
    }
    let hash = luz::imageio::provenance::content_hash(&std::fs::read(&scene).unwrap());
    for (img, encoding) in [(&png, "8-bit sRGB"), (&exr, "linear float32")] {
        let (code, out, err) = luz(&["info", s(img)]);
        assert_eq!(code, 0, "{err}");
        for needle in [
            "luz.version ".to_string(),
            "luz.commit ".to_string(),
            "luz.device                        llvmpipe".to_string(),
            "luz.driver ".to_string(),
            "luz.vulkan                        1.".to_string(),
            format!("luz.scene                         {}", scene.display()),
            format!("luz.scene_hash                    {hash}"),
            "luz.size                          48x32".to_string(),
            "luz.tonemap                       aces".to_string(),
            "luz.exposure_ev                   0.5".to_string(),
            "luz.frame.frames                  3".to_string(),
            "luz.frame.cpu_median_ms ".to_string(),
            format!("luz.encoding                      {encoding}"),
        ] {
            assert!(out.contains(&needle), "{needle:?} missing in:\n{out}");
        }
    }
    // Another scene file: diff names the differing provenance (not the frame times).
    let other = dir.join("other.json");
    std::fs::copy(&scene, &other).unwrap();
    let png2 = dir.join("b.png");
    let (code, _, err) = luz(&["render", s(&other), "-o", s(&png2)]);
    assert_eq!(code, 0, "{err}");
    let (code, out, _) = luz(&["diff", s(&png), s(&png2)]);
    assert_eq!(code, 0, "same pixels: {out}");
    assert!(
        out.contains(&format!(
            "provenance differs: luz.scene: expected {} | actual {}",
            scene.display(),
            other.display()
        )),
        "{out}"
    );
    assert!(!out.contains("luz.frame"), "{out}");
    assert!(!out.contains("luz.scene_hash"), "same contents: {out}");
    // Bad input: named, exit 1.
    let (code, _, err) = luz(&["info", s(&dir.join("missing.png"))]);
    assert_eq!(code, 1);
    assert!(err.contains("missing.png: no such file"), "{err}");
}

/// The fidelity site's score written out from the formula (pixelmatch's YIQ colour delta,
/// model-viewer's `ImageComparator.analyze` and `toDecibel`), independently of luz's code.
fn khronos_db_by_the_formula(candidate: &[[u8; 4]], golden: &[[u8; 4]]) -> f64 {
    fn yiq(p: [u8; 4]) -> [f64; 3] {
        let a = f64::from(p[3]) / 255.0;
        let [r, g, b] = [p[0], p[1], p[2]].map(|c| 255.0 + (f64::from(c) - 255.0) * a);
        [
            r * 0.29889531 + g * 0.58662247 + b * 0.11448223,
            r * 0.59597799 - g * 0.27417610 - b * 0.32180189,
            r * 0.21147017 - g * 0.52261711 + b * 0.31114694,
        ]
    }
    let (mut sum, mut n) = (0.0, 0.0);
    for (c, g) in candidate.iter().zip(golden) {
        if c[3] == 0 {
            continue;
        }
        let (p, q) = (yiq(*c), yiq(*g));
        let (y, i, qq) = (p[0] - q[0], p[1] - q[1], p[2] - q[2]);
        let delta = 0.5053 * y * y + 0.299 * i * i + 0.1957 * qq * qq;
        sum += delta * delta;
        n += 1.0;
    }
    10.0 * ((sum / n).sqrt() / 35215.0).log10()
}

fn save_rgba(path: &Path, w: u32, h: u32, px: &[[u8; 4]]) {
    let bytes: Vec<u8> = px.iter().flatten().copied().collect();
    image::save_buffer(path, &bytes, w, h, image::ColorType::Rgba8).unwrap();
}

fn printed_db(out: &str) -> f64 {
    let line = out
        .lines()
        .find(|l| l.starts_with("khronos-db  "))
        .unwrap_or_else(|| panic!("{out}"));
    line["khronos-db  ".len()..]
        .split(" dB")
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

/// `luz diff --metric khronos-db` equals the formula (transparent candidate pixels skipped,
/// semi-transparent ones blended with white) and fails above model-viewer's −22 dB.
#[test]
fn khronos_db_matches_the_formula_and_the_threshold() {
    let dir = scratch("khronos-db");
    let (w, h) = (40u32, 30u32);
    let golden: Vec<[u8; 4]> = (0..w * h)
        .map(|i| [(i % w * 6) as u8, (i / w * 8) as u8, 90, 255])
        .collect();
    // A small change: a few pixels shifted, one semi-transparent, two transparent (skipped).
    let mut near = golden.clone();
    for i in (0..near.len()).step_by(7) {
        near[i][0] = near[i][0].saturating_add(12);
    }
    near[5][3] = 250;
    near[6] = [0, 0, 0, 0];
    near[9] = [255, 0, 0, 0];
    // A large change: the colours inverted.
    let far: Vec<[u8; 4]> = golden
        .iter()
        .map(|p| [255 - p[0], 255 - p[1], 255 - p[2], 255])
        .collect();
    let g = dir.join("golden.png");
    save_rgba(&g, w, h, &golden);
    for (name, img, passes) in [("near", &near, true), ("far", &far, false)] {
        let c = dir.join(format!("{name}.png"));
        save_rgba(&c, w, h, img);
        let (code, out, err) = luz(&["diff", s(&g), s(&c), "--metric", "khronos-db"]);
        let want = khronos_db_by_the_formula(img, &golden);
        let got = printed_db(&out);
        assert!(
            (got - want).abs() < 1e-3,
            "{name}: printed {got}, formula {want}\n{out}"
        );
        assert!(out.contains("checks   khronos-db ≤ -22 dB"), "{out}");
        assert_eq!(
            code,
            if passes { 0 } else { 1 },
            "{name} ({want} dB): {out}\n{err}"
        );
        assert_eq!(want < -22.0, passes, "{name}: {want}");
    }
    // The transparent pixels were skipped: 1200 − 2 counted.
    let c = dir.join("near.png");
    let (_, out, _) = luz(&["diff", s(&g), s(&c), "--metric", "khronos-db"]);
    assert!(out.contains("over 1198 non-transparent pixels"), "{out}");
    // Identical: −∞; a threshold of one's own; FLIP options are refused with this metric.
    let (code, out, _) = luz(&["diff", s(&g), s(&g), "--metric", "khronos-db"]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("-inf dB (identical)"), "{out}");
    let (code, out, _) = luz(&[
        "diff",
        s(&g),
        s(&c),
        "--metric",
        "khronos-db",
        "--max-db",
        "-60",
    ]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("above --max-db -60"), "{out}");
    let (code, _, err) = luz(&[
        "diff",
        s(&g),
        s(&c),
        "--metric",
        "khronos-db",
        "--max-abs",
        "3",
    ]);
    assert_eq!(code, 1);
    assert!(err.contains("--max-db"), "{err}");
}
