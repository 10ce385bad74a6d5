//! The bad-input corpus (`tests/bad_inputs/`, issue 8): malformed, truncated, absurd or missing
//! inputs for every loader — scene JSON, OBJ/MTL, texture PNG/EXR/HDR, environment HDR/EXR and
//! the images of `luz diff` — each run through the real binary.
//!
//! `tests/bad_inputs/EXPECTATIONS.json` has one entry per file or folder of the corpus (the test
//! fails on a file without an entry and on an entry without a file). An entry lists `runs`: the
//! command's arguments (placeholders `{file}`, `{dir}`, `{tmp}`), the expected exit code and
//! substrings of stderr. Every run must not panic and must not report a Vulkan validation error
//! (`LUZ_VALIDATION=1`). Optional `stdout` substrings are checked too. A failing run (unless
//! `"error": false`: a verdict such as `luz diff` beyond a tolerance) must name the offending file (`names`, by default the
//! entry itself). A succeeding run must report `validation: 0 errors`, and any EXR it wrote must
//! be free of NaN and Inf. Helper files (OBJ, MTL, images used by the scenes) list the scenes
//! that use them in `helper_for`. Big inputs are generated at test time (`generate`): the scene
//! is copied into a scratch folder and the named files are written next to it.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use serde_json::Value;

use common::{luz_command, root, scratch};

fn corpus() -> PathBuf {
    root().join("tests/bad_inputs")
}

/// Writes a generated input named by `kind` to `path`.
fn generate(kind: &str, path: &Path) {
    const MIB: usize = 1 << 20;
    let text = match kind {
        // A valid triangle with a 1 MiB comment line in the middle.
        "long_comment_line" => format!(
            "v 0 0 0\nv 1 0 0\nv 0 1 0\n# {}\nf 1 2 3\n",
            "x".repeat(MIB)
        ),
        // A vertex line of 1 MiB: 3 coordinates followed by 2^19 more numbers.
        "long_vertex_line" => format!(
            "v 0 0 0 {}\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
            "0 ".repeat(MIB / 2)
        ),
        // A 16×8 equirectangular EXR holding NaN, ±Inf, negative and huge values.
        "nan_inf_exr" => {
            let mut img = luz::imageio::LinearImage::filled(16, 8, [0.5, 0.5, 0.5, 1.0]);
            let bad = [
                f32::NAN,
                f32::INFINITY,
                f32::NEG_INFINITY,
                -1.0,
                1e30,
                f32::MAX,
            ];
            for (i, v) in bad.into_iter().enumerate() {
                *img.pixel_mut(i as u32 * 2, i as u32 % 8) = [v, v, 0.5, 1.0];
            }
            luz::imageio::save(path, &img, 0.0, luz::color::Tonemap::None).unwrap();
            return;
        }
        other => panic!("EXPECTATIONS.json: unknown generator {other:?}"),
    };
    std::fs::write(path, text).unwrap();
}

fn strings(v: &Value, key: &str) -> Vec<String> {
    match v.get(key) {
        None => Vec::new(),
        Some(Value::Array(a)) => a
            .iter()
            .map(|s| {
                s.as_str()
                    .unwrap_or_else(|| panic!("{key}: expected strings, got {s}"))
                    .to_string()
            })
            .collect(),
        Some(other) => panic!("{key}: expected an array of strings, got {other}"),
    }
}

/// True when the scene `user`, or the OBJ or MTL file of the same stem next to it, mentions
/// `helper`.
fn uses(dir: &Path, user: &str, helper: &str) -> bool {
    let stem = user.strip_suffix(".json").unwrap_or(user);
    [
        user.to_string(),
        format!("{stem}.obj"),
        format!("{stem}.mtl"),
    ]
    .iter()
    .any(|f| std::fs::read_to_string(dir.join(f)).is_ok_and(|t| t.contains(helper)))
}

