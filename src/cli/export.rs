//! `luz export`: a scene to another renderer's format ([`luz::export`]), for cross-checks.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::{Args, ValueEnum};

use super::common::ViewOverrides;

/// The formats `luz export` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// Mitsuba 3 XML (`scene.xml`, `<scene version="3.0.0">`) with PLY meshes.
    Mitsuba,
}

/// The integrators of the exported scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum IntegratorArg {
    /// Direct illumination only, as luz renders (Mitsuba's `direct`).
    Direct,
    /// Path tracing to --max-depth (Mitsuba's `path`).
    Path,
}

/// `luz export`.
#[derive(Args, Debug)]
#[command(
    after_help = "Writes DIR/scene.xml with the meshes as binary PLY (DIR/meshes/), the \
textures (DIR/textures/) and the environment (DIR/env/) beside it: the camera, spheres as exact \
spheres, every other mesh as PLY, directional/point/spot lights with their units, the environment \
(turned by 180° about y: Mitsuba's equirectangular origin is luz's opposite) and the materials with \
a like-for-like counterpart. Everything without one is exported as the closest thing or left out, \
and listed in one warning. Every mapping: docs/export.md.\n\n\
Render the result with Mitsuba 3 (scripts/setup.sh installs it into .deps/mitsuba-venv):\n  \
.deps/mitsuba-venv/bin/python -c \"import mitsuba as mi; mi.set_variant('scalar_rgb'); \
mi.Bitmap(mi.render(mi.load_file('DIR/scene.xml'))).write('mitsuba.exr')\"\n\n\
Examples:\n  luz export scene.json --format mitsuba --out mts/              direct illumination\n  \
luz export scene.json --format mitsuba --out mts/ --max-depth 8  path tracing, 8 bounces\n  \
luz export scene.json --format mitsuba --out mts/ --spp 1024 --width 320 --height 240"
)]
pub struct ExportArgs {
    /// Scene file (JSON) or model (.obj, .gltf, .glb); the embedded default scene when omitted.
    pub scene: Option<PathBuf>,
    /// The output format.
    #[arg(long, value_enum, default_value_t = Format::Mitsuba)]
    pub format: Format,
    /// The output folder (created when missing; files in it are overwritten).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// How the exported scene integrates light: "direct" (what luz computes) or "path"
    /// (--max-depth implies it).
    #[arg(long, value_enum)]
    pub integrator: Option<IntegratorArg>,
    /// Longest path of the "path" integrator (2 = direct illumination; Mitsuba's max_depth).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub max_depth: Option<u32>,
    /// Samples per pixel of the exported sampler.
    #[arg(long, default_value_t = 256, value_parser = clap::value_parser!(u32).range(1..=1_048_576))]
    pub spp: u32,
    #[command(flatten)]
    pub view: ViewOverrides,
}

/// Runs `luz export`.
pub fn run(a: ExportArgs) -> Result<ExitCode> {
    let integrator = match (a.integrator, a.max_depth) {
        (Some(IntegratorArg::Direct), Some(_)) => {
            anyhow::bail!("--max-depth is for --integrator path (direct illumination has no depth)")
        }
        (Some(IntegratorArg::Direct), None) | (None, None) => luz::export::Integrator::Direct,
        (Some(IntegratorArg::Path), d) | (None, d @ Some(_)) => luz::export::Integrator::Path {
            max_depth: d.unwrap_or(8),
        },
    };
    let mut scene = luz::scene::load_or_default(a.scene.as_deref())?;
    a.view.apply(&mut scene)?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    let opts = luz::export::ExportOptions {
        integrator,
        spp: a.spp,
    };
    let report = match a.format {
        Format::Mitsuba => luz::export::export_mitsuba(&scene, &opts, &a.out)?,
    };
    if let Some(w) = report.warning() {
        eprintln!("warning: {w}");
    }
    println!("scene: {}", scene.display_name());
    println!(
        "wrote {} ({} file{} in all)",
        report.scene_file.display(),
        report.files.len(),
        if report.files.len() == 1 { "" } else { "s" }
    );
    Ok(ExitCode::SUCCESS)
}
