//! Independent truth (issue 37): scenes exported with `luz export --format mitsuba`, rendered by
//! Mitsuba 3 (`scalar_rgb`, direct illumination, from `.deps/mitsuba-venv`, which
//! `scripts/setup.sh` installs) and compared with luz's CPU reference and its GPU render (the
//! validation layer on, zero messages) in linear radiance, on the pixels covered by surfaces away
//! from silhouettes (the coverage mask eroded by one pixel).
//!
//! Where the models are the same the references must agree within 1 % relative RMSE
//! (`sqrt(Σ(a − b)² / Σ b²)` over the masked pixels and channels). The GPU's figures are its
//! approximations (tessellation, split sum, SH9) against Mitsuba: reported, and held to a looser
//! bound per scene. `scripts/crosscheck.sh` runs this group and writes the table of
//! docs/accuracy.md (with `LUZ_CROSSCHECK_OUT=DIR` every image is kept in DIR).
//!
//! The group skips visibly when Mitsuba is not importable, and the scenes of `../shared` skip
//! visibly without it.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use common::*;
use luz::export::{ExportOptions, Integrator};
use luz::imageio::LinearImage;
use luz::scene::Scene;

/// The venv's Python when `import mitsuba` and the `scalar_rgb` variant work, else `None` after
/// one visible note.
fn mitsuba_python() -> Option<PathBuf> {
    static FOUND: OnceLock<Option<PathBuf>> = OnceLock::new();
    let found = FOUND.get_or_init(|| {
        let py = root().join(".deps/mitsuba-venv/bin/python");
        let ok = Command::new(&py)
            .args(["-c", "import mitsuba as mi; mi.set_variant('scalar_rgb')"])
            .output()
            .is_ok_and(|o| o.status.success());
        ok.then_some(py)
    });
    if found.is_none() {
        eprintln!(
            "SKIPPED: Mitsuba 3 is not importable from .deps/mitsuba-venv (run scripts/setup.sh with network)"
        );
    }
    found.clone()
}

/// Renders `xml` with Mitsuba to `exr` (radiance, RGB) and its depth (distance along the
/// primary ray, 16 rays per pixel, in R, G and B) to `depth_exr`.
fn mitsuba_render(py: &Path, xml: &Path, exr: &Path, depth_exr: &Path) {
    let out = Command::new(py)
        .args([
            "-c",
            "import sys, mitsuba as mi\n\
             mi.set_variant('scalar_rgb')\n\
             scene = mi.load_file(sys.argv[1])\n\
             mi.Bitmap(mi.render(scene)).write(sys.argv[2])\n\
             aov = mi.load_dict({'type': 'aov', 'aovs': 'd:depth'})\n\
             d = mi.render(scene, integrator=aov, spp=16)\n\
             mi.Bitmap(d, pixel_format=mi.Bitmap.PixelFormat.Y).convert(\n\
                 mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, False).write(sys.argv[3])",
        ])
        .arg(xml)
        .arg(exr)
        .arg(depth_exr)
        .output()
        .expect("run Mitsuba's Python");
    assert!(
        out.status.success(),
        "Mitsuba failed on {}:\n{}",
        xml.display(),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Relative RMSE and max of `a` against `b` over `mask`: `sqrt(Σ(a − b)² / Σ b²)` over masked
/// pixels and RGB channels, and the largest per-pixel |Δ luminance| / mean luminance.
fn compare(a: &[[f32; 4]], b: &[[f32; 4]], mask: &[bool]) -> (f64, f64) {
    let lum = |p: &[f32; 4]| 0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64;
    let (mut num, mut den, mut n, mut sum_l) = (0.0f64, 0.0f64, 0usize, 0.0f64);
    for i in 0..a.len() {
        if !mask[i] {
            continue;
        }
        for c in 0..3 {
            let d = a[i][c] as f64 - b[i][c] as f64;
            num += d * d;
            den += (b[i][c] as f64).powi(2);
        }
        sum_l += lum(&b[i]);
        n += 1;
    }
    let mean_l = sum_l / n.max(1) as f64;
    let mut max = 0.0f64;
    for i in 0..a.len() {
        if mask[i] {
            max = max.max((lum(&a[i]) - lum(&b[i])).abs() / mean_l.max(1e-12));
        }
    }
    ((num / den.max(1e-30)).sqrt(), max)
}

/// Pixels fully covered by a surface, eroded by one pixel (8-neighbourhood): from a reference
/// render of the same geometry lit only by a white ambient term on white Lambert materials.
/// Also returns the background's mask: pixels no surface touches, eroded the same way.
fn surface_mask(scene: &Scene) -> (Vec<bool>, Vec<bool>) {
    let mut s = scene.clone();
    s.environment = None;
    s.lights.clear();
    s.fog = None;
    s.ambient = glam::Vec3::ONE;
    s.output.background = glam::Vec3::ZERO;
    s.saturation = luz::scene::Saturation::None;
    for m in &mut s.materials {
        m.material = luz::brdf::Model::Lambert(luz::brdf::LambertParams {
            albedo: glam::Vec3::ONE,
        });
        m.textures = Default::default();
    }
    let opts = luz::reference::ReferenceOptions {
        spp: 16,
        samples: 1,
        ..Default::default()
    };
    let img = luz::reference::render_reference(&s, &opts, None).expect("mask render");
    let (w, h) = (img.width as i64, img.height as i64);
    let erode = |inside: Vec<bool>| {
        let mut out = vec![false; inside.len()];
        for y in 0..h {
            for x in 0..w {
                let mut all = true;
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        let (xx, yy) = (x + dx, y + dy);
                        all &= xx >= 0
                            && yy >= 0
                            && xx < w
                            && yy < h
                            && inside[(yy * w + xx) as usize];
                    }
                }
                out[(y * w + x) as usize] = all;
            }
        }
        out
    };
    (
        erode(img.pixels.iter().map(|p| p[0] > 0.999).collect()),
        erode(img.pixels.iter().map(|p| p[0] == 0.0).collect()),
    )
}

