//! The lab's `area` group (issue 36): every GPU method for each area light shape (rect, disk,
//! sphere, tube) × the material's roughness × the light's solid angle × its elevation (overhead
//! or near the horizon), each row's GPU time beside its error against the CPU reference.
//!
//! Unlike the other groups, each row changes the light and the material, so each *cell* (shape,
//! roughness, solid angle, elevation) has its own reference, shared by its methods. The scene
//! file gives the camera, the output size (the error's resolution) and the surface (its
//! metal_rough materials take the cell's roughness); the group puts one light over the point the
//! camera looks at (the scene's `camera.target`, on a surface with normal +y), `distance` away,
//! facing it, sized for the cell's solid angle there, with radiance 2 / Ω (irradiance ≈ 2 at the
//! target when overhead), `visible: false` (shading only). Time is measured at a larger size
//! ([`AreaSweep::timing_size`]) against the same scene lit by one point light of the same power
//! at the light's centre, in the same run, frames interleaved, so the ratio travels between
//! machines better than the milliseconds do.

use std::path::Path;

use anyhow::{Context as _, Result};
use glam::Vec3;

use crate::headless::Headless;
use crate::imageio::LinearImage;
use crate::scene::{AreaMethod, Material, Scene};

use super::{error_metrics, ErrorMetrics};

/// The shapes of the group, in order.
pub const SHAPES: [&str; 4] = ["rect", "disk", "sphere", "tube"];
/// Roughness of the full sweep.
pub const ROUGHNESS: [f32; 4] = [0.05, 0.25, 0.5, 1.0];
/// Solid angles (sr) at the target of the small and the large light.
pub const SOLID_ANGLES: [(&str, f32); 2] = [("small", 0.01), ("large", 0.25)];
/// Elevations (degrees above the surface, seen from the target) of the light: overhead and
/// near the horizon.
pub const ELEVATIONS: [(&str, f32); 2] = [("overhead", 90.0), ("grazing", 20.0)];
/// Sample counts of the `sampled` method.
pub const SAMPLES: [u32; 3] = [4, 16, 64];
/// Distance (m) from the target to the light's centre.
pub const DISTANCE: f32 = 3.0;
/// A tube's length over its radius.
pub const TUBE_ASPECT: f32 = 8.0;

