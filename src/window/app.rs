//! The viewer's event loop and frame: winit 0.30 `ApplicationHandler`, the swapchain, frames in
//! flight, the passes of the headless core, egui on top, screenshots and the profiler.
//!
//! One frame: wait for this frame slot's fence → acquire a swapchain image → run egui → apply
//! edits (per-frame data in this slot; a rebuild when the scene's structure changed) → record
//! forward → saturate → tone map (RGBA32F → RGBA8 sRGB codes) → blit into the swapchain image →
//! egui → present. The HDR, depth and LDR images are shared by the slots: every frame's first
//! barrier on them waits for the previous frame's last use on the same queue.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use anyhow::{anyhow, Context as _, Result};
use ash::vk;
use gpu_allocator::MemoryLocation;
use raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, ModifiersState, NamedKey};
use winit::window::{Window, WindowId};

use super::camera::OrbitCamera;
use super::script::{self, Action};
use super::swapchain::{color_range, Swapchain};
use super::ui::{self, UiAction, UiState, ViewSettings};
use super::{ViewOptions, ViewOutcome};
use crate::headless::{build_ibl, RenderOptions};
use crate::imageio::LinearImage;
use crate::profiler::{FrameSample, Profiler};
use crate::render::display::DisplayPass;
use crate::render::forward::{ForwardPass, TargetFormat};
use crate::render::ibl::Ibl;
use crate::render::saturate::SaturatePass;
use crate::render::target::{FrameStart, HdrTarget, COLOR_ATTACHMENT, COLOR_FORMAT, DEPTH_FORMAT};
use crate::scene::Scene;
use crate::vk::cmd::{copy_image_to_buffer, transition, CommandPool, Transition};
use crate::vk::timing::GpuTimer;
use crate::vk::{Buffer, Context, ContextDesc, InstanceDesc, VkError};

/// Frames the CPU may record ahead of the GPU.
const FRAMES_IN_FLIGHT: usize = 2;
/// Frames kept by the profiler's rolling window.
const PROFILER_WINDOW: usize = 300;

type Access = (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2);

pub fn run(args: ViewOptions) -> Result<ViewOutcome> {
    let scene = crate::scene::load_or_default(args.scene.as_deref())?;
    for w in &scene.warnings {
        log::warn!("{w}");
    }
    let script = match &args.script {
        Some(s) => script::parse(s)?,
        None => Vec::new(),
    };
    if let Some(p) = &args.screenshot {
        crate::imageio::FileFormat::from_path(p)?;
    }
    let event_loop = EventLoop::new().context("cannot open a window (is a display available?)")?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App {
        args,
        scene: Some(scene),
        script,
        viewer: None,
        result: None,
    };
    event_loop.run_app(&mut app)?;
    app.result.unwrap_or(Ok(ViewOutcome::default()))
}

struct App {
    args: ViewOptions,
    scene: Option<Scene>,
    script: Vec<(u64, Action)>,
    viewer: Option<Viewer>,
    result: Option<Result<ViewOutcome>>,
}

impl App {
    fn fail(&mut self, el: &ActiveEventLoop, e: anyhow::Error) {
        self.result = Some(Err(e));
        self.shutdown(el);
    }

    fn shutdown(&mut self, el: &ActiveEventLoop) {
        if let Some(v) = self.viewer.take() {
            let code = v.finish(&self.args);
            if self.result.is_none() {
                self.result = Some(code);
            }
        }
        el.exit();
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, el: &ActiveEventLoop) {
        if self.viewer.is_some() {
            return;
        }
        let Some(scene) = self.scene.take() else {
            return;
        };
        match Viewer::new(el, scene, &self.args, std::mem::take(&mut self.script)) {
            Ok(v) => self.viewer = Some(v),
            Err(e) => self.fail(el, e),
        }
    }