/// `a`, `b` and `mask` as the means of `n` × `n` blocks whose pixels are all in the mask.
fn binned(
    a: &[[f32; 4]],
    b: &[[f32; 4]],
    mask: &[bool],
    w: usize,
    n: usize,
) -> (Vec<[f32; 4]>, Vec<[f32; 4]>, Vec<bool>) {
    let h = mask.len() / w;
    let (mut oa, mut ob, mut om) = (Vec::new(), Vec::new(), Vec::new());
    for by in 0..h / n {
        for bx in 0..w / n {
            let (mut sa, mut sb, mut all) = ([0.0f32; 4], [0.0f32; 4], true);
            for y in by * n..by * n + n {
                for x in bx * n..bx * n + n {
                    let i = y * w + x;
                    all &= mask[i];
                    for c in 0..4 {
                        sa[c] += a[i][c] / (n * n) as f32;
                        sb[c] += b[i][c] / (n * n) as f32;
                    }
                }
            }
            oa.push(sa);
            ob.push(sb);
            om.push(all);
        }
    }
    (oa, ob, om)
}

/// Takes the silhouettes inside the covered area out of `mask` (a part in front of another):
/// pixels within one pixel of a jump in Mitsuba's depth (a second difference along x or y above
/// 2 % of the depth; smooth surfaces, even at grazing angles, stay far below it).
fn drop_depth_edges(mask: &mut [bool], depth: &[[f32; 4]], w: usize) {
    let h = depth.len() / w;
    let d = |x: usize, y: usize| depth[y * w + x][0];
    let mut edge = vec![false; depth.len()];
    for y in 1..h.saturating_sub(1) {
        for x in 1..w.saturating_sub(1) {
            let c = d(x, y);
            let ddx = (d(x - 1, y) + d(x + 1, y) - 2.0 * c).abs();
            let ddy = (d(x, y - 1) + d(x, y + 1) - 2.0 * c).abs();
            edge[y * w + x] = ddx.max(ddy) > 0.02 * c.abs().max(1e-6);
        }
    }
    for y in 0..h {
        for x in 0..w {
            if !edge[y * w + x] {
                continue;
            }
            for yy in y.saturating_sub(1)..(y + 2).min(h) {
                for xx in x.saturating_sub(1)..(x + 2).min(w) {
                    mask[yy * w + xx] = false;
                }
            }
        }
    }
}

/// One scene of the group.
struct Case {
    name: &'static str,
    /// The scene file's text (kept beside the images) and the scene (the text's, or adjusted).
    json: String,
    scene: Scene,
    /// Also compare the background (environment scenes): the pixels no surface covers, eroded.
    background_tolerance: Option<f64>,
    /// The tolerances judge the means of `bin` × `bin` blocks of masked pixels (1: the pixels).
    bin: usize,
    /// The reference's primary rays and environment samples per pixel.
    ref_spp: u32,
    ref_samples: u32,
    /// Mitsuba's samples per pixel and integrator (direct light, or paths for glass).
    mitsuba_spp: u32,
    integrator: Integrator,
    /// Largest relative RMSE of the CPU reference against Mitsuba.
    ref_tolerance: f64,
    /// Largest relative RMSE of the GPU against Mitsuba.
    gpu_tolerance: f64,
    /// Other GPU methods on the same scene, a row each (reported, not asserted): the method's
    /// name and how it changes the scene.
    gpu_methods: Vec<GpuMethod>,
}

/// A GPU method other than the scene's own: its row label and the scene change that selects it.
struct GpuMethod {
    label: String,
    apply: Box<dyn Fn(&mut Scene)>,
}

impl GpuMethod {
    fn new(label: impl Into<String>, apply: impl Fn(&mut Scene) + 'static) -> Self {
        Self {
            label: label.into(),
            apply: Box::new(apply),
        }
    }
}

