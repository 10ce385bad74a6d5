//! pixelmatch's YIQ colour distance and anti-aliasing detector, and the Khronos glTF Render
//! Fidelity metric built on the distance.
//!
//! * [`color_delta`]: the squared YIQ distance of Kotsarenko and Ramos ("Measuring perceived color
//!   difference using YIQ NTSC transmission color space in mobile applications"), as pixelmatch
//!   computes it (semi-transparent colours blended with white first); at most
//!   [`MAX_COLOR_DISTANCE`] (pixelmatch's bound).
//! * [`antialiased`]: pixelmatch's reading of V. Vysniauskas's "Anti-aliased pixel and intensity
//!   slope detector" (2009): a pixel is anti-aliasing when, among its 8 neighbours, at most 2 equal
//!   it, some are darker and some brighter, and the darkest or the brightest of them sits in a flat
//!   area (3 or more equal neighbours) in both images.
//! * [`khronos_db`]: the fidelity site's score (model-viewer's `ImageComparator.analyze` and
//!   `toDecibel`): the root mean square of [`color_delta`] over the pixels of the candidate that
//!   are not fully transparent, divided by [`MAX_COLOR_DISTANCE`], in decibels (10·log10).
//!   model-viewer's own fidelity test fails above [`MODEL_VIEWER_THRESHOLD_DB`].
//!
//! Images are 8-bit RGBA, row-major.

/// The bound pixelmatch and model-viewer give for [`color_delta`] (black against white is
/// 0.5053 · 255² ≈ 32857).
pub const MAX_COLOR_DISTANCE: f64 = 35215.0;

/// model-viewer's `FIDELITY_TEST_THRESHOLD`: a render whose score is above −22 dB fails.
pub const MODEL_VIEWER_THRESHOLD_DB: f64 = -22.0;

fn rgb2y(r: f64, g: f64, b: f64) -> f64 {
    r * 0.298_895_31 + g * 0.586_622_47 + b * 0.114_482_23
}
fn rgb2i(r: f64, g: f64, b: f64) -> f64 {
    r * 0.595_977_99 - g * 0.274_176_10 - b * 0.321_801_89
}
fn rgb2q(r: f64, g: f64, b: f64) -> f64 {
    r * 0.211_470_17 - g * 0.522_617_11 + b * 0.311_146_94
}

/// A colour with alpha < 255 blended over white, as floats.
fn blended(p: [u8; 4]) -> [f64; 3] {
    let [r, g, b, a] = p.map(f64::from);
    if p[3] == 255 {
        return [r, g, b];
    }
    let a = a / 255.0;
    [r, g, b].map(|c| 255.0 + (c - 255.0) * a)
}

/// The squared YIQ distance of two pixels (0 when equal), in [0, [`MAX_COLOR_DISTANCE`]].
pub fn color_delta(p: [u8; 4], q: [u8; 4]) -> f64 {
    if p == q {
        return 0.0;
    }
    let ([r1, g1, b1], [r2, g2, b2]) = (blended(p), blended(q));
    let y = rgb2y(r1, g1, b1) - rgb2y(r2, g2, b2);
    let i = rgb2i(r1, g1, b1) - rgb2i(r2, g2, b2);
    let q = rgb2q(r1, g1, b1) - rgb2q(r2, g2, b2);
    0.5053 * y * y + 0.299 * i * i + 0.1957 * q * q
}

/// The brightness (Y) difference of two pixels, signed (0 when equal).
fn brightness_delta(p: [u8; 4], q: [u8; 4]) -> f64 {
    if p == q {
        return 0.0;
    }
    let ([r1, g1, b1], [r2, g2, b2]) = (blended(p), blended(q));
    rgb2y(r1, g1, b1) - rgb2y(r2, g2, b2)
}

/// An 8-bit RGBA image borrowed for the detector.
#[derive(Clone, Copy)]
pub struct Rgba8<'a> {
    pub width: u32,
    pub height: u32,
    pub pixels: &'a [[u8; 4]],
}

impl Rgba8<'_> {
    fn at(&self, x: u32, y: u32) -> [u8; 4] {
        self.pixels[(y * self.width + x) as usize]
    }

    /// The 3×3 window around (x, y) clipped to the image, and whether (x, y) is on the border.
    fn window(
        &self,
        x: u32,
        y: u32,
    ) -> (
        std::ops::RangeInclusive<u32>,
        std::ops::RangeInclusive<u32>,
        bool,
    ) {
        let (x0, y0) = (x.saturating_sub(1), y.saturating_sub(1));
        let (x2, y2) = ((x + 1).min(self.width - 1), (y + 1).min(self.height - 1));
        let border = x == x0 || x == x2 || y == y0 || y == y2;
        (x0..=x2, y0..=y2, border)
    }

    /// Whether (x, y) has 3 or more neighbours of exactly its colour (a border counts as one).
    fn has_many_siblings(&self, x: u32, y: u32) -> bool {
        let (xs, ys, border) = self.window(x, y);
        let centre = self.at(x, y);
        let mut equal = u32::from(border);
        for nx in xs {
            for ny in ys.clone() {
                if (nx, ny) != (x, y) && self.at(nx, ny) == centre {
                    equal += 1;
                    if equal > 2 {
                        return true;
                    }
                }
            }
        }
        false
    }
}

