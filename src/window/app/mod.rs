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
use super::swapchain::Swapchain;
use super::ui::{self, UiAction, UiState, ViewSettings};
use super::{DisplayPath, ViewOptions, ViewOutcome};
use crate::graph::{Access, FrameGraph, ImageStateBefore, ImportedImage};
use crate::headless::{build_ibl, RenderOptions};
use crate::imageio::LinearImage;
use crate::prepare::PreparedScene;
use crate::profiler::{FrameSample, Profiler};
use crate::render::display::DisplayPass;
use crate::render::forward::{ForwardPass, Output, PassNames, TargetFormat};
use crate::render::frame::{add_readback, SceneTarget, Transients, HDR_DISPLAY_READ};
use crate::render::ibl::Ibl;
use crate::render::saturate::SaturatePass;
use crate::render::target::{HdrTarget, COLOR_FORMAT, DEPTH_FORMAT};
use crate::render::world::Change;
use crate::scene::Scene;
use crate::vk::cmd::CommandPool;
use crate::vk::timing::GpuTimer;
use crate::vk::{Buffer, Context, VkError};

/// Frames the CPU may record ahead of the GPU.
mod bench;
mod frame;
mod lab;
mod lod;
mod open;
mod shadow_view;

const FRAMES_IN_FLIGHT: usize = 2;
/// Frames kept by the profiler's rolling window.
const PROFILER_WINDOW: usize = 300;

