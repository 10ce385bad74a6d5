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
use glam::Vec3;

use crate::brdf::{
    dielectric_ior, metal_preset, ComplexIor, CookTorranceParams, Diffuse, Distribution, Fresnel,
    Geometry, MetalRoughParams, SpecularSource, DIELECTRIC_NAMES, METAL_NAMES,
};
use crate::color::Tonemap;
use crate::profiler::Profiler;
use crate::render::forward::DebugView;
use crate::scene::{
    DiffuseMethod, EnvSource, Environment, Falloff, Fog, Light, LightKind, Material, Saturation,
    Scene, Shading, SpecularMethod, DEFAULT_SUN_DIRECTION, DEFAULT_SUN_INTENSITY, MAX_ENV_SAMPLES,
    MAX_SUN_INTENSITY,
};

pub use crate::scene::edit::{
    default_light, default_material, fix_cook_torrance, set_light_kind, set_material_model,
};
use crate::scene::edit::{fog_gap, light_field, unit_vec, LightField};

/// Viewer settings that are not part of the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewSettings {
    pub debug_view: DebugView,
    pub vsync: bool,
    /// The key help window.
    pub show_help: bool,
    /// The side and profiler panels (Tab).
    pub show_panels: bool,
    /// The shadow-map window.
    pub shadow_maps: bool,
}

impl Default for ViewSettings {
    fn default() -> Self {
        ViewSettings {
            debug_view: DebugView::None,
            vsync: true,
            show_help: false,
            show_panels: true,
            shadow_maps: false,
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
    /// Show or hide the lab panel (A/B comparison, error view, lobe plots).
    ToggleLab,
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
    ("L", "lab panel: A/B comparison, error view, lobe plots"),
    ("B", "A/B toggle mode: show the other side"),
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
                    if ui.button("Lab: A/B, error view, lobe plots (L)").clicked() {
                        out.actions.push(UiAction::ToggleLab);
                    }
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

pub mod compare;
mod environment;
mod lights;
mod materials;
mod profiler;
mod scene_panel;
mod shadow;
mod widgets;

use environment::*;
use lights::*;
use materials::*;
use profiler::*;
use scene_panel::*;
use widgets::*;

#[cfg(test)]
mod tests;
