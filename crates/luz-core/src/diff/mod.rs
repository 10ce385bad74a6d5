//! `luz diff`: compare two images the way the golden-image tests do.
//!
//! Three measures, each with its own tolerance:
//!
//! * **FLIP** (NVIDIA's perceptual difference, LDR variant via `nv-flip`) on the images *as a
//!   viewer shows them*: the 8-bit sRGB [`LoadedImage::display`] bytes. For EXR that means the
//!   linear values clamped to [0, 1] and sRGB-encoded, without exposure or tone map, so FLIP sees
//!   the same picture an image viewer would; HDR detail above 1 is covered by `max_abs`, not FLIP.
//!   Pixels per degree default to 67 (nv-flip's default: a 0.7 m viewing distance on a 4K
//!   monitor of 0.7 m width).
//! * **Max abs** per channel in the files' *encoded units*: 8-bit code values for 8-bit PNGs,
//!   16-bit code values for 16-bit PNGs, linear radiance for EXRs. An 8-bit PNG against a 16-bit
//!   PNG is compared in 8-bit units (16-bit values scaled by 255/65535). A PNG against an EXR is
//!   compared in linear float, RGB only (luz's PNGs carry no alpha unless the scene is
//!   transparent), and the report's `units` says so.
//! * **Differing pixels**: pixels where any compared channel differs by more than
//!   [`DiffOptions::bad_pixel_threshold`] (same units as max abs).
//!
//! NaN and Inf are counted per image (EXR only; PNG cannot hold them). A NaN/Inf in the *actual*
//! image is always a violation. Channel pairs where either side is non-finite do not enter
//! `max_abs`; such a pair counts as differing unless both sides are NaN or both are the same
//! infinity.

use std::fmt;
use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::imageio::{self, FileFormat, ImageError, LoadedImage};

mod overrides;
pub mod pixelmatch;
pub use overrides::{
    parse_sidecar, read_sidecar, OverrideError, ToleranceOverrides, FIELDS as OVERRIDE_FIELDS,
};

/// nv-flip's default pixels per degree (0.7 m from a 0.7 m wide 3840-pixel monitor).
pub const DEFAULT_PIXELS_PER_DEGREE: f32 = 67.0;

/// Tolerances and outputs of a comparison.
#[derive(Debug, Clone, PartialEq)]
pub struct DiffOptions {
    /// Largest allowed mean FLIP error (0 = identical, 1 = maximally different).
    pub max_flip_mean: Option<f32>,
    /// Largest allowed per-channel absolute difference, in the report's units.
    pub max_abs: Option<f32>,
    /// Largest allowed number of differing pixels.
    pub max_bad_pixels: Option<u64>,
    /// A pixel is 'different' when any channel's absolute difference exceeds this, in the
    /// image's encoded units (default 0: any difference).
    pub bad_pixel_threshold: f32,
    /// Write the FLIP error map here as a PNG with the magma palette.
    pub heatmap: Option<PathBuf>,
    /// FLIP's pixels per degree of visual angle (default [`DEFAULT_PIXELS_PER_DEGREE`]).
    pub pixels_per_degree: f32,
}

impl Default for DiffOptions {
    fn default() -> Self {
        Self {
            max_flip_mean: None,
            max_abs: None,
            max_bad_pixels: None,
            bad_pixel_threshold: 0.0,
            heatmap: None,
            pixels_per_degree: DEFAULT_PIXELS_PER_DEGREE,
        }
    }
}

/// The golden-image tolerances, in 8-bit sRGB steps: what luz's own golden tests use and what
/// `luz diff` and `luz golden` check unless told otherwise. Same machine: byte-exact; another CPU
/// moves a few LSB (lavapipe's approximate rcp/rsqrt), a real change moves far more.
pub const GOLDEN_MAX_FLIP_MEAN: f32 = 0.005;
/// Largest per-channel difference, in 8-bit steps.
pub const GOLDEN_MAX_ABS_STEPS: f32 = 8.0;
/// Pixels allowed to differ by more than [`GOLDEN_BAD_THRESHOLD_STEPS`].
pub const GOLDEN_MAX_BAD_PIXELS: u64 = 64;
/// A pixel 'differs' beyond this many 8-bit steps.
pub const GOLDEN_BAD_THRESHOLD_STEPS: f32 = 3.0;

