//! Line and scatter charts (linear or log axes).

use super::*;

// ---------------------------------------------------------------------------------------------
// Line and scatter charts
// ---------------------------------------------------------------------------------------------

macro_rules! with_axes {
    ($xa:expr, $xr:expr, $ya:expr, $yr:expr, |$xs:ident, $ys:ident| $body:expr) => {{
        let (x0, x1) = $xr;
        let (y0, y1) = $yr;
        match ($xa.log, $ya.log) {
            (false, false) => {
                let $xs = x0..x1;
                let $ys = y0..y1;
                $body
            }
            (true, false) => {
                let $xs = (x0..x1).log_scale();
                let $ys = y0..y1;
                $body
            }
            (false, true) => {
                let $xs = x0..x1;
                let $ys = (y0..y1).log_scale();
                $body
            }
            (true, true) => {
                let $xs = (x0..x1).log_scale();
                let $ys = (y0..y1).log_scale();
                $body
            }
        }
    }};
}

pub(super) fn draw_line<DB: DrawingBackend>(
    c: &LineChart,
    root: &DrawingArea<DB, Shift>,
) -> Result<()> {
    let keep = |a: &Axis, v: f64| v.is_finite() && (!a.log || v > 0.0);
    let xr = fit(
        &c.x,
        c.series.iter().flat_map(|s| s.points.iter().map(|p| p.0)),
    );
    let yr = fit(
        &c.y,
        c.series.iter().flat_map(|s| s.points.iter().map(|p| p.1)),
    );
    let h = root.dim_in_pixel().1;
    let fs = font_size(h, 16.0);
    with_axes!(c.x, xr, c.y, yr, |xs, ys| {
        let mut chart = ChartBuilder::on(root)
            .caption(&c.title, (FAMILY, font_size(h, 22.0)))
            .margin(font_size(h, 14.0) as u32)
            .x_label_area_size((fs * 3.0) as u32)
            .y_label_area_size((fs * 4.5) as u32)
            .build_cartesian_2d(xs, ys)
            .map_err(de)?;
        chart
            .configure_mesh()
            .x_desc(c.x.label.as_str())
            .y_desc(c.y.label.as_str())
            .label_style((FAMILY, fs))
            .axis_desc_style((FAMILY, fs))
            .x_label_formatter(&|v| format_number(*v))
            .y_label_formatter(&|v| format_number(*v))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(de)?;
        let mut any_label = false;
        for (i, s) in c.series.iter().enumerate() {
            let color = s.color.unwrap_or_else(|| palette(i));
            let style = ShapeStyle::from(color).stroke_width(2);
            let pts: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|&(x, y)| keep(&c.x, x) && keep(&c.y, y))
                .collect();
            let anno = if s.dashed {
                chart
                    .draw_series(DashedLineSeries::new(pts.clone(), 8, 5, style))
                    .map_err(de)?
            } else {
                chart
                    .draw_series(LineSeries::new(pts.clone(), style))
                    .map_err(de)?
            };
            if !s.label.is_empty() {
                any_label = true;
                anno.label(s.label.as_str())
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
            }
            if s.markers {
                chart
                    .draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))
                    .map_err(de)?;
            }
        }
        if let (true, Some(pos)) = (any_label, legend_pos(c.legend)) {
            chart
                .configure_series_labels()
                .position(pos)
                .label_font((FAMILY, fs))
                .background_style(WHITE.mix(0.85))
                .border_style(RGBColor(160, 160, 160))
                .draw()
                .map_err(de)?;
        }
        Ok(())
    })
}

pub(super) fn draw_scatter<DB: DrawingBackend>(
    c: &ScatterChart,
    root: &DrawingArea<DB, Shift>,
) -> Result<()> {
    let keep = |a: &Axis, v: f64| v.is_finite() && (!a.log || v > 0.0);
    let mut xr = fit(&c.x, c.points.iter().map(|p| p.x));
    let yr = fit(&c.y, c.points.iter().map(|p| p.y));
    if c.x.range.is_none() {
        // Room for the labels right of the rightmost points.
        xr.1 = if c.x.log {
            xr.1 * (xr.1 / xr.0).powf(0.15)
        } else {
            xr.1 + (xr.1 - xr.0) * 0.15
        };
    }
    let h = root.dim_in_pixel().1;
    let fs = font_size(h, 16.0);
    with_axes!(c.x, xr, c.y, yr, |xs, ys| {
        let mut chart = ChartBuilder::on(root)
            .caption(&c.title, (FAMILY, font_size(h, 22.0)))
            .margin(font_size(h, 14.0) as u32)
            .x_label_area_size((fs * 3.0) as u32)
            .y_label_area_size((fs * 4.5) as u32)
            .build_cartesian_2d(xs, ys)
            .map_err(de)?;
        chart
            .configure_mesh()
            .x_desc(c.x.label.as_str())
            .y_desc(c.y.label.as_str())
            .label_style((FAMILY, fs))
            .axis_desc_style((FAMILY, fs))
            .x_label_formatter(&|v| format_number(*v))
            .y_label_formatter(&|v| format_number(*v))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(de)?;
        let groups = c
            .points
            .iter()
            .map(|p| p.group + 1)
            .max()
            .unwrap_or(0)
            .max(c.groups.len());
        for g in 0..groups {
            let color = palette(g);
            let pts: Vec<&LabeledPoint> = c
                .points
                .iter()
                .filter(|p| p.group == g && keep(&c.x, p.x) && keep(&c.y, p.y))
                .collect();
            let anno = chart
                .draw_series(
                    pts.iter()
                        .map(|p| Circle::new((p.x, p.y), 5, color.filled())),
                )
                .map_err(de)?;
            if let Some(name) = c.groups.get(g) {
                anno.label(name.as_str())
                    .legend(move |(x, y)| Circle::new((x + 10, y), 5, color.filled()));
            }
            let label_style = TextStyle::from((FAMILY, fs * 0.85).into_font()).color(&BLACK);
            chart
                .draw_series(pts.iter().filter(|p| !p.label.is_empty()).map(|p| {
                    EmptyElement::at((p.x, p.y))
                        + Text::new(p.label.clone(), (8, -(fs as i32) / 2), label_style.clone())
                }))
                .map_err(de)?;
        }
        if let (false, Some(pos)) = (c.groups.is_empty(), legend_pos(c.legend)) {
            chart
                .configure_series_labels()
                .position(pos)
                .label_font((FAMILY, fs))
                .background_style(WHITE.mix(0.85))
                .border_style(RGBColor(160, 160, 160))
                .draw()
                .map_err(de)?;
        }
        Ok(())
    })
}
