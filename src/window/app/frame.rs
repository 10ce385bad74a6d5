//! One frame: scripted actions, the UI, recording the scene passes, the display pass and the UI
//! into the swapchain image, presenting, and screenshots.

use super::*;
use crate::vk::cmd::Load;
use crate::window::ui::compare::MAP_SCOPE;

impl Viewer {
    pub(super) fn run_script(&mut self) -> Result<()> {
        while let Some((f, _)) = self.script.first() {
            if *f > self.frame_index {
                break;
            }
            let (_, action) = self.script.remove(0);
            self.view_changed |= lod::changes_view(&action);
            match action {
                Action::Resize(w, h) => {
                    let _ = self
                        .window
                        .request_inner_size(PhysicalSize::new(w.max(1), h.max(1)));
                }
                Action::Minimize => self.window.set_minimized(true),
                Action::Restore => self.window.set_minimized(false),
                Action::Exposure(e) => self.edited_scene().output.exposure = e,
                Action::Tonemap(t) => self.edited_scene().output.tonemap = t,
                Action::CompareEdit(b) => self.lab.settings.edit_b = b,
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
                Action::ShadowMap(light) => {
                    self.settings.shadow_maps = light.is_some();
                    if let Some(i) = light {
                        self.shadow_view.light = i;
                        self.shadow_view.due = true;
                    }
                }
                Action::ShadowMapSave(p) => self.shadow_view.save = Some(p),
                Action::LightShadow(i, edit) => {
                    // The lights panel's path: the edit here, the rebuild after the UI when the
                    // shadow's structure changed.
                    let text = script::light_shadow_text(i, edit);
                    let lights = &mut self.edited_scene().lights;
                    let n = lights.len();
                    let light = lights.get_mut(i).ok_or_else(|| {
                        anyhow!("script: {text}: no light {i} (the scene has {n} light(s))")
                    })?;
                    crate::scene::edit::edit_shadow(light, edit)
                        .map_err(|e| anyhow!("script: {text}: {e}"))?;
                }
                Action::Open(p) => self.open_path(&p),
                Action::Save(p) => self.apply_actions(vec![UiAction::Save(p)])?,
                Action::CompareMode(m) => {
                    self.lab.settings.mode = m;
                    self.lab.settings.open = true;
                }
                Action::CompareSplit(x) => {
                    self.lab.settings.split = x;
                    self.lab.settings.open = true;
                }
                Action::CompareFlip => self.lab.settings.show_b = !self.lab.settings.show_b,
                Action::CompareDuplicate => self
                    .apply_lab_actions(vec![super::super::ui::compare::CompareAction::Duplicate]),
                Action::ErrorView(on) => {
                    self.lab.settings.error_view = on;
                    self.lab.settings.open = true;
                }
                Action::ErrorMetric(m) => self.lab.settings.metric = m,
                Action::LobePlots(on) => {
                    self.lab.settings.plots = on;
                    self.lab.settings.open = true;
                }
                Action::AddLights(field, n) => {
                    let bounds = self.scene.bounds();
                    let lights = crate::scene::edit::light_field(field, n as usize, bounds);
                    self.scene.lights.extend(lights);
                }
            }
        }
        Ok(())
    }

    /// The scene the panels edit: B's when "panels edit B" is on and B exists, else A's.
    fn edited_scene(&mut self) -> &mut Scene {
        match (&mut self.lab.b, self.lab.settings.edit_b) {
            (Some(b), true) => &mut b.scene,
            _ => &mut self.scene,
        }
    }

