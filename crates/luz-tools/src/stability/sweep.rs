//! One row of the sweep in named steps: cases, evaluation, statistics, comparison, albedo.

use std::cell::{Cell, RefCell};

use anyhow::{Context as _, Result};
use glam::Vec3;
use rayon::prelude::*;

use crate::brdf::{self, Model};

use super::{
    Batch, Case, Comparison, Dir, Evaluator, Output, ParamSet, Row, RowReport, SetAlbedo,
    SideStats, SweepOptions, ALBEDO_COS_L, COMPARE_ABS, COMPARE_REL, GRAZING_SAMPLE_FACTOR,
    INTENSITIES, REFINE_FACTOR, REFINE_MARGIN,
};

/// An albedo integral to compute: set, light direction, its quadrature points.
struct AlbedoJob {
    set: usize,
    cos_l: f32,
    l: Vec3,
    lobes: Vec<brdf::Lobe>,
    samples: u32,
    start: usize,
    len: usize,
}

/// Quadrature points for the albedo at `cos θ_l`: `base`, and four times as many below
/// cos θ_l = 0.1, where half the specular samples reflect below the horizon and the
/// low-discrepancy error grows (measured: ≈ 1e-3 at 4096 points for cos θ_l = 1e-3).
pub fn albedo_samples(cos_l: f32, base: u32) -> u32 {
    if cos_l < 0.1 {
        base.saturating_mul(GRAZING_SAMPLE_FACTOR)
    } else {
        base
    }
}

/// The light direction of [`brdf::directional_albedo`] at `cos θ_l`.
pub fn albedo_light(cos_l: f32) -> Vec3 {
    let c = cos_l.clamp(0.0, 1.0);
    brdf::safe_normalize(Vec3::new((1.0 - c * c).max(0.0).sqrt(), 0.0, c))
}

/// The outgoing directions [`brdf::integrate_hemisphere`] evaluates f at, in call order.
fn quadrature_points(l: Vec3, lobes: &[brdf::Lobe], samples: u32) -> Vec<Vec3> {
    let points = RefCell::new(Vec::new());
    brdf::integrate_hemisphere(
        |v| {
            points.borrow_mut().push(v);
            Vec3::ZERO
        },
        l,
        lobes,
        samples,
    );
    points.into_inner()
}

/// [`brdf::integrate_hemisphere`] with f taken from `values`, in call order.
fn replay_albedo(l: Vec3, lobes: &[brdf::Lobe], samples: u32, values: &[Output]) -> Vec3 {
    let next = Cell::new(0usize);
    let r = brdf::integrate_hemisphere(
        |_| {
            let i = next.get();
            next.set(i + 1);
            values.get(i).map(|o| o.f).unwrap_or(Vec3::NAN)
        },
        l,
        lobes,
        samples,
    );
    debug_assert_eq!(next.get(), values.len());
    r
}

fn max_channel(v: Vec3) -> f32 {
    // NaN-propagating: a NaN channel makes the result NaN.
    if v.is_nan() {
        f32::NAN
    } else {
        v.max_element()
    }
}

fn fmt_vec(v: Vec3) -> String {
    format!("({:e}, {:e}, {:e})", v.x, v.y, v.z)
}

fn describe(row: &Row, set: &ParamSet, d: &Dir, side: &str, what: &str, o: &Output) -> String {
    format!(
        "{} {}: {side}: {what} at set [{}], {}: n={} l={} v={} x={} y={}; f={} L(E=1,1e3,1e6)={} {} {}",
        row.model,
        row.variant,
        set.label,
        d.label,
        fmt_vec(d.n),
        fmt_vec(d.l),
        fmt_vec(d.v),
        fmt_vec(d.x),
        fmt_vec(d.y),
        fmt_vec(o.f),
        fmt_vec(o.radiance[0]),
        fmt_vec(o.radiance[1]),
        fmt_vec(o.radiance[2]),
    )
}

