//! Options and helpers shared by the subcommands: GPU selection and validation, IBL sizes, scene
//! loading, progress bars, timing tables, exit codes, and the logger that prints the library's
//! messages.

use std::path::Path;
use std::process::ExitCode;
use std::sync::Arc;

use anyhow::{bail, Context as _, Result};
use clap::Args;

use luz::headless::{RenderOptions, TimingReport};
use luz::imageio::FileFormat;
use luz::render::forward::DebugView;
use luz::scene::Scene;
use luz::vk::{Context, ContextDesc, InstanceDesc};

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

/// `--width`, `--height` and `--camera` of the commands that render a scene file's view.
#[derive(Args, Debug, Clone, Copy)]
pub struct ViewOverrides {
    /// Override the scene's output width.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub width: Option<u32>,
    /// Override the scene's output height.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub height: Option<u32>,
    /// Use camera N of the model's glTF file (0 = the first) instead of the scene's camera.
    #[arg(long, value_name = "N")]
    pub camera: Option<usize>,
}

impl ViewOverrides {
    /// Applies them to a loaded scene: the camera first, then the output size
    /// ([`Scene::override_size`]).
    pub fn apply(&self, scene: &mut Scene) -> Result<()> {
        if let Some(n) = self.camera {
            luz::scene::model::use_camera(scene, n)?;
        }
        scene.override_size(self.width, self.height);
        Ok(())
    }
}

/// `--csv`, `--json` and `--trace` (the viewer's options hold the same).
pub use luz::timing::TimingFiles;

/// `--ibl-quality` and `--no-cache`: the image-based lighting data of every command that renders.
#[derive(Args, Debug, Clone, Copy)]
pub struct IblArgs {
    /// Sizes of the image-based lighting data: "full" (512² cubes, 512² LUT at 1024 samples) or
    /// "fast" (128² cubes and LUT, for previews).
    #[arg(long, value_enum, default_value_t = IblQuality::Full)]
    pub ibl_quality: IblQuality,
    /// Recompute image-based lighting data instead of reading it from the cache, and do not
    /// write it there ($LUZ_CACHE_DIR, else $XDG_CACHE_HOME/luz, else ~/.cache/luz).
    #[arg(long)]
    pub no_cache: bool,
}

/// Presets of `render::ibl::IblSettings`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum IblQuality {
    Full,
    Fast,
}

impl IblQuality {
    pub fn settings(self) -> luz::render::ibl::IblSettings {
        match self {
            IblQuality::Full => Default::default(),
            IblQuality::Fast => luz::render::ibl::IblSettings::fast(),
        }
    }
}

/// A tolerance: a finite number ≥ 0 (a NaN tolerance would make every comparison pass).
pub fn finite_non_negative(s: &str) -> std::result::Result<f32, String> {
    let v: f32 = s
        .trim()
        .parse()
        .map_err(|_| format!("{s:?} is not a number"))?;
    if !v.is_finite() || v < 0.0 {
        return Err(format!("{s:?} must be a finite number ≥ 0"));
    }
    Ok(v)
}

/// Parses a `--debug-view` name ([`DebugView::name`]).
pub fn debug_view_parser() -> impl clap::builder::TypedValueParser<Value = DebugView> {
    use clap::builder::TypedValueParser as _;
    clap::builder::PossibleValuesParser::new(
        DebugView::ALL.map(|v| clap::builder::PossibleValue::new(v.name()).help(v.help())),
    )
    .map(|s| DebugView::from_name(&s).unwrap_or_default())
}

/// Loads the scene named on the command line, or the embedded default; `camera`: `--camera N`
/// (one of the cameras of the scene's glTF files).
pub fn load_scene(path: Option<&Path>, camera: Option<usize>) -> Result<Scene> {
    let mut scene = luz::scene::load_or_default(path)?;
    if let Some(n) = camera {
        luz::scene::model::use_camera(&mut scene, n)?;
    }
    Ok(scene)
}