    fn window_event(&mut self, el: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(v) = &mut self.viewer else { return };
        let consumed = v.egui_state.on_window_event(&v.window, &event).consumed;
        match event {
            WindowEvent::CloseRequested => self.shutdown(el),
            WindowEvent::Resized(_) => v.swapchain_dirty = true,
            WindowEvent::RedrawRequested => match v.frame() {
                Ok(true) => {}
                Ok(false) => self.shutdown(el),
                Err(e) => self.fail(el, e),
            },
            WindowEvent::DroppedFile(path) => v.open_path(&path),
            WindowEvent::ModifiersChanged(m) => v.modifiers = m.state(),
            WindowEvent::KeyboardInput { event, .. }
                if !consumed && event.state == ElementState::Pressed && !event.repeat =>
            {
                if let Key::Named(NamedKey::Escape) = event.logical_key {
                    self.shutdown(el);
                    return;
                }
                v.key(&event.logical_key);
            }
            WindowEvent::MouseInput { state, button, .. } => {
                let pressed = state == ElementState::Pressed;
                if pressed && consumed {
                    return;
                }
                match button {
                    MouseButton::Left => v.drag.left = pressed,
                    MouseButton::Middle => v.drag.middle = pressed,
                    _ => {}
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                let p = (position.x as f32, position.y as f32);
                if let Some(last) = v.drag.last {
                    let (dx, dy) = (p.0 - last.0, p.1 - last.1);
                    let h = v.swapchain.extent.height.max(1) as f32;
                    let pan = v.drag.middle || (v.drag.left && v.modifiers.shift_key());
                    if pan {
                        v.orbit.pan(dx / h, dy / h);
                    } else if v.drag.left {
                        v.orbit.orbit(-dx * 0.3, dy * 0.3);
                    }
                }
                v.drag.last = Some(p);
            }
            WindowEvent::MouseWheel { delta, .. } if !consumed => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                v.orbit.zoom(steps);
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _el: &ActiveEventLoop) {
        if let Some(v) = &self.viewer {
            v.window.request_redraw();
        }
    }
}

#[derive(Default)]
struct Drag {
    left: bool,
    middle: bool,
    last: Option<(f32, f32)>,
}

/// One frame slot: what a frame in flight owns until its fence signals.
struct FrameSlot {
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    acquired: vk::Semaphore,
    timer: Option<GpuTimer>,
    submitted: bool,
    /// egui textures to free once this slot's frame has finished.
    free_textures: Vec<egui::TextureId>,
    /// Host time spent on the frame (UI, recording, submit, present).
    cpu_ms: f64,
    /// Wall time from this frame's start to the next frame's start (what a user sees).
    frame_ms: f64,
}

/// A screenshot being copied to the host.
struct Shot {
    path: PathBuf,
    buffer: Buffer,
    /// True: the swapchain image (8-bit, UI included); false: the HDR radiance.
    display: bool,
    extent: vk::Extent2D,
}

/// (mesh identity, shading, material index, (model, BRDF selectors), map bits) of an object.
type ObjectStructure = (
    usize,
    crate::scene::Shading,
    usize,
    (crate::brdf::ModelKind, crate::render::forward::TermsKey),
    u32,
);

/// What, when it changes, needs the passes rebuilt rather than new per-frame data.
#[derive(Debug, Clone, PartialEq)]
struct Structure {
    objects: Vec<ObjectStructure>,
    lights: usize,
    light_kinds: u32,
    fog: bool,
    saturation: crate::scene::Saturation,
    msaa: u32,
    debug: crate::render::forward::DebugView,
    environment: Option<crate::scene::Environment>,
}

impl Structure {
    fn of(scene: &Scene, settings: &ViewSettings) -> Self {
        Self {
            objects: scene
                .objects
                .iter()
                .map(|o| {
                    let m = &scene.materials[o.material];
                    (
                        Arc::as_ptr(&o.mesh) as usize,
                        o.shading,
                        o.material,
                        crate::render::gpu::material_key(&m.material),
                        crate::render::material::map_bits(&m.textures),
                    )
                })
                .collect(),
            lights: scene.lights.len(),
            light_kinds: crate::render::gpu::light_kinds(&scene.lights),
            fog: scene.fog.is_some(),
            saturation: scene.saturation,
            msaa: scene.output.msaa,
            debug: settings.debug_view,
            environment: scene.environment.clone(),
        }
    }
}

struct Viewer {
    // Dropped first: everything below outlives the GPU work these record.
    egui_renderer:
        Option<egui_ash_renderer::Renderer<egui_ash_renderer::allocator::DefaultAllocator>>,
    egui_state: egui_winit::State,
    egui_ctx: egui::Context,
    ui_state: UiState,
    settings: ViewSettings,
    profiler: Profiler,
    bench_frames: Vec<FrameSample>,
    display: DisplayPass,
    saturate: Option<SaturatePass>,
    forward: ForwardPass,
    ibl: Option<Ibl>,
    targets: HdrTarget,
    frames: Vec<FrameSlot>,
    pool: CommandPool,
    swapchain: Swapchain,
    surface: Surface,
    swapchain_dirty: bool,
    structure: Structure,
    /// The scene the current passes were built for ([`App::rebuild`]).
    built_scene: Scene,
    scene: Scene,
    initial_camera: OrbitCamera,
    orbit: OrbitCamera,
    render_options: RenderOptions,
    samples: vk::SampleCountFlags,
    script: Vec<(u64, Action)>,
    frame_limit: Option<u64>,
    bench: bool,
    warmup: u64,
    frame_index: u64,
    slot: usize,
    last_frame_start: Option<Instant>,
    pending_screenshot: Option<PathBuf>,
    status: Option<String>,
    modifiers: ModifiersState,
    drag: Drag,
    window: Window,
    ctx: Arc<Context>,
}

fn sample_flags(msaa: u32) -> vk::SampleCountFlags {
    vk::SampleCountFlags::from_raw(msaa.max(1))
}

impl Viewer {
    fn new(
        el: &ActiveEventLoop,
        scene: Scene,
        args: &ViewOptions,
        script: Vec<(u64, Action)>,
    ) -> Result<Self> {
        let width = args.width.unwrap_or(scene.output.width);
        let height = args.height.unwrap_or(scene.output.height);
        let title = match &scene.source {
            Some(p) => format!("luz — {}", p.display()),
            None => "luz — default scene".to_string(),
        };
        let window = el.create_window(
            Window::default_attributes()
                .with_title(title)
                .with_inner_size(PhysicalSize::new(width, height)),
        )?;
        let display = window.display_handle()?.as_raw();
        let required = ash_window::enumerate_required_extensions(display)?;
        // SAFETY: ash-window returns pointers to static, NUL-terminated extension names.
        let extensions = required
            .iter()
            .map(|&p| unsafe { std::ffi::CStr::from_ptr(p) })
            .collect();
        let ctx = Context::new(&ContextDesc {
            instance: InstanceDesc {
                validation: args.validate,
                sync_validation: args.sync_validation,
                extensions,
            },
            device_name: args.device.clone(),
            device_extensions: vec![ash::khr::swapchain::NAME],
        })?;
        log::info!("device: {}", ctx.info.summary());
        for line in crate::scene::tessellation::summary(&scene, false) {
            log::info!("{line}");
        }
        let surface_loader =
            ash::khr::surface::Instance::new(&ctx.instance.entry, &ctx.instance.raw);
        // SAFETY: the window outlives the surface (both owned by the viewer; the surface is
        // destroyed first in Drop).
        let surface = Surface {
            raw: unsafe {
                ash_window::create_surface(
                    &ctx.instance.entry,
                    &ctx.instance.raw,
                    display,
                    window.window_handle()?.as_raw(),
                    None,
                )?
            },
            loader: surface_loader,
        };
        let settings = ViewSettings {
            debug_view: Default::default(),
            vsync: !(args.no_vsync || args.bench),
            show_help: false,
            show_panels: !(args.no_panels || args.bench),
        };
        let size = window.inner_size();
        let swapchain = Swapchain::new(
            &ctx,
            &surface.loader,
            surface.raw,
            (size.width.max(1), size.height.max(1)),
            settings.vsync,
            vk::SwapchainKHR::null(),
        )?;
        let pool = CommandPool::new(&ctx, "viewer commands")?;
        let cmds = pool.allocate(FRAMES_IN_FLIGHT as u32)?;
        let mut frames = Vec::new();
        for (i, cmd) in cmds.into_iter().enumerate() {
            let fence = unsafe {
                ctx.device
                    .create_fence(&vk::FenceCreateInfo::default(), None)?
            };
            let acquired = unsafe {
                ctx.device
                    .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)?
            };
            ctx.set_name(fence, &format!("frame {i} fence"));
            ctx.set_name(acquired, &format!("frame {i} image acquired"));
            frames.push(FrameSlot {
                cmd,
                fence,
                acquired,
                timer: GpuTimer::new(&ctx, 8)?,
                submitted: false,
                free_textures: Vec::new(),
                cpu_ms: 0.0,
                frame_ms: 0.0,
            });
        }
        let render_options = RenderOptions {
            progress: args.progress.clone(),
            ..RenderOptions::new(args.ibl, args.no_cache, settings.debug_view)
        };
        let samples = sample_flags(scene.output.msaa);
        let extent = swapchain.extent;
        let targets = HdrTarget::new(&ctx, "viewer", nonzero(extent), samples)?;
        let ibl = match &scene.environment {
            Some(env) => Some(build_ibl(
                &ctx,
                &pool,
                &scene,
                env,
                &render_options.ibl,
                render_options.cache_dir.as_deref(),
                render_options.progress.as_deref(),
            )?),
            None => None,
        };
        let forward = make_forward(
            &ctx,
            &pool,
            &scene,
            samples,
            ibl.as_ref(),
            &settings,
            extent,
        )?;
        let saturate = SaturatePass::for_scene(&ctx, &scene, &targets.color)?;
        let display = DisplayPass::new(&ctx, targets.color.view, vk::ImageLayout::GENERAL)?;
        let egui_ctx = egui::Context::default();
        let egui_state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            None,
            Some(ctx.info.limits.max_image_dimension2_d as usize),
        );
        let egui_renderer = egui_ash_renderer::Renderer::with_default_allocator(
            &ctx.instance.raw,
            ctx.physical,
            ctx.device.clone(),
            egui_ash_renderer::RenderMode::DynamicRendering(egui_ash_renderer::DynamicRendering {
                color_attachment_format: swapchain.format,
                depth_attachment_format: None,
                stencil_attachment_format: None,
            }),
            egui_ash_renderer::Options {
                in_flight_frames: FRAMES_IN_FLIGHT,
                srgb_framebuffer: false,
                ..Default::default()
            },
        )
        .map_err(|e| anyhow!("egui renderer: {e}"))?;
        let orbit = OrbitCamera::from_camera(&scene.camera);
        let structure = Structure::of(&scene, &settings);
        Ok(Self {
            egui_renderer: Some(egui_renderer),
            egui_state,
            egui_ctx,
            ui_state: UiState::default(),
            settings,
            profiler: Profiler::new(PROFILER_WINDOW),
            bench_frames: Vec::new(),
            display,
            saturate,
            forward,
            ibl,
            targets,
            frames,
            pool,
            swapchain,
            surface,
            swapchain_dirty: false,
            structure,
            built_scene: scene.clone(),
            scene,
            initial_camera: orbit,
            orbit,
            render_options,
            samples,
            script,
            frame_limit: args.frames.or(if args.bench { Some(300) } else { None }),
            bench: args.bench,
            warmup: args.warmup,
            frame_index: 0,
            slot: 0,
            last_frame_start: None,
            pending_screenshot: None,
            status: None,
            modifiers: ModifiersState::empty(),
            drag: Drag::default(),
            window,
            ctx,
        })
    }

