//! Heat maps with a colour bar (linear or log colour scale).

use super::*;

// ---------------------------------------------------------------------------------------------
// Heatmap
// ---------------------------------------------------------------------------------------------

pub(super) const EMPTY_GREY: RGBColor = RGBColor(150, 150, 150);

pub(super) fn draw_heatmap<DB: DrawingBackend>(
    c: &Heatmap,
    root: &DrawingArea<DB, Shift>,
) -> Result<()> {
    let (Some((x0, x1)), Some((y0, y1))) = (c.x.range, c.y.range) else {
        bail!("heatmap: the x and y ranges are required");
    };
    if c.nx == 0 || c.ny == 0 || c.values.len() != c.nx * c.ny {
        bail!(
            "heatmap: {} values for {} × {} cells",
            c.values.len(),
            c.nx,
            c.ny
        );
    }
    let valid = |v: f64| v.is_finite() && (!c.log_color || v > 0.0);
    let (mut lo, mut hi) = match c.color_range {
        Some(r) => r,
        None => {
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            for &v in c.values.iter().filter(|v| valid(**v)) {
                lo = lo.min(v);
                hi = hi.max(v);
            }
            if lo > hi {
                (lo, hi) = if c.log_color { (0.1, 1.0) } else { (0.0, 1.0) };
            }
            if c.log_color {
                let decades = if c.log_decades > 0.0 {
                    c.log_decades
                } else {
                    4.0
                };
                lo = lo.max(hi * 10f64.powf(-decades));
            }
            (lo, hi)
        }
    };
    if c.log_color {
        lo = lo.max(f64::MIN_POSITIVE);
        if hi <= lo * 1.01 {
            (lo, hi) = (lo / 1.5, hi.max(lo) * 1.5);
        }
    } else if hi <= lo {
        (lo, hi) = (lo - 0.5, hi + 0.5);
    }
    let to_t = |v: f64| -> f64 {
        if c.log_color {
            (v.log10() - lo.log10()) / (hi.log10() - lo.log10())
        } else {
            (v - lo) / (hi - lo)
        }
    };
    let (w, h) = root.dim_in_pixel();
    let fs = font_size(h, 16.0);
    let root = titled(root, &c.title)?;
    let bar_w = ((w as f64) * 0.17).max(fs * 6.0) as u32;
    let (left, right) = root.split_horizontally(w.saturating_sub(bar_w));
    let mut chart = ChartBuilder::on(&left)
        .margin(font_size(h, 12.0) as u32)
        .x_label_area_size((fs * 3.0) as u32)
        .y_label_area_size((fs * 4.0) as u32)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(de)?;
    draw_axes(&mut chart, &c.x, &c.y, fs, false)?;
    let (dx, dy) = ((x1 - x0) / c.nx as f64, (y1 - y0) / c.ny as f64);
    let mut any_empty = false;
    // Runs of equal colour along a row become one rectangle (keeps the SVG small).
    let mut rects = Vec::new();
    for j in 0..c.ny {
        let row = &c.values[j * c.nx..(j + 1) * c.nx];
        let mut i = 0;
        while i < c.nx {
            let colour = |v: f64| {
                if valid(v) {
                    viridis(to_t(v))
                } else {
                    EMPTY_GREY
                }
            };
            let col = colour(row[i]);
            any_empty |= !valid(row[i]);
            let mut k = i + 1;
            while k < c.nx && colour(row[k]) == col {
                any_empty |= !valid(row[k]);
                k += 1;
            }
            rects.push(Rectangle::new(
                [
                    (x0 + i as f64 * dx, y0 + j as f64 * dy),
                    (x0 + k as f64 * dx, y0 + (j + 1) as f64 * dy),
                ],
                col.filled(),
            ));
            i = k;
        }
    }
    chart.draw_series(rects).map_err(de)?;

    // Colour bar: a strip of cells on a linear axis of v (or log10 v), ticks drawn here so that
    // ranges under a decade are labelled too.
    let tr = |v: f64| if c.log_color { v.log10() } else { v };
    let (b0, b1) = (tr(lo), tr(hi));
    let mut bar = ChartBuilder::on(&right)
        .margin_top(font_size(h, 12.0) as u32)
        .margin_bottom((fs * 3.0 + font_size(h, 12.0)) as u32)
        .margin_left((fs * 2.0) as u32)
        .margin_right((fs * 4.5) as u32)
        .build_cartesian_2d(0.0..1.0, b0..b1)
        .map_err(de)?;
    let steps = 128;
    bar.draw_series((0..steps).map(|s| {
        let a = b0 + (b1 - b0) * s as f64 / steps as f64;
        let b = b0 + (b1 - b0) * (s + 1) as f64 / steps as f64;
        Rectangle::new(
            [(0.0, a), (1.0, b)],
            viridis((s as f64 + 0.5) / steps as f64).filled(),
        )
    }))
    .map_err(de)?;
    bar.draw_series(std::iter::once(Rectangle::new(
        [(0.0, b0), (1.0, b1)],
        BLACK.stroke_width(1),
    )))
    .map_err(de)?;
    let tick_style = TextStyle::from((FAMILY, fs * 0.9).into_font()).color(&BLACK);
    bar.draw_series(color_ticks(lo, hi, c.log_color).into_iter().map(|t| {
        EmptyElement::at((1.0, tr(t)))
            + PathElement::new(vec![(0, 0), (5, 0)], BLACK.stroke_width(1))
            + Text::new(
                format_number(t),
                (8, -(fs * 0.45) as i32),
                tick_style.clone(),
            )
    }))
    .map_err(de)?;
    {
        let (rw, rh) = right.dim_in_pixel();
        let style = TextStyle::from((FAMILY, fs).into_font())
            .transform(FontTransform::Rotate270)
            .color(&BLACK);
        let tw = (c.color_label.chars().count() as f64 * fs * 0.55) as i32;
        let _ = rw;
        right
            .draw(&Text::new(
                c.color_label.clone(),
                (
                    (fs * 0.3) as i32,
                    (rh as i32 - (fs * 3.0) as i32) / 2 + tw / 2,
                ),
                style,
            ))
            .map_err(de)?;
    }
    let empty_note = (any_empty && !c.empty_label.is_empty()).then(|| c.empty_label.clone());
    if let Some(note) = empty_note {
        // A grey square, then the note's lines (split at '\n') beside and under it.
        let (rw, rh) = right.dim_in_pixel();
        let lines: Vec<&str> = note.lines().collect();
        let lh = (fs * 1.05) as i32;
        let y = rh as i32 - (fs * 0.6) as i32 - lh * lines.len() as i32;
        let x = (rw as f64 * 0.04) as i32;
        let sq = (fs * 0.8) as i32;
        right
            .draw(&Rectangle::new(
                [(x, y + 2), (x + sq, y + 2 + sq)],
                EMPTY_GREY.filled(),
            ))
            .map_err(de)?;
        for (k, line) in lines.iter().enumerate() {
            right
                .draw(&Text::new(
                    line.to_string(),
                    (x + sq + 4, y + k as i32 * lh),
                    (FAMILY, fs * 0.8),
                ))
                .map_err(de)?;
        }
    }
    Ok(())
}
