//! Scene files on disk: every malformed scene under `tests/bad_scenes/` fails with the expected
//! message, every scene under `assets/scenes/` loads, and the real OBJ models load.
//!
//! `tests/bad_scenes/expected.txt` has one line per scene file:
//! `<file name>\t<substring>[\t<more substrings>…]`. The error message must contain the file name
//! and every substring; the first substring includes the JSON path. Lines starting with `#` and
//! blank lines are ignored. Other files in the folder (`.obj`, `.mtl`) are helpers the scenes use.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use luz::scene;

use common::{root, shared_dir, shared_path};

fn expectations(dir: &Path) -> BTreeMap<String, Vec<String>> {
    let text = std::fs::read_to_string(dir.join("expected.txt")).expect("expected.txt");
    let mut map = BTreeMap::new();
    for (n, line) in text.lines().enumerate() {
        if line.trim().is_empty() || line.starts_with('#') {
            continue;
        }
        let mut parts = line.split('\t');
        let file = parts.next().unwrap_or_default().to_string();
        let subs: Vec<String> = parts.map(str::to_string).collect();
        assert!(
            !subs.is_empty() && subs.iter().all(|s| !s.is_empty()),
            "expected.txt line {}: needs <file>\\t<substring>",
            n + 1
        );
        assert!(
            map.insert(file.clone(), subs).is_none(),
            "expected.txt lists {file} twice"
        );
    }
    map
}

#[test]
fn bad_scenes_fail_with_their_expected_messages() {
    let dir = root().join("tests/bad_scenes");
    let mut expected = expectations(&dir);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    assert!(files.len() >= 76, "only {} bad scenes", files.len());
    let mut failures = Vec::new();
    for path in &files {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let Some(subs) = expected.remove(&name) else {
            failures.push(format!("{name}: not listed in expected.txt"));
            continue;
        };
        match scene::load(path) {
            Ok(_) => failures.push(format!("{name}: loaded, but should fail")),
            Err(e) => {
                let msg = e.to_string();
                if !msg.contains(&name) {
                    failures.push(format!("{name}: message does not name the file: {msg}"));
                }
                for s in &subs {
                    if !msg.contains(s.as_str()) {
                        failures.push(format!("{name}: {msg:?}\n    does not contain {s:?}"));
                    }
                }
                println!("{msg}");
            }
        }
    }
    for name in expected.keys() {
        failures.push(format!("{name}: listed in expected.txt but missing"));
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
}

#[test]
fn every_asset_scene_loads() {
    let mut stack = vec![root().join("assets/scenes")];
    let mut count = 0;
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "json") {
                let s = scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
                assert!(s.triangle_count() > 0, "{}", path.display());
                count += 1;
            }
        }
    }
    assert!(count >= 10, "found {count} scenes");
    // The embedded default is one of them, and parses on its own.
    assert!(scene::default_scene().triangle_count() > 0);
}

/// The complete example in docs/scene-format.md is a valid scene.
#[test]
fn documented_example_parses() {
    let doc = std::fs::read_to_string(root().join("docs/scene-format.md")).unwrap();
    let start = doc.find("```json\n").expect("a ```json block") + 8;
    let end = start + doc[start..].find("```").unwrap();
    let mut text = doc[start..end].to_string();
    let teapot = shared_path("models/teapot.obj");
    let replacement = if teapot.is_file() {
        format!("{:?}", teapot.to_str().unwrap())
    } else {
        "\"missing\"".to_string()
    };
    if !teapot.is_file() {
        text = text.replace(
            r#"{ "type": "obj", "path": "../models/teapot.obj" }"#,
            r#"{ "type": "sphere" }"#,
        );
    }
    text = text.replace("\"../models/teapot.obj\"", &replacement);
    let s = scene::parse(&text, Path::new("docs/example.json")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.objects.len(), 5);
    assert_eq!(s.lights.len(), 3);
}

/// Every other ```json block of docs/scene-format.md is a `materials` map (one per model
/// section) that loads, and together they show every physically based model.
#[test]
fn documented_material_examples_parse() {
    let doc = std::fs::read_to_string(root().join("docs/scene-format.md")).unwrap();
    let blocks: Vec<&str> = doc
        .split("```json\n")
        .skip(2)
        .map(|b| &b[..b.find("```").expect("an unterminated ```json block")])
        .collect();
    assert!(blocks.len() >= 4, "{} material examples", blocks.len());
    let mut models = std::collections::BTreeSet::new();
    for block in blocks {
        let text = format!(
            r#"{{"materials": {block}, "objects": [{{"mesh": {{"type": "cube"}}, "material": {first:?}}}]}}"#,
            first = block.split('"').nth(1).expect("a material name"),
        );
        let s = scene::parse(&text, Path::new("docs/materials.json"))
            .unwrap_or_else(|e| panic!("{e}\n{block}"));
        for m in &s.materials {
            models.insert(m.material.name());
        }
    }
    for model in ["cook_torrance", "metal_rough", "principled", "oren_nayar"] {
        assert!(models.contains(model), "no documented {model} example");
    }
}

#[test]
fn real_obj_models_load() {
    let Some(models) = shared_dir("models") else {
        return;
    };
    for (file, min_triangles) in [
        ("stanford-bunny.obj", 69_000),
        ("teapot.obj", 6_000),
        ("suzanne.obj", 900),
        ("spot.obj", 5_800),
        ("cow.obj", 5_800),
        ("homer.obj", 12_000),
    ] {
        let path = models.join(file);
        // A tiny scene next to nothing: the OBJ path is absolute.
        let text = format!(
            r#"{{"materials": {{"m": {{"model": "blinn_phong"}}}},
                "objects": [{{"mesh": {{"type": "obj", "path": {path:?}}}, "material": "m"}}]}}"#,
            path = path.to_str().unwrap()
        );
        let s = scene::parse(&text, Path::new("tiny.json")).unwrap_or_else(|e| panic!("{e}"));
        let triangles = s.triangle_count();
        assert!(triangles >= min_triangles, "{file}: {triangles} triangles");
        for o in &s.objects {
            let m = &o.mesh;
            m.validate().unwrap_or_else(|e| panic!("{file}: {e}"));
            assert!(m.positions.iter().all(|p| p.is_finite()), "{file}");
            assert!(
                m.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-4),
                "{file}: normals not unit"
            );
            let (lo, hi) = m.bounds();
            assert!((hi - lo).max_element() > 0.0, "{file}: flat bounds");
        }
        if file == "spot.obj" {
            assert!(
                s.objects.iter().all(|o| !o.mesh.uvs.is_empty()),
                "spot.obj has UVs"
            );
        }
        println!(
            "{file}: {triangles} triangles in {} object(s)",
            s.objects.len()
        );
    }
}
