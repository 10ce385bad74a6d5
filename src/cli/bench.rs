//! `luz bench`: frame-time statistics over many frames, and memory samples (a soak).

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context as _, Result};
use clap::Args;

use luz::headless::{Headless, TimingReport};
use luz::render::forward::{DebugView, Output};
use luz::vk::Context;

use super::common::{
    context, debug_view_parser, light_loop_line, load_scene, print_timing, render_options,
    report_tessellation, validation_exit, Bar, GpuArgs, IblArgs, LightLoopArg, RenderPathArg,
    SwitchArgs, TimingFiles, ViewOverrides,
};

#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Scene file (JSON); the embedded default scene when omitted.
    pub scene: Option<PathBuf>,
    /// Frames to time (after the warm-up).
    #[arg(long, default_value_t = 50, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub frames: u32,
    /// Frames rendered first and not timed.
    #[arg(long, default_value_t = 3)]
    pub warmup: u32,
    #[command(flatten)]
    pub files: TimingFiles,
    #[command(flatten)]
    pub view: ViewOverrides,
    #[command(flatten)]
    pub ibl: IblArgs,
    /// Show one quantity instead of the shaded radiance (see `luz render --help`);
    /// `base_color` is the unlit floor: the same geometry and pixels with no lighting.
    #[arg(long, value_parser = debug_view_parser(), default_value = "none")]
    pub debug_view: DebugView,
    /// What the forward pass writes: "hdr" (RGBA32F radiance, read back at 16 bytes per pixel,
    /// as `luz render`) or "display" (exposure, tone map and sRGB encode in the fragment shader
    /// into RGBA8, the viewer's direct path; not with normalize saturation or MSAA).
    #[arg(long, value_enum, default_value_t = BenchOutput::Hdr)]
    pub output: BenchOutput,
    /// "auto": deferred lighting (a G-buffer pass, then one lighting pass over the covered
    /// pixels) when every object shares one lean Phong variant, no environment, no MSAA; forward
    /// otherwise. "forward": always forward (for comparisons).
    #[arg(long, value_enum, default_value_t = RenderPathArg::Auto)]
    pub render_path: RenderPathArg,
    /// How the fragment stage loops over lights: "auto" (clustered with 4 or more lights with
    /// a range when the clusters cull them, else plain), "plain" or "clustered" (see
    /// `luz render --help`).
    #[arg(long, value_enum, default_value_t = LightLoopArg::Auto)]
    pub light_loop: LightLoopArg,
    /// Sample resident memory and GPU allocations every N frames (a soak: they must stay flat);
    /// default: a tenth of --frames.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..))]
    pub memory_every: Option<u32>,
    /// Exit 4 when resident memory grows by more than this many MiB between the first and the
    /// last sample, or the GPU allocation count or bytes change.
    #[arg(long)]
    pub max_memory_growth_mib: Option<f64>,
    /// Also time the scene at this `output.tessellation_error_px` (0: full detail, every mesh
    /// whole and primitives at the most segments) in the same run, its frames alternating with
    /// the scene's own, and print both and their ratio.
    #[arg(long, value_name = "PX")]
    pub compare_budget: Option<f32>,
    #[command(flatten)]
    pub switches: SwitchArgs,
    #[command(flatten)]
    pub gpu: GpuArgs,
}

/// `--output` values.
#[derive(clap::ValueEnum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum BenchOutput {
    Hdr,
    Display,
}

/// One sample of a soak: resident memory and the GPU allocator's live allocations.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct MemorySample {
    pub frame: u64,
    pub rss_mib: f64,
    pub gpu_allocations: usize,
    pub gpu_bytes: u64,
}

/// Resident set size of this process in MiB (Linux `/proc/self/statm`; NaN elsewhere).
pub fn resident_mib() -> f64 {
    let Ok(statm) = std::fs::read_to_string("/proc/self/statm") else {
        return f64::NAN;
    };
    let pages: f64 = statm
        .split_whitespace()
        .nth(1)
        .and_then(|v| v.parse().ok())
        .unwrap_or(f64::NAN);
    pages * 4096.0 / (1024.0 * 1024.0)
}

