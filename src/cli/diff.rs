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
}

pub fn run(a: DiffArgs) -> Result<ExitCode> {
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
