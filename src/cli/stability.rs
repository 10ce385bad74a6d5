//! `luz stability`: every BRDF model and term at the edges of its domain, CPU reference against
//! GPU mirror ([`luz::stability`]).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context as _, Result};
use clap::Args;

use luz::stability::{
    albedo_samples, directions, format_model, rows, sweep, CpuEvaluator, Evaluator, GpuEvaluator,
    Row, SweepOptions, DEFAULT_SAMPLES, ENERGY_TOLERANCE, MODELS, REFINE_FACTOR, REFINE_MARGIN,
};

use super::common::{context, validation_exit, GpuArgs};

const EXAMPLES: &str = "\
Sweeps every model and every selectable term over roughness {0, 1e-4, 1e-3, 1e-2, 0.1, 0.5, 1},
n·l and n·v in {1, 0.5, 0.1, 1e-2, 1e-3, 1e-4, 1e-6, 0} at azimuths 0°/90°/180° (l = v and mirror
pairs), l = −v, below-horizon directions, zero/tiny/huge/non-unit normals, l and v, degenerate
tangents, and light irradiances {1, 1e3, 1e6}; Phong/Blinn-Phong shininess 0 … 1e4, Oren-Nayar
σ 0° … 90°, the Principled parameters at 0 and 1, every D × G × F of Cook-Torrance (k_d 0, 0.5,
1; Fresnel inputs F0 ∈ {0, 1}, η ∈ {1e-4, 1, 1.5, 1e20}, gold, and a complex index whose squares
overflow f32) and of metallic-roughness (metallic 0, 0.5, 1, with and without the (1 − F) weight).
Each input is evaluated on the CPU reference
and on the GPU mirror (a compute shader running shaders_glsl/brdf/models.glsl).

Columns (per side): NaN, Inf, neg = inputs with a NaN, ±Inf or negative output (f or radiance);
max L = largest radiance f·E·cosθ; max R = largest directional albedo ∫ f cosθ dω over the
light angles cosθl ∈ {1, 0.5, 0.1, 1e-2, 1e-3}; gain = R − 1 over the sets the model claims to
conserve (claim column; '-' = not claimed). max rel = largest |GPU − CPU| / (|CPU| + 1e-5·E);
>bound = values beyond the tests' bound 1e-3·|CPU| + 1e-5·E.

Albedo: multiple importance sampling (src/brdf/albedo.rs), --samples points (4× below
cosθl = 0.1); the GPU's albedo replays the CPU's quadrature points with GPU values. Claimed
estimates above 1 + tolerance − 2e-3 are re-integrated on the CPU at 16× the points (each side
keeps its own difference from the CPU on the first points), which brings the quadrature error
(measured ≤ 1.8e-3 near R = 1 at 2048 points) below 3.3e-4.

Exit status: 0 clean; 1 on any NaN, Inf or negative value, or a claimed energy gain beyond
--energy-tolerance; 3 on validation errors (--validate / LUZ_VALIDATION=1).

Examples:
  luz stability
  luz stability --cpu-only --model cook_torrance
  LUZ_VALIDATION=1 luz stability --json stability.json";

/// `luz stability`: NaN/Inf/negative values and energy gain at the edges of every model's domain,
/// CPU reference against GPU mirror.
#[derive(Args, Debug, Clone)]
#[command(after_long_help = EXAMPLES)]
pub struct StabilityArgs {
    /// Write the full table (every row, both sides, where each maximum was found) as JSON.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Evaluate the CPU reference only (no Vulkan device needed).
    #[arg(long)]
    pub cpu_only: bool,
    /// Only these models (lambert, phong, blinn_phong, cook_torrance, metal_rough, principled,
    /// oren_nayar); repeatable. Default: all.
    #[arg(long, value_name = "NAME")]
    pub model: Vec<String>,
    /// Quadrature points per directional albedo (4× below cosθl = 0.1; claimed estimates near 1
    /// are refined at 16×). The tolerance's justification assumes the default.
    #[arg(long, default_value_t = DEFAULT_SAMPLES, value_parser = clap::value_parser!(u32).range(16..=1_048_576))]
    pub samples: u32,
    /// A model that claims energy conservation fails when its albedo exceeds 1 + this.
    #[arg(long, default_value_t = ENERGY_TOLERANCE)]
    pub energy_tolerance: f32,
    #[command(flatten)]
    pub gpu: GpuArgs,
}

