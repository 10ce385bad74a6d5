//! `luz golden` through the binary: bless, check, per-case failures that do not stop the run,
//! sidecar tolerances, bad input, and the report (HTML loaded in a real headless Chromium, JUnit
//! XML, Markdown). Validation is on in every run and must stay silent.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{luz, scratch};

/// A small scene: one sphere of `colour` under a directional light, `w × h` pixels.
fn scene(colour: [f32; 3], w: u32, h: u32) -> String {
    format!(
        r#"{{
  "camera": {{"position": [0, 0, 4], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 40, "near": 0.1, "far": 10}},
  "output": {{"width": {w}, "height": {h}, "msaa": 1, "tonemap": "none"}},
  "lights": [{{"type": "directional", "direction": [-0.4, -0.5, -0.8], "color": [1, 1, 1], "intensity": 1}}],
  "materials": {{"m": {{"model": "lambert", "albedo": [{}, {}, {}]}}}},
  "objects": [{{"mesh": {{"type": "sphere", "radius": 1, "segments": 32, "rings": 16}}, "material": "m"}}]
}}"#,
        colour[0], colour[1], colour[2]
    )
}

fn write(path: &Path, text: &str) {
    std::fs::write(path, text).unwrap();
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs `luz golden` and checks the run was clean: no panic, validation silent.
fn golden(args: &[&str]) -> (i32, String, String) {
    let mut all = vec!["golden"];
    all.extend_from_slice(args);
    let (code, out, err) = luz(&all);
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        err.contains("validation: 0 errors, 0 warnings"),
        "validation must be on and silent: {err}"
    );
    (code, out, err)
}

const RED: [f32; 3] = [0.8, 0.2, 0.1];
const BLUE: [f32; 3] = [0.1, 0.3, 0.8];

