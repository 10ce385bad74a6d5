//! `luz view`: the interactive viewer ([`luz::window`]).

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::Args;

use luz::window::ViewOptions;

use super::common::{
    validation_exit_counts, Bar, GpuArgs, IblArgs, RenderPathArg, TimingFiles, ViewOverrides,
};

/// `luz view`: the interactive viewer.
#[derive(Args, Debug, Clone)]
pub struct ViewArgs {
    /// Scene file (JSON) or model file (.obj, .gltf, .glb); the embedded default scene when
    /// omitted.
    pub scene: Option<PathBuf>,
    /// A/B comparison: show this scene or model file as side B beside the first (split,
    /// difference, FLIP or toggle; the lab panel and the compare_* script actions choose).
    #[arg(long, value_name = "B")]
    pub compare: Option<PathBuf>,
    #[command(flatten)]
    pub gpu: GpuArgs,
    /// Quit after this many frames (scripts, tests and --bench).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    pub frames: Option<u64>,
    /// Write a screenshot of the last frame, UI included (.png), or the linear radiance (.exr).
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    /// Scripted actions, `FRAME:ACTION` separated by `;`. Actions: resize=WxH, minimize, restore,
    /// exposure=EV, tonemap=NAME, panels=on|off, help=on|off, orbit=DX,DY (degrees), zoom=STEPS,
    /// frame_all, reset, vsync=on|off, debug_view=NAME, screenshot=PATH, open=PATH (a scene, an
    /// .obj model or an .hdr/.exr environment, as when dropped on the window), save=PATH,
    /// compare_mode=split|difference|flip|toggle, compare_split=0..1, compare_flip (toggle: the
    /// other side), compare_duplicate (B = a copy of A), error_view=on|off,
    /// error_metric=relative|flip, lobe_plots=on|off, compare_edit=a|b (the side the panels,
    /// exposure and tonemap change).
    /// Example: "10:resize=800x600;20:exposure=1".
    #[arg(long)]
    pub script: Option<String>,
    /// Frame-time benchmark: no panels, no vsync, the scene's output size; prints p50/p95/p99
    /// frame time, the stutter count, per-pass GPU medians and the LOD budget and triangles
    /// drawn (300 frames unless --frames). The camera stays still unless --turntable or a
    /// script moves it, so with --target-ms the frames after the first 3 draw at the scene's
    /// budget.
    #[arg(long)]
    pub bench: bool,
    /// Frames excluded from --bench statistics (pipeline warm-up, first presents).
    #[arg(long, default_value_t = 10)]
    pub warmup: u64,
    #[command(flatten)]
    pub files: TimingFiles,
    #[command(flatten)]
    pub view: ViewOverrides,
    /// Start with vsync off (V toggles it).
    #[arg(long)]
    pub no_vsync: bool,
    /// Hide the panels at start (Tab toggles them).
    #[arg(long)]
    pub no_panels: bool,
    #[command(flatten)]
    pub ibl: IblArgs,
    /// How frames reach the window: "auto" shades, tone-maps and encodes straight into the
    /// window's image when the frame needs no whole-image operation (normalize saturation, MSAA,
    /// an EXR screenshot take the float path); "hdr" always renders the float image first and
    /// runs the display pass (same codes, more time: for comparisons).
    #[arg(long, value_enum, default_value_t = DisplayPathArg::Auto)]
    pub display_path: DisplayPathArg,
    /// Frame-time target in ms (0 or "off": none). While the view changes (orbit, zoom, edits,
    /// --turntable) the viewer coarsens the meshes' automatic LOD to hold it: the budget rises
    /// above the scene's output.tessellation_error_px when frames (their GPU time) take longer and
    /// falls back, never below the scene's, when they are faster. After 3 still frames it draws at
    /// the scene's budget, the exact picture `luz render` makes, once, then waits for input
    /// (without --bench, --frames or a script);
    /// screenshots always draw at it. A scene asking for full detail (0) gets it at rest and while
    /// moving as long as frames meet the target. Primitives' tessellation and shadow casters keep
    /// the scene's budget; the lab's A/B comparison and error view pause the target. The headless
    /// commands (render, bench, lab) always use the scene's budget, so their images and figures
    /// stay exact.
    #[arg(long, value_name = "MS", default_value = "100", value_parser = parse_target_ms)]
    pub target_ms: f64,
    /// Orbit the camera by this many degrees every frame (a turntable: a moving view for
    /// --bench, which otherwise keeps the camera still).
    #[arg(long, value_name = "DEGREES", allow_hyphen_values = true, value_parser = parse_degrees)]
    pub turntable: Option<f32>,
    /// "auto": deferred lighting (a G-buffer pass, then one lighting pass over the covered
    /// pixels) when every object shares one lean Phong variant, no environment, no MSAA; forward
    /// otherwise. "forward": always forward (for comparisons).
    #[arg(long, value_enum, default_value_t = RenderPathArg::Auto)]
    pub render_path: RenderPathArg,
}

/// `--display-path` values.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum DisplayPathArg {
    Auto,
    Hdr,
}

/// `--target-ms`: a number of milliseconds >= 0, or "off" (0).
fn parse_target_ms(s: &str) -> Result<f64, String> {
    if s.eq_ignore_ascii_case("off") {
        return Ok(0.0);
    }
    match s.parse::<f64>() {
        Ok(ms) if ms.is_finite() && ms >= 0.0 => Ok(ms),
        _ => Err(format!(
            "expected a frame time in milliseconds >= 0, or off, got {s:?}"
        )),
    }
}

/// `--turntable`: a finite number of degrees.
fn parse_degrees(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(d) if d.is_finite() => Ok(d),
        _ => Err(format!("expected a number of degrees, got {s:?}")),
    }
}

/// Runs the viewer until the window closes (or `--frames` have been shown).
pub fn run(a: ViewArgs) -> Result<ExitCode> {
    let outcome = luz::window::run(ViewOptions {
        scene: a.scene,
        compare: a.compare,
        camera: a.view.camera,
        gpu: a.gpu.context_desc(),
        frames: a.frames,
        screenshot: a.screenshot,
        script: a.script,
        bench: a.bench,
        warmup: a.warmup,
        files: a.files,
        width: a.view.width,
        height: a.view.height,
        no_vsync: a.no_vsync,
        no_panels: a.no_panels,
        ibl: a.ibl.ibl_quality.settings(),
        no_cache: a.ibl.no_cache,
        display_path: match a.display_path {
            DisplayPathArg::Auto => luz::window::DisplayPath::Auto,
            DisplayPathArg::Hdr => luz::window::DisplayPath::Hdr,
        },
        render_path: a.render_path.path(),
        target_ms: (a.target_ms > 0.0).then_some(a.target_ms),
        turntable: a.turntable,
        progress: Some(luz::progress::ProgressSink::new(Bar::new(
            "setup {bar:30} {pos}/{len} {msg} {elapsed}",
        ))),
    })?;
    Ok(validation_exit_counts(
        outcome.validation,
        outcome.validation_errors,
        outcome.validation_warnings,
    ))
}
