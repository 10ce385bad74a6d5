//! `luz lab`: speed against accuracy. Renders a scene with every method variant that applies to
//! it — shading frequency × tessellation, BRDF terms, IBL methods — times each on the GPU and
//! measures its error against the CPU reference, then writes `results.csv`, `results.json`,
//! `chart.png`/`chart.svg` (error, log, against GPU ms with the Pareto front marked) and one FLIP
//! heat map per variant.

pub mod area;
pub mod glass;
pub mod layers;
pub mod shadows;

use std::path::Path;

use anyhow::{bail, Context as _, Result};

use crate::brdf::{Diffuse, Distribution, Fresnel, Geometry, SpecularSource};
use crate::headless::Headless;
use crate::imageio::LinearImage;
use crate::scene::{
    DiffuseMethod, Material, MeshDesc, Scene, Shading, SpecularMethod, MAX_PRIMITIVE_TRIANGLES,
};

/// One method variant: a label, its group and the scene that realises it.
pub struct Variant {
    pub group: &'static str,
    pub label: String,
    pub scene: Scene,
}

/// Error of an image against the reference.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct ErrorMetrics {
    /// Root mean square of the per-channel linear radiance difference.
    pub rmse: f64,
    /// Mean over pixels and channels of |x − r| / max(r, 0.01 · mean(r)).
    pub mean_relative: f64,
    /// Mean FLIP of the display-encoded images (scene exposure and tone map).
    pub flip_mean: f64,
    /// Largest per-channel absolute difference (linear radiance).
    pub max_abs: f64,
    /// Pixels with a NaN or Inf channel in the variant's image.
    pub nan_pixels: u64,
}

/// Linear-radiance and display-space error of `image` against `reference` (same size).
pub fn error_metrics(
    reference: &LinearImage,
    image: &LinearImage,
    exposure_ev: f32,
    tonemap: crate::color::Tonemap,
) -> Result<(ErrorMetrics, crate::diff::FlipMap)> {
    if (reference.width, reference.height) != (image.width, image.height) {
        bail!(
            "reference is {}x{}, the render {}x{}",
            reference.width,
            reference.height,
            image.width,
            image.height
        );
    }
    let n = reference.pixels.len().max(1) as f64;
    let mean_ref: f64 = reference
        .pixels
        .iter()
        .flat_map(|p| p[..3].iter())
        .filter(|v| v.is_finite())
        .map(|&v| v as f64)
        .sum::<f64>()
        / (3.0 * n);
    let floor = (0.01 * mean_ref).max(1e-6);
    let (mut sq, mut rel, mut max_abs, mut nan) = (0.0f64, 0.0f64, 0.0f64, 0u64);
    for (r, x) in reference.pixels.iter().zip(&image.pixels) {
        if x[..3].iter().any(|v| !v.is_finite()) {
            nan += 1;
            continue;
        }
        for c in 0..3 {
            let d = (x[c] as f64 - r[c] as f64).abs();
            sq += d * d;
            rel += d / (r[c] as f64).max(floor);
            max_abs = max_abs.max(d);
        }
    }
    let finite = (n - nan as f64).max(1.0);
    let map = crate::compare::display_flip(
        &reference.pixels,
        &image.pixels,
        (image.width, image.height),
        exposure_ev,
        tonemap,
    );
    let flip_mean = map.values.iter().map(|&v| v as f64).sum::<f64>() / n;
    Ok((
        ErrorMetrics {
            rmse: (sq / (3.0 * finite)).sqrt(),
            mean_relative: rel / (3.0 * finite),
            flip_mean,
            max_abs,
            nan_pixels: nan,
        },
        map,
    ))
}

/// Segment counts the tessellation sweep uses.
pub const SEGMENTS: [u32; 6] = [8, 16, 32, 64, 128, 256];
/// Budgets (px of silhouette error) of the automatic-tessellation sweep
/// ([`crate::scene::tessellation`]).
pub const TESSELLATION_BUDGETS_PX: [f32; 7] = [1.0, 0.5, 0.25, 0.1, 0.05, 0.025, 0.01];