/// `LUZ_SYNC_VALIDATION=1` (with validation on) also enables the layer's synchronization
/// validation: hazards between commands are reported as errors.
pub fn sync_validation_requested() -> bool {
    std::env::var_os("LUZ_SYNC_VALIDATION").is_some_and(|v| !v.is_empty() && v != "0")
}

/// `LUZ_MALLOC_TUNING=0` (or off, false, no) keeps glibc's malloc defaults on a CPU device
/// (`luz::vk::host`); the library reads no environment for it.
pub fn malloc_tuning_requested() -> bool {
    use luz::vk::host::{disabled_by, ENV_DISABLE};
    !disabled_by(std::env::var(ENV_DISABLE).ok().as_deref())
}

impl GpuArgs {
    /// The context these options ask for (with `LUZ_SYNC_VALIDATION` and `LUZ_MALLOC_TUNING`
    /// from the environment), without extensions: what `context` builds and the viewer extends.
    pub fn context_desc(&self) -> ContextDesc {
        ContextDesc {
            instance: InstanceDesc {
                validation: self.validate,
                sync_validation: sync_validation_requested(),
                ..Default::default()
            },
            device_name: self.device.clone(),
            device_extensions: Vec::new(),
            malloc_tuning: malloc_tuning_requested(),
        }
    }
}

pub fn context(gpu: &GpuArgs) -> Result<Arc<Context>> {
    let ctx = Context::new(&gpu.context_desc())?;
    Ok(ctx)
}

/// Fails early (before any rendering) when the output cannot be written.
pub fn check_output(path: &Path) -> Result<FileFormat> {
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

/// Says what was written (and warns when the image holds `nan` non-finite pixels).
pub fn report_written(path: &Path, format: FileFormat, nan: u64) {
    if nan > 0 {
        eprintln!("warning: {nan} pixels hold NaN or Inf");
    }
    println!(
        "wrote {} ({})",
        path.display(),
        match format {
            FileFormat::Png => "PNG, exposed, tone-mapped, sRGB",
            FileFormat::Exr => "EXR, linear float32 radiance",
        }
    );
}

/// Prints the validation counts (when validation is on) and returns exit code 3 on any error.
pub fn validation_exit(ctx: &Context) -> ExitCode {
    validation_exit_counts(
        ctx.instance.validation,
        ctx.validation_log().errors(),
        ctx.validation_log().warnings(),
    )
}

/// [`validation_exit`] from counts taken before the device was destroyed.
pub fn validation_exit_counts(enabled: bool, errors: u32, warnings: u32) -> ExitCode {
    if enabled {
        eprintln!("validation: {errors} errors, {warnings} warnings");
        if errors > 0 {
            return ExitCode::from(3);
        }
    }
    ExitCode::SUCCESS
}

/// What a measurement or a comparison turns off (`luz render`, `luz bench`); each is on by
/// default, and the image's provenance records all three.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct SwitchArgs {
    /// Record one draw per object instead of one instanced draw per run of objects that share
    /// mesh, LOD level, pipeline and material (what instancing saves; the image is the same).
    #[arg(long)]
    pub no_instancing: bool,
    /// Draw every shadow map in every frame instead of reusing the maps nothing they see changed
    /// in (what a moving scene pays; the image is the same).
    #[arg(long)]
    pub no_shadow_cache: bool,
    /// Shadow lookups at every fragment instead of only where shadows can fall (what the
    /// receiver culling saves; the image is the same).
    #[arg(long)]
    pub no_shadow_receivers: bool,
}

impl SwitchArgs {
    pub fn switches(&self) -> luz::render::forward::Switches {
        luz::render::forward::Switches {
            instancing: !self.no_instancing,
            shadow_cache: !self.no_shadow_cache,
            shadow_receivers: !self.no_shadow_receivers,
        }
    }
}

