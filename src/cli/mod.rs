//! The `luz` command line: one file per subcommand, `common.rs` for the options and helpers they
//! share. Only the binary prints, draws progress bars and chooses exit codes; the library returns
//! data and errors.

mod bench;
mod brdf;
mod budget;
mod common;
mod devices;
mod diff;
mod export;
mod fidelity;
mod golden;
mod info;
mod lab;
mod reference;
mod render;
mod stability;
#[cfg(feature = "window")]
mod view;

use std::process::ExitCode;

use anyhow::Result;
use clap::{Parser, Subcommand};

#[derive(Parser, Debug)]
#[command(
    name = "luz",
    version,
    about = "A Vulkan renderer that measures how right and how fast each lighting model is",
    long_about = "luz renders scenes with classic and physically based lighting models on any Vulkan 1.3 \
device (Mesa lavapipe included), headless or in a window, times every pass, and compares images.\n\n\
Examples:\n  luz render -o out.png                 render the embedded default scene\n  \
luz render scene.json -o out.exr      linear float radiance, no tone mapping\n  \
luz bench scene.json --frames 100     frame-time statistics\n  \
luz diff expected.png actual.png      FLIP, max abs difference, NaN count; exit 1 beyond tolerances\n  \
luz golden scenes/ --goldens goldens/ each scene against its golden; --bless, --report out/\n  \
luz fidelity '{\"scenario\": …}'     a glTF Render Fidelity scenario to its PNG\n  \
luz view scene.json                   interactive viewer (H lists the keys)\n  \
luz reference scene.json -o ref.exr   the CPU reference answer\n  \
luz export scene.json --out mts/      Mitsuba 3 XML + PLY, to cross-check with an independent renderer\n  \
luz lab scene.json --out lab/         every method variant: GPU ms against error, chart\n  \
luz stability                         BRDFs at the edges of their domain, CPU and GPU"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
    /// Size cap of the disk cache (IBL data and LOD chains, in $LUZ_CACHE_DIR, else
    /// $XDG_CACHE_HOME/luz, else ~/.cache/luz), in MiB: beyond it the least recently used cache
    /// files are removed.
    #[arg(long, global = true, value_name = "MB", default_value_t = luz::files::cache_dir::DEFAULT_MAX_MB)]
    pub cache_max_mb: u64,
    /// The input budget (docs/reliability.md, "Input budget").
    #[command(flatten)]
    pub budget: budget::BudgetArgs,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a scene (or the embedded default) headless to a PNG or EXR image.
    Render(render::RenderArgs),
    /// Render a scene many times and report median, p95 and p99 of GPU ms per pass and CPU ms.
    Bench(bench::BenchArgs),
    /// Compare two PNG or EXR images (FLIP, max absolute difference, NaN/Inf) with tolerances.
    Diff(diff::DiffArgs),
    /// Render scenes and check each against its golden image (exit 1 when any fails), or bless
    /// the goldens; --report writes an HTML page, JUnit XML and a Markdown summary.
    Golden(golden::GoldenArgs),
    /// Render a Khronos glTF Render Fidelity scenario (the generator's offline-renderer contract:
    /// one JSON argument {"scenario": {…}, "outputFile": "….png"}) to its PNG.
    Fidelity(fidelity::FidelityArgs),
    /// Export a scene to another renderer (Mitsuba 3 XML with PLY meshes) for cross-checks;
    /// whatever has no like-for-like counterpart is listed in one warning.
    Export(export::ExportArgs),
    /// Print an image's size, format and provenance (luz version and commit, device, driver,
    /// scene and its hash, tone map, exposure, frame times).
    Info(info::InfoArgs),
    /// Evaluate a BRDF of the CPU reference at given directions (or JSON lines on stdin), or plot
    /// its lobe, a θh × θd slice and its directional albedo.
    Brdf(brdf::BrdfArgs),
    /// List the Vulkan devices luz can use and the one it would pick.
    Devices(common::GpuArgs),
    /// Speed against accuracy: render the scene with every method variant that applies, time each
    /// on the GPU, measure its error against the CPU reference, chart error against GPU ms.
    Lab(lab::LabArgs),
    /// Render a scene on the CPU as the reference answer (exact primitives, per-pixel shading,
    /// the environment converged by Monte Carlo) to an EXR or PNG image.
    Reference(reference::ReferenceArgs),
    /// Sweep every BRDF model and term to the edges of its domain on the CPU reference and the
    /// GPU mirror: NaN/Inf/negative counts, largest radiance, energy gain; exit 1 on any finding.
    Stability(stability::StabilityArgs),
    /// Open the interactive viewer: orbit camera, panels for every scene field, frame-time
    /// profiler, screenshots; `--bench` measures windowed frame times.
    #[cfg(feature = "window")]
    View(view::ViewArgs),
}

/// Parses the arguments, runs the command, prints errors as `luz: error: …`.
pub fn run() -> ExitCode {
    common::Logger::install();
    let cli = Cli::parse();
    luz::files::cache_dir::set_max_mb(cli.cache_max_mb);
    cli.budget.budget().install();
    match dispatch(cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("luz: error: {e:#}");
            ExitCode::from(1)
        }
    }
}

fn dispatch(cli: Cli) -> Result<ExitCode> {
    match cli.command {
        Command::Render(a) => render::run(a),
        Command::Bench(a) => bench::run(a),
        Command::Diff(a) => diff::run(a),
        Command::Golden(a) => golden::run(a),
        Command::Fidelity(a) => fidelity::run(a),
        Command::Export(a) => export::run(a),
        Command::Info(a) => info::run(a),
        Command::Brdf(a) => brdf::run(a),
        Command::Devices(a) => devices::run(a),
        Command::Lab(a) => lab::run(a),
        Command::Reference(a) => reference::run(a),
        Command::Stability(a) => stability::run(a),
        #[cfg(feature = "window")]
        Command::View(a) => view::run(a),
    }
}
