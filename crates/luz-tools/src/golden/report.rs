//! The report of a golden run, for people and CI systems, in one folder:
//!
//! * `index.html`: per scene, expected | actual | FLIP heat map, a slider that fades from the
//!   expected to the actual image (and a button that flips between them), the figures and the
//!   reasons. Self-contained: the images sit beside it in `images/`, a few lines of inline
//!   script drive the slider, nothing is fetched from the network.
//! * `junit.xml`: one `testcase` per scene; a failing case has a `failure` with the figures.
//! * `summary.md`: a Markdown table for pull-request comments.
//! * `cases.json`: the same as data ([`RunRecord`]), which [`merge`] reads to join the reports of
//!   a sharded run (`luz golden … --shard K/N`) into one, as if one job had run every case.
//!
//! Masked pixels (a case file's `mask`) are drawn hatched over the expected and actual images
//! (an overlay `images/<case>.mask.png`), differences forgiven as anti-aliasing in yellow.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::{BlessChange, Case, GoldenError, Shard, Verdict};
use crate::diff;

/// What the report says about the run as a whole.
#[derive(Debug, Clone, Default)]
pub struct RunInfo {
    /// The device and driver that rendered the actual images.
    pub device: String,
    /// The goldens folder.
    pub goldens: PathBuf,
    /// luz's version (and commit when known).
    pub luz: String,
    /// The shard this run was (`None`: every case).
    pub shard: Option<Shard>,
    /// Cases of the whole run, all shards together.
    pub total: usize,
}

/// The version of `cases.json` this luz writes and reads.
pub const RECORD_FORMAT: u32 = 1;

/// `cases.json`: a report as data.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RunRecord {
    pub format: u32,
    pub device: String,
    pub goldens: String,
    pub luz: String,
    /// `[K, N]` for shard K of N.
    pub shard: Option<[u32; 2]>,
    /// Cases of the whole run (every shard).
    pub total: usize,
    pub cases: Vec<CaseRecord>,
}

/// One case of a report, as shown.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CaseRecord {
    /// The case's place in the whole run's order.
    pub order: usize,
    pub name: String,
    pub scene: String,
    pub golden: String,
    /// `PASS`, `FAIL`, `BLESSED (…)`.
    pub status: String,
    /// `pass`, `fail` or `blessed`.
    pub class: String,
    pub passed: bool,
    pub figures: String,
    pub tolerances: String,
    pub failures: Vec<String>,
    pub provenance_differences: Vec<String>,
    /// `golden: device, driver` and `actual: …` lines.
    pub devices: Vec<String>,
    /// FLIP mean, max abs, differing pixels as the tables show them.
    pub table: Option<[String; 3]>,
    pub millis: f64,
    /// One line per region: its pixels, figures and tolerances.
    pub regions: Vec<String>,
    /// What was left out (masked, forgiven as anti-aliasing).
    pub ignored: Option<String>,
    /// Paths of the images, relative to the report folder.
    pub expected: Option<String>,
    pub actual: Option<String>,
    pub flip: Option<String>,
    /// The hatched overlay of the ignored pixels.
    pub mask: Option<String>,
}

/// Creates `dir` (and its `images/` folder) and checks it can be written, before any rendering.
pub fn prepare(dir: &Path) -> Result<(), GoldenError> {
    let err = |reason: String| GoldenError::Report {
        path: dir.to_path_buf(),
        reason,
    };
    if dir.exists() && !dir.is_dir() {
        return Err(err("it exists and is not a folder".into()));
    }
    std::fs::create_dir_all(dir.join("images")).map_err(|e| err(e.to_string()))?;
    let probe = dir.join("index.html");
    std::fs::OpenOptions::new()
        .write(true)
        .create(true)
        .truncate(false)
        .open(&probe)
        .map_err(|e| err(e.to_string()))?;
    Ok(())
}

