//! Golden-image checks of scenes (`luz golden`, and luz's own golden tests): render each scene
//! headless, compare its PNG encoding with `<goldens>/<name>.png` (or its linear radiance with
//! `<name>.exr`) under the golden-image
//! tolerances (or the scene's own, from a sidecar `<name>.golden.json`), or bless (write) the
//! goldens.
//!
//! A scene that fails to load or render, a missing golden, a golden of another size: that case
//! fails with the reason, and the run goes on with the others. Only bad input for the whole run
//! (scenes that do not exist, an unreadable goldens folder) is an error ([`GoldenError`]).
//!
//! The library returns data: [`Case`]s with their figures and images; [`report`] writes the HTML
//! page, the JUnit XML and the Markdown summary; the binary prints.

mod case;
pub mod report;

pub use crate::diff::{parse_sidecar, read_sidecar, OverrideError, ToleranceOverrides};
pub use case::{read_mask, CaseFile, Masking, Region, RegionArea, CASE_FIELDS};

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use crate::diff::{DiffReport, FlipMap, Tolerance};
use crate::headless::{Headless, RenderOptions};
use crate::imageio::{self, FileFormat, LoadedImage, Provenance};
use crate::progress::{ProgressSink, Reporting};
use crate::vk::Context;

/// The scene file extensions `luz golden` reads: JSON scenes, and OBJ and glTF models (a model
/// is a scene with its own cameras and lights or the default rig, `scene::model`).
pub const SCENE_EXTENSIONS: &[&str] = &["json", "obj", "gltf", "glb"];
/// Held while a case uses the GPU ([`run_case`]).
static GPU_QUEUE: Mutex<()> = Mutex::new(());

/// A sidecar's suffix: `<name>.golden.json` holds that scene's tolerances.
pub const SIDECAR_SUFFIX: &str = ".golden.json";

/// How to run.
#[derive(Debug, Clone)]
pub struct GoldenOptions {
    /// The folder of `<name>.png` goldens (and `<name>.golden.json` sidecars).
    pub goldens: PathBuf,
    /// Write (or replace) the goldens instead of checking them.
    pub bless: bool,
    /// Scenes rendered at once (each on its own renderer; one device).
    pub jobs: usize,
    /// How to render (IBL sizes and cache).
    pub render: RenderOptions,
    /// Tolerances of scenes without a sidecar.
    pub tolerance: Tolerance,
    /// Told after each scene.
    pub progress: Option<ProgressSink>,
    /// The goldens' format: `<name>.png` (the 8-bit display encoding, exposure and tone map
    /// applied) or `<name>.exr` (the linear float radiance; the tolerances' 8-bit steps become
    /// steps of 1/255 in radiance).
    pub format: FileFormat,
}

impl GoldenOptions {
    /// Checking (not blessing) `goldens` with one job, the golden-image tolerances and
    /// `render`'s settings.
    pub fn new(goldens: impl Into<PathBuf>, render: RenderOptions) -> Self {
        Self {
            goldens: goldens.into(),
            bless: false,
            jobs: 1,
            render,
            tolerance: Tolerance::golden(),
            progress: None,
            format: FileFormat::Png,
        }
    }
}

/// Bad input for the whole run: every message names the path.
#[derive(Debug, thiserror::Error)]
pub enum GoldenError {
    #[error("{}: no such scene file or folder", .0.display())]
    NoSuchScene(PathBuf),
    #[error("cannot read the scene folder {}: {reason}", .path.display())]
    SceneFolder { path: PathBuf, reason: String },
    #[error("{}: no scene files in it (luz golden reads {})", .0.display(), scene_kinds())]
    EmptyFolder(PathBuf),
    #[error("no scenes given")]
    NoScenes,
    #[error("goldens folder {}: no such folder (run with --bless to create it)", .0.display())]
    NoGoldens(PathBuf),
    #[error("goldens folder {}: {reason}", .path.display())]
    Goldens { path: PathBuf, reason: String },
    #[error("cannot write the report to {}: {reason}", .path.display())]
    Report { path: PathBuf, reason: String },
}