#[test]
fn bless_check_and_failures_that_do_not_stop_the_run() {
    let dir = scratch("golden-run");
    let scenes = dir.join("scenes");
    let goldens = dir.join("goldens");
    std::fs::create_dir_all(&scenes).unwrap();
    write(&scenes.join("red.json"), &scene(RED, 96, 64));
    write(&scenes.join("blue.json"), &scene(BLUE, 96, 64));

    // Bless: the folder is created, both goldens written.
    let (code, out, _) = golden(&[s(&scenes), "--goldens", s(&goldens), "--bless"]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("BLESSED (new) blue"), "{out}");
    assert!(out.contains("BLESSED (new) red"), "{out}");
    assert!(
        out.contains("blessed 2 scenes (2 new, 0 unchanged, 0 replaced)"),
        "{out}"
    );
    let red_png = goldens.join("red.png");
    let img = luz::imageio::load(&red_png).unwrap();
    assert_eq!((img.width, img.height), (96, 64));
    let bytes = std::fs::read(&red_png).unwrap();

    // Blessing again changes nothing on disk.
    let (code, out, _) = golden(&[s(&scenes), "--goldens", s(&goldens), "--bless"]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("BLESSED (unchanged) red"), "{out}");
    assert_eq!(std::fs::read(&red_png).unwrap(), bytes);

    // Check: both pass, byte-exact on one machine, two at once.
    let (code, out, _) = golden(&[s(&scenes), "--goldens", s(&goldens), "--jobs", "2"]);
    assert_eq!(code, 0, "{out}");
    assert!(
        out.contains("PASS blue  FLIP mean 0.000000, max abs 0"),
        "{out}"
    );
    assert!(
        out.contains("PASS red   FLIP mean 0.000000, max abs 0"),
        "{out}"
    );
    assert!(
        out.contains("luz golden: 2 passed, 0 failed, 2 scenes"),
        "{out}"
    );

    // Break things: blue changes colour, a scene without golden, a broken scene, an OBJ, a scene
    // whose size changed. Every case is reported; the run goes on.
    write(&scenes.join("blue.json"), &scene([0.2, 0.8, 0.2], 96, 64));
    write(&scenes.join("new.json"), &scene(RED, 32, 32));
    write(&scenes.join("broken.json"), "{ \"camera\": ");
    write(&scenes.join("model.obj"), "v 0 0 0\n");
    write(&scenes.join("wide.json"), &scene(RED, 96, 64));
    let (code, out, _) = golden(&[
        s(&scenes.join("wide.json")),
        "--goldens",
        s(&goldens),
        "--bless",
    ]);
    assert_eq!(code, 0, "{out}");
    write(&scenes.join("wide.json"), &scene(RED, 80, 64));
    let (code, out, _) = golden(&[s(&scenes), "--goldens", s(&goldens)]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("FAIL blue"), "{out}");
    assert!(out.contains("exceeds max-flip-mean 0.005"), "{out}");
    // The scene file changed: its hash says so.
    assert!(
        out.contains("provenance differs: luz.scene_hash: golden fnv1a64:"),
        "{out}"
    );
    assert!(
        out.contains(&format!(
            "no golden {} (run with --bless",
            goldens.join("new.png").display()
        )),
        "{out}"
    );
    assert!(out.contains("broken.json"), "{out}");
    // An OBJ is a scene (the model with the default rig); this one is broken: its case fails
    // with the loader's reason.
    assert!(
        out.contains("model.obj") && out.contains("no faces"),
        "{out}"
    );
    assert!(
        out.contains("size mismatch") && out.contains("is 96×64, the scene renders 80×64"),
        "{out}"
    );
    assert!(out.contains("PASS red"), "{out}");
    assert!(
        out.contains("luz golden: 1 passed, 5 failed, 6 scenes"),
        "{out}"
    );

    // A sidecar beside the goldens turns blue's checks off: it passes, the figures still shown.
    write(
        &goldens.join("blue.golden.json"),
        r#"{"max_flip_mean": null, "max_abs": null, "max_bad_pixels": null}"#,
    );
    let (code, out, _) = golden(&[s(&scenes.join("blue.json")), "--goldens", s(&goldens)]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("PASS blue"), "{out}");
    assert!(
        !out.contains("FLIP mean 0.000000"),
        "blue did change: {out}"
    );
    // A broken sidecar is that case's failure, naming the file.
    write(&goldens.join("blue.golden.json"), r#"{"max_flip": 1}"#);
    let (code, out, _) = golden(&[s(&scenes.join("blue.json")), "--goldens", s(&goldens)]);
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains("blue.golden.json: unknown field \"max_flip\""),
        "{out}"
    );
    std::fs::remove_file(goldens.join("blue.golden.json")).unwrap();

    // Bless the change: what changed is printed.
    let (code, out, _) = golden(&[
        s(&scenes.join("blue.json")),
        "--goldens",
        s(&goldens),
        "--bless",
    ]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("BLESSED (changed) blue"), "{out}");
    assert!(out.contains("pixels changed"), "{out}");
}

#[test]
fn bad_input_is_named_before_any_rendering() {
    let dir = scratch("golden-bad");
    let scenes = dir.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    write(&scenes.join("a.json"), &scene(RED, 16, 16));
    let goldens = dir.join("goldens");
    std::fs::create_dir_all(&goldens).unwrap();
    let check = |args: &[&str], needle: &str| {
        let mut all = vec!["golden"];
        all.extend_from_slice(args);
        let (code, out, err) = luz(&all);
        assert_eq!(code, 1, "{args:?}: {out}\n{err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(
            err.contains("luz: error:") && err.contains(needle),
            "{args:?}: expected {needle:?} in: {err}"
        );
        assert!(!out.contains("device:"), "nothing is rendered: {out}");
    };
    let missing = dir.join("no-such-scene.json");
    check(
        &[s(&missing), "--goldens", s(&goldens)],
        &format!("{}: no such scene file or folder", missing.display()),
    );
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    check(
        &[s(&empty), "--goldens", s(&goldens)],
        "no scene files in it",
    );
    let nowhere = dir.join("no-goldens");
    check(
        &[s(&scenes), "--goldens", s(&nowhere)],
        &format!("goldens folder {}: no such folder", nowhere.display()),
    );
    let file = scenes.join("a.json");
    check(&[s(&scenes), "--goldens", s(&file)], "a.json: not a folder");
    // A report path under a file cannot be written.
    let report = file.join("report");
    check(
        &[s(&scenes), "--goldens", s(&goldens), "--report", s(&report)],
        &format!("cannot write the report to {}", report.display()),
    );
    // An unreadable goldens folder (permissions mean nothing to root).
    let locked = dir.join("locked");
    std::fs::create_dir_all(&locked).unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o000)).unwrap();
    if std::fs::read_dir(&locked).is_err() {
        check(
            &[s(&scenes), "--goldens", s(&locked)],
            &format!("goldens folder {}: cannot read it", locked.display()),
        );
    } else {
        eprintln!("SKIPPED: the unreadable-folder case (running as root)");
    }
    std::fs::set_permissions(&locked, std::fs::Permissions::from_mode(0o755)).unwrap();
    // No scenes at all: clap's own message.
    let (code, _, err) = luz(&["golden", "--goldens", s(&goldens)]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("SCENES"), "{err}");
}

