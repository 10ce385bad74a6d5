//! Offscreen rendering: an HDR float colour target plus depth, the passes of a scene, GPU timestamps,
//! and readback of the linear radiance to the host.

use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::imageio::LinearImage;
use crate::prepare::PreparedScene;
use crate::render::forward::{prepare_for, DebugView, ForwardPass, Output, PassNames};
use crate::render::frame::{add_readback, SceneTarget, Transients};
use crate::render::ibl::{EquirectView, Ibl, IblInputs, IblSettings, IblTimes};
use crate::render::saturate::SaturatePass;
use crate::render::target::HdrTarget;
use crate::render::world::Change;
use crate::scene::Scene;
use crate::stats::Summary;
use crate::vk::cmd::CommandPool;
use crate::vk::timing::GpuTimer;
use crate::vk::{Buffer, Context, VkError};
use luz_graph::FrameGraph;

/// The split-sum LUT read back: (geometry selector BRDF_G_*, texels) per layer.
pub type LutLayers = Vec<(i32, Vec<[f32; 4]>)>;

pub use crate::render::target::{COLOR_FORMAT, DEPTH_FORMAT};

/// How to render, beyond what the scene says.
#[derive(Debug, Clone, Default)]
pub struct RenderOptions {
    /// Sizes of the image-based lighting data.
    pub ibl: IblSettings,
    /// Keep precomputed IBL data here between runs (`render::ibl::default_cache_dir`).
    pub cache_dir: Option<std::path::PathBuf>,
    /// Show one quantity instead of the shaded radiance.
    pub debug_view: DebugView,
    /// "All features" pipelines instead of ones specialised to the scene (see
    /// [`crate::render::forward::PassOptions::generic`]).
    pub generic_pipelines: bool,
    /// Told the progress of the IBL precomputation (the binary draws a bar).
    pub progress: Option<crate::progress::ProgressSink>,
    /// Deferred lighting where the scene allows it, or always forward.
    pub render_path: crate::render::forward::RenderPath,
    /// Plain or clustered light loop (or chosen from the scene's lights).
    pub light_loop: crate::render::forward::LightLoop,
    /// What a measurement or a comparison turns off (all on by default; recorded in provenance
    /// by [`crate::provenance::add_switches`]).
    pub switches: crate::render::forward::Switches,
}

impl RenderOptions {
    /// The options most commands want: IBL sizes, the default cache unless `no_cache`, a debug
    /// view.
    pub fn new(ibl: IblSettings, no_cache: bool, debug_view: DebugView) -> Self {
        Self {
            ibl,
            cache_dir: if no_cache {
                None
            } else {
                crate::render::ibl::default_cache_dir()
            },
            debug_view,
            generic_pipelines: false,
            progress: None,
            render_path: Default::default(),
            light_loop: Default::default(),
            switches: Default::default(),
        }
    }

    fn pass_options(&self) -> crate::render::forward::PassOptions {
        crate::render::forward::PassOptions {
            debug: self.debug_view,
            slots: 1,
            generic: self.generic_pipelines,
            output: crate::render::forward::Output::Hdr,
            path: self.render_path,
            light_loop: self.light_loop,
            lod_cache: self.cache_dir.clone(),
            switches: self.switches,
        }
    }
}

