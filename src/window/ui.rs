//! egui panels of the viewer: scene editing (lights, objects and materials, scene settings,
//! environment), file actions, the frame-time profiler and the key help.
//!
//! [`draw`] runs once per frame inside `egui::Context::run_ui` and returns what the app must do
//! ([`UiAction`]). Every edit keeps the scene valid by the rules of the scene decoder
//! (`src/scene/decode*.rs`, `docs/scene-format.md`): numbers stay finite and in range, directions
//! stay unit length, and a material's texture maps stay those its model takes. Widgets edit a copy
//! of each value and write it back only when the user changed it, so a frame without input never
//! touches the scene (and never reports [`UiAction::SceneEdited`]).

use std::ops::RangeInclusive;
use std::path::PathBuf;

use egui::{
    Align2, CollapsingHeader, Color32, ComboBox, DragValue, FontId, Grid, Id, Panel, Pos2,
    ScrollArea, Sense, Slider, SliderClamping, Stroke, Ui, Vec2,
};
use glam::{DVec3, Vec3};

use crate::brdf::{
    dielectric_ior, metal_preset, ComplexIor, CookTorranceParams, Diffuse, Distribution, Fresnel,
    Geometry, MetalRoughParams, OrenNayarParams, PrincipledParams, SpecularSource,
    DIELECTRIC_NAMES, METAL_NAMES,
};
use crate::color::Tonemap;
use crate::profiler::Profiler;
use crate::render::forward::DebugView;
use crate::scene::{
    slots_for_model, DiffuseMethod, EnvSource, Environment, Falloff, Fog, Light, LightKind,
    Material, Saturation, Scene, Shading, SpecularMethod, DEFAULT_SUN_DIRECTION,
    DEFAULT_SUN_INTENSITY, MAX_ENV_SAMPLES, MAX_SUN_INTENSITY,
};

/// Viewer settings that are not part of the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewSettings {
    pub debug_view: DebugView,
    pub vsync: bool,
    /// The key help window.
    pub show_help: bool,
    /// The side and profiler panels (Tab).
    pub show_panels: bool,
}

impl Default for ViewSettings {
    fn default() -> Self {
        ViewSettings {
            debug_view: DebugView::None,
            vsync: true,
            show_help: false,
            show_panels: true,
        }
    }
}

/// What the app must do after a frame of UI.
#[derive(Debug, Clone, PartialEq)]
pub enum UiAction {
    /// The scene was changed in place (at most once per frame). Structural changes (lights
    /// added or removed, a material's model, an object's shading, the environment) are included:
    /// the app compares what it needs to.
    SceneEdited,
    /// Write the scene to this file.
    Save(PathBuf),
    /// Load this scene file instead of the current one.
    Open(PathBuf),
    /// Use this equirectangular `.hdr`/`.exr` file as the environment (the app validates it and
    /// sets `EnvSource::Hdr`, keeping the other environment settings).
    OpenEnvironmentFile(PathBuf),
    /// Save the current frame: PNG (display-encoded) or EXR (linear radiance).
    Screenshot {
        exr: bool,
    },
    ResetCamera,
    FrameAll,
    /// `ViewSettings::vsync` changed.
    VsyncChanged,
    /// `ViewSettings::debug_view` changed.
    DebugViewChanged,
}

/// UI state kept between frames.
#[derive(Debug, Default)]
pub struct UiState {
    /// Index into `Scene::objects` of the object shown in the Objects panel.
    pub selected_object: usize,
    /// The File panel's path field.
    pub scene_path: String,
    /// The Environment panel's file field.
    pub env_path: String,
    /// A one-line message shown in the File panel (set by the app, e.g. a load error).
    pub message: Option<String>,
    /// "file" was chosen as the environment source but no file is loaded yet.
    env_file_pending: bool,
    initialized: bool,
    /// Every collapsing header open (tests: draw every widget).
    expand_all: bool,
    /// `Scene::source` when the fields were last filled: another scene resets them.
    source: Option<PathBuf>,
}

impl UiState {
    /// Fills the path fields from `scene` and selects its first object (done by [`draw`] on its
    /// first frame and whenever `Scene::source` changes, i.e. another scene was loaded).
    pub fn reset_for(&mut self, scene: &Scene) {
        self.scene_path = scene
            .source
            .as_ref()
            .map(|p| p.display().to_string())
            .unwrap_or_default();
        self.env_path = match scene.environment.as_ref().map(|e| &e.source) {
            Some(EnvSource::Hdr(p)) => p.display().to_string(),
            _ => String::new(),
        };
        self.env_file_pending = false;
        self.selected_object = 0;
        self.source = scene.source.clone();
        self.initialized = true;
    }
}

/// Keys of the viewer, for the help window: (key, what it does).
pub const KEYS: &[(&str, &str)] = &[
    ("Left drag", "orbit"),
    ("Middle drag / Shift+left drag", "pan"),
    ("Wheel", "zoom"),
    ("R", "reset camera"),
    ("F", "frame all"),
    ("P", "screenshot PNG"),
    ("Shift+P", "screenshot EXR"),
    ("H or F1", "this help"),
    ("Tab", "hide/show panels"),
    ("V", "vsync on/off"),
    ("Esc", "quit"),
];

/// Collects the frame's actions; `edited` becomes one [`UiAction::SceneEdited`].
#[derive(Default)]
struct Out {
    actions: Vec<UiAction>,
    edited: bool,
}

impl Out {
    fn edit(&mut self, changed: bool) {
        self.edited |= changed;
    }
}

