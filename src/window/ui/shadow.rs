//! A light's shadow rows in the lights panel: on/off, method, resolution, kernel, biases,
//! cascades and the light's size. Method, resolution and cascades rebuild the passes; the rest
//! take effect on the next frame.

use super::*;
use crate::scene::{Shadow, ShadowMethod};

const RESOLUTIONS: [(u32, &str); 6] = [
    (256, "256²"),
    (512, "512²"),
    (1024, "1024²"),
    (2048, "2048²"),
    (4096, "4096²"),
    (8192, "8192²"),
];

pub(super) fn shadow_rows(ui: &mut Ui, light: &mut Light) -> bool {
    let mut c = row(ui, "Shadow", |ui| {
        let mut on = light.shadow.is_some();
        if checkbox(ui, &mut on, "") {
            light.shadow = on.then(|| Shadow::default_for(light.kind));
            true
        } else {
            false
        }
    });
    let kind = light.kind;
    let has_size = light.radius > 0.0 || light.angular_radius_deg > 0.0;
    let Some(s) = &mut light.shadow else {
        return c;
    };
    c |= row(ui, "Method", |ui| {
        let mut options = vec![(ShadowMethod::Hard, "hard"), (ShadowMethod::Pcf, "pcf")];
        // PCSS needs the light's size (set below).
        if has_size {
            options.push((ShadowMethod::Pcss, "pcss"));
        }
        combo(ui, ui.id().with("shadow_method"), &mut s.method, &options)
    });
    c |= row(ui, "Resolution", |ui| {
        combo(
            ui,
            ui.id().with("shadow_resolution"),
            &mut s.resolution,
            &RESOLUTIONS,
        )
    });
    if s.method != ShadowMethod::Hard {
        c |= row(ui, "Kernel", |ui| {
            ui.add(egui::Slider::new(&mut s.pcf_kernel, 1..=9))
                .changed()
        });
    }
    c |= row(ui, "Bias (texels)", |ui| {
        drag_speed(ui, &mut s.bias, 0.0..=f32::INFINITY, 0.05)
    });
    c |= row(ui, "Normal bias", |ui| {
        drag_speed(ui, &mut s.normal_bias, 0.0..=f32::INFINITY, 0.05)
    });
    c |= row(ui, "Slope bias", |ui| {
        drag_speed(ui, &mut s.slope_bias, 0.0..=f32::INFINITY, 0.05)
    });
    if kind == LightKind::Directional {
        c |= row(ui, "Cascades", |ui| {
            ui.add(egui::Slider::new(&mut s.cascades, 1..=4)).changed()
        });
        c |= row(ui, "Angular radius (°)", |ui| {
            drag_speed(ui, &mut light.angular_radius_deg, 0.0..=45.0, 0.01)
        });
    } else {
        c |= row(ui, "Radius (m)", |ui| {
            drag_speed(ui, &mut light.radius, 0.0..=f32::INFINITY, 0.005)
        });
    }
    // PCSS without a size is not a valid scene: fall back to PCF.
    if let Some(s) = &mut light.shadow {
        if s.method == ShadowMethod::Pcss && light.radius <= 0.0 && light.angular_radius_deg <= 0.0
        {
            s.method = ShadowMethod::Pcf;
            c = true;
        }
    }
    c
}