/// Timings of one frame.
#[derive(Debug, Clone, Default)]
pub struct FrameTimes {
    /// (pass, GPU milliseconds) in recording order; empty when the device has no timestamps.
    pub gpu_ms: Vec<(&'static str, f64)>,
    /// Wall time of recording, submitting and waiting for the frame.
    pub cpu_ms: f64,
    /// Of `cpu_ms`, the time spent declaring, compiling and recording the frame graph (the rest
    /// is the submission and the wait for the GPU).
    pub record_ms: f64,
}

impl FrameTimes {
    pub fn gpu_total(&self) -> f64 {
        self.gpu_ms.iter().map(|(_, t)| t).sum()
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
}

/// The 8-bit UNORM format [`Headless::render_display`] writes.
pub const DISPLAY_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;

pub struct Headless {
    forward: ForwardPass,
    /// The frame's one-frame images (depth, MSAA colour, the display output's 8-bit target),
    /// pooled across frames.
    transients: Transients,
    /// The scene's LOD chains, kept for the next [`Headless::apply`] (its maps are dropped once
    /// uploaded).
    prepared: PreparedScene,
    /// The last frame's graph.
    plan: Option<luz_graph::Plan>,
    /// What the last frame wrote into the readback buffer.
    last_output: Output,
    ibl: Option<Ibl>,
    saturate: Option<SaturatePass>,
    timer: Option<GpuTimer>,
    readback: Buffer,
    target: HdrTarget,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    pool: CommandPool,
    width: u32,
    height: u32,
    options: RenderOptions,
    ctx: Arc<Context>,
}

/// The sample count of `output.msaa`; an error names the scene file and the field, and lists
/// the counts the device supports as numbers.
fn sample_flags(ctx: &Context, scene: &Scene) -> Result<vk::SampleCountFlags, VkError> {
    let msaa = scene.output.msaa;
    let flags_of = |n: u32| match n {
        1 => Some(vk::SampleCountFlags::TYPE_1),
        2 => Some(vk::SampleCountFlags::TYPE_2),
        4 => Some(vk::SampleCountFlags::TYPE_4),
        8 => Some(vk::SampleCountFlags::TYPE_8),
        16 => Some(vk::SampleCountFlags::TYPE_16),
        _ => None,
    };
    let Some(flags) = flags_of(msaa) else {
        return Err(VkError::Setup(format!(
            "{}: output.msaa: {msaa} is not a power of two in 1..16",
            scene.display_name()
        )));
    };
    let limits = &ctx.info.limits;
    let supported = limits.framebuffer_color_sample_counts & limits.framebuffer_depth_sample_counts;
    if !supported.contains(flags) {
        let counts: Vec<String> = [1, 2, 4, 8, 16]
            .into_iter()
            .filter(|&n| flags_of(n).is_some_and(|f| supported.contains(f)))
            .map(|n| n.to_string())
            .collect();
        return Err(VkError::Setup(format!(
            "{}: output.msaa: {msaa} samples are not supported by {} (it supports {})",
            scene.display_name(),
            ctx.info.name,
            counts.join(", ")
        )));
    }
    Ok(flags)
}

impl Headless {
    /// Builds the target and the passes for `scene` at the scene's output size.
    pub fn new(ctx: &Arc<Context>, scene: &Scene) -> Result<Self, VkError> {
        Self::with_ibl_settings(ctx, scene, &IblSettings::default())
    }

    /// As [`Headless::new`], with explicit IBL precomputation sizes.
    pub fn with_ibl_settings(
        ctx: &Arc<Context>,
        scene: &Scene,
        ibl_settings: &IblSettings,
    ) -> Result<Self, VkError> {
        Self::with_options(
            ctx,
            scene,
            &RenderOptions {
                ibl: *ibl_settings,
                ..Default::default()
            },
        )
    }