/// The scene with every sphere, cone and cylinder tessellated automatically within `budget_px`
/// (shading as written); `None` when it has none.
fn with_auto_tessellation(scene: &Scene, budget_px: f32) -> Option<(Scene, u32, u32)> {
    let mut s = scene.clone();
    crate::scene::tessellation::make_automatic(&mut s, budget_px);
    let segments: Vec<u32> = s.objects.iter().filter_map(|o| o.desc.segments()).collect();
    let lo = *segments.iter().min()?;
    let hi = *segments.iter().max()?;
    Some((s, lo, hi))
}

/// Budgets (px) of the `lod` group: `output.tessellation_error_px` from full detail (0) up;
/// automatic LOD of OBJ and glTF meshes ([`crate::scene::lod`]) and the primitives' automatic
/// tessellation follow it.
pub const LOD_BUDGETS_PX: [f32; 8] = [0.0, 0.05, 0.1, 0.25, 0.5, 1.0, 2.0, 4.0];

/// The `lod` group: the scene at each of [`LOD_BUDGETS_PX`]; nothing without an OBJ or glTF
/// mesh (no level to choose).
fn lod_variants(scene: &Scene) -> Vec<Variant> {
    use crate::scene::MeshDesc;
    if !scene
        .objects
        .iter()
        .any(|o| matches!(o.desc, MeshDesc::Obj { .. } | MeshDesc::Gltf { .. }))
    {
        return Vec::new();
    }
    LOD_BUDGETS_PX
        .iter()
        .map(|&b| {
            let mut s = scene.clone();
            s.output.tessellation_error_px = b;
            crate::scene::tessellation::resolve(&mut s);
            Variant {
                group: "lod",
                label: if b == 0.0 {
                    "lod 0 px (full detail)".into()
                } else {
                    format!("lod {b} px")
                },
                scene: s,
            }
        })
        .collect()
}

/// Sample counts of the importance-sampling sweep.
pub const IBL_SAMPLES: [u32; 6] = [1, 4, 16, 64, 256, 1024];

fn with_tessellation(scene: &Scene, shading: Shading, segments: u32) -> Option<Scene> {
    let mut s = scene.clone();
    let mut changed = false;
    for o in &mut s.objects {
        let desc = match o.desc {
            MeshDesc::Sphere { radius, .. } => MeshDesc::Sphere {
                radius,
                segments,
                rings: (segments / 2).max(3),
            },
            MeshDesc::Cone { radius, height, .. } => MeshDesc::Cone {
                radius,
                height,
                segments,
            },
            MeshDesc::Cylinder { radius, height, .. } => MeshDesc::Cylinder {
                radius,
                height,
                segments,
            },
            _ => continue,
        };
        if desc.triangle_count().unwrap_or(u64::MAX) > MAX_PRIMITIVE_TRIANGLES {
            return None;
        }
        o.mesh = std::sync::Arc::new(desc.build()?);
        o.desc = desc;
        o.shading = shading;
        o.tessellation = crate::scene::Tessellation::Given;
        changed = true;
    }
    changed.then_some(s)
}

fn with_terms(scene: &Scene, d: Distribution, g: Geometry, f: Fresnel) -> Option<Scene> {
    let mut s = scene.clone();
    let mut changed = false;
    for m in &mut s.materials {
        match &mut m.material {
            Material::MetalRough(p) => {
                if matches!(f, Fresnel::Conductor | Fresnel::ConductorExact) {
                    continue;
                }
                p.distribution = d;
                p.geometry = g;
                p.fresnel = f;
                changed = true;
            }
            Material::CookTorrance(p) => {
                p.distribution = d;
                p.geometry = g;
                p.fresnel = f;
                changed = true;
            }
            _ => {}
        }
    }
    // Cook-Torrance's Fresnel source must suit the form (F0 vs η/κ): keep only valid scenes.
    let valid = s.materials.iter().all(|m| match &m.material {
        Material::CookTorrance(p) => match p.fresnel {
            Fresnel::Conductor | Fresnel::ConductorExact => {
                matches!(p.specular, SpecularSource::Complex(_))
            }
            Fresnel::Dielectric => !matches!(p.specular, SpecularSource::Complex(_)),
            _ => true,
        },
        _ => true,
    });
    (changed && valid).then_some(s)
}