/// What a case measured on the GPU: relative RMSE against Mitsuba of the scene's own method and
/// of each [`GpuMethod`], in order ([`run_case`] returns none when Mitsuba is missing).
struct GpuFigures {
    own: f64,
    methods: Vec<f64>,
}

/// Mean LDR FLIP of `test` against `reference` over `mask`, both shown at exposure 0 through the
/// Khronos PBR Neutral tone map (the scenes' radiance reaches above 1).
fn mean_flip(reference: &[[f32; 4]], test: &[[f32; 4]], mask: &[bool], size: (u32, u32)) -> f64 {
    let map = luz::compare::flip_map(
        reference,
        test,
        size,
        (0.0, luz::color::Tonemap::KhronosNeutral),
    );
    let (sum, n) = map
        .values
        .iter()
        .zip(mask)
        .filter(|(_, &m)| m)
        .fold((0.0f64, 0usize), |(s, n), (&v, _)| (s + v as f64, n + 1));
    sum / n.max(1) as f64
}

/// Where this run keeps its images: `LUZ_CROSSCHECK_OUT/<name>` (kept), else a scratch folder.
enum Out {
    Kept(PathBuf),
    Scratch(Scratch),
}

impl Out {
    fn path(&self) -> &Path {
        match self {
            Out::Kept(p) => p,
            Out::Scratch(s) => s,
        }
    }
}

fn run_case(case: Case) -> Option<GpuFigures> {
    let py = mitsuba_python()?;
    let scene = &case.scene;
    let out = match std::env::var_os("LUZ_CROSSCHECK_OUT") {
        Some(d) => {
            let p = PathBuf::from(d).join(case.name);
            std::fs::create_dir_all(&p).unwrap();
            Out::Kept(p)
        }
        None => Out::Scratch(scratch(case.name)),
    };
    let dir = out.path();
    std::fs::write(dir.join("scene.json"), &case.json).unwrap();
    let report = luz::export::export_mitsuba(
        scene,
        &ExportOptions {
            integrator: case.integrator,
            spp: case.mitsuba_spp,
        },
        &dir.join("mitsuba"),
    )
    .unwrap_or_else(|e| panic!("{}: export: {e}", case.name));
    let mitsuba_exr = dir.join("mitsuba.exr");
    let depth_exr = dir.join("mitsuba_depth.exr");
    mitsuba_render(&py, &report.scene_file, &mitsuba_exr, &depth_exr);
    let depth = luz::imageio::load(&depth_exr).expect("Mitsuba's depth EXR");
    let mi = luz::imageio::load(&mitsuba_exr).expect("Mitsuba's EXR");
    assert_eq!(
        (mi.width, mi.height),
        (scene.output.width, scene.output.height)
    );

    let reference = luz::reference::render_reference(
        scene,
        &luz::reference::ReferenceOptions {
            spp: case.ref_spp,
            samples: case.ref_samples,
            ..Default::default()
        },
        None,
    )
    .expect("reference");
    let ctx = gpu();
    let gpu_img = render_on(&ctx, scene);
    assert_no_validation_messages(&ctx);
    let save = |img: &LinearImage, name: &str| {
        luz::imageio::save(&dir.join(name), img, 0.0, luz::color::Tonemap::None).unwrap();
    };
    save(&reference, "reference.exr");
    save(&gpu_img, "gpu.exr");

    let (mut mask, background) = surface_mask(scene);
    drop_depth_edges(&mut mask, &depth.linear, scene.output.width as usize);
    let covered = mask.iter().filter(|&&m| m).count();
    assert!(
        covered > 200,
        "{}: only {covered} pixels to compare",
        case.name
    );
    let w = scene.output.width as usize;
    let judge = |img: &[[f32; 4]]| {
        let (a, b, m) = binned(img, &mi.linear, &mask, w, case.bin);
        compare(&a, &b, &m)
    };
    let (ref_rmse, ref_max) = judge(&reference.pixels);
    let (gpu_rmse, gpu_max) = judge(&gpu_img.pixels);
    let size = (scene.output.width, scene.output.height);
    let flip = |img: &[[f32; 4]]| mean_flip(&mi.linear, img, &mask, size);
    let judged_on = if case.bin == 1 {
        "pixels".to_string()
    } else {
        format!("{0}×{0} means", case.bin)
    };
    // The other GPU methods' rows: the reference's columns are the scene's row's.
    let mut method_rows = String::new();
    let mut method_rmse = Vec::new();
    for m in &case.gpu_methods {
        let mut s = scene.clone();
        (m.apply)(&mut s);
        let img = render_on(&ctx, &s);
        assert_no_validation_messages(&ctx);
        save(
            &img,
            &format!("gpu_{}.exr", m.label.replace([' ', ','], "_")),
        );
        let (rmse, max) = judge(&img.pixels);
        method_rmse.push(rmse);
        method_rows.push_str(&format!(
            "| {} (GPU: {}) | | | | {:.3} % | {:.2} % | {:.4} | {covered} | {judged_on} |\n",
            case.name,
            m.label,
            rmse * 100.0,
            max * 100.0,
            flip(&img.pixels)
        ));
    }
    let bg = case.background_tolerance.map(|tol| {
        let (rmse, _) = compare(&reference.pixels, &mi.linear, &background);
        eprintln!(
            "crosscheck: {}: background (the environment seen directly), reference against Mitsuba: {:.3} % relative RMSE",
            case.name,
            rmse * 100.0
        );
        (rmse, tol)
    });
    let row = format!(
        "| {} | {:.3} % | {:.2} % | {:.4} | {:.3} % | {:.2} % | {:.4} | {covered} | {judged_on} |\n{method_rows}",
        case.name,
        ref_rmse * 100.0,
        ref_max * 100.0,
        flip(&reference.pixels),
        gpu_rmse * 100.0,
        gpu_max * 100.0,
        flip(&gpu_img.pixels),
    );
    for line in row.lines() {
        eprintln!("crosscheck: {line}");
    }
    if let Out::Kept(p) = &out {
        std::fs::write(p.join("row.md"), &row).unwrap();
        if let Some(w) = report.warning() {
            std::fs::write(p.join("export-warning.txt"), w).unwrap();
        }
    }
    assert!(
        ref_rmse <= case.ref_tolerance,
        "{}: luz's reference against Mitsuba: {:.3} % relative RMSE, over {:.3} % (images in {})",
        case.name,
        ref_rmse * 100.0,
        case.ref_tolerance * 100.0,
        dir.display()
    );
    assert!(
        gpu_rmse <= case.gpu_tolerance,
        "{}: luz's GPU against Mitsuba: {:.3} % relative RMSE, over {:.3} % (images in {})",
        case.name,
        gpu_rmse * 100.0,
        case.gpu_tolerance * 100.0,
        dir.display()
    );
    if let Some((rmse, tol)) = bg {
        assert!(
            rmse <= tol,
            "{}: the environment's background differs from Mitsuba's: {:.3} % relative RMSE, over {:.1} % (a wrong rotation convention?)",
            case.name,
            rmse * 100.0,
            tol * 100.0
        );
    }
    if let Out::Scratch(s) = out {
        drop(s);
    }
    Some(GpuFigures {
        own: gpu_rmse,
        methods: method_rmse,
    })
}

