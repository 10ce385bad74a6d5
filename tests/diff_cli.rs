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