/// Draws the viewer's UI for one frame into `ui`, the root `Ui` of `egui::Context::run_ui`
/// (egui 0.36 panels are shown inside a `Ui`; the root one keeps
/// `Context::is_pointer_over_egui` right for the camera controls). Keys are the app's to handle;
/// this only lists them ([`KEYS`]).
pub fn draw(
    ui: &mut Ui,
    scene: &mut Scene,
    settings: &mut ViewSettings,
    profiler: &Profiler,
    state: &mut UiState,
) -> Vec<UiAction> {
    if !state.initialized || state.source != scene.source {
        state.reset_for(scene);
    }
    let mut out = Out::default();
    if settings.show_panels {
        Panel::left(Id::new("luz_scene_panel"))
            .resizable(true)
            .default_size(330.0)
            .show(ui, |ui| {
                ScrollArea::vertical().show(ui, |ui| {
                    let all = state.expand_all;
                    section(ui, "File", true, all, |ui| file_ui(ui, state, &mut out));
                    section(ui, "Scene", true, all, |ui| {
                        scene_ui(ui, scene, settings, &mut out)
                    });
                    section(ui, "Lights", false, all, |ui| {
                        lights_ui(ui, scene, all, &mut out)
                    });
                    section(ui, "Objects", false, all, |ui| {
                        objects_ui(ui, scene, state, &mut out)
                    });
                    section(ui, "Environment", false, all, |ui| {
                        environment_ui(ui, scene, state, &mut out)
                    });
                });
            });
        Panel::bottom(Id::new("luz_profiler_panel"))
            .resizable(true)
            .default_size(170.0)
            .show(ui, |ui| profiler_ui(ui, profiler));
    } else {
        compact_profiler(ui.ctx(), profiler);
    }
    if settings.show_help {
        egui::Window::new("Keys")
            .open(&mut settings.show_help)
            .collapsible(false)
            .resizable(false)
            .anchor(Align2::CENTER_CENTER, Vec2::ZERO)
            .show(ui.ctx(), |ui| {
                Grid::new("luz_keys").num_columns(2).show(ui, |ui| {
                    for (key, what) in KEYS {
                        ui.strong(*key);
                        ui.label(*what);
                        ui.end_row();
                    }
                });
            });
    }
    if out.edited {
        out.actions.push(UiAction::SceneEdited);
    }
    out.actions
}

fn section(ui: &mut Ui, title: &str, open: bool, expand_all: bool, add: impl FnOnce(&mut Ui)) {
    CollapsingHeader::new(title)
        .default_open(open)
        .open(expand_all.then_some(true))
        .show(ui, add);
}

// ---------------------------------------------------------------------------------------------
// Widgets that edit a copy and write back only on a user edit, within the valid range.

/// Writes `x` into `v` when the user `changed` it and it is finite; clamped to `range`.
fn commit(v: &mut f32, x: f32, range: &RangeInclusive<f32>, changed: bool) -> bool {
    if !changed || !x.is_finite() {
        return false;
    }
    let x = x.clamp(*range.start(), *range.end());
    if x == *v {
        return false;
    }
    *v = x;
    true
}

/// A drag value in `range` (ends may be infinite); the speed follows the value's magnitude.
fn drag(ui: &mut Ui, v: &mut f32, range: RangeInclusive<f32>) -> bool {
    let speed = (v.abs() * 0.01).max(0.005);
    drag_speed(ui, v, range, speed)
}

fn drag_speed(ui: &mut Ui, v: &mut f32, range: RangeInclusive<f32>, speed: f32) -> bool {
    let mut x = *v;
    let r = ui.add(
        DragValue::new(&mut x)
            .range(range.clone())
            .clamp_existing_to_range(false)
            .speed(speed)
            .max_decimals(4),
    );
    commit(v, x, &range, r.changed())
}

/// A slider in a finite `range`, logarithmic if asked.
fn slider(ui: &mut Ui, v: &mut f32, range: RangeInclusive<f32>, log: bool) -> bool {
    let mut x = *v;
    let r = ui.add(
        Slider::new(&mut x, range.clone())
            .logarithmic(log)
            .clamping(SliderClamping::Edits)
            .max_decimals(4),
    );
    commit(v, x, &range, r.changed())
}

/// A [0, 1] parameter.
fn unit(ui: &mut Ui, v: &mut f32) -> bool {
    slider(ui, v, 0.0..=1.0, false)
}

/// A drag value plus a logarithmic slider for a non-negative quantity (intensities).
fn intensity(ui: &mut Ui, v: &mut f32, slider_max: f32) -> bool {
    ui.horizontal(|ui| {
        let a = drag(ui, v, 0.0..=f32::INFINITY);
        let mut s = v.min(slider_max);
        let before = s;
        let b = slider(ui, &mut s, 0.0..=slider_max, true) && s != before;
        if b {
            *v = s;
        }
        a || b
    })
    .inner
}

fn checkbox(ui: &mut Ui, v: &mut bool, text: &str) -> bool {
    let mut x = *v;
    let r = ui.checkbox(&mut x, text);
    if r.changed() && x != *v {
        *v = x;
        true
    } else {
        false
    }
}

/// Three drag values, each clamped to `range`.
fn vec3(ui: &mut Ui, v: &mut Vec3, range: RangeInclusive<f32>, speed: f32) -> bool {
    ui.horizontal(|ui| {
        let mut changed = false;
        for (i, axis) in ["x", "y", "z"].into_iter().enumerate() {
            let mut x = v[i];
            let r = ui.add(
                DragValue::new(&mut x)
                    .range(range.clone())
                    .clamp_existing_to_range(false)
                    .speed(speed)
                    .max_decimals(4)
                    .prefix(format!("{axis} ")),
            );
            changed |= commit(&mut v[i], x, &range, r.changed());
        }
        changed
    })
    .inner
}

/// Unit vector of `v` (in f64, like the decoder); `None` for a zero or non-finite vector.
fn unit_vec(v: Vec3) -> Option<Vec3> {
    let d = DVec3::new(f64::from(v.x), f64::from(v.y), f64::from(v.z));
    let len = d.length();
    (len > 1e-12 && len.is_finite()).then(|| (d / len).as_vec3())
}

/// A unit direction: three components, normalised on edit; an edit that would make it zero
/// (or, with `max_y`, point above that y) is refused.
fn direction(ui: &mut Ui, v: &mut Vec3, max_y: Option<f32>) -> bool {
    let mut x = *v;
    if !vec3(ui, &mut x, -1.0..=1.0, 0.01) {
        return false;
    }
    if let Some(m) = max_y {
        x.y = x.y.min(m);
    }
    match unit_vec(x) {
        Some(d) if max_y.is_none_or(|m| d.y <= m) && d != *v => {
            *v = d;
            true
        }
        _ => false,
    }
}