fn scene_kinds() -> String {
    SCENE_EXTENSIONS
        .iter()
        .map(|e| format!(".{e}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The scene files named by `inputs`: files as given, folders' scene files (sorted, not
/// recursive; `*.golden.json` sidecars left out).
pub fn collect_scenes(inputs: &[PathBuf]) -> Result<Vec<PathBuf>, GoldenError> {
    if inputs.is_empty() {
        return Err(GoldenError::NoScenes);
    }
    let mut out = Vec::new();
    for input in inputs {
        let meta = std::fs::metadata(input).map_err(|e| match e.kind() {
            std::io::ErrorKind::NotFound => GoldenError::NoSuchScene(input.clone()),
            _ => GoldenError::SceneFolder {
                path: input.clone(),
                reason: e.to_string(),
            },
        })?;
        if !meta.is_dir() {
            out.push(input.clone());
            continue;
        }
        let folder_err = |e: std::io::Error| GoldenError::SceneFolder {
            path: input.clone(),
            reason: e.to_string(),
        };
        let mut found = Vec::new();
        for entry in std::fs::read_dir(input).map_err(folder_err)? {
            let path = entry.map_err(folder_err)?.path();
            if path.is_dir() {
                continue;
            }
            // Sidecars are cases when they name their scene (a folder of goldens runs as it
            // is); otherwise they only hold tolerances.
            if is_sidecar(&path) {
                if case::names_a_scene(&path) {
                    found.push(path);
                }
                continue;
            }
            let ext = extension(&path);
            if SCENE_EXTENSIONS.contains(&ext.as_str()) {
                found.push(path);
            }
        }
        if found.is_empty() {
            return Err(GoldenError::EmptyFolder(input.clone()));
        }
        found.sort();
        out.extend(found);
    }
    Ok(out)
}

/// Checks the goldens folder before any rendering: it must be a readable folder; when blessing
/// it is created if missing and must be writable.
pub fn check_goldens_dir(dir: &Path, bless: bool) -> Result<(), GoldenError> {
    let err = |reason: String| GoldenError::Goldens {
        path: dir.to_path_buf(),
        reason,
    };
    match std::fs::metadata(dir) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            if !bless {
                return Err(GoldenError::NoGoldens(dir.to_path_buf()));
            }
            std::fs::create_dir_all(dir).map_err(|e| err(format!("cannot create it: {e}")))?;
        }
        Err(e) => return Err(err(e.to_string())),
        Ok(m) if !m.is_dir() => return Err(err("not a folder".into())),
        Ok(_) => {}
    }
    std::fs::read_dir(dir).map_err(|e| err(format!("cannot read it: {e}")))?;
    if bless {
        let probe = dir.join(format!(".luz-write-probe-{}", std::process::id()));
        std::fs::write(&probe, b"").map_err(|e| err(format!("cannot write in it: {e}")))?;
        let _ = std::fs::remove_file(probe);
    }
    Ok(())
}

fn extension(path: &Path) -> String {
    crate::files::lowercase_extension(path).unwrap_or_default()
}

fn is_sidecar(path: &Path) -> bool {
    path.file_name()
        .and_then(|n| n.to_str())
        .is_some_and(|n| n.to_ascii_lowercase().ends_with(SIDECAR_SUFFIX))
}

/// A scene's case name: its file name without the extension (`.golden.json` for a case file).
pub fn case_name(scene: &Path) -> String {
    if is_sidecar(scene) {
        let n = scene.file_name().unwrap_or_default().to_string_lossy();
        return n[..n.len() - SIDECAR_SUFFIX.len()].to_string();
    }
    scene
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| scene.display().to_string())
}

/// What happened to one scene.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// Within the tolerances.
    Pass,
    /// Beyond a tolerance, or the case could not be checked (`Case::failures` says why).
    Fail,
    /// The golden was written or left as it was.
    Blessed(BlessChange),
}

/// Writes `path` through `write` on a temporary file beside it (same folder, same extension),
/// flushed to disk and renamed over `path`: a run killed or failing mid-write leaves the old
/// golden whole (a rename is atomic), never a truncated one. The temporary file is removed when
/// the write fails.
pub fn replace_atomically(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), String>,
) -> Result<(), String> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.bless-{}.{ext}", std::process::id()));
    let result = write(&tmp).and_then(|()| {
        let synced = std::fs::File::open(&tmp).and_then(|f| f.sync_all());
        synced
            .and_then(|()| std::fs::rename(&tmp, path))
            .map_err(|e| format!("cannot replace {}: {e}", path.display()))
    });
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
        return result;
    }
    let dir = path.parent().unwrap_or(Path::new("."));
    // The rename itself reaches the disk with its folder (best effort).
    if let Ok(d) = std::fs::File::open(dir) {
        let _ = d.sync_all();
    }
    // Temporary files of runs killed mid-write are stale now.
    let stale = format!(".{name}.bless-");
    for entry in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        if entry.file_name().to_string_lossy().starts_with(&stale) {
            let _ = std::fs::remove_file(entry.path());
        }
    }
    result
}

/// What `--bless` did to a golden.
#[derive(Debug, Clone, PartialEq)]
pub enum BlessChange {
    /// There was none; it was written.
    New,
    /// The rendered pixels equal the golden's: the file was left alone.
    Unchanged,
    /// The pixels changed; the golden was replaced. The report compares old with new.
    Changed(Box<DiffReport>),
    /// The size changed; the golden was replaced.
    Resized { from: (u32, u32), to: (u32, u32) },
    /// The old golden could not be read; it was replaced.
    Replaced { reason: String },
}