/// Whether pixel (x, y) of `img` looks like anti-aliasing, `other` being the image it is compared
/// with (pixelmatch's `antialiased(img, x, y, width, height, img2)`).
pub fn antialiased(img: Rgba8, x: u32, y: u32, other: Rgba8) -> bool {
    let (xs, ys, border) = img.window(x, y);
    let centre = img.at(x, y);
    let mut equal = u32::from(border);
    let (mut min, mut max) = (0.0f64, 0.0f64);
    let (mut darkest, mut brightest) = ((0, 0), (0, 0));
    for nx in xs {
        for ny in ys.clone() {
            if (nx, ny) == (x, y) {
                continue;
            }
            let delta = brightness_delta(centre, img.at(nx, ny));
            if delta == 0.0 {
                equal += 1;
                if equal > 2 {
                    return false;
                }
            } else if delta < min {
                min = delta;
                darkest = (nx, ny);
            } else if delta > max {
                max = delta;
                brightest = (nx, ny);
            }
        }
    }
    if min == 0.0 || max == 0.0 {
        return false;
    }
    let flat =
        |(px, py): (u32, u32)| img.has_many_siblings(px, py) && other.has_many_siblings(px, py);
    flat(darkest) || flat(brightest)
}

/// Per pixel: the two images differ there and the pixel is anti-aliasing in either (what
/// pixelmatch does not count unless `includeAA`).
pub fn antialiased_differences(a: Rgba8, b: Rgba8) -> Vec<bool> {
    assert!(a.width == b.width && a.height == b.height, "one size");
    let mut out = vec![false; a.pixels.len()];
    for y in 0..a.height {
        for x in 0..a.width {
            let i = (y * a.width + x) as usize;
            if a.pixels[i] != b.pixels[i] {
                out[i] = antialiased(a, x, y, b) || antialiased(b, x, y, a);
            }
        }
    }
    out
}

/// The fidelity score of `candidate` against `golden` (same size): 10·log10 of the RMS of
/// [`color_delta`] over the candidate's pixels with alpha > 0, divided by
/// [`MAX_COLOR_DISTANCE`]. Identical images score −∞; `None` when every candidate pixel is
/// transparent (model-viewer would divide 0 by 0).
pub fn khronos_db(candidate: &[[u8; 4]], golden: &[[u8; 4]]) -> Option<f64> {
    assert_eq!(candidate.len(), golden.len(), "one size");
    let mut square_sum = 0.0f64;
    let mut counted = 0u64;
    for (c, g) in candidate.iter().zip(golden) {
        if c[3] == 0 {
            continue;
        }
        let d = color_delta(*c, *g);
        square_sum += d * d;
        counted += 1;
    }
    if counted == 0 {
        return None;
    }
    let ratio = (square_sum / counted as f64).sqrt() / MAX_COLOR_DISTANCE;
    Some(10.0 * ratio.log10())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn delta_extremes_and_blending() {
        let (black, white) = ([0, 0, 0, 255], [255, 255, 255, 255]);
        assert_eq!(color_delta(black, black), 0.0);
        // Black against white: 0.5053 · 255² (I and Q cancel); no pair exceeds the maximum.
        let d = color_delta(black, white);
        assert!((d - 0.5053 * 255.0 * 255.0).abs() < 1.0, "{d}");
        for p in [[255, 0, 0, 255], [0, 255, 0, 255], [0, 0, 255, 255], white] {
            for q in [
                black,
                [0, 255, 255, 255],
                [255, 0, 255, 255],
                [255, 255, 0, 255],
            ] {
                assert!(color_delta(p, q) <= MAX_COLOR_DISTANCE, "{p:?} {q:?}");
            }
        }
        // Fully transparent black is white once blended.
        assert_eq!(color_delta([0, 0, 0, 0], white), 0.0);
    }

    #[test]
    fn an_antialiased_edge_is_found_and_a_lone_dot_is_not() {
        // A vertical edge: black | grey | white columns; the grey column is anti-aliasing.
        let (w, h) = (6u32, 6u32);
        let edge: Vec<[u8; 4]> = (0..w * h)
            .map(|i| match i % w {
                0..=2 => [0, 0, 0, 255],
                3 => [128, 128, 128, 255],
                _ => [255, 255, 255, 255],
            })
            .collect();
        let mut moved = edge.clone();
        for y in 0..h {
            moved[(y * w + 3) as usize] = [90, 90, 90, 255];
        }
        let a = Rgba8 {
            width: w,
            height: h,
            pixels: &edge,
        };
        let b = Rgba8 {
            width: w,
            height: h,
            pixels: &moved,
        };
        let aa = antialiased_differences(a, b);
        for y in 1..h - 1 {
            assert!(aa[(y * w + 3) as usize], "row {y}");
        }
        // A dot in a flat area is a real difference.
        let flat = vec![[40u8, 40, 40, 255]; 36];
        let mut dot = flat.clone();
        dot[14] = [200, 0, 0, 255];
        let a = Rgba8 {
            width: 6,
            height: 6,
            pixels: &flat,
        };
        let b = Rgba8 {
            width: 6,
            height: 6,
            pixels: &dot,
        };
        assert!(!antialiased_differences(a, b).iter().any(|&x| x));
    }
}