/// Tolerances of one comparison, in 8-bit sRGB steps (`None` turns a check off). [`Tolerance::golden`]
/// is the default; [`Tolerance::options_for`] turns it into [`DiffOptions`] in the units two
/// images are compared in.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Tolerance {
    pub max_flip_mean: Option<f32>,
    /// In 8-bit steps (scaled to the comparison's units).
    pub max_abs: Option<f32>,
    pub max_bad_pixels: Option<u64>,
    /// In 8-bit steps (scaled to the comparison's units).
    pub bad_pixel_threshold: f32,
}

impl Default for Tolerance {
    fn default() -> Self {
        Self::golden()
    }
}

impl Tolerance {
    /// The golden-image tolerances (`GOLDEN_*`).
    pub const fn golden() -> Self {
        Self {
            max_flip_mean: Some(GOLDEN_MAX_FLIP_MEAN),
            max_abs: Some(GOLDEN_MAX_ABS_STEPS),
            max_bad_pixels: Some(GOLDEN_MAX_BAD_PIXELS),
            bad_pixel_threshold: GOLDEN_BAD_THRESHOLD_STEPS,
        }
    }

    /// No check at all (the figures are still measured).
    pub const fn report_only() -> Self {
        Self {
            max_flip_mean: None,
            max_abs: None,
            max_bad_pixels: None,
            bad_pixel_threshold: GOLDEN_BAD_THRESHOLD_STEPS,
        }
    }

    /// [`DiffOptions`] for comparing `expected` with `actual`: the 8-bit steps scaled to the units
    /// [`compare`] will use (×1 for 8-bit PNGs or a mix of 8- and 16-bit PNGs, ×257 for two 16-bit
    /// PNGs, ÷255 for linear float when an EXR is involved).
    pub fn options_for(&self, expected: &LoadedImage, actual: &LoadedImage) -> DiffOptions {
        let scale = step_size(expected, actual);
        DiffOptions {
            max_flip_mean: self.max_flip_mean,
            max_abs: self.max_abs.map(|v| v * scale),
            max_bad_pixels: self.max_bad_pixels,
            bad_pixel_threshold: self.bad_pixel_threshold * scale,
            ..DiffOptions::default()
        }
    }
}

/// One 8-bit sRGB step in the units [`compare`] uses for this pair of images.
pub fn step_size(expected: &LoadedImage, actual: &LoadedImage) -> f32 {
    match (expected.format, actual.format) {
        (FileFormat::Png, FileFormat::Png) => {
            if expected.encoded_max == actual.encoded_max {
                expected.encoded_max / 255.0
            } else {
                1.0
            }
        }
        _ => 1.0 / 255.0,
    }
}

impl DiffOptions {
    /// One line naming every check and its limit, in `units`: `FLIP mean ≤ 0.005, max abs ≤ 8,
    /// ≤ 64 pixels beyond 3` (a check that is off reads `off`).
    pub fn describe_tolerances(&self) -> String {
        let flip = match self.max_flip_mean {
            Some(t) => format!("FLIP mean ≤ {t}"),
            None => "FLIP mean off".into(),
        };
        let abs = match self.max_abs {
            Some(t) => format!("max abs ≤ {t}"),
            None => "max abs off".into(),
        };
        let bad = match self.max_bad_pixels {
            Some(t) => format!("≤ {t} pixels beyond {}", self.bad_pixel_threshold),
            None => format!("differing pixels (beyond {}) off", self.bad_pixel_threshold),
        };
        format!("{flip}, {abs}, {bad}")
    }
}

