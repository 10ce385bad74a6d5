//! The lab in the window, app side: side B of an A/B comparison (a second scene with its own
//! forward, saturate and display passes and HDR target, from the headless core, drawn every frame
//! with the shared camera), the read-backs of both HDR images for the CPU maps (difference,
//! FLIP) and the error view's reference job. The panel and the overlays are `ui::compare`'s.

use super::*;
use crate::render::compare::{CompareKind, ComparePass};
use crate::window::jobs::{ErrorResult, MapImage, MapKind, ReferenceJob};
use crate::window::ui::compare::{
    CompareAction, CompareInfo, CompareMode, CompareSettings, ErrorMetric, ErrorStatus,
};

/// Environment samples per pixel of the error view's reference (`luz reference` takes 1024:
/// the viewer trades noise in environment-lit scenes for a reference in seconds).
pub(super) const ERROR_VIEW_ENV_SAMPLES: u32 = 64;

pub(super) use crate::window::ui::compare::MAP_SCOPE;

/// Side B: a scene and the passes that draw it, like A's in [`Viewer`].
pub(super) struct Side {
    pub scene: Scene,
    /// The scene the passes were built for.
    built_scene: Scene,
    forward: ForwardPass,
    ibl: Option<Ibl>,
    targets: HdrTarget,
    saturate: Option<SaturatePass>,
    display: DisplayPass,
}

/// What B's passes are built with.
pub(super) struct SideEnv<'a> {
    pub ctx: &'a Arc<Context>,
    pub pool: &'a CommandPool,
    pub settings: &'a ViewSettings,
    pub options: &'a RenderOptions,
    pub path: crate::render::forward::RenderPath,
    pub extent: vk::Extent2D,
}

impl Side {
    /// Builds B's passes for `scene`, reusing `ibl` when given (same environment).
    fn new(env: &SideEnv, scene: Scene, ibl: Option<Option<Ibl>>) -> Result<Self> {
        let samples = sample_flags(scene.output.msaa);
        let targets = HdrTarget::new("viewer B", nonzero(env.extent), samples);
        let ibl = match ibl {
            Some(i) => i,
            None => scene_ibl(env.ctx, env.pool, &scene, env.options)?,
        };
        let (forward, _) = make_forward(
            env.ctx,
            env.pool,
            (&scene, None),
            samples,
            ibl.as_ref(),
            env.extent,
            pass_options(env.settings, (Output::Hdr, env.path)),
        )?;
        let saturate = SaturatePass::for_scene(env.ctx, &scene)?;
        let display = DisplayPass::new(env.ctx, vk::ImageLayout::GENERAL)?;
        Ok(Self {
            built_scene: scene.clone(),
            scene,
            forward,
            ibl,
            targets,
            saturate,
            display,
        })
    }

    /// Rebuilds what B's scene or the window size now needs; then this frame's per-frame data.
    /// A failed rebuild undoes the edit (B's passes fit the last scene that built). Returns
    /// `Some` when B's passes and image were rebuilt: the message of a failed edit, or empty.
    fn sync(
        side: &mut Option<Side>,
        env: &SideEnv,
        camera: crate::scene::Camera,
        (slot, format): (usize, vk::Format),
    ) -> Result<Option<String>> {
        let Some(b) = side else { return Ok(None) };
        let mut message = None;
        let change = b
            .forward
            .shape()
            .change_to(&b.scene, env.settings.debug_view);
        let changed = change != Change::InPlace;
        if changed || nonzero(env.extent) != b.targets.extent() {
            message = Some(String::new());
            // SAFETY: the device is live and only this thread submits; afterwards nothing B's
            // old passes recorded is pending.
            unsafe { env.ctx.device.device_wait_idle()? };
            let same_env = change != (Change::Rebuild { environment: true });
            let ibl = same_env.then(|| b.ibl.take());
            match Side::new(env, b.scene.clone(), ibl) {
                Ok(new) => *b = new,
                Err(e) => {
                    message = Some(format!("B: {e:#} (the edit was undone)"));
                    // (a non-empty message: the edit failed; empty: B was rebuilt)
                    *b = Side::new(env, b.built_scene.clone(), None)?;
                }
            }
        }
        b.scene.camera = camera;
        let aspect = env.extent.width as f32 / env.extent.height.max(1) as f32;
        b.forward.update(slot, &b.scene, aspect)?;
        b.forward.prepare(Output::Hdr)?;
        b.forward.prepare_extent(env.extent)?;
        b.display.prepare(b.scene.output.tonemap, format)?;
        Ok(message)
    }
}

