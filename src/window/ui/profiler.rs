//! The frame-time profiler: statistics, the frame graph and the compact overlay.

use super::*;

// ---------------------------------------------------------------------------------------------
// Profiler.

pub(super) fn ms(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.2} ms")
    } else {
        "–".to_string()
    }
}

pub(super) fn fps(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.1}")
    } else {
        "–".to_string()
    }
}

pub(super) fn profiler_ui(ui: &mut Ui, profiler: &Profiler) {
    let s = profiler.stats();
    ui.horizontal_top(|ui| {
        ui.vertical(|ui| {
            ui.set_width(200.0);
            Grid::new("luz_profiler_grid")
                .num_columns(2)
                .spacing([12.0, 2.0])
                .show(ui, |ui| {
                    let mut rows = vec![
                        ("FPS", fps(s.fps)),
                        ("p50", ms(s.p50)),
                        ("p95", ms(s.p95)),
                        ("p99", ms(s.p99)),
                        ("max", ms(s.max)),
                        ("CPU p50", ms(s.cpu_p50)),
                        ("GPU p50", ms(s.gpu_p50)),
                        ("stutters", format!("{} / {} frames", s.stutters, s.frames)),
                        (
                            "triangles",
                            profiler.geometry().map_or("–".into(), |g| g.0.to_string()),
                        ),
                        (
                            "LOD levels",
                            profiler.geometry().map_or("–".into(), |g| g.1.clone()),
                        ),
                    ];
                    // Only when a mesh has simplified levels (the row would say nothing else).
                    if let Some(b) = profiler.lod_budget() {
                        rows.push(("LOD budget", b.to_string()));
                    }
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
                    for &(name, t) in &passes {
                        ui.label(name);
                        ui.monospace(ms(t));
                        ui.end_row();
                    }
                });
            // A/B comparison: say what the frame pays for.
            let scope = |n: &str| passes.iter().find(|(p, _)| *p == n).map(|(_, t)| *t);
            let b_passes: Vec<f64> = passes
                .iter()
                .filter(|(p, _)| super::compare::is_b(p))
                .map(|(_, t)| *t)
                .collect();
            if !b_passes.is_empty() {
                let b: f64 = b_passes.iter().sum();
                let total: f64 = passes.iter().map(|(_, t)| t).sum();
                ui.weak(format!(
                    "A/B: the frame renders both scenes (B {} of {} GPU){}.",
                    ms(b),
                    ms(total),
                    match scope(super::compare::MAP_SCOPE) {
                        Some(m) => format!(", plus the A/B map ({})", ms(m)),
                        None => String::new(),
                    }
                ));
            }
        });
        ui.separator();
        frame_graph(ui, profiler, s.p50);
    });
}

/// The window's frame times as a polyline (newest at the right), with reference lines at the
/// median and at the stutter threshold (2 × median).
pub(super) fn frame_graph(ui: &mut Ui, profiler: &Profiler, median: f64) {
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
    pass_bars(&painter, rect, profiler, (x0, dx), &y);
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

/// The colour of pass `i` (in the order passes first appear in the window).
fn pass_colour(i: usize) -> Color32 {
    const COLOURS: [(u8, u8, u8); 8] = [
        (70, 130, 200),
        (220, 140, 50),
        (90, 170, 90),
        (180, 90, 180),
        (200, 200, 80),
        (80, 190, 190),
        (200, 90, 90),
        (150, 150, 150),
    ];
    let (r, g, b) = COLOURS[i % COLOURS.len()];
    Color32::from_rgba_unmultiplied(r, g, b, 170)
}

/// Per frame, a bar of its GPU passes stacked from the bottom (the frame line is drawn over
/// them), with the passes' names in their colours along the top.
fn pass_bars(
    painter: &egui::Painter,
    rect: egui::Rect,
    profiler: &Profiler,
    (x0, dx): (f32, f32),
    y: &dyn Fn(f64) -> f32,
) {
    let names: Vec<&'static str> = profiler.pass_history().iter().map(|(n, _)| *n).collect();
    let half = (dx * 0.4).max(0.5);
    for (i, s) in profiler.samples().enumerate() {
        let x = x0 + dx * i as f32;
        let mut total = 0.0;
        for (name, ms) in &s.gpu_ms {
            if !ms.is_finite() || *ms <= 0.0 {
                continue;
            }
            let k = names.iter().position(|n| n == name).unwrap_or(0);
            let (bottom, top) = (y(total), y(total + ms));
            total += ms;
            painter.rect_filled(
                egui::Rect::from_min_max(Pos2::new(x - half, top), Pos2::new(x + half, bottom)),
                0.0,
                pass_colour(k),
            );
        }
    }
    let mut at = Pos2::new(rect.left() + 4.0, rect.top() + 2.0);
    for (k, name) in names.iter().enumerate() {
        let r = painter.text(
            at,
            Align2::LEFT_TOP,
            *name,
            FontId::monospace(10.0),
            pass_colour(k).to_opaque(),
        );
        at.x = r.right() + 8.0;
    }
}

/// One line in the top-right corner: FPS and frame-time median (when the panels are hidden).
pub(super) fn compact_profiler(ctx: &egui::Context, profiler: &Profiler) {
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
