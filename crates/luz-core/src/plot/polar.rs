//! Polar plots (BRDF lobes) and the tick rules of colour bars and rings.

use super::*;

// ---------------------------------------------------------------------------------------------
// Polar plot
// ---------------------------------------------------------------------------------------------

/// Tick values for a colour bar over `lo … hi`: 1, 2, 5 × 10^k on a log scale (only powers of
/// ten when there are many), else (or when fewer than 2 fit) about 5 evenly spaced nice values.
pub(super) fn color_ticks(lo: f64, hi: f64, log: bool) -> Vec<f64> {
    let inside = |t: &f64| *t >= lo * (1.0 - 1e-9) && *t <= hi * (1.0 + 1e-9);
    if log && lo > 0.0 {
        let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
        let mut t: Vec<f64> = (k0..=k1)
            .flat_map(|k| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(k)))
            .filter(inside)
            .collect();
        if t.len() > 10 {
            t = (k0..=k1).map(|k| 10f64.powi(k)).filter(inside).collect();
            while t.len() > 10 {
                t = t.into_iter().step_by(2).collect();
            }
        }
        if t.len() >= 2 {
            return t;
        }
    }
    let raw = (hi - lo) / 5.0;
    if !(raw > 0.0 && raw.is_finite()) {
        return vec![lo];
    }
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

/// "Nice" ring radii (1, 2, 2.5, 5 × 10^k), about 4 of them, the last one ≥ `r_max`.
pub(super) fn ring_ticks(r_max: f64) -> Vec<f64> {
    if !(r_max > 0.0 && r_max.is_finite()) {
        return vec![1.0];
    }
    // The tightest outer ring over steps 1, 2, 2.5, 5 × 10^k giving 3 to 6 rings.
    let mag = 10f64.powf((r_max / 4.0).log10().floor());
    let mut best: Option<(f64, usize)> = None;
    for k in [-1, 0, 1] {
        for m in [1.0, 2.0, 2.5, 5.0] {
            let step = m * mag * 10f64.powi(k);
            let n = ((r_max / step) * (1.0 - 1e-9)).ceil().max(1.0) as usize;
            if !(3..=6).contains(&n) {
                continue;
            }
            let outer = n as f64 * step;
            let better = match best {
                None => true,
                Some((s, bn)) => {
                    let bo = bn as f64 * s;
                    outer < bo * (1.0 - 1e-9) || ((outer - bo).abs() <= bo * 1e-9 && n < bn)
                }
            };
            if better {
                best = Some((step, n));
            }
        }
    }
    let (step, n) = best.unwrap_or((r_max, 1));
    (1..=n).map(|k| k as f64 * step).collect()
}

