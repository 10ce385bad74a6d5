//! `luz diff`: FLIP, max absolute difference and NaN counts of two images, checked against the
//! golden-image tolerances unless told otherwise.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::Args;

use luz::diff::Tolerance;

use super::common::{count_or_none, finite_non_negative, tolerance_or_none, Check};

#[derive(Args, Debug)]
pub struct DiffArgs {
    /// The reference image (PNG or EXR).
    pub expected: PathBuf,
    /// The image to check (PNG or EXR, same size).
    pub actual: PathBuf,
    /// Write the FLIP error heatmap (PNG).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Fail when the mean FLIP error exceeds this (0..1), or `none` [default: 0.005].
    #[arg(long, value_parser = tolerance_or_none)]
    pub max_flip_mean: Option<Check<f32>>,
    /// Fail when any channel differs by more than this (8-bit steps for PNG, radiance for EXR),
    /// or `none` [default: 8 steps; 8/255 in linear units when an EXR is involved].
    #[arg(long, value_parser = tolerance_or_none)]
    pub max_abs: Option<Check<f32>>,
    /// Fail when more pixels than this differ by more than --threshold, or `none` [default: 64].
    #[arg(long, value_parser = count_or_none)]
    pub max_bad_pixels: Option<Check<u64>>,
    /// A pixel differs when a channel differs by more than this, in the same units as --max-abs
    /// [default: 3 steps; 3/255 in linear units when an EXR is involved].
    #[arg(long, value_parser = finite_non_negative)]
    pub threshold: Option<f32>,
    /// Measure and print, but check nothing: exit 0 whatever the difference (a NaN in the actual
    /// image included).
    #[arg(long)]
    pub report_only: bool,
    /// What to measure: flip (FLIP, max abs, differing pixels: the golden-image checks) or
    /// khronos-db (the glTF Render Fidelity score: RMS of pixelmatch's YIQ colour distance over
    /// the actual image's non-transparent pixels, divided by its maximum 35215, in dB).
    #[arg(long, value_enum, default_value_t = Metric::Flip)]
    pub metric: Metric,
    /// With --metric khronos-db: fail when the score is above this many dB (less negative is
    /// further apart) [default: -22, model-viewer's fidelity test threshold].
    #[arg(long, value_name = "DB", allow_negative_numbers = true)]
    pub max_db: Option<f64>,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Metric {
    Flip,
    KhronosDb,
}

fn khronos_db(a: &DiffArgs) -> Result<ExitCode> {
    use luz::diff::pixelmatch;
    let expected = luz::imageio::load(&a.expected)?;
    let actual = luz::imageio::load(&a.actual)?;
    if (expected.width, expected.height) != (actual.width, actual.height) {
        anyhow::bail!(
            "image sizes differ: expected {} is {}×{}, actual {} is {}×{}",
            a.expected.display(),
            expected.width,
            expected.height,
            a.actual.display(),
            actual.width,
            actual.height
        );
    }
    if a.max_flip_mean.is_some() || a.max_abs.is_some() || a.max_bad_pixels.is_some() {
        anyhow::bail!("--max-flip-mean, --max-abs and --max-bad-pixels go with --metric flip; --metric khronos-db checks --max-db");
    }
    let max_db = a.max_db.unwrap_or(pixelmatch::MODEL_VIEWER_THRESHOLD_DB);
    if !max_db.is_finite() {
        anyhow::bail!("--max-db: must be a finite number of dB, not {max_db}");
    }
    let (e, c) = (
        luz::diff::display_rgba8(&expected),
        luz::diff::display_rgba8(&actual),
    );
    let counted = c.iter().filter(|p| p[3] > 0).count();
    let score = pixelmatch::khronos_db(&c, &e);
    println!("size     {}×{}", expected.width, expected.height);
    let shown = match score {
        Some(db) if db == f64::NEG_INFINITY => "-inf dB (identical)".to_string(),
        Some(db) => format!("{db:.4} dB"),
        None => "none (every pixel of the actual image is transparent)".to_string(),
    };
    println!(
        "khronos-db  {shown}: RMS of pixelmatch's YIQ distance / 35215, 10·log10, over {counted} \
         non-transparent pixels of the actual image"
    );
    if a.report_only {
        println!("checks   none (report only: nothing is checked)");
        println!("PASS");
        return Ok(ExitCode::SUCCESS);
    }
    println!("checks   khronos-db ≤ {max_db} dB");
    match score {
        Some(db) if db > max_db => {
            println!("FAIL: khronos-db {db:.4} dB is above --max-db {max_db}");
            Ok(ExitCode::from(1))
        }
        None => {
            println!("FAIL: no pixel to compare");
            Ok(ExitCode::from(1))
        }
        Some(_) => {
            println!("PASS");
            Ok(ExitCode::SUCCESS)
        }
    }
}

pub fn run(a: DiffArgs) -> Result<ExitCode> {
    if a.metric == Metric::KhronosDb {
        return khronos_db(&a);
    }
    if a.max_db.is_some() {
        anyhow::bail!("--max-db goes with --metric khronos-db");
    }
    let expected = luz::imageio::load(&a.expected)?;
    let actual = luz::imageio::load(&a.actual)?;
    let base = if a.report_only {
        Tolerance::report_only()
    } else {
        Tolerance::golden()
    };
    let mut opts = base.options_for(&expected, &actual);
    let given = a.max_flip_mean.is_some()
        || a.max_abs.is_some()
        || a.max_bad_pixels.is_some()
        || a.threshold.is_some();
    if let Some(c) = a.max_flip_mean {
        opts.max_flip_mean = c.into();
    }
    if let Some(c) = a.max_abs {
        opts.max_abs = c.into();
    }
    if let Some(c) = a.max_bad_pixels {
        opts.max_bad_pixels = c.into();
    }
    if let Some(t) = a.threshold {
        opts.bad_pixel_threshold = t;
    }
    opts.heatmap = a.output.clone();
    let report = luz::diff::compare_named(&a.expected, &expected, &a.actual, &actual, &opts)?;
    println!("{report}");
    let origin = if a.report_only {
        "report only: nothing is checked"
    } else if given {
        "as given, the rest the golden-image defaults"
    } else {
        "the golden-image defaults"
    };
    println!(
        "checks   {} ({}; {origin})",
        opts.describe_tolerances(),
        report.units
    );
    // Where the two images came from, when that differs (another driver explains a few LSB).
    if let (Ok(pe), Ok(pa)) = (
        luz::imageio::provenance::read(&a.expected),
        luz::imageio::provenance::read(&a.actual),
    ) {
        for line in pe.difference_lines(&pa) {
            println!("provenance differs: {line}");
        }
    }
    if let Some(h) = &a.output {
        println!("wrote {}", h.display());
    }
    let violations = if a.report_only {
        Vec::new()
    } else {
        report.violations(&opts)
    };
    if violations.is_empty() {
        println!("PASS");
        Ok(ExitCode::SUCCESS)
    } else {
        for v in &violations {
            println!("FAIL: {v}");
        }
        Ok(ExitCode::from(1))
    }
}
