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
            .args([
                "-c",
                "import mitsuba as mi; mi.set_variant('scalar_rgb')",
            ])
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

/// Renders `xml` with Mitsuba to `exr` (radiance, RGB).
fn mitsuba_render(py: &Path, xml: &Path, exr: &Path) {
    let out = Command::new(py)
        .args([
            "-c",
            "import sys, mitsuba as mi\n\
             mi.set_variant('scalar_rgb')\n\
             img = mi.render(mi.load_file(sys.argv[1]))\n\
             mi.Bitmap(img).write(sys.argv[2])",
        ])
        .arg(xml)
        .arg(exr)
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
fn surface_mask(scene: &Scene) -> Vec<bool> {
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
    let covered: Vec<bool> = img.pixels.iter().map(|p| p[0] > 0.999).collect();
    let mut out = vec![false; covered.len()];
    for y in 0..h {
        for x in 0..w {
            let mut all = true;
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let (xx, yy) = (x + dx, y + dy);
                    all &= xx >= 0 && yy >= 0 && xx < w && yy < h && covered[(yy * w + xx) as usize];
                }
            }
            out[(y * w + x) as usize] = all;
        }
    }
    out
}

/// One scene of the group.
struct Case {
    name: &'static str,
    scene: String,
    /// The reference's primary rays and environment samples per pixel.
    ref_spp: u32,
    ref_samples: u32,
    /// Mitsuba's samples per pixel.
    mitsuba_spp: u32,
    /// Largest relative RMSE of the CPU reference against Mitsuba.
    ref_tolerance: f64,
    /// Largest relative RMSE of the GPU against Mitsuba.
    gpu_tolerance: f64,
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

fn run_case(case: Case) {
    let Some(py) = mitsuba_python() else { return };
    let scene = luz::scene::parse(&case.scene, &root().join("tests/crosscheck.json"))
        .unwrap_or_else(|e| panic!("{}: {e}", case.name));
    let out = match std::env::var_os("LUZ_CROSSCHECK_OUT") {
        Some(d) => {
            let p = PathBuf::from(d).join(case.name);
            std::fs::create_dir_all(&p).unwrap();
            Out::Kept(p)
        }
        None => Out::Scratch(scratch(case.name)),
    };
    let dir = out.path();
    std::fs::write(dir.join("scene.json"), &case.scene).unwrap();
    let report = luz::export::export_mitsuba(
        &scene,
        &ExportOptions {
            integrator: Integrator::Direct,
            spp: case.mitsuba_spp,
        },
        &dir.join("mitsuba"),
    )
    .unwrap_or_else(|e| panic!("{}: export: {e}", case.name));
    let mitsuba_exr = dir.join("mitsuba.exr");
    mitsuba_render(&py, &report.scene_file, &mitsuba_exr);
    let mi = luz::imageio::load(&mitsuba_exr).expect("Mitsuba's EXR");
    assert_eq!(
        (mi.width, mi.height),
        (scene.output.width, scene.output.height)
    );

    let reference = luz::reference::render_reference(
        &scene,
        &luz::reference::ReferenceOptions {
            spp: case.ref_spp,
            samples: case.ref_samples,
            ..Default::default()
        },
        None,
    )
    .expect("reference");
    let ctx = gpu();
    let gpu_img = render_on(&ctx, &scene);
    assert_no_validation_messages(&ctx);
    let save = |img: &LinearImage, name: &str| {
        luz::imageio::save(&dir.join(name), img, 0.0, luz::color::Tonemap::None).unwrap();
    };
    save(&reference, "reference.exr");
    save(&gpu_img, "gpu.exr");

    let mask = surface_mask(&scene);
    let covered = mask.iter().filter(|&&m| m).count();
    assert!(covered > 200, "{}: only {covered} pixels to compare", case.name);
    let (ref_rmse, ref_max) = compare(&reference.pixels, &mi.linear, &mask);
    let (gpu_rmse, gpu_max) = compare(&gpu_img.pixels, &mi.linear, &mask);
    let row = format!(
        "| {} | {:.3} % | {:.2} % | {:.3} % | {:.2} % | {} |",
        case.name,
        ref_rmse * 100.0,
        ref_max * 100.0,
        gpu_rmse * 100.0,
        gpu_max * 100.0,
        covered
    );
    eprintln!("crosscheck: {row}");
    if let Out::Kept(p) = &out {
        std::fs::write(p.join("row.md"), format!("{row}\n")).unwrap();
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
    if let Out::Scratch(s) = out {
        drop(s);
    }
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
const DIRECTIONAL: &str =
    r#"{"type": "directional", "direction": [0.5, -0.5, -0.7], "intensity": 2, "color": [1, 0.9, 0.8]}"#;
const POINT: &str = r#"{"type": "point", "position": [-2, 2, 3], "intensity": 20, "color": [1, 0.95, 0.9]}"#;
const SPOT: &str = r#"{"type": "spot", "position": [0, 3, 3], "target": [0.3, 0.1, 0], "intensity": 30, "umbra_deg": 12}"#;

/// Cook-Torrance with GGX, separable Smith G and the conductor Fresnel of gold: Mitsuba's
/// `roughconductor` term for term. α = roughness².
fn gold_ggx(alpha: f32) -> String {
    format!(
        r#"{{"model": "cook_torrance", "kd": 0, "roughness": {}, "distribution": "ggx", "geometry": "smith_ggx", "fresnel": "conductor", "preset": "gold"}}"#,
        alpha.sqrt()
    )
}

fn direct(name: &'static str, scene: String) -> Case {
    Case {
        name,
        scene,
        ref_spp: 16,
        ref_samples: 16,
        mitsuba_spp: 64,
        ref_tolerance: 0.01,
        gpu_tolerance: 0.02,
    }
}

#[test]
fn lambert_directional() {
    run_case(direct("lambert_directional", sphere_scene(LAMBERT, DIRECTIONAL, "")));
}

#[test]
fn lambert_point() {
    run_case(direct("lambert_point", sphere_scene(LAMBERT, POINT, "")));
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
        ..direct("gold_ggx_a0.1_point", sphere_scene(&gold_ggx(0.1), POINT, ""))
    });
}

#[test]
fn gold_ggx_alpha_0_3_directional() {
    run_case(direct(
        "gold_ggx_a0.3_directional",
        sphere_scene(&gold_ggx(0.3), DIRECTIONAL, ""),
    ));
}

#[test]
fn principled_metal_point() {
    let m = r#"{"model": "principled", "base_color": [0.95, 0.64, 0.54], "metallic": 1, "roughness": 0.5}"#;
    run_case(direct("principled_metal_point", sphere_scene(m, POINT, "")));
}