/// Sweeps one row: every parameter set over `dirs` and the albedo integrals, with every evaluator
/// (the first is the reference).
pub(super) fn sweep_row(
    row: &Row,
    dirs: &[Dir],
    evaluators: &mut [&mut dyn Evaluator],
    opts: &SweepOptions,
) -> Result<RowReport> {
    let models: Vec<Model> = row.sets.iter().map(|s| s.model).collect();
    let cases = point_cases(row, dirs);
    let (jobs, albedo_cases) = albedo_jobs(row, opts);

    let mut sides = Vec::new();
    let mut point_outputs: Vec<Vec<Output>> = Vec::new();
    let mut albedos: Vec<Vec<Vec3>> = Vec::new();
    for ev in evaluators.iter_mut() {
        let (outs, fs) = evaluate(&mut **ev, row, &models, &cases, &albedo_cases)?;
        let mut s = SideStats {
            side: ev.name().to_string(),
            cases: cases.len() + albedo_cases.len(),
            energy_gain: row.sets.iter().any(|s| s.conserving).then_some(0.0),
            ..Default::default()
        };
        point_stats(&mut s, row, dirs, ev.name(), &outs);
        albedo_point_stats(&mut s, row, &jobs, &albedo_cases, ev.name(), &fs);
        let side_albedo = replay_albedos(&jobs, &fs);
        sides.push(s);
        point_outputs.push(outs);
        albedos.push(side_albedo);
    }

    let (refined, final_albedos) = refine(row, &jobs, &albedos, opts);
    for (s, side_albedo) in sides.iter_mut().zip(&final_albedos) {
        albedo_stats(s, row, &jobs, side_albedo, &refined);
    }

    let comparison = compare(row, dirs, evaluators, &point_outputs, &jobs, &albedos);
    let set_albedo = set_albedos(row, &jobs, &final_albedos);

    Ok(RowReport {
        model: row.model.to_string(),
        variant: row.variant.clone(),
        claim: row.claim.to_string(),
        sets: row.sets.len(),
        points: cases.len(),
        albedo_samples: albedo_cases.len(),
        refined: refined.len(),
        sides,
        comparison,
        set_albedo,
    })
}

/// The point cases: every parameter set at every direction case, set-major.
fn point_cases(row: &Row, dirs: &[Dir]) -> Vec<Case> {
    let mut cases = Vec::with_capacity(row.sets.len() * dirs.len());
    for set in 0..row.sets.len() {
        for d in dirs {
            cases.push(Case {
                set: set as u32,
                n: d.n,
                l: d.l,
                v: d.v,
                x: d.x,
                y: d.y,
            });
        }
    }
    cases
}

/// The albedo integrals (conserving or reported sets × `ALBEDO_COS_L`) and the cases holding their
/// quadrature points, each job's at `start..start + len`.
fn albedo_jobs(row: &Row, opts: &SweepOptions) -> (Vec<AlbedoJob>, Vec<Case>) {
    // Albedo integrals: (set, light angle), their quadrature points generated in parallel.
    let specs: Vec<(usize, f32)> = row
        .sets
        .iter()
        .enumerate()
        .filter(|(_, set)| set.albedo)
        .flat_map(|(si, _)| ALBEDO_COS_L.iter().map(move |&c| (si, c)))
        .collect();
    let generated: Vec<(AlbedoJob, Vec<Vec3>)> = specs
        .par_iter()
        .map(|&(si, cos_l)| {
            let lobes = brdf::sampling_lobes(&row.sets[si].model);
            let l = albedo_light(cos_l);
            let samples = albedo_samples(cos_l, opts.samples);
            let points = quadrature_points(l, &lobes, samples);
            let job = AlbedoJob {
                set: si,
                cos_l,
                l,
                lobes,
                samples,
                start: 0,
                len: points.len(),
            };
            (job, points)
        })
        .collect();
    let mut jobs = Vec::with_capacity(generated.len());
    let mut albedo_cases = Vec::new();
    for (mut job, points) in generated {
        job.start = albedo_cases.len();
        albedo_cases.extend(points.into_iter().map(|v| Case {
            set: job.set as u32,
            n: Vec3::Z,
            l: job.l,
            v,
            x: Vec3::X,
            y: Vec3::Y,
        }));
        jobs.push(job);
    }
    (jobs, albedo_cases)
}

