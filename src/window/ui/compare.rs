//! The lab in the window: the A/B comparison panel (mode, divider, duplicate the scene into B,
//! which side the scene panels edit, each side's GPU time), the error view against the CPU
//! reference (progress, summary figures), and what is painted over the scene: the comparison
//! or error map, the split divider and the colour bar.

use egui::{
    Align2, Color32, FontId, Id, Panel, Pos2, Rect, Sense, Stroke, TextureHandle, Ui, Vec2,
};

use crate::compare::{palette, MapStats};
use crate::window::jobs::{ErrorResult, MapImage};

/// How A and B are shown.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CompareMode {
    /// A left of a draggable vertical divider, B right of it, one camera.
    #[default]
    Split,
    /// `max_c |A − B|` in linear radiance, scaled, with a colour bar.
    Difference,
    /// The FLIP heat map of B against A.
    Flip,
    /// A or B, whole; the B key (or `compare_flip`) switches.
    Toggle,
}

impl CompareMode {
    pub const ALL: [CompareMode; 4] = [
        CompareMode::Split,
        CompareMode::Difference,
        CompareMode::Flip,
        CompareMode::Toggle,
    ];

    pub fn name(self) -> &'static str {
        match self {
            CompareMode::Split => "split",
            CompareMode::Difference => "difference",
            CompareMode::Flip => "flip",
            CompareMode::Toggle => "toggle",
        }
    }

    pub fn from_name(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.name() == s)
    }

    /// Whether the mode shows a map computed from both read-back images.
    pub fn needs_map(self) -> bool {
        matches!(self, CompareMode::Difference | CompareMode::Flip)
    }
}

/// Which per-pixel error the error view shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ErrorMetric {
    #[default]
    Relative,
    Flip,
}

/// The comparison settings the panel and the script change.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CompareSettings {
    pub mode: CompareMode,
    /// The divider's position, 0 (left edge) to 1 (right edge).
    pub split: f32,
    /// Toggle mode shows B.
    pub show_b: bool,
    /// The scene panels edit B instead of A.
    pub edit_b: bool,
    pub error_view: bool,
    pub metric: ErrorMetric,
    /// The selected material's lobe plots.
    pub plots: bool,
    /// The lab panel is shown (the L key; opened by `--compare` and the lab's script actions).
    pub open: bool,
}

impl Default for CompareSettings {
    fn default() -> Self {
        Self {
            mode: CompareMode::Split,
            split: 0.5,
            show_b: false,
            edit_b: false,
            error_view: false,
            metric: ErrorMetric::Relative,
            plots: false,
            open: false,
        }
    }
}

/// What B's GPU timer scopes start with (its shadows, scene and saturate passes: "B: forward", …).
pub const B_PREFIX: &str = "B: ";

/// Whether a GPU timer scope is one of B's passes.
pub fn is_b(scope: &str) -> bool {
    scope.starts_with(B_PREFIX)
}
/// The name of the A/B map's GPU timer scope (difference or FLIP of both images).
pub const MAP_SCOPE: &str = "A/B map";

/// Where the error view is.
#[derive(Debug, Clone, Copy)]
pub enum ErrorStatus<'a> {
    Off,
    /// The reference is rendering: rows done of total.
    Running(u64, u64),
    Done(&'a ErrorResult),
    Failed(&'a str),
}

/// What the panel shows, read-only.
pub struct CompareInfo<'a> {
    /// Whether a B side exists.
    pub has_b: bool,
    /// Median GPU ms of A's scene passes and of B's (the profiler's window).
    pub gpu_ms: (f64, f64),
    /// The newest A/B map (difference or flip modes).
    pub map: Option<&'a MapImage>,
    pub error: ErrorStatus<'a>,
    /// B's error view (comparing only).
    pub error_b: ErrorStatus<'a>,
    /// The lobe plots, when shown.
    pub plots: Option<&'a crate::window::plots::PlotWorker>,
}

/// What the app must do after the panel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CompareAction {
    /// Make B a copy of A (the scene, its camera shared).
    Duplicate,
    /// Stop comparing.
    DropB,
}

/// The colour bar: the palette from 0 to `scale`, labelled.
fn colour_bar(ui: &mut Ui, label: &str, scale: f32, percent: bool) {
    ui.label(label);
    let (response, painter) = ui.allocate_painter(Vec2::new(200.0, 14.0), Sense::hover());
    let r = response.rect;
    let lut = palette();
    let n = 64;
    for i in 0..n {
        let c = lut[i * 255 / (n - 1)];
        let x0 = r.left() + r.width() * i as f32 / n as f32;
        let x1 = r.left() + r.width() * (i + 1) as f32 / n as f32 + 0.5;
        painter.rect_filled(
            Rect::from_min_max(Pos2::new(x0, r.top()), Pos2::new(x1, r.bottom())),
            0.0,
            Color32::from_rgb(c[0], c[1], c[2]),
        );
    }
    let top = if percent {
        format!("≥ {:.0} %", scale * 100.0)
    } else if scale == 0.0 || (1e-3..1e4).contains(&scale) {
        format!("≥ {scale:.4}")
    } else {
        format!("≥ {scale:.3e}")
    };
    ui.horizontal(|ui| {
        ui.monospace("0");
        ui.add_space(140.0);
        ui.monospace(top);
    });
}