/// A sphere of radius 1 (a little right of the centre, so a mirrored image would show) seen from
/// +z, with one light and one material.
fn sphere_scene(material: &str, light: &str, extra: &str) -> String {
    format!(
        r#"{{
  "camera": {{"position": [0, 0, 4], "target": [0, 0, 0], "fov_y_deg": 40, "near": 0.1, "far": 100}},
  "output": {{"width": 128, "height": 96, "msaa": 4, "tonemap": "none"}},
  "lights": [{light}],
  "materials": {{"m": {material}}},
  "objects": [{{"mesh": {{"type": "sphere", "radius": 1}}, "material": "m", "position": [0.3, 0.1, 0]}}]{extra}
}}"#
    )
}

const LAMBERT: &str = r#"{"model": "lambert", "albedo": [0.8, 0.5, 0.3]}"#;
const DIRECTIONAL: &str = r#"{"type": "directional", "direction": [0.5, -0.5, -0.7], "intensity": 2, "color": [1, 0.9, 0.8]}"#;
const POINT: &str =
    r#"{"type": "point", "position": [-2, 2, 3], "intensity": 20, "color": [1, 0.95, 0.9]}"#;
const SPOT: &str = r#"{"type": "spot", "position": [0, 3, 3], "target": [0.3, 0.1, 0], "intensity": 30, "umbra_deg": 12}"#;

/// Cook-Torrance with GGX, separable Smith G and the exact conductor Fresnel of gold: Mitsuba's
/// `roughconductor` term for term. α = roughness².
fn gold_ggx(alpha: f32) -> String {
    format!(
        r#"{{"model": "cook_torrance", "kd": 0, "roughness": {}, "distribution": "ggx", "geometry": "smith_ggx", "fresnel": "conductor_exact", "preset": "gold"}}"#,
        alpha.sqrt()
    )
}

fn direct(name: &'static str, json: String) -> Case {
    let scene = luz::scene::parse(&json, &root().join("tests/crosscheck.json"))
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    Case {
        name,
        json,
        scene,
        background_tolerance: None,
        bin: 1,
        ref_spp: 16,
        ref_samples: 16,
        mitsuba_spp: 64,
        integrator: Integrator::Direct,
        ref_tolerance: 0.01,
        gpu_tolerance: 0.02,
        gpu_methods: Vec::new(),
    }
}

#[test]
fn lambert_directional() {
    run_case(direct(
        "lambert_directional",
        sphere_scene(LAMBERT, DIRECTIONAL, ""),
    ));
}