/// The numbers a comparison produces.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DiffReport {
    pub width: u32,
    pub height: u32,
    pub flip_mean: f32,
    pub flip_p50: f32,
    pub flip_p95: f32,
    pub flip_p99: f32,
    pub flip_max: f32,
    /// Largest per-channel absolute difference over finite channel pairs, in `units`:
    /// 8-bit LSB for PNG, linear radiance for EXR.
    pub max_abs: f32,
    /// What `max_abs` and the bad-pixel threshold are measured in.
    pub units: &'static str,
    /// Pixels where some channel differs by more than `bad_pixel_threshold`.
    pub differing_pixels: u64,
    /// The threshold used for `differing_pixels`, in `units`.
    pub bad_pixel_threshold: f32,
    /// Pixels holding NaN or Inf in the expected image.
    pub nan_inf_expected: u64,
    /// Pixels holding NaN or Inf in the actual image (always a violation).
    pub nan_inf_actual: u64,
    /// Pixels left out of every figure ([`compare_masked`]: a golden's mask, other regions,
    /// forgiven anti-aliasing); 0 for a plain comparison.
    pub ignored_pixels: u64,
}

/// A per-pixel FLIP error map, row-major, values in [0, 1].
#[derive(Clone, PartialEq)]
pub struct FlipMap {
    pub width: u32,
    pub height: u32,
    pub values: Vec<f32>,
}

impl fmt::Debug for FlipMap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("FlipMap")
            .field("width", &self.width)
            .field("height", &self.height)
            .finish_non_exhaustive()
    }
}

/// Why a comparison could not be made (as opposed to a comparison that found differences).
#[derive(Debug, thiserror::Error)]
pub enum DiffError {
    // The message already ends with the I/O reason: no `source`, or `{e:#}` (anyhow's chain)
    // would print the reason twice ("cannot write x.png: Is a directory: Is a directory").
    #[error("{0}")]
    Image(ImageError),
    #[error(
        "image sizes differ: expected {}, actual {}",
        describe(.expected_path.as_deref(), *.expected_size),
        describe(.actual_path.as_deref(), *.actual_size)
    )]
    SizeMismatch {
        expected_size: (u32, u32),
        actual_size: (u32, u32),
        expected_path: Option<PathBuf>,
        actual_path: Option<PathBuf>,
    },
}

impl From<ImageError> for DiffError {
    fn from(e: ImageError) -> Self {
        DiffError::Image(e)
    }
}

fn describe(path: Option<&Path>, (w, h): (u32, u32)) -> String {
    match path {
        Some(p) => format!("{} is {w}×{h}", p.display()),
        None => format!("{w}×{h}"),
    }
}

/// Compares two loaded images; writes the FLIP heat map when `opts.heatmap` is set.
pub fn compare(
    expected: &LoadedImage,
    actual: &LoadedImage,
    opts: &DiffOptions,
) -> Result<DiffReport, DiffError> {
    let (report, map) = compare_detailed(expected, actual, opts)?;
    if let Some(path) = &opts.heatmap {
        write_heatmap(path, &map)?;
    }
    Ok(report)
}

/// Loads both files and compares them; errors name the file at fault.
pub fn compare_files(
    expected: &Path,
    actual: &Path,
    opts: &DiffOptions,
) -> Result<DiffReport, DiffError> {
    let e = imageio::load(expected)?;
    let a = imageio::load(actual)?;
    compare_named(expected, &e, actual, &a, opts)
}

/// [`compare`] of two images loaded from `expected_path` and `actual_path` (a size mismatch
/// names both files).
pub fn compare_named(
    expected_path: &Path,
    expected: &LoadedImage,
    actual_path: &Path,
    actual: &LoadedImage,
    opts: &DiffOptions,
) -> Result<DiffReport, DiffError> {
    compare(expected, actual, opts).map_err(|err| match err {
        DiffError::SizeMismatch {
            expected_size,
            actual_size,
            ..
        } => DiffError::SizeMismatch {
            expected_size,
            actual_size,
            expected_path: Some(expected_path.to_path_buf()),
            actual_path: Some(actual_path.to_path_buf()),
        },
        other => other,
    })
}

