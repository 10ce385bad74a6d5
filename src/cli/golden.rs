//! `luz golden`: render scenes and check them against golden images (or bless the goldens), with
//! a report for people (HTML), CI systems (JUnit XML) and pull requests (Markdown).

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::Args;

use luz::golden::{self, report, BlessChange, GoldenOptions, Shard, Verdict};
use luz::render::forward::DebugView;

use super::common::{context, validation_exit, Bar, GpuArgs, IblArgs};

#[derive(Args, Debug)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct GoldenArgs {
    #[command(subcommand)]
    pub action: Option<GoldenAction>,
    /// Scene files (.json) or folders of them.
    #[arg(required = true)]
    pub scenes: Vec<PathBuf>,
    /// The folder of goldens: <name>.png for the scene <name>.json, tolerances in an optional
    /// <name>.golden.json (else beside the scene).
    #[arg(long, required = true)]
    pub goldens: Option<PathBuf>,
    /// Run shard K of N only: a deterministic contiguous 1/N of the sorted cases (sizes differ
    /// by at most one); shards 1..N together run every case once. Merge their reports with
    /// `luz golden merge`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<Shard>,
    /// Write (or replace) the goldens instead of checking them, and say what changed.
    #[arg(long)]
    pub bless: bool,
    /// Write index.html, junit.xml, summary.md and cases.json (and the images) into this
    /// folder; `luz golden merge` joins the folders of a sharded run.
    #[arg(long, value_name = "OUT")]
    pub report: Option<PathBuf>,
    /// Scenes rendered at once.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub jobs: u32,
    #[command(flatten)]
    pub ibl: IblArgs,
    /// The goldens' format: png (<name>.png, the display encoding) or exr (<name>.exr, the
    /// linear float radiance, compared in linear float; tolerance steps are 1/255 of radiance).
    #[arg(long, value_enum, default_value_t = GoldenFormat::Png)]
    pub format: GoldenFormat,
    #[command(flatten)]
    pub gpu: GpuArgs,
}

#[derive(clap::Subcommand, Debug)]
pub enum GoldenAction {
    /// Merge the report folders of a sharded run (`--shard K/N --report DIR`) into one HTML
    /// page, JUnit file and summary, as if one job had run every case. Exit 1 when a case
    /// failed, or (with an error naming it) when a shard is missing or given twice.
    Merge(MergeArgs),
}

#[derive(Args, Debug)]
pub struct MergeArgs {
    /// The shards' report folders (each holds cases.json).
    #[arg(required = true, value_name = "DIR")]
    pub dirs: Vec<PathBuf>,
    /// Write the merged index.html, junit.xml, summary.md and cases.json here.
    #[arg(long, value_name = "OUT")]
    pub report: PathBuf,
}

fn merge(a: MergeArgs) -> Result<ExitCode> {
    report::merge(&a.dirs, &a.report)?;
    let text = luz::files::read_input_text(&a.report.join("cases.json"))?;
    let run: report::RunRecord = serde_json::from_str(&text)?;
    let failed = run.cases.iter().filter(|c| !c.passed).count();
    let width = run.cases.iter().map(|c| c.name.len()).max().unwrap_or(0);
    for c in &run.cases {
        println!("{} {:width$}  {}", c.status, c.name, c.figures);
    }
    println!("report: {}", a.report.join("index.html").display());
    println!(
        "luz golden merge: {} reports, {} passed, {failed} failed, {} scenes",
        a.dirs.len(),
        run.cases.len() - failed,
        run.cases.len()
    );
    Ok(if failed > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum GoldenFormat {
    Png,
    Exr,
}

pub fn run(a: GoldenArgs) -> Result<ExitCode> {
    if let Some(GoldenAction::Merge(m)) = a.action {
        return merge(m);
    }
    let goldens = a.goldens.clone().expect("clap requires --goldens");
    // Bad input for the whole run fails before any rendering.
    let scenes = golden::collect_scenes(&a.scenes)?;
    let selected = match a.shard {
        Some(s) => s.range(scenes.len()),
        None => 0..scenes.len(),
    };
    golden::check_goldens_dir(&goldens, a.bless)?;
    if let Some(out) = &a.report {
        report::prepare(out)?;
    }
    let ctx = context(&a.gpu)?;
    let device = ctx.info.summary();
    println!("device: {device}");
    if let Some(s) = a.shard {
        println!("shard {s}: {} of {} cases", selected.len(), scenes.len());
    }
    let mut opts = GoldenOptions::new(
        &goldens,
        luz::headless::RenderOptions {
            // One frame per case.
            switches: luz::render::forward::Switches::default().for_frames(1),
            ..luz::headless::RenderOptions::new(
                a.ibl.ibl_quality.settings(),
                a.ibl.no_cache,
                DebugView::None,
            )
        },
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
    let cases = golden::run_some(&ctx, &scenes, selected, &opts);

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
            goldens: goldens.clone(),
            luz: format!("luz {}", env!("CARGO_PKG_VERSION")),
            shard: a.shard,
            total: scenes.len(),
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
