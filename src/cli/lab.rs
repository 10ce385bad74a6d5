//! `luz lab`: speed against accuracy (the measuring is [`luz::lab`]; this prints and draws).

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{bail, Context as _, Result};
use clap::Args;

use luz::lab::{measure, variants, write_outputs, LabOptions};

use super::common::{
    context, render_options, report_tessellation, validation_exit, Bar, GpuArgs, IblArgs,
    IblQuality, SwitchArgs, ViewOverrides,
};

#[derive(Args, Debug)]
pub struct LabArgs {
    /// Scene file (JSON).
    pub scene: PathBuf,
    /// Folder for results.csv, results.json, chart.png, chart.svg, reference.exr and heat maps.
    #[arg(long)]
    pub out: PathBuf,
    /// Timed frames per variant (median of their GPU time).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub frames: u32,
    /// Timing rounds over all variants, alternating forward and reverse order; a variant's time
    /// is the smallest of its rounds' medians, so a burst of load elsewhere on the machine (which
    /// only ever adds time) or a variant's place in the run weighs less.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=100))]
    pub rounds: u32,
    /// Use this linear EXR as the reference instead of rendering it with `luz reference`.
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Environment samples per pixel of the reference (Monte Carlo).
    #[arg(long, default_value_t = 1024)]
    pub reference_samples: u32,
    // --width and --height: the lab renders every variant at this size.
    #[command(flatten)]
    pub view: ViewOverrides,
    /// Only these variant groups (comma separated: tessellation, auto, brdf, lights, ibl, shadows, lod, glass, layers;
    /// `area` runs alone: one reference per cell of its sweep, docs/area-lights.md).
    #[arg(long, value_delimiter = ',')]
    pub only: Vec<String>,
    /// With `--only area`: only these light shapes (comma separated: rect, disk, sphere, tube).
    #[arg(long, value_delimiter = ',')]
    pub area_shapes: Vec<String>,
    /// Sizes of the image-based lighting data.
    #[arg(long, value_enum, default_value_t = IblQuality::Full)]
    pub ibl_quality: IblQuality,
    #[command(flatten)]
    pub switches: SwitchArgs,
    #[command(flatten)]
    pub gpu: GpuArgs,
}

pub fn run(a: LabArgs) -> Result<ExitCode> {
    let mut scene = luz::scene::load(&a.scene)?;
    a.view.apply(&mut scene)?;
    report_tessellation(&scene, false);
    if a.only.iter().any(|g| g == "area") {
        return run_area(&a, &scene);
    }
    if !a.area_shapes.is_empty() {
        bail!("--area-shapes goes with --only area");
    }
    std::fs::create_dir_all(a.out.join("heatmaps"))
        .with_context(|| format!("cannot create {}", a.out.display()))?;
    let reference = match &a.reference {
        Some(p) => {
            let img = luz::imageio::load_radiance(p)?;
            if (img.width, img.height) != (scene.output.width, scene.output.height) {
                bail!(
                    "{}: the reference is {}x{}, the scene renders {}x{}",
                    p.display(),
                    img.width,
                    img.height,
                    scene.output.width,
                    scene.output.height
                );
            }
            img
        }
        None => {
            println!(
                "reference: rendering on the CPU ({} environment samples per pixel)",
                a.reference_samples
            );
            let bar = Bar::new("reference {bar:40} {pos}/{len} rows {elapsed}");
            let progress = |done: u64, total: u64| {
                luz::progress::Progress::update(&bar, "", done, total);
            };
            // As many primary rays per pixel as the rasteriser's samples, so edges compare alike.
            let opts = luz::reference::ReferenceOptions {
                samples: a.reference_samples,
                spp: scene.output.msaa.max(1),
                ..Default::default()
            };
            let img = luz::reference::render_reference(&scene, &opts, Some(&progress))?;
            bar.finish_and_clear();
            luz::imageio::save(
                &a.out.join("reference.exr"),
                &img,
                0.0,
                luz::color::Tonemap::None,
            )?;
            img
        }
    };
    let ctx = context(&a.gpu)?;
    println!("device: {}", ctx.info.summary());
    let variants = variants(&scene, &a.only);
    let options = LabOptions {
        frames: a.frames,
        rounds: a.rounds,
        render: lab_render_options(&a),
    };
    let bar = Bar::new("{bar:40} {pos}/{len} variants {elapsed} {msg}");
    let results = measure(
        &ctx,
        &scene,
        &variants,
        &reference,
        &a.out,
        &options,
        Some(&bar),
    )?;
    write_outputs(&a.out, &scene, &results)?;
    if let (Some(min), Some(all)) = (results.first(), results.last()) {
        println!(
            "pipelines built for the scene as written: {}",
            min.pipelines.join("; ")
        );
        println!(
            "minimal pipelines {:.3} ms, all-features pipelines {:.3} ms ({:.2}x)",
            min.gpu_ms,
            all.gpu_ms,
            all.gpu_ms / min.gpu_ms
        );
    }
    println!(
        "{:<4} {:<14} {:<34} {:>10} {:>10} {:>10} {:>10} {:>10} {:>6} {:>10}",
        "",
        "group",
        "variant",
        "GPU ms",
        "shadow ms",
        "FLIP",
        "RMSE",
        "rel err",
        "NaN",
        "FLIP full"
    );
    for (i, r) in results.iter().enumerate() {
        println!(
            "{:<4} {:<14} {:<34} {:>10.3} {:>10.3} {:>10.5} {:>10.5} {:>10.5} {:>6} {:>10}{}",
            i,
            r.group,
            r.label,
            r.gpu_ms,
            r.shadow_ms,
            r.error.flip_mean,
            r.error.rmse,
            r.error.mean_relative,
            r.error.nan_pixels,
            r.flip_vs_full
                .map(|f| format!("{f:.5}"))
                .unwrap_or_else(|| "-".into()),
            if r.pareto { "  ← Pareto" } else { "" }
        );
    }
    println!(
        "wrote {0}/results.csv, {0}/results.json, {0}/chart.png, {0}/chart.svg, {0}/heatmaps/",
        a.out.display()
    );
    Ok(validation_exit(&ctx))
}