/// What the error view's reference depends on: when it changes (the camera moved, the window
/// was resized, the scene was edited), a running reference is cancelled and a shown one dropped.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct ViewKey {
    camera: crate::scene::Camera,
    extent: (u32, u32),
    output: crate::scene::Output,
    ambient: glam::Vec3,
    lights: Vec<crate::scene::Light>,
    materials: Vec<crate::scene::NamedMaterial>,
    objects: Vec<(crate::scene::Transform, usize, crate::scene::Shading, usize)>,
    fog: Option<crate::scene::Fog>,
    saturation: crate::scene::Saturation,
    environment: Option<crate::scene::Environment>,
}

impl ViewKey {
    fn of(scene: &Scene, extent: vk::Extent2D) -> Self {
        Self {
            camera: scene.camera,
            extent: (extent.width, extent.height),
            output: scene.output,
            ambient: scene.ambient,
            lights: scene.lights.clone(),
            materials: scene.materials.clone(),
            objects: scene
                .objects
                .iter()
                .map(|o| {
                    (
                        o.transform,
                        o.material,
                        o.shading,
                        Arc::as_ptr(&o.mesh) as usize,
                    )
                })
                .collect(),
            fog: scene.fog,
            saturation: scene.saturation,
            environment: scene.environment.clone(),
        }
    }
}

/// The error view of one side (A or B): its reference job, result and overlay.
#[derive(Default)]
struct ErrorSide {
    job: Option<(ReferenceJob, ViewKey)>,
    error: Option<(ErrorResult, ViewKey)>,
    failed: Option<String>,
    texture: Option<(egui::TextureHandle, ErrorMetric)>,
    /// The view of the previous frame: a reference starts once the view held still a frame.
    last_key: Option<ViewKey>,
    /// This side's image is read back this frame for a new job.
    want: bool,
}

impl ErrorSide {
    fn poll(&mut self, ctx: &egui::Context, metric: ErrorMetric, side: &str) {
        let finished = self.job.as_mut().and_then(|(j, _)| j.poll());
        if let Some(r) = finished {
            let (_, key) = self.job.take().expect("polled above");
            match r {
                Ok(Some(result)) => {
                    log::info!(
                        "error view{side}: reference {}x{} in {:.0} ms; relative error mean {:.3e} \
                         p99 {:.3e} max {:.3e}; FLIP mean {:.4}",
                        result.width,
                        result.height,
                        result.reference_ms,
                        result.relative.stats.mean,
                        result.relative.stats.p99,
                        result.relative.stats.max,
                        result.flip.stats.mean
                    );
                    self.error = Some((result, key));
                    self.texture = None;
                }
                Ok(None) => {}
                Err(e) => {
                    log::error!("error view{side}: {e}");
                    self.failed = Some(e);
                }
            }
        }
        if let Some((r, _)) = &self.error {
            if self.texture.as_ref().map(|(_, m)| *m) != Some(metric) {
                let map = match metric {
                    ErrorMetric::Relative => &r.relative,
                    ErrorMetric::Flip => &r.flip,
                };
                let mut slot = self.texture.take().map(|(t, _)| t);
                texture(ctx, &mut slot, &format!("luz_error_map{side}"), map);
                self.texture = slot.map(|t| (t, metric));
            }
        }
    }

