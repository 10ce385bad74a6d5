//! `luz diff`: FLIP, max absolute difference and NaN counts of two images, with tolerances.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::Args;

use super::common::finite_non_negative;

#[derive(Args, Debug)]
pub struct DiffArgs {
    /// The reference image (PNG or EXR).
    pub expected: PathBuf,
    /// The image to check (PNG or EXR, same size).
    pub actual: PathBuf,
    /// Write the FLIP error heatmap (PNG).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Fail when the mean FLIP error exceeds this (0..1).
    #[arg(long, value_parser = finite_non_negative)]
    pub max_flip_mean: Option<f32>,
    /// Fail when any channel differs by more than this (8-bit steps for PNG, radiance for EXR).
    #[arg(long, value_parser = finite_non_negative)]
    pub max_abs: Option<f32>,
    /// Fail when more pixels than this differ (by more than --threshold).
    #[arg(long)]
    pub max_bad_pixels: Option<u64>,
    /// A pixel differs when a channel differs by more than this (default 0: any difference).
    #[arg(long, default_value_t = 0.0, value_parser = finite_non_negative)]
    pub threshold: f32,
}

pub fn run(a: DiffArgs) -> Result<ExitCode> {
    let opts = luz::diff::DiffOptions {
        max_flip_mean: a.max_flip_mean,
        max_abs: a.max_abs,
        max_bad_pixels: a.max_bad_pixels,
        bad_pixel_threshold: a.threshold,
        heatmap: a.output.clone(),
        ..Default::default()
    };
    let report = luz::diff::compare_files(&a.expected, &a.actual, &opts)?;
    println!("{report}");
    if let Some(h) = &a.output {
        println!("wrote {}", h.display());
    }
    let violations = report.violations(&opts);
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
