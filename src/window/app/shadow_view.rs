//! The shadow-map window (issue 15's debug view of each map): a shadowed light's layers as the
//! last frame drew them ([`crate::render::shadow::view`]), read back every
//! [`REFRESH_FRAMES`] frames while the window is open (and at once when asked), since reading
//! waits for the GPU to go idle.

use super::*;
use crate::render::shadow::{picture, MapLayer};

/// Frames between two read-backs while the window is open.
pub(super) const REFRESH_FRAMES: u64 = 30;

#[derive(Default)]
pub(super) struct ShadowView {
    /// The scene light whose maps are shown.
    pub light: usize,
    /// Read back at the next frame (opened, another light chosen, Refresh, a script action).
    pub due: bool,
    /// Write the picture here after the next read-back (`shadow_map_save=PATH`).
    pub save: Option<PathBuf>,
    last_read: Option<u64>,
    texture: Option<egui::TextureHandle>,
    /// The picture's size and what it shows.
    shown: Option<(u32, u32, String)>,
}

impl ShadowView {
    /// The window (when `open`): a light chooser among `lights` (index, name) and the picture.
    pub fn ui(&mut self, ui: &mut egui::Ui, open: &mut bool, lights: &[(usize, String)]) {
        if !*open {
            return;
        }
        let mut keep = true;
        egui::Window::new("Shadow maps")
            .open(&mut keep)
            .default_width(560.0)
            .show(ui.ctx(), |ui| {
                if lights.is_empty() {
                    ui.label("No light casts a shadow (a light's Shadow row turns it on).");
                    return;
                }
                ui.horizontal(|ui| {
                    let name = |i: usize| {
                        lights
                            .iter()
                            .find(|(l, _)| *l == i)
                            .map_or_else(|| format!("light {i}"), |(_, n)| n.clone())
                    };
                    egui::ComboBox::from_id_salt("luz_shadow_map_light")
                        .selected_text(name(self.light))
                        .show_ui(ui, |ui| {
                            for (i, n) in lights {
                                if ui.selectable_value(&mut self.light, *i, n).changed() {
                                    self.due = true;
                                }
                            }
                        });
                    if ui.button("Refresh").clicked() {
                        self.due = true;
                    }
                });
                match (&self.texture, &self.shown) {
                    (Some(t), Some((w, h, text))) => {
                        ui.label(text.as_str());
                        let width = ui.available_width().min(*w as f32);
                        let size = egui::vec2(width, width * *h as f32 / *w as f32);
                        ui.add(egui::Image::new((t.id(), size)));
                        ui.label(
                            "Near white, far black; dark blue: nothing drawn. Layers left to \
                             right: cascades near to far, or cube faces +x −x +y −y +z −z.",
                        );
                    }
                    _ => {
                        ui.label("Reading the maps…");
                    }
                }
            });
        if !keep {
            *open = false;
        }
        if !lights.iter().any(|(i, _)| *i == self.light) {
            if let Some((i, _)) = lights.first() {
                self.light = *i;
                self.due = true;
            }
        }
    }

    /// Whether the window needs a read-back at frame `frame`.
    pub fn wants_read(&self, open: bool, frame: u64) -> bool {
        self.save.is_some()
            || open && (self.due || self.last_read.is_none_or(|f| frame >= f + REFRESH_FRAMES))
    }

    /// Shows the light's layers of `layers` (read at frame `frame`) and writes the picture when
    /// asked.
    pub fn show(&mut self, ctx: &egui::Context, layers: &[MapLayer], frame: u64) -> Result<()> {
        self.due = false;
        self.last_read = Some(frame);
        let own: Vec<&MapLayer> = layers.iter().filter(|l| l.light == self.light).collect();
        let save = self.save.take();
        let Some((w, h, pixels)) = picture(&own) else {
            self.texture = None;
            self.shown = None;
            if let Some(p) = save {
                anyhow::bail!(
                    "shadow_map_save={}: light {} has no shadow map",
                    p.display(),
                    self.light
                );
            }
            return Ok(());
        };
        if let Some(p) = &save {
            image::save_buffer(p, &pixels, w, h, image::ExtendedColorType::Rgba8)
                .with_context(|| format!("shadow_map_save={}", p.display()))?;
        }
        let (near, far) = own
            .iter()
            .flat_map(|l| l.distance.iter().flatten())
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(n, f), d| {
                (n.min(*d), f.max(*d))
            });
        let range = if near <= far {
            format!("distances {near:.3}–{far:.3} m")
        } else {
            "nothing drawn".to_string()
        };
        let text = format!(
            "light {}: {} layer(s) of {}², {range}; read at frame {frame}",
            self.light,
            own.len(),
            own[0].resolution
        );
        let image = egui::ColorImage::from_rgba_unmultiplied([w as usize, h as usize], &pixels);
        match &mut self.texture {
            Some(t) => t.set(image, egui::TextureOptions::NEAREST),
            None => {
                self.texture =
                    Some(ctx.load_texture("luz_shadow_map", image, egui::TextureOptions::NEAREST))
            }
        }
        self.shown = Some((w, h, text));
        Ok(())
    }
}

impl Viewer {
    /// Before a frame: read the maps back when the window (or a script) wants them.
    pub(super) fn refresh_shadow_view(&mut self) -> Result<()> {
        let open = self.settings.shadow_maps;
        if self.frame_index == 0 || !self.shadow_view.wants_read(open, self.frame_index) {
            return Ok(());
        }
        // SAFETY: waiting for the device has no preconditions; afterwards no submitted frame
        // writes the maps while they are copied.
        unsafe { self.ctx.device.device_wait_idle()? };
        let layers = self.forward.shadow_maps().read_layers(&self.pool)?;
        self.shadow_view
            .show(&self.egui_ctx, &layers, self.frame_index)
    }

    /// The shadowed lights, for the window's chooser.
    pub(super) fn shadowed_lights(&self) -> Vec<(usize, String)> {
        self.forward
            .shadow_maps()
            .maps()
            .iter()
            .filter_map(|m| {
                let n = self.scene.lights.len();
                let kind = match self.scene.lights.get(m.light) {
                    Some(l) => format!("{:?}", l.kind).to_lowercase(),
                    // Area lights' maps follow the punctual lights' (render::shadow).
                    None => {
                        let k = m.light - n;
                        let shape = self.scene.area_lights.get(k)?.shape.name();
                        return Some((m.light, format!("area light {k} ({shape})")));
                    }
                };
                Some((m.light, format!("light {} ({kind})", m.light)))
            })
            .collect()
    }
}
