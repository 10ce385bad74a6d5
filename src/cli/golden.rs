//! `luz golden`: render scenes and check them against golden images (or bless the goldens), with
//! a report for people (HTML), CI systems (JUnit XML) and pull requests (Markdown).

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::Args;

use luz::golden::{self, report, BlessChange, GoldenOptions, Verdict};
use luz::render::forward::DebugView;

use super::common::{context, validation_exit, Bar, GpuArgs, IblQuality};

#[derive(Args, Debug)]
pub struct GoldenArgs {
    /// Scene files (.json) or folders of them.
    #[arg(required = true)]
    pub scenes: Vec<PathBuf>,
    /// The folder of goldens: <name>.png for the scene <name>.json, tolerances in an optional
    /// <name>.golden.json (else beside the scene).
    #[arg(long)]
    pub goldens: PathBuf,
    /// Write (or replace) the goldens instead of checking them, and say what changed.
    #[arg(long)]
    pub bless: bool,
    /// Write index.html, junit.xml and summary.md (and the images) into this folder.
    #[arg(long, value_name = "OUT")]
    pub report: Option<PathBuf>,
    /// Scenes rendered at once.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub jobs: u32,
    /// Sizes of the image-based lighting data (see `luz render --help`).
    #[arg(long, value_enum, default_value_t = IblQuality::Full)]
    pub ibl_quality: IblQuality,
    /// Recompute image-based lighting data instead of reading it from the cache.
    #[arg(long)]
    pub no_cache: bool,
    /// The goldens' format: png (<name>.png, the display encoding) or exr (<name>.exr, the
    /// linear float radiance, compared in linear float; tolerance steps are 1/255 of radiance).
    #[arg(long, value_enum, default_value_t = GoldenFormat::Png)]
    pub format: GoldenFormat,
    #[command(flatten)]
    pub gpu: GpuArgs,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum GoldenFormat {
    Png,
    Exr,
}

pub fn run(a: GoldenArgs) -> Result<ExitCode> {
    // Bad input for the whole run fails before any rendering.
    let scenes = golden::collect_scenes(&a.scenes)?;
    golden::check_goldens_dir(&a.goldens, a.bless)?;
    if let Some(out) = &a.report {
        report::prepare(out)?;
    }
    let ctx = context(&a.gpu)?;
    let device = ctx.info.summary();
    println!("device: {device}");
    let mut opts = GoldenOptions::new(
        &a.goldens,
        luz::headless::RenderOptions::new(a.ibl_quality.settings(), a.no_cache, DebugView::None),
    );
    opts.bless = a.bless;
    opts.jobs = a.jobs as usize;
    opts.format = match a.format {
        GoldenFormat::Png => luz::imageio::FileFormat::Png,
        GoldenFormat::Exr => luz::imageio::FileFormat::Exr,
    };
    opts.progress = Some(luz::progress::ProgressSink::new(Bar::new(
        "golden {bar:30} {pos}/{len} {msg} {elapsed}",
    )));
    let cases = golden::run(&ctx, &scenes, &opts);

    let width = cases.iter().map(|c| c.name.len()).max().unwrap_or(0);
    for c in &cases {
        let status = report::status_word(c);
        match &c.verdict {
            Verdict::Pass => println!("{status} {:width$}  {}", c.name, report::figures(c)),
            Verdict::Fail => {
                println!("{status} {:width$}  {}", c.name, report::figures(c));
                for f in &c.failures {
                    println!("     {:width$}  {f}", "");
                }
                for d in c.provenance_differences() {
                    println!("     {:width$}  provenance differs: {d}", "");
                }
            }
            Verdict::Blessed(change) => {
                let what = match change {
                    BlessChange::New => format!("wrote {}", c.golden.display()),
                    BlessChange::Unchanged => format!("{} unchanged", c.golden.display()),
                    BlessChange::Changed(r) => format!(
                        "replaced {}: FLIP mean {:.6}, max abs {}, {} pixels changed",
                        c.golden.display(),
                        r.flip_mean,
                        r.max_abs,
                        r.differing_pixels
                    ),
                    BlessChange::Resized { from, to } => format!(
                        "replaced {}: {}×{} → {}×{}",
                        c.golden.display(),
                        from.0,
                        from.1,
                        to.0,
                        to.1
                    ),
                    BlessChange::Replaced { reason } => {
                        format!("replaced {} (the old one: {reason})", c.golden.display())
                    }
                };
                println!("{status} {:width$}  {what}", c.name);
            }
        }
    }
    let failed = cases.iter().filter(|c| !c.passed()).count();
    if let Some(out) = &a.report {
        let info = report::RunInfo {
            device,
            goldens: a.goldens.clone(),
            luz: format!("luz {}", env!("CARGO_PKG_VERSION")),
        };
        report::write(out, &cases, &info)?;
        println!("report: {}", out.join("index.html").display());
    }
    if a.bless {
        let count = |f: fn(&BlessChange) -> bool| {
            cases
                .iter()
                .filter(|c| matches!(&c.verdict, Verdict::Blessed(ch) if f(ch)))
                .count()
        };
        println!(
            "luz golden: blessed {} scenes ({} new, {} unchanged, {} replaced), {failed} failed",
            cases.len() - failed,
            count(|c| *c == BlessChange::New),
            count(|c| *c == BlessChange::Unchanged),
            count(|c| !matches!(c, BlessChange::New | BlessChange::Unchanged)),
        );
    } else {
        println!(
            "luz golden: {} passed, {failed} failed, {} scenes",
            cases.len() - failed,
            cases.len()
        );
    }
    let code = validation_exit(&ctx);
    if code != ExitCode::SUCCESS {
        return Ok(code);
    }
    Ok(if failed > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}