    fn key(&mut self, key: &Key) {
        let shift = self.modifiers.shift_key();
        match key {
            Key::Named(NamedKey::Tab) => self.settings.show_panels = !self.settings.show_panels,
            Key::Named(NamedKey::F1) => self.settings.show_help = !self.settings.show_help,
            Key::Character(c) => match c.to_lowercase().as_str() {
                "r" => self.orbit = self.initial_camera,
                "f" => self.frame_all(),
                "h" => self.settings.show_help = !self.settings.show_help,
                "v" => {
                    self.settings.vsync = !self.settings.vsync;
                    self.swapchain_dirty = true;
                }
                "p" => self.pending_screenshot = Some(screenshot_name(shift)),
                _ => {}
            },
            _ => {}
        }
    }

    fn frame_all(&mut self) {
        if let Some(b) = self.scene.bounds() {
            self.orbit.frame(b);
        }
    }

    /// Opens a dropped or typed path: a scene, an OBJ model or an environment image.
    fn open_path(&mut self, path: &Path) {
        match self.try_open(path) {
            Ok(msg) => {
                log::info!("{msg}");
                self.status = Some(msg);
            }
            Err(e) => {
                let msg = format!("{e:#}");
                log::error!("{msg}");
                self.status = Some(msg);
            }
        }
    }

