//! The file actions and the scene settings panel (camera, output, ambient, fog, saturation, debug view).

use super::*;

// ---------------------------------------------------------------------------------------------
// File.

pub(super) fn file_ui(ui: &mut Ui, state: &mut UiState, out: &mut Out) {
    ui.horizontal(|ui| {
        ui.label("Scene file");
        ui.add(
            egui::TextEdit::singleline(&mut state.scene_path)
                .hint_text("scenes/my_scene.json")
                .desired_width(f32::INFINITY),
        );
    });
    let path = state.scene_path.trim();
    ui.horizontal(|ui| {
        if ui
            .add_enabled(!path.is_empty(), egui::Button::new("Open"))
            .clicked()
        {
            out.actions.push(UiAction::Open(PathBuf::from(path)));
        }
        if ui
            .add_enabled(!path.is_empty(), egui::Button::new("Save as"))
            .clicked()
        {
            out.actions.push(UiAction::Save(PathBuf::from(path)));
        }
    });
    ui.horizontal(|ui| {
        if ui.button("Screenshot PNG").clicked() {
            out.actions.push(UiAction::Screenshot { exr: false });
        }
        if ui.button("Screenshot EXR").clicked() {
            out.actions.push(UiAction::Screenshot { exr: true });
        }
    });
    ui.horizontal(|ui| {
        if ui.button("Reset camera").clicked() {
            out.actions.push(UiAction::ResetCamera);
        }
        if ui.button("Frame all").clicked() {
            out.actions.push(UiAction::FrameAll);
        }
    });
    if let Some(m) = &state.message {
        ui.label(m.as_str());
    }
}

// ---------------------------------------------------------------------------------------------
// Scene settings.

pub(super) fn debug_view_name(v: DebugView) -> String {
    v.name().to_string()
}

const SATURATIONS: [(Saturation, &str); 3] = [
    (Saturation::Clamp, "clamp"),
    (Saturation::Normalize, "normalize"),
    (Saturation::None, "none"),
];

pub(super) fn scene_ui(ui: &mut Ui, scene: &mut Scene, settings: &mut ViewSettings, out: &mut Out) {
    let near = scene.camera.near;
    let far = scene.camera.far;
    let changed = grid(ui, "luz_scene_grid", |ui| {
        let mut c = false;
        c |= row(ui, "Ambient", |ui| {
            color(ui, &mut scene.ambient, f32::INFINITY)
        });
        c |= row(ui, "Background", |ui| {
            color(ui, &mut scene.output.background, f32::INFINITY)
        });
        c |= row(ui, "Exposure (EV)", |ui| {
            drag_speed(ui, &mut scene.output.exposure, -64.0..=64.0, 0.05)
        });
        c |= row(ui, "Tone mapping", |ui| {
            let options: Vec<(Tonemap, &str)> =
                Tonemap::ALL.iter().map(|t| (*t, t.name())).collect();
            combo(ui, "luz_tonemap", &mut scene.output.tonemap, &options)
        });
        c |= row(ui, "Saturation", |ui| {
            combo(ui, "luz_saturation", &mut scene.saturation, &SATURATIONS)
        });
        c
    });
    out.edit(changed);

    // Fog (depth cueing).
    let mut on = scene.fog.is_some();
    if checkbox(ui, &mut on, "Fog (depth cueing)") {
        scene.fog = on.then_some(Fog {
            z_a: near,
            z_b: far,
            s_a: 0.0,
            s_b: 1.0,
            color: scene.output.background,
        });
        out.edit(true);
    }
    if let Some(fog) = &mut scene.fog {
        let changed = grid(ui, "luz_fog_grid", |ui| fog_ui(ui, fog));
        out.edit(changed);
    }

    ui.separator();
    grid(ui, "luz_view_grid", |ui| {
        row(ui, "Debug view", |ui| {
            let mut v = settings.debug_view;
            let mut changed = false;
            ComboBox::from_id_salt("luz_debug_view")
                .selected_text(debug_view_name(v))
                .show_ui(ui, |ui| {
                    for o in &DebugView::ALL {
                        changed |= ui
                            .selectable_value(&mut v, *o, debug_view_name(*o))
                            .changed();
                    }
                });
            if changed && v != settings.debug_view {
                settings.debug_view = v;
                out.actions.push(UiAction::DebugViewChanged);
            }
            false
        });
        row(ui, "Shadow maps", |ui| {
            checkbox(ui, &mut settings.shadow_maps, "show the window")
        });
        row(ui, "Vsync", |ui| {
            if checkbox(ui, &mut settings.vsync, "") {
                out.actions.push(UiAction::VsyncChanged);
            }
            false
        });
        false
    });
}

/// Fog fields: 0 ≤ z_a < z_b, s_a and s_b in [0, 1], colour ≥ 0.
pub(super) fn fog_ui(ui: &mut Ui, fog: &mut Fog) -> bool {
    let mut c = false;
    c |= row(ui, "z_a (start)", |ui| {
        let hi = (fog.z_b - fog_gap(fog.z_b)).max(0.0);
        drag(ui, &mut fog.z_a, 0.0..=hi)
    });
    c |= row(ui, "z_b (end)", |ui| {
        let lo = fog.z_a + fog_gap(fog.z_a);
        drag(ui, &mut fog.z_b, lo..=f32::MAX)
    });
    c |= row(ui, "s_a (near)", |ui| unit(ui, &mut fog.s_a));
    c |= row(ui, "s_b (far)", |ui| unit(ui, &mut fog.s_b));
    c |= row(ui, "Colour", |ui| color(ui, &mut fog.color, f32::INFINITY));
    // Keep z_b > z_a whatever happened (e.g. z_a edited to the top of its range).
    if fog.z_b <= fog.z_a {
        fog.z_b = fog.z_a + fog_gap(fog.z_a);
    }
    c
}