/// A linear RGB colour, each channel in [0, `max`] (`max` may be infinite): a colour picker
/// (scaled to the brightest channel when that exceeds 1) and three channels.
fn color(ui: &mut Ui, v: &mut Vec3, max: f32) -> bool {
    ui.horizontal(|ui| {
        let mut changed = false;
        let scale = v.max_element().max(1.0);
        let mut shown = (*v / scale).to_array();
        if egui::color_picker::color_edit_button_rgb(ui, &mut shown).changed() {
            let c = (Vec3::from_array(shown) * scale).clamp(Vec3::ZERO, Vec3::splat(max));
            if c.is_finite() && c != *v {
                *v = c;
                changed = true;
            }
        }
        for (i, ch) in ["r", "g", "b"].into_iter().enumerate() {
            let mut x = v[i];
            let r = ui.add(
                DragValue::new(&mut x)
                    .range(0.0..=max)
                    .clamp_existing_to_range(false)
                    .speed(0.005 * scale)
                    .max_decimals(3)
                    .prefix(format!("{ch} ")),
            );
            changed |= commit(&mut v[i], x, &(0.0..=max), r.changed());
        }
        changed
    })
    .inner
}

/// A combo box over `options` (value, label).
fn combo<T: PartialEq + Copy>(
    ui: &mut Ui,
    id_salt: impl egui::AsIdSalt,
    v: &mut T,
    options: &[(T, &str)],
) -> bool {
    let current = options
        .iter()
        .find(|(o, _)| o == v)
        .map_or("?", |(_, n)| *n);
    let mut x = *v;
    let mut changed = false;
    ComboBox::from_id_salt(id_salt)
        .selected_text(current)
        .show_ui(ui, |ui| {
            for (o, name) in options {
                changed |= ui.selectable_value(&mut x, *o, *name).changed();
            }
        });
    if changed && x != *v {
        *v = x;
        true
    } else {
        false
    }
}

/// A label in the first column of a two-column grid.
fn row(ui: &mut Ui, label: &str, add: impl FnOnce(&mut Ui) -> bool) -> bool {
    ui.label(label);
    let changed = add(ui);
    ui.end_row();
    changed
}

fn grid(ui: &mut Ui, id_salt: impl egui::AsIdSalt, add: impl FnOnce(&mut Ui) -> bool) -> bool {
    Grid::new(id_salt)
        .num_columns(2)
        .spacing([8.0, 4.0])
        .show(ui, add)
        .inner
}

// ---------------------------------------------------------------------------------------------
// File.

