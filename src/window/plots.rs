//! Live lobe plots of the selected material in the viewer: the in-plane polar lobe at the current
//! light angle, the θh × θd slice and the directional-albedo curve — the charts of
//! `luz brdf --plot` ([`crate::plot::brdf_charts`]), rendered by [`crate::plot::render_rgb`] on a
//! worker thread whenever the material or the light angle changes, shown as egui textures.
//!
//! The light angle θl is the incidence at the point of the selected object that faces the camera:
//! the angle between the direction from the object's centre to the camera (the normal there)
//! and the direction to the scene's first light, clamped to [0°, 89°].

use std::sync::mpsc::{channel, Receiver, Sender};

use glam::Vec3;

use crate::brdf::Model;
use crate::plot::brdf_charts::{albedo_chart_of, lobe_chart, slice_chart};
use crate::plot::Chart;
use crate::scene::{LightKind, Scene};

/// Chart size in pixels, shown 1:1 (the lab panel widens to fit them while they are on).
pub const PLOT_W: u32 = 520;
pub const PLOT_H: u32 = 380;
/// The slice's cells per axis and colour decades; the albedo's samples per angle.
const SLICE_CELLS: usize = 48;
const SLICE_DECADES: f64 = 4.0;
const ALBEDO_SAMPLES: u32 = 256;

/// What the plots show.
#[derive(Debug, Clone, PartialEq)]
pub struct PlotKey {
    pub model: Model,
    /// Degrees, rounded to a tenth.
    pub theta_l: f64,
}

/// θl of `scene`'s object `object` ([module docs](self)); `None` without lights or objects.
pub fn light_angle(scene: &Scene, object: usize) -> Option<f64> {
    let o = scene.objects.get(object)?;
    let light = scene.lights.first()?;
    let centre = o.transform.position;
    let n = (scene.camera.position - centre).try_normalize()?;
    let l = match light.kind {
        LightKind::Directional => -light.direction,
        _ => (light.position - centre).try_normalize()?,
    };
    let cos = n.dot(l.normalize_or(Vec3::Y)).clamp(-1.0, 1.0);
    let deg = f64::from(cos.acos().to_degrees()).clamp(0.0, 89.0);
    Some((deg * 10.0).round() / 10.0)
}

/// The three charts of `key` as RGB8 images (title, pixels).
fn render(key: &PlotKey) -> Result<Vec<(String, Vec<u8>)>, String> {
    let lobe = lobe_chart(&key.model, &[key.theta_l]).map_err(|e| format!("{e:#}"))?;
    let charts: [(String, Chart); 3] = [
        (format!("lobe at θl = {:.1}°", key.theta_l), lobe.into()),
        (
            "θh × θd slice (φd = 90°)".into(),
            slice_chart(&key.model, 90.0, SLICE_CELLS, SLICE_DECADES).into(),
        ),
        (
            "directional albedo".into(),
            albedo_chart_of(&key.model, ALBEDO_SAMPLES).into(),
        ),
    ];
    charts
        .into_iter()
        .map(|(title, chart)| {
            crate::plot::render_rgb(&chart, PLOT_W, PLOT_H)
                .map(|px| (title, px))
                .map_err(|e| format!("{e:#}"))
        })
        .collect()
}

type PlotResult = (PlotKey, Result<Vec<(String, Vec<u8>)>, String>);

/// A thread drawing the newest requested key (older queued requests are skipped).
pub struct PlotWorker {
    tx: Sender<PlotKey>,
    rx: Receiver<PlotResult>,
    requested: Option<PlotKey>,
    shown: Option<PlotKey>,
    textures: Vec<(String, egui::TextureHandle)>,
    error: Option<String>,
}

impl PlotWorker {
    pub fn new() -> Self {
        let (tx, job_rx) = channel::<PlotKey>();
        let (result_tx, rx) = channel();
        let _ = std::thread::Builder::new()
            .name("luz-plots".into())
            .spawn(move || {
                while let Ok(mut key) = job_rx.recv() {
                    while let Ok(newer) = job_rx.try_recv() {
                        key = newer;
                    }
                    let out = render(&key);
                    if result_tx.send((key, out)).is_err() {
                        break;
                    }
                }
            });
        Self {
            tx,
            rx,
            requested: None,
            shown: None,
            textures: Vec::new(),
            error: None,
        }
    }