    /// Cancels what the view of `scene` (camera set) at `extent` no longer matches and starts
    /// a reference once the view held still; sets `want` when this frame's image must go to it.
    fn tick(&mut self, scene: &Scene, extent: vk::Extent2D) {
        self.want = false;
        let key = ViewKey::of(scene, extent);
        if self.job.as_ref().is_some_and(|(_, k)| *k != key) {
            self.job = None; // dropping cancels
        }
        if self.error.as_ref().is_some_and(|(_, k)| *k != key) {
            self.error = None;
            self.texture = None;
            self.failed = None;
        }
        let still = self.last_key.as_ref() == Some(&key);
        if self.job.is_none() && self.error.is_none() && self.failed.is_none() && still {
            let mut s = scene.clone();
            s.output.width = extent.width;
            s.output.height = extent.height;
            let opts = crate::reference::ReferenceOptions {
                samples: ERROR_VIEW_ENV_SAMPLES,
                ..Default::default()
            };
            let job = ReferenceJob::start(s, opts, scene.output.exposure, scene.output.tonemap);
            self.job = Some((job, key.clone()));
            self.want = true;
        }
        self.last_key = Some(key);
    }

    fn give(&mut self, image: Option<LinearImage>) {
        if let (Some(image), Some((job, _))) = (image, &mut self.job) {
            if job.wants_gpu_image() {
                job.give_gpu_image(image);
            }
        }
    }

    fn status(&self) -> ErrorStatus<'_> {
        if let Some(e) = &self.failed {
            return ErrorStatus::Failed(e);
        }
        if let Some((r, _)) = &self.error {
            return ErrorStatus::Done(r);
        }
        match &self.job {
            Some((j, _)) => ErrorStatus::Running(j.rows_done(), j.total_rows),
            None => ErrorStatus::Running(0, 0),
        }
    }

    fn map(&self, metric: ErrorMetric) -> Option<&MapImage> {
        self.error.as_ref().map(|(r, _)| match metric {
            ErrorMetric::Relative => &r.relative,
            ErrorMetric::Flip => &r.flip,
        })
    }
}

/// The lab's state in the viewer.
#[derive(Default)]
pub(super) struct Lab {
    pub settings: CompareSettings,
    pub b: Option<Side>,
    /// The GPU maps of A and B (difference, FLIP), built for the current pair of images.
    pub(super) gpu: Option<ComparePass>,
    /// The map kind each frame slot recorded (its figures are read after the slot's fence).
    recorded: [Option<CompareKind>; FRAMES_IN_FLIGHT],
    /// The figures of the newest map read back.
    map: Option<MapImage>,
    /// Maps drawn in the session, per kind, and the last figures (for the exit log).
    maps_drawn: [(usize, Option<MapImage>); 2],
    /// The error view of A and of B.
    errors: [ErrorSide; 2],
    plots: Option<crate::window::plots::PlotWorker>,
}

fn texture(ctx: &egui::Context, slot: &mut Option<egui::TextureHandle>, name: &str, m: &MapImage) {
    let image =
        egui::ColorImage::from_rgba_unmultiplied([m.width as usize, m.height as usize], &m.rgba);
    match slot {
        Some(t) => t.set(image, egui::TextureOptions::NEAREST),
        None => *slot = Some(ctx.load_texture(name, image, egui::TextureOptions::NEAREST)),
    }
}

/// The GPU map kind a comparison mode draws.
fn map_kind(mode: CompareMode) -> Option<CompareKind> {
    match mode {
        CompareMode::Difference => Some(CompareKind::Difference),
        CompareMode::Flip => Some(CompareKind::Flip),
        _ => None,
    }
}

impl Lab {
    /// A's forward pass must draw the float image (B is composed with it, or it is read back).
    pub fn forces_hdr(&self) -> bool {
        self.b.is_some() || self.settings.error_view
    }