/// Like [`compare`] but never writes files and also returns the FLIP map (so a test harness can
/// write the heat map only when a tolerance fails).
pub fn compare_detailed(
    expected: &LoadedImage,
    actual: &LoadedImage,
    opts: &DiffOptions,
) -> Result<(DiffReport, FlipMap), DiffError> {
    let (ew, eh, aw, ah) = (expected.width, expected.height, actual.width, actual.height);
    if (ew, eh) != (aw, ah) {
        return Err(DiffError::SizeMismatch {
            expected_size: (ew, eh),
            actual_size: (aw, ah),
            expected_path: None,
            actual_path: None,
        });
    }

    // Pick the common units.
    let same_encoding =
        expected.format == actual.format && expected.encoded_max == actual.encoded_max;
    let (units, channels, e_vals, a_vals, e_scale, a_scale) = if same_encoding {
        let units = match expected.format {
            FileFormat::Exr => "linear radiance, EXR float",
            FileFormat::Png if expected.encoded_max == 255.0 => "8-bit sRGB code values",
            FileFormat::Png => "16-bit sRGB code values",
        };
        (units, 4, &expected.encoded, &actual.encoded, 1.0, 1.0)
    } else if expected.format == FileFormat::Png && actual.format == FileFormat::Png {
        (
            "8-bit sRGB code values, 16-bit PNG scaled by 255/65535",
            4,
            &expected.encoded,
            &actual.encoded,
            255.0 / expected.encoded_max,
            255.0 / actual.encoded_max,
        )
    } else {
        (
            "linear float, RGB only: PNG vs EXR compared after sRGB decoding",
            3,
            &expected.linear,
            &actual.linear,
            1.0,
            1.0,
        )
    };

    let threshold = opts.bad_pixel_threshold;
    let mut max_abs = 0.0f32;
    let mut differing = 0u64;
    for (e, a) in e_vals.iter().zip(a_vals) {
        let mut differs = false;
        for c in 0..channels {
            let (x, y) = (e[c] * e_scale, a[c] * a_scale);
            if x.is_finite() && y.is_finite() {
                let d = (x - y).abs();
                max_abs = max_abs.max(d);
                differs |= d > threshold;
            } else {
                let same = (x.is_nan() && y.is_nan()) || x == y;
                differs |= !same;
            }
        }
        differing += u64::from(differs);
    }

    let map = flip_error_map(
        &expected.display,
        &actual.display,
        ew,
        eh,
        opts.pixels_per_degree,
    );
    let stats = FlipStats::of(&map.values);

    let report = DiffReport {
        width: ew,
        height: eh,
        flip_mean: stats.mean,
        flip_p50: stats.p50,
        flip_p95: stats.p95,
        flip_p99: stats.p99,
        flip_max: stats.max,
        max_abs,
        units,
        differing_pixels: differing,
        bad_pixel_threshold: threshold,
        nan_inf_expected: expected.non_finite_pixels(),
        nan_inf_actual: actual.non_finite_pixels(),
        ignored_pixels: 0,
    };
    Ok((report, map))
}

/// [`compare_detailed`] leaving out the pixels where `ignored` is true (row-major, one entry per
/// pixel): the actual image takes the expected one's values there before comparing, so they
/// neither count nor leak into their neighbours through FLIP's filters, and the FLIP statistics
/// are taken over the other pixels only (the map is 0 at ignored pixels).
pub fn compare_masked(
    expected: &LoadedImage,
    actual: &LoadedImage,
    opts: &DiffOptions,
    ignored: &[bool],
) -> Result<(DiffReport, FlipMap), DiffError> {
    if (expected.width, expected.height) != (actual.width, actual.height) {
        return compare_detailed(expected, actual, opts);
    }
    assert_eq!(
        ignored.len(),
        expected.display.len(),
        "one mask entry per pixel"
    );
    let mut a = actual.clone();
    let same_format = expected.format == actual.format;
    for (i, _) in ignored.iter().enumerate().filter(|(_, &x)| x) {
        a.display[i] = expected.display[i];
        a.linear[i] = expected.linear[i];
        // Mixed PNG and EXR compare the linear values: the encoding stays as it is.
        if same_format {
            a.encoded[i] =
                expected.encoded[i].map(|c| c * actual.encoded_max / expected.encoded_max);
        }
    }
    let (mut report, mut map) = compare_detailed(expected, &a, opts)?;
    let mut kept = Vec::with_capacity(map.values.len());
    for (v, &skip) in map.values.iter_mut().zip(ignored) {
        if skip {
            *v = 0.0;
        } else {
            kept.push(*v);
        }
    }
    let stats = FlipStats::of(&kept);
    report.flip_mean = stats.mean;
    report.flip_p50 = stats.p50;
    report.flip_p95 = stats.p95;
    report.flip_p99 = stats.p99;
    report.flip_max = stats.max;
    report.ignored_pixels = ignored.iter().filter(|&&x| x).count() as u64;
    Ok((report, map))
}

