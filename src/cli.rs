//! The `luz` command line: subcommands and their options. `main.rs` only calls [`run`].

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::time::Instant;

use anyhow::{bail, Context as _, Result};
use clap::{Args, Parser, Subcommand};

use crate::headless::{FrameTimes, Headless};
use crate::imageio::FileFormat;
use crate::scene::Scene;
use crate::stats::Summary;
use crate::vk::{Context, ContextDesc, InstanceDesc};

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
luz view scene.json                   interactive viewer (H lists the keys)\n  \
luz reference scene.json -o ref.exr   the CPU reference answer\n  \
luz lab scene.json --out lab/         every method variant: GPU ms against error, chart\n  \
luz stability                         BRDFs at the edges of their domain, CPU and GPU"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a scene (or the embedded default) headless to a PNG or EXR image.
    Render(RenderArgs),
    /// Render a scene many times and report median, p95 and p99 of GPU ms per pass and CPU ms.
    Bench(BenchArgs),
    /// Compare two PNG or EXR images (FLIP, max absolute difference, NaN/Inf) with tolerances.
    Diff(DiffArgs),
    /// Evaluate a BRDF of the CPU reference at given directions (or JSON lines on stdin), or plot
    /// its lobe, a θh × θd slice and its directional albedo.
    Brdf(crate::brdf_cli::BrdfArgs),
    /// List the Vulkan devices luz can use and the one it would pick.
    Devices(GpuArgs),
    /// Speed against accuracy: render the scene with every method variant that applies, time each
    /// on the GPU, measure its error against the CPU reference, chart error against GPU ms.
    Lab(crate::lab::LabArgs),
    /// Render a scene on the CPU as the reference answer (exact primitives, per-pixel shading,
    /// the environment converged by Monte Carlo) to an EXR or PNG image.
    Reference(crate::reference::ReferenceArgs),
    /// Sweep every BRDF model and term to the edges of its domain on the CPU reference and the
    /// GPU mirror: NaN/Inf/negative counts, largest radiance, energy gain; exit 1 on any finding.
    Stability(crate::stability::StabilityArgs),
    /// Open the interactive viewer: orbit camera, panels for every scene field, frame-time
    /// profiler, screenshots; `--bench` measures windowed frame times.
    #[cfg(feature = "window")]
    View(crate::window::ViewArgs),
}

/// Options shared by every command that touches the GPU.
#[derive(Args, Debug, Clone)]
pub struct GpuArgs {
    /// Enable the Khronos validation layer; errors are counted and make the exit code 3.
    #[arg(long, env = "LUZ_VALIDATION", value_parser = clap::builder::BoolishValueParser::new(), default_value_t = false, action = clap::ArgAction::Set, num_args = 0..=1, default_missing_value = "true")]
    pub validate: bool,
    /// Use the device whose name contains this text (case-insensitive) instead of the best one
    /// (discrete > integrated > virtual > CPU).
    #[arg(long, env = "LUZ_DEVICE")]
    pub device: Option<String>,
}

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Scene file (JSON); the embedded default scene when omitted.
    pub scene: Option<PathBuf>,
    /// Output image: .png (exposed, tone-mapped, sRGB) or .exr (linear float32 radiance).
    #[arg(short, long, default_value = "luz.png")]
    pub output: PathBuf,
    /// Frames to render; timings are the median over them.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub frames: u32,
    /// Override the scene's output width.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub width: Option<u32>,
    /// Override the scene's output height.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub height: Option<u32>,
    /// List the pipeline variants built and more detail.
    #[arg(short, long)]
    pub verbose: bool,
    /// Recompute image-based lighting data instead of reading it from the cache
    /// ($LUZ_CACHE_DIR, else $XDG_CACHE_HOME/luz, else ~/.cache/luz).
    #[arg(long)]
    pub no_cache: bool,
    /// Sizes of the image-based lighting data: "full" (512² cubes, 512² LUT at 1024 samples) or
    /// "fast" (128² cubes and LUT, for previews).
    #[arg(long, value_enum, default_value_t = IblQuality::Full)]
    pub ibl_quality: IblQuality,
    /// Show one quantity instead of the shaded radiance (BRDF terms are for the first light).
    #[arg(long, value_enum, default_value_t = crate::render::forward::DebugView::None)]
    pub debug_view: crate::render::forward::DebugView,
    #[command(flatten)]
    pub gpu: GpuArgs,
}

/// Presets of `render::ibl::IblSettings`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum IblQuality {
    Full,
    Fast,
}