/// Writes `index.html`, `junit.xml`, `summary.md` and the images into `dir` (see the module
/// docs). Returns the files written.
pub fn write(dir: &Path, cases: &[Case], info: &RunInfo) -> Result<Vec<PathBuf>, GoldenError> {
    prepare(dir)?;
    let werr = |path: &Path, reason: String| GoldenError::Report {
        path: path.to_path_buf(),
        reason,
    };
    let mut records = Vec::with_capacity(cases.len());
    for (i, case) in cases.iter().enumerate() {
        let shown = write_images(dir, i, case).map_err(|e| werr(dir, e))?;
        records.push(record(case, shown));
    }
    let run = RunRecord {
        format: RECORD_FORMAT,
        device: info.device.clone(),
        goldens: info.goldens.display().to_string(),
        luz: info.luz.clone(),
        shard: info.shard.map(|s| [s.index, s.count]),
        total: info.total.max(cases.len()),
        cases: records,
    };
    write_all(dir, &run)
}

/// Writes the HTML page, JUnit XML, Markdown summary and `cases.json` of `run` into `dir`.
fn write_all(dir: &Path, run: &RunRecord) -> Result<Vec<PathBuf>, GoldenError> {
    let werr = |path: &Path, reason: String| GoldenError::Report {
        path: path.to_path_buf(),
        reason,
    };
    let mut files = Vec::new();
    let json = serde_json::to_string_pretty(run).map_err(|e| werr(dir, e.to_string()))?;
    for (name, text) in [
        ("index.html", html(run)),
        ("junit.xml", junit(run)),
        ("summary.md", markdown(run)),
        ("cases.json", json),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, text).map_err(|e| werr(&path, e.to_string()))?;
        files.push(path);
    }
    Ok(files)
}

/// A case as the report shows it.
fn record(c: &Case, img: Images) -> CaseRecord {
    let table = c.report.as_ref().map(|r| {
        [
            format!("{:.6}", r.flip_mean),
            r.max_abs.to_string(),
            r.differing_pixels.to_string(),
        ]
    });
    let mut devices = Vec::new();
    for (side, p) in [
        ("golden", &c.expected_provenance),
        ("actual", &c.actual_provenance),
    ] {
        if let Some(p) = p {
            let device = [
                p.get("luz.device"),
                p.get("luz.driver"),
                p.get("luz.vulkan"),
            ]
            .iter()
            .flatten()
            .copied()
            .collect::<Vec<_>>()
            .join(", ");
            if !device.is_empty() {
                devices.push(format!("{side}: {device}"));
            }
        }
    }
    let regions = c
        .regions
        .iter()
        .map(|r| {
            format!(
                "region {}: {} pixels, FLIP mean {:.6}, max abs {}, {} pixels beyond {}; \
                 tolerances {}{}",
                r.name,
                r.pixels,
                r.report.flip_mean,
                r.report.max_abs,
                r.report.differing_pixels,
                r.report.bad_pixel_threshold,
                limits(&r.tolerance),
                if r.failures.is_empty() {
                    "; passes"
                } else {
                    "; FAILS"
                }
            )
        })
        .collect();
    let ignored = c.ignored.as_ref().map(|g| {
        format!(
            "left out: {} masked pixels (hatched), {} pixels forgiven as anti-aliasing (yellow)",
            g.masked_pixels(),
            g.antialiased_pixels()
        )
    });
    CaseRecord {
        order: c.order,
        name: c.name.clone(),
        scene: c.scene.display().to_string(),
        golden: c.golden.display().to_string(),
        status: status_word(c),
        class: match c.verdict {
            Verdict::Pass => "pass",
            Verdict::Fail => "fail",
            Verdict::Blessed(_) => "blessed",
        }
        .into(),
        passed: c.passed(),
        figures: figures(c),
        tolerances: tolerance_text(c),
        failures: c.failures.clone(),
        provenance_differences: c.provenance_differences(),
        devices,
        table,
        millis: c.millis,
        regions,
        ignored,
        expected: img.expected,
        actual: img.actual,
        flip: img.flip,
        mask: img.mask,
    }
}

