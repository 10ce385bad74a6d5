//! A light's shadow rows in the lights panel: on/off, method, resolution, kernel, biases,
//! cascades and the light's size. Method, resolution and cascades rebuild the passes; the rest
//! take effect on the next frame.

use super::*;
use crate::scene::edit::{
    edit_shadow, fix_shadow_method, has_size, ShadowEdit, SHADOW_RESOLUTIONS,
};
use crate::scene::ShadowMethod;

/// The rows; every change of the checkbox, method or resolution goes through
/// [`edit_shadow`], as the script's `light_shadow` and `light_shadow_resolution` do.
pub(super) fn shadow_rows(ui: &mut Ui, light: &mut Light) -> bool {
    let mut on = light.shadow.is_some();
    let mut c = row(ui, "Shadow", |ui| checkbox(ui, &mut on, ""))
        && edit_shadow(light, if on { ShadowEdit::On } else { ShadowEdit::Off }).unwrap_or(false);
    let kind = light.kind;
    let sized = has_size(light);
    let Some(current) = light.shadow else {
        return c;
    };
    let mut method = current.method;
    if row(ui, "Method", |ui| {
        let mut options = vec![(ShadowMethod::Hard, "hard"), (ShadowMethod::Pcf, "pcf")];
        // PCSS needs the light's size (set below).
        if sized {
            options.push((ShadowMethod::Pcss, "pcss"));
        }
        combo(ui, ui.id().with("shadow_method"), &mut method, &options)
    }) {
        c |= edit_shadow(light, ShadowEdit::Method(method)).unwrap_or(false);
    }
    let mut resolution = current.resolution;
    if row(ui, "Resolution", |ui| {
        let labels = SHADOW_RESOLUTIONS.map(|r| (r, format!("{r}²")));
        let options: Vec<(u32, &str)> = labels.iter().map(|(r, t)| (*r, t.as_str())).collect();
        combo(
            ui,
            ui.id().with("shadow_resolution"),
            &mut resolution,
            &options,
        )
    }) {
        c |= edit_shadow(light, ShadowEdit::Resolution(resolution)).unwrap_or(false);
    }
    let Some(s) = &mut light.shadow else {
        return c;
    };
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
    c |= fix_shadow_method(light);
    c
}
