//! The shadow tests' judge (`tests/shadows.rs`, `tests/shadow_stability.rs`): per pixel, a
//! light's class from CPU references (lit, umbra, penumbra, not reached), then the GPU image
//! against the reference on the pixels whose class is sure, away from every change of class.

use luz::imageio::LinearImage;

/// Rec. 709 luminance of a linear RGBA pixel.
pub fn luminance(p: [f32; 4]) -> f32 {
    0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]
}

/// A pixel fully in the light's umbra.
pub const UMBRA: u8 = 0;
/// A pixel partly lit (soft shadows): not judged.
pub const PENUMBRA: u8 = 1;
/// A pixel the light reaches unshadowed.
pub const LIT: u8 = 2;
/// A pixel the light adds nothing to (the background, faces turned away).
pub const UNREACHED: u8 = 3;

/// One light's class at every pixel, from three references: the scene without the light
/// (`none`), with it shadowed (`with`) and with it unshadowed (`without`). The light's
/// visibility is (with − none) / (without − none).
pub fn light_classes(none: &LinearImage, with: &LinearImage, without: &LinearImage) -> Vec<u8> {
    (0..none.pixels.len())
        .map(|i| {
            let (a, s, n) = (
                luminance(none.pixels[i]),
                luminance(with.pixels[i]),
                luminance(without.pixels[i]),
            );
            let light = n - a;
            if light <= 1e-6 * n.max(1e-6) {
                return UNREACHED;
            }
            let vis = (s - a) / light;
            if vis > 1.0 - 1e-4 {
                LIT
            } else if vis < 1e-4 {
                UMBRA
            } else {
                PENUMBRA
            }
        })
        .collect()
}

/// What the judgement found for one method at one band width: lit and shadowed pixels judged,
/// and how many of each were within 2 % of the reference.
#[derive(Debug, Clone, Copy, Default)]
pub struct Judged {
    pub lit: usize,
    pub lit_ok: usize,
    pub dark: usize,
    pub dark_ok: usize,
}

impl Judged {
    /// Some lit pixels judged, and 99.5 % of the lit and of the shadowed ones right.
    pub fn passes(&self) -> bool {
        self.lit > 0
            && self.lit_ok as f64 >= 0.995 * self.lit as f64
            && self.dark_ok as f64 >= 0.995 * self.dark as f64
    }
}

/// Judges the GPU image against the reference (`w` × `h`) outside a band of `band` pixels around
/// every change of class, on pixels whose unshadowed GPU and reference images agree within 2 %
/// (the tessellated silhouettes differ from the exact ones; that is not the shadows' error).
/// `kind` tells a class's pixels apart: `Some(true)` lit, `Some(false)` shadowed, `None` not
/// judged (penumbra: soft shadows are the methods' approximation; not reached).
pub fn judge<C: Copy + PartialEq>(
    class: &[C],
    (w, h): (u32, u32),
    kind: impl Fn(C) -> Option<bool>,
    (gpu, reference): (&LinearImage, &LinearImage),
    (gpu_plain, ref_plain): (&LinearImage, &LinearImage),
    band: i32,
) -> Judged {
    let mut j = Judged::default();
    let (w, h) = (w as i32, h as i32);
    let at = |x: i32, y: i32| (y * w + x) as usize;
    for y in 0..h {
        for x in 0..w {
            let i = at(x, y);
            let (gp, rp) = (
                luminance(gpu_plain.pixels[i]),
                luminance(ref_plain.pixels[i]),
            );
            if rp <= 0.0 || (gp - rp).abs() > 0.02 * rp {
                continue;
            }
            let c = class[i];
            let Some(lit) = kind(c) else {
                continue;
            };
            let near_edge = (-band..=band).any(|dy| {
                (-band..=band).any(|dx| {
                    let (xx, yy) = (x + dx, y + dy);
                    xx >= 0 && yy >= 0 && xx < w && yy < h && class[at(xx, yy)] != c
                })
            });
            if near_edge {
                continue;
            }
            let (g, r) = (luminance(gpu.pixels[i]), luminance(reference.pixels[i]));
            let ok = (g - r).abs() <= 0.02 * r;
            if lit {
                j.lit += 1;
                j.lit_ok += ok as usize;
            } else {
                j.dark += 1;
                j.dark_ok += ok as usize;
            }
        }
    }
    j
}