/// Why `luz golden merge` cannot merge: every message names the folder or file.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    #[error("{}: {reason}", .path.display())]
    Input { path: PathBuf, reason: String },
    #[error("{0}")]
    Shards(String),
    #[error(transparent)]
    Output(#[from] GoldenError),
}

/// Merges the report folders of a sharded run (`dirs`, each written by [`write`]) into `out`:
/// one page, one JUnit file, one summary and one `cases.json`, the cases in the whole run's
/// order, as if one job had run them all. Every shard 1..=N must be there exactly once (when the
/// reports are shards) and each case name once. Returns the cases merged.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<usize, MergeError> {
    let mut runs: Vec<(PathBuf, RunRecord)> = Vec::new();
    for d in dirs {
        let path = d.join("cases.json");
        let input = |reason: String| MergeError::Input {
            path: path.clone(),
            reason,
        };
        let text = crate::files::read_input_text(&path).map_err(|e| {
            input(format!(
                "{e} (is {} a report folder of luz golden --report?)",
                d.display()
            ))
        })?;
        let run: RunRecord = serde_json::from_str(&text)
            .map_err(|e| input(format!("not a luz golden report: {e}")))?;
        if run.format != RECORD_FORMAT {
            return Err(input(format!(
                "format {} (this luz reads format {RECORD_FORMAT})",
                run.format
            )));
        }
        runs.push((d.clone(), run));
    }
    if runs.is_empty() {
        return Err(MergeError::Shards("no report folders given".into()));
    }
    // Shards: one N, every K once, one total.
    let sharded: Vec<_> = runs
        .iter()
        .filter_map(|(d, r)| r.shard.map(|s| (d, s)))
        .collect();
    if !sharded.is_empty() {
        if sharded.len() != runs.len() {
            return Err(MergeError::Shards(
                "some reports are shards (--shard) and some are not".into(),
            ));
        }
        let n = sharded[0].1[1];
        let mut seen: Vec<Option<&PathBuf>> = vec![None; n as usize];
        for (d, [k, count]) in &sharded {
            if *count != n {
                return Err(MergeError::Shards(format!(
                    "{} is shard {k}/{count}, {} is shard {}/{n}: one run has one shard count",
                    d.display(),
                    sharded[0].0.display(),
                    sharded[0].1[0]
                )));
            }
            let slot = &mut seen[(*k - 1) as usize];
            if let Some(other) = slot {
                return Err(MergeError::Shards(format!(
                    "shard {k}/{n} is given twice: {} and {}",
                    other.display(),
                    d.display()
                )));
            }
            *slot = Some(d);
        }
        let missing: Vec<String> = seen
            .iter()
            .enumerate()
            .filter(|(_, s)| s.is_none())
            .map(|(i, _)| format!("{}/{n}", i + 1))
            .collect();
        if !missing.is_empty() {
            return Err(MergeError::Shards(format!(
                "shard {} missing: the merged report would not hold every case",
                missing.join(", ")
            )));
        }
        let total = runs[0].1.total;
        if let Some((d, r)) = runs.iter().find(|(_, r)| r.total != total) {
            return Err(MergeError::Shards(format!(
                "{} belongs to a run of {} cases, {} to one of {total}: shards of different runs",
                d.display(),
                r.total,
                runs[0].0.display()
            )));
        }
    }
    // Each case once.
    let mut cases: Vec<(&PathBuf, &CaseRecord)> = runs
        .iter()
        .flat_map(|(d, r)| r.cases.iter().map(move |c| (d, c)))
        .collect();
    cases.sort_by(|a, b| a.1.order.cmp(&b.1.order).then(a.1.name.cmp(&b.1.name)));
    for w in cases.windows(2) {
        if w[0].1.name == w[1].1.name {
            return Err(MergeError::Shards(format!(
                "the case {:?} is in {} and in {}",
                w[0].1.name,
                w[0].0.display(),
                w[1].0.display()
            )));
        }
    }
    prepare(out)?;
    let mut merged = Vec::with_capacity(cases.len());
    for (i, (d, c)) in cases.iter().enumerate() {
        let stem = file_stem(i, &c.name);
        let mut c = (*c).clone();
        for (suffix, slot) in [
            ("expected", &mut c.expected),
            ("actual", &mut c.actual),
            ("flip", &mut c.flip),
            ("mask", &mut c.mask),
        ] {
            if let Some(rel) = slot.as_ref() {
                let from = d.join(rel);
                let to_rel = format!("images/{stem}.{suffix}.png");
                std::fs::copy(&from, out.join(&to_rel)).map_err(|e| MergeError::Input {
                    path: from.clone(),
                    reason: format!("cannot copy it into {}: {e}", out.display()),
                })?;
                *slot = Some(to_rel);
            }
        }
        merged.push(c);
    }
    let mut devices: Vec<&str> = Vec::new();
    let mut goldens: Vec<&str> = Vec::new();
    for (_, r) in &runs {
        if !devices.contains(&r.device.as_str()) {
            devices.push(&r.device);
        }
        if !goldens.contains(&r.goldens.as_str()) {
            goldens.push(&r.goldens);
        }
    }
    let n = merged.len();
    let run = RunRecord {
        format: RECORD_FORMAT,
        device: devices.join("; "),
        goldens: goldens.join("; "),
        luz: runs[0].1.luz.clone(),
        shard: None,
        total: n,
        cases: merged,
    };
    write_all(out, &run)?;
    Ok(n)
}