    /// Drops the GPU map pass (A's or B's image was replaced; the device is idle).
    pub fn drop_gpu(&mut self) {
        self.gpu = None;
        self.recorded = Default::default();
    }

    /// One line on the A/B maps drawn in the session (count and last figures per kind), for
    /// the exit log; `None` without maps.
    pub fn summary(&self) -> Option<String> {
        let parts: Vec<String> = self
            .maps_drawn
            .iter()
            .filter_map(|(n, m)| {
                let m = m.as_ref()?;
                let name = if m.kind == MapKind::Flip {
                    "flip"
                } else {
                    "difference"
                };
                Some(format!(
                    "{n} {name} maps at {}x{} on the GPU, last: mean {:.6e} p99 {:.6e} max {:.6e} \
                     scale {:.6e} above {:.4}",
                    m.width,
                    m.height,
                    m.stats.mean,
                    m.stats.p99,
                    m.stats.max,
                    m.scale,
                    m.stats.above
                ))
            })
            .collect();
        (!parts.is_empty()).then(|| format!("A/B maps: {}", parts.join("; ")))
    }

    /// Takes finished work from the threads (never waits).
    pub fn poll(&mut self, ctx: &egui::Context) {
        let metric = self.settings.metric;
        let [a, b] = &mut self.errors;
        a.poll(ctx, metric, "");
        b.poll(ctx, metric, " B");
    }

    /// The error view's state machine for this frame, with A's scene (camera set) at `extent`,
    /// and B's when comparing.
    pub fn error_tick(&mut self, scene: &Scene, extent: vk::Extent2D) {
        if !self.settings.error_view {
            self.errors = Default::default();
            return;
        }
        self.errors[0].tick(scene, extent);
        match &self.b {
            Some(b) => self.errors[1].tick(&b.scene, extent),
            None => self.errors[1] = ErrorSide::default(),
        }
    }

    /// Reads slot `slot`'s figures of the map it drew last (after the slot's fence), and forgets
    /// the map when the mode no longer draws one.
    fn read_map(&mut self, slot: usize, gpu_ms: f64) -> Result<()> {
        if self.b.is_none() || map_kind(self.settings.mode).is_none() {
            self.map = None;
        }
        let (Some(pass), Some(kind)) = (&self.gpu, self.recorded[slot].take()) else {
            return Ok(());
        };
        let s = pass.read_stats(slot, kind)?;
        let e = pass.extent();
        let kind = match kind {
            CompareKind::Difference => MapKind::Difference,
            CompareKind::Flip => MapKind::Flip,
        };
        let m = MapImage {
            kind,
            width: e.width,
            height: e.height,
            rgba: Vec::new(),
            stats: s.stats,
            scale: s.scale,
            ms: gpu_ms,
        };
        let i = usize::from(kind == MapKind::Flip);
        self.maps_drawn[i].0 += 1;
        self.maps_drawn[i].1 = Some(m.clone());
        if map_kind(self.settings.mode).is_some() && self.b.is_some() {
            self.map = Some(m);
        }
        Ok(())
    }

    /// Hands this frame's read-back images to the error view's jobs.
    pub fn deliver(&mut self, a: Option<LinearImage>, b: Option<LinearImage>) {
        self.errors[0].give(a);
        self.errors[1].give(b);
    }