pub(super) fn draw_polar<DB: DrawingBackend>(
    c: &PolarChart,
    root: &DrawingArea<DB, Shift>,
) -> Result<()> {
    let (_, h0) = root.dim_in_pixel();
    let fs = font_size(h0, 16.0);
    let root = titled(root, &c.title)?;
    let (w, h) = root.dim_in_pixel();
    let (w, h) = (w as f64, h as f64);
    let data_max = c
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .filter(|r| r.is_finite())
        .fold(0.0f64, f64::max);
    let r_max = c
        .r_max
        .filter(|r| *r > 0.0 && r.is_finite())
        .unwrap_or(if data_max > 0.0 { data_max } else { 1.0 });
    let rings = ring_ticks(r_max);
    let r_outer = rings.last().copied().unwrap_or(r_max).max(r_max);
    // Pixel geometry: margins for angle labels around, the radius label and legend below.
    let (m, mx) = (fs * 2.2, fs * 3.5);
    let bottom = if c.r_label.is_empty() { m } else { fs * 3.5 };
    // Centred vertically in the space left over.
    let (cx, cy, rp) = if c.half {
        let rp = ((w - 2.0 * mx) / 2.0).min(h - m - bottom).max(10.0);
        let spare = (h - m - bottom - rp).max(0.0) / 2.0;
        (w / 2.0, m + spare + rp, rp)
    } else {
        let rp = ((w - 2.0 * mx) / 2.0).min((h - m - bottom) / 2.0).max(10.0);
        let spare = (h - m - bottom - 2.0 * rp).max(0.0) / 2.0;
        (w / 2.0, m + spare + rp, rp)
    };
    let to_px = |deg: f64, r: f64| -> (i32, i32) {
        let a = deg.to_radians();
        let s = (r / r_outer) * rp;
        (
            (cx + s * a.sin()).round() as i32,
            (cy - s * a.cos()).round() as i32,
        )
    };
    let (a0, a1) = if c.half {
        (-90.0, 90.0)
    } else {
        (-180.0, 180.0)
    };
    let grid = ShapeStyle::from(RGBColor(200, 200, 200)).stroke_width(1);
    let axis = ShapeStyle::from(RGBColor(90, 90, 90)).stroke_width(1);
    // Rings with their radius labels (along +90°).
    for (k, &r) in rings.iter().enumerate() {
        let n = 180;
        let pts: Vec<(i32, i32)> = (0..=n)
            .map(|i| to_px(a0 + (a1 - a0) * i as f64 / n as f64, r))
            .collect();
        let last = k + 1 == rings.len();
        root.draw(&PathElement::new(pts, if last { axis } else { grid }))
            .map_err(de)?;
        let (x, y) = to_px(90.0, r);
        root.draw(&Text::new(
            format_number(r),
            (x - (fs * 0.8) as i32, y + (fs * 0.25) as i32),
            (FAMILY, fs * 0.8),
        ))
        .map_err(de)?;
    }
    // Spokes every 15° (labels every 30°).
    let mut deg = a0;
    while deg <= a1 + 1e-9 {
        if !(c.half || deg > -180.0) {
            deg += 15.0;
            continue;
        }
        root.draw(&PathElement::new(
            vec![to_px(deg, 0.0), to_px(deg, r_outer)],
            grid,
        ))
        .map_err(de)?;
        if (deg as i64) % 30 == 0 {
            let (x, y) = to_px(deg, r_outer * 1.0 + r_outer * (fs * 1.1) / rp);
            let text = format!("{}°", deg as i64);
            let tw = (text.chars().count() as f64 * fs * 0.55) as i32;
            root.draw(&Text::new(
                text,
                (x - tw / 2, y - (fs * 0.5) as i32),
                (FAMILY, fs * 0.9),
            ))
            .map_err(de)?;
        }
        deg += 15.0;
    }
    if c.half {
        root.draw(&PathElement::new(
            vec![to_px(-90.0, r_outer), to_px(90.0, r_outer)],
            axis,
        ))
        .map_err(de)?;
    }
    // Curves and rays.
    for (i, s) in c.series.iter().enumerate() {
        let color = s.color.unwrap_or_else(|| palette(i));
        let style = ShapeStyle::from(color).stroke_width(2);
        for &ray in &s.rays {
            root.draw(&DashedPathElement::new(
                vec![to_px(ray, 0.0), to_px(ray, r_outer)],
                6,
                4,
                ShapeStyle::from(color).stroke_width(1),
            ))
            .map_err(de)?;
        }
        let pts: Vec<(i32, i32)> = s
            .points
            .iter()
            .filter(|p| p.0.is_finite() && p.1.is_finite())
            .map(|&(a, r)| to_px(a, r.clamp(0.0, r_outer)))
            .collect();
        root.draw(&PathElement::new(pts, style)).map_err(de)?;
    }
    // Legend (top left) and the radius label (bottom).
    let mut y = (fs * 0.3) as i32;
    for (i, s) in c
        .series
        .iter()
        .enumerate()
        .filter(|(_, s)| !s.label.is_empty())
    {
        let color = s.color.unwrap_or_else(|| palette(i));
        let x = (fs * 0.5) as i32;
        let ym = y + (fs * 0.5) as i32;
        root.draw(&PathElement::new(
            vec![(x, ym), (x + (fs * 1.5) as i32, ym)],
            ShapeStyle::from(color).stroke_width(2),
        ))
        .map_err(de)?;
        root.draw(&Text::new(
            s.label.clone(),
            (x + (fs * 2.0) as i32, y),
            (FAMILY, fs * 0.9),
        ))
        .map_err(de)?;
        y += (fs * 1.2) as i32;
    }
    if !c.r_label.is_empty() {
        let base = if c.half { cy } else { cy + rp };
        let tw = (c.r_label.chars().count() as f64 * fs * 0.5) as i32;
        root.draw(&Text::new(
            c.r_label.clone(),
            (
                (w / 2.0) as i32 - tw / 2,
                (base + bottom - fs * 1.8).min(h - fs * 1.6) as i32,
            ),
            (FAMILY, fs),
        ))
        .map_err(de)?;
    }
    Ok(())
}