/// One evaluator's outputs for the point cases (with radiances) and the albedo cases (f only).
fn evaluate(
    ev: &mut dyn Evaluator,
    row: &Row,
    models: &[Model],
    cases: &[Case],
    albedo_cases: &[Case],
) -> Result<(Vec<Output>, Vec<Output>)> {
    let batch = |cases, with_radiance| Batch {
        sets: models,
        cases,
        intensities: INTENSITIES,
        with_radiance,
    };
    let outs = ev
        .evaluate(&batch(cases, true))
        .with_context(|| format!("{} {}: {} evaluation", row.model, row.variant, ev.name()))?;
    let fs = ev
        .evaluate(&batch(albedo_cases, false))
        .with_context(|| format!("{} {}: {} albedo", row.model, row.variant, ev.name()))?;
    anyhow::ensure!(
        outs.len() == cases.len() && fs.len() == albedo_cases.len(),
        "{}: returned {} + {} values for {} + {} cases",
        ev.name(),
        outs.len(),
        fs.len(),
        cases.len(),
        albedo_cases.len()
    );
    Ok((outs, fs))
}

impl SideStats {
    /// Counts `values` (one output's) as NaN, Inf and negative where any channel is; `describe`
    /// says where for each kind found, kept for the first few problems.
    fn count_problems(&mut self, values: &[Vec3], describe: impl Fn(&str) -> String) {
        let nan = values.iter().any(|v| v.is_nan());
        let inf = values
            .iter()
            .any(|v| v.to_array().iter().any(|c| c.is_infinite()));
        let neg = values.iter().any(|v| v.to_array().iter().any(|&c| c < 0.0));
        for (flag, count, what) in [
            (nan, &mut self.nan, "NaN"),
            (inf, &mut self.inf, "Inf"),
            (neg, &mut self.negative, "negative"),
        ] {
            if flag {
                *count += 1;
                if self.first_problems.len() < 8 {
                    self.first_problems.push(describe(what));
                }
            }
        }
    }
}

/// Counts NaN, Inf and negative point outputs (describing the first few) and records the largest
/// f and radiance.
fn point_stats(s: &mut SideStats, row: &Row, dirs: &[Dir], side: &str, outs: &[Output]) {
    let nd = dirs.len();
    for (i, o) in outs.iter().enumerate() {
        let (set, d) = (&row.sets[i / nd], &dirs[i % nd]);
        let values = [o.f, o.radiance[0], o.radiance[1], o.radiance[2]];
        s.count_problems(&values, |what| describe(row, set, d, side, what, o));
        for c in o.f.to_array() {
            if c.is_finite() && c > s.max_f {
                s.max_f = c;
            }
        }
        for (k, r) in o.radiance.iter().enumerate() {
            for c in r.to_array() {
                if c.is_finite() && c > s.max_radiance {
                    s.max_radiance = c;
                    s.max_radiance_at =
                        format!("[{}], {}, E={:e}", set.label, d.label, INTENSITIES[k]);
                }
            }
        }
    }
}

/// Counts NaN, Inf and negative values at the albedo quadrature points (describing the first few).
fn albedo_point_stats(
    s: &mut SideStats,
    row: &Row,
    jobs: &[AlbedoJob],
    albedo_cases: &[Case],
    side: &str,
    fs: &[Output],
) {
    for job in jobs {
        for (k, o) in fs[job.start..job.start + job.len].iter().enumerate() {
            s.count_problems(&[o.f], |what| {
                let c = &albedo_cases[job.start + k];
                format!(
                    "{} {}: {}: {what} at set [{}], albedo point: n=+z l={} v={}; f={}",
                    row.model,
                    row.variant,
                    side,
                    row.sets[job.set].label,
                    fmt_vec(c.l),
                    fmt_vec(c.v),
                    fmt_vec(o.f)
                )
            });
        }
    }
}