pub fn run(args: ViewOptions) -> Result<ViewOutcome> {
    let mut scene = crate::scene::load_or_default(args.scene.as_deref())?;
    if let Some(n) = args.camera {
        crate::scene::model::use_camera(&mut scene, n)?;
    }
    for w in &scene.warnings {
        log::warn!("{w}");
    }
    let compare = match &args.compare {
        Some(p) => {
            let b = crate::scene::load(p)?;
            for w in &b.warnings {
                log::warn!("B: {w}");
            }
            Some(b)
        }
        None => None,
    };
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
        compare,
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
    /// Side B (`--compare`), until the viewer exists.
    compare: Option<Scene>,
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
        let made = Viewer::new(el, scene, &self.args, std::mem::take(&mut self.script)).and_then(
            |mut v| {
                if let Some(b) = self.compare.take() {
                    v.set_b(b)?;
                }
                Ok(v)
            },
        );
        match made {
            Ok(v) => self.viewer = Some(v),
            Err(e) => self.fail(el, e),
        }
    }

    fn window_event(&mut self, el: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(v) = &mut self.viewer else { return };
        let consumed = v.egui_state.on_window_event(&v.window, &event).consumed;
        // Input wakes a viewer waiting at rest: a few frames for the panels to answer; the cursor
        // only over a panel or while a button is held (a drag that moves the view).
        let wakes = match &event {
            WindowEvent::RedrawRequested => false,
            WindowEvent::CursorMoved { .. } => {
                v.drag.left || v.drag.middle || v.egui_ctx.is_pointer_over_egui()
            }
            _ => true,
        };
        if wakes {
            v.awake = AWAKE_FRAMES;
        }
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

    fn about_to_wait(&mut self, el: &ActiveEventLoop) {
        if let Some(v) = &mut self.viewer {
            if v.may_wait() {
                // The exact picture is on its way to the window: draw again on the next event,
                // with nothing in flight when the view starts to move; the idle gap is no frame
                // time.
                el.set_control_flow(ControlFlow::Wait);
                v.last_frame_start = None;
            } else {
                el.set_control_flow(ControlFlow::Poll);
                v.window.request_redraw();
            }
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
    /// The LOD budget and triangles the slot's frame drew with.
    lod: lod::FrameLod,
}

/// A screenshot being copied to the host.
struct Shot {
    path: PathBuf,
    buffer: Buffer,
    /// True: the swapchain image (8-bit, UI included); false: the HDR radiance.
    display: bool,
    extent: vk::Extent2D,
}

/// Frames an input event keeps the viewer drawing at rest (egui's hover and click feedback).
const AWAKE_FRAMES: u32 = 3;

struct Viewer {
    // Dropped first: everything below outlives the GPU work these record.
    egui_renderer:
        Option<egui_ash_renderer::Renderer<egui_ash_renderer::allocator::DefaultAllocator>>,
    egui_state: egui_winit::State,
    egui_ctx: egui::Context,
    ui_state: UiState,
    settings: ViewSettings,
    /// A/B comparison and the error view.
    lab: lab::Lab,
    /// This frame's read-backs for the lab (read after its fence).
    lab_copies: lab::Readbacks,
    /// The shadow-map window.
    shadow_view: shadow_view::ShadowView,
    profiler: Profiler,
    bench_frames: Vec<FrameSample>,
    /// Per entry of `bench_frames`: the LOD budget and triangles of that frame.
    bench_lod: Vec<lod::FrameLod>,
    /// The frame-time target's controller of the mesh LOD budget (`--target-ms`).
    lod_target: crate::window::lod_target::LodTarget,
    /// Set by whatever changes the picture besides the camera and the window size (edits,
    /// scripted actions, rebuilds): the target's "the view changed".
    view_changed: bool,
    /// The camera and window size of the last frame.
    last_view: Option<(crate::scene::Camera, vk::Extent2D)>,
    /// Degrees the camera orbits every frame (`--turntable`).
    turntable: Option<f32>,
    display: DisplayPass,
    saturate: Option<SaturatePass>,
    forward: ForwardPass,
    /// The scene's LOD chains, kept so a rebuild after an edit builds or reads only the chains
    /// of meshes the edit brought ([`crate::prepare::prepare_again`]).
    prepared: PreparedScene,
    ibl: Option<Ibl>,
    targets: HdrTarget,
    /// The frame graph's one-frame images (depth, MSAA colour), pooled across frames.
    transients: Transients,
    frames: Vec<FrameSlot>,
    pool: CommandPool,
    swapchain: Swapchain,
    surface: Surface,
    swapchain_dirty: bool,
    /// The scene the current passes were built for ([`App::rebuild`]).
    built_scene: Scene,
    scene: Scene,
    initial_camera: OrbitCamera,
    orbit: OrbitCamera,
    render_options: RenderOptions,
    samples: vk::SampleCountFlags,
    display_path: DisplayPath,
    render_path: crate::render::forward::RenderPath,
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
    /// Frames to draw after an input event before the viewer may wait at rest.
    awake: u32,
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
        let mut desc = args.gpu.clone();
        // SAFETY: ash-window returns pointers to static, NUL-terminated extension names.
        let extensions = required
            .iter()
            .map(|&p| unsafe { std::ffi::CStr::from_ptr(p) });
        desc.instance.extensions.extend(extensions);
        desc.device_extensions.push(ash::khr::swapchain::NAME);
        let ctx = Context::new(&desc)?;
        log::info!("device: {}", ctx.info.summary());
        for line in crate::scene::tessellation::summary(&scene, false) {
            log::info!("{line}");
        }
        let surface_loader =
            ash::khr::surface::Instance::new(&ctx.instance.entry, &ctx.instance.raw);
        let surface = Surface {
            // SAFETY: the window outlives the surface (both owned by the viewer; the surface is
            // destroyed first in Drop), and the handles come from that live window.
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
            shadow_maps: false,
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
            // SAFETY: `ctx.device` is live; the default create infos are valid; fences and semaphores are
            // destroyed in `Drop` after the device is idle.
            let fence = unsafe {
                ctx.device
                    .create_fence(&vk::FenceCreateInfo::default(), None)?
            };
            // SAFETY: as for the fence above.
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
                timer: GpuTimer::new(&ctx, 16)?,
                submitted: false,
                free_textures: Vec::new(),
                cpu_ms: 0.0,
                frame_ms: 0.0,
                lod: Default::default(),
            });
        }
        let render_options = RenderOptions {
            progress: args.progress.clone(),
            ..RenderOptions::new(args.ibl, args.no_cache, settings.debug_view)
        };
        let samples = sample_flags(scene.output.msaa);
        let extent = swapchain.extent;
        let targets = HdrTarget::new("viewer", nonzero(extent), samples);
        let ibl = scene_ibl(&ctx, &pool, &scene, &render_options)?;
        let (forward, prepared) = make_forward(
            &ctx,
            &pool,
            (&scene, None),
            samples,
            ibl.as_ref(),
            extent,
            pass_options(
                &settings,
                (
                    frame::preferred_output(&scene, args.display_path, samples, swapchain.format),
                    args.render_path,
                ),
            ),
        )?;
        let saturate = SaturatePass::for_scene(&ctx, &scene)?;
        let display = DisplayPass::new(&ctx, vk::ImageLayout::GENERAL)?;
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
        Ok(Self {
            egui_renderer: Some(egui_renderer),
            egui_state,
            egui_ctx,
            ui_state: UiState::default(),
            settings,
            lab: lab::Lab::default(),
            lab_copies: lab::Readbacks::default(),
            shadow_view: Default::default(),
            profiler: Profiler::new(PROFILER_WINDOW),
            bench_frames: Vec::new(),
            bench_lod: Vec::new(),
            lod_target: crate::window::lod_target::LodTarget::new(
                args.target_ms,
                scene.output.tessellation_error_px,
            ),
            view_changed: true,
            last_view: None,
            turntable: args.turntable.filter(|d| *d != 0.0),
            display,
            saturate,
            forward,
            prepared,
            ibl,
            targets,
            transients: Transients::new(&ctx),
            frames,
            pool,
            swapchain,
            surface,
            swapchain_dirty: false,
            built_scene: scene.clone(),
            scene,
            initial_camera: orbit,
            orbit,
            render_options,
            samples,
            display_path: args.display_path,
            render_path: args.render_path,
            script,
            frame_limit: args.frames.or(if args.bench { Some(300) } else { None }),
            bench: args.bench,
            warmup: args.warmup,
            frame_index: 0,
            slot: 0,
            last_frame_start: None,
            awake: AWAKE_FRAMES,
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
                "b" => self.lab.settings.show_b = !self.lab.settings.show_b,
                "l" => self.lab.settings.open = !self.lab.settings.open,
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
                UiAction::ToggleLab => self.lab.settings.open = !self.lab.settings.open,
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

/// The image-based lighting of `scene`'s environment with `options`' sizes, cache and progress;
/// `None` without an environment.
fn scene_ibl(
    ctx: &Arc<Context>,
    pool: &CommandPool,
    scene: &Scene,
    options: &RenderOptions,
) -> Result<Option<Ibl>, VkError> {
    let Some(env) = &scene.environment else {
        return Ok(None);
    };
    let ibl = build_ibl(
        ctx,
        pool,
        scene,
        env,
        &options.ibl,
        options.cache_dir.as_deref(),
        options.progress.as_deref(),
    )?;
    Ok(Some(ibl))
}

fn make_forward(
    ctx: &Arc<Context>,
    pool: &CommandPool,
    (scene, reuse): (&Scene, Option<PreparedScene>),
    samples: vk::SampleCountFlags,
    ibl: Option<&Ibl>,
    extent: vk::Extent2D,
    options: crate::render::forward::PassOptions,
) -> Result<(ForwardPass, PreparedScene), VkError> {
    let mut prepared =
        crate::render::forward::prepare_for(ctx, scene, (options.lod_cache.clone(), None), reuse)?;
    let pass = ForwardPass::prepared(
        ctx,
        pool,
        (scene, &prepared),
        TargetFormat {
            color: COLOR_FORMAT,
            depth: DEPTH_FORMAT,
            samples,
        },
        extent.width as f32 / extent.height.max(1) as f32,
        ibl,
        options,
    )?;
    // The maps are on the GPU now: no second copy stays in memory.
    prepared.forget_textures();
    Ok((pass, prepared))
}

/// The viewer's forward-pass options: its debug view, one slot per frame in flight, specialised
/// pipelines, drawing `output` along `path`.
fn pass_options(
    settings: &ViewSettings,
    (output, path): (Output, crate::render::forward::RenderPath),
) -> crate::render::forward::PassOptions {
    crate::render::forward::PassOptions {
        debug: settings.debug_view,
        slots: FRAMES_IN_FLIGHT,
        generic: false,
        output,
        path,
        light_loop: Default::default(),
        lod_cache: crate::render::ibl::default_cache_dir(),
        switches: Default::default(),
    }
}

impl Drop for Viewer {
    fn drop(&mut self) {
        // SAFETY: the device is live; waiting for idle is the precondition of destroying what follows.
        unsafe {
            let _ = self.ctx.device.device_wait_idle();
        }
        // egui's buffers and textures first, while the device is alive.
        self.egui_renderer = None;
        // SAFETY: the device is idle (above), so no submission uses these fences and semaphores; each
        // was created from this device and is destroyed once.
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
        // SAFETY: the swapchain built on this surface was dropped before it (field order), and the
        // surface was created from this instance and is destroyed once.
        unsafe { self.loader.destroy_surface(self.raw, None) };
    }
}