    /// With every option: IBL sizes, the IBL cache, a debug view.
    pub fn with_options(
        ctx: &Arc<Context>,
        scene: &Scene,
        options: &RenderOptions,
    ) -> Result<Self, VkError> {
        let ibl_settings = &options.ibl;
        let cache_dir = options.cache_dir.as_deref();
        let (width, height) = (scene.output.width, scene.output.height);
        // The output size against the device, named after the scene's fields, before any target
        // is allocated: the readback holds 16 bytes per pixel, the colour target 16 per sample.
        let target_pixel = 16 * u64::from(scene.output.msaa.max(1));
        ctx.limits()
            .check_render_size(&scene.display_name(), width, height, target_pixel, 16)?;
        let samples = sample_flags(ctx, scene)?;
        // The pipelines of earlier runs on this device (saved when this renderer is dropped).
        if let Some(dir) = cache_dir {
            ctx.load_pipeline_cache(&dir.join(crate::vk::pipeline_cache::PIPELINE_CACHE_FILE));
        }
        let pool = CommandPool::new(ctx, "headless commands")?;
        let target = HdrTarget::new("headless", vk::Extent2D { width, height }, samples);
        let bytes = width as u64 * height as u64 * 16;
        let readback = Buffer::new(
            ctx,
            "readback",
            bytes,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        let aspect = width as f32 / height as f32;
        let ibl = match &scene.environment {
            Some(env) => Some(build_ibl(
                ctx,
                &pool,
                scene,
                env,
                ibl_settings,
                cache_dir,
                options.progress.as_deref(),
            )?),
            None => None,
        };
        let mut prepared = prepare_for(
            ctx,
            scene,
            (options.cache_dir.clone(), options.progress.as_deref()),
            None,
        )?;
        let forward = ForwardPass::prepared(
            ctx,
            &pool,
            (scene, &prepared),
            target.format(),
            aspect,
            ibl.as_ref(),
            options.pass_options(),
        )?;
        prepared.forget_textures();
        let saturate = SaturatePass::for_scene(ctx, scene)?;
        let timer = GpuTimer::new(ctx, 8)?;
        let cmd = pool.allocate(1)?[0];
        // SAFETY: `ctx.device` is a live device; the default create info is valid, and the fence is
        // destroyed in `Drop` after the device is idle.
        let fence = unsafe {
            ctx.device
                .create_fence(&vk::FenceCreateInfo::default(), None)
        }?;
        ctx.set_name(fence, "headless frame fence");
        Ok(Self {
            forward,
            prepared,
            transients: Transients::new(ctx),
            plan: None,
            last_output: Output::Hdr,
            ibl,
            saturate,
            timer,
            readback,
            target,
            cmd,
            fence,
            pool,
            width,
            height,
            options: options.clone(),
            ctx: ctx.clone(),
        })
    }

    /// Switches to another environment (or none) without restarting: the device, targets and
    /// meshes stay; the IBL data (from the cache when this environment was seen before) and the
    /// pipelines that depend on it are rebuilt. `scene` is the scene being shown; its own
    /// `environment` is ignored in favour of `environment`.
    pub fn set_environment(
        &mut self,
        scene: &Scene,
        environment: Option<crate::scene::Environment>,
    ) -> Result<(), VkError> {
        let mut scene = scene.clone();
        scene.environment = environment;
        // SAFETY: the device is live; waiting for idle has no preconditions beyond external
        // synchronisation of the queue, which only this thread submits to here.
        unsafe { self.ctx.device.device_wait_idle()? };
        let ibl = match &scene.environment {
            Some(env) => Some(build_ibl(
                &self.ctx,
                &self.pool,
                &scene,
                env,
                &self.options.ibl,
                self.options.cache_dir.as_deref(),
                self.options.progress.as_deref(),
            )?),
            None => None,
        };
        let forward = ForwardPass::in_flight(
            &self.ctx,
            &self.pool,
            &scene,
            self.target.format(),
            self.width as f32 / self.height as f32,
            ibl.as_ref(),
            self.options.pass_options(),
        )?;
        self.forward = forward;
        self.ibl = ibl;
        Ok(())
    }

    /// Wall-time of each IBL precomputation stage (empty without an environment).
    pub fn ibl_times(&self) -> Option<&IblTimes> {
        self.ibl.as_ref().map(|i| &i.times)
    }

    /// The split-sum BRDF LUT as computed on the GPU: (geometry selector, texels) per layer.
    pub fn lut(&self) -> Result<Option<LutLayers>, VkError> {
        let Some(ibl) = &self.ibl else {
            return Ok(None);
        };
        let layers = ibl.read_lut(&self.ctx, &self.pool)?;
        Ok(Some(
            ibl.lut_geometries().iter().copied().zip(layers).collect(),
        ))
    }

    /// Names of every pipeline variant built for the scene.
    pub fn variants(&self) -> Vec<String> {
        let mut v = self.forward.variants();
        if let Some(s) = &self.saturate {
            v.push(s.name().to_string());
        }
        v
    }

    pub fn triangle_count(&self) -> u64 {
        self.forward.triangle_count()
    }

    /// Objects drawn after frustum culling, and all objects with something to draw.
    pub fn drawn_objects(&self) -> (usize, usize) {
        self.forward.drawn_objects(0)
    }

    /// Triangles drawn into the shadow maps per frame (every layer; casters at their LOD levels).
    pub fn shadow_triangles_drawn(&self) -> u64 {
        self.forward.shadow_triangles_drawn(0)
    }

    /// Frames recorded with some shadow map layer drawn, and with every layer reused
    /// (unchanged), and the layers drawn over all frames.
    pub fn shadow_frames_drawn_reused(&self) -> (u64, u64, u64) {
        let m = self.forward.shadow_maps();
        let (drawn, reused) = m.frames_drawn_reused();
        (drawn, reused, m.layers_drawn())
    }

    /// Takes `scene`'s per-frame data for the next frames: camera, lights, object transforms,
    /// materials' values (what the viewer edits without rebuilding; the scene's structure —
    /// objects, meshes, models, shadow settings — must be the one the renderer was built for).
    pub fn update_scene(&mut self, scene: &Scene) -> Result<(), VkError> {
        let aspect = self.width as f32 / self.height as f32;
        self.forward.update(0, scene, aspect)
    }

    /// Takes an edited `scene` for the next frames and says what it cost
    /// ([`crate::render::world::Change`], answered by the shape the passes were built for):
    /// per-frame data in place, new pipelines, or a rebuild of the passes (and of the
    /// image-based lighting when the environment changed, and of the targets when the sample
    /// count did). The LOD chains of meshes the scene still uses are kept from the last build
    /// ([`crate::prepare::prepare_again`]). The output size must stay: a new size is a new `Headless`. On an error the
    /// renderer keeps drawing the scene it had.
    pub fn apply(&mut self, scene: &Scene) -> Result<Change, VkError> {
        if (scene.output.width, scene.output.height) != (self.width, self.height) {
            return Err(VkError::Setup(format!(
                "{}: output size {}×{} differs from the renderer's {}×{}; make a new renderer",
                scene.display_name(),
                scene.output.width,
                scene.output.height,
                self.width,
                self.height
            )));
        }
        let change = self
            .forward
            .shape()
            .change_to(scene, self.options.debug_view);
        if change == Change::InPlace {
            self.update_scene(scene)?;
            return Ok(change);
        }
        // SAFETY: the device is live and only this thread submits to its queue; afterwards
        // nothing the rebuild replaces is in use.
        unsafe { self.ctx.device.device_wait_idle()? };
        let ibl = match (change, &scene.environment) {
            (Change::Rebuild { environment: true }, Some(env)) => Some(Some(build_ibl(
                &self.ctx,
                &self.pool,
                scene,
                env,
                &self.options.ibl,
                self.options.cache_dir.as_deref(),
                self.options.progress.as_deref(),
            )?)),
            (Change::Rebuild { environment: true }, None) => Some(None),
            _ => None,
        };
        let samples = sample_flags(&self.ctx, scene)?;
        let target = (samples != self.target.samples()).then(|| {
            HdrTarget::new(
                "headless",
                vk::Extent2D {
                    width: self.width,
                    height: self.height,
                },
                samples,
            )
        });
        let mut prepared = prepare_for(
            &self.ctx,
            scene,
            (
                self.options.cache_dir.clone(),
                self.options.progress.as_deref(),
            ),
            Some(std::mem::take(&mut self.prepared)),
        )?;
        let forward = ForwardPass::prepared(
            &self.ctx,
            &self.pool,
            (scene, &prepared),
            target.as_ref().unwrap_or(&self.target).format(),
            self.width as f32 / self.height as f32,
            match &ibl {
                Some(new) => new.as_ref(),
                None => self.ibl.as_ref(),
            },
            self.options.pass_options(),
        )?;
        prepared.forget_textures();
        let saturate = SaturatePass::for_scene(&self.ctx, scene)?;
        // Everything is built: replace.
        self.forward = forward;
        self.prepared = prepared;
        self.saturate = saturate;
        if let Some(ibl) = ibl {
            self.ibl = ibl;
        }
        if let Some(t) = target {
            self.target = t;
        }
        Ok(change)
    }

    /// Draw calls per frame (an instanced draw counts once) and the objects they draw.
    pub fn draw_calls(&self) -> (usize, usize) {
        self.forward.draw_calls(0)
    }

    /// Triangles drawn per frame: the objects in view at their LOD levels.
    pub fn triangles_drawn(&self) -> u64 {
        self.forward.triangles_drawn(0)
    }

    /// The LOD level of each object with a simplified mesh (`scene`: the scene rendered).
    pub fn lod_choices(&self, scene: &Scene) -> Vec<crate::scene::lod::LodChoice> {
        self.forward.lod_choices(0, scene)
    }

    /// LOD chains built, read from the disk cache and failed when the pass was made.
    pub fn lod_stats(&self) -> crate::scene::lod::ChainStats {
        self.forward.lod_stats().clone()
    }

    /// What the receiver test left out: lookups compiled out of draws no shadow can reach, and
    /// draws with lookups only where shadows can fall on screen.
    pub fn shadow_receivers(&self) -> crate::render::forward::ReceiverStats {
        self.forward.shadow_receivers()
    }

    /// Per shadowed light: its maps, their memory and the casters drawn into each layer.
    pub fn shadow_maps(&self) -> Vec<crate::render::shadow::MapReport> {
        self.forward.shadow_maps().report()
    }

    /// Every shadow-map layer as the last frame drew it (distances from each layer's eye):
    /// [`crate::render::shadow::view`].
    pub fn shadow_map_layers(&self) -> Result<Vec<crate::render::shadow::MapLayer>, VkError> {
        self.forward.shadow_maps().read_layers(&self.pool)
    }

    /// Lights per cluster of the clustered light loop (`None`: the plain loop).
    pub fn cluster_stats(&self) -> Option<crate::render::forward::ClusterStats> {
        self.forward.cluster_stats()
    }

    /// "deferred" or "forward": how the scene is drawn ([`crate::render::forward::RenderPath`]).
    pub fn render_path(&self) -> &'static str {
        self.forward.render_path()
    }