/// The image as 8-bit RGBA as a display shows it ([`LoadedImage::display`], with the file's
/// alpha scaled to 0..=255; 255 for EXR).
pub fn display_rgba8(img: &LoadedImage) -> Vec<[u8; 4]> {
    img.display
        .iter()
        .zip(&img.encoded)
        .map(|(d, e)| {
            let a = match img.format {
                FileFormat::Png => (e[3] / img.encoded_max * 255.0).round().clamp(0.0, 255.0) as u8,
                FileFormat::Exr => 255,
            };
            [d[0], d[1], d[2], a]
        })
        .collect()
}

/// LDR FLIP between two 8-bit sRGB RGB images of `width × height` (row-major, top-left first).
/// An empty image gives an empty map.
pub fn flip_error_map(
    reference: &[[u8; 3]],
    test: &[[u8; 3]],
    width: u32,
    height: u32,
    pixels_per_degree: f32,
) -> FlipMap {
    let n = width as usize * height as usize;
    assert!(
        reference.len() == n && test.len() == n,
        "FLIP inputs must hold {width}×{height} pixels"
    );
    let values = if n == 0 {
        Vec::new()
    } else {
        let r = nv_flip::FlipImageRgb8::with_data(width, height, reference.as_flattened());
        let t = nv_flip::FlipImageRgb8::with_data(width, height, test.as_flattened());
        nv_flip::flip(r, t, pixels_per_degree).to_vec()
    };
    FlipMap {
        width,
        height,
        values,
    }
}

struct FlipStats {
    mean: f32,
    p50: f32,
    p95: f32,
    p99: f32,
    max: f32,
}

impl FlipStats {
    /// Plain (unweighted) statistics of the map; percentiles by nearest rank.
    fn of(values: &[f32]) -> Self {
        if values.is_empty() {
            return Self {
                mean: 0.0,
                p50: 0.0,
                p95: 0.0,
                p99: 0.0,
                max: 0.0,
            };
        }
        let mean = (values.iter().map(|&v| f64::from(v)).sum::<f64>() / values.len() as f64) as f32;
        let mut sorted = values.to_vec();
        sorted.sort_unstable_by(f32::total_cmp);
        let rank = |p: f64| {
            let idx = (p * sorted.len() as f64).ceil() as usize;
            sorted[idx.clamp(1, sorted.len()) - 1]
        };
        Self {
            mean,
            p50: rank(0.50),
            p95: rank(0.95),
            p99: rank(0.99),
            max: sorted[sorted.len() - 1],
        }
    }
}

/// Writes the FLIP map as a PNG through nv-flip's magma palette (black = no error).
pub fn write_heatmap(path: &Path, map: &FlipMap) -> Result<(), DiffError> {
    let rgb = if map.values.is_empty() {
        Vec::new()
    } else {
        let img = nv_flip::FlipImageFloat::with_data(map.width, map.height, &map.values);
        img.apply_color_lut(&nv_flip::magma_lut()).to_vec()
    };
    imageio::save_png_rgb8(path, map.width, map.height, &rgb)?;
    Ok(())
}