/// The images of one case, for the report.
#[derive(Debug, Clone)]
pub struct CaseImages {
    /// The golden as loaded (absent when missing or unreadable).
    pub expected: Option<LoadedImage>,
    /// The rendered frame, exactly as its PNG (or EXR) holds it.
    pub actual: LoadedImage,
    /// The FLIP error map (when both sides have one size).
    pub flip: Option<FlipMap>,
}

/// One scene's result.
#[derive(Debug, Clone)]
pub struct Case {
    /// The case's place in the whole run (all shards): its index in the scene list.
    pub order: usize,
    pub name: String,
    pub scene: PathBuf,
    pub golden: PathBuf,
    pub tolerance: Tolerance,
    /// Where the tolerances come from: `golden-image defaults` or the sidecar's path.
    pub tolerance_source: String,
    pub verdict: Verdict,
    /// Why it failed: each violated tolerance, or the reason it could not be checked.
    pub failures: Vec<String>,
    /// The comparison's figures (absent when there was nothing to compare).
    pub report: Option<DiffReport>,
    pub images: Option<CaseImages>,
    /// Wall-clock milliseconds of load, render and comparison.
    pub millis: f64,
    /// Where the golden came from, as its file records it (absent without a readable golden).
    pub expected_provenance: Option<Provenance>,
    /// Where the actual image came from (this run's device, the scene and its hash).
    pub actual_provenance: Option<Provenance>,
    /// The case file's regions, each checked with its own tolerances.
    pub regions: Vec<RegionOutcome>,
    /// What the check left out (a mask, forgiven anti-aliasing), for the report's hatching.
    pub ignored: Option<Ignored>,
}

/// One region's check.
#[derive(Debug, Clone)]
pub struct RegionOutcome {
    pub name: String,
    /// Pixels of the region that were compared (not masked, not in an earlier region).
    pub pixels: u64,
    pub tolerance: Tolerance,
    pub report: DiffReport,
    /// Each violated tolerance (empty: the region passes).
    pub failures: Vec<String>,
}

/// The pixels a comparison left out.
#[derive(Debug, Clone)]
pub struct Ignored {
    pub width: u32,
    pub height: u32,
    /// White in the case's mask.
    pub masked: Vec<bool>,
    /// Differences forgiven as anti-aliasing (outside the mask).
    pub antialiased: Vec<bool>,
}

impl Ignored {
    pub fn masked_pixels(&self) -> u64 {
        self.masked.iter().filter(|&&x| x).count() as u64
    }
    pub fn antialiased_pixels(&self) -> u64 {
        self.antialiased.iter().filter(|&&x| x).count() as u64
    }
}

impl Case {
    /// The provenance entries that differ between the golden and this run (another driver
    /// explains a few-LSB difference), as `key: golden … | actual …` lines.
    pub fn provenance_differences(&self) -> Vec<String> {
        match (&self.expected_provenance, &self.actual_provenance) {
            (Some(e), Some(a)) => e
                .differences(a)
                .into_iter()
                .filter(|(k, _, _)| k != "luz.encoding")
                .map(|(k, e, a)| {
                    format!(
                        "{k}: golden {} | actual {}",
                        e.as_deref().unwrap_or("(none)"),
                        a.as_deref().unwrap_or("(none)")
                    )
                })
                .collect(),
            _ => Vec::new(),
        }
    }
}

impl Case {
    pub fn passed(&self) -> bool {
        !matches!(self.verdict, Verdict::Fail)
    }

    fn failed(
        name: String,
        scene: &Path,
        golden: PathBuf,
        tolerance: Tolerance,
        reason: String,
    ) -> Self {
        Case {
            order: 0,
            name,
            scene: scene.to_path_buf(),
            golden,
            tolerance,
            tolerance_source: "golden-image defaults".into(),
            verdict: Verdict::Fail,
            failures: vec![reason],
            report: None,
            images: None,
            millis: 0.0,
            expected_provenance: None,
            actual_provenance: None,
            regions: Vec::new(),
            ignored: None,
        }
    }
}

/// One shard of a run: `index` of `count` (1-based), `--shard K/N`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub index: u32,
    pub count: u32,
}

