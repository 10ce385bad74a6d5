//! Opening what is dropped or typed (a scene, an OBJ or glTF model, an environment), and rebuilding the
//! passes or the swapchain when the scene's structure or the window changes.

use super::*;

impl Viewer {
    /// Opens a dropped or typed path: a scene, an OBJ or glTF model (lit as the current scene is)
    /// or an environment image.
    pub(super) fn open_path(&mut self, path: &Path) {
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

    pub(super) fn try_open(&mut self, path: &Path) -> Result<String> {
        let ext = crate::files::lowercase_extension(path).unwrap_or_default();
        match ext.as_str() {
            "json" => {
                let scene = crate::scene::load(path)?;
                self.replace_scene(scene, true)?;
                Ok(format!("opened {}", path.display()))
            }
            "obj" | "gltf" | "glb" => {
                let abs = std::fs::canonicalize(path)
                    .with_context(|| format!("cannot open {}", path.display()))?;
                let text = serde_json::json!({
                    "objects": [{ "name": abs.file_stem().and_then(|s| s.to_str()).unwrap_or("model"),
                                  "mesh": { "type": if ext == "obj" { "obj" } else { "gltf" }, "path": abs } }]
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
    pub(super) fn replace_scene(&mut self, scene: Scene, new_camera: bool) -> Result<()> {
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
    pub(super) fn rebuild(&mut self, environment: bool) -> Result<()> {
        self.view_changed = true;
        // SAFETY: the device is live and only this thread submits to its queue, so waiting for idle needs no
        // further synchronisation; afterwards nothing the rebuild replaces is in use.
        unsafe { self.ctx.device.device_wait_idle()? };
        let ibl = if environment {
            Some(scene_ibl(
                &self.ctx,
                &self.pool,
                &self.scene,
                &self.render_options,
            )?)
        } else {
            None
        };
        let samples = sample_flags(self.scene.output.msaa);
        let targets = if samples != self.samples {
            Some(HdrTarget::new(
                "viewer",
                nonzero(self.swapchain.extent),
                samples,
            ))
        } else {
            None
        };
        self.scene.camera = self.orbit.to_camera();
        let (forward, prepared) = make_forward(
            &self.ctx,
            &self.pool,
            (&self.scene, Some(std::mem::take(&mut self.prepared))),
            samples,
            match &ibl {
                Some(new) => new.as_ref(),
                None => self.ibl.as_ref(),
            },
            self.swapchain.extent,
            pass_options(
                &self.settings,
                (
                    frame::preferred_output(
                        &self.scene,
                        self.display_path,
                        samples,
                        self.swapchain.format,
                    ),
                    self.render_path,
                ),
            ),
        )?;
        let saturate = SaturatePass::for_scene(&self.ctx, &self.scene)?;
        // Everything is built: replace (the old passes are dropped after the new ones exist).
        self.forward = forward;
        self.prepared = prepared;
        self.saturate = saturate;
        if let Some(ibl) = ibl {
            self.ibl = ibl;
        }
        if let Some(t) = targets {
            self.targets = t;
            self.samples = samples;
            self.lab.drop_gpu();
        }
        self.built_scene = self.scene.clone();
        Ok(())
    }

    pub(super) fn recreate_swapchain(&mut self) -> Result<()> {
        let size = self.window.inner_size();
        if size.width == 0 || size.height == 0 {
            return Ok(());
        }
        // SAFETY: the device is live and only this thread submits to its queue, so waiting for idle needs no
        // further synchronisation; the old swapchain is retired only after this.
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
        if extent != self.targets.extent() {
            self.targets = self.targets.resized(extent);
            self.lab.drop_gpu();
        }
        self.swapchain_dirty = false;
        Ok(())
    }
}
