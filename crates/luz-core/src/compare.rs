//! Per-pixel comparison maps of two linear radiance images (the viewer's A/B `difference` and
//! `flip` modes and its error view against the CPU reference), their summary figures and their
//! colour mapping. CPU only, no window code: the viewer reads both images back and calls these on
//! a worker thread.
//!
//! * [`difference_map`]: `max_c |A_c − B_c|` in linear radiance (before exposure and tone
//!   mapping), so identical inputs give an all-zero map whatever the scale.
//! * [`relative_error_map`]: `max_c |T_c − R_c| / max(R_c, floor)` against a reference `R`.
//! * [`flip_map`]: LDR FLIP (the `luz diff` code, [`crate::diff::flip_error_map`]) of both
//!   images after the scene's exposure and tone map.
//! * [`colorize`]: `value / scale` clamped to [0, 1] through FLIP's magma palette (near black =
//!   0),
//!   the palette [`palette`] returns for colour bars.

use std::sync::OnceLock;

use crate::color::{to_display_rgba8, Tonemap};

/// A scalar value per pixel, row-major, top row first.
#[derive(Debug, Clone, PartialEq)]
pub struct ErrorMap {
    pub width: u32,
    pub height: u32,
    pub values: Vec<f32>,
}

/// Summary figures of a map: plain mean, nearest-rank percentiles, maximum, and the share of
/// pixels above a threshold.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MapStats {
    pub mean: f32,
    pub p50: f32,
    pub p95: f32,
    pub p99: f32,
    pub max: f32,
    /// Share of the pixels whose value exceeds [`MapStats::ABOVE`].
    pub above: f32,
}

impl MapStats {
    /// The threshold of [`MapStats::above`]: 1 % (relative error) or 0.01 (radiance, FLIP).
    pub const ABOVE: f32 = 0.01;

    pub fn of(values: &[f32]) -> Self {
        if values.is_empty() {
            return Self::default();
        }
        let finite = |v: f32| if v.is_finite() { v } else { f32::MAX };
        let mut sorted: Vec<f32> = values.iter().copied().map(finite).collect();
        sorted.sort_unstable_by(f32::total_cmp);
        let n = sorted.len();
        let rank = |p: f64| sorted[((p * n as f64).ceil() as usize).clamp(1, n) - 1];
        Self {
            mean: (sorted.iter().map(|&v| f64::from(v)).sum::<f64>() / n as f64) as f32,
            p50: rank(0.50),
            p95: rank(0.95),
            p99: rank(0.99),
            max: sorted[n - 1],
            above: sorted.iter().filter(|&&v| v > Self::ABOVE).count() as f32 / n as f32,
        }
    }
}

fn check(a: &[[f32; 4]], b: &[[f32; 4]], width: u32, height: u32) {
    let n = width as usize * height as usize;
    assert!(
        a.len() == n && b.len() == n,
        "comparison inputs must both hold {width}×{height} pixels ({} and {})",
        a.len(),
        b.len()
    );
}

fn per_pixel(
    a: &[[f32; 4]],
    b: &[[f32; 4]],
    (width, height): (u32, u32),
    f: impl Fn(f32, f32) -> f32,
) -> ErrorMap {
    check(a, b, width, height);
    let values = a
        .iter()
        .zip(b)
        .map(|(p, q)| (0..3).map(|c| f(p[c], q[c])).fold(0.0f32, f32::max))
        .collect();
    ErrorMap {
        width,
        height,
        values,
    }
}

/// `max_c |a_c − b_c|` per pixel (linear radiance; a NaN channel counts as +∞).
pub fn difference_map(a: &[[f32; 4]], b: &[[f32; 4]], width: u32, height: u32) -> ErrorMap {
    per_pixel(a, b, (width, height), |x, y| {
        let d = (x - y).abs();
        if d.is_nan() {
            f32::INFINITY
        } else {
            d
        }
    })
}

/// The smallest reference value a relative error divides by (dark pixels: an absolute error).
pub const RELATIVE_FLOOR: f32 = 1e-3;

/// `max_c |test_c − reference_c| / max(reference_c, RELATIVE_FLOOR)` per pixel.
pub fn relative_error_map(
    test: &[[f32; 4]],
    reference: &[[f32; 4]],
    width: u32,
    height: u32,
) -> ErrorMap {
    per_pixel(test, reference, (width, height), |t, r| {
        let e = (t - r).abs() / r.abs().max(RELATIVE_FLOOR);
        if e.is_nan() {
            f32::INFINITY
        } else {
            e
        }
    })
}

/// LDR FLIP of `test` against `reference` after the display's exposure (EV) and tone map (what
/// the viewer shows), at `luz diff`'s default pixels per degree. Values in [0, 1].
pub fn flip_map(
    reference: &[[f32; 4]],
    test: &[[f32; 4]],
    (width, height): (u32, u32),
    (exposure_ev, tonemap): (f32, Tonemap),
) -> ErrorMap {
    check(reference, test, width, height);
    let map = display_flip(reference, test, (width, height), exposure_ev, tonemap);
    ErrorMap {
        width,
        height,
        values: map.values,
    }
}