impl std::str::FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || format!("expected K/N with 1 ≤ K ≤ N (e.g. 2/4), not {s:?}");
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count) = (
            k.trim().parse::<u32>().map_err(|_| bad())?,
            n.trim().parse::<u32>().map_err(|_| bad())?,
        );
        if index == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl Shard {
    /// The indices of this shard's cases among `total`: a contiguous run of the whole list (as
    /// Playwright's `--shard`), the shards' sizes differing by at most one. Shards 1..=N cover
    /// 0..total, each index once, and depend only on `total` (the case list is sorted:
    /// [`collect_scenes`]).
    pub fn range(&self, total: usize) -> std::ops::Range<usize> {
        let (k, n) = (self.index as usize, self.count as usize);
        (k - 1) * total / n..k * total / n
    }
}

/// Renders and checks (or blesses) every scene, `opts.jobs` at a time on `ctx`. Never fails as a
/// whole: each case carries its own failure. Cases come back in the order of `scenes`.
pub fn run(ctx: &Arc<Context>, scenes: &[PathBuf], opts: &GoldenOptions) -> Vec<Case> {
    run_some(ctx, scenes, 0..scenes.len(), opts)
}

/// [`run`] of the cases `selected` of `scenes` only (a shard), each case's `order` its index in
/// `scenes`; a name used by an earlier scene of the whole list fails as in a full run.
pub fn run_some(
    ctx: &Arc<Context>,
    all: &[PathBuf],
    selected: std::ops::Range<usize>,
    opts: &GoldenOptions,
) -> Vec<Case> {
    let names: Vec<String> = all.iter().map(|s| case_name(s)).collect();
    let first = selected.start;
    let scenes = &all[selected];
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<Case>>> = Mutex::new(vec![None; scenes.len()]);
    let progress = Reporting(opts.progress.as_deref());
    let total = scenes.len() as u64;
    progress.update("rendering", 0, total);
    let jobs = opts.jobs.clamp(1, scenes.len().max(1));
    std::thread::scope(|s| {
        for _ in 0..jobs {
            s.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                if k >= scenes.len() {
                    break;
                }
                let i = first + k;
                let duplicate = names[..i].iter().position(|n| *n == names[i]);
                let case = match duplicate {
                    Some(j) => Case::failed(
                        names[i].clone(),
                        &all[i],
                        golden_path(opts, &names[i]),
                        opts.tolerance,
                        format!(
                            "another scene has the name {:?} ({}); each scene's golden is \
                             <name>.png, so names must differ",
                            names[i],
                            all[j].display()
                        ),
                    ),
                    None => run_case(ctx, &all[i], &names[i], opts),
                };
                let mut case = case;
                case.order = i;
                results.lock().unwrap()[k] = Some(case);
                let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                progress.update(&names[i], n as u64, total);
            });
        }
    });
    results
        .into_inner()
        .unwrap()
        .into_iter()
        .map(|c| c.expect("every case ran"))
        .collect()
}

/// The golden of case `name`: `<goldens>/<name>.png` or `.exr` (`opts.format`).
pub fn golden_path(opts: &GoldenOptions, name: &str) -> PathBuf {
    let ext = match opts.format {
        FileFormat::Png => "png",
        FileFormat::Exr => "exr",
    };
    opts.goldens.join(format!("{name}.{ext}"))
}