impl IblQuality {
    pub fn settings(self) -> crate::render::ibl::IblSettings {
        match self {
            IblQuality::Full => Default::default(),
            IblQuality::Fast => crate::render::ibl::IblSettings::fast(),
        }
    }
}

#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Scene file (JSON); the embedded default scene when omitted.
    pub scene: Option<PathBuf>,
    /// Frames to time (after the warm-up).
    #[arg(long, default_value_t = 50, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub frames: u32,
    /// Frames rendered first and not timed.
    #[arg(long, default_value_t = 3)]
    pub warmup: u32,
    /// Write one line per frame: frame, cpu_ms, then GPU ms of each pass.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Write the summary as JSON.
    #[arg(long)]
    pub json: Option<PathBuf>,
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub width: Option<u32>,
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub height: Option<u32>,
    /// Recompute image-based lighting data instead of reading it from the cache.
    #[arg(long)]
    pub no_cache: bool,
    /// Sizes of the image-based lighting data (see `luz render --help`).
    #[arg(long, value_enum, default_value_t = IblQuality::Full)]
    pub ibl_quality: IblQuality,
    /// Sample resident memory and GPU allocations every N frames (a soak: they must stay flat);
    /// default: a tenth of --frames.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub memory_every: Option<u32>,
    /// Exit 4 when resident memory grows by more than this many MiB between the first and the
    /// last sample, or the GPU allocation count or bytes change.
    #[arg(long)]
    pub max_memory_growth_mib: Option<f64>,
    #[command(flatten)]
    pub gpu: GpuArgs,
}

/// One sample of a soak: resident memory and the GPU allocator's live allocations.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct MemorySample {
    pub frame: u64,
    pub rss_mib: f64,
    pub gpu_allocations: usize,
    pub gpu_bytes: u64,
}

/// Resident set size of this process in MiB (Linux `/proc/self/statm`; NaN elsewhere).
pub fn resident_mib() -> f64 {
    let Ok(statm) = std::fs::read_to_string("/proc/self/statm") else {
        return f64::NAN;
    };
    let pages: f64 = statm
        .split_whitespace()
        .nth(1)
        .and_then(|v| v.parse().ok())
        .unwrap_or(f64::NAN);
    pages * 4096.0 / (1024.0 * 1024.0)
}

fn memory_sample(ctx: &Context, frame: u64) -> MemorySample {
    let report = ctx.allocator().generate_report();
    MemorySample {
        frame,
        rss_mib: resident_mib(),
        gpu_allocations: report.allocations.len(),
        gpu_bytes: report.total_allocated_bytes,
    }
}

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

/// A tolerance: a finite number ≥ 0 (a NaN tolerance would make every comparison pass).
fn finite_non_negative(s: &str) -> std::result::Result<f32, String> {
    let v: f32 = s
        .trim()
        .parse()
        .map_err(|_| format!("{s:?} is not a number"))?;
    if !v.is_finite() || v < 0.0 {
        return Err(format!("{s:?} must be a finite number ≥ 0"));
    }
    Ok(v)
}

/// Parses the arguments, runs the command, prints errors as `luz: error: …`.
pub fn run() -> ExitCode {
    let cli = Cli::parse();
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
        Command::Render(a) => render(a),
        Command::Bench(a) => bench(a),
        Command::Diff(a) => diff(a),
        Command::Brdf(a) => crate::brdf_cli::run(a),
        Command::Devices(a) => devices(a),
        Command::Lab(a) => crate::lab::run(a),
        Command::Reference(a) => crate::reference::run(a),
        Command::Stability(a) => crate::stability::run(a),
        #[cfg(feature = "window")]
        Command::View(a) => crate::window::run(a),
    }
}

/// Loads the scene named on the command line, or the embedded default.
pub fn load_scene(path: Option<&Path>) -> Result<Scene> {
    match path {
        Some(p) => Ok(crate::scene::load(p)?),
        None => Ok(crate::scene::default_scene()),
    }
}

/// `LUZ_SYNC_VALIDATION=1` (with validation on) also enables the layer's synchronization
/// validation: hazards between commands are reported as errors.
pub fn sync_validation_requested() -> bool {
    std::env::var_os("LUZ_SYNC_VALIDATION").is_some_and(|v| !v.is_empty() && v != "0")
}

pub fn context(gpu: &GpuArgs) -> Result<Arc<Context>> {
    let ctx = Context::new(&ContextDesc {
        instance: InstanceDesc {
            validation: gpu.validate,
            sync_validation: sync_validation_requested(),
            ..Default::default()
        },
        device_name: gpu.device.clone(),
        device_extensions: Vec::new(),
    })?;
    Ok(ctx)
}

