//! The BRDF charts of `luz brdf --plot` and of the viewer's lobe plots: the in-plane polar lobe,
//! the θh × θd slice and the directional-albedo curve of a [`Model`], as plain chart data
//! ([`super::PolarChart`], [`super::Heatmap`], [`super::LineChart`]) for [`super::save`] or
//! [`super::render_rgb`].

use anyhow::{bail, Result};
use glam::Vec3;

use crate::brdf::{self, Model};
use crate::plot;

/// The unit vector at polar angle `theta` and azimuth `phi` (degrees), n = +z, x = +x.
pub fn spherical(theta_deg: f64, phi_deg: f64) -> Vec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    // Exact zeros at multiples of 90° (sin π is 1.2e-16, not 0).
    let c = |x: f64| if x.abs() < 1e-12 { 0.0 } else { x as f32 };
    Vec3::new(c(t.sin() * p.cos()), c(t.sin() * p.sin()), c(t.cos()))
}

/// Rec. 709 luminance of a linear RGB value.
pub fn luminance(c: Vec3) -> f64 {
    0.2126 * c.x as f64 + 0.7152 * c.y as f64 + 0.0722 * c.z as f64
}

/// The polar lobe chart: f·cos θv (luminance) in the plane of incidence for each θl.
pub fn lobe_chart(model: &Model, incidence: &[f64]) -> Result<plot::PolarChart> {
    let mut series = Vec::new();
    for &tl in incidence {
        if !(0.0..90.0).contains(&tl) {
            bail!("--incidence {tl}: light angles must be in [0, 90) degrees");
        }
        // Light on the left (φ = 180), views across the plane (θv < 0: φ = 180, > 0: φ = 0);
        // dense around the mirror direction θv = +θl so narrow lobes are resolved.
        let mut angles: Vec<f64> = (0..=720).map(|i| -90.0 + i as f64 * 0.25).collect();
        angles.extend(
            (-300..=300)
                .map(|i| tl + i as f64 * 0.01)
                .filter(|a| *a <= 90.0),
        );
        angles.sort_by(f64::total_cmp);
        angles.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        let l = spherical(tl, 180.0);
        let points = angles
            .into_iter()
            .map(|tv| {
                let v = spherical(tv, 0.0);
                let f = brdf::eval(model, Vec3::Z, l, v, Vec3::X, Vec3::Y);
                (tv, luminance(f) * (v.z.max(0.0) as f64))
            })
            .collect();
        series.push(plot::PolarSeries {
            label: format!("θl = {}°", plot::format_number(tl)),
            points,
            color: None,
            rays: vec![-tl],
        });
    }
    Ok(plot::PolarChart {
        title: format!("{}: in-plane lobe f·cos θv", model.name()),
        series,
        r_max: None,
        half: true,
        r_label: "radius: f·cos θv (luminance, 1/sr) at view angle θv; dashed: light direction"
            .into(),
    })
}

/// The θh × θd slice of f (luminance) at `phi_d` degrees, `cells` × `cells`.
pub fn slice_chart(model: &Model, phi_d: f64, cells: usize, decades: f64) -> plot::Heatmap {
    let step = 90.0 / cells as f64;
    let mut values = Vec::with_capacity(cells * cells);
    let (sp, cp) = phi_d.to_radians().sin_cos();
    for j in 0..cells {
        let td = ((j as f64 + 0.5) * step).to_radians();
        let d = (td.sin() * cp, td.sin() * sp, td.cos());
        for i in 0..cells {
            let th = ((i as f64 + 0.5) * step).to_radians();
            let (s, c) = th.sin_cos();
            // Rotate the difference vector (and its reflection about h) by θh about y.
            let rot = |x: f64, y: f64, z: f64| {
                Vec3::new((x * c + z * s) as f32, y as f32, (-x * s + z * c) as f32)
            };
            let l = rot(d.0, d.1, d.2);
            let v = rot(-d.0, -d.1, d.2);
            let value = if l.z <= 0.0 || v.z <= 0.0 {
                f64::NAN
            } else {
                luminance(brdf::eval(model, Vec3::Z, l, v, Vec3::X, Vec3::Y))
            };
            values.push(value);
        }
    }
    plot::Heatmap {
        title: format!(
            "{}: f(θh, θd) at φd = {}°, log scale",
            model.name(),
            plot::format_number(phi_d)
        ),
        x: plot::Axis::new("θh (degrees)").range(0.0, 90.0),
        y: plot::Axis::new("θd (degrees)").range(0.0, 90.0),
        nx: cells,
        ny: cells,
        values,
        log_color: true,
        color_range: None,
        log_decades: decades,
        color_label: "f (luminance, 1/sr)".into(),
        empty_label: "f = 0: l or v\nbelow horizon".into(),
    }
}

pub fn albedo_angles() -> Vec<f64> {
    let mut a: Vec<f64> = (0..36).map(|i| i as f64 * 2.5).collect();
    a.push(89.0);
    a
}

/// Directional albedo R(θl) of `model` at [`albedo_angles`] (`samples` per angle).
pub fn albedo_curve(model: &Model, samples: u32) -> Vec<(f64, Vec3)> {
    albedo_angles()
        .iter()
        .map(|&t| {
            (
                t,
                brdf::directional_albedo(model, t.to_radians().cos() as f32, samples),
            )
        })
        .collect()
}

/// The directional-albedo chart of one model: one curve per channel, one when R = G = B.
pub fn albedo_chart_of(model: &Model, samples: u32) -> plot::LineChart {
    let title = format!("{}: directional albedo", model.name());
    let c = albedo_curve(model, samples);
    let mut series = Vec::new();
    let grey = c
        .iter()
        .all(|(_, r)| (r.x - r.y).abs() < 1e-6 && (r.x - r.z).abs() < 1e-6);
    if grey {
        series.push(
            plot::Series::new(
                "R = G = B",
                c.iter().map(|(t, r)| (*t, r.x as f64)).collect(),
            )
            .color(plot::palette(0)),
        );
    } else {
        let chans = [
            ("red", plot::RGBColor(200, 30, 30), 0usize),
            ("green", plot::RGBColor(30, 150, 30), 1),
            ("blue", plot::RGBColor(40, 70, 220), 2),
        ];
        for (name, col, k) in chans {
            let pts = c.iter().map(|(t, r)| (*t, r[k] as f64)).collect();
            series.push(plot::Series::new(name, pts).color(col));
        }
    }
    albedo_line_chart(title, series, false)
}

/// The albedo chart around `series`: the y range, the dashed line at 1 and the axis labels
/// (`swept`: one curve per parameter value, largest channel).
pub fn albedo_line_chart(
    title: String,
    mut series: Vec<plot::Series>,
    swept: bool,
) -> plot::LineChart {
    let y_max = series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .fold(1.0f64, f64::max);
    series.push(
        plot::Series::new("1 (energy conserved)", vec![(0.0, 1.0), (90.0, 1.0)])
            .color(plot::RGBColor(0, 0, 0))
            .dashed(),
    );
    let y_label = if swept {
        "directional albedo R(θl), largest RGB channel"
    } else {
        "directional albedo R(θl)"
    };
    plot::LineChart {
        title,
        x: plot::Axis::new("light angle θl (degrees)").range(0.0, 90.0),
        y: plot::Axis::new(y_label).range(0.0, y_max * 1.08),
        series,
        legend: plot::Legend::LowerLeft,
    }
}