fn memory_sample(ctx: &Context, frame: u64) -> MemorySample {
    let report = ctx.allocator().generate_report();
    MemorySample {
        frame,
        rss_mib: resident_mib(),
        gpu_allocations: report.allocations.len(),
        gpu_bytes: report.total_allocated_bytes,
    }
}

pub fn run(a: BenchArgs) -> Result<ExitCode> {
    let mut scene = load_scene(a.scene.as_deref(), None)?;
    a.view.apply(&mut scene)?;
    for p in [&a.files.csv, &a.files.json, &a.files.trace]
        .into_iter()
        .flatten()
    {
        std::fs::write(p, b"").with_context(|| format!("cannot write {}", p.display()))?;
    }
    let ctx = context(&a.gpu)?;
    println!("device: {}", ctx.info.summary());
    report_tessellation(&scene, false);
    let options = luz::headless::RenderOptions {
        render_path: a.render_path.path(),
        light_loop: a.light_loop.light_loop(),
        switches: a.switches.switches(),
        ..render_options(&a.ibl, a.debug_view)
    };
    let mut renderer = Headless::with_options(&ctx, &scene, &options)?;
    let mut compared = match a.compare_budget {
        Some(b) if !(b.is_finite() && b >= 0.0) => {
            anyhow::bail!("--compare-budget: must be a number of pixels >= 0, got {b}")
        }
        Some(b) => {
            let mut other = scene.clone();
            other.output.tessellation_error_px = b;
            luz::scene::tessellation::resolve(&mut other);
            let r = Headless::with_options(&ctx, &other, &options)?;
            Some((other, r, Vec::with_capacity(a.frames as usize)))
        }
        None => None,
    };
    let output = match a.output {
        BenchOutput::Hdr => Output::Hdr,
        BenchOutput::Display => renderer.display_output(&scene)?,
    };
    let render = |r: &mut Headless| match output {
        Output::Hdr => r.render(),
        o => r.render_display(o),
    };
    for _ in 0..a.warmup {
        render(&mut renderer)?;
        if let Some((_, r, _)) = &mut compared {
            render(r)?;
        }
    }
    let bar = Bar::with_length("{bar:40} {pos}/{len} frames {elapsed}", a.frames as u64);
    let mut frames = Vec::with_capacity(a.frames as usize);
    let clock = std::time::Instant::now();
    let mut starts = Vec::with_capacity(a.frames as usize);
    let every = a.memory_every.unwrap_or((a.frames / 10).max(1)) as u64;
    let mut memory = vec![memory_sample(&ctx, 0)];
    for i in 1..=a.frames as u64 {
        starts.push(clock.elapsed().as_secs_f64() * 1e6);
        frames.push(render(&mut renderer)?);
        if let Some((_, r, f)) = &mut compared {
            f.push(render(r)?);
        }
        bar.inc(1);
        if i % every == 0 {
            memory.push(memory_sample(&ctx, i));
        }
    }
    bar.finish_and_clear();
    if let Some(path) = &a.files.trace {
        write_trace(path, &frames, &starts)?;
    }
    println!(
        "scene: {} ({}x{}, {} triangles, {} drawn, {} of {} objects in view in {} draw calls, \
         {} lights), {} path, output {}",
        scene.display_name(),
        scene.output.width,
        scene.output.height,
        renderer.triangle_count(),
        renderer.triangles_drawn(),
        renderer.drawn_objects().0,
        renderer.drawn_objects().1,
        renderer.draw_calls().0,
        scene.lights.len(),
        renderer.render_path(),
        match output {
            Output::Hdr => "hdr (RGBA32F radiance)".to_string(),
            Output::Display { tonemap, .. } => format!(
                "display (RGBA8 codes, {} tone map in the forward pass)",
                tonemap.name()
            ),
        }
    );
    let clusters = renderer.cluster_stats();
    println!("{}", light_loop_line(clusters));
    let report = TimingReport::of(&frames);
    print_timing(&report);
    if let Some((other, r, f)) = &compared {
        print_comparison(
            (&scene, &renderer, &report),
            (other, r, &TimingReport::of(f)),
        );
    }
    let wall: Vec<f64> = frames.iter().map(|f| f.cpu_ms).collect();
    let stutters = luz::profiler::stutter_count(&wall);
    println!("stutters: {stutters} frames slower than 2x the rolling median of the frame time");
    let (drawn, reused, layers) = renderer.shadow_frames_drawn_reused();
    if drawn + reused > 0 {
        println!(
            "shadow maps: layers drawn in {drawn} frame(s) ({layers} layers in all), every layer \
             reused in {reused} (nothing it sees moved; --no-shadow-cache draws them every frame)"
        );
    }
    println!("memory (resident MiB, GPU allocations, GPU bytes) every {every} frames:");
    for m in &memory {
        println!(
            "  frame {:>8}  {:>9.2} MiB  {:>5} allocations  {:>12} bytes",
            m.frame, m.rss_mib, m.gpu_allocations, m.gpu_bytes
        );
    }
    // The first sample is before any timed frame; growth is judged from the second on (the
    // first frames fault in the driver's caches).
    let base = memory.get(1).unwrap_or(&memory[0]);
    let last = memory.last().unwrap_or(base);
    let growth = last.rss_mib - base.rss_mib;
    let gpu_flat = last.gpu_allocations == base.gpu_allocations && last.gpu_bytes == base.gpu_bytes;
    println!(
        "memory growth from frame {} to {}: {growth:+.2} MiB resident, GPU allocations {}",
        base.frame,
        last.frame,
        if gpu_flat { "flat" } else { "CHANGED" }
    );
    let megapixels = scene.output.width as f64 * scene.output.height as f64 / 1e6;
    // The scene's passes: "forward", or "gbuffer" + "lighting" on the deferred path.
    let scene_ms: Vec<f64> = frames
        .iter()
        .map(|f| {
            f.gpu_ms
                .iter()
                .filter(|(n, _)| matches!(*n, "forward" | "gbuffer" | "lighting"))
                .map(|(_, ms)| ms)
                .sum()
        })
        .collect();
    let forward = (!frames.is_empty() && frames.iter().any(|f| !f.gpu_ms.is_empty()))
        .then(|| luz::stats::median(&scene_ms));
    let per_mp_light = match forward {
        Some(ms) if !scene.lights.is_empty() => {
            let v = ms / (megapixels * scene.lights.len() as f64);
            println!(
                "GPU scene passes per megapixel·light: {v:.4} ms (median {ms:.3} ms / ({megapixels:.4} MP × {} lights))",
                scene.lights.len()
            );
            Some(v)
        }
        _ => None,
    };
    if let Some(p) = &a.files.csv {
        let mut out = String::from("frame,cpu_ms");
        for (n, _) in &report.passes {
            out.push_str(&format!(",gpu_{n}_ms"));
        }
        out.push('\n');
        for (i, f) in frames.iter().enumerate() {
            out.push_str(&format!("{i},{:.4}", f.cpu_ms));
            for (n, _) in &report.passes {
                let t = f.gpu_ms.iter().find(|(m, _)| m == n).map(|(_, t)| *t);
                out.push_str(&format!(",{:.4}", t.unwrap_or(f64::NAN)));
            }
            out.push('\n');
        }
        std::fs::write(p, out).with_context(|| format!("cannot write {}", p.display()))?;
        println!("wrote {}", p.display());
    }
    if let Some(p) = &a.files.json {
        let passes: serde_json::Map<String, serde_json::Value> = report
            .passes
            .iter()
            .map(|(n, s)| (n.to_string(), serde_json::to_value(s).unwrap_or_default()))
            .collect();
        let json = serde_json::json!({
            "device": ctx.info.summary(),
            "frames": report.frames,
            "width": scene.output.width,
            "height": scene.output.height,
            "triangles": renderer.triangle_count(),
            "triangles_drawn": renderer.triangles_drawn(),
            "draw_calls": renderer.draw_calls().0,
            "shadow_triangles_drawn": renderer.shadow_triangles_drawn(),
            "shadow_frames_drawn": renderer.shadow_frames_drawn_reused().0,
            "shadow_frames_reused": renderer.shadow_frames_drawn_reused().1,
            "shadow_layers_drawn": renderer.shadow_frames_drawn_reused().2,
            "objects_drawn": renderer.drawn_objects().0,
            "tessellation_error_px": scene.output.tessellation_error_px,
            "compared": compared.as_ref().map(|(o, r, f)| serde_json::json!({
                "tessellation_error_px": o.output.tessellation_error_px,
                "triangles_drawn": r.triangles_drawn(),
                "draw_calls": r.draw_calls().0,
                "gpu_total_ms": TimingReport::of(f).gpu_total,
                "cpu_ms": TimingReport::of(f).cpu,
            })),
            "lights": scene.lights.len(),
            "render_path": renderer.render_path(),
            "light_loop": if clusters.is_some() { "clustered" } else { "plain" },
            "cluster_build_ms": clusters.map(|c| c.build_ms),
            "cluster_lights_max": clusters.map(|c| c.max),
            "cluster_lights_mean": clusters.map(|c| c.mean),
            "area_lights": scene.area_lights.len(),
            "cluster_area_lights_max": clusters.map(|c| c.area_max),
            "cluster_area_lights_mean": clusters.map(|c| c.area_mean),
            "output": match output { Output::Hdr => "hdr", Output::Display { .. } => "display" },
            "cpu_ms": report.cpu,
            "gpu_total_ms": report.gpu_total,
            "gpu_pass_ms": passes,
            "gpu_forward_ms_per_megapixel_light": per_mp_light,
            "stutters": stutters,
            "memory": memory,
            "memory_growth_mib": growth,
            "gpu_allocations_flat": gpu_flat,
        });
        std::fs::write(p, serde_json::to_string_pretty(&json)?)
            .with_context(|| format!("cannot write {}", p.display()))?;
        println!("wrote {}", p.display());
    }
    if let Some(max) = a.max_memory_growth_mib {
        if growth > max || !gpu_flat {
            eprintln!(
                "luz: error: memory not flat: {growth:+.2} MiB resident (limit {max}), GPU allocations {}",
                if gpu_flat { "flat" } else { "changed" }
            );
            return Ok(ExitCode::from(4));
        }
    }
    Ok(validation_exit(&ctx))
}