    /// Renders one frame, copies it to the host-visible readback buffer and waits for it.
    pub fn render(&mut self) -> Result<FrameTimes, VkError> {
        self.render_frame(Output::Hdr)
    }

    /// The display output of this scene ([`Output::display_for`] into [`DISPLAY_FORMAT`]), or an
    /// error naming why the scene needs the float image first.
    pub fn display_output(&self, scene: &Scene) -> Result<Output, VkError> {
        if self.target.samples() != vk::SampleCountFlags::TYPE_1 {
            return Err(VkError::Setup(format!(
                "{}: output.msaa {} resolves radiance: the display output needs msaa 1",
                scene.display_name(),
                scene.output.msaa
            )));
        }
        Output::display_for(scene, DISPLAY_FORMAT).ok_or_else(|| {
            VkError::Setup(format!(
                "{}: saturation \"normalize\" needs the whole float image: no display output",
                scene.display_name()
            ))
        })
    }

    /// Renders one frame as the viewer's direct path does: exposure, tone map and sRGB encode in
    /// the forward pass's fragment shader, into an 8-bit target ([`Headless::display_codes`]
    /// reads it). `output` comes from [`Headless::display_output`].
    pub fn render_display(&mut self, output: Output) -> Result<FrameTimes, VkError> {
        if output == Output::Hdr {
            return Err(VkError::Setup(
                "render_display: the HDR output is what render() writes".into(),
            ));
        }
        self.render_frame(output)
    }