/// Tessellation budgets (px) the faceting chart measures besides the default 0.05 (the scenes'
/// own rows); 0 is full detail (256 segments).
const BUDGETS: [f32; 8] = [0.0, 0.01, 0.02, 0.1, 0.2, 0.5, 1.0, 2.0];

/// `case` with a GPU row per budget of [`BUDGETS`].
fn with_budgets(case: Case) -> Case {
    Case {
        gpu_methods: BUDGETS
            .map(|b| {
                GpuMethod::new(format!("tessellation {b} px"), move |s| {
                    luz::scene::tessellation::make_automatic(s, b)
                })
            })
            .into(),
        ..case
    }
}

/// Faceting (issue 37): the GPU's shading error against Mitsuba as the sphere's tessellation
/// budget changes, on a Lambert sphere under a point light and on gold (α 0.3) under a
/// directional light. The error falls with the budget and is smallest at full detail; with
/// `LUZ_CROSSCHECK_OUT` set the chart is written there (`faceting.png`, `.svg`).
#[test]
fn lambert_point_and_gold_directional_against_the_tessellation_budget() {
    let cases = [
        direct("lambert_point", sphere_scene(LAMBERT, POINT, "")),
        direct(
            "gold_ggx_a0.3_directional",
            sphere_scene(&gold_ggx(0.3), DIRECTIONAL, ""),
        ),
    ];
    let mut series = Vec::new();
    for (i, case) in cases.into_iter().enumerate() {
        let name = case.name;
        let Some(f) = run_case(with_budgets(case)) else {
            return;
        };
        // Budget 0.05 (the default) is the scene's own row.
        let mut points: Vec<(f64, f64)> = BUDGETS[1..]
            .iter()
            .zip(&f.methods[1..])
            .map(|(&b, &e)| (b as f64, e * 100.0))
            .chain([(0.05, f.own * 100.0)])
            .collect();
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        let full = f.methods[0];
        let coarse = f.methods[BUDGETS.len() - 1];
        assert!(
            full < f.own && f.own < coarse,
            "{name}: the error should fall with the budget: full detail {full}, 0.05 px {}, 2 px {coarse}",
            f.own
        );
        series.push(
            luz::plot::Series::new(name, points)
                .color(luz::plot::palette(i))
                .markers(),
        );
        series.push(
            luz::plot::Series::new(
                format!("{name}, full detail"),
                vec![(0.01, full * 100.0), (2.0, full * 100.0)],
            )
            .color(luz::plot::palette(i))
            .dashed(),
        );
    }
    if let Some(d) = std::env::var_os("LUZ_CROSSCHECK_OUT") {
        let chart = luz::plot::Chart::Line(luz::plot::LineChart {
            title: "GPU shading error against Mitsuba by tessellation budget".into(),
            x: luz::plot::Axis::new("tessellation budget (px, output.tessellation_error_px)").log(),
            y: luz::plot::Axis::new("relative RMSE against Mitsuba (%)").log(),
            series,
            ..Default::default()
        });
        luz::plot::save_png_svg(&chart, &PathBuf::from(d).join("faceting"), 800, 500)
            .expect("faceting chart");
    }
}

#[test]
fn lambert_spot() {
    // The GPU shades once per pixel (at its centre, MSAA or not): across the hard edge of the
    // cone it is 0 or lit where Mitsuba and the 16-ray reference average the pixel (the reference
    // at 1 ray per pixel is 3.2 % off too).
    run_case(Case {
        gpu_tolerance: 0.05,
        ..direct("lambert_spot", sphere_scene(LAMBERT, SPOT, ""))
    });
}

#[test]
fn gold_ggx_alpha_0_1_point() {
    // A small, sharp highlight. The GPU shades it once per pixel where Mitsuba and the reference
    // average the pixel's area: the reference at 1 ray per pixel is 1.8 % off too.
    run_case(Case {
        gpu_tolerance: 0.04,
        ..direct(
            "gold_ggx_a0.1_point",
            sphere_scene(&gold_ggx(0.1), POINT, ""),
        )
    });
}

#[test]
fn principled_metal_point() {
    let m = r#"{"model": "principled", "base_color": [0.95, 0.64, 0.54], "metallic": 1, "roughness": 0.5}"#;
    run_case(direct("principled_metal_point", sphere_scene(m, POINT, "")));
}

#[test]
fn gold_beckmann_point() {
    // Beckmann (m = roughness in Cook-Torrance) with its own Smith G (Walter's rational G1, within
    // 0.31 % of Mitsuba's exact one) and the exact conductor Fresnel: the same model (issue 34).
    let m = r#"{"model": "cook_torrance", "kd": 0, "roughness": 0.3, "distribution": "beckmann", "geometry": "smith_beckmann", "fresnel": "conductor_exact", "preset": "gold"}"#;
    run_case(direct(
        "gold_beckmann_m0.3_point",
        sphere_scene(m, POINT, ""),
    ));
}