/// The renderer options the `render` and `bench` flags ask for, with a progress bar for the IBL
/// precomputation.
pub fn render_options(ibl: &IblArgs, debug_view: DebugView) -> RenderOptions {
    RenderOptions {
        progress: Some(luz::progress::ProgressSink::new(Bar::new(
            "setup {bar:30} {pos}/{len} {msg} {elapsed}",
        ))),
        ..RenderOptions::new(ibl.ibl_quality.settings(), ibl.no_cache, debug_view)
    }
}

/// Says how many objects were tessellated automatically and with how many segments; `verbose`
/// lists each object's choice.
pub fn report_tessellation(scene: &Scene, verbose: bool) {
    for line in luz::scene::tessellation::summary(scene, verbose) {
        println!("{line}");
    }
}

/// Says which LOD levels the meshes draw at (the budget, levels, triangles drawn of all) and
/// how their chains were made; `verbose` lists each object's level.
pub fn report_lod(scene: &Scene, renderer: &luz::headless::Headless, verbose: bool) {
    let choices = renderer.lod_choices(scene);
    for line in luz::scene::lod::summary(scene, &choices, verbose) {
        println!("{line}");
    }
    let s = renderer.lod_stats();
    if verbose && s.built + s.loaded + s.failed > 0 {
        println!(
            "LOD chains: {} built, {} read from the cache, {} failed (drawn whole)",
            s.built, s.loaded, s.failed
        );
    }
}

/// A terminal progress bar (hidden when stderr is not a terminal) for the library's
/// [`luz::progress::Progress`] reports.
pub struct Bar(indicatif::ProgressBar);

impl Bar {
    /// A bar with an indicatif template; its length is set by the first update.
    pub fn new(template: &str) -> Self {
        Self::with_length(template, 1)
    }

    pub fn with_length(template: &str, len: u64) -> Self {
        let bar = indicatif::ProgressBar::new(len);
        bar.set_style(
            indicatif::ProgressStyle::with_template(template)
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        Self(bar)
    }

    pub fn inc(&self, n: u64) {
        self.0.inc(n);
    }

    pub fn finish_and_clear(&self) {
        self.0.finish_and_clear();
    }
}

impl luz::progress::Progress for Bar {
    fn update(&self, stage: &str, done: u64, total: u64) {
        self.0.set_length(total);
        self.0.set_position(done);
        self.0.set_message(stage.to_string());
    }

    fn finish(&self) {
        self.0.finish_and_clear();
    }
}

/// Prints the library's log records: info on stdout as is, warnings on stderr as
/// `warning: …`, errors on stderr as `luz: …`.
pub struct Logger;

static LOGGER: Logger = Logger;

impl Logger {
    pub fn install() {
        if log::set_logger(&LOGGER).is_ok() {
            log::set_max_level(log::LevelFilter::Info);
        }
    }
}

impl log::Log for Logger {
    fn enabled(&self, metadata: &log::Metadata<'_>) -> bool {
        metadata.level() <= log::Level::Info
    }

    fn log(&self, record: &log::Record<'_>) {
        match record.level() {
            log::Level::Error => eprintln!("luz: {}", record.args()),
            log::Level::Warn => eprintln!("warning: {}", record.args()),
            log::Level::Info => println!("{}", record.args()),
            _ => {}
        }
    }