/// One scene: load, render, compare or bless.
pub fn run_case(ctx: &Arc<Context>, scene_path: &Path, name: &str, opts: &GoldenOptions) -> Case {
    let t0 = Instant::now();
    let golden = golden_path(opts, name);
    let fail = |reason: String| {
        let mut c = Case::failed(
            name.to_string(),
            scene_path,
            golden.clone(),
            opts.tolerance,
            reason,
        );
        c.millis = t0.elapsed().as_secs_f64() * 1e3;
        c
    };
    let ext = extension(scene_path);
    let case_file = if is_sidecar(scene_path) {
        match CaseFile::read(scene_path) {
            Ok(c) if c.scene.is_some() => Some(c),
            Ok(_) => {
                return fail(format!(
                    "{}: scene: missing (a sidecar of tolerances is not a case)",
                    scene_path.display()
                ))
            }
            Err(e) => return fail(e),
        }
    } else {
        None
    };
    if case_file.is_none() && !SCENE_EXTENSIONS.contains(&ext.as_str()) {
        return fail(format!(
            "{}: not a scene file (luz golden reads {} scene files)",
            scene_path.display(),
            scene_kinds()
        ));
    }

    let loaded = match &case_file {
        Some(c) => c.load_scene(),
        None => crate::scene::load(scene_path).map_err(|e| e.to_string()),
    };
    let scene = match loaded {
        Ok(s) => s,
        Err(e) => return fail(e),
    };
    // Tolerances: the defaults, then the scene's `output.golden`, then a sidecar
    // <goldens>/<name>.golden.json (else beside the scene): each field of a later one wins.
    let (mut tolerance, mut tolerance_source) = if scene.output.golden.is_empty() {
        (opts.tolerance, "golden-image defaults".to_string())
    } else {
        (
            scene.output.golden.apply(opts.tolerance),
            format!("{}: output.golden", scene_path.display()),
        )
    };
    let sidecar_name = format!("{name}{SIDECAR_SUFFIX}");
    let sidecar = match &case_file {
        // A case file is its own sidecar.
        Some(c) => Some(c.path.clone()),
        None => [
            opts.goldens.join(&sidecar_name),
            scene_path
                .parent()
                .unwrap_or(Path::new(""))
                .join(&sidecar_name),
        ]
        .into_iter()
        .find(|p| p.is_file()),
    };
    let mut masking = Masking::default();
    if let Some(p) = &sidecar {
        match CaseFile::read(p) {
            Ok(c) => {
                tolerance = c.tolerance.apply(tolerance);
                masking = c.masking;
            }
            Err(e) => return fail(e),
        }
        tolerance_source = if scene.output.golden.is_empty() {
            p.display().to_string()
        } else {
            format!("{tolerance_source}, then {}", p.display())
        };
    }
    let rendered = {
        // The jobs share one device and its one queue, whose use must be externally
        // synchronised (one thread's vkDeviceWaitIdle while another submits is undefined
        // behaviour, and validation says so): the GPU part of a case runs alone, from building
        // the renderer to dropping it. Loading, comparing and encoding run in parallel.
        let _queue = GPU_QUEUE.lock().unwrap_or_else(|e| e.into_inner());
        let mut render = opts.render.clone();
        match case_file.as_ref().and_then(|c| c.fast_ibl) {
            Some(true) => render.ibl = crate::render::ibl::IblSettings::fast(),
            Some(false) => render.ibl = Default::default(),
            None => {}
        }
        Headless::with_options(ctx, &scene, &render).and_then(|mut r| {
            r.render()?;
            r.image()
        })
    };
    let image = match rendered {
        Ok(i) => i,
        Err(e) => return fail(format!("{}: cannot render: {e}", scene_path.display())),
    };
    let nan = imageio::count_non_finite(&image.pixels);
    let actual = LoadedImage::from_linear(
        &image,
        opts.format,
        scene.output.exposure,
        scene.output.tonemap,
    );
    let mut case = Case {
        order: 0,
        name: name.to_string(),
        scene: scene_path.to_path_buf(),
        golden: golden.clone(),
        tolerance,
        tolerance_source,
        verdict: Verdict::Pass,
        failures: Vec::new(),
        report: None,
        images: None,
        millis: 0.0,
        expected_provenance: None,
        actual_provenance: Some(crate::provenance::of_render(&ctx.info, &scene, None)),
        regions: Vec::new(),
        ignored: None,
    };

    if opts.bless {
        let old = golden.is_file().then(|| imageio::load(&golden));
        let change = match old {
            None => BlessChange::New,
            Some(Err(e)) => BlessChange::Replaced {
                reason: e.to_string(),
            },
            Some(Ok(old)) if (old.width, old.height) != (actual.width, actual.height) => {
                BlessChange::Resized {
                    from: (old.width, old.height),
                    to: (actual.width, actual.height),
                }
            }
            Some(Ok(old)) => {
                let exact = crate::diff::DiffOptions::default();
                match crate::diff::compare(&old, &actual, &exact) {
                    Ok(r) if r.differing_pixels == 0 => BlessChange::Unchanged,
                    Ok(r) => BlessChange::Changed(Box::new(r)),
                    Err(e) => BlessChange::Replaced {
                        reason: e.to_string(),
                    },
                }
            }
        };
        if change != BlessChange::Unchanged {
            let meta = case.actual_provenance.clone().unwrap_or_default();
            let saved = replace_atomically(&golden, |tmp| {
                imageio::save_render(tmp, &image, scene.output.encoding(), &meta)
                    .map_err(|e| e.to_string())
            });
            if let Err(e) = saved {
                case.verdict = Verdict::Fail;
                case.failures.push(e);
                case.millis = t0.elapsed().as_secs_f64() * 1e3;
                return case;
            }
        }
        case.verdict = Verdict::Blessed(change);
        case.images = Some(CaseImages {
            expected: None,
            actual,
            flip: None,
        });
        case.millis = t0.elapsed().as_secs_f64() * 1e3;
        return case;
    }

    let cmp = compare_with_golden_masked(&golden, nan, actual, tolerance, &masking);
    case.regions = cmp.regions;
    case.ignored = cmp.ignored;
    case.failures = cmp.failures;
    case.report = cmp.report;
    case.expected_provenance = cmp.expected_provenance;
    if !case.failures.is_empty() {
        case.verdict = Verdict::Fail;
    }
    case.images = Some(CaseImages {
        expected: cmp.expected,
        actual: cmp.actual,
        flip: cmp.flip,
    });
    case.millis = t0.elapsed().as_secs_f64() * 1e3;
    case
}