#[test]
fn metal_rough_dielectric_directional() {
    // A dielectric (metallic 0) with the exact Fresnel and separable Smith G: Lambert plus a
    // GGX lobe, exported as blendbsdf(½) of both doubled.
    let m = r#"{"model": "metal_rough", "base_color": [0.6, 0.2, 0.1], "metallic": 0, "roughness": 0.5, "geometry": "smith_ggx", "fresnel": "dielectric"}"#;
    run_case(direct(
        "metal_rough_dielectric_directional",
        sphere_scene(m, DIRECTIONAL, ""),
    ));
}

/// `../shared/environments/newport_loft.hdr` as the environment (turned by 30°), or `None`
/// after a visible note.
fn loft(intensity: f32) -> Option<String> {
    let hdr = shared_dir("environments")?.join("newport_loft.hdr");
    Some(format!(
        r#", "environment": {{"hdr": {}, "intensity": {intensity}, "rotation_deg": 30}}"#,
        serde_json::to_string(&hdr).unwrap()
    ))
}

fn environment(name: &'static str, material: &str) -> Option<Case> {
    let env = loft(1.0)?;
    // Both sides integrate the environment by Monte Carlo: the per-pixel RMSE is their noise
    // (it halved, 1.85 % → 0.85 % on gold, with 4× the samples on both sides, so it is not a
    // model difference). Judged on 2×2 block means (noise ÷ 2) to keep the run short.
    Some(Case {
        ref_spp: 16,
        ref_samples: 16384,
        mitsuba_spp: 4096,
        bin: 2,
        // The reference's 16 primary rays per pixel over a detailed image: its noise.
        background_tolerance: Some(0.03),
        ..direct(
            name,
            sphere_scene(material, "", &env).replace(
                r#""width": 128, "height": 96"#,
                r#""width": 64, "height": 48"#,
            ),
        )
    })
}

#[test]
fn lambert_hdr_environment() {
    // The GPU's diffuse light is 9 spherical-harmonic coefficients; the cosine-convolved cube is
    // the other method's row.
    let Some(case) = environment("lambert_hdr_environment", LAMBERT) else {
        return;
    };
    run_case(Case {
        gpu_tolerance: 0.05,
        gpu_methods: vec![GpuMethod::new("irradiance cube", |s| {
            s.environment.as_mut().unwrap().diffuse_method = luz::scene::DiffuseMethod::Cubemap
        })],
        ..case
    });
}

/// The GPU's specular methods on a gold sphere in the HDR environment: the fitted lobes (the
/// default, the scene's own, the asserted row: issue 37's goal is 3 %), importance sampling at
/// 16 and 64 samples per pixel and the split sum.
fn gold_environment(name: &'static str, alpha: f32, gpu_tolerance: f64) {
    let Some(case) = environment(name, &gold_ggx(alpha)) else {
        return;
    };
    fn importance(s: &mut Scene, samples: u32) {
        let env = s.environment.as_mut().unwrap();
        env.specular_method = luz::scene::SpecularMethod::Importance;
        env.samples = samples;
    }
    let mut gpu_methods: Vec<GpuMethod> = [16, 64]
        .map(|n| {
            GpuMethod::new(format!("importance, {n} samples"), move |s| {
                importance(s, n)
            })
        })
        .into();
    gpu_methods.push(GpuMethod::new("split sum", |s| {
        s.environment.as_mut().unwrap().specular_method = luz::scene::SpecularMethod::SplitSum
    }));
    run_case(Case {
        gpu_tolerance,
        gpu_methods,
        ..case
    });
}

// Bounds of the fitted lobes against Mitsuba (issue 37's goal: 3 %), just above what 2026-11-28
// measured: 2.89 % (α 0.1), 1.96 % (α 0.3), 1.59 % (α 0.6); the split sum measured 5.0 %, 7.5 %,
// 8.9 % on the same bake (4.3 %, 5.8 %, 5.7 % on the old one; issue 37 measured 7.8 % at α 0.3).
#[test]
fn gold_ggx_alpha_0_3_hdr_environment() {
    gold_environment("gold_ggx_a0.3_hdr_environment", 0.3, 0.025);
}

#[test]
fn gold_ggx_alpha_0_1_hdr_environment() {
    gold_environment("gold_ggx_a0.1_hdr_environment", 0.1, 0.032);
}

#[test]
fn gold_ggx_alpha_0_6_hdr_environment() {
    gold_environment("gold_ggx_a0.6_hdr_environment", 0.6, 0.02);
}