    fn flush(&self) {}
}

/// Prints per-pass statistics: median, p95 and p99 of each pass, the GPU total and the CPU frame.
pub fn print_timing(report: &TimingReport) {
    println!(
        "{:<22} {:>10} {:>10} {:>10}   ({} frames)",
        "", "median ms", "p95 ms", "p99 ms", report.frames
    );
    for (name, s) in &report.passes {
        println!(
            "{:<22} {:>10.3} {:>10.3} {:>10.3}",
            format!("GPU {name}"),
            s.median,
            s.p95,
            s.p99
        );
    }
    if !report.passes.is_empty() {
        let s = &report.gpu_total;
        println!(
            "{:<22} {:>10.3} {:>10.3} {:>10.3}",
            "GPU total", s.median, s.p95, s.p99
        );
    }
    let s = &report.cpu;
    println!(
        "{:<22} {:>10.3} {:>10.3} {:>10.3}",
        "CPU frame", s.median, s.p95, s.p99
    );
}

/// `--render-path` values (`luz bench`, `luz view`): deferred lighting where the scene allows it,
/// or always forward.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum RenderPathArg {
    Auto,
    Forward,
}

impl RenderPathArg {
    pub fn path(self) -> luz::render::forward::RenderPath {
        match self {
            RenderPathArg::Auto => luz::render::forward::RenderPath::Auto,
            RenderPathArg::Forward => luz::render::forward::RenderPath::Forward,
        }
    }
}

/// `--light-loop` values (`luz render`, `luz bench`): how the fragment stage loops over lights.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum LightLoopArg {
    /// Clustered with enough ranged lights that the clusters cull (render::forward::clusters::
    /// CROSSOVER, MAX_LISTED_FRACTION), else plain.
    Auto,
    /// Every light at every fragment.
    Plain,
    /// Only the lights of the fragment's cluster (screen tiles x depth slices).
    Clustered,
}

impl LightLoopArg {
    pub fn light_loop(self) -> luz::render::forward::LightLoop {
        use luz::render::forward::LightLoop;
        match self {
            LightLoopArg::Auto => LightLoop::Auto,
            LightLoopArg::Plain => LightLoop::Plain,
            LightLoopArg::Clustered => LightLoop::Clustered,
        }
    }
}

/// One line on the light loop: plain, or the clusters' grid and lights per cluster.
pub fn light_loop_line(stats: Option<luz::render::forward::ClusterStats>) -> String {
    match stats {
        None => "light loop: plain (every light at every fragment)".to_string(),
        Some(s) => {
            format!(
            "light loop: clustered, {}x{} tiles x {} slices, lights per cluster max {} mean {:.2} \
             (over clusters with a ranged light {:.2}; {} in every cluster), {} indices, \
             assigned on the CPU in {:.2} ms",
            s.tiles_x,
            s.tiles_y,
            s.slices,
            s.max,
            s.mean,
            s.mean_occupied,
            s.always,
            s.indices,
            s.build_ms
        ) + &if s.area_max > 0 {
                format!(
                "; area lights per cluster max {} mean {:.2} (over clusters with a ranged light \
                 {:.2}; {} in every cluster)",
                s.area_max, s.area_mean, s.area_mean_occupied, s.area_always
            )
            } else {
                String::new()
            }
        }
    }
}

/// A tolerance given on the command line: a limit, or `none` (the check is off).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Check<T> {
    Off,
    At(T),
}

impl<T> From<Check<T>> for Option<T> {
    fn from(c: Check<T>) -> Self {
        match c {
            Check::Off => None,
            Check::At(v) => Some(v),
        }
    }
}

/// `none`, or a tolerance as [`finite_non_negative`] reads it.
pub fn tolerance_or_none(s: &str) -> std::result::Result<Check<f32>, String> {
    if s.trim().eq_ignore_ascii_case("none") {
        return Ok(Check::Off);
    }
    finite_non_negative(s)
        .map(Check::At)
        .map_err(|e| format!("{e} (or `none` to turn the check off)"))
}

/// `none`, or a pixel count.
pub fn count_or_none(s: &str) -> std::result::Result<Check<u64>, String> {
    if s.trim().eq_ignore_ascii_case("none") {
        return Ok(Check::Off);
    }
    s.trim().parse::<u64>().map(Check::At).map_err(|_| {
        format!("{s:?} is not a pixel count (a whole number ≥ 0, or `none` to turn the check off)")
    })
}
