//! The report of a golden run, for people and CI systems, in one folder:
//!
//! * `index.html`: per scene, expected | actual | FLIP heat map, a slider that fades from the
//!   expected to the actual image (and a button that flips between them), the figures and the
//!   reasons. Self-contained: the images sit beside it in `images/`, a few lines of inline
//!   script drive the slider, nothing is fetched from the network.
//! * `junit.xml`: one `testcase` per scene; a failing case has a `failure` with the figures.
//! * `summary.md`: a Markdown table for pull-request comments.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::{BlessChange, Case, GoldenError, Verdict};
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
    let mut files = Vec::new();
    let mut shown: Vec<Images> = Vec::with_capacity(cases.len());
    for (i, case) in cases.iter().enumerate() {
        shown.push(write_images(dir, i, case).map_err(|e| werr(dir, e))?);
    }
    for (name, text) in [
        ("index.html", html(cases, &shown, info)),
        ("junit.xml", junit(cases, info)),
        ("summary.md", markdown(cases, info)),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, text).map_err(|e| werr(&path, e.to_string()))?;
        files.push(path);
    }
    Ok(files)
}

/// Relative paths (from the report folder) of a case's images, when it has them.
#[derive(Default)]
struct Images {
    expected: Option<String>,
    actual: Option<String>,
    flip: Option<String>,
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
    Ok(out)
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

fn tolerance_text(case: &Case) -> String {
    let t = &case.tolerance;
    let show = |v: Option<f32>| v.map_or("off".to_string(), |v| v.to_string());
    format!(
        "FLIP mean ≤ {}, max abs ≤ {} steps, ≤ {} pixels beyond {} steps ({})",
        show(t.max_flip_mean),
        show(t.max_abs),
        t.max_bad_pixels
            .map_or("off".to_string(), |v| v.to_string()),
        t.bad_pixel_threshold,
        case.tolerance_source
    )
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

fn html(cases: &[Case], shown: &[Images], info: &RunInfo) -> String {
    let failed = cases.iter().filter(|c| !c.passed()).count();
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
        escape(&info.device),
        escape(&info.luz),
        escape(&info.goldens.display().to_string())
    );
    h.push_str(
        "<table class=\"summary\"><tr><th>scene</th><th>result</th><th>FLIP mean</th>\
         <th>max abs</th><th>differing pixels</th></tr>\n",
    );
    for (i, c) in cases.iter().enumerate() {
        let (flip, abs, bad) = match &c.report {
            Some(r) => (
                format!("{:.6}", r.flip_mean),
                r.max_abs.to_string(),
                r.differing_pixels.to_string(),
            ),
            None => Default::default(),
        };
        let _ = writeln!(
            h,
            "<tr><td><a href=\"#case-{i}\">{}</a></td><td>{}</td><td>{flip}</td><td>{abs}</td>\
             <td>{bad}</td></tr>",
            escape(&c.name),
            escape(&status_word(c))
        );
    }
    h.push_str("</table>\n");
    for (i, (c, img)) in cases.iter().zip(shown).enumerate() {
        let class = match c.verdict {
            Verdict::Pass => "pass",
            Verdict::Fail => "fail",
            Verdict::Blessed(_) => "blessed",
        };
        let _ = write!(
            h,
            "<section class=\"case {class}\" id=\"case-{i}\" data-status=\"{class}\">\n\
             <h2>{} <span class=\"badge\">{}</span></h2>\n\
             <p>scene <code>{}</code>, golden <code>{}</code><br>tolerances: {}<br>{}</p>\n",
            escape(&c.name),
            escape(&status_word(c)),
            escape(&c.scene.display().to_string()),
            escape(&c.golden.display().to_string()),
            escape(&tolerance_text(c)),
            escape(&figures(c))
        );
        let prov = c.provenance_differences();
        if !prov.is_empty() {
            h.push_str("<p>provenance differs:</p><ul class=\"provenance\">");
            for d in &prov {
                let _ = write!(h, "<li>{}</li>", escape(d));
            }
            h.push_str("</ul>\n");
        }
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
                    let _ = writeln!(h, "<p>{side}: {}</p>", escape(&device));
                }
            }
        }
        if !c.failures.is_empty() {
            h.push_str("<ul class=\"reasons\">");
            for f in &c.failures {
                let _ = write!(h, "<li>{}</li>", escape(f));
            }
            h.push_str("</ul>\n");
        }
        h.push_str("<div class=\"row\">");
        let fig = |h: &mut String, src: &Option<String>, caption: &str| {
            if let Some(src) = src {
                let _ = write!(
                    h,
                    "<figure><img src=\"{}\" alt=\"{caption}\"><figcaption>{caption}</figcaption></figure>",
                    escape(src)
                );
            }
        };
        fig(&mut h, &img.expected, "expected");
        fig(&mut h, &img.actual, "actual");
        fig(&mut h, &img.flip, "FLIP error");
        h.push_str("</div>\n");
        if let (Some(e), Some(a)) = (&img.expected, &img.actual) {
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

fn junit(cases: &[Case], info: &RunInfo) -> String {
    let failed = cases.iter().filter(|c| !c.passed()).count();
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
        escape(&info.device),
        escape(&info.goldens.display().to_string())
    );
    for c in cases {
        let _ = write!(
            x,
            "    <testcase classname=\"luz.golden\" name=\"{}\" file=\"{}\" time=\"{:.3}\"",
            escape(&c.name),
            escape(&c.scene.display().to_string()),
            c.millis / 1e3
        );
        if c.passed() {
            let _ = writeln!(
                x,
                "><system-out>{}</system-out></testcase>",
                escape(&format!("{}; {}", status_word(c), figures(c)))
            );
        } else {
            let message = c.failures.first().cloned().unwrap_or_default();
            let mut body = format!(
                "{}\n{}\ntolerances: {}",
                c.failures.join("\n"),
                figures(c),
                tolerance_text(c)
            );
            for d in c.provenance_differences() {
                body.push_str("\nprovenance differs: ");
                body.push_str(&d);
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

fn markdown(cases: &[Case], info: &RunInfo) -> String {
    let failed = cases.iter().filter(|c| !c.passed()).count();
    let mut m = String::new();
    let _ = writeln!(
        m,
        "### luz golden: {} of {} passed{}\n",
        cases.len() - failed,
        cases.len(),
        if failed > 0 { " ❌" } else { " ✅" }
    );
    let _ = writeln!(m, "Rendered on {}.\n", md_cell(&info.device));
    m.push_str("| scene | result | FLIP mean | max abs | differing pixels | reason |\n");
    m.push_str("|---|---|---|---|---|---|\n");
    for c in cases {
        let (flip, abs, bad) = match &c.report {
            Some(r) => (
                format!("{:.6}", r.flip_mean),
                r.max_abs.to_string(),
                r.differing_pixels.to_string(),
            ),
            None => ("–".into(), "–".into(), "–".into()),
        };
        let _ = writeln!(
            m,
            "| {} | {} | {flip} | {abs} | {bad} | {} |",
            md_cell(&c.name),
            status_word(c),
            md_cell(&c.failures.join("; "))
        );
    }
    m
}
