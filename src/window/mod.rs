//! The interactive viewer (feature `window`): a winit window with an ash-window surface and a
//! swapchain, an orbit camera, egui panels and a frame-time profiler, on top of the headless core
//! (the same `render::forward`, `render::saturate` and `render::tonemap` passes `luz render` uses).

mod app;
pub mod camera;
pub mod jobs;
pub mod lod_target;
pub mod plots;
pub mod script;
mod swapchain;
pub mod ui;

use std::path::PathBuf;

use anyhow::Result;

/// What the viewer is asked to do (`luz view`'s options, without the command line).
#[derive(Debug, Clone, Default)]
pub struct ViewOptions {
    /// Scene file; the embedded default scene when `None`.
    pub scene: Option<PathBuf>,
    /// Side B of an A/B comparison (a scene or model file, `--compare`).
    pub compare: Option<PathBuf>,
    /// Camera N of the scene's glTF files instead of the scene's camera (`--camera`).
    pub camera: Option<usize>,
    /// The device to use, validation and malloc tuning: what every command that touches the GPU
    /// builds its context from (the viewer adds its window's extensions).
    pub gpu: crate::vk::ContextDesc,
    /// Quit after this many frames.
    pub frames: Option<u64>,
    /// Write a screenshot of the last frame, UI included (.png), or the linear radiance (.exr).
    pub screenshot: Option<PathBuf>,
    /// Scripted actions, `FRAME:ACTION` separated by `;` ([`script::parse`]).
    pub script: Option<String>,
    /// Frame-time benchmark: no panels, no vsync, the scene's output size.
    pub bench: bool,
    /// Frames excluded from the benchmark's statistics.
    pub warmup: u64,
    /// With `bench`: where the per-frame times (CSV), the summary (JSON) and the measured frames
    /// (a Chrome/Perfetto trace) go.
    pub files: crate::timing::TimingFiles,
    /// Window width (default: the scene's output width).
    pub width: Option<u32>,
    /// Window height (default: the scene's output height).
    pub height: Option<u32>,
    /// Start with vsync off.
    pub no_vsync: bool,
    /// Hide the panels at start.
    pub no_panels: bool,
    /// Sizes of the image-based lighting data.
    pub ibl: crate::render::ibl::IblSettings,
    /// Do not read or write the IBL cache.
    pub no_cache: bool,
    /// Told the progress of IBL precomputations.
    pub progress: Option<crate::progress::ProgressSink>,
    /// How frames reach the window.
    pub display_path: DisplayPath,
    /// Deferred lighting where the scene allows it, or always forward.
    pub render_path: crate::render::forward::RenderPath,
    /// The frame time (ms) the viewer holds while the view changes by raising the mesh LOD
    /// budget ([`lod_target`]); `None`: always the scene's budget.
    pub target_ms: Option<f64>,
    /// Degrees the camera orbits every frame (a turntable, for benchmarks of a moving view).
    pub turntable: Option<f32>,
}

/// How the viewer's frames reach the swapchain image.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum DisplayPath {
    /// Straight from the forward pass (tone map and encode in its fragment shader) whenever the
    /// frame needs no whole-image operation; through the float image otherwise (`normalize`
    /// saturation, multisampling, an EXR screenshot).
    #[default]
    Auto,
    /// Always through the float HDR image and the display pass (the path `luz render` takes).
    Hdr,
}

/// How a viewer session ended: what the validation layer counted before the device went away.
#[derive(Debug, Clone, Copy, Default)]
pub struct ViewOutcome {
    pub validation: bool,
    pub validation_errors: u32,
    pub validation_warnings: u32,
}

/// Runs the viewer until the window closes (or `frames` have been shown). Messages go through the
/// `log` facade (info: what was written or opened; error: what failed).
pub fn run(options: ViewOptions) -> Result<ViewOutcome> {
    app::run(options)
}