/// [`crate::diff::flip_error_map`] of the two images as the display shows them: exposure, tone
/// map and the 8-bit sRGB encode ([`to_display_rgba8`]), at the default pixels per degree. The
/// one place `luz lab` and the viewer turn radiance into FLIP's input.
pub fn display_flip(
    reference: &[[f32; 4]],
    test: &[[f32; 4]],
    (width, height): (u32, u32),
    exposure_ev: f32,
    tonemap: Tonemap,
) -> crate::diff::FlipMap {
    let rgb = |p: &[[f32; 4]]| -> Vec<[u8; 3]> {
        to_display_rgba8(p, exposure_ev, tonemap)
            .chunks_exact(4)
            .map(|c| [c[0], c[1], c[2]])
            .collect()
    };
    crate::diff::flip_error_map(
        &rgb(reference),
        &rgb(test),
        width,
        height,
        crate::diff::DEFAULT_PIXELS_PER_DEGREE,
    )
}

/// FLIP's magma palette: 256 colours from near black ((0, 0, 4) at 0) to light yellow (1).
pub fn palette() -> &'static [[u8; 3]; 256] {
    static LUT: OnceLock<[[u8; 3]; 256]> = OnceLock::new();
    LUT.get_or_init(|| {
        let bytes = nv_flip::magma_lut().to_vec();
        let mut lut = [[0u8; 3]; 256];
        for (i, c) in bytes.chunks_exact(3).take(256).enumerate() {
            lut[i] = [c[0], c[1], c[2]];
        }
        lut
    })
}

/// The palette colour of `value / scale` (clamped to [0, 1]; NaN and ∞ are the top colour).
pub fn color_of(value: f32, scale: f32) -> [u8; 3] {
    let t = if value.is_finite() && scale > 0.0 {
        (value / scale).clamp(0.0, 1.0)
    } else if value.is_finite() && value <= 0.0 {
        0.0
    } else {
        1.0
    };
    palette()[(t * 255.0).round() as usize]
}

/// The map as RGBA8 (alpha 255) through [`color_of`].
pub fn colorize(map: &ErrorMap, scale: f32) -> Vec<u8> {
    let mut out = Vec::with_capacity(map.values.len() * 4);
    for &v in &map.values {
        out.extend(color_of(v, scale));
        out.push(255);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(n: usize, f: impl Fn(usize) -> [f32; 4]) -> Vec<[f32; 4]> {
        (0..n).map(f).collect()
    }

    #[test]
    fn identical_images_give_a_zero_map_in_every_mode() {
        let a = image(64 * 32, |i| [i as f32 * 0.001, 0.5, 2.0, 1.0]);
        let d = difference_map(&a, &a, 64, 32);
        assert!(d.values.iter().all(|&v| v == 0.0));
        let r = relative_error_map(&a, &a, 64, 32);
        assert!(r.values.iter().all(|&v| v == 0.0));
        let f = flip_map(&a, &a, (64, 32), (0.0, Tonemap::KhronosNeutral));
        assert!(
            f.values.iter().all(|&v| v == 0.0),
            "{:?}",
            MapStats::of(&f.values)
        );
        // A zero map is one colour: the palette's first, black but for a little blue.
        let zero = palette()[0];
        assert!(
            zero.iter().map(|&c| u32::from(c)).sum::<u32>() < 10,
            "{zero:?}"
        );
        let rgba = colorize(&d, 0.0);
        assert!(rgba.chunks_exact(4).all(|p| p[..3] == zero && p[3] == 255));
    }

    #[test]
    fn difference_and_relative_error_are_the_formulas() {
        let a = vec![[1.0, 0.5, 0.0, 1.0], [0.0, 0.0, 0.0, 1.0]];
        let b = vec![[0.5, 0.5, 0.25, 1.0], [0.0, 0.0, 0.002, 1.0]];
        let d = difference_map(&a, &b, 2, 1);
        assert_eq!(d.values, vec![0.5, 0.002]);
        let r = relative_error_map(&a, &b, 2, 1);
        // |1 − 0.5| / 0.5 = 1; |0 − 0.25| / 0.25 = 1; |0 − 0.002| / 0.002 = 1.
        assert_eq!(r.values, vec![1.0, 1.0]);
        let s = MapStats::of(&[0.0, 0.02, 0.5, 1.0]);
        assert_eq!((s.max, s.p50, s.above), (1.0, 0.02, 0.75));
        assert!((s.mean - 0.38).abs() < 1e-6);
        let nan = difference_map(&[[f32::NAN, 0.0, 0.0, 1.0]], &[[0.0; 4]], 1, 1);
        assert_eq!(nan.values, vec![f32::INFINITY]);
    }

    #[test]
    fn flip_sees_a_colour_change_and_the_palette_spans_black_to_bright() {
        let red = image(48 * 48, |_| [0.8, 0.05, 0.05, 1.0]);
        let blue = image(48 * 48, |_| [0.05, 0.05, 0.8, 1.0]);
        let f = flip_map(&red, &blue, (48, 48), (0.0, Tonemap::KhronosNeutral));
        assert!(MapStats::of(&f.values).mean > 0.3);
        assert_eq!(color_of(0.0, 1.0), palette()[0]);
        let top = color_of(1.0, 1.0);
        assert!(
            top.iter().map(|&c| u32::from(c)).sum::<u32>() > 500,
            "{top:?}"
        );
        assert_eq!(color_of(f32::INFINITY, 1.0), top);
        assert_eq!(color_of(2.0, 1.0), top);
    }
}
