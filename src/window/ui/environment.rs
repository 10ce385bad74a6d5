//! The environment panel (procedural sky, uniform or HDR image; IBL methods).

use super::*;

// ---------------------------------------------------------------------------------------------
// Environment.

#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum EnvKind {
    None,
    Sky,
    Studio,
    Uniform,
    File,
}

const ENV_SOURCES: [(EnvKind, &str); 5] = [
    (EnvKind::None, "none"),
    (EnvKind::Sky, "procedural sky"),
    (EnvKind::Studio, "studio"),
    (EnvKind::Uniform, "uniform"),
    (EnvKind::File, "file (.hdr / .exr)"),
];

const SPECULAR_METHODS: [(SpecularMethod, &str); 3] = [
    (SpecularMethod::SplitSum, "split sum"),
    (SpecularMethod::FittedLobes, "fitted lobes"),
    (SpecularMethod::Importance, "importance sampling"),
];

const DIFFUSE_METHODS: [(DiffuseMethod, &str); 2] = [
    (DiffuseMethod::Sh9, "SH9"),
    (DiffuseMethod::Cubemap, "convolved cubemap"),
];

pub(super) fn environment_ui(ui: &mut Ui, scene: &mut Scene, state: &mut UiState, out: &mut Out) {
    let current = match scene.environment.as_ref().map(|e| &e.source) {
        None => EnvKind::None,
        Some(EnvSource::Sky { .. }) => EnvKind::Sky,
        Some(EnvSource::Studio) => EnvKind::Studio,
        Some(EnvSource::Uniform(_)) => EnvKind::Uniform,
        Some(EnvSource::Hdr(_)) => EnvKind::File,
    };
    if current == EnvKind::File {
        state.env_file_pending = false;
    }
    let shown = if state.env_file_pending {
        EnvKind::File
    } else {
        current
    };
    let mut k = shown;
    let changed = ui
        .horizontal(|ui| {
            ui.label("Source");
            combo(ui, "luz_env_source", &mut k, &ENV_SOURCES)
        })
        .inner;
    if changed {
        state.env_file_pending = k == EnvKind::File && current != EnvKind::File;
        let source = match k {
            EnvKind::None => None,
            EnvKind::Sky => Some(EnvSource::Sky {
                sun_direction: DEFAULT_SUN_DIRECTION.normalize(),
                sun_intensity: DEFAULT_SUN_INTENSITY,
            }),
            EnvKind::Studio => Some(EnvSource::Studio),
            EnvKind::Uniform => Some(EnvSource::Uniform(Vec3::splat(0.5))),
            // Set by the app once the file loads.
            EnvKind::File => None,
        };
        if k == EnvKind::None {
            out.edit(scene.environment.take().is_some());
        } else if let Some(source) = source.filter(|_| k != current) {
            match &mut scene.environment {
                // Keep the integration settings, change the source.
                Some(env) => env.source = source,
                None => scene.environment = Some(Environment::new(source)),
            }
            out.edit(true);
        }
    }
    if shown == EnvKind::File || (changed && k == EnvKind::File) {
        ui.horizontal(|ui| {
            ui.add(
                egui::TextEdit::singleline(&mut state.env_path)
                    .hint_text("environment.hdr")
                    .desired_width(200.0),
            );
            let path = state.env_path.trim();
            if ui
                .add_enabled(!path.is_empty(), egui::Button::new("Load"))
                .clicked()
            {
                out.actions
                    .push(UiAction::OpenEnvironmentFile(PathBuf::from(path)));
            }
        });
    }
    let Some(env) = &mut scene.environment else {
        return;
    };
    let changed = grid(ui, "luz_env_grid", |ui| {
        let mut c = false;
        match &mut env.source {
            EnvSource::Sky {
                sun_direction,
                sun_intensity,
            } => {
                c |= row(ui, "Sun direction", |ui| {
                    direction(ui, sun_direction, Some(0.0))
                });
                c |= row(ui, "Sun intensity", |ui| {
                    slider(ui, sun_intensity, 0.0..=MAX_SUN_INTENSITY, false)
                });
            }
            EnvSource::Uniform(radiance) => {
                c |= row(ui, "Radiance", |ui| color(ui, radiance, f32::INFINITY));
            }
            EnvSource::Hdr(path) => {
                ui.label("File");
                ui.label(path.display().to_string());
                ui.end_row();
            }
            EnvSource::Studio => {}
        }
        c |= row(ui, "Intensity", |ui| {
            intensity(ui, &mut env.intensity, 100.0)
        });
        c |= row(ui, "Rotation (°)", |ui| {
            drag_speed(ui, &mut env.rotation_deg, -36000.0..=36000.0, 0.5)
        });
        c |= row(ui, "Specular", |ui| {
            combo(
                ui,
                "luz_env_specular",
                &mut env.specular_method,
                &SPECULAR_METHODS,
            )
        });
        if env.specular_method == SpecularMethod::Importance {
            c |= row(ui, "Samples", |ui| {
                let mut n = env.samples;
                let r = ui.add(
                    DragValue::new(&mut n)
                        .range(1..=MAX_ENV_SAMPLES)
                        .clamp_existing_to_range(false)
                        .speed(1.0),
                );
                let n = n.clamp(1, MAX_ENV_SAMPLES);
                if r.changed() && n != env.samples {
                    env.samples = n;
                    true
                } else {
                    false
                }
            });
            c |= row(ui, "Mip-filtered samples", |ui| {
                checkbox(ui, &mut env.mip_filtered_samples, "")
            });
        }
        c |= row(ui, "Diffuse", |ui| {
            combo(
                ui,
                "luz_env_diffuse",
                &mut env.diffuse_method,
                &DIFFUSE_METHODS,
            )
        });
        c |= row(ui, "Energy compensation", |ui| {
            checkbox(ui, &mut env.energy_compensation, "")
        });
        c |= row(ui, "Show background", |ui| {
            checkbox(ui, &mut env.show_background, "")
        });
        c
    });
    out.edit(changed);
}