    fn render_frame(&mut self, output: Output) -> Result<FrameTimes, VkError> {
        let start = Instant::now();
        let d = self.ctx.device.clone();
        let cmd = self.cmd;
        self.forward.prepare(output)?;
        self.forward.prepare_extent(self.target.extent())?;
        // SAFETY: `cmd` was allocated from `self.pool` (created with RESET_COMMAND_BUFFER) and is
        // not pending: the previous `render` waited for its fence before returning.
        unsafe { crate::vk::cmd::restart(&d, cmd) }?;
        if let Some(t) = &mut self.timer {
            t.reset(cmd);
        }
        let graph = frame_graph(
            (&self.forward, self.saturate.as_ref()),
            (&self.target, &self.readback),
            output,
        )?;
        self.plan = Some(graph.plan().clone());
        self.transients
            .execute(&self.ctx, graph, cmd, self.timer.as_mut())?;
        // SAFETY: `cmd` is in the recording state (begun above) and no render pass is open.
        unsafe { d.end_command_buffer(cmd)? };
        let record_ms = start.elapsed().as_secs_f64() * 1e3;

        let cmd_infos = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
        let submit = vk::SubmitInfo2::default().command_buffer_infos(&cmd_infos);
        {
            let _q = self
                .ctx
                .queue_lock
                .lock()
                .unwrap_or_else(|p| p.into_inner());
            // SAFETY: `cmd` is executable (ended above), `self.fence` is unsignalled (reset after
            // the last wait), and the queue is externally synchronised by `queue_lock`.
            unsafe { d.queue_submit2(self.ctx.queue, &[submit], self.fence)? };
        }
        // SAFETY: the fence belongs to this device and was just submitted with the frame;
        // resetting it after the wait leaves no queue operation referring to it.
        unsafe {
            d.wait_for_fences(&[self.fence], true, u64::MAX)?;
            d.reset_fences(&[self.fence])?;
        }
        self.last_output = output;
        let cpu_ms = start.elapsed().as_secs_f64() * 1e3;
        let gpu_ms = match &self.timer {
            Some(t) => t.read()?,
            None => Vec::new(),
        };
        Ok(FrameTimes {
            gpu_ms,
            cpu_ms,
            record_ms,
        })
    }