/// Chromium as the issue asks, or None with a visible note.
fn chromium() -> Option<PathBuf> {
    for name in ["chromium", "chromium-browser"] {
        if Command::new(name)
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
        {
            return Some(PathBuf::from(name));
        }
    }
    eprintln!("SKIPPED: chromium is not installed (scripts/setup.sh installs it; CI has it)");
    None
}

/// The page as a headless Chromium sees it after loading (its images and scripts run).
fn dump_dom(browser: &Path, page: &Path, profile: &Path) -> String {
    let out = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--virtual-time-budget=5000",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg("--dump-dom")
        .arg(format!("file://{}", page.display()))
        .output()
        .expect("run chromium");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

#[test]
fn report_in_a_browser_junit_and_markdown() {
    let dir = scratch("golden-report");
    let scenes = dir.join("scenes");
    let goldens = dir.join("goldens");
    std::fs::create_dir_all(&scenes).unwrap();
    write(&scenes.join("same.json"), &scene(RED, 64, 48));
    write(&scenes.join("changed <&>.json"), &scene(BLUE, 64, 48));
    let (code, out, _) = golden(&[s(&scenes), "--goldens", s(&goldens), "--bless"]);
    assert_eq!(code, 0, "{out}");
    write(
        &scenes.join("changed <&>.json"),
        &scene([0.9, 0.9, 0.1], 64, 48),
    );
    let report = dir.join("report");
    let (code, out, _) = golden(&[s(&scenes), "--goldens", s(&goldens), "--report", s(&report)]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains(&format!("report: {}", report.join("index.html").display())));

    // JUnit: two test cases, one failure with its figures; the name escaped.
    let junit = std::fs::read_to_string(report.join("junit.xml")).unwrap();
    assert!(junit.contains("tests=\"2\" failures=\"1\""), "{junit}");
    assert_eq!(junit.matches("<testcase ").count(), 2, "{junit}");
    assert_eq!(junit.matches("<failure ").count(), 1, "{junit}");
    assert!(junit.contains("name=\"changed &lt;&amp;&gt;\""), "{junit}");
    assert!(junit.contains("exceeds max-flip-mean 0.005"), "{junit}");
    assert!(
        junit.contains("provenance differs: luz.scene_hash"),
        "{junit}"
    );
    // Markdown: a table row per scene.
    let md = std::fs::read_to_string(report.join("summary.md")).unwrap();
    assert!(md.contains("luz golden: 1 of 2 passed"), "{md}");
    assert!(md.contains("| same | PASS | 0.000000 | 0 | 0 |"), "{md}");
    assert!(md.contains("| changed <&> | FAIL |"), "{md}");

    // The page, in a browser: every image loads, the failing case is marked.
    let html = std::fs::read_to_string(report.join("index.html")).unwrap();
    assert!(
        !html.contains("http://") && !html.contains("https://"),
        "no network"
    );
    let Some(browser) = chromium() else { return };
    let profile = dir.join("chromium-profile");
    let dom = dump_dom(&browser, &report.join("index.html"), &profile);
    // Two cases × expected, actual, FLIP + the fade pair = 10 images.
    assert!(dom.contains("data-images-loaded=\"10/10\""), "{dom}");
    assert!(!dom.contains("data-loaded=\"false\""), "{dom}");
    assert!(dom.contains("1 of 2 failed"), "{dom}");
    let failing = dom
        .split("<section ")
        .skip(1)
        .find(|s| s.contains("changed &lt;&amp;&gt;"))
        .expect("the changed case's section");
    assert!(failing.contains("class=\"case fail\""), "{failing}");
    assert!(failing.contains(">FAIL<"), "{failing}");
    let passing = dom
        .split("<section ")
        .skip(1)
        .find(|s| s.contains("<h2>same "))
        .expect("the same case's section");
    assert!(passing.contains("class=\"case pass\""), "{passing}");
    // The check can fail: a missing image is seen.
    let gone = std::fs::read_dir(report.join("images"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.to_string_lossy().ends_with(".flip.png"))
        .unwrap();
    std::fs::remove_file(gone).unwrap();
    let dom = dump_dom(&browser, &report.join("index.html"), &profile);
    assert!(dom.contains("data-images-loaded=\"9/10\""), "{dom}");
    assert!(dom.contains("data-loaded=\"false\""), "{dom}");
}

/// luz's own goldens run literally with `luz golden tests/golden`: every golden has a case file
/// naming its scene, size and IBL sizes
/// (the golden tests load their scenes through the same files: `tests/common/vulkan.rs`), and
/// every case passes.
#[test]
fn the_projects_goldens_pass_with_luz_golden() {
    let dir = common::root().join("tests/golden");
    for e in std::fs::read_dir(&dir).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "png") {
            let stem = p.file_stem().unwrap().to_string_lossy().into_owned();
            let case = dir.join(format!("{stem}.golden.json"));
            assert!(
                case.is_file(),
                "{stem}.png has no case file {}",
                case.display()
            );
        }
    }
    if common::shared_dir("gltf").is_none() {
        return;
    }
    let (code, out, err) = golden(&[s(&dir), "--goldens", s(&dir), "--jobs", "2"]);
    assert_eq!(code, 0, "{out}\n{err}");
    let cases = std::fs::read_dir(&dir)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .path()
                .to_string_lossy()
                .ends_with(".golden.json")
        })
        .count();
    assert!(
        out.contains(&format!(
            "luz golden: {cases} passed, 0 failed, {cases} scenes"
        )),
        "{out}"
    );
}

