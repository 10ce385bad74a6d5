//! `luz stability`: the binary's sweep on the CPU reference and the GPU mirror is clean (no NaN,
//! Inf or negative value, no energy gain of a model that claims conservation, validation silent),
//! and the checker does fail when an evaluator misbehaves.

mod common;

use anyhow::Result;
use luz::brdf::Model;
use luz::stability::{
    self, Batch, CpuEvaluator, Evaluator, Output, SweepOptions, ENERGY_TOLERANCE, MODELS,
};
use serde_json::Value;

use common::{luz, scratch};

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

/// The whole sweep, CPU and GPU, through the binary.
#[test]
fn sweep_is_clean_on_cpu_and_gpu() {
    let dir = scratch("sweep");
    let json = dir.join("stability.json");
    let (code, stdout, stderr) = luz(&["stability", "--json", json.to_str().unwrap()]);
    assert_eq!(code, 0, "stdout:\n{stdout}\nstderr:\n{stderr}");
    assert!(
        stderr.contains("validation: 0 errors"),
        "validation must be on and silent: {stderr}"
    );
    assert!(stdout.contains("PASS"), "{stdout}");
    for m in MODELS {
        assert!(
            stdout.contains(&format!("== {m} ")),
            "table for {m}:\n{stdout}"
        );
    }

    let report: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(report["pass"], Value::Bool(true));
    assert_eq!(report["failures"].as_array().unwrap().len(), 0);
    assert_eq!(report["sides"], serde_json::json!(["cpu", "gpu"]));
    let tolerance = num(&report["sweep"]["energy_tolerance"]);
    assert_eq!(tolerance as f32, ENERGY_TOLERANCE);
    let models = report["models"].as_array().unwrap();
    let names: Vec<&str> = models
        .iter()
        .map(|m| m["model"].as_str().unwrap())
        .collect();
    assert_eq!(names, MODELS.to_vec(), "every model, in order");

    let mut claimed_rows = 0;
    for m in models {
        let rows = m["rows"].as_array().unwrap();
        assert!(!rows.is_empty(), "{}: no rows", m["model"]);
        for row in rows {
            let name = format!("{} {}", row["model"], row["variant"]);
            let sides = row["sides"].as_array().unwrap();
            assert_eq!(sides.len(), 2, "{name}: a CPU and a GPU side");
            for s in sides {
                let side = s["side"].as_str().unwrap();
                for key in ["nan", "inf", "negative"] {
                    assert_eq!(s[key].as_u64(), Some(0), "{name} {side}: {key}: {s}");
                }
                assert!(s["cases"].as_u64().unwrap() > 0, "{name} {side}");
                assert!(
                    num(&s["max_radiance"]).is_finite() && num(&s["max_radiance"]) > 0.0,
                    "{name} {side}: {s}"
                );
                assert!(num(&s["max_albedo"]).is_finite(), "{name} {side}: {s}");
                let claimed = row["claim"] != "no";
                assert_eq!(!s["energy_gain"].is_null(), claimed, "{name} {side}");
                if claimed {
                    let gain = num(&s["energy_gain"]);
                    assert!(
                        (0.0..=tolerance).contains(&gain),
                        "{name} {side}: energy gain {gain} at {}",
                        s["energy_gain_at"]
                    );
                }
            }
            if row["claim"] != "no" {
                claimed_rows += 1;
            }
            let c = &row["comparison"];
            assert_eq!(c["finite_mismatch"].as_u64(), Some(0), "{name}: {c}");
            assert_eq!(c["over_bound"].as_u64(), Some(0), "{name}: {c}");
        }
    }
    // Lambert, and 45 Cook-Torrance and 45 metal-rough term combinations (2 D × 5 G × 5 F, less
    // the 5 that put Beckmann's Smith term on a GGX lobe, which are measured but not claimed).
    assert_eq!(claimed_rows, 91);
}