/// One rendered image against its golden file: what [`run_case`] and luz's own golden tests
/// (`tests/common/vulkan.rs`) both check, so the product and the harness cannot drift.
#[derive(Debug, Clone)]
pub struct Comparison {
    /// Each violated tolerance, or why there was nothing to compare (empty: pass).
    pub failures: Vec<String>,
    pub report: Option<DiffReport>,
    pub expected: Option<LoadedImage>,
    pub actual: LoadedImage,
    pub flip: Option<FlipMap>,
    pub expected_provenance: Option<Provenance>,
    /// The regions' checks ([`compare_with_golden_masked`]).
    pub regions: Vec<RegionOutcome>,
    /// What was left out.
    pub ignored: Option<Ignored>,
}

/// Compares `actual` (a rendered frame as its PNG or EXR holds it, e.g.
/// [`LoadedImage::from_linear`]) with the PNG or EXR `golden` under `tolerance` (8-bit steps;
/// 1/255 of radiance when an EXR is involved). `nan` is the number of NaN/Inf pixels of the
/// rendered radiance (any is a failure). A
/// missing or unreadable golden and a size mismatch are failures with the reason.
pub fn compare_with_golden(
    golden: &Path,
    nan: u64,
    actual: LoadedImage,
    tolerance: Tolerance,
) -> Comparison {
    compare_with_golden_masked(golden, nan, actual, tolerance, &Masking::default())
}

/// [`compare_with_golden`] with a case file's mask, regions and anti-aliasing option: masked
/// pixels (and, with `ignore_antialiasing`, differences where either image is anti-aliasing) are
/// left out of every check; each region's pixels are checked with the region's tolerances (the
/// case's, overridden field by field) and left out of the case's own check. A violation in a
/// region reads `region NAME: …`. A mask that cannot be read or has another size is a failure
/// naming the file.
pub fn compare_with_golden_masked(
    golden: &Path,
    nan: u64,
    actual: LoadedImage,
    tolerance: Tolerance,
    masking: &Masking,
) -> Comparison {
    let mut out = Comparison {
        failures: Vec::new(),
        report: None,
        expected: None,
        actual,
        flip: None,
        expected_provenance: None,
        regions: Vec::new(),
        ignored: None,
    };
    if nan > 0 {
        out.failures.push(format!(
            "{nan} pixels of the rendered radiance hold NaN or Inf"
        ));
    }
    if !golden.is_file() {
        out.failures.push(format!(
            "no golden {} (run with --bless to create it)",
            golden.display()
        ));
        return out;
    }
    let exp = match imageio::load(golden) {
        Ok(e) => e,
        Err(e) => {
            out.failures.push(e.to_string());
            return out;
        }
    };
    out.expected_provenance = imageio::provenance::read(golden).ok();
    let actual = &out.actual;
    if (exp.width, exp.height) != (actual.width, actual.height) {
        out.failures.push(format!(
            "size mismatch: the golden {} is {}×{}, the scene renders {}×{}",
            golden.display(),
            exp.width,
            exp.height,
            actual.width,
            actual.height
        ));
    } else if masking.is_empty() {
        let dopts = tolerance.options_for(&exp, actual);
        match crate::diff::compare_detailed(&exp, actual, &dopts) {
            Ok((report, map)) => {
                out.failures.extend(report.violations(&dopts));
                out.report = Some(report);
                out.flip = Some(map);
            }
            Err(e) => out.failures.push(e.to_string()),
        }
    } else {
        let actual = out.actual.clone();
        if let Err(e) = compare_masked_case(&exp, &actual, tolerance, masking, &mut out) {
            out.failures.push(e);
        }
    }
    out.expected = Some(exp);
    out
}