fn stats_grid(ui: &mut Ui, id: &str, s: &MapStats, percent: bool) {
    let f = |v: f32| {
        if percent {
            format!("{:.2} %", v * 100.0)
        } else {
            format!("{v:.4}")
        }
    };
    egui::Grid::new(id).num_columns(2).show(ui, |ui| {
        for (k, v) in [
            ("mean", f(s.mean)),
            ("p50", f(s.p50)),
            ("p95", f(s.p95)),
            ("p99", f(s.p99)),
            ("max", f(s.max)),
            ("pixels > 0.01", format!("{:.1} %", s.above * 100.0)),
        ] {
            ui.label(k);
            ui.monospace(v);
            ui.end_row();
        }
    });
}

/// The right-hand "Lab" panel.
pub fn compare_panel(
    ui: &mut Ui,
    settings: &mut CompareSettings,
    info: &CompareInfo,
) -> Vec<CompareAction> {
    let mut actions = Vec::new();
    // With the lobe plots the panel is at least as wide as the charts, which are drawn at
    // their pixel size (axis labels legible, not scaled down).
    let min = if settings.plots {
        crate::window::plots::PLOT_W as f32 + 24.0
    } else {
        160.0
    };
    Panel::right(Id::new("luz_lab_panel"))
        .resizable(true)
        .default_size(240.0)
        .min_size(min)
        .show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                ui.heading("A/B comparison");
                if !info.has_b {
                    ui.label("One scene. Duplicate it into B, then change B.");
                    if ui.button("Duplicate the scene into B").clicked() {
                        actions.push(CompareAction::Duplicate);
                    }
                } else {
                    egui::ComboBox::from_label("mode")
                        .selected_text(settings.mode.name())
                        .show_ui(ui, |ui| {
                            for m in CompareMode::ALL {
                                ui.selectable_value(&mut settings.mode, m, m.name());
                            }
                        });
                    match settings.mode {
                        CompareMode::Split => {
                            ui.add(
                                egui::Slider::new(&mut settings.split, 0.0..=1.0).text("divider"),
                            );
                        }
                        CompareMode::Toggle => {
                            ui.horizontal(|ui| {
                                ui.label("showing");
                                ui.selectable_value(&mut settings.show_b, false, "A");
                                ui.selectable_value(&mut settings.show_b, true, "B");
                                ui.weak("(key B)");
                            });
                        }
                        _ => {}
                    }
                    ui.horizontal(|ui| {
                        ui.label("panels edit");
                        ui.selectable_value(&mut settings.edit_b, false, "A");
                        ui.selectable_value(&mut settings.edit_b, true, "B");
                    });
                    ui.horizontal(|ui| {
                        if ui.button("Copy A into B").clicked() {
                            actions.push(CompareAction::Duplicate);
                        }
                        if ui.button("Stop comparing").clicked() {
                            actions.push(CompareAction::DropB);
                        }
                    });
                    ui.label(format!(
                        "GPU scene passes (p50): A {:.2} ms, B {:.2} ms",
                        info.gpu_ms.0, info.gpu_ms.1
                    ));
                    ui.weak("A/B renders both scenes every frame: the frame costs both.");
                    if settings.mode.needs_map() {
                        match info.map {
                            Some(m) => {
                                colour_bar(ui, m.kind.label(), m.scale, false);
                                stats_grid(ui, "luz_ab_stats", &m.stats, false);
                                ui.weak(format!(
                                    "{}×{} map on the GPU every frame: {:.2} ms (p50)",
                                    m.width, m.height, m.ms
                                ));
                            }
                            None => {
                                ui.label("computing the map…");
                            }
                        }
                    }
                }
                ui.separator();
                ui.heading("Error against the reference");
                let label = if settings.error_view {
                    "Hide the error view"
                } else {
                    "Error view"
                };
                if ui.button(label).clicked() {
                    settings.error_view = !settings.error_view;
                }
                if settings.error_view {
                    ui.horizontal(|ui| {
                        ui.selectable_value(
                            &mut settings.metric,
                            ErrorMetric::Relative,
                            "relative",
                        );
                        ui.selectable_value(&mut settings.metric, ErrorMetric::Flip, "FLIP");
                    });
                }
                if info.has_b && settings.error_view {
                    ui.weak(match settings.mode {
                        CompareMode::Toggle => {
                            "Each side against its own reference: the side shown."
                        }
                        _ => "Each side against its own reference: A left of the divider, B right.",
                    });
                    ui.strong("A");
                    error_status(ui, "a", settings, &info.error);
                    ui.strong("B");
                    error_status(ui, "b", settings, &info.error_b);
                } else {
                    error_status(ui, "a", settings, &info.error);
                }
                ui.separator();
                ui.heading("Lobe plots");
                ui.checkbox(&mut settings.plots, "selected material (Objects panel)");
                if let (true, Some(p)) = (settings.plots, info.plots) {
                    p.show(ui);
                }
            });
        });
    actions
}