    /// Paints the overlays (under the panels) and, with `panels`, the lab panel; returns the
    /// panel's actions.
    pub fn ui(
        &mut self,
        ui: &mut egui::Ui,
        panels: bool,
        profiler: &Profiler,
        plot: Option<crate::window::plots::PlotKey>,
    ) -> Vec<CompareAction> {
        use crate::window::ui::compare as c;
        if panels && self.settings.plots {
            self.plots
                .get_or_insert_with(Default::default)
                .update(ui.ctx(), plot);
        }
        let metric = self.settings.metric;
        let has_b = self.b.is_some();
        let error_on = self.settings.error_view;
        // The error view: A whole without B; with B, the side shown in toggle mode, else A left
        // of the divider and B right of it.
        let split = self.settings.split;
        let halves: Vec<(usize, f32, f32)> = match (has_b, self.settings.mode) {
            (false, _) => vec![(0, 0.0, 1.0)],
            (true, CompareMode::Toggle) => vec![(usize::from(self.settings.show_b), 0.0, 1.0)],
            (true, _) => vec![(0, 0.0, split), (1, split, 1.0)],
        };
        let mut error_shown = false;
        if error_on {
            for &(side, x0, x1) in &halves {
                if let Some((t, _)) = &self.errors[side].texture {
                    c::paint_map(ui, t, (x0, x1));
                    error_shown = true;
                }
            }
        }
        if has_b && (self.settings.mode == CompareMode::Split || (error_on && halves.len() == 2)) {
            c::divider(ui, &mut self.settings.split);
        }
        let passes = profiler.pass_history();
        let scope_ms = |name: &str| {
            passes
                .iter()
                .filter(|(n, _)| *n == name)
                .map(|(_, t)| t)
                .sum::<f64>()
        };
        let b_ms = passes
            .iter()
            .filter(|(n, _)| crate::window::ui::compare::is_b(n))
            .map(|(_, t)| t)
            .sum::<f64>();
        let map_ms = scope_ms(MAP_SCOPE);
        let a_ms = passes
            .iter()
            .filter(|(n, _)| {
                !crate::window::ui::compare::is_b(n) && !matches!(*n, MAP_SCOPE | "display" | "ui")
            })
            .map(|(_, t)| t)
            .sum::<f64>();
        if let Some(m) = &mut self.map {
            m.ms = map_ms;
        }
        if !panels {
            let percent = metric == ErrorMetric::Relative;
            let mut legend: Vec<(&str, &MapImage)> = Vec::new();
            if error_shown {
                for &(side, _, _) in &halves {
                    if let Some(m) = self.errors[side].map(metric) {
                        legend.push((["A", "B"][side], m));
                    }
                }
            } else if let Some(m) = self.map.as_ref().filter(|_| has_b) {
                legend.push(("", m));
            }
            if !legend.is_empty() {
                c::corner_legend(ui.ctx(), &legend, percent && error_shown);
            }
            return Vec::new();
        }
        if !self.settings.open {
            return Vec::new();
        }
        let off = ErrorStatus::Off;
        let info = CompareInfo {
            has_b,
            gpu_ms: (a_ms, b_ms),
            map: self.map.as_ref(),
            error: if error_on {
                self.errors[0].status()
            } else {
                off
            },
            error_b: if error_on && has_b {
                self.errors[1].status()
            } else {
                off
            },
            plots: self.plots.as_ref(),
        };
        let mut settings = self.settings;
        let actions = c::compare_panel(ui, &mut settings, &info);
        self.settings = settings;
        actions
    }
}

/// The plot key of the material of `scene`'s object `selected` at its light angle
/// ([`crate::window::plots::light_angle`]; 45° without a light).
pub(super) fn plot_key(scene: &Scene, selected: usize) -> Option<crate::window::plots::PlotKey> {
    let o = scene.objects.get(selected)?;
    let m = scene.materials.get(o.material)?;
    Some(crate::window::plots::PlotKey {
        model: m.material,
        theta_l: crate::window::plots::light_angle(scene, selected).unwrap_or(45.0),
    })
}

impl Viewer {
    /// Starts comparing: B becomes `scene` (a copy of A or the `--compare` file).
    pub(super) fn set_b(&mut self, scene: Scene) -> Result<()> {
        // SAFETY: the device is live and only this thread submits; B's old passes (if any) are
        // dropped below, after nothing uses them.
        unsafe { self.ctx.device.device_wait_idle()? };
        self.lab.b = None;
        self.lab.drop_gpu();
        let env = self.side_env();
        let side = Side::new(&env, scene, None)?;
        self.lab.b = Some(side);
        self.lab.settings.open = true;
        Ok(())
    }