    /// Draws one frame; false when `--frames` are done.
    pub(super) fn frame(&mut self) -> Result<bool> {
        self.awake = self.awake.saturating_sub(1);
        self.run_script()?;
        if let Some(degrees) = self.turntable {
            self.orbit.orbit(degrees, 0.0);
        }
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
                // SAFETY: the fence belongs to this device and was submitted with this slot's last frame.
                unsafe { d.wait_for_fences(&[f.fence], true, u64::MAX)? };
                // SAFETY: the wait above returned, so no queue operation still refers to the fence.
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
                let lod = f.lod;
                if self.bench {
                    self.bench_frames.push(sample.clone());
                    self.bench_lod.push(lod);
                }
                self.lod_target
                    .observe(lod.budget, lod.adaptive, lod::frame_cost(&sample));
                self.profiler.push(sample);
                if let Some(r) = &mut self.egui_renderer {
                    for id in std::mem::take(&mut f.free_textures) {
                        r.free_texture(id).map_err(|e| anyhow!("egui: {e}"))?;
                    }
                }
            }
        }
        self.refresh_shadow_view()?;
        // 2. Acquire.
        let acquired = self.frames[slot].acquired;
        // SAFETY: `acquired` is this slot's semaphore, unsignalled: its last wait was by the submission
        // whose fence was waited for above; the swapchain is live (recreated only between frames).
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
        let mut lab_actions = Vec::new();
        self.lab.poll(&self.egui_ctx);
        let shadow_lights = self.shadowed_lights();
        let output = {
            let (scene, settings, profiler, state, lab, shadow_view) = (
                &mut self.scene,
                &mut self.settings,
                &self.profiler,
                &mut self.ui_state,
                &mut self.lab,
                &mut self.shadow_view,
            );
            let status = &self.status;
            self.egui_ctx.run_ui(raw, |ui| {
                if let Some(s) = status {
                    egui::Panel::bottom("status").show(ui, |ui| {
                        ui.label(s.as_str());
                    });
                }
                let plot = if lab.settings.plots && settings.show_panels {
                    let shown = match (&lab.b, lab.settings.edit_b) {
                        (Some(b), true) => &b.scene,
                        _ => &*scene,
                    };
                    lab::plot_key(shown, state.selected_object)
                } else {
                    None
                };
                lab_actions = lab.ui(ui, settings.show_panels, profiler, plot);
                // The scene panels edit B when asked to (and B exists).
                let edited = match (&mut lab.b, lab.settings.edit_b) {
                    (Some(b), true) => &mut b.scene,
                    _ => scene,
                };
                actions = ui::draw(ui, edited, settings, profiler, state);
                shadow_view.ui(ui, &mut settings.shadow_maps, &shadow_lights);
            })
        };
        self.egui_state
            .handle_platform_output(&self.window, output.platform_output);
        let primitives = self
            .egui_ctx
            .tessellate(output.shapes, output.pixels_per_point);
        self.view_changed |= actions.iter().any(lod::ui_changes_view) || !lab_actions.is_empty();
        self.apply_actions(actions)?;
        self.apply_lab_actions(lab_actions);
        // The forward pass answers what the edits cost it (render::world).
        let change = self
            .forward
            .shape()
            .change_to(&self.scene, self.settings.debug_view);
        if change != Change::InPlace {
            let env = change == (Change::Rebuild { environment: true });
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
        self.choose_lod_budget(slot);
        self.forward.update(slot, &self.scene, aspect)?;
        self.note_lod(slot);
        self.sync_b(slot)?;
        self.lab.error_tick(&self.scene, self.targets.extent());

        // 5. Record.
        let cmd = self.frames[slot].cmd;
        // SAFETY: the slot's command buffer is not pending (its fence was waited for above) and comes
        // from a pool created with RESET_COMMAND_BUFFER.
        unsafe { crate::vk::cmd::restart(&d, cmd) }?;
        let screenshot = self.pending_screenshot.take();
        let output = self.frame_output(screenshot.as_deref());
        self.forward.prepare(output)?;
        self.forward.prepare_extent(self.swapchain.extent)?;
        let readback = self.record(
            cmd,
            slot,
            image_index,
            &primitives,
            screenshot.as_deref(),
            output,
        )?;
        // SAFETY: `cmd` is recording (begun above) and `record` closed its rendering instances.
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
        // SAFETY: `cmd` is executable, the slot's fence is unsignalled (reset after its wait), the
        // semaphores are live, and this thread alone submits to the queue.
        unsafe { d.queue_submit2(self.ctx.queue, &[submit], self.frames[slot].fence)? };
        self.frames[slot].submitted = true;
        let swapchains = [self.swapchain.raw];
        let indices = [image_index];
        let wait = [render_finished];
        let present = vk::PresentInfoKHR::default()
            .wait_semaphores(&wait)
            .swapchains(&swapchains)
            .image_indices(&indices);
        // SAFETY: the image was acquired for this frame and the submission above signals the semaphore
        // the present waits on; the queue is used by this thread only.
        match unsafe {
            self.swapchain
                .loader
                .queue_present(self.ctx.queue, &present)
        } {
            Ok(false) => {}
            Ok(true) | Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => self.swapchain_dirty = true,
            Err(e) => return Err(e.into()),
        }
        let copies = std::mem::take(&mut self.lab_copies);
        if readback.is_some() || copies.any() {
            let f = &self.frames[slot];
            // SAFETY: the fence was submitted with this frame just above; waiting makes its copy visible.
            unsafe { d.wait_for_fences(&[f.fence], true, u64::MAX)? };
        }
        if let Some(shot) = readback {
            self.save_screenshot(&shot)?;
        }
        if copies.any() {
            let (a, b) = copies.images()?;
            self.lab.deliver(a, b);
        }
        self.frames[slot].cpu_ms = start.elapsed().as_secs_f64() * 1e3;
        self.slot = (slot + 1) % FRAMES_IN_FLIGHT;
        self.frame_index += 1;
        Ok(!self.done())
    }

    pub(super) fn done(&self) -> bool {
        self.frame_limit.is_some_and(|n| self.frame_index >= n)
    }

    /// What this frame's forward pass writes: the display codes straight into the swapchain
    /// image when nothing needs the float image ([`preferred_output`]) and the target matches
    /// the window, else the HDR radiance.
    pub(super) fn frame_output(&self, screenshot: Option<&Path>) -> Output {
        let exr = screenshot.is_some_and(is_exr);
        if exr || self.lab.forces_hdr() || self.targets.extent() != self.swapchain.extent {
            return Output::Hdr;
        }
        preferred_output(
            &self.scene,
            self.display_path,
            self.samples,
            self.swapchain.format,
        )
    }

    /// Records the frame's passes into `cmd` as one frame graph; returns the screenshot being
    /// copied, if any.
    ///
    /// The graph: A's scene passes (into the swapchain image directly for a display `output`,
    /// else into A's HDR target, then saturation, an EXR screenshot's copy, B's passes, the A/B
    /// map, the lab's read-backs and the display pass), the UI over the swapchain image, a PNG
    /// screenshot's copy, and the swapchain image left for presenting.
    pub(super) fn record(
        &mut self,
        cmd: vk::CommandBuffer,
        slot: usize,
        image_index: u32,
        primitives: &[egui::ClippedPrimitive],
        screenshot: Option<&Path>,
        output: Output,
    ) -> Result<Option<Shot>> {
        let mut timer = self.frames[slot].timer.take();
        if let Some(t) = &mut timer {
            t.reset(cmd);
        }
        let sc = self.swapchain.extent;
        let hdr_extent = self.targets.extent();
        let direct = matches!(output, Output::Display { .. });
        // The host buffers this frame's copies write, made before the graph borrows them.
        let shot = match screenshot {
            Some(p) if is_exr(p) && !direct => Some(self.shot_buffer(p, false, hdr_extent)?),
            Some(p) if !is_exr(p) && self.swapchain.can_read => {
                Some(self.shot_buffer(p, true, sc)?)
            }
            Some(p) if !is_exr(p) => {
                self.status =
                    Some("this window's images cannot be read back: no screenshot".into());
                None
            }
            _ => None,
        };
        let (map, copies) = if direct {
            (None, lab::Readbacks::default())
        } else {
            self.prepare_lab(slot)?
        };
        let has_ui = self.egui_renderer.is_some() && !primitives.is_empty();
        let pixels_per_point = self.egui_ctx.pixels_per_point();
        let format = self.swapchain.format;
        let mut g = FrameGraph::new();
        let swap = g.import_image(
            "swapchain image",
            ImportedImage::new(
                self.swapchain.images[image_index as usize],
                self.swapchain.views[image_index as usize],
                crate::graph::ImageDesc::color(sc.width, sc.height, format),
            )
            // Acquired: the submission waits for its semaphore at colour output.
            .before(ImageStateBefore::Discard(Access::ColorAttachmentWrite))
            .after(Access::Present),
        );
        let a = self.targets.add_to(&mut g);
        let mut b_target = None;
        if direct {
            let target = SceneTarget {
                color: swap,
                resolve: None,
                ..a
            };
            self.forward
                .add_passes(&mut g, (slot, PassNames::MAIN), output, target)?;
        } else {
            self.forward
                .add_passes(&mut g, (slot, PassNames::MAIN), Output::Hdr, a)?;
            if let Some(sat) = &self.saturate {
                sat.add_pass(&mut g, a.output(), sat.name());
            }
            if let Some(shot) = shot.as_ref().filter(|s| !s.display) {
                add_readback(&mut g, "screenshot", a.output(), &shot.buffer, hdr_extent);
            }
            if let Some(b) = &self.lab.b {
                b_target = Some(lab::add_b_passes(&mut g, b, slot)?);
            }
            let mut shown_map = None;
            if let (Some(kind), Some(bt), Some(pass)) = (map, b_target, self.lab.gpu.as_ref()) {
                let settings = (self.scene.output.exposure, self.scene.output.tonemap);
                shown_map = Some(pass.add_pass(
                    &mut g,
                    (MAP_SCOPE, slot),
                    (a.output(), bt.output()),
                    kind,
                    settings,
                )?);
            }
            if let Some((buffer, extent)) = &copies.a {
                add_readback(&mut g, "read-back A", a.output(), buffer, *extent);
            }
            if let (Some((buffer, extent)), Some(bt)) = (&copies.b, b_target) {
                add_readback(&mut g, "read-back B", bt.output(), buffer, *extent);
            }
            let mut pass = g
                .pass("display")
                .read(a.output(), HDR_DISPLAY_READ)
                .write(swap, Access::ColorAttachmentWrite);
            if let Some(bt) = b_target {
                pass = pass.read(bt.output(), HDR_DISPLAY_READ);
            }
            // The difference and FLIP modes show this frame's map and its figures.
            if let Some(m) = shown_map {
                pass = pass
                    .read(m.map, crate::render::compare::MAP_SHOW_READ)
                    .read(m.figures, Access::FragmentStorageBufferRead);
            }
            let (display, scene, lab) = (&self.display, &self.scene, &self.lab);
            let area = vk::Extent2D {
                width: hdr_extent.width.min(sc.width),
                height: hdr_extent.height.min(sc.height),
            };
            pass.record(move |rc| {
                let view = rc.image(swap)?.view;
                let views = lab::ShownViews {
                    a: rc.image(a.output())?.view,
                    b: match b_target {
                        Some(bt) => Some(rc.image(bt.output())?.view),
                        None => None,
                    },
                    map: match shown_map {
                        Some(m) => Some(rc.image(m.map)?.view),
                        None => None,
                    },
                };
                render_to(rc, view, sc, Load::DontCare, |cmd| {
                    lab::record_display(cmd, (slot, area, format), (display, scene), lab, views)
                })
            });
        }
        if has_ui {
            let renderer = self.egui_renderer.as_mut();
            g.pass("ui")
                .read_write(swap, Access::ColorAttachmentReadWrite)
                .side_effect()
                .record(move |rc| {
                    let view = rc.image(swap)?.view;
                    render_to(rc, view, sc, Load::Keep, |cmd| {
                        if let Some(r) = renderer {
                            r.cmd_draw(cmd, sc, pixels_per_point, primitives)
                                .map_err(|e| anyhow!("egui: {e}"))?;
                        }
                        Ok(())
                    })
                });
        }
        if let Some(shot) = shot.as_ref().filter(|s| s.display) {
            add_readback(&mut g, "screenshot", swap, &shot.buffer, sc);
        }
        let graph = g.compile()?;
        self.transients
            .execute(&self.ctx, graph, cmd, timer.as_mut())?;
        self.frames[slot].timer = timer;
        self.lab_copies = copies;
        Ok(shot)
    }

    /// A host buffer for a screenshot of `extent` (8-bit display codes, or float radiance).
    fn shot_buffer(&self, path: &Path, display: bool, extent: vk::Extent2D) -> Result<Shot> {
        let texel = if display { 4 } else { 16 };
        let buffer = Buffer::new(
            &self.ctx,
            if display {
                "screenshot (display)"
            } else {
                "screenshot (hdr)"
            },
            extent.width as u64 * extent.height as u64 * texel,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        Ok(Shot {
            path: path.to_path_buf(),
            buffer,
            display,
            extent,
        })
    }

    pub(super) fn save_screenshot(&mut self, shot: &Shot) -> Result<()> {
        let bytes = shot.buffer.mapped()?;
        let (w, h) = (shot.extent.width, shot.extent.height);
        // Where it came from: the device, the scene (file, hash, tone map, exposure) as the
        // viewer shows it, the window's size.
        let mut meta = crate::provenance::of_render(&self.ctx.info, &self.scene, None);
        meta.set("luz.size", format!("{w}x{h}"));
        meta.set("luz.capture", "viewer screenshot");
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
            meta.set("luz.encoding", "8-bit sRGB (display image)");
            crate::imageio::save_png_rgb8_with(&shot.path, w, h, &rgb, &meta)?;
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
            // The float image: no tone map or exposure applied.
            meta.entries
                .retain(|(k, _)| k != "luz.tonemap" && k != "luz.exposure_ev");
            crate::imageio::save_with(&shot.path, &img, 0.0, crate::color::Tonemap::None, &meta)?;
        }
        let msg = format!("wrote {} ({w}x{h})", shot.path.display());
        log::info!("{msg}");
        self.status = Some(msg);
        Ok(())
    }
}