/// Runs one case; returns the problems found (empty when it behaved as expected).
fn run_case(name: &str, entry: &Value) -> Vec<String> {
    let dir = corpus();
    let mut problems = Vec::new();
    let runs = entry["runs"].as_array().cloned().unwrap_or_default();
    for (i, run) in runs.iter().enumerate() {
        let tmp = scratch(&format!("{name}-{i}"));
        let mut file = dir.join(name);
        if let Some(generated) = entry.get("generate").and_then(Value::as_object) {
            file = tmp.join(name);
            std::fs::copy(dir.join(name), &file).unwrap();
            for (out, kind) in generated {
                generate(kind.as_str().expect("generator name"), &tmp.join(out));
            }
        }
        let fill = |a: &str| {
            a.replace("{file}", file.to_str().unwrap())
                .replace("{dir}", dir.to_str().unwrap())
                .replace("{tmp}", tmp.to_str().unwrap())
        };
        let args: Vec<String> = strings(run, "args").iter().map(|a| fill(a)).collect();
        let expected_exit = run["exit"].as_i64().expect("exit") as i32;
        let out = common::run(&mut luz_command(&args));
        let code = out.code;
        let stderr = &out.stderr;
        let label = format!("{name} (luz {})", strings(run, "args").join(" "));
        let mut fail = |why: String| problems.push(format!("{label}: {why}\n    stderr: {stderr}"));
        if code != expected_exit {
            fail(format!("exit code {code}, expected {expected_exit}"));
        }
        if stderr.contains("panicked") {
            fail("panicked".into());
        }
        if stderr.contains("VUID") || stderr.lines().any(|l| l.contains("validation error")) {
            fail("a Vulkan validation error".into());
        }
        if let Some(line) = stderr.lines().find(|l| l.starts_with("validation:")) {
            if !line.starts_with("validation: 0 errors") {
                fail(format!("validation reports errors: {line}"));
            }
        }
        for s in strings(run, "stderr") {
            if !stderr.contains(s.as_str()) {
                fail(format!("stderr does not contain {s:?}"));
            }
        }
        let stdout = &out.stdout;
        for s in strings(run, "stdout") {
            if !stdout.contains(s.as_str()) {
                fail(format!("stdout does not contain {s:?}; stdout: {stdout}"));
            }
        }
        // A non-zero exit is an error (one message naming the file) unless "error": false says
        // it is a verdict, as `luz diff` beyond a tolerance.
        let is_error = run
            .get("error")
            .and_then(Value::as_bool)
            .unwrap_or(expected_exit != 0);
        if is_error {
            let mut names = strings(run, "names");
            if names.is_empty() {
                names.push(name.to_string());
            }
            for n in names {
                if !stderr.contains(n.as_str()) {
                    fail(format!("the message does not name {n}"));
                }
            }
            if !stderr.contains("luz: error:") {
                fail("no \"luz: error:\" line".into());
            }
        } else if expected_exit == 0 {
            if !stderr.contains("validation: 0 errors") {
                fail("no \"validation: 0 errors\" (did it reach the GPU?)".into());
            }
            let exr = tmp.join("out.exr");
            if exr.exists() {
                match luz::imageio::load(&exr) {
                    Ok(img) if img.non_finite_pixels() > 0 => {
                        fail(format!("{} NaN/Inf pixels", img.non_finite_pixels()))
                    }
                    Ok(_) => {}
                    Err(e) => fail(format!("cannot read the output: {e}")),
                }
            }
        }
    }
    problems
}

#[test]
fn bad_input_corpus_matches_its_expectations() {
    let start = Instant::now();
    let dir = corpus();
    let text = std::fs::read_to_string(dir.join("EXPECTATIONS.json")).expect("EXPECTATIONS.json");
    let doc: Value = serde_json::from_str(&text).expect("EXPECTATIONS.json is JSON");
    let cases: BTreeMap<String, Value> = doc["cases"]
        .as_object()
        .expect("a \"cases\" object")
        .iter()
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect();

    let mut problems = Vec::new();
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "EXPECTATIONS.json")
        .collect();
    files.sort();
    assert!(files.len() >= 50, "only {} corpus files", files.len());
    for f in &files {
        if !cases.contains_key(f) {
            problems.push(format!("{f}: no entry in EXPECTATIONS.json"));
        }
    }
    for (name, entry) in &cases {
        if !files.contains(name) {
            problems.push(format!(
                "{name}: in EXPECTATIONS.json but not in the corpus"
            ));
        }
        let runs = entry["runs"].as_array().map_or(0, Vec::len);
        let helper_for = strings(entry, "helper_for");
        if runs == 0 && helper_for.is_empty() {
            problems.push(format!("{name}: neither runs nor helper_for"));
        }
        for user in helper_for {
            if !cases.contains_key(&user) {
                problems.push(format!(
                    "{name}: helper_for names {user}, not in the corpus"
                ));
            } else if !uses(&dir, &user, name) {
                problems.push(format!(
                    "{name}: helper_for names {user}, which does not use it"
                ));
            }
        }
    }
    assert!(problems.is_empty(), "\n{}", problems.join("\n"));

    // Two workers: the runs are independent processes.
    let names: Vec<&String> = cases.keys().collect();
    let chunks: Vec<Vec<&String>> = (0..2)
        .map(|w| names.iter().skip(w).step_by(2).copied().collect())
        .collect();
    let results: Vec<Vec<String>> = std::thread::scope(|s| {
        let handles: Vec<_> = chunks
            .iter()
            .map(|chunk| {
                let cases = &cases;
                s.spawn(move || {
                    chunk
                        .iter()
                        .flat_map(|n| run_case(n, &cases[n.as_str()]))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let problems: Vec<String> = results.into_iter().flatten().collect();
    let run_count: usize = cases
        .values()
        .map(|e| e["runs"].as_array().map_or(0, Vec::len))
        .sum();
    println!(
        "{} corpus entries, {run_count} runs in {:.1} s",
        cases.len(),
        start.elapsed().as_secs_f64()
    );
    assert!(problems.is_empty(), "\n{}", problems.join("\n\n"));
}