    fn try_open(&mut self, path: &Path) -> Result<String> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        match ext.as_str() {
            "json" => {
                let scene = crate::scene::load(path)?;
                self.replace_scene(scene, true)?;
                Ok(format!("opened {}", path.display()))
            }
            "obj" => {
                let abs = std::fs::canonicalize(path)
                    .with_context(|| format!("cannot open {}", path.display()))?;
                let text = serde_json::json!({
                    "objects": [{ "name": abs.file_stem().and_then(|s| s.to_str()).unwrap_or("model"),
                                  "mesh": { "type": "obj", "path": abs } }]
                })
                .to_string();
                let mut scene = crate::scene::parse(&text, &abs.with_extension("json"))?;
                scene.camera = self.scene.camera;
                scene.lights = self.scene.lights.clone();
                scene.ambient = self.scene.ambient;
                scene.environment = self.scene.environment.clone();
                scene.output = self.scene.output;
                scene.saturation = self.scene.saturation;
                self.replace_scene(scene, true)?;
                self.frame_all();
                Ok(format!("opened model {}", path.display()))
            }
            "hdr" | "exr" => {
                let mut scene = self.scene.clone();
                let mut env = scene.environment.clone().unwrap_or_else(|| {
                    crate::scene::Environment::new(crate::scene::EnvSource::Uniform(
                        glam::Vec3::ONE,
                    ))
                });
                env.source = crate::scene::EnvSource::Hdr(path.to_path_buf());
                scene.environment = Some(env);
                self.replace_scene(scene, false)?;
                Ok(format!("environment {}", path.display()))
            }
            _ => Err(anyhow!(
                "{}: luz opens .json scenes, .obj models and .hdr/.exr environments",
                path.display()
            )),
        }
    }

    /// Shows `scene` instead of the current one, rebuilding what its structure needs.
    fn replace_scene(&mut self, scene: Scene, new_camera: bool) -> Result<()> {
        let old = std::mem::replace(&mut self.scene, scene);
        if let Err(e) = self.rebuild(old.environment != self.scene.environment) {
            self.scene = old;
            self.rebuild(true)?;
            return Err(e);
        }
        if new_camera {
            self.initial_camera = OrbitCamera::from_camera(&self.scene.camera);
            self.orbit = self.initial_camera;
        }
        Ok(())
    }

    /// Rebuilds the passes for the current scene (and the IBL data when `environment` changed).
    /// All or nothing: everything new is built before anything old is replaced, so a failure
    /// (say, an environment file that does not load) leaves the previous passes intact.
    fn rebuild(&mut self, environment: bool) -> Result<()> {
        unsafe { self.ctx.device.device_wait_idle()? };
        let ibl = if environment {
            Some(match &self.scene.environment {
                Some(env) => Some(build_ibl(
                    &self.ctx,
                    &self.pool,
                    &self.scene,
                    env,
                    &self.render_options.ibl,
                    self.render_options.cache_dir.as_deref(),
                    self.render_options.progress.as_deref(),
                )?),
                None => None,
            })
        } else {
            None
        };
        let samples = sample_flags(self.scene.output.msaa);
        let targets = if samples != self.samples {
            Some(HdrTarget::new(
                &self.ctx,
                "viewer",
                nonzero(self.swapchain.extent),
                samples,
            )?)
        } else {
            None
        };
        self.scene.camera = self.orbit.to_camera();
        let forward = make_forward(
            &self.ctx,
            &self.pool,
            &self.scene,
            samples,
            match &ibl {
                Some(new) => new.as_ref(),
                None => self.ibl.as_ref(),
            },
            &self.settings,
            self.swapchain.extent,
        )?;
        let color = targets.as_ref().unwrap_or(&self.targets);
        let saturate = SaturatePass::for_scene(&self.ctx, &self.scene, &color.color)?;
        // Everything is built: replace (the old passes are dropped after the new ones exist).
        self.forward = forward;
        self.saturate = saturate;
        if let Some(ibl) = ibl {
            self.ibl = ibl;
        }
        if let Some(t) = targets {
            self.targets = t;
            self.samples = samples;
            self.display.set_source(self.targets.color.view);
        }
        self.structure = Structure::of(&self.scene, &self.settings);
        self.built_scene = self.scene.clone();
        Ok(())
    }

    fn recreate_swapchain(&mut self) -> Result<()> {
        let size = self.window.inner_size();
        if size.width == 0 || size.height == 0 {
            return Ok(());
        }
        unsafe { self.ctx.device.device_wait_idle()? };
        let new = Swapchain::new(
            &self.ctx,
            &self.surface.loader,
            self.surface.raw,
            (size.width, size.height),
            self.settings.vsync,
            self.swapchain.raw,
        )?;
        let format_changed = new.format != self.swapchain.format;
        self.swapchain = new;
        if format_changed {
            if let Some(r) = &mut self.egui_renderer {
                r.set_render_mode(egui_ash_renderer::RenderMode::DynamicRendering(
                    egui_ash_renderer::DynamicRendering {
                        color_attachment_format: self.swapchain.format,
                        depth_attachment_format: None,
                        stencil_attachment_format: None,
                    },
                ))
                .map_err(|e| anyhow!("egui renderer: {e}"))?;
            }
        }
        let extent = nonzero(self.swapchain.extent);
        if extent != self.targets.color.extent() {
            self.targets = self.targets.resized(&self.ctx, extent)?;
            self.display.set_source(self.targets.color.view);
            self.saturate = SaturatePass::for_scene(&self.ctx, &self.scene, &self.targets.color)?;
        }
        self.swapchain_dirty = false;
        Ok(())
    }

    fn run_script(&mut self) -> Result<()> {
        while let Some((f, _)) = self.script.first() {
            if *f > self.frame_index {
                break;
            }
            let (_, action) = self.script.remove(0);
            match action {
                Action::Resize(w, h) => {
                    let _ = self
                        .window
                        .request_inner_size(PhysicalSize::new(w.max(1), h.max(1)));
                }
                Action::Minimize => self.window.set_minimized(true),
                Action::Restore => self.window.set_minimized(false),
                Action::Exposure(e) => self.scene.output.exposure = e,
                Action::Tonemap(t) => self.scene.output.tonemap = t,
                Action::Panels(on) => self.settings.show_panels = on,
                Action::Help(on) => self.settings.show_help = on,
                Action::Orbit(dx, dy) => self.orbit.orbit(dx, dy),
                Action::Zoom(s) => self.orbit.zoom(s),
                Action::FrameAll => self.frame_all(),
                Action::Reset => self.orbit = self.initial_camera,
                Action::Vsync(on) => {
                    self.settings.vsync = on;
                    self.swapchain_dirty = true;
                }
                Action::DebugView(d) => self.settings.debug_view = d,
                Action::Screenshot(p) => self.pending_screenshot = Some(p),
                Action::Open(p) => self.open_path(&p),
                Action::Save(p) => self.apply_actions(vec![UiAction::Save(p)])?,
            }
        }
        Ok(())
    }

    /// Draws one frame; false when `--frames` are done.
    fn frame(&mut self) -> Result<bool> {
        self.run_script()?;
        if self.swapchain_dirty {
            self.recreate_swapchain()?;
        }
        let size = self.window.inner_size();
        let minimized =
            size.width == 0 || size.height == 0 || self.window.is_minimized() == Some(true);
        if minimized {
            // Nothing to present to; count the frame so scripts and --frames still advance.
            std::thread::sleep(std::time::Duration::from_millis(5));
            self.frame_index += 1;
            return Ok(!self.done());
        }
        let start = Instant::now();
        let d = self.ctx.device.clone();
        let slot = self.slot;
        let previous = (slot + FRAMES_IN_FLIGHT - 1) % FRAMES_IN_FLIGHT;
        if let Some(last) = self.last_frame_start {
            self.frames[previous].frame_ms = (start - last).as_secs_f64() * 1e3;
        }
        self.last_frame_start = Some(start);
        // 1. This slot's previous frame: wait, read its timestamps, free its egui textures.
        {
            let f = &mut self.frames[slot];
            if f.submitted {
                unsafe { d.wait_for_fences(&[f.fence], true, u64::MAX)? };
                unsafe { d.reset_fences(&[f.fence])? };
                f.submitted = false;
                let gpu_ms = match &f.timer {
                    Some(t) => t.read()?,
                    None => Vec::new(),
                };
                let sample = FrameSample {
                    frame_ms: f.frame_ms,
                    cpu_ms: f.cpu_ms,
                    gpu_ms,
                };
                if self.bench {
                    self.bench_frames.push(sample.clone());
                }
                self.profiler.push(sample);
                if let Some(r) = &mut self.egui_renderer {
                    for id in std::mem::take(&mut f.free_textures) {
                        r.free_texture(id).map_err(|e| anyhow!("egui: {e}"))?;
                    }
                }
            }
        }
        // 2. Acquire.
        let acquired = self.frames[slot].acquired;
        let image_index = match unsafe {
            self.swapchain.loader.acquire_next_image(
                self.swapchain.raw,
                u64::MAX,
                acquired,
                vk::Fence::null(),
            )
        } {
            Ok((i, suboptimal)) => {
                if suboptimal {
                    self.swapchain_dirty = true;
                }
                i
            }
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => {
                self.swapchain_dirty = true;
                return Ok(true);
            }
            Err(e) => return Err(e.into()),
        };
        // 3. UI.
        let raw = self.egui_state.take_egui_input(&self.window);
        let mut actions = Vec::new();
        let output = {
            let (scene, settings, profiler, state) = (
                &mut self.scene,
                &mut self.settings,
                &self.profiler,
                &mut self.ui_state,
            );
            let status = &self.status;
            self.egui_ctx.run_ui(raw, |ui| {
                if let Some(s) = status {
                    egui::Panel::bottom("status").show(ui, |ui| {
                        ui.label(s.as_str());
                    });
                }
                actions = ui::draw(ui, scene, settings, profiler, state);
            })
        };
        self.egui_state
            .handle_platform_output(&self.window, output.platform_output);
        let primitives = self
            .egui_ctx
            .tessellate(output.shapes, output.pixels_per_point);
        self.apply_actions(actions)?;
        if Structure::of(&self.scene, &self.settings) != self.structure {
            let env = self.structure.environment != self.scene.environment;
            if let Err(e) = self.rebuild(env) {
                // The passes still fit the last scene that built: go back to it, so the next
                // frame's update matches them.
                self.scene = self.built_scene.clone();
                self.status = Some(format!("{e:#} (the edit was undone)"));
                log::error!("{e:#} (the edit was undone)");
            }
        }
        if let Some(r) = &mut self.egui_renderer {
            for (id, deltas) in &output.textures_delta.set {
                for delta in deltas {
                    r.set_texture(self.ctx.queue, self.pool.raw, *id, delta)
                        .map_err(|e| anyhow!("egui: {e}"))?;
                }
            }
        }
        self.frames[slot]
            .free_textures
            .extend(output.textures_delta.free.iter().copied());

        self.display
            .prepare(self.scene.output.tonemap, self.swapchain.format)?;
        // 4. Per-frame data of this slot.
        self.scene.camera = self.orbit.to_camera();
        let extent = self.swapchain.extent;
        let aspect = extent.width as f32 / extent.height.max(1) as f32;
        self.forward.update(slot, &self.scene, aspect)?;

        // 5. Record.
        let cmd = self.frames[slot].cmd;
        unsafe {
            d.reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty())?;
            d.begin_command_buffer(
                cmd,
                &vk::CommandBufferBeginInfo::default()
                    .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
            )?;
        }
        let screenshot = self.pending_screenshot.take();
        let readback = self.record(cmd, slot, image_index, &primitives, screenshot.as_deref())?;
        unsafe { d.end_command_buffer(cmd)? };

        // 6. Submit and present.
        let waits = [vk::SemaphoreSubmitInfo::default()
            .semaphore(acquired)
            .stage_mask(vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT)];
        let render_finished = self.swapchain.render_finished[image_index as usize];
        let signals = [vk::SemaphoreSubmitInfo::default()
            .semaphore(render_finished)
            .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)];
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
        let submit = vk::SubmitInfo2::default()
            .wait_semaphore_infos(&waits)
            .command_buffer_infos(&cmds)
            .signal_semaphore_infos(&signals);
        unsafe { d.queue_submit2(self.ctx.queue, &[submit], self.frames[slot].fence)? };
        self.frames[slot].submitted = true;
        let swapchains = [self.swapchain.raw];
        let indices = [image_index];
        let wait = [render_finished];
        let present = vk::PresentInfoKHR::default()
            .wait_semaphores(&wait)
            .swapchains(&swapchains)
            .image_indices(&indices);
        match unsafe {
            self.swapchain
                .loader
                .queue_present(self.ctx.queue, &present)
        } {
            Ok(false) => {}
            Ok(true) | Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => self.swapchain_dirty = true,
            Err(e) => return Err(e.into()),
        }
        if let Some(shot) = readback {
            let f = &self.frames[slot];
            unsafe { d.wait_for_fences(&[f.fence], true, u64::MAX)? };
            self.save_screenshot(&shot)?;
        }
        self.frames[slot].cpu_ms = start.elapsed().as_secs_f64() * 1e3;
        self.slot = (slot + 1) % FRAMES_IN_FLIGHT;
        self.frame_index += 1;
        Ok(!self.done())
    }

    fn done(&self) -> bool {
        self.frame_limit.is_some_and(|n| self.frame_index >= n)
    }

    /// Records the frame's passes into `cmd`; returns the screenshot being copied, if any.
    fn record(
        &mut self,
        cmd: vk::CommandBuffer,
        slot: usize,
        image_index: u32,
        primitives: &[egui::ClippedPrimitive],
        screenshot: Option<&Path>,
    ) -> Result<Option<Shot>> {
        let d = self.ctx.device.clone();
        let mut timer = self.frames[slot].timer.take();
        if let Some(t) = &mut timer {
            t.reset(cmd);
        }
        let t = &self.targets;
        // The previous frame's last uses of the shared images come first on the queue: the
        // display pass's read and a screenshot's copy of the colour image.
        t.begin_frame(
            &d,
            cmd,
            FrameStart::AfterPrevious {
                color_read_stages: vk::PipelineStageFlags2::FRAGMENT_SHADER
                    | vk::PipelineStageFlags2::COPY,
            },
        );
        let views = t.views();
        let s = timer.as_mut().and_then(|t| t.begin(cmd, "forward"));
        self.forward.record_slot(cmd, &views, slot);
        if let Some(t) = &mut timer {
            t.end(cmd, s);
        }
        let mut last = COLOR_ATTACHMENT;
        if let Some(sat) = &self.saturate {
            let s = timer.as_mut().and_then(|t| t.begin(cmd, sat.name()));
            last = sat.record(cmd, last);
            if let Some(t) = &mut timer {
                t.end(cmd, s);
            }
        }
        let exr =
            screenshot.filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr")));
        let mut read = self.display.source_access();
        if exr.is_some() {
            read.1 |= vk::PipelineStageFlags2::COPY;
            read.2 |= vk::AccessFlags2::TRANSFER_READ;
        }
        // The swapchain image: written whole by the display pass, then the UI on top.
        let image = self.swapchain.images[image_index as usize];
        let attachment: Access = (
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::COLOR_ATTACHMENT_READ | vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
        );
        transition(
            &d,
            cmd,
            &[
                Transition {
                    image: t.color.raw,
                    range: t.color.subresource_range(),
                    from: last,
                    to: read,
                },
                Transition {
                    image,
                    range: color_range(),
                    // Chained to the acquire semaphore's wait at this stage.
                    from: (
                        vk::ImageLayout::UNDEFINED,
                        vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                        vk::AccessFlags2::NONE,
                    ),
                    to: attachment,
                },
            ],
        );
        let extent = t.color.extent();
        let mut shot = None;
        if let Some(path) = exr {
            let buffer = Buffer::new(
                &self.ctx,
                "screenshot (hdr)",
                extent.width as u64 * extent.height as u64 * 16,
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )?;
            copy_image_to_buffer(
                &d,
                cmd,
                t.color.raw,
                vk::ImageLayout::GENERAL,
                &buffer,
                extent,
            );
            shot = Some(Shot {
                path: path.to_path_buf(),
                buffer,
                display: false,
                extent,
            });
        }
        let sc = self.swapchain.extent;
        let colors = [vk::RenderingAttachmentInfo::default()
            .image_view(self.swapchain.views[image_index as usize])
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::DONT_CARE)
            .store_op(vk::AttachmentStoreOp::STORE)];
        let info = vk::RenderingInfo::default()
            .render_area(vk::Rect2D {
                offset: vk::Offset2D::default(),
                extent: sc,
            })
            .layer_count(1)
            .color_attachments(&colors);
        unsafe { d.cmd_begin_rendering(cmd, &info) };
        let s = timer.as_mut().and_then(|t| t.begin(cmd, "display"));
        let area = vk::Extent2D {
            width: extent.width.min(sc.width),
            height: extent.height.min(sc.height),
        };
        self.display.record(
            cmd,
            self.scene.output.tonemap,
            self.swapchain.format,
            self.scene.output.exposure,
            area,
        )?;
        if let Some(t) = &mut timer {
            t.end(cmd, s);
        }
        let s = timer.as_mut().and_then(|t| t.begin(cmd, "ui"));
        if let Some(r) = &mut self.egui_renderer {
            r.cmd_draw(cmd, sc, self.egui_ctx.pixels_per_point(), primitives)
                .map_err(|e| anyhow!("egui: {e}"))?;
        }
        unsafe { d.cmd_end_rendering(cmd) };
        let mut last = attachment;
        let png = screenshot.filter(|_| exr.is_none());
        if let Some(path) = png {
            if !self.swapchain.can_read {
                self.status =
                    Some("this window's images cannot be read back: no screenshot".into());
            } else {
                let src: Access = (
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    vk::PipelineStageFlags2::COPY,
                    vk::AccessFlags2::TRANSFER_READ,
                );
                transition(
                    &d,
                    cmd,
                    &[Transition {
                        image,
                        range: color_range(),
                        from: last,
                        to: src,
                    }],
                );
                last = src;
                let buffer = Buffer::new(
                    &self.ctx,
                    "screenshot (display)",
                    sc.width as u64 * sc.height as u64 * 4,
                    vk::BufferUsageFlags::TRANSFER_DST,
                    MemoryLocation::GpuToCpu,
                )?;
                copy_image_to_buffer(
                    &d,
                    cmd,
                    image,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    &buffer,
                    sc,
                );
                shot = Some(Shot {
                    path: path.to_path_buf(),
                    buffer,
                    display: true,
                    extent: sc,
                });
            }
        }
        transition(
            &d,
            cmd,
            &[Transition {
                image,
                range: color_range(),
                from: last,
                to: (
                    vk::ImageLayout::PRESENT_SRC_KHR,
                    vk::PipelineStageFlags2::NONE,
                    vk::AccessFlags2::NONE,
                ),
            }],
        );
        if let Some(t) = &mut timer {
            t.end(cmd, s);
        }
        if shot.is_some() {
            crate::vk::cmd::memory_barrier(
                &d,
                cmd,
                (
                    vk::PipelineStageFlags2::COPY,
                    vk::AccessFlags2::TRANSFER_WRITE,
                ),
                (vk::PipelineStageFlags2::HOST, vk::AccessFlags2::HOST_READ),
            );
        }
        self.frames[slot].timer = timer;
        Ok(shot)
    }

    fn save_screenshot(&mut self, shot: &Shot) -> Result<()> {
        let bytes = shot.buffer.mapped()?;
        let (w, h) = (shot.extent.width, shot.extent.height);
        let n = w as usize * h as usize;
        if shot.display {
            let bgra = self.swapchain.format == vk::Format::B8G8R8A8_UNORM;
            let rgb: Vec<u8> = bytes[..n * 4]
                .chunks_exact(4)
                .flat_map(|p| {
                    if bgra {
                        [p[2], p[1], p[0]]
                    } else {
                        [p[0], p[1], p[2]]
                    }
                })
                .collect();
            crate::imageio::save_png_rgb8(&shot.path, w, h, &rgb)?;
        } else {
            let floats: &[f32] = bytemuck::try_cast_slice(&bytes[..n * 16])
                .map_err(|e| anyhow!("screenshot buffer: {e}"))?;
            let img = LinearImage {
                width: w,
                height: h,
                pixels: floats
                    .chunks_exact(4)
                    .map(|c| [c[0], c[1], c[2], c[3]])
                    .collect(),
            };
            crate::imageio::save(&shot.path, &img, 0.0, crate::color::Tonemap::None)?;
        }
        let msg = format!("wrote {} ({w}x{h})", shot.path.display());
        log::info!("{msg}");
        self.status = Some(msg);
        Ok(())
    }

    /// Ends the session: the final screenshot, the benchmark report, validation's verdict.
    fn finish(mut self, args: &ViewOptions) -> Result<ViewOutcome> {
        unsafe { self.ctx.device.device_wait_idle()? };
        if let Some(path) = &args.screenshot {
            // One more frame, copied: what the window shows at the end.
            self.pending_screenshot = Some(path.clone());
            self.frame_limit = None;
            self.frame()?;
            unsafe { self.ctx.device.device_wait_idle()? };
        }
        if self.bench {
            self.report_bench(args)?;
        }
        let stats = self.profiler.stats();
        log::info!(
            "frames: {} shown, frame time p50 {:.2} ms, p95 {:.2} ms, p99 {:.2} ms, {} stutters (> 2x median)",
            self.frame_index, stats.p50, stats.p95, stats.p99, stats.stutters
        );
        let ctx = self.ctx.clone();
        drop(self);
        let log = ctx.validation_log();
        Ok(ViewOutcome {
            validation: ctx.instance.validation,
            validation_errors: log.errors(),
            validation_warnings: log.warnings(),
        })
    }

    fn report_bench(&self, args: &ViewOptions) -> Result<()> {
        let frames: Vec<&FrameSample> = self
            .bench_frames
            .iter()
            .skip(self.warmup as usize)
            .collect();
        if frames.is_empty() {
            return Err(anyhow!(
                "--bench: no frames after the {} warm-up frames; raise --frames",
                self.warmup
            ));
        }
        let frame_ms: Vec<f64> = frames.iter().map(|f| f.frame_ms).collect();
        let cpu_ms: Vec<f64> = frames.iter().map(|f| f.cpu_ms).collect();
        let summary = crate::stats::Summary::of(&frame_ms);
        let stutters = crate::profiler::stutter_count(&frame_ms);
        let extent = self.swapchain.extent;
        log::info!(
            "view --bench: {} frames at {}x{} ({} triangles, present mode {:?})",
            frames.len(),
            extent.width,
            extent.height,
            self.forward.triangle_count(),
            self.swapchain.present_mode
        );
        log::info!(
            "frame ms (wall, presenting): median {:.2}, p95 {:.2}, p99 {:.2}, max {:.2}; p99/p50 {:.3}; stutters {}",
            summary.median,
            summary.p95,
            summary.p99,
            summary.max,
            summary.p99 / summary.median,
            stutters
        );
        let mut names: Vec<&'static str> = Vec::new();
        for f in &frames {
            for (n, _) in &f.gpu_ms {
                if !names.contains(n) {
                    names.push(n);
                }
            }
        }
        let mut passes = serde_json::Map::new();
        for n in &names {
            let v: Vec<f64> = frames
                .iter()
                .filter_map(|f| f.gpu_ms.iter().find(|(m, _)| m == n).map(|(_, t)| *t))
                .collect();
            let s = crate::stats::Summary::of(&v);
            log::info!(
                "  GPU {n:<20} median {:8.3} ms  p95 {:8.3}  p99 {:8.3}",
                s.median,
                s.p95,
                s.p99
            );
            passes.insert(n.to_string(), serde_json::to_value(s)?);
        }
        if let Some(p) = &args.csv {
            let mut out = String::from("frame,frame_ms,cpu_ms");
            for n in &names {
                out.push_str(&format!(",gpu_{n}_ms"));
            }
            out.push('\n');
            for (i, f) in frames.iter().enumerate() {
                out.push_str(&format!("{i},{:.4},{:.4}", f.frame_ms, f.cpu_ms));
                for n in &names {
                    let t = f.gpu_ms.iter().find(|(m, _)| m == n).map(|(_, t)| *t);
                    out.push_str(&format!(",{:.4}", t.unwrap_or(f64::NAN)));
                }
                out.push('\n');
            }
            std::fs::write(p, out).with_context(|| format!("cannot write {}", p.display()))?;
            log::info!("wrote {}", p.display());
        }
        if let Some(p) = &args.json {
            let json = serde_json::json!({
                "device": self.ctx.info.summary(),
                "mode": "view --bench (windowed, presenting)",
                "present_mode": format!("{:?}", self.swapchain.present_mode),
                "frames": frames.len(),
                "warmup": self.warmup,
                "width": extent.width,
                "height": extent.height,
                "triangles": self.forward.triangle_count(),
                "frame_ms": summary,
                "p99_over_p50": summary.p99 / summary.median,
                "stutters": stutters,
                "cpu_ms": crate::stats::Summary::of(&cpu_ms),
                "gpu_pass_ms": passes,
            });
            std::fs::write(p, serde_json::to_string_pretty(&json)?)
                .with_context(|| format!("cannot write {}", p.display()))?;
            log::info!("wrote {}", p.display());
        }
        Ok(())
    }

    fn apply_actions(&mut self, actions: Vec<UiAction>) -> Result<()> {
        for a in actions {
            match a {
                UiAction::SceneEdited | UiAction::DebugViewChanged => {}
                UiAction::VsyncChanged => self.swapchain_dirty = true,
                UiAction::Save(p) => {
                    let msg = match crate::scene::save(&self.scene_with_camera(), &p) {
                        Ok(()) => {
                            let m = format!("saved {}", p.display());
                            log::info!("{m}");
                            m
                        }
                        Err(e) => {
                            let m = format!("{e:#}");
                            log::error!("{m}");
                            m
                        }
                    };
                    self.status = Some(msg);
                }
                UiAction::Open(p) | UiAction::OpenEnvironmentFile(p) => self.open_path(&p),
                UiAction::Screenshot { exr } => {
                    self.pending_screenshot = Some(screenshot_name(exr))
                }
                UiAction::ResetCamera => self.orbit = self.initial_camera,
                UiAction::FrameAll => self.frame_all(),
            }
        }
        Ok(())
    }

    fn scene_with_camera(&self) -> Scene {
        let mut s = self.scene.clone();
        s.camera = self.orbit.to_camera();
        s
    }
}

