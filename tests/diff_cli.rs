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