    fn side_env(&self) -> SideEnv<'_> {
        SideEnv {
            ctx: &self.ctx,
            pool: &self.pool,
            settings: &self.settings,
            options: &self.render_options,
            path: self.render_path,
            extent: self.swapchain.extent,
        }
    }

    pub(super) fn apply_lab_actions(&mut self, actions: Vec<CompareAction>) {
        for a in actions {
            let r = match a {
                CompareAction::Duplicate => self.set_b(self.scene.clone()),
                CompareAction::DropB => {
                    // SAFETY: as in `set_b`.
                    let idle = unsafe { self.ctx.device.device_wait_idle() };
                    self.lab.b = None;
                    self.lab.drop_gpu();
                    self.lab.settings.edit_b = false;
                    idle.map_err(Into::into)
                }
            };
            if let Err(e) = r {
                let msg = format!("B: {e:#}");
                log::error!("{msg}");
                self.status = Some(msg);
            }
        }
    }

    /// B's rebuilds and per-frame data, before recording.
    pub(super) fn sync_b(&mut self, slot: usize) -> Result<()> {
        let camera = self.orbit.to_camera();
        // B is taken out while the environment borrows the viewer, and put back before any error
        // goes up.
        let mut b = self.lab.b.take();
        let synced = Side::sync(
            &mut b,
            &self.side_env(),
            camera,
            (slot, self.swapchain.format),
        );
        self.lab.b = b;
        if let Some(m) = synced? {
            // B's image is a new one (the device is idle): the map pass is built again.
            self.lab.drop_gpu();
            if !m.is_empty() {
                log::error!("{m}");
                self.status = Some(m);
            }
        }
        Ok(())
    }

    /// Gets the lab ready for slot `slot`'s frame: reads the figures of the slot's previous map
    /// (its fence was waited for), builds the map kernels the comparison mode needs, and makes
    /// the host buffers of this frame's read-backs. Returns the map kind to record, if any.
    pub(super) fn prepare_lab(&mut self, slot: usize) -> Result<(Option<CompareKind>, Readbacks)> {
        let map_ms = self.profiler.pass_history();
        let map_ms = map_ms
            .iter()
            .filter(|(n, _)| *n == MAP_SCOPE)
            .map(|(_, t)| t)
            .sum::<f64>();
        self.lab.read_map(slot, map_ms)?;
        let kind = map_kind(self.lab.settings.mode).filter(|_| self.lab.b.is_some());
        if let Some(kind) = kind {
            if self.lab.gpu.is_none() {
                let extent = self.targets.extent();
                self.lab.gpu = Some(ComparePass::new(&self.ctx, extent, FRAMES_IN_FLIGHT)?);
            }
            let pass = self.lab.gpu.as_mut().expect("built above");
            let output = self.scene.output;
            pass.prepare(kind, output.tonemap, self.swapchain.format)?;
            self.lab.recorded[slot] = Some(kind);
        }
        let mut out = Readbacks::default();
        if self.lab.errors[0].want {
            out.a = Some(self.copy_buffer(&self.targets, "read-back A")?);
        }
        if self.lab.errors[1].want {
            if let Some(b) = &self.lab.b {
                out.b = Some(self.copy_buffer(&b.targets, "read-back B")?);
            }
        }
        Ok((kind, out))
    }

    /// A host buffer for the whole HDR colour image of `targets`.
    fn copy_buffer(&self, targets: &HdrTarget, name: &str) -> Result<(Buffer, vk::Extent2D)> {
        let extent = targets.extent();
        let buffer = Buffer::new(
            &self.ctx,
            name,
            extent.width as u64 * extent.height as u64 * 16,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        Ok((buffer, extent))
    }
}