/// The scene with every Cook-Torrance and metal-rough material's diffuse lobe set to `diffuse`
/// (the other terms as written), and the label `d/g/f/diffuse` of its terms (`terms as
/// written/diffuse` when the materials differ). `None` without such materials.
fn with_diffuse(scene: &Scene, diffuse: Diffuse) -> Option<(Scene, String)> {
    let mut s = scene.clone();
    let mut terms = std::collections::BTreeSet::new();
    for m in &mut s.materials {
        match &mut m.material {
            Material::MetalRough(p) => {
                p.diffuse = diffuse;
                terms.insert(format!(
                    "{:?}/{:?}/{:?}",
                    p.distribution, p.geometry, p.fresnel
                ));
            }
            Material::CookTorrance(p) => {
                p.diffuse = diffuse;
                terms.insert(format!(
                    "{:?}/{:?}/{:?}",
                    p.distribution, p.geometry, p.fresnel
                ));
            }
            _ => {}
        }
    }
    let terms = match terms.len() {
        0 => return None,
        1 => terms.pop_first().unwrap_or_default().to_lowercase(),
        _ => "terms as written".to_string(),
    };
    Some((s, format!("{terms}/{}", diffuse.name())))
}

/// Radiance-cut thresholds of the `lights` group: each inverse-square point and spot light gets
/// the range at which cutting it changes the irradiance anywhere by at most the threshold
/// ([`crate::scene::range_for_threshold`]; the radiance by at most the BRDF's f·cos θ times that).
pub const RANGE_THRESHOLDS: [f32; 4] = [1e-2, 1e-3, 1e-4, 1e-5];

/// The scene with every inverse-square point and spot light given the range for `threshold`
/// (`None`: every range removed); `None` when no light changes.
fn with_ranges(scene: &Scene, threshold: Option<f32>) -> Option<Scene> {
    use crate::scene::{Falloff, LightKind};
    let mut s = scene.clone();
    let mut changed = false;
    for l in &mut s.lights {
        if l.kind == LightKind::Directional {
            continue;
        }
        let range = match threshold {
            None => None,
            Some(_) if l.falloff != Falloff::InverseSquare => continue,
            Some(t) => crate::scene::range_for_threshold(l.intensity * l.color.max_element(), t),
        };
        if range.is_none() && threshold.is_some() {
            continue;
        }
        changed |= l.range != range;
        l.range = range;
    }
    changed.then_some(s)
}