fn is_exr(p: &Path) -> bool {
    p.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr"))
}

/// The output the viewer's forward pass draws with when nothing else in the frame needs the float
/// image: straight into the swapchain image unless `path` asks for the float path, the scene
/// needs the whole float image (normalize saturation) or is multisampled (the resolve averages
/// radiance, as `luz render` does).
pub(super) fn preferred_output(
    scene: &Scene,
    path: DisplayPath,
    samples: vk::SampleCountFlags,
    format: vk::Format,
) -> Output {
    if path == DisplayPath::Hdr || samples != vk::SampleCountFlags::TYPE_1 {
        return Output::Hdr;
    }
    Output::display_for(scene, format).unwrap_or(Output::Hdr)
}

/// Records `draw` inside one rendering instance on the colour attachment `view` (the swapchain
/// image, in COLOR_ATTACHMENT_OPTIMAL as the graph left it), loaded with `load`.
fn render_to(
    rc: &mut crate::graph::RecordContext<'_>,
    view: vk::ImageView,
    extent: vk::Extent2D,
    load: Load,
    draw: impl FnOnce(vk::CommandBuffer) -> Result<()>,
) -> Result<(), crate::graph::PassError> {
    let (d, cmd) = (rc.device(), rc.cmd());
    let colors = [crate::vk::cmd::color_attachment(view, load, true)];
    let area = vk::Rect2D {
        offset: vk::Offset2D::default(),
        extent,
    };
    let info = crate::vk::cmd::rendering_info(area, &colors, None);
    // SAFETY: `cmd` is recording outside a rendering instance (the graph records one pass at a
    // time) and the image behind `view` is in COLOR_ATTACHMENT_OPTIMAL (the pass's declared
    // access); `info` outlives the call.
    unsafe { d.cmd_begin_rendering(cmd, &info) };
    let result = draw(cmd);
    // SAFETY: closes the rendering begun above in the same command buffer.
    unsafe { d.cmd_end_rendering(cmd) };
    result.map_err(|e| format!("{e:#}").into())
}