/// `--cpu-only` needs no device and prints no validation line.
#[test]
fn cpu_only_needs_no_device() {
    let (code, stdout, stderr) = luz(&["stability", "--cpu-only", "--model", "oren_nayar"]);
    assert_eq!(code, 0, "stdout:\n{stdout}\nstderr:\n{stderr}");
    assert!(stdout.contains("== oren_nayar") && !stdout.contains("== lambert"));
    assert!(!stdout.contains(" GPU "), "{stdout}");
    assert!(!stderr.contains("validation:"), "{stderr}");
    let (code, _, stderr) = luz(&["stability", "--cpu-only", "--model", "nope"]);
    assert_eq!(code, 1);
    assert!(
        stderr.contains("luz: error:") && stderr.contains("nope"),
        "{stderr}"
    );
}

/// The CPU reference with planted faults.
struct Planted {
    /// Point-case index whose E = 1e6 radiance becomes NaN.
    nan_at: Option<usize>,
    /// Point-case index whose f becomes +Inf.
    inf_at: Option<usize>,
    /// Point-case index whose f becomes negative.
    negative_at: Option<usize>,
    /// Factor on f at the albedo quadrature points (an energy gain of `gain − 1`).
    gain: f32,
}

impl Evaluator for Planted {
    fn name(&self) -> &str {
        "planted"
    }

    fn evaluate(&mut self, batch: &Batch<'_>) -> Result<Vec<Output>> {
        let mut out = CpuEvaluator.evaluate(batch)?;
        if batch.with_radiance {
            if let Some(i) = self.nan_at {
                out[i].radiance[2].y = f32::NAN;
            }
            if let Some(i) = self.inf_at {
                out[i].f.x = f32::INFINITY;
            }
            if let Some(i) = self.negative_at {
                out[i].f.z = -1e-3;
            }
        } else {
            for o in &mut out {
                o.f *= self.gain;
            }
        }
        Ok(out)
    }
}

fn small_sweep() -> Vec<stability::Row> {
    stability::rows()
        .into_iter()
        .filter(|r| r.model == "lambert" || r.variant == "ggx smith_ggx_correlated schlick")
        .collect()
}

fn sweep_with(ev: &mut dyn Evaluator) -> stability::Report {
    let rows = small_sweep();
    assert_eq!(rows.len(), 3, "lambert, cook_torrance and metal_rough rows");
    let opts = SweepOptions {
        samples: 256,
        ..Default::default()
    };
    stability::sweep(&rows, &stability::directions(), &mut [ev], &opts, |_| {}).unwrap()
}

#[test]
fn checker_passes_the_reference_and_catches_planted_faults() {
    // The unmodified reference passes, so every failure below is the planted one's.
    let clean = sweep_with(&mut CpuEvaluator);
    assert!(clean.pass, "{:#?}", clean.failures);

    let mut planted = Planted {
        nan_at: Some(17),
        inf_at: Some(101),
        negative_at: Some(5),
        gain: 1.0,
    };
    let report = sweep_with(&mut planted);
    assert!(!report.pass);
    let lambert = &report.models[0].rows[0].sides[0];
    assert_eq!(
        (lambert.nan, lambert.inf, lambert.negative),
        (1, 1, 1),
        "{lambert:#?}"
    );
    assert!(
        report
            .failures
            .iter()
            .any(|f| f.contains("lambert") && f.contains("1 NaN, 1 Inf, 1 negative")),
        "{:#?}",
        report.failures
    );
    // A NaN only in the radiance at E = 1e6 is found too, and described with its inputs.
    assert!(lambert.first_problems[0].contains("n="), "{lambert:#?}");

    // A 1 % energy gain: caught for the claiming models (Lambert, Cook-Torrance, metal-rough at
    // metallic 1), through the refinement stage.
    let mut planted = Planted {
        nan_at: None,
        inf_at: None,
        negative_at: None,
        gain: 1.01,
    };
    let report = sweep_with(&mut planted);
    assert!(!report.pass);
    for model in ["lambert", "cook_torrance", "metal_rough"] {
        assert!(
            report
                .failures
                .iter()
                .any(|f| f.starts_with(model) && f.contains("gains energy")),
            "{model}: {:#?}",
            report.failures
        );
    }
    let gain = report.models[0].rows[0].sides[0].energy_gain.unwrap();
    assert!((gain - 0.01).abs() < 1e-4, "lambert gain {gain}");

    // Below the tolerance it passes.
    let mut planted = Planted {
        nan_at: None,
        inf_at: None,
        negative_at: None,
        gain: 1.0 + ENERGY_TOLERANCE / 4.0,
    };
    let report = sweep_with(&mut planted);
    assert!(report.pass, "{:#?}", report.failures);
}