/// Every variant of the lab that applies to `scene` (the scene as written comes first).
pub fn variants(scene: &Scene, only: &[String]) -> Vec<Variant> {
    let want = |g: &str| only.is_empty() || only.iter().any(|o| o == g);
    let mut out = vec![Variant {
        group: "as written",
        label: "as written".into(),
        scene: scene.clone(),
    }];
    if want("tessellation") {
        for (shading, name) in [
            (Shading::Flat, "flat"),
            (Shading::Gouraud, "gouraud"),
            (Shading::Phong, "phong"),
        ] {
            for seg in SEGMENTS {
                if let Some(s) = with_tessellation(scene, shading, seg) {
                    out.push(Variant {
                        group: "tessellation",
                        label: format!("{name} {seg}"),
                        scene: s,
                    });
                }
            }
        }
    }
    if want("auto") {
        for budget in TESSELLATION_BUDGETS_PX {
            if let Some((s, lo, hi)) = with_auto_tessellation(scene, budget) {
                let range = if lo == hi {
                    format!("{lo}")
                } else {
                    format!("{lo}-{hi}")
                };
                out.push(Variant {
                    group: "auto tessellation",
                    label: format!("auto {budget} px ({range} seg.)"),
                    scene: s,
                });
            }
        }
    }
    // The terms only change punctual lighting (image-based lighting uses its own GGX prefilter
    // and LUT), so without lights they would all measure the same image.
    if want("brdf") && !scene.lights.is_empty() {
        for d in [Distribution::Beckmann, Distribution::Ggx] {
            // Beckmann's own Smith term beside the GGX forms at its width (issue 34).
            let beckmann = (d == Distribution::Beckmann).then_some(Geometry::SmithBeckmann);
            for g in [
                Geometry::CookTorrance,
                Geometry::SmithGgx,
                Geometry::SmithGgxCorrelated,
                Geometry::SchlickGgx,
            ]
            .into_iter()
            .chain(beckmann)
            {
                // The conductor Fresnel's approximation beside the exact equations (issue 34).
                for f in [
                    Fresnel::Schlick,
                    Fresnel::Dielectric,
                    Fresnel::Conductor,
                    Fresnel::ConductorExact,
                ] {
                    if let Some(s) = with_terms(scene, d, g, f) {
                        out.push(Variant {
                            group: "brdf",
                            label: format!("{d:?}/{g:?}/{f:?}").to_lowercase(),
                            scene: s,
                        });
                    }
                }
            }
        }
        // Lambert vs Burley diffuse, with the scene's own specular terms (two variants rather
        // than doubling the grid above).
        for diffuse in Diffuse::ALL {
            if let Some((s, label)) = with_diffuse(scene, diffuse) {
                out.push(Variant {
                    group: "brdf",
                    label,
                    scene: s,
                });
            }
        }
    }
    // Light ranges: cheaper frames (clustered culling) against the error of the cut-off; the
    // reference has no cut-off unless the scene sets one.
    if want("lights") {
        if let Some(s) = with_ranges(scene, None) {
            out.push(Variant {
                group: "lights",
                label: "no ranges".into(),
                scene: s,
            });
        }
        for t in RANGE_THRESHOLDS {
            if let Some(s) = with_ranges(scene, Some(t)) {
                out.push(Variant {
                    group: "lights",
                    label: format!("ranges for {t:.0e}"),
                    scene: s,
                });
            }
        }
    }
    if want("shadows") {
        out.extend(shadows::variants(scene));
    }
    if want("lod") {
        out.extend(lod_variants(scene));
    }
    if want("glass") {
        out.extend(glass::variants(scene));
    }
    if want("layers") {
        out.extend(layers::variants(scene));
    }
    if want("ibl") {
        if let Some(env) = &scene.environment {
            let mut push = |label: String, f: &dyn Fn(&mut crate::scene::Environment)| {
                let mut s = scene.clone();
                if let Some(e) = &mut s.environment {
                    f(e);
                }
                out.push(Variant {
                    group: "ibl",
                    label,
                    scene: s,
                });
            };
            for (dn, diffuse) in DiffuseMethod::NAMED {
                for ec in [false, true] {
                    push(
                        format!("split sum, {dn}{}", if ec { ", energy comp." } else { "" }),
                        &|e| {
                            e.specular_method = SpecularMethod::SplitSum;
                            e.diffuse_method = diffuse;
                            e.energy_compensation = ec;
                        },
                    );
                }
            }
            for (dn, diffuse) in DiffuseMethod::NAMED {
                push(format!("fitted lobes, {dn}"), &|e| {
                    e.specular_method = SpecularMethod::FittedLobes;
                    e.diffuse_method = diffuse;
                    e.energy_compensation = false;
                });
            }
            for n in IBL_SAMPLES {
                push(format!("importance N={n}"), &|e| {
                    e.specular_method = SpecularMethod::Importance;
                    e.samples = n;
                    e.mip_filtered_samples = true;
                });
            }
            let _ = env;
        }
    }
    out
}

/// One measured variant.
#[derive(Debug, Clone, serde::Serialize)]
pub struct LabResult {
    pub group: String,
    pub label: String,
    /// The smallest of `gpu_ms_rounds`.
    pub gpu_ms: f64,
    /// Each timing round's median GPU ms, in round order.
    pub gpu_ms_rounds: Vec<f64>,
    /// The shadow pass's part of `gpu_ms` (median of the same frames; 0 without shadows).
    pub shadow_ms: f64,
    pub triangles: u64,
    pub pipelines: Vec<String>,
    pub error: ErrorMetrics,
    /// The `lod` group only: mean FLIP against the group's full-detail render (budget 0), the
    /// measure of issue 17's goal; `error` is against the reference.
    pub flip_vs_full: Option<f64>,
    pub pareto: bool,
}