impl DiffReport {
    /// One human-readable line per exceeded tolerance; empty when the comparison passes.
    /// NaN/Inf in the actual image is always a violation.
    pub fn violations(&self, opts: &DiffOptions) -> Vec<String> {
        let mut out = Vec::new();
        if let Some(t) = opts.max_flip_mean {
            if self.flip_mean > t || self.flip_mean.is_nan() {
                out.push(format!(
                    "FLIP mean {:.6} exceeds max-flip-mean {t}",
                    self.flip_mean
                ));
            }
        }
        if let Some(t) = opts.max_abs {
            if self.max_abs > t {
                out.push(format!(
                    "max abs difference {} exceeds max-abs {t} ({})",
                    self.max_abs, self.units
                ));
            }
        }
        if let Some(t) = opts.max_bad_pixels {
            if self.differing_pixels > t {
                out.push(format!(
                    "{} pixels differ by more than {} ({}), more than max-bad-pixels {t}",
                    self.differing_pixels, self.bad_pixel_threshold, self.units
                ));
            }
        }
        if self.nan_inf_actual > 0 {
            out.push(format!(
                "{} pixels of the actual image hold NaN or Inf",
                self.nan_inf_actual
            ));
        }
        out
    }
}

impl fmt::Display for DiffReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let total = u64::from(self.width) * u64::from(self.height);
        let pct = if total == 0 {
            0.0
        } else {
            100.0 * self.differing_pixels as f64 / total as f64
        };
        writeln!(f, "size     {}×{}", self.width, self.height)?;
        writeln!(
            f,
            "FLIP     mean {:.6}  p50 {:.6}  p95 {:.6}  p99 {:.6}  max {:.6}",
            self.flip_mean, self.flip_p50, self.flip_p95, self.flip_p99, self.flip_max
        )?;
        writeln!(f, "max abs  {} ({})", self.max_abs, self.units)?;
        writeln!(
            f,
            "differ   {} pixels ({pct:.3}%) by more than {}",
            self.differing_pixels, self.bad_pixel_threshold
        )?;
        write!(
            f,
            "NaN/Inf  expected {}, actual {}",
            self.nan_inf_expected, self.nan_inf_actual
        )?;
        if self.ignored_pixels > 0 {
            write!(f, "\nignored  {} pixels (masked)", self.ignored_pixels)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::Tonemap;
    use crate::imageio::LinearImage;

    fn scene(width: u32, height: u32) -> LinearImage {
        let mut img = LinearImage::filled(width, height, [0.0, 0.0, 0.0, 1.0]);
        for y in 0..height {
            for x in 0..width {
                let u = x as f32 / width as f32;
                let v = y as f32 / height as f32;
                *img.pixel_mut(x, y) = [u * 1.5, v, ((x / 4 + y / 4) % 2) as f32 * 0.6, 1.0];
            }
        }
        img
    }

    fn png(img: &LinearImage) -> LoadedImage {
        LoadedImage::from_linear(img, FileFormat::Png, 0.0, Tonemap::None)
    }

    fn exr(img: &LinearImage) -> LoadedImage {
        LoadedImage::from_linear(img, FileFormat::Exr, 0.0, Tonemap::None)
    }

    fn strict() -> DiffOptions {
        DiffOptions {
            max_flip_mean: Some(0.0),
            max_abs: Some(0.0),
            max_bad_pixels: Some(0),
            ..DiffOptions::default()
        }
    }

    #[test]
    fn identical_images_have_no_difference() {
        let img = scene(32, 24);
        for loaded in [png(&img), exr(&img)] {
            let r = compare(&loaded, &loaded, &strict()).unwrap();
            assert_eq!(r.flip_mean, 0.0);
            assert_eq!(r.flip_max, 0.0);
            assert_eq!(r.max_abs, 0.0);
            assert_eq!(r.differing_pixels, 0);
            assert_eq!((r.nan_inf_expected, r.nan_inf_actual), (0, 0));
            assert!(r.violations(&strict()).is_empty(), "{r}");
        }
    }

    #[test]
    fn one_pixel_change_in_png() {
        let img = scene(32, 24);
        let expected = png(&img);
        let mut actual = expected.clone();
        let i = 5 * 32 + 7;
        let old = actual.display[i][1];
        let new = if old >= 100 { old - 9 } else { old + 9 };
        actual.display[i][1] = new;
        actual.encoded[i][1] = new as f32;
        actual.linear[i][1] = crate::color::srgb_decode_u8(new);
        let r = compare(&expected, &actual, &DiffOptions::default()).unwrap();
        assert_eq!(r.differing_pixels, 1);
        assert_eq!(r.max_abs, 9.0);
        assert_eq!(r.units, "8-bit sRGB code values");
        assert!(r.flip_max > 0.0 && r.flip_mean > 0.0 && r.flip_mean < r.flip_max);
        assert_eq!(r.flip_p50, 0.0);
        let v = r.violations(&strict());
        assert_eq!(v.len(), 3, "{v:?}");
        // Loose tolerances pass.
        let loose = DiffOptions {
            max_flip_mean: Some(0.01),
            max_abs: Some(9.0),
            max_bad_pixels: Some(1),
            ..DiffOptions::default()
        };
        assert!(r.violations(&loose).is_empty());
        // A threshold at the change makes the pixel not count.
        let opts = DiffOptions {
            bad_pixel_threshold: 9.0,
            ..DiffOptions::default()
        };
        assert_eq!(
            compare(&expected, &actual, &opts).unwrap().differing_pixels,
            0
        );
    }

    #[test]
    fn one_pixel_change_in_exr() {
        let img = scene(16, 16);
        let mut changed = img.clone();
        changed.pixel_mut(3, 9)[2] += 0.25;
        let r = compare(&exr(&img), &exr(&changed), &DiffOptions::default()).unwrap();
        assert_eq!(r.differing_pixels, 1);
        assert_eq!(r.max_abs, 0.25);
        assert!(r.units.contains("linear"));
        // Above 1 the display is clamped: FLIP cannot see it, max abs can.
        let mut bright = LinearImage::filled(8, 8, [2.0, 2.0, 2.0, 1.0]);
        let base = exr(&bright);
        bright.pixel_mut(1, 1)[0] = 3.0;
        let r = compare(&base, &exr(&bright), &DiffOptions::default()).unwrap();
        assert_eq!((r.flip_max, r.max_abs, r.differing_pixels), (0.0, 1.0, 1));
    }

    #[test]
    fn nan_in_exr_is_counted_and_a_violation() {
        let img = scene(16, 16);
        let mut bad = img.clone();
        bad.pixel_mut(2, 2)[0] = f32::NAN;
        bad.pixel_mut(4, 4)[1] = f32::INFINITY;
        let r = compare(&exr(&img), &exr(&bad), &DiffOptions::default()).unwrap();
        assert_eq!(r.nan_inf_actual, 2);
        assert_eq!(r.nan_inf_expected, 0);
        assert_eq!(r.differing_pixels, 2);
        assert_eq!(r.max_abs, 0.0, "non-finite pairs stay out of max abs");
        let v = r.violations(&DiffOptions::default());
        assert_eq!(v.len(), 1);
        assert!(v[0].contains("NaN"), "{v:?}");
        // In the expected image only: counted, not a violation.
        let r = compare(&exr(&bad), &exr(&bad), &DiffOptions::default()).unwrap();
        assert_eq!((r.nan_inf_expected, r.differing_pixels), (2, 0));
        let r = compare(&exr(&bad), &exr(&img), &DiffOptions::default()).unwrap();
        assert!(r.violations(&DiffOptions::default()).is_empty());
    }

    #[test]
    fn size_mismatch_is_an_error() {
        let err = compare(
            &png(&scene(8, 8)),
            &png(&scene(8, 9)),
            &DiffOptions::default(),
        )
        .unwrap_err();
        let msg = err.to_string();
        assert!(msg.contains("8×8") && msg.contains("8×9"), "{msg}");

        let dir = std::env::temp_dir().join(format!("luz-diff-size-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (a, b) = (dir.join("a.png"), dir.join("b.exr"));
        imageio::save(&a, &scene(8, 8), 0.0, Tonemap::None).unwrap();
        imageio::save(&b, &scene(9, 8), 0.0, Tonemap::None).unwrap();
        let msg = compare_files(&a, &b, &DiffOptions::default())
            .unwrap_err()
            .to_string();
        assert!(
            msg.contains("a.png is 8×8") && msg.contains("b.exr is 9×8"),
            "{msg}"
        );
        let msg = compare_files(&a, &dir.join("nope.png"), &DiffOptions::default())
            .unwrap_err()
            .to_string();
        assert!(msg.contains("nope.png"), "{msg}");
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn files_mixed_formats_and_heatmap() {
        let dir = std::env::temp_dir().join(format!("luz-diff-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let img = scene(40, 30);
        let mut changed = img.clone();
        for x in 10..20 {
            changed.pixel_mut(x, 12)[0] = 0.9;
        }
        let (ep, ap, xp) = (dir.join("e.png"), dir.join("a.png"), dir.join("e.exr"));
        imageio::save(&ep, &img, 0.0, Tonemap::None).unwrap();
        imageio::save(&ap, &changed, 0.0, Tonemap::None).unwrap();
        imageio::save(&xp, &img, 0.0, Tonemap::None).unwrap();

        let heat = dir.join("heat.png");
        let opts = DiffOptions {
            heatmap: Some(heat.clone()),
            ..DiffOptions::default()
        };
        let r = compare_files(&ep, &ap, &opts).unwrap();
        assert!(r.differing_pixels > 0 && r.differing_pixels <= 10);
        let heat_img = imageio::load(&heat).unwrap();
        assert_eq!((heat_img.width, heat_img.height), (40, 30));
        // Unchanged rows far from the edit are black (magma at 0), the edit is not.
        assert_eq!(heat_img.display[0], heat_img.display[40 * 29]);
        assert_ne!(heat_img.display[12 * 40 + 15], heat_img.display[0]);

        // PNG against the EXR it came from: compared in linear float. FLIP sees identical display
        // bytes (the EXR is clamped and encoded exactly as the PNG was); max abs sees the clamp of
        // the brightest red (1.5 · 39/40 = 1.4625 stored as 1.0 in the PNG).
        let r = compare_files(&xp, &ep, &DiffOptions::default()).unwrap();
        assert!(r.units.contains("PNG vs EXR"), "{}", r.units);
        assert_eq!(r.flip_max, 0.0);
        assert!((r.max_abs - 0.4625).abs() < 1e-4, "{}", r.max_abs);
        let shown = r.to_string();
        assert!(
            shown.contains("FLIP") && shown.contains("PNG vs EXR"),
            "{shown}"
        );
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn png_depths_compare_in_8_bit_units() {
        let img = scene(4, 4);
        let eight = png(&img);
        let mut sixteen = eight.clone();
        sixteen.encoded_max = 65535.0;
        for p in &mut sixteen.encoded {
            *p = p.map(|c| c * 257.0);
        }
        sixteen.encoded[3][0] += 257.0 * 2.0;
        let r = compare(&eight, &sixteen, &DiffOptions::default()).unwrap();
        assert!(r.units.starts_with("8-bit"));
        assert!((r.max_abs - 2.0).abs() < 1e-4);
        assert_eq!(r.differing_pixels, 1);
    }

    #[test]
    fn percentiles_by_nearest_rank() {
        let values: Vec<f32> = (1..=100).map(|i| i as f32 / 100.0).collect();
        let s = FlipStats::of(&values);
        assert_eq!((s.p50, s.p95, s.p99, s.max), (0.5, 0.95, 0.99, 1.0));
        assert!((s.mean - 0.505).abs() < 1e-6);
        let s = FlipStats::of(&[0.3]);
        assert_eq!((s.p50, s.p99, s.max), (0.3, 0.3, 0.3));
    }
}