/// Declares B's scene passes (timed on rows of their own, "B: …") into its HDR target.
pub(super) fn add_b_passes<'a>(
    g: &mut FrameGraph<'a>,
    b: &'a Side,
    slot: usize,
) -> Result<SceneTarget> {
    let target = b.targets.add_to(g);
    b.forward
        .add_passes(g, (slot, PassNames::B), Output::Hdr, target)?;
    if let Some(sat) = &b.saturate {
        sat.add_pass(g, target.output(), "B: saturate");
    }
    Ok(target)
}

/// This frame's views of what the display pass reads: A's and B's HDR colour and the A/B map.
pub(super) struct ShownViews {
    pub a: vk::ImageView,
    pub b: Option<vk::ImageView>,
    pub map: Option<vk::ImageView>,
}

/// Draws the window's scene image: A, or A and B as the comparison mode shows them (the
/// difference and FLIP maps of this frame, slot `slot`).
pub(super) fn record_display(
    cmd: vk::CommandBuffer,
    (slot, area, format): (usize, vk::Extent2D, vk::Format),
    a: (&DisplayPass, &Scene),
    lab: &Lab,
    views: ShownViews,
) -> Result<()> {
    let lab_b = &lab.b;
    let rect = |x0: u32, x1: u32| vk::Rect2D {
        offset: vk::Offset2D { x: x0 as i32, y: 0 },
        extent: vk::Extent2D {
            width: x1.saturating_sub(x0),
            height: area.height,
        },
    };
    let draw = |(pass, scene): (&DisplayPass, &Scene), view, clip: vk::Rect2D| {
        pass.record_clipped(
            cmd,
            view,
            (scene.output.tonemap, format),
            scene.output.exposure,
            (area, clip),
        )
    };
    let (Some(b), Some(b_view)) = (lab_b, views.b) else {
        return Ok(draw(a, views.a, rect(0, area.width))?);
    };
    let b = (&b.display, &b.scene);
    match (lab.settings.mode, &lab.gpu) {
        (CompareMode::Split, _) => {
            let x = ((lab.settings.split * area.width as f32).round() as u32).min(area.width);
            if x > 0 {
                draw(a, views.a, rect(0, x))?;
            }
            if x < area.width {
                draw(b, b_view, rect(x, area.width))?;
            }
        }
        (CompareMode::Toggle, _) if lab.settings.show_b => draw(b, b_view, rect(0, area.width))?,
        (CompareMode::Difference | CompareMode::Flip, Some(pass))
            if lab.recorded[slot].is_some() && views.map.is_some() =>
        {
            let map = views.map.expect("checked in the guard");
            pass.record_show(cmd, (slot, map), format, area, rect(0, area.width))?
        }
        _ => draw(a, views.a, rect(0, area.width))?,
    }
    Ok(())
}

/// Host copies recorded this frame: (buffer, extent) of A and B.
#[derive(Default)]
pub(super) struct Readbacks {
    pub a: Option<(Buffer, vk::Extent2D)>,
    pub b: Option<(Buffer, vk::Extent2D)>,
}

impl Readbacks {
    pub fn any(&self) -> bool {
        self.a.is_some() || self.b.is_some()
    }

    /// The copies as images (after the frame's fence).
    pub fn images(&self) -> Result<(Option<LinearImage>, Option<LinearImage>)> {
        let read = |r: &Option<(Buffer, vk::Extent2D)>| -> Result<Option<LinearImage>> {
            let Some((buffer, e)) = r else {
                return Ok(None);
            };
            let n = e.width as usize * e.height as usize;
            let bytes = buffer.mapped()?;
            let floats: &[f32] = bytemuck::try_cast_slice(&bytes[..n * 16])
                .map_err(|e| anyhow!("read-back buffer: {e}"))?;
            Ok(Some(LinearImage {
                width: e.width,
                height: e.height,
                pixels: floats
                    .chunks_exact(4)
                    .map(|c| [c[0], c[1], c[2], c[3]])
                    .collect(),
            }))
        };
        Ok((read(&self.a)?, read(&self.b)?))
    }
}