    /// Asks for `key` unless it is what was last asked for; takes finished images.
    pub fn update(&mut self, ctx: &egui::Context, key: Option<PlotKey>) {
        if let Some(k) = key {
            if self.requested.as_ref() != Some(&k) {
                let _ = self.tx.send(k.clone());
                self.requested = Some(k);
            }
        }
        while let Ok((key, out)) = self.rx.try_recv() {
            match out {
                Ok(images) => {
                    self.error = None;
                    for (i, (title, px)) in images.into_iter().enumerate() {
                        let image =
                            egui::ColorImage::from_rgb([PLOT_W as usize, PLOT_H as usize], &px);
                        match self.textures.get_mut(i) {
                            Some((t, tex)) => {
                                *t = title;
                                tex.set(image, egui::TextureOptions::LINEAR);
                            }
                            None => {
                                let tex = ctx.load_texture(
                                    format!("luz_plot_{i}"),
                                    image,
                                    egui::TextureOptions::LINEAR,
                                );
                                self.textures.push((title, tex));
                            }
                        }
                    }
                }
                Err(e) => self.error = Some(e),
            }
            self.shown = Some(key);
        }
    }

    /// The plots in `ui` at their pixel size (scaled down only when the panel is narrower).
    pub fn show(&self, ui: &mut egui::Ui) {
        if let Some(e) = &self.error {
            ui.colored_label(egui::Color32::from_rgb(220, 90, 90), e);
            return;
        }
        let Some(key) = &self.shown else {
            ui.label("drawing…");
            return;
        };
        ui.label(format!("{} at θl = {:.1}°", key.model.name(), key.theta_l));
        if self.requested.as_ref() != Some(key) {
            ui.weak("updating…");
        }
        let w = ui.available_width().clamp(100.0, PLOT_W as f32);
        let size = egui::Vec2::new(w, w * PLOT_H as f32 / PLOT_W as f32);
        for (title, tex) in &self.textures {
            ui.add(egui::Image::new((tex.id(), size)).alt_text(title.as_str()));
        }
    }
}

impl Default for PlotWorker {
    fn default() -> Self {
        Self::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(light_dir: [f32; 3]) -> Scene {
        let text = format!(
            r#"{{"camera": {{"position": [0, 0, 5], "target": [0, 0, 0]}},
               "lights": [{{"type": "directional", "direction": {light_dir:?}}}],
               "materials": {{"m": {{"model": "lambert"}}}},
               "objects": [{{"mesh": {{"type": "sphere"}}, "material": "m"}}]}}"#
        );
        crate::scene::parse(&text, std::path::Path::new("plots_test.json")).unwrap()
    }

    #[test]
    fn light_angle_is_the_incidence_at_the_point_facing_the_camera() {
        // Light from behind the camera: normal incidence.
        assert_eq!(light_angle(&scene([0.0, 0.0, -1.0]), 0), Some(0.0));
        // Light from the side: 90°, clamped to 89° (the lobe chart takes [0, 90)).
        assert_eq!(light_angle(&scene([-1.0, 0.0, 0.0]), 0), Some(89.0));
        // 45° between the view axis and the light.
        let d = std::f32::consts::FRAC_1_SQRT_2;
        assert_eq!(light_angle(&scene([-d, 0.0, -d]), 0), Some(45.0));
        // No such object.
        assert_eq!(light_angle(&scene([0.0, 0.0, -1.0]), 3), None);
    }

    #[test]
    fn the_three_charts_render() {
        if crate::plot::init_font().is_err() {
            eprintln!("SKIPPED: no chart font");
            return;
        }
        let key = PlotKey {
            model: scene([0.0, 0.0, -1.0]).materials[0].material,
            theta_l: 30.0,
        };
        let images = render(&key).unwrap();
        assert_eq!(images.len(), 3);
        for (title, px) in &images {
            assert_eq!(px.len(), (PLOT_W * PLOT_H * 3) as usize, "{title}");
            // Not blank: the chart drew something other than its white background.
            assert!(px.iter().filter(|&&c| c < 128).count() > 500, "{title}");
        }
    }
}