/// Fails early (before any rendering) when the output cannot be written.
fn check_output(path: &Path) -> Result<FileFormat> {
    let format = FileFormat::from_path(path)?;
    if path.is_dir() {
        bail!("cannot write {}: it is a directory", path.display());
    }
    let existed = path.exists();
    std::fs::OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(false)
        .open(path)
        .with_context(|| format!("cannot write {}", path.display()))?;
    if !existed {
        // Only a probe: leave nothing behind if rendering fails later.
        let _ = std::fs::remove_file(path);
    }
    Ok(format)
}

pub(crate) fn validation_exit(ctx: &Context) -> ExitCode {
    let log = ctx.validation_log();
    if ctx.instance.validation {
        eprintln!(
            "validation: {} errors, {} warnings",
            log.errors(),
            log.warnings()
        );
        if log.errors() > 0 {
            return ExitCode::from(3);
        }
    }
    ExitCode::SUCCESS
}

/// The renderer options the `render` and `bench` flags ask for.
pub(crate) fn render_options(
    no_cache: bool,
    quality: IblQuality,
    debug_view: crate::render::forward::DebugView,
) -> crate::headless::RenderOptions {
    crate::headless::RenderOptions {
        ibl: quality.settings(),
        cache_dir: if no_cache {
            None
        } else {
            crate::render::ibl::default_cache_dir()
        },
        debug_view,
        generic_pipelines: false,
    }
}

/// Says how many objects were tessellated automatically and with how many segments; `verbose`
/// lists each object's choice.
pub fn report_tessellation(scene: &Scene, verbose: bool) {
    let lines = crate::scene::tessellation::report(scene);
    if lines.is_empty() {
        return;
    }
    let segments: Vec<u32> = scene
        .objects
        .iter()
        .filter(|o| matches!(o.tessellation, crate::scene::Tessellation::Auto { .. }))
        .filter_map(|o| o.desc.segments())
        .collect();
    let (lo, hi) = (
        segments.iter().min().copied().unwrap_or(0),
        segments.iter().max().copied().unwrap_or(0),
    );
    println!(
        "automatic tessellation (budget {} px): {} object(s), {lo}-{hi} segments{}",
        scene.output.tessellation_error_px,
        lines.len(),
        if verbose {
            ":"
        } else {
            " (--verbose lists them)"
        }
    );
    if verbose {
        for l in lines {
            println!("  {l}");
        }
    }
}

/// Overrides the output size; automatic tessellation is chosen again for the new height.
pub fn apply_size(scene: &mut Scene, width: Option<u32>, height: Option<u32>) {
    if let Some(w) = width {
        scene.output.width = w;
    }
    if let Some(h) = height {
        scene.output.height = h;
        crate::scene::tessellation::resolve(scene);
    }
}

/// Per-pass statistics over many frames.
pub struct TimingReport {
    pub frames: usize,
    pub cpu: Summary,
    pub passes: Vec<(&'static str, Summary)>,
    pub gpu_total: Summary,
}

impl TimingReport {
    pub fn of(frames: &[FrameTimes]) -> Self {
        let cpu: Vec<f64> = frames.iter().map(|f| f.cpu_ms).collect();
        let mut names: Vec<&'static str> = Vec::new();
        for f in frames {
            for (n, _) in &f.gpu_ms {
                if !names.contains(n) {
                    names.push(n);
                }
            }
        }
        let passes = names
            .iter()
            .map(|n| {
                let v: Vec<f64> = frames
                    .iter()
                    .filter_map(|f| f.gpu_ms.iter().find(|(m, _)| m == n).map(|(_, t)| *t))
                    .collect();
                (*n, Summary::of(&v))
            })
            .collect();
        let totals: Vec<f64> = frames.iter().map(|f| f.gpu_total()).collect();
        Self {
            frames: frames.len(),
            cpu: Summary::of(&cpu),
            passes,
            gpu_total: Summary::of(&totals),
        }
    }