fn screenshot_name(exr: bool) -> PathBuf {
    let t = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs())
        .unwrap_or(0);
    PathBuf::from(format!("luz-{t}.{}", if exr { "exr" } else { "png" }))
}

fn nonzero(e: vk::Extent2D) -> vk::Extent2D {
    vk::Extent2D {
        width: e.width.max(1),
        height: e.height.max(1),
    }
}

fn make_forward(
    ctx: &Arc<Context>,
    pool: &CommandPool,
    scene: &Scene,
    samples: vk::SampleCountFlags,
    ibl: Option<&Ibl>,
    settings: &ViewSettings,
    extent: vk::Extent2D,
) -> Result<ForwardPass, VkError> {
    ForwardPass::in_flight(
        ctx,
        pool,
        scene,
        TargetFormat {
            color: COLOR_FORMAT,
            depth: DEPTH_FORMAT,
            samples,
        },
        extent.width as f32 / extent.height.max(1) as f32,
        ibl,
        crate::render::forward::PassOptions {
            debug: settings.debug_view,
            slots: FRAMES_IN_FLIGHT,
            generic: false,
        },
    )
}

impl Drop for Viewer {
    fn drop(&mut self) {
        unsafe {
            let _ = self.ctx.device.device_wait_idle();
        }
        // egui's buffers and textures first, while the device is alive.
        self.egui_renderer = None;
        unsafe {
            for f in &self.frames {
                self.ctx.device.destroy_fence(f.fence, None);
                self.ctx.device.destroy_semaphore(f.acquired, None);
            }
        }
        // Fields drop after this: the swapchain before its surface, the context last.
    }
}

/// The window surface, destroyed when dropped (after the swapchain, before the context).
struct Surface {
    loader: ash::khr::surface::Instance,
    raw: vk::SurfaceKHR,
}

impl Drop for Surface {
    fn drop(&mut self) {
        unsafe { self.loader.destroy_surface(self.raw, None) };
    }
}