/// Glass (issue 35): a sphere of index 1.5 in the HDR environment, seen through (Mitsuba's
/// path tracer, 16 bounces: the light refracted through the sphere, reflected and internally
/// reflected, against luz's reference walk). The exact dielectric Fresnel and separable Smith G
/// on the reflection, as Mitsuba's dielectrics. The GPU's row is its screen-space refraction
/// (docs/glass.md: no second refraction, so the sphere does not invert the environment behind
/// it), recorded, not held; the "environment" row (the ray followed out of the sphere, the
/// environment read there) is held ([`glass_environment_row`]). The thickness is the sphere's
/// diameter, which only the GPU reads (the reference walks the real surface).
/// Thin-walled glass has no like-for-like counterpart (Mitsuba's `thindielectric` is a slab
/// with internal reflections, 2R/(1 + R), and its back wall is seen): no row.
/// Bounds of the `"environment"` refraction rows against Mitsuba (2026-11-28: 18.2 % smooth,
/// 39.5 % at α 0.1; docs/accuracy.md).
const ENV_GLASS_SMOOTH: f64 = 0.25;
const ENV_GLASS_ROUGH: f64 = 0.50;

fn glass_case(name: &'static str, roughness: f32) -> Option<Case> {
    let env = loft(1.0)?;
    let material = format!(
        r#"{{"model": "metal_rough", "base_color": [1, 1, 1], "metallic": 0, "roughness": {roughness}, "fresnel": "dielectric", "geometry": "smith_ggx", "transmission": {{"transmissionFactor": 1}}, "volume": {{"thicknessFactor": 2}}}}"#
    );
    Some(Case {
        ref_spp: 16,
        ref_samples: 16384,
        mitsuba_spp: 1024,
        integrator: Integrator::Path { max_depth: 16 },
        bin: 2,
        background_tolerance: Some(0.03),
        ref_tolerance: 0.03,
        gpu_tolerance: f64::INFINITY,
        gpu_methods: vec![GpuMethod::new("environment", |s| {
            s.output.refraction = luz::scene::Refraction::Environment
        })],
        ..direct(
            name,
            sphere_scene(&material, "", &env).replace(
                r#""width": 128, "height": 96"#,
                r#""width": 64, "height": 48"#,
            ),
        )
    })
}

/// Runs a glass case and holds its `"environment"` row (the method that follows the ray out of
/// the sphere and reads the environment, docs/glass.md) within `environment_tolerance`.
fn glass_environment_row(case: Case, environment_tolerance: f64) {
    let name = case.name;
    if let Some(f) = run_case(case) {
        let rmse = f.methods[0];
        assert!(
            rmse <= environment_tolerance,
            "{name}: the GPU's environment refraction against Mitsuba: {:.3} % relative RMSE, over {:.1} %",
            rmse * 100.0,
            environment_tolerance * 100.0
        );
    }
}

#[test]
fn glass_smooth_sphere_hdr_environment() {
    if let Some(case) = glass_case("glass_smooth_hdr_environment", 0.0) {
        glass_environment_row(case, ENV_GLASS_SMOOTH);
    }
}

#[test]
fn glass_rough_sphere_hdr_environment() {
    if let Some(case) = glass_case("glass_rough_a0.1_hdr_environment", 0.1f32.sqrt()) {
        glass_environment_row(case, ENV_GLASS_ROUGH);
    }
}

/// Area lights (issue 36): a one-sided rect above and in front of the sphere, with a shadow
/// (Mitsuba always shadows; the reference traces shadow rays, the GPU has no area-light shadows
/// yet, which only the sphere's own terminator would show). The GPU shades it by LTC (the
/// scene's row) and by 64 samples (the other row).
const RECT: &str = r#"{"type": "rect", "position": [0.3, 2.6, 1.5], "direction": [0, -1, -0.4], "up": [0, 0, -1], "size": [1.5, 1], "intensity": 4, "color": [1, 0.95, 0.9], "shadow": {"method": "hard"}}"#;

fn area_case(name: &'static str, material: &str, gpu_tolerance: f64) -> Case {
    Case {
        gpu_tolerance,
        gpu_methods: vec![GpuMethod::new("sampled, 64 samples", |s| {
            s.area_lights[0].method = luz::scene::AreaMethod::Sampled { samples: 64 }
        })],
        ref_spp: 16,
        ref_samples: 4096,
        mitsuba_spp: 1024,
        bin: 2,
        ..direct(
            name,
            sphere_scene(material, RECT, "").replace(
                r#""width": 128, "height": 96"#,
                r#""width": 64, "height": 48"#,
            ),
        )
    }
}

#[test]
fn lambert_rect_light() {
    // LTC's diffuse is exact above the horizon: 0.59 % (2026-11-28).
    run_case(area_case("lambert_rect_light", LAMBERT, 0.02));
}

#[test]
fn gold_ggx_alpha_0_3_rect_light() {
    // LTC's GGX fit: 4.1 % (2026-11-28); docs/area-lights.md has it by roughness.
    run_case(area_case("gold_ggx_a0.3_rect_light", &gold_ggx(0.3), 0.06));
}