/// The two budgets of `--compare-budget` side by side: triangles drawn, GPU total and CPU frame
/// medians, and the first's cost as a fraction of the second's.
fn print_comparison(
    (a, ra, ta): (&luz::scene::Scene, &Headless, &TimingReport),
    (b, rb, tb): (&luz::scene::Scene, &Headless, &TimingReport),
) {
    println!("budgets compared in this run (frames alternating):");
    println!(
        "  {:<26} {:>14} {:>16} {:>16}",
        "tessellation_error_px", "triangles", "GPU total ms", "CPU frame ms"
    );
    for (s, r, t) in [(a, ra, ta), (b, rb, tb)] {
        println!(
            "  {:<26} {:>14} {:>16.3} {:>16.3}",
            s.output.tessellation_error_px,
            r.triangles_drawn(),
            t.gpu_total.median,
            t.cpu.median
        );
    }
    println!(
        "  ratio {} px / {} px: GPU total {:.3}x, CPU frame {:.3}x, triangles {:.4}x",
        a.output.tessellation_error_px,
        b.output.tessellation_error_px,
        ta.gpu_total.median / tb.gpu_total.median,
        ta.cpu.median / tb.cpu.median,
        ra.triangles_drawn() as f64 / rb.triangles_drawn().max(1) as f64
    );
}

/// `--trace FILE`: the timed frames as a Chrome/Perfetto trace. Frame `i` starts at `starts[i]`
/// (µs since the first timed frame); its GPU spans start when recording ends (the submission).
fn write_trace(
    path: &std::path::Path,
    frames: &[luz::headless::FrameTimes],
    starts: &[f64],
) -> Result<()> {
    let mut trace = luz::graph::Trace::new();
    for (i, (f, &t)) in frames.iter().zip(starts).enumerate() {
        trace.sequential_frame(
            i as u64,
            t,
            ("record", f.record_ms * 1e3),
            ("submit + wait", f.cpu_ms * 1e3),
            &f.gpu_ms,
        );
    }
    std::fs::write(path, trace.to_json())
        .with_context(|| format!("cannot write {}", path.display()))?;
    println!("wrote {} ({} frames)", path.display(), frames.len());
    Ok(())
}