/// Tolerances in the scene's `output.golden`, overridden field by field by a sidecar; bad
/// values name the field. EXR goldens (`--format exr`) compare the linear radiance.
#[test]
fn scene_tolerances_and_exr_goldens() {
    let dir = scratch("golden-output-tol");
    let scenes = dir.join("scenes");
    let goldens = dir.join("goldens");
    std::fs::create_dir_all(&scenes).unwrap();
    write(&scenes.join("ball.json"), &scene(RED, 48, 32));
    for fmt in ["png", "exr"] {
        let (code, out, _) = golden(&[
            s(&scenes),
            "--goldens",
            s(&goldens),
            "--bless",
            "--format",
            fmt,
        ]);
        assert_eq!(code, 0, "{out}");
        assert!(goldens.join(format!("ball.{fmt}")).is_file(), "{out}");
    }
    // A visibly different ball fails both formats by default.
    write(&scenes.join("ball.json"), &scene(BLUE, 48, 32));
    for fmt in ["png", "exr"] {
        let (code, out, _) = golden(&[s(&scenes), "--goldens", s(&goldens), "--format", fmt]);
        assert_eq!(code, 1, "{fmt}: {out}");
        assert!(out.contains("FAIL ball"), "{out}");
    }
    // The scene's own tolerances turn the checks off...
    let lenient = scene(BLUE, 48, 32).replace(
        r#""tonemap": "none"}"#,
        r#""tonemap": "none", "golden": {"max_flip_mean": null, "max_abs": null, "max_bad_pixels": null}}"#,
    );
    write(&scenes.join("ball.json"), &lenient);
    for fmt in ["png", "exr"] {
        let (code, out, _) = golden(&[s(&scenes), "--goldens", s(&goldens), "--format", fmt]);
        assert_eq!(code, 0, "{fmt}: {out}");
    }
    // ...and a sidecar wins over them, field by field.
    write(&goldens.join("ball.golden.json"), r#"{"max_abs": 8}"#);
    let (code, out, _) = golden(&[s(&scenes), "--goldens", s(&goldens)]);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("exceeds max-abs 8"), "{out}");
    assert!(!out.contains("max-flip-mean"), "{out}");
    std::fs::remove_file(goldens.join("ball.golden.json")).unwrap();
    // Bad values: the case fails naming the scene file and the field.
    write(
        &scenes.join("ball.json"),
        &lenient.replace(r#""max_abs": null"#, r#""max_abs": -2"#),
    );
    let (code, out, _) = golden(&[s(&scenes), "--goldens", s(&goldens)]);
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains("ball.json")
            && out.contains("output.golden.max_abs")
            && out.contains("must be a number ≥ 0"),
        "{out}"
    );
}