/// Measures the albedo quadrature error behind `ENERGY_TOLERANCE` and `REFINE_MARGIN` (see the
/// module docs of `luz::stability`): every claimed Cook-Torrance and metal-rough set with F = 1
/// against 2¹⁸ points. About 20 s on 2 cores: `cargo test --release --test stability -- --ignored`.
#[test]
#[ignore]
fn albedo_quadrature_error() {
    use luz::brdf::directional_albedo;
    use rayon::prelude::*;
    use stability::{albedo_samples, ALBEDO_COS_L, DEFAULT_SAMPLES, REFINE_FACTOR, REFINE_MARGIN};
    let sets: Vec<(String, Model)> = stability::rows()
        .into_iter()
        .filter(|r| r.variant.ends_with(" schlick"))
        .flat_map(|r| {
            let name = format!("{} {}", r.model, r.variant);
            r.sets
                .into_iter()
                .filter(|s| s.conserving && s.albedo && !s.label.contains("gold"))
                .map(move |s| (format!("{name} [{}]", s.label), s.model))
        })
        .collect();
    assert_eq!(sets.len(), 2 * 8 * 7, "(CT + MR) × (D, G) × roughness");
    #[derive(Debug, Clone)]
    #[allow(dead_code)] // `set` and `cos_l` are read by the Debug print only.
    struct Measured {
        set: String,
        cos_l: f32,
        reference: f32,
        stage1: f32,
        stage2: f32,
    }
    let results: Vec<Measured> = sets
        .par_iter()
        .flat_map(|(name, model)| {
            ALBEDO_COS_L.par_iter().map(move |&c| {
                let reference = directional_albedo(model, c, 1 << 18).max_element();
                let n = albedo_samples(c, DEFAULT_SAMPLES);
                Measured {
                    set: name.clone(),
                    cos_l: c,
                    reference,
                    stage1: directional_albedo(model, c, n).max_element() - reference,
                    stage2: directional_albedo(model, c, n * REFINE_FACTOR).max_element()
                        - reference,
                }
            })
        })
        .collect();
    let worst = |f: &dyn Fn(&Measured) -> f32, near: bool| {
        results
            .iter()
            .filter(|r| !near || r.reference > 0.995)
            .max_by(|a, b| f(a).total_cmp(&f(b)))
            .unwrap()
            .clone()
    };
    let s1 = worst(&|r| r.stage1.abs(), false);
    let s1_near = worst(&|r| r.stage1.abs(), true);
    let s1_over = worst(&|r| r.stage1, false);
    let s2 = worst(&|r| r.stage2.abs(), false);
    let s2_over = worst(&|r| r.stage2, false);
    let reference = worst(&|r| r.reference, false);
    eprintln!("stage 1: max |error| {:.2e} at {s1:?}", s1.stage1);
    eprintln!(
        "stage 1, R > 0.995: max |error| {:.2e} at {s1_near:?}",
        s1_near.stage1
    );
    eprintln!(
        "stage 1: max overestimate {:.2e} at {s1_over:?}",
        s1_over.stage1
    );
    eprintln!("stage 2: max |error| {:.2e} at {s2:?}", s2.stage2);
    eprintln!(
        "stage 2: max overestimate {:.2e} at {s2_over:?}",
        s2_over.stage2
    );
    eprintln!(
        "largest reference albedo {:.6} at {reference:?}",
        reference.reference
    );
    assert!(
        s1_near.stage1.abs() < REFINE_MARGIN,
        "stage-1 error near 1 vs the margin"
    );
    assert!(
        s2.stage2.abs() < ENERGY_TOLERANCE / 2.0,
        "stage-2 error vs the tolerance"
    );
    assert!(
        reference.reference < 1.0 + ENERGY_TOLERANCE / 4.0,
        "converged albedo"
    );
}
