//! `luz render`: a scene headless to a PNG or EXR image.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::Result;
use clap::Args;

use luz::headless::{Headless, TimingReport};
use luz::render::forward::DebugView;

use super::common::{
    check_output, context, debug_view_parser, light_loop_line, load_scene, print_timing,
    render_options, report_lod, report_tessellation, report_written, validation_exit, GpuArgs,
    IblArgs, LightLoopArg, SwitchArgs, ViewOverrides,
};

#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Scene file (JSON); the embedded default scene when omitted.
    pub scene: Option<PathBuf>,
    /// Output image: .png (exposed, tone-mapped, sRGB) or .exr (linear float32 radiance).
    #[arg(short, long, default_value = "luz.png")]
    pub output: PathBuf,
    /// Frames to render; timings are the median over them.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub frames: u32,
    #[command(flatten)]
    pub view: ViewOverrides,
    /// List the pipeline variants built and more detail.
    #[arg(short, long)]
    pub verbose: bool,
    #[command(flatten)]
    pub ibl: IblArgs,
    /// Show one quantity instead of the shaded radiance (BRDF terms are for the first light).
    #[arg(long, value_parser = debug_view_parser(), default_value = "none")]
    pub debug_view: DebugView,
    /// How the fragment stage loops over lights: "auto" (clustered with 4 or more lights with
    /// a range when the clusters cull them, else plain), "plain" (every light everywhere) or "clustered" (the fragment's cluster only).
    #[arg(long, value_enum, default_value_t = LightLoopArg::Auto)]
    pub light_loop: LightLoopArg,
    /// Also write each shadowed light's maps as DIR/light<N>.png after the last frame: its
    /// layers (cascades, cube faces +x −x +y −y +z −z) side by side, the distance from the light
    /// from white (nearest drawn texel) to black (farthest), dark blue where nothing was drawn.
    #[arg(long, value_name = "DIR")]
    pub shadow_maps: Option<PathBuf>,
    /// Also write the last frame's graph: its passes in order (with their median GPU ms; passes
    /// nobody needed dashed), the resources they use (imported or transient, format and size)
    /// and each use's access kind. Graphviz DOT, or a standalone SVG when FILE ends in ".svg".
    #[arg(long, value_name = "FILE")]
    pub graph: Option<PathBuf>,
    #[command(flatten)]
    pub switches: SwitchArgs,
    #[command(flatten)]
    pub gpu: GpuArgs,
}

pub fn run(a: RenderArgs) -> Result<ExitCode> {
    let t0 = Instant::now();
    let format = check_output(&a.output)?;
    let mut scene = load_scene(a.scene.as_deref(), None)?;
    a.view.apply(&mut scene)?;
    let ctx = context(&a.gpu)?;
    println!("device: {}", ctx.info.summary());
    let switches = a.switches.switches().for_frames(a.frames);
    let mut renderer = Headless::with_options(
        &ctx,
        &scene,
        &luz::headless::RenderOptions {
            light_loop: a.light_loop.light_loop(),
            switches,
            ..render_options(&a.ibl, a.debug_view)
        },
    )?;
    if a.verbose {
        println!("pipeline variants built:");
        for v in renderer.variants() {
            println!("  {v}");
        }
        println!("triangles: {}", renderer.triangle_count());
        let (drawn, all) = renderer.drawn_objects();
        println!("objects drawn after frustum culling: {drawn} of {all}");
        let (calls, objects) = renderer.draw_calls();
        println!("draw calls: {calls} for {objects} objects (instancing)");
        let maps = renderer.shadow_maps();
        if maps.is_empty() {
            println!("shadow maps: none (no light has \"shadow\"; no shadow pass)");
        } else {
            println!(
                "shadow maps (their GPU time is the \"shadows\" row below; {} triangles drawn \
                 into them, casters at their LOD levels):",
                renderer.shadow_triangles_drawn()
            );
            let lights = luz::render::shadow::shadow_lights(&scene);
            for m in &maps {
                let kernel = lights[m.light].shadow.map_or(0, |s| s.pcf_kernel);
                let line = m.describe(kernel);
                // Area lights' maps follow the punctual lights' (render::shadow::shadow_lights).
                let line = match m.light.checked_sub(scene.lights.len()) {
                    Some(k) => {
                        line.replacen(&format!("light {}", m.light), &format!("area light {k}"), 1)
                    }
                    None => line,
                };
                println!("  {line}");
            }
            let r = renderer.shadow_receivers();
            if !switches.shadow_receivers {
                println!(
                    "shadow receivers: not culled ({}; lookups everywhere)",
                    if a.switches.no_shadow_receivers {
                        "--no-shadow-receivers"
                    } else {
                        "one frame: compiling the culled variants costs more than it saves; \
                         --frames 2 or more culls"
                    }
                );
            } else if r.deferred {
                println!(
                    "shadow receivers (deferred lighting pass): {} of {} shadowed lights' \
                     lookups compiled out (no caster can darken any object); lookups {} \
                     (--no-shadow-receivers: lookups everywhere)",
                    r.skipped,
                    r.pairs,
                    if r.split == 1 {
                        "only inside the screen rectangle shadows can reach"
                    } else {
                        "everywhere"
                    }
                );
            } else {
                println!(
                    "shadow receivers: {} of {} (object, shadowed light) lookups compiled out (no \
                 caster can darken the object); {} object(s) with lookups only inside the screen \
                 rectangle shadows can reach (--no-shadow-receivers: lookups everywhere)",
                    r.skipped, r.pairs, r.split
                );
            }
        }
        println!("{}", light_loop_line(renderer.cluster_stats()));
    }
    report_tessellation(&scene, a.verbose);
    report_lod(&scene, &renderer, a.verbose);
    if let Some(t) = renderer.ibl_times() {
        let stages: Vec<String> = t
            .stages
            .iter()
            .map(|(n, ms)| format!("{n} {ms:.0} ms"))
            .collect();
        println!(
            "IBL precomputation: {:.0} ms ({})",
            t.total(),
            stages.join(", ")
        );
    }
    for w in &scene.warnings {
        eprintln!("warning: {w}");
    }
    let mut frames = Vec::with_capacity(a.frames as usize);
    let first = renderer.render()?;
    let ttff = t0.elapsed().as_secs_f64() * 1e3;
    frames.push(first);
    for _ in 1..a.frames {
        frames.push(renderer.render()?);
    }
    let image = renderer.image()?;
    let timing = TimingReport::of(&frames);
    luz::imageio::save_render(&a.output, &image, scene.output.encoding(), &{
        let mut p = luz::provenance::of_render(&ctx.info, &scene, Some(&timing));
        luz::provenance::add_switches(&mut p, &switches);
        p
    })?;
    let nan = luz::imageio::count_non_finite(&image.pixels);
    println!(
        "scene: {} ({}x{}, msaa {})",
        scene.display_name(),
        scene.output.width,
        scene.output.height,
        scene.output.msaa
    );
    println!("time to first frame: {ttff:.1} ms (process start to first frame on the host)");
    print_timing(&timing);
    report_written(&a.output, format, nan);
    if let Some(dir) = &a.shadow_maps {
        write_shadow_maps(&renderer, dir)?;
    }
    if let Some(path) = &a.graph {
        write_graph(&renderer, &timing, path)?;
    }
    Ok(validation_exit(&ctx))
}