/// Relative paths (from the report folder) of a case's images, when it has them.
#[derive(Default)]
struct Images {
    expected: Option<String>,
    actual: Option<String>,
    flip: Option<String>,
    mask: Option<String>,
}

/// A file name made of the case's index and the safe characters of its name.
fn file_stem(i: usize, name: &str) -> String {
    let safe: String = name.chars().map(crate::files::file_safe_char).collect();
    format!("{i:03}-{safe}")
}

fn write_images(dir: &Path, i: usize, case: &Case) -> Result<Images, String> {
    let mut out = Images::default();
    let Some(imgs) = &case.images else {
        return Ok(out);
    };
    let stem = file_stem(i, &case.name);
    let save = |suffix: &str, img: &crate::imageio::LoadedImage| -> Result<String, String> {
        let rel = format!("images/{stem}.{suffix}.png");
        let rgb: Vec<u8> = img.display.iter().flatten().copied().collect();
        crate::imageio::save_png_rgb8(&dir.join(&rel), img.width, img.height, &rgb)
            .map_err(|e| e.to_string())?;
        Ok(rel)
    };
    if let Some(e) = &imgs.expected {
        out.expected = Some(save("expected", e)?);
    }
    out.actual = Some(save("actual", &imgs.actual)?);
    if let Some(map) = &imgs.flip {
        let rel = format!("images/{stem}.flip.png");
        diff::write_heatmap(&dir.join(&rel), map).map_err(|e| e.to_string())?;
        out.flip = Some(rel);
    }
    if let Some(g) = &case.ignored {
        let rel = format!("images/{stem}.mask.png");
        write_hatching(&dir.join(&rel), g)?;
        out.mask = Some(rel);
    }
    Ok(out)
}