// ---------------------------------------------------------------------------------------------
// Issue 39: shards and merged reports, masks, regions.

fn cases_of(report: &Path) -> Vec<serde_json::Value> {
    let text = std::fs::read_to_string(report.join("cases.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["cases"].as_array().unwrap().clone()
}

/// What a case shows, without where its images are (those are renamed by a merge) nor its time.
fn shown(c: &serde_json::Value) -> String {
    let mut c = c.clone();
    let o = c.as_object_mut().unwrap();
    for k in ["expected", "actual", "flip", "mask", "millis"] {
        o.remove(k);
    }
    c.to_string()
}

/// `--shard K/N` runs a contiguous 1/N of the sorted cases; the N shards' union is the
/// unsharded run (the same cases, verdicts and figures, each once), and `luz golden merge`
/// writes one report of them in the run's order, as one job would (checked in Chromium).
#[test]
fn shards_union_is_the_unsharded_run_and_merge_lists_each_case_once() {
    let dir = scratch("golden-shards");
    let scenes = dir.join("scenes");
    let goldens = dir.join("goldens");
    std::fs::create_dir_all(&scenes).unwrap();
    let names = ["a1", "b2", "c3", "d4", "e5", "f6", "g7"];
    for (i, n) in names.iter().enumerate() {
        let t = i as f32 / 7.0;
        write(
            &scenes.join(format!("{n}.json")),
            &scene([t, 0.5, 1.0 - t], 24, 16),
        );
    }
    let (code, out, _) = golden(&[s(&scenes), "--goldens", s(&goldens), "--bless"]);
    assert_eq!(code, 0, "{out}");
    // d4 changes: one failure to carry through.
    write(&scenes.join("d4.json"), &scene([0.9, 0.9, 0.1], 24, 16));

    let full = dir.join("full");
    let (code, out, _) = golden(&[s(&scenes), "--goldens", s(&goldens), "--report", s(&full)]);
    assert_eq!(code, 1, "{out}");
    let full_cases = cases_of(&full);
    assert_eq!(full_cases.len(), 7);

    let n = 3;
    let mut union: Vec<String> = Vec::new();
    let mut sizes = Vec::new();
    let mut shard_dirs = Vec::new();
    for k in 1..=n {
        let rep = dir.join(format!("shard{k}"));
        let (code, out, _) = golden(&[
            s(&scenes),
            "--goldens",
            s(&goldens),
            "--shard",
            &format!("{k}/{n}"),
            "--report",
            s(&rep),
        ]);
        let cases = cases_of(&rep);
        let has_d4 = cases.iter().any(|c| c["name"] == "d4");
        assert_eq!(code, i32::from(has_d4), "{out}");
        assert!(
            out.contains(&format!("shard {k}/{n}: {} of 7 cases", cases.len())),
            "{out}"
        );
        sizes.push(cases.len());
        union.extend(
            cases
                .iter()
                .map(|c| c["name"].as_str().unwrap().to_string()),
        );
        shard_dirs.push(rep);
    }
    // Balanced, and every case in exactly one shard.
    assert_eq!(sizes, [2, 2, 3]);
    let mut sorted = union.clone();
    sorted.sort();
    sorted.dedup();
    assert_eq!(sorted.len(), union.len(), "a case ran twice: {union:?}");
    assert_eq!(union, names, "the shards in order are the whole run");

    // Merged (given in any order): exactly the unsharded run's cases, as shown.
    let merged = dir.join("merged");
    let dirs: Vec<&str> = [2, 0, 1].iter().map(|&i| s(&shard_dirs[i])).collect();
    let mut args = vec!["golden", "merge"];
    args.extend(&dirs);
    args.extend(["--report", s(&merged)]);
    let (code, out, err) = luz(&args);
    assert_eq!(code, 1, "one case failed: {out}\n{err}");
    assert!(
        out.contains("luz golden merge: 3 reports, 6 passed, 1 failed, 7 scenes"),
        "{out}"
    );
    let merged_cases = cases_of(&merged);
    let a: Vec<String> = full_cases.iter().map(shown).collect();
    let b: Vec<String> = merged_cases.iter().map(shown).collect();
    assert_eq!(a, b);
    let junit = std::fs::read_to_string(merged.join("junit.xml")).unwrap();
    assert!(junit.contains("tests=\"7\" failures=\"1\""), "{junit}");
    assert_eq!(junit.matches("<testcase ").count(), 7, "{junit}");
    for n in names {
        assert_eq!(
            junit.matches(&format!("name=\"{n}\"")).count(),
            1,
            "{n}: {junit}"
        );
    }
    let md = std::fs::read_to_string(merged.join("summary.md")).unwrap();
    assert!(md.contains("luz golden: 6 of 7 passed"), "{md}");
    assert_eq!(
        md.matches("| PASS |").count() + md.matches("| FAIL |").count(),
        7
    );

    // A missing shard, a shard given twice, a folder that is no report: errors naming them.
    let bad_out = dir.join("bad");
    let bad = |dirs: &[&str], needle: &str| {
        let mut args = vec!["golden", "merge"];
        args.extend(dirs);
        args.extend(["--report", s(&bad_out)]);
        let (code, out, err) = luz(&args[..]);
        assert_eq!(code, 1, "{out}\n{err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(err.contains(needle), "expected {needle:?}: {err}");
    };
    bad(&[dirs[0], dirs[1]], "shard 2/3 missing");
    bad(&[dirs[0], dirs[1], dirs[1], dirs[2]], "given twice");
    bad(&[s(&scenes)], "cases.json");

    // The merged page in a browser: 7 sections, every image loads (expected, actual, FLIP and
    // the fade pair per case).
    let Some(browser) = chromium() else { return };
    let dom = dump_dom(&browser, &merged.join("index.html"), &dir.join("profile"));
    assert!(dom.contains("data-images-loaded=\"35/35\""), "{dom}");
    assert_eq!(dom.matches("<section ").count(), 7);
    assert!(dom.contains("1 of 7 failed"), "{dom}");
    for n in names {
        assert_eq!(dom.matches(&format!("<h2>{n} ")).count(), 1, "{n}");
    }
}

/// Paints the rectangle `[x, y, w, h]` of a PNG golden with `f(old)` (what a changed render
/// would show there), keeping its size.
fn paint(png: &Path, [x0, y0, w, h]: [u32; 4], f: impl Fn([u8; 3]) -> [u8; 3]) {
    let mut img = image::open(png).unwrap().to_rgb8();
    for y in y0..y0 + h {
        for x in x0..x0 + w {
            let p = img.get_pixel_mut(x, y);
            p.0 = f(p.0);
        }
    }
    img.save(png).unwrap();
}

/// A mask PNG of `w × h`, white in `rect`.
fn mask(path: &Path, w: u32, h: u32, [x0, y0, rw, rh]: [u32; 4]) {
    let img = image::GrayImage::from_fn(w, h, |x, y| {
        let inside = x >= x0 && x < x0 + rw && y >= y0 && y < y0 + rh;
        image::Luma([if inside { 255 } else { 0 }])
    });
    img.save(path).unwrap();
}

/// A golden changed in one patch: the case fails; with a mask over the patch it passes, with
/// the mask elsewhere it fails; the report hatches the masked pixels (Chromium loads the overlay).
#[test]
fn a_masked_change_passes_and_the_same_change_unmasked_fails() {
    let dir = scratch("golden-mask");
    let scenes = dir.join("scenes");
    let goldens = dir.join("goldens");
    std::fs::create_dir_all(&scenes).unwrap();
    write(&scenes.join("ball.json"), &scene(RED, 64, 48));
    let (code, out, _) = golden(&[s(&scenes), "--goldens", s(&goldens), "--bless"]);
    assert_eq!(code, 0, "{out}");
    let patch = [20, 14, 12, 10];
    paint(&goldens.join("ball.png"), patch, |_| [255, 0, 255]);
    let check = |report: Option<&Path>| {
        let mut args = vec![s(&scenes), "--goldens", s(&goldens)];
        if let Some(r) = report {
            args.extend(["--report", s(r)]);
        }
        golden(&args)
    };
    // Unmasked: the change fails.
    let (code, out, _) = check(None);
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains("FAIL ball") && out.contains("exceeds max-abs 8"),
        "{out}"
    );
    // Masked (the mask a little larger than the patch): it passes, byte-exact elsewhere.
    mask(&goldens.join("ball.mask.png"), 64, 48, [18, 12, 16, 14]);
    write(
        &goldens.join("ball.golden.json"),
        r#"{"mask": "ball.mask.png"}"#,
    );
    let report = dir.join("report");
    let (code, out, _) = check(Some(&report));
    assert_eq!(code, 0, "{out}");
    assert!(
        out.contains("PASS ball  FLIP mean 0.000000, max abs 0"),
        "{out}"
    );
    // The same mask elsewhere: the change is seen again.
    mask(&goldens.join("ball.mask.png"), 64, 48, [40, 0, 16, 14]);
    let (code, out, _) = check(None);
    assert_eq!(code, 1, "{out}");
    assert!(out.contains("exceeds max-abs 8"), "{out}");
    // A mask of another size or a missing one: the case fails naming the file and field.
    mask(&goldens.join("ball.mask.png"), 32, 48, [0, 0, 1, 1]);
    let (code, out, _) = check(None);
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains("ball.golden.json: mask:")
            && out.contains("the mask is 32×48, the golden 64×48"),
        "{out}"
    );
    write(&goldens.join("ball.golden.json"), r#"{"mask": 3}"#);
    let (code, out, _) = check(None);
    assert_eq!(code, 1, "{out}");
    assert!(
        out.contains("ball.golden.json: mask: must be a PNG file name"),
        "{out}"
    );

    // The report of the passing run: the mask's 16×14 white pixels hatched.
    let cases = cases_of(&report);
    assert_eq!(
        cases[0]["ignored"],
        "left out: 224 masked pixels (hatched), 0 pixels forgiven as anti-aliasing (yellow)"
    );
    let overlay = image::open(report.join(cases[0]["mask"].as_str().unwrap()))
        .unwrap()
        .to_rgba8();
    assert!(overlay.get_pixel(20, 14).0[3] > 0, "masked: drawn");
    assert_eq!(overlay.get_pixel(5, 5).0[3], 0, "not masked: transparent");
    let Some(browser) = chromium() else { return };
    let dom = dump_dom(&browser, &report.join("index.html"), &dir.join("profile"));
    // expected, actual, FLIP, the hatching over expected and actual, the fade pair.
    assert!(dom.contains("data-images-loaded=\"7/7\""), "{dom}");
    assert_eq!(dom.matches("class=\"top hatch\"").count(), 2, "{dom}");
    assert!(dom.contains("224 masked pixels"), "{dom}");
}

/// A region's tolerances apply inside it only: a lenient region over a large change passes
/// while the same region elsewhere fails; a strict region over a small change (within the
/// case's tolerances) fails while the same region elsewhere passes.
#[test]
fn a_region_tolerance_applies_only_inside_its_region() {
    let dir = scratch("golden-region");
    let scenes = dir.join("scenes");
    let goldens = dir.join("goldens");
    std::fs::create_dir_all(&scenes).unwrap();
    write(&scenes.join("ball.json"), &scene(BLUE, 64, 48));
    let (code, out, _) = golden(&[s(&scenes), "--goldens", s(&goldens), "--bless"]);
    assert_eq!(code, 0, "{out}");
    let pristine = std::fs::read(goldens.join("ball.png")).unwrap();
    let sidecar = goldens.join("ball.golden.json");
    let run = || golden(&[s(&scenes), "--goldens", s(&goldens)]);

    // A large change at the patch.
    let patch = [24, 16, 10, 8];
    paint(&goldens.join("ball.png"), patch, |_| [0, 255, 0]);
    let lenient = |rect: [u32; 4]| {
        format!(
            r#"{{"regions": [{{"name": "label", "rect": [{}, {}, {}, {}], "max_abs": null, "max_flip_mean": null, "max_bad_pixels": null}}]}}"#,
            rect[0], rect[1], rect[2], rect[3]
        )
    };
    write(&sidecar, &lenient(patch));
    let (code, out, _) = run();
    assert_eq!(code, 0, "lenient region over the change: {out}");
    assert!(
        out.contains("PASS ball  FLIP mean 0.000000, max abs 0"),
        "{out}"
    );
    write(&sidecar, &lenient([0, 0, 10, 8]));
    let (code, out, _) = run();
    assert_eq!(code, 1, "lenient region elsewhere: {out}");
    assert!(out.contains("exceeds max-abs 8"), "{out}");
    assert!(
        !out.contains("region label:"),
        "the region itself passes: {out}"
    );

    // A small change (2 steps, within the case's tolerances) at the patch.
    std::fs::write(goldens.join("ball.png"), &pristine).unwrap();
    paint(&goldens.join("ball.png"), patch, |p| {
        p.map(|c| c.saturating_add(2))
    });
    std::fs::remove_file(&sidecar).unwrap();
    let (code, out, _) = run();
    assert_eq!(code, 0, "within the case's tolerances: {out}");
    let strict = |rect: [u32; 4]| {
        format!(
            r#"{{"regions": [{{"name": "strict", "rect": [{}, {}, {}, {}], "max_abs": 0}}]}}"#,
            rect[0], rect[1], rect[2], rect[3]
        )
    };
    write(&sidecar, &strict([20, 12, 20, 16]));
    let (code, out, _) = run();
    assert_eq!(code, 1, "strict region over the change: {out}");
    assert!(
        out.contains("region strict: max abs difference 2 exceeds max-abs 0"),
        "{out}"
    );
    write(&sidecar, &strict([0, 0, 16, 12]));
    let (code, out, _) = run();
    assert_eq!(code, 0, "strict region elsewhere: {out}");

    // Bad regions name the field.
    for (bad, needle) in [
        (
            r#"{"regions": [{"rect": [0, 0, 0, 4]}]}"#,
            "regions[0].rect: must be [x, y, width, height]",
        ),
        (
            r#"{"regions": [{"rect": [0, 0, 4, 4], "max_abs": -1}]}"#,
            "regions[0].max_abs: must be a number",
        ),
        (r#"{"regions": [{}]}"#, "regions[0]: needs a rect or a mask"),
        (r#"{"regions": {}}"#, "regions: must be a list"),
    ] {
        write(&sidecar, bad);
        let (code, out, _) = run();
        assert_eq!(code, 1, "{bad}: {out}");
        assert!(
            out.contains(&format!("ball.golden.json: {needle}")),
            "{bad}: {out}"
        );
    }
}