    /// The graph of the last frame rendered (passes, resources, barriers), for `--graph`.
    pub fn last_graph(&self) -> Option<&luz_graph::Plan> {
        self.plan.as_ref()
    }

    /// The last frame of [`Headless::render_display`]: RGBA8 display codes, row by row.
    pub fn display_codes(&self) -> Result<Vec<u8>, VkError> {
        if self.last_output == Output::Hdr {
            return Err(VkError::Setup(
                "display_codes: the last frame was rendered by render(), not render_display()"
                    .into(),
            ));
        }
        let n = self.width as usize * self.height as usize;
        Ok(self.readback.mapped()?[..n * 4].to_vec())
    }

    /// The last rendered frame as linear RGBA radiance.
    pub fn image(&self) -> Result<LinearImage, VkError> {
        if self.last_output != Output::Hdr {
            return Err(VkError::Setup(
                "image: the last frame was rendered by render_display(), not render()".into(),
            ));
        }
        let bytes = self.readback.mapped()?;
        let n = self.width as usize * self.height as usize;
        let floats: &[f32] = bytemuck::try_cast_slice(&bytes[..n * 16])
            .map_err(|e| VkError::Setup(format!("readback buffer is misaligned: {e}")))?;
        let pixels = floats
            .chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]])
            .collect();
        Ok(LinearImage {
            width: self.width,
            height: self.height,
            pixels,
        })
    }
}

impl Drop for Headless {
    fn drop(&mut self) {
        // SAFETY: after the device is idle no submission uses the fence, which was created from
        // this device and is destroyed exactly once.
        unsafe {
            let _ = self.ctx.device.device_wait_idle();
            self.ctx.device.destroy_fence(self.fence, None);
        }
        // The remaining fields free themselves; the command pool frees `cmd`.
        let _ = &self.pool;
        // The end of a run: keep the pipelines compiled in it for the next one.
        if let Some(dir) = &self.options.cache_dir {
            self.ctx
                .save_pipeline_cache(&dir.join(crate::vk::pipeline_cache::PIPELINE_CACHE_FILE));
        }
    }
}

/// This frame as a graph: the scene's passes into the HDR target (or, for a display
/// output, into an 8-bit transient target), saturation, and the readback.
fn frame_graph<'a>(
    (forward, saturate): (&'a ForwardPass, Option<&'a SaturatePass>),
    (target, readback): (&'a HdrTarget, &'a Buffer),
    output: Output,
) -> Result<luz_graph::CompiledGraph<'a>, VkError> {
    let mut g = FrameGraph::new();
    let scene = target.add_to(&mut g);
    let extent = target.extent();
    let source = match output {
        Output::Display { format, .. } => {
            let codes = g.create_image(
                "display codes",
                luz_graph::ImageDesc::color(extent.width, extent.height, format),
            );
            let target = SceneTarget {
                color: codes,
                resolve: None,
                ..scene
            };
            forward.add_passes(&mut g, (0, PassNames::MAIN), output, target)?;
            codes
        }
        Output::Hdr => {
            forward.add_passes(&mut g, (0, PassNames::MAIN), Output::Hdr, scene)?;
            if let Some(s) = saturate {
                s.add_pass(&mut g, scene.output(), s.name());
            }
            scene.output()
        }
    };
    add_readback(&mut g, "readback", source, readback, extent);
    Ok(g.compile()?)
}

/// The widest equirectangular image (2:1, RGBA32F on the GPU) the device takes: at most
/// `maxImageDimension2D`, and small enough that its 8·width² bytes fit one allocation
/// (`maxMemoryAllocationSize`) and one staging buffer (`maxBufferSize`). Larger environments are
/// downscaled to fit ([`crate::env::load_equirect`]).
pub fn equirect_max_dimension(limits: &crate::vk::Limits) -> u32 {
    let bytes = limits
        .max_memory_allocation_size
        .min(limits.max_buffer_size);
    let by_memory = ((bytes / 8) as f64).sqrt().floor();
    // The square root may round up for large values: step down until it fits (in u128: no
    // overflow).
    let mut w = by_memory.min(u32::MAX as f64) as u64;
    while w > 0 && 8 * u128::from(w) * u128::from(w) > u128::from(bytes) {
        w -= 1;
    }
    limits
        .max_image_dimension_2d
        .min(u32::try_from(w).unwrap_or(u32::MAX))
}

