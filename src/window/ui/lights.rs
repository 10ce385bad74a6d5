//! The lights panel.

use super::*;

// ---------------------------------------------------------------------------------------------
// Lights.

pub(super) fn kind_name(k: LightKind) -> &'static str {
    match k {
        LightKind::Directional => "directional",
        LightKind::Point => "point",
        LightKind::Spot => "spot",
    }
}

/// Lights listed in the panel, one row each.
const SHOWN_LIGHTS: usize = 64;

pub(super) fn lights_ui(ui: &mut Ui, scene: &mut Scene, expand_all: bool, out: &mut Out) {
    ui.horizontal(|ui| {
        ui.label("Add");
        for kind in [LightKind::Point, LightKind::Directional, LightKind::Spot] {
            if ui.button(kind_name(kind)).clicked() {
                scene.lights.push(default_light(kind, scene.bounds()));
                out.edit(true);
            }
        }
    });
    // Many lights at once: a grid or random field of ranged point lights
    // (scene::edit::light_field), and removing them all.
    ui.horizontal(|ui| {
        ui.label("Add many");
        let id = ui.id().with("luz_add_many");
        let mut n = ui.data_mut(|d| *d.get_temp_mut_or(id, 256u32));
        ui.add(
            egui::DragValue::new(&mut n)
                .range(1..=crate::scene::edit::MAX_ADDED_LIGHTS)
                .speed(4.0),
        );
        ui.data_mut(|d| d.insert_temp(id, n));
        for field in [LightField::Grid, LightField::Random] {
            if ui.button(field.name()).clicked() {
                let bounds = scene.bounds();
                scene.lights.extend(light_field(field, n as usize, bounds));
                out.edit(true);
            }
        }
        if !scene.lights.is_empty() && ui.button("Remove all").clicked() {
            scene.lights.clear();
            out.edit(true);
        }
    });
    if scene.lights.is_empty() {
        ui.label("No lights.");
    }
    let mut remove = None;
    // A panel row per light for the first SHOWN_LIGHTS (thousands of rows would cost every frame).
    if scene.lights.len() > SHOWN_LIGHTS {
        ui.label(format!(
            "{} lights; the first {SHOWN_LIGHTS} are listed",
            scene.lights.len()
        ));
    }
    for (i, light) in scene.lights.iter_mut().enumerate().take(SHOWN_LIGHTS) {
        ui.push_id(("luz_light", i), |ui| {
            CollapsingHeader::new(format!("Light {i}: {}", kind_name(light.kind)))
                .id_salt(("luz_light_header", i))
                .default_open(i == 0)
                .open(expand_all.then_some(true))
                .show(ui, |ui| {
                    out.edit(light_ui(ui, light));
                    if ui.button("Remove").clicked() {
                        remove = Some(i);
                    }
                });
        });
    }
    if let Some(i) = remove {
        scene.lights.remove(i);
        out.edit(true);
    }
}

const LIGHT_KINDS: [(LightKind, &str); 3] = [
    (LightKind::Directional, "directional"),
    (LightKind::Point, "point"),
    (LightKind::Spot, "spot"),
];

pub(super) fn light_ui(ui: &mut Ui, light: &mut Light) -> bool {
    grid(ui, "luz_light_grid", |ui| {
        let mut c = false;
        c |= row(ui, "Type", |ui| {
            let mut k = light.kind;
            let changed = combo(ui, "kind", &mut k, &LIGHT_KINDS);
            if changed {
                set_light_kind(light, k);
            }
            changed
        });
        if light.kind != LightKind::Point {
            c |= row(ui, "Direction", |ui| {
                direction(ui, &mut light.direction, None)
            });
        }
        if light.kind != LightKind::Directional {
            c |= row(ui, "Position", |ui| {
                vec3(ui, &mut light.position, f32::MIN..=f32::MAX, 0.02)
            });
        }
        c |= row(ui, "Colour", |ui| {
            color(ui, &mut light.color, f32::INFINITY)
        });
        c |= row(ui, "Intensity", |ui| {
            intensity(ui, &mut light.intensity, 1000.0)
        });
        if light.kind != LightKind::Directional {
            c |= row(ui, "Falloff", |ui| falloff_ui(ui, &mut light.falloff));
            // Off: infinite range. On: KHR_lights_punctual's window, nothing beyond the range
            // (turning it on or off rebuilds the pipelines: the window is specialised).
            c |= row(ui, "Range (m)", |ui| {
                ui.horizontal(|ui| {
                    let mut on = light.range.is_some();
                    let mut changed = false;
                    if checkbox(ui, &mut on, "") {
                        light.range = on.then_some(10.0);
                        changed = true;
                    }
                    if let Some(range) = &mut light.range {
                        changed |= drag_speed(ui, range, 0.01..=f32::INFINITY, 0.05);
                    }
                    changed
                })
                .inner
            });
        }
        if light.kind == LightKind::Spot {
            c |= row(ui, "Umbra (°)", |ui| {
                let changed = drag_speed(ui, &mut light.umbra_deg, 0.01..=90.0, 0.2);
                if let Some(inner) = &mut light.inner_deg {
                    if *inner >= light.umbra_deg {
                        *inner = light.umbra_deg * 0.99;
                    }
                }
                changed
            });
            c |= row(ui, "Inner (°)", |ui| {
                ui.horizontal(|ui| {
                    let mut on = light.inner_deg.is_some();
                    let mut changed = false;
                    if checkbox(ui, &mut on, "") {
                        light.inner_deg = on.then_some(light.umbra_deg * 0.75);
                        changed = true;
                    }
                    if let Some(inner) = &mut light.inner_deg {
                        let hi = light.umbra_deg * 0.99;
                        changed |= drag_speed(ui, inner, 0.0..=hi, 0.2);
                    }
                    changed
                })
                .inner
            });
            c |= row(ui, "Exponent", |ui| {
                drag(ui, &mut light.exponent, 0.0..=f32::INFINITY)
            });
        }
        c |= super::shadow::shadow_rows(ui, light);
        c
    })
}

/// Falloff of a point or spot light: none, inverse square or classic (c1, c2, c3 ≥ 0).
pub(super) fn falloff_ui(ui: &mut Ui, f: &mut Falloff) -> bool {
    ui.vertical(|ui| {
        #[derive(Clone, Copy, PartialEq)]
        enum K {
            None,
            InverseSquare,
            Classic,
        }
        let mut k = match f {
            Falloff::None => K::None,
            Falloff::InverseSquare => K::InverseSquare,
            Falloff::Classic { .. } => K::Classic,
        };
        const KINDS: [(K, &str); 3] = [
            (K::None, "none"),
            (K::InverseSquare, "inverse square"),
            (K::Classic, "classic f_at"),
        ];
        let mut changed = combo(ui, "falloff", &mut k, &KINDS);
        if changed {
            // The classic coefficients default to the decoder's (c1 = 1, c2 = c3 = 0).
            *f = match k {
                K::None => Falloff::None,
                K::InverseSquare => Falloff::InverseSquare,
                K::Classic => Falloff::Classic {
                    c1: 1.0,
                    c2: 0.0,
                    c3: 0.0,
                },
            };
        }
        if let Falloff::Classic { c1, c2, c3 } = f {
            ui.horizontal(|ui| {
                for (name, c) in [("c1", c1), ("c2", c2), ("c3", c3)] {
                    ui.label(name);
                    changed |= drag_speed(ui, c, 0.0..=f32::INFINITY, 0.005);
                }
            });
        }
        changed
    })
    .inner
}
