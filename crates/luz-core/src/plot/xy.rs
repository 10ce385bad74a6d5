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
    let fs = font_size(root.dim_in_pixel().1, 16.0);
    with_axes!(c.x, xr, c.y, yr, |xs, ys| {
        let mut chart = chart_with_axes(root, &c.title, (&c.x, xs), (&c.y, ys))?;
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
            draw_legend(&mut chart, pos, fs)?;
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
    let fs = font_size(root.dim_in_pixel().1, 16.0);
    with_axes!(c.x, xr, c.y, yr, |xs, ys| {
        let mut chart = chart_with_axes(root, &c.title, (&c.x, xs), (&c.y, ys))?;
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
            draw_legend(&mut chart, pos, fs)?;
        }
        Ok(())
    })
}

/// The chart context of [`chart_with_axes`] on the coordinate ranges `X`, `Y`.
type XyChart<'a, DB, X, Y> = ChartContext<
    'a,
    DB,
    Cartesian2d<<X as AsRangedCoord>::CoordDescType, <Y as AsRangedCoord>::CoordDescType>,
>;

/// A line or scatter chart on `root`: the title above, the axes drawn ([`draw_axes`] with grid
/// lines) on the coordinate ranges `xs`, `ys`.
fn chart_with_axes<'a, DB, X, Y>(
    root: &'a DrawingArea<DB, Shift>,
    title: &str,
    (x, xs): (&Axis, X),
    (y, ys): (&Axis, Y),
) -> Result<XyChart<'a, DB, X, Y>>
where
    DB: DrawingBackend,
    X: AsRangedCoord,
    Y: AsRangedCoord,
    X::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let h = root.dim_in_pixel().1;
    let fs = font_size(h, 16.0);
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FAMILY, font_size(h, 22.0)))
        .margin(font_size(h, 14.0) as u32)
        .x_label_area_size((fs * 3.0) as u32)
        .y_label_area_size((fs * 4.5) as u32)
        .build_cartesian_2d(xs, ys)
        .map_err(de)?;
    draw_axes(&mut chart, x, y, fs, true)?;
    Ok(chart)
}

/// The series' legend box at `pos`, text at `fs` pixels.
fn draw_legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    pos: SeriesLabelPosition,
    fs: f64,
) -> Result<()> {
    chart
        .configure_series_labels()
        .position(pos)
        .label_font((FAMILY, fs))
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(160, 160, 160))
        .draw()
        .map_err(de)
}
