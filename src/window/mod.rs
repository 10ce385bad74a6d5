//! The interactive viewer (feature `window`): a winit window with an ash-window surface and a
//! swapchain, an orbit camera, egui panels and a frame-time profiler, on top of the headless core
//! (the same `render::forward`, `render::saturate` and `render::tonemap` passes `luz render` uses).

mod app;
pub mod camera;
pub mod script;
mod swapchain;
pub mod ui;

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::Args;

use crate::cli::{GpuArgs, IblQuality};

/// `luz view`: the interactive viewer.
#[derive(Args, Debug, Clone)]
pub struct ViewArgs {
    /// Scene file (JSON); the embedded default scene when omitted.
    pub scene: Option<PathBuf>,
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
    /// .obj model or an .hdr/.exr environment, as when dropped on the window), save=PATH.
    /// Example: "10:resize=800x600;20:exposure=1".
    #[arg(long)]
    pub script: Option<String>,
    /// Frame-time benchmark: no panels, no vsync, the scene's output size; prints p50/p95/p99
    /// frame time, the stutter count and per-pass GPU medians (300 frames unless --frames).
    #[arg(long)]
    pub bench: bool,
    /// Frames excluded from --bench statistics (pipeline warm-up, first presents).
    #[arg(long, default_value_t = 10)]
    pub warmup: u64,
    /// With --bench: per-frame times as CSV.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// With --bench: a JSON summary.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Window width in pixels (default: the scene's output width).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub width: Option<u32>,
    /// Window height in pixels (default: the scene's output height).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub height: Option<u32>,
    /// Start with vsync off (V toggles it).
    #[arg(long)]
    pub no_vsync: bool,
    /// Hide the panels at start (Tab toggles them).
    #[arg(long)]
    pub no_panels: bool,
    /// Sizes of the image-based lighting data.
    #[arg(long, value_enum, default_value_t = IblQuality::Full)]
    pub ibl_quality: IblQuality,
    /// Do not read or write the IBL cache.
    #[arg(long)]
    pub no_cache: bool,
}

/// Runs the viewer until the window closes (or `--frames` have been shown).
pub fn run(args: ViewArgs) -> Result<ExitCode> {
    app::run(args)
}