/// What the group sweeps (the full sweep is [`AreaSweep::default`]; tests run less).
#[derive(Debug, Clone)]
pub struct AreaSweep {
    pub shapes: Vec<&'static str>,
    pub roughness: Vec<f32>,
    pub solid_angles: Vec<(&'static str, f32)>,
    pub elevations: Vec<(&'static str, f32)>,
    pub samples: Vec<u32>,
    /// Size the GPU times are measured at (the error is measured at the scene's output size).
    pub timing_size: (u32, u32),
    /// Timed frames per method (median), interleaved with the cell's other methods and its base.
    pub frames: u32,
    /// The reference's directions per pixel per strategy.
    pub reference_samples: u32,
}

impl Default for AreaSweep {
    fn default() -> Self {
        AreaSweep {
            shapes: SHAPES.to_vec(),
            roughness: ROUGHNESS.to_vec(),
            solid_angles: SOLID_ANGLES.to_vec(),
            elevations: ELEVATIONS.to_vec(),
            samples: SAMPLES.to_vec(),
            timing_size: (320, 192),
            frames: 7,
            reference_samples: 1024,
        }
    }
}

/// One cell of the sweep: a light and a surface, one reference.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct AreaCell {
    pub shape: &'static str,
    pub roughness: f32,
    /// "small" or "large".
    pub size: &'static str,
    /// The solid angle (sr) the light subtends at the target (a tube: its silhouette rectangle's).
    pub solid_angle_sr: f32,
    /// "overhead" or "grazing".
    pub elevation: &'static str,
    pub elevation_deg: f32,
}

/// The methods that apply to `shape`: LTC for every shape (tubes by their facing ribbon), representative
/// point only for spheres and tubes (the GPU shades a rect or disk asking for it by LTC).
pub fn methods(shape: &str, samples: &[u32]) -> Vec<AreaMethod> {
    let mut m = vec![AreaMethod::Ltc];
    if matches!(shape, "sphere" | "tube") {
        m.push(AreaMethod::RepresentativePoint);
    }
    m.extend(
        samples
            .iter()
            .map(|&samples| AreaMethod::Sampled { samples }),
    );
    m
}

/// The method's label: `ltc`, `representative_point`, `sampled 16`.
pub fn method_label(m: AreaMethod) -> String {
    match m {
        AreaMethod::Sampled { samples } => format!("sampled {samples}"),
        m => m.name().to_string(),
    }
}

/// The cells of `sweep`, shape-major.
pub fn cells(sweep: &AreaSweep) -> Vec<AreaCell> {
    let mut out = Vec::new();
    for &shape in &sweep.shapes {
        for &(size, solid_angle_sr) in &sweep.solid_angles {
            for &(elevation, elevation_deg) in &sweep.elevations {
                for &roughness in &sweep.roughness {
                    out.push(AreaCell {
                        shape,
                        roughness,
                        size,
                        solid_angle_sr,
                        elevation,
                        elevation_deg,
                    });
                }
            }
        }
    }
    out
}

/// Solid angle of a `2a × 2b` rectangle seen on its axis from distance `d`.
fn rect_solid_angle(a: f32, b: f32, d: f32) -> f32 {
    4.0 * (a * b / ((a * a + d * d) * (b * b + d * d)).sqrt()).asin()
}

/// The light's JSON for `cell` over `target` (the scene format's fields), and the point light of
/// the same power at its centre.
fn light_json(cell: &AreaCell, target: Vec3, method: Option<AreaMethod>) -> String {
    let omega = cell.solid_angle_sr;
    let d = DISTANCE;
    let e = cell.elevation_deg.to_radians();
    // The light sits in the y-z plane, on the side away from +z (the camera's side in the
    // group's scene), so a grazing light's highlight lies between it and the camera.
    let to_light = Vec3::new(0.0, e.sin(), -e.cos()).normalize();
    let pos = target + to_light * d;
    let dir = -to_light;
    let radiance = 2.0 / omega;
    let p = |v: Vec3| format!("[{}, {}, {}]", v.x, v.y, v.z);
    let Some(method) = method else {
        // A point light giving the same irradiance at the target as the emitter overhead.
        return format!(
            r#"{{"type": "point", "position": {}, "intensity": {}, "falloff": "inverse_square"}}"#,
            p(pos),
            radiance * omega * d * d
        );
    };
    let method = match method {
        AreaMethod::Sampled { samples } => {
            format!(r#""method": "sampled", "samples": {samples}"#)
        }
        m => format!(r#""method": "{}""#, m.name()),
    };
    let cos_cap = 1.0 - omega / (2.0 * std::f32::consts::PI);
    let shape = match cell.shape {
        "rect" => {
            let s = (omega / 4.0).sin();
            let a = d * (s / (1.0 - s)).sqrt();
            // `up` perpendicular to the facing direction, in the y-z plane.
            let up = Vec3::X.cross(dir);
            format!(
                r#""type": "rect", "direction": {}, "up": {}, "size": [{}, {}]"#,
                p(dir),
                p(up),
                2.0 * a,
                2.0 * a
            )
        }
        "disk" => format!(
            r#""type": "disk", "direction": {}, "radius": {}"#,
            p(dir),
            d * cos_cap.acos().tan()
        ),
        "sphere" => format!(
            r#""type": "sphere", "radius": {}"#,
            d * cos_cap.acos().sin()
        ),
        _ => {
            // Bisection on the radius: the silhouette (2r × TUBE_ASPECT·r) subtends omega.
            let (mut lo, mut hi) = (0.0f32, d);
            for _ in 0..60 {
                let r = 0.5 * (lo + hi);
                if rect_solid_angle(r, 0.5 * TUBE_ASPECT * r, d) < omega {
                    lo = r;
                } else {
                    hi = r;
                }
            }
            let r = 0.5 * (lo + hi);
            format!(
                r#""type": "tube", "direction": [1, 0, 0], "length": {}, "radius": {}"#,
                TUBE_ASPECT * r,
                r
            )
        }
    };
    format!(
        r#"{{{shape}, "position": {}, "intensity": {radiance}, "visible": false, "shadow": false, {method}}}"#,
        p(pos)
    )
}

/// The scene of `cell` lit by `method` (`None`: the point light of the same power), every
/// metal_rough material at the cell's roughness, at `size` (`None`: the scene's own).
pub fn cell_scene(
    base: &Scene,
    cell: &AreaCell,
    method: Option<AreaMethod>,
    size: Option<(u32, u32)>,
) -> Result<Scene> {
    let json = format!(
        r#"{{"camera": {{"position": [0, 1, 3], "target": [0, 0, 0]}}, "lights": [{}],
            "materials": {{}}, "objects": []}}"#,
        light_json(cell, base.camera.target, method)
    );
    let lights = crate::scene::parse(&json, Path::new("<area group light>"))
        .with_context(|| format!("the area group's light: {json}"))?;
    let mut s = base.clone();
    s.lights = lights.lights;
    s.area_lights = lights.area_lights;
    for m in &mut s.materials {
        if let Material::MetalRough(p) = &mut m.material {
            p.roughness = cell.roughness;
        }
    }
    if let Some((w, h)) = size {
        s.output.width = w;
        s.output.height = h;
    }
    Ok(s)
}

/// One measured row.
#[derive(Debug, Clone, serde::Serialize)]
pub struct AreaRow {
    pub cell: AreaCell,
    /// `ltc`, `representative_point` or `sampled`.
    pub method: &'static str,
    /// The `sampled` method's count (0 for the others).
    pub samples: u32,
    /// Median GPU ms of the forward pass (where area lights are shaded) at the timing size.
    pub forward_ms: f64,
    /// The same for the cell's point-light scene, measured in the same frames' rounds.
    pub base_forward_ms: f64,
    /// Median GPU ms of the whole frame but the readback, at the timing size.
    pub frame_ms: f64,
    /// Σ|gpu − ref| / Σ ref over every channel of every pixel (the radiance-weighted mean
    /// relative error).
    pub relative_l1: f64,
    pub error: ErrorMetrics,
}

impl AreaRow {
    /// The method's label (`sampled 16`).
    pub fn label(&self) -> String {
        if self.samples > 0 {
            format!("{} {}", self.method, self.samples)
        } else {
            self.method.to_string()
        }
    }

