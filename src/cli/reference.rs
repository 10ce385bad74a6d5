//! `luz reference`: the CPU reference renderer ([`luz::reference`]) to an EXR or PNG image.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::Result;
use clap::Args;

use super::common::{check_output, report_written, Bar, ViewOverrides};

/// `luz reference`.
#[derive(Args, Debug)]
#[command(
    after_help = "Exact primitives (an icosphere is a sphere), per-pixel shading with the CPU \
BRDFs whatever the object's shading frequency, the environment's light converged by multiple importance \
sampling; the same camera, lights, maps, fog, background and saturation as `luz render`; shadow rays \
for lights with \"shadow\" (soft for lights with a size, --shadow-samples), no inter-reflections (as the GPU \
path). Compare it with a GPU frame with `luz diff`.\n\n\
Examples:\n  luz reference scene.json -o ref.exr              pixel centres (compare with msaa 1)\n  \
luz reference scene.json -o ref.exr --spp 16      antialiased\n  \
luz reference ibl.json -o ref.exr --samples 4096  a more converged environment integral"
)]
pub struct ReferenceArgs {
    /// Scene file (JSON); the embedded default scene when omitted.
    pub scene: Option<PathBuf>,
    /// Output image: .exr (linear float32 radiance) or .png (exposed, tone-mapped, sRGB).
    #[arg(short, long, default_value = "reference.exr")]
    pub output: PathBuf,
    /// Primary rays per pixel: 1 shoots through the pixel centre (compare with msaa 1 renders);
    /// more average correlated multi-jittered rays (an antialiased reference).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=luz::reference::MAX_SPP as i64))]
    pub spp: u32,
    /// Directions per pixel for the environment's light and, per sampling strategy (the emitter
    /// and each BRDF lobe), for each area light (Monte Carlo with multiple importance sampling;
    /// split between the primary rays when --spp > 1). The default puts a Lambert plane under
    /// an area light within 0.5 % of its exact irradiance.
    #[arg(long, default_value_t = 1024, value_parser = clap::value_parser!(u32).range(1..=luz::reference::MAX_SAMPLES as i64))]
    pub samples: u32,
    /// Seed of the random numbers (same seed, same image).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Shadow rays per light per primary ray for lights with a size (radius or angular radius:
    /// soft shadows); point-like lights take one (hard shadows).
    #[arg(long, default_value_t = luz::reference::DEFAULT_SHADOW_SAMPLES, value_parser = clap::value_parser!(u32).range(1..=luz::reference::MAX_SAMPLES as i64))]
    pub shadow_samples: u32,
    #[command(flatten)]
    pub view: ViewOverrides,
}

/// Runs `luz reference`.
pub fn run(a: ReferenceArgs) -> Result<ExitCode> {
    let t0 = Instant::now();
    let format = check_output(&a.output)?;
    let mut scene = luz::scene::load_or_default(a.scene.as_deref())?;
    a.view.apply(&mut scene)?;
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    let opts = luz::reference::ReferenceOptions {
        spp: a.spp,
        samples: a.samples,
        seed: a.seed,
        shadow_samples: a.shadow_samples,
    };
    let bar = Bar::with_length(
        "reference {bar:30} {pos}/{len} rows {elapsed} (eta {eta})",
        u64::from(scene.output.height),
    );
    let report = |done: u64, total: u64| {
        luz::progress::Progress::update(&bar, "", done, total);
    };
    let t_render = Instant::now();
    let image = luz::reference::render_reference(&scene, &opts, Some(&report));
    bar.finish_and_clear();
    let image = image?;
    let render_s = t_render.elapsed().as_secs_f64();
    let mut meta = luz::imageio::Provenance::base();
    luz::provenance::add_scene(&mut meta, &scene);
    meta.set("luz.device", "CPU reference renderer");
    luz::imageio::save_with(
        &a.output,
        &image,
        scene.output.exposure,
        scene.output.tonemap,
        &meta,
    )?;
    let nan = luz::imageio::count_non_finite(&image.pixels);
    println!(
        "scene: {} ({}x{}, {} objects, {} lights{})",
        scene.display_name(),
        scene.output.width,
        scene.output.height,
        scene.objects.len(),
        scene.lights.len(),
        if scene.environment.is_some() {
            ", environment"
        } else {
            ""
        }
    );
    println!(
        "reference: {} spp, {} environment samples per pixel, seed {}, {} threads",
        opts.spp,
        opts.samples,
        opts.seed,
        rayon::current_num_threads()
    );
    println!(
        "render time: {render_s:.2} s ({:.2} s in all)",
        t0.elapsed().as_secs_f64()
    );
    report_written(&a.output, format, nan);
    Ok(ExitCode::SUCCESS)
}