/// Each job's albedo from one side's values at its quadrature points.
fn replay_albedos(jobs: &[AlbedoJob], fs: &[Output]) -> Vec<Vec3> {
    jobs.par_iter()
        .map(|job| {
            replay_albedo(
                job.l,
                &job.lobes,
                job.samples,
                &fs[job.start..job.start + job.len],
            )
        })
        .collect()
}

/// Stage 2: claimed estimates near or above 1 are re-integrated on the CPU reference with
/// REFINE_FACTOR× the points; each side's refined value is that plus its own difference from the
/// CPU reference on the stage-1 points (a control variate: the quadrature error cancels in the
/// difference, which only holds the BRDF values' disagreement). Returns the refined jobs as (job,
/// fine CPU albedo, stage-1 CPU albedo) and every side's albedos with the refinement applied.
#[allow(clippy::type_complexity)]
fn refine(
    row: &Row,
    jobs: &[AlbedoJob],
    albedos: &[Vec<Vec3>],
    opts: &SweepOptions,
) -> (Vec<(usize, Vec3, Vec3)>, Vec<Vec<Vec3>>) {
    let threshold = 1.0 + opts.energy_tolerance - REFINE_MARGIN;
    let refine: Vec<usize> = (0..jobs.len())
        .filter(|&j| {
            row.sets[jobs[j].set].conserving
                && albedos.iter().any(|a| {
                    let m = max_channel(a[j]);
                    m.is_nan() || m > threshold
                })
        })
        .collect();
    let refined: Vec<(usize, Vec3, Vec3)> = refine
        .par_iter()
        .map(|&j| {
            let job = &jobs[j];
            let model = &row.sets[job.set].model;
            let fine = brdf::directional_albedo_dir(model, job.l, job.samples * REFINE_FACTOR);
            let base = brdf::directional_albedo_dir(model, job.l, job.samples);
            (j, fine, base)
        })
        .collect();
    let mut final_albedos = albedos.to_vec();
    for &(j, fine, base) in &refined {
        for a in final_albedos.iter_mut() {
            a[j] = fine + (a[j] - base);
        }
    }
    (refined, final_albedos)
}

/// One side's largest albedo and, over the conserving sets, its largest R as the energy gain.
fn albedo_stats(
    s: &mut SideStats,
    row: &Row,
    jobs: &[AlbedoJob],
    side_albedo: &[Vec3],
    refined: &[(usize, Vec3, Vec3)],
) {
    // Largest R of a conserving set (NaN sticks).
    let mut conserving_r: Option<f32> = None;
    for (j, (job, &r)) in jobs.iter().zip(side_albedo).enumerate() {
        let m = max_channel(r);
        let set = &row.sets[job.set];
        let how = if refined.iter().any(|x| x.0 == j) {
            format!(
                "{} points, refined at {}",
                job.samples,
                job.samples * REFINE_FACTOR
            )
        } else {
            format!("{} points", job.samples)
        };
        let at = format!(
            "[{}] cosθl={:e}: R={} ({how})",
            set.label,
            job.cos_l,
            fmt_vec(r)
        );
        if s.max_albedo_at.is_empty() || m > s.max_albedo || m.is_nan() {
            s.max_albedo = m;
            s.max_albedo_at = at.clone();
        }
        if set.conserving {
            let worse = match conserving_r {
                None => true,
                Some(c) => !c.is_nan() && (m > c || m.is_nan()),
            };
            if worse {
                conserving_r = Some(m);
                s.energy_gain_at = at;
            }
        }
    }
    if let Some(r) = conserving_r {
        s.energy_gain = Some(if r.is_nan() {
            f32::NAN
        } else {
            (r - 1.0).max(0.0)
        });
    }
}