fn file_ui(ui: &mut Ui, state: &mut UiState, out: &mut Out) {
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

fn debug_view_name(v: DebugView) -> String {
    v.name().to_string()
}

fn scene_ui(ui: &mut Ui, scene: &mut Scene, settings: &mut ViewSettings, out: &mut Out) {
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
            combo(
                ui,
                "luz_saturation",
                &mut scene.saturation,
                &[
                    (Saturation::Clamp, "clamp"),
                    (Saturation::Normalize, "normalize"),
                    (Saturation::None, "none"),
                ],
            )
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
fn fog_ui(ui: &mut Ui, fog: &mut Fog) -> bool {
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

/// Smallest separation kept between the fog's z_a and z_b.
fn fog_gap(z: f32) -> f32 {
    (z.abs() * 1e-3).max(1e-3)
}

// ---------------------------------------------------------------------------------------------
// Lights.

fn kind_name(k: LightKind) -> &'static str {
    match k {
        LightKind::Directional => "directional",
        LightKind::Point => "point",
        LightKind::Spot => "spot",
    }
}

/// A new light of `kind` with sensible defaults, placed for a scene whose objects span `bounds`.
pub fn default_light(kind: LightKind, bounds: Option<(Vec3, Vec3)>) -> Light {
    let (lo, hi) = bounds.unwrap_or((Vec3::splat(-1.0), Vec3::splat(1.0)));
    let centre = (lo + hi) * 0.5;
    let size = (hi - lo).length().max(1.0);
    let above = centre + Vec3::new(0.0, size, 0.0);
    let base = Light {
        kind,
        direction: Vec3::NEG_Y,
        position: above,
        color: Vec3::ONE,
        intensity: 1.0,
        falloff: Falloff::InverseSquare,
        umbra_deg: 180.0,
        inner_deg: None,
        exponent: 0.0,
    };
    match kind {
        LightKind::Directional => Light {
            direction: Vec3::new(-0.4, -1.0, -0.5).normalize(),
            position: Vec3::ZERO,
            falloff: Falloff::None,
            ..base
        },
        // About irradiance 1 at the scene's centre.
        LightKind::Point => Light {
            position: centre + Vec3::new(0.5, 1.0, 0.5) * size * 0.7,
            intensity: size * size,
            ..base
        },
        LightKind::Spot => Light {
            intensity: 2.0 * size * size,
            umbra_deg: 30.0,
            inner_deg: Some(20.0),
            ..base
        },
    }
}

/// Changes a light's kind, keeping what carries over and resetting what the new kind fixes
/// (the decoder's values: point lights point down, non-spots have umbra 180°, no inner cone and
/// exponent 0, directional lights have no falloff).
pub fn set_light_kind(light: &mut Light, kind: LightKind) {
    if light.kind == kind {
        return;
    }
    let from = light.kind;
    light.kind = kind;
    match kind {
        LightKind::Directional => {
            light.falloff = Falloff::None;
            light.umbra_deg = 180.0;
            light.inner_deg = None;
            light.exponent = 0.0;
            if from == LightKind::Point {
                light.direction = Vec3::new(-0.4, -1.0, -0.5).normalize();
            }
        }
        LightKind::Point => {
            light.direction = Vec3::NEG_Y;
            light.umbra_deg = 180.0;
            light.inner_deg = None;
            light.exponent = 0.0;
            if from == LightKind::Directional {
                light.falloff = Falloff::InverseSquare;
            }
        }
        LightKind::Spot => {
            light.umbra_deg = 30.0;
            light.inner_deg = None;
            light.exponent = 0.0;
            if from == LightKind::Directional {
                light.falloff = Falloff::InverseSquare;
            }
        }
    }
}

fn lights_ui(ui: &mut Ui, scene: &mut Scene, expand_all: bool, out: &mut Out) {
    ui.horizontal(|ui| {
        ui.label("Add");
        for kind in [LightKind::Point, LightKind::Directional, LightKind::Spot] {
            if ui.button(kind_name(kind)).clicked() {
                scene.lights.push(default_light(kind, scene.bounds()));
                out.edit(true);
            }
        }
    });
    if scene.lights.is_empty() {
        ui.label("No lights.");
    }
    let mut remove = None;
    for (i, light) in scene.lights.iter_mut().enumerate() {
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

fn light_ui(ui: &mut Ui, light: &mut Light) -> bool {
    grid(ui, "luz_light_grid", |ui| {
        let mut c = false;
        c |= row(ui, "Type", |ui| {
            let mut k = light.kind;
            let changed = combo(
                ui,
                "kind",
                &mut k,
                &[
                    (LightKind::Directional, "directional"),
                    (LightKind::Point, "point"),
                    (LightKind::Spot, "spot"),
                ],
            );
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
        c
    })
}

/// Falloff of a point or spot light: none, inverse square or classic (c1, c2, c3 ≥ 0).
fn falloff_ui(ui: &mut Ui, f: &mut Falloff) -> bool {
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
        let mut changed = combo(
            ui,
            "falloff",
            &mut k,
            &[
                (K::None, "none"),
                (K::InverseSquare, "inverse square"),
                (K::Classic, "classic f_at"),
            ],
        );
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

// ---------------------------------------------------------------------------------------------
// Objects and materials.

fn objects_ui(ui: &mut Ui, scene: &mut Scene, state: &mut UiState, out: &mut Out) {
    if scene.objects.is_empty() {
        ui.label("No objects.");
        return;
    }
    state.selected_object = state.selected_object.min(scene.objects.len() - 1);
    ComboBox::from_id_salt("luz_object")
        .selected_text(scene.objects[state.selected_object].name.as_str())
        .show_ui(ui, |ui| {
            for (i, o) in scene.objects.iter().enumerate() {
                ui.selectable_value(&mut state.selected_object, i, o.name.as_str());
            }
        });
    let material_names: Vec<String> = scene.materials.iter().map(|m| m.name.clone()).collect();
    let object = &mut scene.objects[state.selected_object];
    let changed = grid(ui, "luz_object_grid", |ui| {
        let mut c = false;
        let t = &mut object.transform;
        c |= row(ui, "Position", |ui| {
            vec3(ui, &mut t.position, f32::MIN..=f32::MAX, 0.02)
        });
        c |= row(ui, "Rotation (°)", |ui| {
            vec3(ui, &mut t.rotation_deg, -36000.0..=36000.0, 0.5)
        });
        c |= row(ui, "Scale", |ui| vec3(ui, &mut t.scale, 1e-3..=1e6, 0.01));
        c |= row(ui, "Shading", |ui| {
            combo(
                ui,
                "luz_shading",
                &mut object.shading,
                &[
                    (Shading::Flat, "flat"),
                    (Shading::Gouraud, "Gouraud"),
                    (Shading::Phong, "Phong"),
                ],
            )
        });
        c |= row(ui, "Material", |ui| {
            let mut m = object.material;
            let mut changed = false;
            ComboBox::from_id_salt("luz_object_material")
                .selected_text(material_names.get(m).map_or("?", String::as_str))
                .show_ui(ui, |ui| {
                    for (i, name) in material_names.iter().enumerate() {
                        changed |= ui.selectable_value(&mut m, i, name.as_str()).changed();
                    }
                });
            if changed && m != object.material && m < material_names.len() {
                object.material = m;
                true
            } else {
                false
            }
        });
        c
    });
    out.edit(changed);

    let mi = scene.objects[state.selected_object].material;
    let users = scene.objects.iter().filter(|o| o.material == mi).count();
    let Some(named) = scene.materials.get_mut(mi) else {
        return;
    };
    ui.separator();
    ui.label(format!(
        "Material \"{}\"{}",
        named.name,
        if users > 1 {
            format!(" (shared by {users} objects)")
        } else {
            String::new()
        }
    ));
    let mut model = named.material.name();
    let models = [
        "phong",
        "blinn_phong",
        "lambert",
        "cook_torrance",
        "metal_rough",
        "principled",
        "oren_nayar",
    ];
    let options: Vec<(&str, &str)> = models.iter().map(|m| (*m, *m)).collect();
    if combo(ui, ("luz_model", mi), &mut model, &options) {
        set_material_model(&mut named.material, &mut named.textures, model);
        out.edit(true);
    }
    let changed = ui
        .push_id(("luz_material", mi), |ui| {
            material_ui(ui, &mut named.material)
        })
        .inner;
    out.edit(changed);
    let maps: Vec<&str> = named.textures.maps().map(|(s, _)| s.name()).collect();
    if !maps.is_empty() {
        ui.label(format!("Texture maps: {}", maps.join(", ")));
    }
}

/// The material `model` (a scene-format model name) with its defaults, as the decoder makes it
/// when a material gives only its model. Unknown names give the classic Phong.
pub fn default_material(model: &str) -> Material {
    match model {
        "blinn_phong" => Material::default_phong(true),
        "lambert" => Material::Lambert(crate::brdf::LambertParams {
            albedo: crate::brdf::LambertParams::default().albedo,
        }),
        "cook_torrance" => Material::CookTorrance(CookTorranceParams::default()),
        "metal_rough" => Material::MetalRough(MetalRoughParams::default()),
        "principled" => Material::Principled(PrincipledParams::default()),
        "oren_nayar" => Material::OrenNayar(OrenNayarParams::default()),
        _ => Material::default_phong(false),
    }
}

/// Switches a material to another model: Phong ↔ Blinn-Phong only flips `blinn`; any other
/// switch replaces the material with the model's defaults. Texture maps the new model does not
/// take are dropped (the decoder rejects them).
pub fn set_material_model(
    material: &mut Material,
    textures: &mut crate::scene::MaterialTextures,
    model: &str,
) {
    if material.name() == model {
        return;
    }
    let phong_pair = matches!(model, "phong" | "blinn_phong");
    match material {
        Material::Phong(crate::brdf::PhongParams { blinn, .. }) if phong_pair => {
            *blinn = model == "blinn_phong"
        }
        _ => *material = default_material(model),
    }
    let takes = slots_for_model(material.name());
    for slot in crate::scene::TextureSlot::ALL {
        if !takes.contains(&slot) {
            *textures.get_mut(slot) = None;
        }
    }
    if textures.occlusion.is_none() && textures.orm.is_none() {
        textures.occlusion_strength = 1.0;
    }
    if textures.normal.is_none() {
        textures.normal_scale = 1.0;
    }
}

const DISTRIBUTIONS: [(Distribution, &str); 2] = [
    (Distribution::Beckmann, "Beckmann"),
    (Distribution::Ggx, "GGX"),
];

const DIFFUSES: [(Diffuse, &str); 2] = [
    (Diffuse::Lambert, "Lambert"),
    (Diffuse::Burley, "Burley (Disney)"),
];

const GEOMETRIES: [(Geometry, &str); 4] = [
    (Geometry::CookTorrance, "Cook-Torrance"),
    (Geometry::SmithGgx, "Smith GGX (separable)"),
    (
        Geometry::SmithGgxCorrelated,
        "Smith GGX (height-correlated)",
    ),
    (Geometry::SchlickGgx, "Schlick-GGX"),
];

const FRESNELS: [(Fresnel, &str); 4] = [
    (Fresnel::Schlick, "Schlick"),
    (Fresnel::SchlickSg, "Schlick (spherical Gaussian)"),
    (Fresnel::Dielectric, "dielectric (exact)"),
    (Fresnel::Conductor, "conductor (complex index)"),
];

fn material_ui(ui: &mut Ui, m: &mut Material) -> bool {
    grid(ui, "luz_material_grid", |ui| match m {
        Material::Phong(crate::brdf::PhongParams {
            blinn,
            ka,
            kd,
            ks,
            shininess,
            diffuse_color,
            specular_color,
        }) => {
            let mut c = false;
            c |= row(ui, "Blinn (n·h)", |ui| checkbox(ui, blinn, ""));
            c |= row(ui, "k_a", |ui| drag(ui, ka, 0.0..=f32::INFINITY));
            c |= row(ui, "k_d", |ui| drag(ui, kd, 0.0..=f32::INFINITY));
            c |= row(ui, "k_s", |ui| drag(ui, ks, 0.0..=f32::INFINITY));
            c |= row(ui, "Shininess n", |ui| {
                slider(ui, shininess, 0.0..=10_000.0, true)
            });
            c |= row(ui, "O_d (diffuse)", |ui| {
                color(ui, diffuse_color, f32::INFINITY)
            });
            c |= row(ui, "O_s (specular)", |ui| {
                color(ui, specular_color, f32::INFINITY)
            });
            c
        }
        Material::Lambert(crate::brdf::LambertParams { albedo }) => {
            row(ui, "Albedo", |ui| color(ui, albedo, 1.0))
        }
        Material::CookTorrance(p) => cook_torrance_ui(ui, p),
        Material::MetalRough(p) => metal_rough_ui(ui, p),
        Material::Principled(p) => {
            let mut c = false;
            c |= row(ui, "Base colour", |ui| color(ui, &mut p.base_color, 1.0));
            let fields: [(&str, &mut f32); 10] = [
                ("Subsurface", &mut p.subsurface),
                ("Metallic", &mut p.metallic),
                ("Specular", &mut p.specular),
                ("Specular tint", &mut p.specular_tint),
                ("Roughness", &mut p.roughness),
                ("Anisotropic", &mut p.anisotropic),
                ("Sheen", &mut p.sheen),
                ("Sheen tint", &mut p.sheen_tint),
                ("Clearcoat", &mut p.clearcoat),
                ("Clearcoat gloss", &mut p.clearcoat_gloss),
            ];
            for (name, v) in fields {
                c |= row(ui, name, |ui| unit(ui, v));
            }
            c
        }
        Material::OrenNayar(p) => {
            let mut c = false;
            c |= row(ui, "Albedo", |ui| color(ui, &mut p.albedo, 1.0));
            c |= row(ui, "σ (°)", |ui| {
                slider(ui, &mut p.sigma_deg, 0.0..=90.0, false)
            });
            c
        }
    })
}

/// How a Cook-Torrance material gives its Fresnel reflectance, for the combo box.
#[derive(Debug, Clone, Copy, PartialEq)]
enum SourceKind {
    Ior,
    F0,
    Complex,
}

/// Makes the Fresnel term and its source agree as the decoder requires: the conductor Fresnel
/// needs a complex index (gold when there is none), the dielectric one a real index (the mean η
/// of a complex one).
pub fn fix_cook_torrance(p: &mut CookTorranceParams) {
    match (p.fresnel, p.specular) {
        (Fresnel::Conductor, SpecularSource::Ior(_) | SpecularSource::F0(_)) => {
            if let Some(gold) = metal_preset("gold") {
                p.specular = SpecularSource::Complex(gold);
            }
        }
        (Fresnel::Dielectric, SpecularSource::Complex(c)) => {
            let eta = (c.eta.x + c.eta.y + c.eta.z) / 3.0;
            p.specular = SpecularSource::Ior(if eta.is_finite() && eta > 0.0 {
                eta
            } else {
                1.5
            });
        }
        _ => {}
    }
}

fn cook_torrance_ui(ui: &mut Ui, p: &mut CookTorranceParams) -> bool {
    let mut c = false;
    c |= row(ui, "Colour", |ui| color(ui, &mut p.color, 1.0));
    c |= row(ui, "k_d", |ui| unit(ui, &mut p.kd));
    c |= row(ui, "Roughness", |ui| unit(ui, &mut p.roughness));
    c |= row(ui, "Diffuse", |ui| {
        combo(ui, "ct_diffuse", &mut p.diffuse, &DIFFUSES)
    });
    c |= row(ui, "D", |ui| {
        combo(ui, "ct_d", &mut p.distribution, &DISTRIBUTIONS)
    });
    c |= row(ui, "G", |ui| {
        combo(ui, "ct_g", &mut p.geometry, &GEOMETRIES)
    });
    c |= row(ui, "F", |ui| {
        let changed = combo(ui, "ct_f", &mut p.fresnel, &FRESNELS);
        if changed {
            fix_cook_torrance(p);
        }
        changed
    });
    c |= row(ui, "Fresnel source", |ui| {
        let mut k = match p.specular {
            SpecularSource::Ior(_) => SourceKind::Ior,
            SpecularSource::F0(_) => SourceKind::F0,
            SpecularSource::Complex(_) => SourceKind::Complex,
        };
        // Only the sources the selected Fresnel accepts.
        let options: Vec<(SourceKind, &str)> = [
            (SourceKind::Ior, "index of refraction η"),
            (SourceKind::F0, "F0"),
            (SourceKind::Complex, "complex index η + iκ"),
        ]
        .into_iter()
        .filter(|(k, _)| match p.fresnel {
            Fresnel::Conductor => *k == SourceKind::Complex,
            Fresnel::Dielectric => *k != SourceKind::Complex,
            _ => true,
        })
        .collect();
        let mut changed = combo(ui, "ct_source", &mut k, &options);
        if changed {
            let f0 = p.specular.fresnel_inputs(Fresnel::Schlick).0;
            p.specular = match k {
                SourceKind::Ior => SpecularSource::Ior(1.5),
                SourceKind::F0 => SpecularSource::F0(f0.clamp(Vec3::ZERO, Vec3::ONE)),
                SourceKind::Complex => {
                    SpecularSource::Complex(metal_preset("gold").unwrap_or(ComplexIor {
                        eta: Vec3::ONE,
                        k: Vec3::ZERO,
                    }))
                }
            };
        }
        // Presets: metals give a complex index, dielectrics a real one.
        let mut preset: Option<&str> = None;
        ComboBox::from_id_salt("ct_preset")
            .selected_text("preset…")
            .show_ui(ui, |ui| {
                if p.fresnel != Fresnel::Dielectric {
                    for name in METAL_NAMES {
                        if ui.selectable_label(false, name).clicked() {
                            preset = Some(name);
                        }
                    }
                }
                if p.fresnel != Fresnel::Conductor {
                    ui.separator();
                    for name in DIELECTRIC_NAMES {
                        if ui.selectable_label(false, name).clicked() {
                            preset = Some(name);
                        }
                    }
                }
            });
        if let Some(name) = preset {
            if let Some(c) = metal_preset(name) {
                p.specular = SpecularSource::Complex(c);
                changed = true;
            } else if let Some(eta) = dielectric_ior(name) {
                p.specular = SpecularSource::Ior(eta);
                changed = true;
            }
            fix_cook_torrance(p);
        }
        changed
    });
    c |= match &mut p.specular {
        SpecularSource::Ior(eta) => row(ui, "η", |ui| drag_speed(ui, eta, 1e-3..=100.0, 0.005)),
        SpecularSource::F0(f0) => row(ui, "F0", |ui| color(ui, f0, 1.0)),
        SpecularSource::Complex(ci) => {
            let mut c = row(ui, "η (r, g, b)", |ui| {
                vec3(ui, &mut ci.eta, 1e-3..=100.0, 0.005)
            });
            c |= row(ui, "κ (r, g, b)", |ui| {
                vec3(ui, &mut ci.k, 0.0..=100.0, 0.005)
            });
            c
        }
    };
    c
}

fn metal_rough_ui(ui: &mut Ui, p: &mut MetalRoughParams) -> bool {
    let mut c = false;
    c |= row(ui, "Base colour", |ui| color(ui, &mut p.base_color, 1.0));
    c |= row(ui, "Metallic", |ui| unit(ui, &mut p.metallic));
    c |= row(ui, "Roughness", |ui| unit(ui, &mut p.roughness));
    c |= row(ui, "Metal preset", |ui| {
        let mut preset = None;
        ComboBox::from_id_salt("mr_preset")
            .selected_text("preset…")
            .show_ui(ui, |ui| {
                for name in METAL_NAMES {
                    if ui.selectable_label(false, name).clicked() {
                        preset = metal_preset(name);
                    }
                }
            });
        match preset {
            // As the decoder: base colour = the metal's F0, metallic 1.
            Some(m) => {
                p.base_color = m.f0().clamp(Vec3::ZERO, Vec3::ONE);
                p.metallic = 1.0;
                true
            }
            None => false,
        }
    });
    c |= row(ui, "D", |ui| {
        combo(ui, "mr_d", &mut p.distribution, &DISTRIBUTIONS)
    });
    c |= row(ui, "G", |ui| {
        combo(ui, "mr_g", &mut p.geometry, &GEOMETRIES)
    });
    c |= row(ui, "F", |ui| combo(ui, "mr_f", &mut p.fresnel, &FRESNELS));
    c |= row(ui, "Diffuse", |ui| {
        combo(ui, "mr_diffuse", &mut p.diffuse, &DIFFUSES)
    });
    c |= row(ui, "Diffuse × (1 − F)", |ui| {
        checkbox(ui, &mut p.diffuse_fresnel_weight, "")
    });
    c
}

// ---------------------------------------------------------------------------------------------
// Environment.

#[derive(Debug, Clone, Copy, PartialEq)]
enum EnvKind {
    None,
    Sky,
    Studio,
    Uniform,
    File,
}

fn environment_ui(ui: &mut Ui, scene: &mut Scene, state: &mut UiState, out: &mut Out) {
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
            combo(
                ui,
                "luz_env_source",
                &mut k,
                &[
                    (EnvKind::None, "none"),
                    (EnvKind::Sky, "procedural sky"),
                    (EnvKind::Studio, "studio"),
                    (EnvKind::Uniform, "uniform"),
                    (EnvKind::File, "file (.hdr / .exr)"),
                ],
            )
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
                &[
                    (SpecularMethod::SplitSum, "split sum"),
                    (SpecularMethod::Importance, "importance sampling"),
                ],
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
                &[
                    (DiffuseMethod::Sh9, "SH9"),
                    (DiffuseMethod::Cubemap, "convolved cubemap"),
                ],
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

// ---------------------------------------------------------------------------------------------
// Profiler.

fn ms(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.2} ms")
    } else {
        "–".to_string()
    }
}

fn fps(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.1}")
    } else {
        "–".to_string()
    }
}

fn profiler_ui(ui: &mut Ui, profiler: &Profiler) {
    let s = profiler.stats();
    ui.horizontal_top(|ui| {
        ui.vertical(|ui| {
            ui.set_width(200.0);
            Grid::new("luz_profiler_grid")
                .num_columns(2)
                .spacing([12.0, 2.0])
                .show(ui, |ui| {
                    let rows = [
                        ("FPS", fps(s.fps)),
                        ("p50", ms(s.p50)),
                        ("p95", ms(s.p95)),
                        ("p99", ms(s.p99)),
                        ("max", ms(s.max)),
                        ("CPU p50", ms(s.cpu_p50)),
                        ("GPU p50", ms(s.gpu_p50)),
                        ("stutters", format!("{} / {} frames", s.stutters, s.frames)),
                    ];
                    for (k, v) in rows {
                        ui.label(k);
                        ui.monospace(v);
                        ui.end_row();
                    }
                });
        });
        ui.separator();
        ui.vertical(|ui| {
            ui.set_width(170.0);
            ui.strong("GPU passes (p50)");
            let passes = profiler.pass_history();
            if passes.is_empty() {
                ui.label("no timestamps");
            }
            Grid::new("luz_passes_grid")
                .num_columns(2)
                .spacing([12.0, 2.0])
                .show(ui, |ui| {
                    for (name, t) in passes {
                        ui.label(name);
                        ui.monospace(ms(t));
                        ui.end_row();
                    }
                });
        });
        ui.separator();
        frame_graph(ui, profiler, s.p50);
    });
}

/// The window's frame times as a polyline (newest at the right), with reference lines at the
/// median and at the stutter threshold (2 × median).
fn frame_graph(ui: &mut Ui, profiler: &Profiler, median: f64) {
    let size = Vec2::new(
        ui.available_width().max(120.0),
        ui.available_height().clamp(60.0, 400.0),
    );
    let (response, painter) = ui.allocate_painter(size, Sense::hover());
    let rect = response.rect;
    let visuals = ui.visuals();
    painter.rect_filled(rect, 2.0, visuals.extreme_bg_color);
    let history: Vec<f64> = profiler.frame_history().collect();
    if history.is_empty() || !median.is_finite() || median <= 0.0 {
        painter.text(
            rect.center(),
            Align2::CENTER_CENTER,
            "no frames yet",
            FontId::proportional(12.0),
            visuals.weak_text_color(),
        );
        return;
    }
    let threshold = crate::profiler::STUTTER_FACTOR * median;
    let y_max = history
        .iter()
        .copied()
        .filter(|x| x.is_finite())
        .fold(threshold * 1.25, f64::max)
        .min(threshold * 4.0);
    let y = |v: f64| -> f32 {
        let t = (v / y_max).clamp(0.0, 1.0) as f32;
        rect.bottom() - t * rect.height()
    };
    let n = profiler.capacity().max(2);
    let dx = rect.width() / (n - 1) as f32;
    let x0 = rect.right() - dx * (history.len() - 1) as f32;
    let points: Vec<Pos2> = history
        .iter()
        .enumerate()
        .map(|(i, v)| {
            Pos2::new(
                x0 + dx * i as f32,
                y(if v.is_finite() { *v } else { y_max }),
            )
        })
        .collect();
    let font = FontId::monospace(10.0);
    for (level, label, colour) in [
        (median, "median", Color32::from_rgb(90, 170, 90)),
        (threshold, "2× median", Color32::from_rgb(200, 80, 80)),
    ] {
        let yy = y(level);
        painter.hline(rect.x_range(), yy, Stroke::new(1.0, colour));
        painter.text(
            Pos2::new(rect.left() + 4.0, yy - 1.0),
            Align2::LEFT_BOTTOM,
            format!("{label} {level:.1} ms"),
            font.clone(),
            colour,
        );
    }
    if points.len() >= 2 {
        painter.line(points, Stroke::new(1.5, visuals.text_color()));
    }
    painter.text(
        rect.right_top() + Vec2::new(-4.0, 2.0),
        Align2::RIGHT_TOP,
        format!("{y_max:.1} ms"),
        font,
        visuals.weak_text_color(),
    );
}

/// One line in the top-right corner: FPS and frame-time median (when the panels are hidden).
fn compact_profiler(ctx: &egui::Context, profiler: &Profiler) {
    let s = profiler.stats();
    egui::Area::new(Id::new("luz_compact_profiler"))
        .anchor(Align2::RIGHT_TOP, Vec2::new(-8.0, 8.0))
        .interactable(false)
        .show(ctx, |ui| {
            egui::Frame::popup(ui.style()).show(ui, |ui| {
                ui.monospace(format!(
                    "{} fps  {}  p99 {}  stutters {}",
                    fps(s.fps),
                    ms(s.p50),
                    ms(s.p99),
                    s.stutters
                ));
            });
        });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::profiler::FrameSample;
    use egui::Rect;
    use std::path::Path;

    fn profiler() -> Profiler {
        let mut p = Profiler::new(120);
        for i in 0..200 {
            p.push(FrameSample {
                frame_ms: if i % 50 == 49 {
                    40.0
                } else {
                    16.0 + (i % 3) as f64
                },
                cpu_ms: 2.0,
                gpu_ms: vec![("forward", 5.0), ("tonemap", 0.4)],
            });
        }
        p
    }

    /// Runs a few frames of `draw` without input; returns every action.
    fn run(scene: &mut Scene, settings: &mut ViewSettings) -> Vec<UiAction> {
        let ctx = egui::Context::default();
        let mut state = UiState {
            expand_all: true,
            ..Default::default()
        };
        let profiler = profiler();
        let mut all = Vec::new();
        for _ in 0..3 {
            let input = egui::RawInput {
                screen_rect: Some(Rect::from_min_size(Pos2::ZERO, Vec2::new(1280.0, 720.0))),
                ..Default::default()
            };
            let _ = ctx.run_ui(input, |ui| {
                all.extend(draw(ui, scene, settings, &profiler, &mut state));
            });
        }
        all
    }

    #[test]
    fn draws_without_input_and_edits_nothing() {
        let ibl =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/ibl/seed001_grid_sky.json");
        let scenes = [
            crate::scene::default_scene(),
            crate::scene::parse(crate::scene::DEFAULT_SCENE_JSON, Path::new("default.json"))
                .expect("default scene"),
            crate::scene::load(&ibl).expect("ibl scene"),
        ];
        for mut scene in scenes {
            let before_lights = scene.lights.clone();
            let before_materials = scene.materials.clone();
            let before_env = scene.environment.clone();
            for (panels, help) in [(true, false), (true, true), (false, true), (false, false)] {
                let mut settings = ViewSettings {
                    show_panels: panels,
                    show_help: help,
                    ..Default::default()
                };
                let actions = run(&mut scene, &mut settings);
                assert!(actions.is_empty(), "{actions:?}");
                assert_eq!(settings.show_help, help);
            }
            assert_eq!(scene.lights, before_lights);
            assert_eq!(scene.materials, before_materials);
            assert_eq!(scene.environment, before_env);
        }
    }

    #[test]
    fn every_material_model_draws() {
        let mut scene = crate::scene::default_scene();
        let models = [
            "phong",
            "blinn_phong",
            "lambert",
            "cook_torrance",
            "metal_rough",
            "principled",
            "oren_nayar",
        ];
        for model in models {
            let m = &mut scene.materials[0];
            set_material_model(&mut m.material, &mut m.textures, model);
            assert_eq!(m.material.name(), model);
            let mut settings = ViewSettings::default();
            assert!(run(&mut scene, &mut settings).is_empty());
        }
        // Every light kind and environment source.
        for kind in [LightKind::Directional, LightKind::Point, LightKind::Spot] {
            scene.lights.push(default_light(kind, scene.bounds()));
        }
        for source in [
            EnvSource::Studio,
            EnvSource::Uniform(Vec3::ONE),
            EnvSource::Sky {
                sun_direction: DEFAULT_SUN_DIRECTION.normalize(),
                sun_intensity: 3.0,
            },
        ] {
            let mut env = Environment::new(source);
            env.specular_method = SpecularMethod::Importance;
            scene.environment = Some(env);
            let mut settings = ViewSettings::default();
            assert!(run(&mut scene, &mut settings).is_empty());
        }
    }

    /// The decoder's rules for a light (src/scene/decode.rs `light`).
    fn assert_valid_light(l: &Light) {
        assert!((l.direction.length() - 1.0).abs() < 1e-5, "{l:?}");
        assert!(l.color.min_element() >= 0.0 && l.intensity >= 0.0, "{l:?}");
        match l.kind {
            LightKind::Directional => assert_eq!(l.falloff, Falloff::None),
            LightKind::Point => assert_eq!(l.direction, Vec3::NEG_Y),
            LightKind::Spot => {}
        }
        if l.kind == LightKind::Spot {
            assert!(l.umbra_deg > 0.0 && l.umbra_deg <= 90.0, "{l:?}");
            if let Some(i) = l.inner_deg {
                assert!(i >= 0.0 && i < l.umbra_deg, "{l:?}");
            }
            assert!(l.exponent >= 0.0);
        } else {
            assert_eq!((l.umbra_deg, l.inner_deg, l.exponent), (180.0, None, 0.0));
        }
    }

    #[test]
    fn light_kind_changes_keep_lights_valid() {
        let kinds = [LightKind::Directional, LightKind::Point, LightKind::Spot];
        for from in kinds {
            for to in kinds {
                let mut l = default_light(from, None);
                assert_valid_light(&l);
                set_light_kind(&mut l, to);
                assert_eq!(l.kind, to);
                assert_valid_light(&l);
            }
        }
    }

    #[test]
    fn model_switch_uses_defaults_and_drops_foreign_maps() {
        use crate::scene::{MaterialTextures, TextureRef};
        let mut m = Material::MetalRough(MetalRoughParams {
            roughness: 0.1,
            ..Default::default()
        });
        let mut t = MaterialTextures {
            metallic: Some(TextureRef::new("m.png")),
            normal: Some(TextureRef::new("n.png")),
            ..Default::default()
        };
        set_material_model(&mut m, &mut t, "principled");
        assert_eq!(m, Material::Principled(PrincipledParams::default()));
        assert!(t.metallic.is_some());
        set_material_model(&mut m, &mut t, "lambert");
        assert_eq!(
            m,
            Material::Lambert(crate::brdf::LambertParams {
                albedo: Vec3::splat(0.8)
            })
        );
        assert!(t.metallic.is_none() && t.normal.is_some());
        set_material_model(&mut m, &mut t, "phong");
        assert_eq!(m, Material::default_phong(false));
        if let Material::Phong(crate::brdf::PhongParams { ks, .. }) = &mut m {
            *ks = 0.9;
        }
        // Phong ↔ Blinn-Phong keeps the parameters.
        set_material_model(&mut m, &mut t, "blinn_phong");
        assert!(
            matches!(m, Material::Phong(crate::brdf::PhongParams { blinn: true, ks, .. }) if ks == 0.9)
        );
    }

    #[test]
    fn cook_torrance_fresnel_and_source_agree() {
        let mut p = CookTorranceParams {
            fresnel: Fresnel::Conductor,
            ..Default::default()
        };
        fix_cook_torrance(&mut p);
        assert!(matches!(p.specular, SpecularSource::Complex(_)));
        p.fresnel = Fresnel::Dielectric;
        fix_cook_torrance(&mut p);
        assert!(matches!(p.specular, SpecularSource::Ior(eta) if eta > 0.0));
        p.fresnel = Fresnel::Schlick;
        let before = p;
        fix_cook_torrance(&mut p);
        assert_eq!(p, before);
    }

    #[test]
    fn keys_are_listed() {
        assert!(KEYS.iter().any(|(k, _)| *k == "Esc"));
        assert_eq!(KEYS.len(), 11);
    }
}