/// Loads the scene's environment and precomputes its IBL data on the GPU, telling `progress` each
/// stage.
pub fn build_ibl(
    ctx: &Arc<Context>,
    pool: &CommandPool,
    scene: &Scene,
    env: &crate::scene::Environment,
    settings: &IblSettings,
    cache_dir: Option<&std::path::Path>,
    progress: Option<&dyn crate::progress::Progress>,
) -> Result<Ibl, VkError> {
    let max = equirect_max_dimension(&ctx.limits());
    let eq = crate::env::load_equirect(env, max).map_err(|e| VkError::Setup(e.to_string()))?;
    let sh = crate::env::sh9_irradiance_coeffs(&crate::env::sh9_project(&eq));
    let reporting = crate::progress::Reporting(progress);
    let lut_geometries = crate::render::forward::lut_geometries(scene);
    let inputs = IblInputs {
        equirect: EquirectView {
            width: eq.width,
            height: eq.height,
            texels: &eq.texels,
        },
        sh_irradiance: sh,
        rotation_deg: env.rotation_deg,
        lut_geometries: &lut_geometries,
        anisotropy: crate::render::forward::needs_aniso_lut(scene),
        cache: cache_dir.map(|d| (d, crate::env::cache_key(env, &settings.describe()))),
    };
    Ibl::new(ctx, pool, &inputs, settings, |name, step, total| {
        reporting.update(name, step, total)
    })
}

/// Bakes the default scene's environment at the default settings on `ctx`, without the shipped
/// data, into a temporary cache folder: the cache file's name and bytes (what
/// `render::ibl::shipped` ships).
pub fn bake_default_environment(ctx: &Arc<Context>) -> Result<(String, Vec<u8>), VkError> {
    let scene = crate::scene::default_scene();
    let env = scene
        .environment
        .as_ref()
        .ok_or_else(|| VkError::Setup("the default scene has no environment".into()))?;
    let dir = std::env::temp_dir().join(format!("luz-default-env-{}", std::process::id()));
    let io = |e: std::io::Error| VkError::Setup(format!("{}: {e}", dir.display()));
    std::fs::create_dir_all(&dir).map_err(io)?;
    let settings = IblSettings {
        shipped: false,
        ..Default::default()
    };
    let pool = CommandPool::new(ctx, "default environment bake")?;
    let ibl = build_ibl(ctx, &pool, &scene, env, &settings, Some(&dir), None);
    let name = format!(
        "{}-{}.ibl",
        crate::env::cache_key(env, &settings.describe()),
        settings.describe().replace(' ', "_")
    );
    let bytes = ibl.and_then(|_| std::fs::read(dir.join(&name)).map_err(io));
    let _ = std::fs::remove_dir_all(&dir);
    Ok((name, bytes?))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vk::Limits;

    #[test]
    fn equirect_fits_the_dimension_and_memory_limits() {
        let mut l = Limits::unbounded();
        l.max_image_dimension_2d = 16384;
        assert_eq!(equirect_max_dimension(&l), 16384);
        // lavapipe: 2 GiB allocations, 16384 texels: 16384 × 8192 × 16 bytes is exactly 2 GiB.
        l.max_memory_allocation_size = 1 << 31;
        assert_eq!(equirect_max_dimension(&l), 16384);
        // Vulkan's minimum (1 GiB): 11585 × 5792 × 16 bytes fits, 11586 does not.
        l.max_memory_allocation_size = 1 << 30;
        let w = equirect_max_dimension(&l) as u64;
        assert_eq!(w, 11585);
        assert!(8 * w * w <= 1 << 30 && 8 * (w + 1) * (w + 1) > 1 << 30);
        l.max_buffer_size = 800;
        assert_eq!(equirect_max_dimension(&l), 10);
        // Unbounded memory: the dimension limit alone, no overflow.
        let l = Limits::unbounded();
        assert_eq!(equirect_max_dimension(&l), 1_518_500_249);
    }
}