/// The overlay of the left-out pixels: masked ones hatched (diagonal magenta stripes over a
/// light veil), forgiven anti-aliasing yellow, the rest transparent.
fn write_hatching(path: &Path, g: &super::Ignored) -> Result<(), String> {
    let mut rgba = Vec::with_capacity(g.masked.len() * 4);
    for (i, (&m, &aa)) in g.masked.iter().zip(&g.antialiased).enumerate() {
        let (x, y) = (i as u32 % g.width, i as u32 / g.width);
        let px = if m {
            if (x + y) % 6 < 2 {
                [200, 0, 200, 230]
            } else {
                [255, 255, 255, 90]
            }
        } else if aa {
            [255, 230, 0, 200]
        } else {
            [0, 0, 0, 0]
        };
        rgba.extend_from_slice(&px);
    }
    image::save_buffer_with_format(
        path,
        &rgba,
        g.width,
        g.height,
        image::ExtendedColorType::Rgba8,
        image::ImageFormat::Png,
    )
    .map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// `PASS`, `FAIL` or what blessing did.
pub fn status_word(case: &Case) -> String {
    match &case.verdict {
        Verdict::Pass => "PASS".into(),
        Verdict::Fail => "FAIL".into(),
        Verdict::Blessed(change) => match change {
            BlessChange::New => "BLESSED (new)".into(),
            BlessChange::Unchanged => "BLESSED (unchanged)".into(),
            BlessChange::Changed(_) => "BLESSED (changed)".into(),
            BlessChange::Resized { .. } => "BLESSED (resized)".into(),
            BlessChange::Replaced { .. } => "BLESSED (replaced)".into(),
        },
    }
}

/// The figures of a case in one line (empty without a comparison).
pub fn figures(case: &Case) -> String {
    match &case.report {
        Some(r) => format!(
            "FLIP mean {:.6}, max abs {} ({}), {} pixels beyond {}",
            r.flip_mean, r.max_abs, r.units, r.differing_pixels, r.bad_pixel_threshold
        ),
        None => String::new(),
    }
}

fn limits(t: &diff::Tolerance) -> String {
    let show = |v: Option<f32>| v.map_or("off".to_string(), |v| v.to_string());
    format!(
        "FLIP mean ≤ {}, max abs ≤ {} steps, ≤ {} pixels beyond {} steps",
        show(t.max_flip_mean),
        show(t.max_abs),
        t.max_bad_pixels
            .map_or("off".to_string(), |v| v.to_string()),
        t.bad_pixel_threshold,
    )
}

fn tolerance_text(case: &Case) -> String {
    format!("{} ({})", limits(&case.tolerance), case.tolerance_source)
}

/// `items` (escaped) as an HTML list of class `class`, ending its line.
fn push_list(h: &mut String, class: &str, items: &[String]) {
    let _ = write!(h, "<ul class=\"{class}\">");
    for item in items {
        let _ = write!(h, "<li>{}</li>", escape(item));
    }
    h.push_str("</ul>\n");
}

/// Escapes text for HTML and XML (element content and quoted attributes).
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            // XML 1.0 forbids most control characters even escaped.
            c if (c as u32) < 0x20 && !matches!(c, '\n' | '\t' | '\r') => out.push('\u{FFFD}'),
            c => out.push(c),
        }
    }
    out
}