/// Every further side against the first (None with one evaluator).
fn compare(
    row: &Row,
    dirs: &[Dir],
    evaluators: &[&mut dyn Evaluator],
    point_outputs: &[Vec<Output>],
    jobs: &[AlbedoJob],
    albedos: &[Vec<Vec3>],
) -> Option<Comparison> {
    (evaluators.len() > 1).then(|| {
        let mut c = Comparison::default();
        for other in 1..evaluators.len() {
            let name = evaluators[other].name();
            compare_points(
                &mut c,
                row,
                dirs,
                &point_outputs[0],
                &point_outputs[other],
                name,
            );
            compare_albedos(&mut c, row, jobs, &albedos[0], &albedos[other], name);
        }
        c
    })
}

/// f and the radiances of side `name` (`got`) against the reference's.
fn compare_points(
    c: &mut Comparison,
    row: &Row,
    dirs: &[Dir],
    reference: &[Output],
    got: &[Output],
    name: &str,
) {
    let nd = dirs.len();
    for (i, (a, b)) in reference.iter().zip(got).enumerate() {
        let pairs = [
            (a.f, b.f, 1.0, "f"),
            (a.radiance[0], b.radiance[0], INTENSITIES[0], "L(E=1)"),
            (a.radiance[1], b.radiance[1], INTENSITIES[1], "L(E=1e3)"),
            (a.radiance[2], b.radiance[2], INTENSITIES[2], "L(E=1e6)"),
        ];
        for (ref_v, got_v, e, what) in pairs {
            for ch in 0..3 {
                let (r, g) = (ref_v[ch], got_v[ch]);
                c.add(r, g, e, || {
                    let (set, d) = (&row.sets[i / nd], &dirs[i % nd]);
                    format!(
                        "{what}[{ch}] at [{}], {}: cpu {r:e}, {} {g:e}",
                        set.label, d.label, name
                    )
                });
            }
        }
    }
}

/// The albedos of side `name` (`got`) against the reference's.
fn compare_albedos(
    c: &mut Comparison,
    row: &Row,
    jobs: &[AlbedoJob],
    reference: &[Vec3],
    got: &[Vec3],
    name: &str,
) {
    for (j, job) in jobs.iter().enumerate() {
        let (a, b) = (reference[j], got[j]);
        for ch in 0..3 {
            let (r, g) = (a[ch], b[ch]);
            c.add(r, g, 1.0, || {
                format!(
                    "albedo[{ch}] at [{}] cosθl={:e}: cpu {r:e}, {} {g:e}",
                    row.sets[job.set].label, job.cos_l, name
                )
            });
        }
    }
}

impl Comparison {
    /// Counts one channel of a side, `g`, against the reference's `r` at light intensity `e` (1
    /// for f and albedos); `at` says where, kept when the relative difference is the largest yet.
    fn add(&mut self, r: f32, g: f32, e: f32, at: impl FnOnce() -> String) {
        if r.is_finite() != g.is_finite() {
            self.finite_mismatch += 1;
            return;
        }
        if !r.is_finite() {
            return;
        }
        let diff = (g - r).abs();
        let rel = diff / (r.abs() + COMPARE_ABS * e);
        if diff > COMPARE_REL * r.abs() + COMPARE_ABS * e {
            self.over_bound += 1;
        }
        if rel > self.max_rel {
            self.max_rel = rel;
            self.max_rel_at = at();
        }
    }
}

/// Per parameter set, its largest albedo over the light angles (the reference side decides which).
fn set_albedos(row: &Row, jobs: &[AlbedoJob], final_albedos: &[Vec<Vec3>]) -> Vec<SetAlbedo> {
    let mut set_albedo: Vec<SetAlbedo> = Vec::new();
    for (j, job) in jobs.iter().enumerate() {
        let per_side: Vec<f32> = final_albedos.iter().map(|a| max_channel(a[j])).collect();
        let set = &row.sets[job.set];
        match set_albedo.iter_mut().find(|s| s.set == set.label) {
            Some(s) => {
                if per_side[0] > s.max_albedo[0] {
                    s.max_albedo = per_side;
                    s.cos_theta_l = job.cos_l;
                }
            }
            None => set_albedo.push(SetAlbedo {
                set: set.label.clone(),
                conserving: set.conserving,
                max_albedo: per_side,
                cos_theta_l: job.cos_l,
            }),
        }
    }
    set_albedo
}