/// The masked and regional part of [`compare_with_golden_masked`] (both images of one size).
fn compare_masked_case(
    exp: &LoadedImage,
    actual: &LoadedImage,
    tolerance: Tolerance,
    masking: &Masking,
    out: &mut Comparison,
) -> Result<(), String> {
    let (w, h) = (exp.width, exp.height);
    let n = exp.display.len();
    let masked = match &masking.mask {
        Some(p) => {
            read_mask(p, w, h).map_err(|e| format!("{}: mask: {e}", masking.case_file.display()))?
        }
        None => vec![false; n],
    };
    let antialiased: Vec<bool> = if masking.ignore_antialiasing {
        let (e, a) = (
            crate::diff::display_rgba8(exp),
            crate::diff::display_rgba8(actual),
        );
        let img = |p| crate::diff::pixelmatch::Rgba8 {
            width: w,
            height: h,
            pixels: p,
        };
        crate::diff::pixelmatch::antialiased_differences(img(&e), img(&a))
            .into_iter()
            .zip(&masked)
            .map(|(aa, &m)| aa && !m)
            .collect()
    } else {
        vec![false; n]
    };
    let left_out: Vec<bool> = masked
        .iter()
        .zip(&antialiased)
        .map(|(m, a)| *m || *a)
        .collect();
    // Each region's own pixels: inside, not left out, not claimed by an earlier region.
    let mut claimed = vec![false; n];
    let mut members = Vec::with_capacity(masking.regions.len());
    for r in &masking.regions {
        let inside: Vec<bool> = match &r.area {
            RegionArea::Rect([x, y, rw, rh]) => (0..n)
                .map(|i| {
                    let (px, py) = (
                        (i as u64 % u64::from(w)) as u32,
                        (i as u64 / u64::from(w)) as u32,
                    );
                    px >= *x
                        && py >= *y
                        && u64::from(px) < u64::from(*x) + u64::from(*rw)
                        && u64::from(py) < u64::from(*y) + u64::from(*rh)
                })
                .collect(),
            RegionArea::Mask(p) => read_mask(p, w, h)
                .map_err(|e| format!("{}: {}.mask: {e}", masking.case_file.display(), r.field))?,
        };
        let mine: Vec<bool> = (0..n)
            .map(|i| inside[i] && !left_out[i] && !claimed[i])
            .collect();
        for (c, m) in claimed.iter_mut().zip(&mine) {
            *c |= *m;
        }
        members.push(mine);
    }
    // The case's own check: everything but the left-out pixels and the regions'.
    let ignored: Vec<bool> = left_out
        .iter()
        .zip(&claimed)
        .map(|(a, b)| *a || *b)
        .collect();
    let dopts = tolerance.options_for(exp, actual);
    let (report, mut map) =
        crate::diff::compare_masked(exp, actual, &dopts, &ignored).map_err(|e| e.to_string())?;
    out.failures.extend(report.violations(&dopts));
    for (r, mine) in masking.regions.iter().zip(&members) {
        let rt = r.tolerance.apply(tolerance);
        let ropts = rt.options_for(exp, actual);
        let outside: Vec<bool> = mine.iter().map(|m| !m).collect();
        let (rreport, rmap) = crate::diff::compare_masked(exp, actual, &ropts, &outside)
            .map_err(|e| e.to_string())?;
        // The heat map shows each pixel's error under the check it belongs to.
        for (i, m) in mine.iter().enumerate() {
            if *m {
                map.values[i] = rmap.values[i];
            }
        }
        let failures: Vec<String> = rreport
            .violations(&ropts)
            .into_iter()
            .map(|v| format!("region {}: {v}", r.name))
            .collect();
        out.failures.extend(failures.iter().cloned());
        out.regions.push(RegionOutcome {
            name: r.name.clone(),
            pixels: mine.iter().filter(|&&m| m).count() as u64,
            tolerance: rt,
            report: rreport,
            failures,
        });
    }
    out.report = Some(report);
    out.flip = Some(map);
    out.ignored = Some(Ignored {
        width: w,
        height: h,
        masked,
        antialiased,
    });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sidecar_overrides_and_turns_off() {
        let base = Tolerance::golden();
        let t = parse_sidecar(r#"{"max_flip_mean": 0.02, "max_abs": null}"#, base).unwrap();
        assert_eq!(t.max_flip_mean, Some(0.02));
        assert_eq!(t.max_abs, None);
        assert_eq!(t.max_bad_pixels, base.max_bad_pixels);
        let t =
            parse_sidecar(r#"{"max_bad_pixels": 500, "bad_pixel_threshold": 6}"#, base).unwrap();
        assert_eq!((t.max_bad_pixels, t.bad_pixel_threshold), (Some(500), 6.0));
        for (bad, needle) in [
            (r#"{"max_abs": -1}"#, "max_abs"),
            (r#"{"max_bad_pixels": 1.5}"#, "whole number"),
            (r#"{"max_flip": 1}"#, "unknown field \"max_flip\""),
            (r#"[1]"#, "JSON object"),
            (
                r#"{"max_flip_mean": "a"}"#,
                "max_flip_mean: must be a number",
            ),
            (r#"{"#, "not valid JSON"),
            (r#"{"bad_pixel_threshold": null}"#, "bad_pixel_threshold"),
        ] {
            let e = parse_sidecar(bad, base).unwrap_err();
            assert!(e.contains(needle), "{bad}: {e}");
        }
    }

    /// `ignore_antialiasing`: an anti-aliased edge drawn with another grey passes, a dot in a
    /// flat area still fails; without the option both fail.
    #[test]
    fn antialiased_edges_are_forgiven_and_real_changes_are_not() {
        let dir = std::env::temp_dir().join(format!("luz-golden-aa-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let (w, h) = (24u32, 16u32);
        let edge = |grey: u8| -> Vec<u8> {
            (0..w * h)
                .flat_map(|i| match i % w {
                    0..=9 => [0, 0, 0],
                    10 => [grey; 3],
                    _ => [255, 255, 255],
                })
                .collect()
        };
        let save = |name: &str, rgb: &[u8]| {
            let p = dir.join(name);
            crate::imageio::save_png_rgb8(&p, w, h, rgb).unwrap();
            p
        };
        let golden = save("golden.png", &edge(128));
        let moved = crate::imageio::load(&save("moved.png", &edge(80))).unwrap();
        let mut dotted_rgb = edge(128);
        dotted_rgb[(5 * w + 3) as usize * 3] = 200;
        let dotted = crate::imageio::load(&save("dotted.png", &dotted_rgb)).unwrap();
        let aa = Masking {
            ignore_antialiasing: true,
            ..Masking::default()
        };
        let strict = Tolerance {
            max_abs: Some(8.0),
            max_bad_pixels: Some(0),
            ..Tolerance::golden()
        };
        let plain = compare_with_golden(&golden, 0, moved.clone(), strict);
        assert!(!plain.failures.is_empty(), "the moved edge differs");
        let forgiven = compare_with_golden_masked(&golden, 0, moved, strict, &aa);
        assert!(forgiven.failures.is_empty(), "{:?}", forgiven.failures);
        let ignored = forgiven.ignored.unwrap();
        assert_eq!(
            ignored.antialiased_pixels(),
            u64::from(h),
            "the whole grey column"
        );
        assert_eq!(forgiven.report.unwrap().ignored_pixels, u64::from(h));
        let dot = compare_with_golden_masked(&golden, 0, dotted, strict, &aa);
        assert!(
            dot.failures.iter().any(|f| f.contains("max-abs 8")),
            "{:?}",
            dot.failures
        );
        assert_eq!(dot.ignored.unwrap().antialiased_pixels(), 0);
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn shards_cover_every_case_once_and_balance() {
        for total in 0..40usize {
            for n in 1..=9u32 {
                let mut seen = vec![0; total];
                let mut sizes = Vec::new();
                for k in 1..=n {
                    let r = Shard { index: k, count: n }.range(total);
                    sizes.push(r.len());
                    for i in r {
                        seen[i] += 1;
                    }
                }
                assert!(seen.iter().all(|&c| c == 1), "{total} in {n}");
                let (lo, hi) = (sizes.iter().min().unwrap(), sizes.iter().max().unwrap());
                assert!(hi - lo <= 1, "{total} in {n}: {sizes:?}");
            }
        }
        assert_eq!("2/4".parse::<Shard>(), Ok(Shard { index: 2, count: 4 }));
        for bad in ["0/3", "4/3", "1", "a/b", "1/0"] {
            let e = bad.parse::<Shard>().unwrap_err();
            assert!(e.contains("K/N"), "{bad}: {e}");
        }
    }

    #[test]
    fn scenes_from_files_and_folders() {
        let dir = std::env::temp_dir().join(format!("luz-golden-collect-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        for f in ["b.json", "a.json", "a.golden.json", "m.obj", "notes.txt"] {
            std::fs::write(dir.join(f), "{}").unwrap();
        }
        let got = collect_scenes(std::slice::from_ref(&dir)).unwrap();
        let names: Vec<_> = got.iter().map(|p| case_name(p)).collect();
        assert_eq!(names, ["a", "b", "m"]);
        let e = collect_scenes(&[dir.join("nope.json")]).unwrap_err();
        assert!(e.to_string().contains("nope.json"), "{e}");
        let e = collect_scenes(&[dir.join("sub")]).unwrap_err();
        assert!(e.to_string().contains("no scene files"), "{e}");
        assert!(matches!(collect_scenes(&[]), Err(GoldenError::NoScenes)));
        // The goldens folder.
        assert!(check_goldens_dir(&dir, false).is_ok());
        let e = check_goldens_dir(&dir.join("b.json"), false).unwrap_err();
        assert!(e.to_string().contains("not a folder"), "{e}");
        let missing = dir.join("goldens");
        let e = check_goldens_dir(&missing, false).unwrap_err();
        assert!(e.to_string().contains("--bless"), "{e}");
        check_goldens_dir(&missing, true).unwrap();
        assert!(missing.is_dir());
        std::fs::remove_dir_all(dir).unwrap();
    }
}