/// `luz stability`.
pub fn run(a: StabilityArgs) -> Result<ExitCode> {
    let t0 = Instant::now();
    for name in &a.model {
        anyhow::ensure!(
            MODELS.contains(&name.as_str()),
            "--model {name}: unknown model (one of {})",
            MODELS.join(", ")
        );
    }
    anyhow::ensure!(
        a.energy_tolerance.is_finite() && a.energy_tolerance >= 0.0,
        "--energy-tolerance: must be a finite number ≥ 0, got {}",
        a.energy_tolerance
    );
    if let Some(p) = &a.json {
        std::fs::write(p, b"").with_context(|| format!("cannot write {}", p.display()))?;
    }
    let rows: Vec<Row> = rows()
        .into_iter()
        .filter(|r| a.model.is_empty() || a.model.iter().any(|m| m == r.model))
        .collect();
    let dirs = directions();
    let opts = SweepOptions {
        samples: a.samples,
        energy_tolerance: a.energy_tolerance,
    };
    let ctx = if a.cpu_only {
        None
    } else {
        Some(context(&a.gpu)?)
    };
    let mut cpu = CpuEvaluator;
    let mut gpu = match &ctx {
        Some(ctx) => Some(GpuEvaluator::new(ctx)?),
        None => None,
    };
    match &ctx {
        Some(ctx) => println!("device: {}", ctx.info.summary()),
        None => println!("device: none (--cpu-only)"),
    }
    let sets: usize = rows.iter().map(|r| r.sets.len()).sum();
    println!(
        "sweep: {} rows, {sets} parameter sets × {} direction cases × E ∈ {{1, 1e3, 1e6}}",
        rows.len(),
        dirs.len(),
    );
    println!(
        "albedo: cosθl ∈ {{1, 0.5, 0.1, 1e-2, 1e-3}}, {} points ({} below cosθl = 0.1); claimed \
         estimates above 1 + {:e} − {REFINE_MARGIN:e} re-integrated at {REFINE_FACTOR}× (GPU: plus its \
         difference from the CPU on the same points); energy tolerance {:e}",
        a.samples,
        albedo_samples(0.0, a.samples),
        a.energy_tolerance,
        a.energy_tolerance
    );
    println!(
        "columns: inputs with NaN / ±Inf / negative output; max L = f·E·cosθ; max R = directional \
         albedo; gain = R − 1 of claimed sets ('-': none claimed); max rel = |GPU − CPU| / (|CPU| + \
         1e-5·E); >bound = beyond 1e-3·|CPU| + 1e-5·E"
    );
    let mut evaluators: Vec<&mut dyn Evaluator> = vec![&mut cpu];
    if let Some(g) = gpu.as_mut() {
        evaluators.push(g);
    }
    let mut report = sweep(&rows, &dirs, &mut evaluators, &opts, |m| {
        print!("{}", format_model(m))
    })?;
    drop(evaluators);
    report.device = ctx.as_ref().map(|c| c.info.summary());
    report.seconds = t0.elapsed().as_secs_f64();
    println!();
    if let Some(p) = &a.json {
        std::fs::write(p, serde_json::to_string_pretty(&report)?)
            .with_context(|| format!("cannot write {}", p.display()))?;
        println!("wrote {}", p.display());
    }
    println!("time: {:.1} s", report.seconds);
    let code = if report.failures.is_empty() {
        println!("PASS: no NaN, Inf or negative value; no claimed energy gain");
        ExitCode::SUCCESS
    } else {
        for f in &report.failures {
            println!("FAIL: {f}");
        }
        ExitCode::from(1)
    };
    drop(gpu);
    if let Some(ctx) = &ctx {
        let v = validation_exit(ctx);
        if v != ExitCode::SUCCESS {
            return Ok(v);
        }
    }
    Ok(code)
}