const STYLE: &str = "body{font-family:sans-serif;margin:1.5em;background:#fafafa;color:#222}
h1{font-size:1.4em}table.summary{border-collapse:collapse;margin-bottom:2em}
table.summary td,table.summary th{border:1px solid #ccc;padding:.25em .6em;text-align:left}
.case{border:1px solid #ccc;border-left:8px solid #3a3;background:#fff;margin:1em 0;padding:.5em 1em}
.case.fail{border-left-color:#c22}.case.blessed{border-left-color:#36c}
.badge{font-weight:bold;padding:.1em .5em;border-radius:.3em;color:#fff;background:#3a3}
.fail .badge{background:#c22}.blessed .badge{background:#36c}
.row{display:flex;flex-wrap:wrap;gap:1em}.row figure{margin:0}
.row img{max-width:420px;image-rendering:pixelated;border:1px solid #ddd}
.stack{position:relative;display:inline-block}.stack img.top{position:absolute;left:0;top:0}
ul.reasons{color:#a11}code{background:#eee;padding:0 .2em}";

// After loading, every image is marked `data-loaded="true|false"` and the body says how many
// loaded (`data-images-loaded="3/3"`): a broken image shows, and a headless browser can check.
const SCRIPT: &str = "function fade(id,v){document.getElementById(id).style.opacity=v/100;}
function flip(id){var s=document.getElementById(id+'-s');s.value=s.value>50?0:100;fade(id,s.value);}
window.addEventListener('load',function(){var im=document.images,n=0;
for(var i=0;i<im.length;i++){var ok=im[i].complete&&im[i].naturalWidth>0;if(ok)n++;
im[i].setAttribute('data-loaded',ok?'true':'false');if(!ok)im[i].style.outline='4px dashed red';}
document.body.setAttribute('data-images-loaded',n+'/'+im.length);});";

fn html(run: &RunRecord) -> String {
    let cases = &run.cases;
    let failed = cases.iter().filter(|c| !c.passed).count();
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>luz golden: {} of {} failed</title><style>{STYLE}</style>\
         <script>{SCRIPT}</script></head><body>\n\
         <h1>luz golden: <span id=\"verdict\">{} of {} failed</span></h1>\n\
         <p>Actual images rendered on <b>{}</b> by {}; goldens in <code>{}</code>.</p>\n",
        failed,
        cases.len(),
        failed,
        cases.len(),
        escape(&run.device),
        escape(&run.luz),
        escape(&run.goldens)
    );
    if let Some([k, n]) = run.shard {
        let _ = writeln!(
            h,
            "<p id=\"shard\">Shard {k} of {n}: {} of the run's {} cases.</p>",
            cases.len(),
            run.total
        );
    }
    h.push_str(
        "<table class=\"summary\"><tr><th>scene</th><th>result</th><th>FLIP mean</th>\
         <th>max abs</th><th>differing pixels</th></tr>\n",
    );
    for (i, c) in cases.iter().enumerate() {
        let [flip, abs, bad] = c.table.clone().unwrap_or_default();
        let _ = writeln!(
            h,
            "<tr><td><a href=\"#case-{i}\">{}</a></td><td>{}</td><td>{flip}</td><td>{abs}</td>\
             <td>{bad}</td></tr>",
            escape(&c.name),
            escape(&c.status)
        );
    }
    h.push_str("</table>\n");
    for (i, c) in cases.iter().enumerate() {
        let class = &c.class;
        let _ = write!(
            h,
            "<section class=\"case {class}\" id=\"case-{i}\" data-status=\"{class}\">\n\
             <h2>{} <span class=\"badge\">{}</span></h2>\n\
             <p>scene <code>{}</code>, golden <code>{}</code><br>tolerances: {}<br>{}</p>\n",
            escape(&c.name),
            escape(&c.status),
            escape(&c.scene),
            escape(&c.golden),
            escape(&c.tolerances),
            escape(&c.figures)
        );
        if !c.regions.is_empty() {
            push_list(&mut h, "regions", &c.regions);
        }
        if let Some(g) = &c.ignored {
            let _ = writeln!(h, "<p class=\"ignored\">{}</p>", escape(g));
        }
        if !c.provenance_differences.is_empty() {
            h.push_str("<p>provenance differs:</p>");
            push_list(&mut h, "provenance", &c.provenance_differences);
        }
        for d in &c.devices {
            let _ = writeln!(h, "<p>{}</p>", escape(d));
        }
        if !c.failures.is_empty() {
            push_list(&mut h, "reasons", &c.failures);
        }
        h.push_str("<div class=\"row\">");
        let fig = |h: &mut String, src: &Option<String>, caption: &str, hatch: bool| {
            if let Some(src) = src {
                let over = match (&c.mask, hatch) {
                    (Some(m), true) => format!(
                        "<img class=\"top hatch\" src=\"{}\" alt=\"left out ({caption})\">",
                        escape(m)
                    ),
                    _ => String::new(),
                };
                let _ = write!(
                    h,
                    "<figure><div class=\"stack\"><img src=\"{}\" alt=\"{caption}\">{over}</div>\
                     <figcaption>{caption}</figcaption></figure>",
                    escape(src)
                );
            }
        };
        fig(&mut h, &c.expected, "expected", true);
        fig(&mut h, &c.actual, "actual", true);
        fig(&mut h, &c.flip, "FLIP error", false);
        h.push_str("</div>\n");
        if let (Some(e), Some(a)) = (&c.expected, &c.actual) {
            let id = format!("fade-{i}");
            let _ = writeln!(
                h,
                "<p>expected <input type=\"range\" id=\"{id}-s\" min=\"0\" max=\"100\" value=\"0\" \
                 oninput=\"fade('{id}',this.value)\"> actual \
                 <button type=\"button\" onclick=\"flip('{id}')\">flip</button></p>\
                 <div class=\"stack\"><img src=\"{}\" alt=\"expected (under)\">\
                 <img class=\"top\" id=\"{id}\" src=\"{}\" alt=\"actual (over)\" style=\"opacity:0\"></div>",
                escape(e),
                escape(a)
            );
        }
        h.push_str("</section>\n");
    }
    h.push_str("</body></html>\n");
    h
}

fn junit(run: &RunRecord) -> String {
    let cases = &run.cases;
    let failed = cases.iter().filter(|c| !c.passed).count();
    let total_s: f64 = cases.iter().map(|c| c.millis).sum::<f64>() / 1e3;
    let mut x = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        x,
        "<testsuites name=\"luz golden\" tests=\"{}\" failures=\"{failed}\" errors=\"0\" time=\"{total_s:.3}\">",
        cases.len()
    );
    let _ = writeln!(
        x,
        "  <testsuite name=\"luz golden\" tests=\"{}\" failures=\"{failed}\" errors=\"0\" skipped=\"0\" time=\"{total_s:.3}\">",
        cases.len()
    );
    let _ = writeln!(
        x,
        "    <properties><property name=\"device\" value=\"{}\"/><property name=\"goldens\" value=\"{}\"/></properties>",
        escape(&run.device),
        escape(&run.goldens)
    );
    for c in cases {
        let _ = write!(
            x,
            "    <testcase classname=\"luz.golden\" name=\"{}\" file=\"{}\" time=\"{:.3}\"",
            escape(&c.name),
            escape(&c.scene),
            c.millis / 1e3
        );
        if c.passed {
            let _ = writeln!(
                x,
                "><system-out>{}</system-out></testcase>",
                escape(&format!("{}; {}", c.status, c.figures))
            );
        } else {
            let message = c.failures.first().cloned().unwrap_or_default();
            let mut body = format!(
                "{}\n{}\ntolerances: {}",
                c.failures.join("\n"),
                c.figures,
                c.tolerances
            );
            for r in &c.regions {
                body.push('\n');
                body.push_str(r);
            }
            for d in &c.provenance_differences {
                body.push_str("\nprovenance differs: ");
                body.push_str(d);
            }
            let _ = writeln!(
                x,
                ">\n      <failure message=\"{}\" type=\"golden mismatch\">{}</failure>\n    </testcase>",
                escape(&message),
                escape(&body)
            );
        }
    }
    x.push_str("  </testsuite>\n</testsuites>\n");
    x
}

fn md_cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

fn markdown(run: &RunRecord) -> String {
    let cases = &run.cases;
    let failed = cases.iter().filter(|c| !c.passed).count();
    let mut m = String::new();
    let _ = writeln!(
        m,
        "### luz golden: {} of {} passed{}\n",
        cases.len() - failed,
        cases.len(),
        if failed > 0 { " ❌" } else { " ✅" }
    );
    let _ = writeln!(m, "Rendered on {}.\n", md_cell(&run.device));
    if let Some([k, n]) = run.shard {
        let _ = writeln!(
            m,
            "Shard {k} of {n}: {} of the run's {} cases.\n",
            cases.len(),
            run.total
        );
    }
    m.push_str("| scene | result | FLIP mean | max abs | differing pixels | reason |\n");
    m.push_str("|---|---|---|---|---|---|\n");
    for c in cases {
        let [flip, abs, bad] = c
            .table
            .clone()
            .unwrap_or_else(|| ["–".into(), "–".into(), "–".into()]);
        let _ = writeln!(
            m,
            "| {} | {} | {flip} | {abs} | {bad} | {} |",
            md_cell(&c.name),
            c.status,
            md_cell(&c.failures.join("; "))
        );
    }
    m
}