    pub fn print(&self) {
        println!(
            "{:<22} {:>10} {:>10} {:>10}   ({} frames)",
            "", "median ms", "p95 ms", "p99 ms", self.frames
        );
        for (name, s) in &self.passes {
            println!(
                "{:<22} {:>10.3} {:>10.3} {:>10.3}",
                format!("GPU {name}"),
                s.median,
                s.p95,
                s.p99
            );
        }
        if !self.passes.is_empty() {
            let s = &self.gpu_total;
            println!(
                "{:<22} {:>10.3} {:>10.3} {:>10.3}",
                "GPU total", s.median, s.p95, s.p99
            );
        }
        let s = &self.cpu;
        println!(
            "{:<22} {:>10.3} {:>10.3} {:>10.3}",
            "CPU frame", s.median, s.p95, s.p99
        );
    }
}

fn render(a: RenderArgs) -> Result<ExitCode> {
    let t0 = Instant::now();
    let format = check_output(&a.output)?;
    let mut scene = load_scene(a.scene.as_deref())?;
    apply_size(&mut scene, a.width, a.height);
    let ctx = context(&a.gpu)?;
    println!("device: {}", ctx.info.summary());
    let mut renderer = Headless::with_options(
        &ctx,
        &scene,
        &render_options(a.no_cache, a.ibl_quality, a.debug_view),
    )?;
    if a.verbose {
        println!("pipeline variants built:");
        for v in renderer.variants() {
            println!("  {v}");
        }
        println!("triangles: {}", renderer.triangle_count());
    }
    report_tessellation(&scene, a.verbose);
    if let Some(t) = renderer.ibl_times() {
        let stages: Vec<String> = t
            .stages
            .iter()
            .map(|(n, ms)| format!("{n} {ms:.0} ms"))
            .collect();
        println!(
            "IBL precomputation: {:.0} ms ({})",
            t.total(),
            stages.join(", ")
        );
    }
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    let mut frames = Vec::with_capacity(a.frames as usize);
    let first = renderer.render()?;
    let ttff = t0.elapsed().as_secs_f64() * 1e3;
    frames.push(first);
    for _ in 1..a.frames {
        frames.push(renderer.render()?);
    }
    let image = renderer.image()?;
    crate::imageio::save(
        &a.output,
        &image,
        scene.output.exposure,
        scene.output.tonemap,
    )?;
    let nan = crate::imageio::count_non_finite(&image.pixels);
    println!(
        "scene: {} ({}x{}, msaa {})",
        scene.display_name(),
        scene.output.width,
        scene.output.height,
        scene.output.msaa
    );
    println!("time to first frame: {ttff:.1} ms (process start to first frame on the host)");
    TimingReport::of(&frames).print();
    if nan > 0 {
        eprintln!("warning: {nan} pixels hold NaN or Inf");
    }
    println!(
        "wrote {} ({})",
        a.output.display(),
        match format {
            FileFormat::Png => "PNG, exposed, tone-mapped, sRGB",
            FileFormat::Exr => "EXR, linear float32 radiance",
        }
    );
    Ok(validation_exit(&ctx))
}

fn bench(a: BenchArgs) -> Result<ExitCode> {
    let mut scene = load_scene(a.scene.as_deref())?;
    apply_size(&mut scene, a.width, a.height);
    for p in [&a.csv, &a.json].into_iter().flatten() {
        std::fs::write(p, b"").with_context(|| format!("cannot write {}", p.display()))?;
    }
    let ctx = context(&a.gpu)?;
    println!("device: {}", ctx.info.summary());
    report_tessellation(&scene, false);
    let mut renderer = Headless::with_options(
        &ctx,
        &scene,
        &render_options(a.no_cache, a.ibl_quality, Default::default()),
    )?;
    for _ in 0..a.warmup {
        renderer.render()?;
    }
    let bar = indicatif::ProgressBar::new(a.frames as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} frames {elapsed}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let mut frames = Vec::with_capacity(a.frames as usize);
    let every = a.memory_every.unwrap_or((a.frames / 10).max(1)) as u64;
    let mut memory = vec![memory_sample(&ctx, 0)];
    for i in 1..=a.frames as u64 {
        frames.push(renderer.render()?);
        bar.inc(1);
        if i % every == 0 {
            memory.push(memory_sample(&ctx, i));
        }
    }
    bar.finish_and_clear();
    println!(
        "scene: {} ({}x{}, {} triangles, {} lights)",
        scene.display_name(),
        scene.output.width,
        scene.output.height,
        renderer.triangle_count(),
        scene.lights.len()
    );
    let report = TimingReport::of(&frames);
    report.print();
    let wall: Vec<f64> = frames.iter().map(|f| f.cpu_ms).collect();
    let stutters = crate::profiler::stutter_count(&wall);
    println!("stutters: {stutters} frames slower than 2x the rolling median of the frame time");
    println!("memory (resident MiB, GPU allocations, GPU bytes) every {every} frames:");
    for m in &memory {
        println!(
            "  frame {:>8}  {:>9.2} MiB  {:>5} allocations  {:>12} bytes",
            m.frame, m.rss_mib, m.gpu_allocations, m.gpu_bytes
        );
    }
    // The first sample is before any timed frame; growth is judged from the second on (the
    // first frames fault in the driver's caches).
    let base = memory.get(1).unwrap_or(&memory[0]);
    let last = memory.last().unwrap_or(base);
    let growth = last.rss_mib - base.rss_mib;
    let gpu_flat = last.gpu_allocations == base.gpu_allocations && last.gpu_bytes == base.gpu_bytes;
    println!(
        "memory growth from frame {} to {}: {growth:+.2} MiB resident, GPU allocations {}",
        base.frame,
        last.frame,
        if gpu_flat { "flat" } else { "CHANGED" }
    );
    let megapixels = scene.output.width as f64 * scene.output.height as f64 / 1e6;
    let forward = report
        .passes
        .iter()
        .find(|(n, _)| *n == "forward")
        .map(|(_, s)| s.median);
    let per_mp_light = match forward {
        Some(ms) if !scene.lights.is_empty() => {
            let v = ms / (megapixels * scene.lights.len() as f64);
            println!(
                "GPU forward per megapixel·light: {v:.4} ms (median {ms:.3} ms / ({megapixels:.4} MP × {} lights))",
                scene.lights.len()
            );
            Some(v)
        }
        _ => None,
    };
    if let Some(p) = &a.csv {
        let mut out = String::from("frame,cpu_ms");
        for (n, _) in &report.passes {
            out.push_str(&format!(",gpu_{n}_ms"));
        }
        out.push('\n');
        for (i, f) in frames.iter().enumerate() {
            out.push_str(&format!("{i},{:.4}", f.cpu_ms));
            for (n, _) in &report.passes {
                let t = f.gpu_ms.iter().find(|(m, _)| m == n).map(|(_, t)| *t);
                out.push_str(&format!(",{:.4}", t.unwrap_or(f64::NAN)));
            }
            out.push('\n');
        }
        std::fs::write(p, out).with_context(|| format!("cannot write {}", p.display()))?;
        println!("wrote {}", p.display());
    }
    if let Some(p) = &a.json {
        let passes: serde_json::Map<String, serde_json::Value> = report
            .passes
            .iter()
            .map(|(n, s)| (n.to_string(), serde_json::to_value(s).unwrap_or_default()))
            .collect();
        let json = serde_json::json!({
            "device": ctx.info.summary(),
            "frames": report.frames,
            "width": scene.output.width,
            "height": scene.output.height,
            "triangles": renderer.triangle_count(),
            "lights": scene.lights.len(),
            "cpu_ms": report.cpu,
            "gpu_total_ms": report.gpu_total,
            "gpu_pass_ms": passes,
            "gpu_forward_ms_per_megapixel_light": per_mp_light,
            "stutters": stutters,
            "memory": memory,
            "memory_growth_mib": growth,
            "gpu_allocations_flat": gpu_flat,
        });
        std::fs::write(p, serde_json::to_string_pretty(&json)?)
            .with_context(|| format!("cannot write {}", p.display()))?;
        println!("wrote {}", p.display());
    }
    if let Some(max) = a.max_memory_growth_mib {
        if growth > max || !gpu_flat {
            eprintln!(
                "luz: error: memory not flat: {growth:+.2} MiB resident (limit {max}), GPU allocations {}",
                if gpu_flat { "flat" } else { "changed" }
            );
            return Ok(ExitCode::from(4));
        }
    }
    Ok(validation_exit(&ctx))
}

fn diff(a: DiffArgs) -> Result<ExitCode> {
    let opts = crate::diff::DiffOptions {
        max_flip_mean: a.max_flip_mean,
        max_abs: a.max_abs,
        max_bad_pixels: a.max_bad_pixels,
        bad_pixel_threshold: a.threshold,
        heatmap: a.output.clone(),
        ..Default::default()
    };
    let report = crate::diff::compare_files(&a.expected, &a.actual, &opts)?;
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

fn devices(a: GpuArgs) -> Result<ExitCode> {
    let ctx = context(&a)?;
    println!("{}", ctx.info.summary());
    println!(
        "  maxImageDimension2D {}, maxPushConstantsSize {}, minUniformBufferOffsetAlignment {}, \
         timestampPeriod {} ns, timestampValidBits {}",
        ctx.info.limits.max_image_dimension2_d,
        ctx.info.limits.max_push_constants_size,
        ctx.info.limits.min_uniform_buffer_offset_alignment,
        ctx.info.timestamp_period_ns,
        ctx.info.timestamp_valid_bits
    );
    Ok(validation_exit(&ctx))
}