/// Marks the results no other result beats in both GPU ms and FLIP error.
pub fn mark_pareto(results: &mut [LabResult]) {
    let pts: Vec<(f64, f64)> = results
        .iter()
        .map(|r| (r.gpu_ms, r.error.flip_mean))
        .collect();
    for (i, r) in results.iter_mut().enumerate() {
        let (t, e) = pts[i];
        r.pareto = t.is_finite()
            && e.is_finite()
            && !pts
                .iter()
                .enumerate()
                .any(|(j, &(t2, e2))| j != i && t2 <= t && e2 <= e && (t2 < t || e2 < e));
    }
}

/// How [`measure`] times each variant.
#[derive(Debug, Clone)]
pub struct LabOptions {
    /// Timed frames per variant (median of their GPU time).
    pub frames: u32,
    /// Timing rounds over all variants, alternating forward and reverse order; a variant's time
    /// is the smallest of its rounds' medians.
    pub rounds: u32,
    /// How every variant is rendered (IBL sizes, cache).
    pub render: crate::headless::RenderOptions,
}

/// Renders the scene as written and every variant on `ctx`, times each (`options.rounds` rounds
/// of `options.frames` frames, alternating order), measures each image against `reference` and
/// writes its FLIP heat map to `heatmaps/NNN.png` under `out`. The last result is the scene as
/// written with "all features" pipelines. `progress` is told each variant (stage: its label, or
/// the timing round).
pub fn measure(
    ctx: &std::sync::Arc<crate::vk::Context>,
    scene: &Scene,
    variants: &[Variant],
    reference: &LinearImage,
    out: &Path,
    options: &LabOptions,
    progress: Option<&dyn crate::progress::Progress>,
) -> Result<Vec<LabResult>> {
    let reporting = crate::progress::Reporting(progress);
    // A throw-away run first, so the first variant is not timed on cold caches.
    {
        let mut warm = Headless::with_options(ctx, scene, &options.render)?;
        for _ in 0..3 {
            warm.render()?;
        }
    }
    // The scene as written once more with "all features" pipelines (runtime BRDF selectors, every
    // map and light kind): what building only the pipelines a scene needs saves.
    let mut runs: Vec<(&'static str, String, &Scene, bool)> = variants
        .iter()
        .map(|v| (v.group, v.label.clone(), &v.scene, false))
        .collect();
    runs.push((
        "all features",
        "as written, all-features pipelines".into(),
        scene,
        true,
    ));
    let total = runs.len() as u64;
    let mut results = Vec::new();
    // The `lod` group's full-detail image (its first variant), for its FLIP against full detail.
    let mut lod_full: Option<LinearImage> = None;
    let time = |vscene: &Scene, generic: bool| -> Result<(f64, f64, Headless)> {
        let opts = crate::headless::RenderOptions {
            generic_pipelines: generic,
            ..options.render.clone()
        };
        let mut r = Headless::with_options(ctx, vscene, &opts)?;
        // Warm-up: the first frames compile the driver's code and fault in memory.
        r.render()?;
        r.render()?;
        let (mut times, mut shadow) = (Vec::new(), Vec::new());
        for _ in 0..options.frames {
            let t = r.render()?;
            shadow.push(
                t.gpu_ms
                    .iter()
                    .filter(|(n, _)| *n == "shadows")
                    .map(|(_, ms)| ms)
                    .sum::<f64>(),
            );
            let gpu: f64 = t
                .gpu_ms
                .iter()
                .filter(|(n, _)| *n != "readback")
                .map(|(_, ms)| ms)
                .sum();
            times.push(gpu);
        }
        Ok((
            crate::stats::median(&times),
            crate::stats::median(&shadow),
            r,
        ))
    };
    for (i, (group, label, vscene, generic)) in runs.iter().enumerate() {
        reporting.update(label, i as u64, total);
        let (ms, shadow_ms, r) = time(vscene, *generic)?;
        let image = r.image()?;
        let (error, map) = error_metrics(
            reference,
            &image,
            scene.output.exposure,
            scene.output.tonemap,
        )?;
        crate::diff::write_heatmap(&out.join(format!("heatmaps/{i:03}.png")), &map)?;
        let flip_vs_full = if *group == "lod" {
            let full = lod_full.get_or_insert_with(|| image.clone());
            let (e, _) = error_metrics(full, &image, scene.output.exposure, scene.output.tonemap)?;
            Some(e.flip_mean)
        } else {
            None
        };
        results.push(LabResult {
            group: group.to_string(),
            label: label.clone(),
            gpu_ms: ms,
            gpu_ms_rounds: vec![ms],
            shadow_ms,
            triangles: r.triangle_count(),
            pipelines: r.variants(),
            error,
            flip_vs_full,
            pareto: false,
        });
    }
    // More timing rounds, alternating reverse and forward order: a variant's time is the
    // smallest of its rounds' medians, so where it sits in the run (caches, other load on a
    // shared machine) matters less.
    for round in 1..options.rounds {
        let stage = format!("timing round {}/{}", round + 1, options.rounds);
        let order: Vec<usize> = if round % 2 == 1 {
            (0..runs.len()).rev().collect()
        } else {
            (0..runs.len()).collect()
        };
        for (done, i) in order.into_iter().enumerate() {
            reporting.update(&stage, done as u64, total);
            let (_, _, vscene, generic) = &runs[i];
            let (ms, shadow_ms, _) = time(vscene, *generic)?;
            if ms < results[i].gpu_ms {
                results[i].shadow_ms = shadow_ms;
            }
            results[i].gpu_ms = results[i].gpu_ms.min(ms);
            results[i].gpu_ms_rounds.push(ms);
        }
    }
    mark_pareto(&mut results);
    Ok(results)
}

/// Writes `results.csv`, `results.json` and the chart (`chart.png`, `chart.svg`) into `dir`.
pub fn write_outputs(dir: &Path, scene: &Scene, results: &[LabResult]) -> Result<()> {
    let mut csv = String::from(
        "group,variant,gpu_ms,flip_mean,rmse,mean_relative,max_abs,nan_pixels,triangles,pareto,shadow_ms,flip_vs_full\n",
    );
    for r in results {
        csv.push_str(&format!(
            "{},\"{}\",{:.4},{:.6},{:.6},{:.6},{:.6},{},{},{},{:.4},{}\n",
            r.group,
            r.label,
            r.gpu_ms,
            r.error.flip_mean,
            r.error.rmse,
            r.error.mean_relative,
            r.error.max_abs,
            r.error.nan_pixels,
            r.triangles,
            r.pareto,
            r.shadow_ms,
            r.flip_vs_full
                .map(|f| format!("{f:.6}"))
                .unwrap_or_default()
        ));
    }
    std::fs::write(dir.join("results.csv"), csv)
        .with_context(|| format!("cannot write {}", dir.join("results.csv").display()))?;
    let json = serde_json::json!({
        "scene": scene.source.as_ref().map(|p| p.display().to_string()),
        "width": scene.output.width,
        "height": scene.output.height,
        "results": results,
    });
    std::fs::write(
        dir.join("results.json"),
        serde_json::to_string_pretty(&json)?,
    )
    .with_context(|| format!("cannot write {}", dir.join("results.json").display()))?;
    let mut groups: Vec<String> = Vec::new();
    for r in results {
        if !groups.contains(&r.group) {
            groups.push(r.group.clone());
        }
    }
    let pareto_group = groups.len();
    groups.push("Pareto front".into());
    let points = results
        .iter()
        .filter(|r| r.error.flip_mean > 0.0)
        .map(|r| crate::plot::LabeledPoint {
            x: r.gpu_ms,
            y: r.error.flip_mean,
            label: if r.pareto {
                r.label.clone()
            } else {
                String::new()
            },
            group: if r.pareto {
                pareto_group
            } else {
                groups.iter().position(|g| *g == r.group).unwrap_or(0)
            },
        })
        .collect();
    let chart = crate::plot::ScatterChart {
        title: format!(
            "{}: error against GPU time",
            scene
                .source
                .as_ref()
                .and_then(|p| p.file_name())
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_else(|| "scene".into())
        ),
        x: crate::plot::Axis::new("GPU ms per frame (median, log)").log(),
        y: crate::plot::Axis::new("mean FLIP against the CPU reference").log(),
        points,
        groups,
        legend: crate::plot::Legend::UpperRight,
    };
    // The chart records the scene it measured (file, hash) and how many variants.
    let mut meta = crate::imageio::Provenance::base();
    crate::provenance::add_scene(&mut meta, scene);
    meta.set("luz.lab.variants", results.len().to_string());
    crate::plot::save_png_svg_with(&chart.into(), &dir.join("chart"), (1100, 700), &meta)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The repository's root.
    fn repo() -> &'static Path {
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
    }

    /// The diffuse term and the D, G, F selectors of a microfacet material.
    fn microfacet(m: &Material) -> Option<(Diffuse, (Distribution, Geometry, Fresnel))> {
        match m {
            Material::MetalRough(p) => Some((p.diffuse, (p.distribution, p.geometry, p.fresnel))),
            Material::CookTorrance(p) => Some((p.diffuse, (p.distribution, p.geometry, p.fresnel))),
            _ => None,
        }
    }

    /// Loads the scene at `path` in the repository.
    fn repo_scene(path: &str) -> Scene {
        crate::scene::load(&repo().join(path)).unwrap()
    }

    fn result(ms: f64, flip: f64) -> LabResult {
        LabResult {
            group: "g".into(),
            label: format!("{ms}/{flip}"),
            gpu_ms: ms,
            gpu_ms_rounds: vec![ms],
            shadow_ms: 0.0,
            triangles: 0,
            pipelines: Vec::new(),
            error: ErrorMetrics {
                rmse: 0.0,
                mean_relative: 0.0,
                flip_mean: flip,
                max_abs: 0.0,
                nan_pixels: 0,
            },
            flip_vs_full: None,
            pareto: false,
        }
    }

    #[test]
    fn pareto_front_keeps_only_unbeaten_points() {
        let mut r = vec![
            result(1.0, 0.5),
            result(2.0, 0.2),
            result(3.0, 0.3), // beaten by (2, 0.2)
            result(4.0, 0.1),
            result(4.0, 0.1), // a tie: neither beats the other
        ];
        mark_pareto(&mut r);
        let front: Vec<bool> = r.iter().map(|x| x.pareto).collect();
        assert_eq!(front, [true, true, false, true, true]);
    }

    #[test]
    fn metrics_of_identical_and_shifted_images() {
        let a = LinearImage::filled(8, 4, [0.5, 0.25, 1.0, 1.0]);
        let (m, _) = error_metrics(&a, &a, 0.0, crate::color::Tonemap::None).unwrap();
        assert_eq!(
            (m.rmse, m.max_abs, m.flip_mean, m.nan_pixels),
            (0.0, 0.0, 0.0, 0)
        );
        let mut b = a.clone();
        for p in &mut b.pixels {
            p[0] += 0.1;
        }
        b.pixels[3] = [f32::NAN, 0.0, 0.0, 1.0];
        let (m, _) = error_metrics(&a, &b, 0.0, crate::color::Tonemap::None).unwrap();
        assert_eq!(m.nan_pixels, 1);
        assert!((m.max_abs - 0.1).abs() < 1e-6, "{m:?}");
        // One channel in three is off by 0.1: RMSE = 0.1/√3.
        assert!((m.rmse - 0.1 / 3f64.sqrt()).abs() < 1e-6, "{m:?}");
        assert!(m.flip_mean > 0.0);
        let small = LinearImage::filled(4, 4, [0.0; 4]);
        assert!(error_metrics(&a, &small, 0.0, crate::color::Tonemap::None).is_err());
    }

    /// The `lod` group: one variant per budget, in order, on a scene of OBJ meshes.
    #[test]
    fn lod_group_sweeps_the_budget_on_mesh_scenes() {
        if !repo().join("../shared/models/stanford-bunny.obj").exists() {
            eprintln!("SKIPPED: ../shared/models/stanford-bunny.obj not found");
            return;
        }
        let scene = repo_scene("assets/scenes/lod/bunnies_lab.json");
        let v = variants(&scene, &["lod".to_string()]);
        let budgets: Vec<f32> = v
            .iter()
            .filter(|x| x.group == "lod")
            .map(|x| x.scene.output.tessellation_error_px)
            .collect();
        assert_eq!(budgets, LOD_BUDGETS_PX);
        assert_eq!(v[1].label, "lod 0 px (full detail)");
    }

    #[test]
    fn variants_cover_each_group_that_applies() {
        let scene = repo_scene("assets/scenes/ibl/seed001_grid_sky.json");
        let v = variants(&scene, &[]);
        let count = |g: &str| v.iter().filter(|x| x.group == g).count();
        assert_eq!(count("as written"), 1);
        assert_eq!(count("tessellation"), 3 * SEGMENTS.len());
        assert_eq!(count("auto tessellation"), TESSELLATION_BUDGETS_PX.len());
        // Tighter budgets never choose fewer segments.
        let tri: Vec<usize> = v
            .iter()
            .filter(|x| x.group == "auto tessellation")
            .map(|x| x.scene.triangle_count())
            .collect();
        assert!(tri.windows(2).all(|w| w[0] <= w[1]), "{tri:?}");
        // No punctual lights: the BRDF-term variants would all give the same image.
        assert_eq!(count("brdf"), 0);
        // Spheres only: no mesh to simplify, no `lod` variant.
        assert_eq!(count("lod"), 0);
        let grid = repo_scene("assets/scenes/bench/grid49.json");
        let g = variants(&grid, &[]);
        assert!(g.iter().filter(|x| x.group == "brdf").count() >= 16);
        // Lambert vs Burley: two variants with the scene's own terms, every Cook-Torrance and
        // metal-rough material switched; the grid keeps the diffuse as written.
        let diffuse: Vec<&Variant> = g
            .iter()
            .filter(|x| {
                x.group == "brdf" && (x.label.ends_with("/lambert") || x.label.ends_with("/burley"))
            })
            .collect();
        assert_eq!(
            diffuse.len(),
            2,
            "{:?}",
            diffuse.iter().map(|x| &x.label).collect::<Vec<_>>()
        );
        for (v, want) in diffuse.iter().zip(Diffuse::ALL) {
            assert!(v.label.ends_with(want.name()), "{}", v.label);
            let mut switched = 0;
            for (m, orig) in v.scene.materials.iter().zip(&grid.materials) {
                if let (Some((diffuse, lobes)), Some((_, orig_lobes))) =
                    (microfacet(&m.material), microfacet(&orig.material))
                {
                    assert_eq!(diffuse, want);
                    assert_eq!(lobes, orig_lobes);
                    switched += 1;
                }
            }
            assert!(switched > 0);
        }
        let brdf_count = g.iter().filter(|x| x.group == "brdf").count();
        assert!(brdf_count <= 24 + 2, "{brdf_count}");
        assert_eq!(g.iter().filter(|x| x.group == "ibl").count(), 0);
        assert_eq!(count("ibl"), 4 + 2 + IBL_SAMPLES.len());
        let only = variants(&scene, &["ibl".to_string()]);
        assert_eq!(only.len(), 1 + 4 + 2 + IBL_SAMPLES.len());
        // No point lights: no light ranges to choose.
        assert_eq!(count("lights"), 0);
    }

    /// lights256: one variant per threshold, ranges growing as the threshold falls, each the
    /// cut-off bound of its intensity; a scene with ranges also gets them removed.
    #[test]
    fn lights_group_sets_ranges_per_threshold() {
        let scene = repo_scene("assets/scenes/bench/lights256.json");
        let v = variants(&scene, &["lights".to_string()]);
        let lights: Vec<&Variant> = v.iter().filter(|x| x.group == "lights").collect();
        assert_eq!(lights.len(), RANGE_THRESHOLDS.len(), "no ranges to remove");
        let mut last = 0.0;
        for (x, t) in lights.iter().zip(RANGE_THRESHOLDS) {
            let l = &x.scene.lights[0];
            let r = l.range.expect("a range");
            assert!(r > last, "{}: {r}", x.label);
            last = r;
            let i = l.intensity * l.color.max_element();
            // The window's largest loss at this range is the threshold.
            let loss = crate::scene::RANGE_CUT_ERROR * i / (r * r);
            assert!((loss - t).abs() <= 1e-3 * t, "{}: {loss}", x.label);
        }
        let ranged = &lights[0].scene;
        let back = variants(ranged, &["lights".to_string()]);
        assert_eq!(back[1].label, "no ranges");
        assert!(back[1].scene.lights.iter().all(|l| l.range.is_none()));
    }
}