fn error_status(ui: &mut Ui, id: &str, settings: &CompareSettings, status: &ErrorStatus) {
    match status {
        ErrorStatus::Off => {}
        ErrorStatus::Running(done, total) => {
            ui.add(
                egui::ProgressBar::new(*done as f32 / (*total).max(1) as f32)
                    .text(format!("reference {done}/{total} rows")),
            );
            ui.weak("Cancelled and started again when the view changes.");
        }
        ErrorStatus::Failed(e) => {
            ui.colored_label(Color32::from_rgb(220, 90, 90), *e);
        }
        ErrorStatus::Done(r) => {
            let (map, percent) = match settings.metric {
                ErrorMetric::Relative => (&r.relative, true),
                ErrorMetric::Flip => (&r.flip, false),
            };
            colour_bar(ui, map.kind.label(), map.scale, percent);
            stats_grid(ui, &format!("luz_error_stats_{id}"), &map.stats, percent);
            ui.weak(format!(
                "reference {}×{} in {:.0} ms (rayon); map {:.1} ms",
                r.width, r.height, r.reference_ms, map.ms
            ));
        }
    }
}

/// Paints the columns `x0..x1` (fractions of the width) of `texture` over the same columns of
/// the scene area (under the panels: call before them).
pub fn paint_map(ui: &Ui, texture: &TextureHandle, (x0, x1): (f32, f32)) {
    let r = ui.ctx().content_rect();
    let rect = Rect::from_min_max(
        Pos2::new(r.left() + r.width() * x0, r.top()),
        Pos2::new(r.left() + r.width() * x1, r.bottom()),
    );
    ui.painter().image(
        texture.id(),
        rect,
        Rect::from_min_max(Pos2::new(x0, 0.0), Pos2::new(x1, 1.0)),
        Color32::WHITE,
    );
}

/// The split divider: a line at `split` of the window's width and a handle to drag it.
pub fn divider(ui: &Ui, split: &mut f32) {
    let ctx = ui.ctx().clone();
    let rect = ctx.content_rect();
    let x = rect.left() + rect.width() * *split;
    ui.painter().vline(
        x,
        rect.y_range(),
        Stroke::new(2.0, Color32::from_rgb(240, 240, 240)),
    );
    let handle = Vec2::new(14.0, 44.0);
    egui::Area::new(Id::new("luz_split_handle"))
        .fixed_pos(Pos2::new(
            x - handle.x * 0.5,
            rect.center().y - handle.y * 0.5,
        ))
        .order(egui::Order::Foreground)
        .show(&ctx, |ui| {
            let (r, painter) = ui.allocate_painter(handle, Sense::drag());
            painter.rect_filled(r.rect, 4.0, Color32::from_rgb(240, 240, 240));
            painter.text(
                r.rect.center(),
                Align2::CENTER_CENTER,
                "↔",
                FontId::proportional(11.0),
                Color32::BLACK,
            );
            if r.dragged() && rect.width() > 0.0 {
                *split = (*split + r.drag_delta().x / rect.width()).clamp(0.0, 1.0);
            }
        });
}

/// A corner box with the colour bar and the figures of `maps` (one line each, named) when the
/// panels are hidden.
pub fn corner_legend(ctx: &egui::Context, maps: &[(&str, &MapImage)], percent: bool) {
    let Some((_, first)) = maps.first() else {
        return;
    };
    egui::Area::new(Id::new("luz_map_legend"))
        .anchor(Align2::RIGHT_BOTTOM, Vec2::new(-8.0, -8.0))
        .interactable(false)
        .show(ctx, |ui| {
            egui::Frame::popup(ui.style()).show(ui, |ui| {
                colour_bar(ui, first.kind.label(), first.scale, percent);
                for (name, map) in maps {
                    ui.monospace(format!(
                        "{name}{}mean {:.4}  p99 {:.4}  max {:.4}",
                        if name.is_empty() { "" } else { ": " },
                        map.stats.mean,
                        map.stats.p99,
                        map.stats.max
                    ));
                }
            });
        });
}