    /// Forward-pass time over the point light's.
    pub fn cost(&self) -> f64 {
        self.forward_ms / self.base_forward_ms
    }
}

/// Σ|x − r| / Σ r over the colour channels.
pub fn relative_l1(reference: &LinearImage, image: &LinearImage) -> f64 {
    let (mut d, mut t) = (0.0f64, 0.0f64);
    for (r, x) in reference.pixels.iter().zip(&image.pixels) {
        for c in 0..3 {
            d += (f64::from(x[c]) - f64::from(r[c])).abs();
            t += f64::from(r[c]).abs();
        }
    }
    d / t.max(1e-30)
}

fn forward_ms(t: &crate::headless::FrameTimes) -> f64 {
    t.gpu_ms
        .iter()
        .filter(|(n, _)| n.contains("forward") || n.contains("lighting") || n.contains("gbuffer"))
        .map(|(_, ms)| ms)
        .sum()
}

fn frame_ms(t: &crate::headless::FrameTimes) -> f64 {
    t.gpu_ms
        .iter()
        .filter(|(n, _)| *n != "readback")
        .map(|(_, ms)| ms)
        .sum()
}

/// Measures every cell of `sweep` on `base`: the cell's reference on the CPU, then each method's
/// image (error at the scene's size) and time (at the timing size, interleaved with the cell's
/// point-light base). `progress` is told each cell.
pub fn measure(
    ctx: &std::sync::Arc<crate::vk::Context>,
    base: &Scene,
    sweep: &AreaSweep,
    render: &crate::headless::RenderOptions,
    progress: Option<&dyn crate::progress::Progress>,
) -> Result<Vec<AreaRow>> {
    let reporting = crate::progress::Reporting(progress);
    let cells = cells(sweep);
    let mut rows = Vec::new();
    for (i, cell) in cells.iter().enumerate() {
        reporting.update(
            &format!(
                "{} {} {} roughness {}",
                cell.shape, cell.size, cell.elevation, cell.roughness
            ),
            i as u64,
            cells.len() as u64,
        );
        let opts = crate::reference::ReferenceOptions {
            samples: sweep.reference_samples,
            spp: base.output.msaa.max(1),
            ..Default::default()
        };
        // Any method's scene: the reference integrates the emitter itself.
        let reference = crate::reference::render_reference(
            &cell_scene(base, cell, Some(AreaMethod::Ltc), None)?,
            &opts,
            None,
        )?;
        let methods = methods(cell.shape, &sweep.samples);
        // Index 0: the point light; then the methods.
        let mut timed = vec![Headless::with_options(
            ctx,
            &cell_scene(base, cell, None, Some(sweep.timing_size))?,
            render,
        )?];
        let mut errors = Vec::new();
        for &m in &methods {
            let scene = cell_scene(base, cell, Some(m), None)?;
            let mut r = Headless::with_options(ctx, &scene, render)?;
            r.render()?;
            let image = r.image()?;
            drop(r);
            let (error, _) = error_metrics(
                &reference,
                &image,
                base.output.exposure,
                base.output.tonemap,
            )?;
            errors.push((relative_l1(&reference, &image), error));
            timed.push(Headless::with_options(
                ctx,
                &cell_scene(base, cell, Some(m), Some(sweep.timing_size))?,
                render,
            )?);
        }
        for r in &mut timed {
            r.render()?;
            r.render()?;
        }
        let mut fwd = vec![Vec::new(); timed.len()];
        let mut frame = vec![Vec::new(); timed.len()];
        for _ in 0..sweep.frames {
            for (k, r) in timed.iter_mut().enumerate() {
                let t = r.render()?;
                fwd[k].push(forward_ms(&t));
                frame[k].push(frame_ms(&t));
            }
        }
        let base_ms = crate::stats::median(&fwd[0]);
        for (k, (&m, (l1, error))) in methods.iter().zip(errors).enumerate() {
            rows.push(AreaRow {
                cell: *cell,
                method: m.name(),
                samples: match m {
                    AreaMethod::Sampled { samples } => samples,
                    _ => 0,
                },
                forward_ms: crate::stats::median(&fwd[k + 1]),
                base_forward_ms: base_ms,
                frame_ms: crate::stats::median(&frame[k + 1]),
                relative_l1: l1,
                error,
            });
        }
    }
    Ok(rows)
}

/// Writes `results.csv`, `results.json` and `chart.png`/`chart.svg` (relative L1 against the
/// forward pass's cost over the point light's, log-log, one colour per method) into `dir`.
pub fn write_outputs(dir: &Path, base: &Scene, sweep: &AreaSweep, rows: &[AreaRow]) -> Result<()> {
    let mut csv = String::from(
        "shape,method,samples,roughness,size,solid_angle_sr,elevation,elevation_deg,forward_ms,point_forward_ms,cost_x_point,frame_ms,relative_l1,mean_relative,rmse,flip_mean,nan_pixels\n",
    );
    for r in rows {
        let c = &r.cell;
        csv.push_str(&format!(
            "{},{},{},{},{},{},{},{},{:.4},{:.4},{:.3},{:.4},{:.6},{:.6},{:.6},{:.6},{}\n",
            c.shape,
            r.method,
            r.samples,
            c.roughness,
            c.size,
            c.solid_angle_sr,
            c.elevation,
            c.elevation_deg,
            r.forward_ms,
            r.base_forward_ms,
            r.cost(),
            r.frame_ms,
            r.relative_l1,
            r.error.mean_relative,
            r.error.rmse,
            r.error.flip_mean,
            r.error.nan_pixels
        ));
    }
    std::fs::write(dir.join("results.csv"), csv)
        .with_context(|| format!("cannot write {}", dir.join("results.csv").display()))?;
    let json = serde_json::json!({
        "scene": base.source.as_ref().map(|p| p.display().to_string()),
        "width": base.output.width,
        "height": base.output.height,
        "timing_size": sweep.timing_size,
        "frames": sweep.frames,
        "reference_samples": sweep.reference_samples,
        "results": rows,
    });
    std::fs::write(
        dir.join("results.json"),
        serde_json::to_string_pretty(&json)?,
    )
    .with_context(|| format!("cannot write {}", dir.join("results.json").display()))?;
    let mut groups: Vec<String> = Vec::new();
    for r in rows {
        if !groups.contains(&r.label()) {
            groups.push(r.label());
        }
    }
    let points = rows
        .iter()
        .filter(|r| r.relative_l1 > 0.0 && r.cost().is_finite() && r.cost() > 0.0)
        .map(|r| crate::plot::LabeledPoint {
            x: r.cost(),
            y: r.relative_l1,
            label: String::new(),
            group: groups.iter().position(|g| *g == r.label()).unwrap_or(0),
        })
        .collect();
    let chart = crate::plot::ScatterChart {
        title: "area lights: error against GPU cost (every shape, roughness, size, elevation)"
            .into(),
        x: crate::plot::Axis::new("forward pass GPU ms / the same scene with a point light (log)")
            .range(1.0, 20.0)
            .log(),
        y: crate::plot::Axis::new("relative L1 against the CPU reference (log)").log(),
        points,
        groups,
        legend: crate::plot::Legend::UpperRight,
    };
    let mut meta = crate::imageio::Provenance::base();
    crate::provenance::add_scene(&mut meta, base);
    meta.set("luz.lab.variants", rows.len().to_string());
    crate::plot::save_png_svg_with(&chart.into(), &dir.join("chart"), (1100, 700), &meta)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn base() -> Scene {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/lab/area.json");
        crate::scene::load(&path).unwrap()
    }

    /// Each shape's light subtends the cell's solid angle at the target (measured by the
    /// reference's own sampling geometry: a sphere's cone, a disk's and a rect's exact on-axis
    /// forms), sits `DISTANCE` away at the cell's elevation above the surface, and the point light
    /// gives the emitter's overhead irradiance.
    #[test]
    fn cells_place_and_size_the_light() {
        let base = base();
        let sweep = AreaSweep::default();
        let all = cells(&sweep);
        assert_eq!(all.len(), 4 * 4 * 2 * 2);
        for cell in &all {
            let s = cell_scene(&base, cell, Some(AreaMethod::Ltc), None).unwrap();
            assert_eq!(s.area_lights.len(), 1);
            assert!(s.lights.is_empty());
            let a = &s.area_lights[0];
            let to = a.position - base.camera.target;
            assert!((to.length() - DISTANCE).abs() < 1e-4);
            let elev = (to.y / to.length()).asin().to_degrees();
            assert!((elev - cell.elevation_deg).abs() < 1e-3, "{elev}");
            assert!(!a.visible);
            let omega = match a.shape {
                crate::scene::AreaShape::Sphere { radius } => {
                    let s = radius / DISTANCE;
                    2.0 * std::f32::consts::PI * (1.0 - (1.0 - s * s).sqrt())
                }
                crate::scene::AreaShape::Disk { radius } => {
                    2.0 * std::f32::consts::PI
                        * (1.0 - DISTANCE / (DISTANCE * DISTANCE + radius * radius).sqrt())
                }
                crate::scene::AreaShape::Rect { width, height, .. } => {
                    rect_solid_angle(0.5 * width, 0.5 * height, DISTANCE)
                }
                crate::scene::AreaShape::Tube { length, radius } => {
                    assert!((length / radius - TUBE_ASPECT).abs() < 1e-3);
                    rect_solid_angle(radius, 0.5 * length, DISTANCE)
                }
            };
            assert!(
                (omega / cell.solid_angle_sr - 1.0).abs() < 1e-3,
                "{cell:?}: {omega}"
            );
            // Every emitter stays above the surface (no horizon crossing in the group).
            let lowest = match a.shape {
                crate::scene::AreaShape::Rect { .. } => {
                    let (x, y) = a.rect_axes().unwrap();
                    a.position.y - x.y.abs() - y.y.abs()
                }
                crate::scene::AreaShape::Disk { radius } => {
                    a.position.y - radius * (1.0 - a.direction.y * a.direction.y).sqrt()
                }
                crate::scene::AreaShape::Sphere { radius }
                | crate::scene::AreaShape::Tube { radius, .. } => a.position.y - radius,
            };
            assert!(lowest > 0.1, "{cell:?}: {lowest}");
            let p = cell_scene(&base, cell, None, Some((8, 4))).unwrap();
            assert!(p.area_lights.is_empty());
            let e = p.lights[0].intensity / (DISTANCE * DISTANCE);
            assert!((e - 2.0).abs() < 1e-4);
            assert_eq!((p.output.width, p.output.height), (8, 4));
        }
        assert_eq!(methods("tube", &SAMPLES).len(), 2 + SAMPLES.len());
        assert_eq!(methods("tube", &SAMPLES)[0], AreaMethod::Ltc);
        assert_eq!(methods("sphere", &SAMPLES).len(), 2 + SAMPLES.len());
        assert_eq!(methods("rect", &SAMPLES)[0], AreaMethod::Ltc);
    }
}