/// The `area` group: its own sweep of lights over the scene's surface, one CPU reference per
/// cell ([`luz::lab::area`]).
/// The renderer's options for every lab run: the IBL quality and switches of `a`, no progress.
fn lab_render_options(a: &LabArgs) -> luz::headless::RenderOptions {
    luz::headless::RenderOptions {
        progress: None,
        switches: a.switches.switches(),
        ..render_options(
            &IblArgs {
                ibl_quality: a.ibl_quality,
                no_cache: false,
            },
            Default::default(),
        )
    }
}

fn run_area(a: &LabArgs, scene: &luz::scene::Scene) -> Result<ExitCode> {
    use luz::lab::area;
    if a.only.len() > 1 {
        bail!("--only area runs alone: each of its cells has its own reference");
    }
    if a.reference.is_some() {
        bail!("--reference: the area group renders one reference per cell itself");
    }
    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("cannot create {}", a.out.display()))?;
    let ctx = context(&a.gpu)?;
    println!("device: {}", ctx.info.summary());
    let mut shapes = area::SHAPES.to_vec();
    if !a.area_shapes.is_empty() {
        if let Some(bad) = a.area_shapes.iter().find(|s| !shapes.contains(&s.as_str())) {
            bail!("--area-shapes: unknown shape {bad} (rect, disk, sphere, tube)");
        }
        shapes.retain(|s| a.area_shapes.iter().any(|w| w == s));
    }
    let sweep = area::AreaSweep {
        shapes,
        frames: a.frames,
        reference_samples: a.reference_samples,
        ..Default::default()
    };
    println!(
        "area: {} cells, reference {} directions per strategy, error at {}x{}, time at {}x{}",
        area::cells(&sweep).len(),
        sweep.reference_samples,
        scene.output.width,
        scene.output.height,
        sweep.timing_size.0,
        sweep.timing_size.1
    );
    let render = lab_render_options(a);
    let bar = Bar::new("{bar:40} {pos}/{len} cells {elapsed} {msg}");
    let rows = area::measure(&ctx, scene, &sweep, &render, Some(&bar))?;
    area::write_outputs(&a.out, scene, &sweep, &rows)?;
    println!(
        "{:<7} {:<22} {:>5} {:>6} {:>7} {:>9} {:>10} {:>8} {:>10} {:>10}",
        "shape",
        "method",
        "rough",
        "size",
        "sr",
        "elevation",
        "fwd ms",
        "× point",
        "rel L1",
        "FLIP"
    );
    for r in &rows {
        println!(
            "{:<7} {:<22} {:>5} {:>6} {:>7} {:>9} {:>10.3} {:>8.2} {:>10.5} {:>10.5}",
            r.cell.shape,
            r.label(),
            r.cell.roughness,
            r.cell.size,
            r.cell.solid_angle_sr,
            r.cell.elevation,
            r.forward_ms,
            r.cost(),
            r.relative_l1,
            r.error.flip_mean
        );
    }
    println!(
        "wrote {0}/results.csv, {0}/results.json, {0}/chart.png, {0}/chart.svg",
        a.out.display()
    );
    Ok(validation_exit(&ctx))
}