/// A glTF model of `../shared/gltf` under a white-ish Lambert material (the file's own
/// materials are glTF metallic-roughness with Schlick's Fresnel, which Mitsuba has no
/// counterpart for), a directional light with a shadow (Mitsuba always shadows; luz's reference
/// traces shadow rays, the GPU reads a shadow map), framed as `luz render model.gltf` frames it.
fn gltf_case(name: &'static str, file: &str) -> Option<Case> {
    let path = shared_dir("gltf")?.join(file);
    let json = format!(
        r#"{{
  "output": {{"width": 160, "height": 120, "msaa": 4, "tonemap": "none"}},
  "lights": [{{"type": "directional", "direction": [0.3, -0.4, -1], "intensity": 2, "color": [1, 0.9, 0.8], "shadow": {{"method": "hard"}}}}],
  "materials": {{"m": {LAMBERT}}},
  "objects": [{{"mesh": {{"type": "gltf", "path": {}}}, "material": "m"}}]
}}"#,
        serde_json::to_string(&path).unwrap()
    );
    // The GPU (and the reference at one ray per pixel: 13.4 % on venus) shades sub-pixel detail
    // at pixel centres where Mitsuba and the 64-ray reference average the pixel.
    let mut case = Case {
        ref_spp: 64,
        mitsuba_spp: 256,
        gpu_tolerance: 0.2,
        ..direct(name, json)
    };
    let bounds = case.scene.bounds().expect("a model with geometry");
    case.scene.camera = luz::scene::model::framing(bounds, case.scene.output.aspect(), 40.0);
    Some(case)
}

#[test]
fn gltf_teapot_spheres() {
    let Some(case) = gltf_case("gltf_color_teapot_spheres", "color_teapot_spheres.gltf") else {
        return;
    };
    run_case(case);
}

#[test]
fn gltf_venus() {
    let Some(case) = gltf_case("gltf_venus", "venus.gltf") else {
        return;
    };
    run_case(case);
}

fn scene_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            scene_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "json") {
            out.push(p);
        }
    }
}

/// Every shipped scene (assets/scenes, all models, lights, maps and environments) exports, and
/// Mitsuba loads what was written. Scenes over two million triangles are left out for time
/// (lod/bunnies_40m takes Mitsuba three minutes to load).
#[test]
fn every_shipped_scene_exports_and_mitsuba_loads_it() {
    let Some(py) = mitsuba_python() else { return };
    let dir = scratch("shipped");
    let mut files = Vec::new();
    scene_files(&root().join("assets/scenes"), &mut files);
    let mut xmls = Vec::new();
    for f in &files {
        let scene = luz::scene::load(f).unwrap_or_else(|e| panic!("{e}"));
        if scene.triangle_count() > 2_000_000 {
            eprintln!("left out (over 2 M triangles): {}", f.display());
            continue;
        }
        let name = f
            .strip_prefix(root().join("assets/scenes"))
            .unwrap()
            .to_string_lossy()
            .replace(['/', '.'], "_");
        let report =
            luz::export::export_mitsuba(&scene, &ExportOptions::default(), &dir.join(name))
                .unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        xmls.push(report.scene_file);
    }
    assert!(xmls.len() >= 30, "only {} scenes", xmls.len());
    let out = Command::new(&py)
        .args([
            "-c",
            "import sys, mitsuba as mi\n\
             mi.set_variant('scalar_rgb')\n\
             for f in sys.argv[1:]:\n    mi.load_file(f)",
        ])
        .args(&xmls)
        .output()
        .expect("run Mitsuba's Python");
    assert!(
        out.status.success(),
        "Mitsuba could not load an export:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A plane (a PLY mesh, two-sided) with an asymmetric base colour map (a gradient in u and v, a
/// bright corner) seen by an orthographic camera: the PLY's UVs, the bitmap's orientation and
/// sRGB decoding, and the orthographic view rectangle.
#[test]
fn textured_plane_orthographic() {
    let tex_dir = scratch("texture");
    let (w, h) = (64u32, 32u32);
    let mut rgb = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let corner = x < 8 && y < 8;
            rgb.extend([
                (255 * x / (w - 1)) as u8,
                (255 * y / (h - 1)) as u8,
                if corner { 255 } else { 26 },
            ]);
        }
    }
    let png = tex_dir.join("gradient.png");
    luz::imageio::save_png_rgb8(&png, w, h, &rgb).unwrap();
    let json = format!(
        r#"{{
  "camera": {{"position": [0, 3, 3], "target": [0, 0, 0], "projection": "orthographic", "ortho_half_height": 1.2, "near": 0.1, "far": 100}},
  "output": {{"width": 128, "height": 96, "msaa": 4, "tonemap": "none"}},
  "lights": [{{"type": "directional", "direction": [0.3, -1, -0.2], "intensity": 2}}],
  "materials": {{"m": {{"model": "lambert", "albedo": 1, "textures": {{"base_color": {}}}}}}},
  "objects": [{{"mesh": {{"type": "plane", "size": [3, 2]}}, "material": "m", "rotation_deg": [0, 20, 0], "position": [0.2, 0, 0]}}]
}}"#,
        serde_json::to_string(&png).unwrap()
    );
    run_case(direct("textured_plane_orthographic", json));
}