/// `--graph FILE`: the last frame's graph as DOT, or SVG for a `.svg` FILE.
fn write_graph(renderer: &Headless, timing: &TimingReport, path: &std::path::Path) -> Result<()> {
    let Some(plan) = renderer.last_graph() else {
        anyhow::bail!("--graph {}: no frame was rendered", path.display());
    };
    let times: Vec<(&str, f64)> = timing.passes.iter().map(|(n, s)| (*n, s.median)).collect();
    let svg = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("svg"));
    let text = if svg {
        plan.to_svg(&times)
    } else {
        plan.to_dot(&times)
    };
    std::fs::write(path, text).map_err(|e| anyhow::anyhow!("--graph {}: {e}", path.display()))?;
    println!(
        "wrote {} (the frame graph: {} passes, {} culled)",
        path.display(),
        plan.live_passes().len(),
        plan.culled_passes().len()
    );
    Ok(())
}

/// `--shadow-maps DIR`: one picture per shadowed light ([`luz::render::shadow::picture`]).
fn write_shadow_maps(renderer: &Headless, dir: &std::path::Path) -> Result<()> {
    let layers = renderer.shadow_map_layers()?;
    if layers.is_empty() {
        println!("shadow maps: none to write (no light has \"shadow\")");
        return Ok(());
    }
    std::fs::create_dir_all(dir)
        .map_err(|e| anyhow::anyhow!("--shadow-maps {}: {e}", dir.display()))?;
    let mut lights: Vec<usize> = layers.iter().map(|l| l.light).collect();
    lights.dedup();
    for light in lights {
        let own: Vec<_> = layers.iter().filter(|l| l.light == light).collect();
        let Some((w, h, pixels)) = luz::render::shadow::picture(&own) else {
            continue;
        };
        let path = dir.join(format!("light{light}.png"));
        image::save_buffer(&path, &pixels, w, h, image::ExtendedColorType::Rgba8)
            .map_err(|e| anyhow::anyhow!("--shadow-maps {}: {e}", path.display()))?;
        let drawn = own.iter().flat_map(|l| l.distance.iter().flatten());
        let (near, far) = drawn.fold((f32::INFINITY, f32::NEG_INFINITY), |(n, f), d| {
            (n.min(*d), f.max(*d))
        });
        let range = if near <= far {
            format!("distances {near:.3}–{far:.3} m")
        } else {
            "nothing drawn".to_string()
        };
        println!(
            "shadow maps of light {light}: {} ({} layer(s) of {}², {range})",
            path.display(),
            own.len(),
            own[0].resolution
        );
    }
    Ok(())
}
