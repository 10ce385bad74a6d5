//! The scene loader is linear in the size of the file: machine-written one-line scenes of
//! 10 MB (about 100,000 point lights, or tens of thousands of materials and objects) parse in
//! well under a second, and a huge file with an error after a huge array is refused as fast.
//! (The scaling check through the scene fuzz target's entry point is in
//! `tests/fuzz_regressions.rs`.) `parsing_speed_comparison` (ignored) prints the numbers of
//! `docs/scene-format.md`, "Parsing speed".

use std::fmt::Write as _;
use std::path::Path;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// The timed tests run one at a time (the test harness would run them in parallel).
static TIMING: Mutex<()> = Mutex::new(());

/// A one-line scene of point lights, about `bytes` long.
fn lights_scene(bytes: usize) -> String {
    let mut s = String::with_capacity(bytes + 200);
    s.push_str(r#"{"description":"generated","lights":["#);
    let mut i = 0u32;
    while s.len() < bytes {
        if i > 0 {
            s.push(',');
        }
        let f = i as f32 * 0.001;
        let _ = write!(
            s,
            r#"{{"type":"point","position":[{f},{},-{f}],"color":[1,0.5,0.25],"intensity":{}}}"#,
            f * 2.0,
            1.0 + f
        );
        i += 1;
    }
    s.push_str("]}");
    s
}

/// A one-line scene of `n` materials and `2 n` objects (distinct cubes, and automatically
/// tessellated spheres of distinct radii), about 250 bytes per material.
fn objects_scene(n: usize) -> String {
    let mut s = String::new();
    s.push_str(r#"{"camera":{"position":[0,0,50]},"materials":{"#);
    for i in 0..n {
        if i > 0 {
            s.push(',');
        }
        let _ = write!(
            s,
            r#""mat-{i}":{{"model":"lambert","albedo":[0.5,0.5,0.5]}}"#
        );
    }
    s.push_str(r#"},"objects":["#);
    for i in 0..n {
        if i > 0 {
            s.push(',');
        }
        let size = 0.01 + i as f32 * 1e-6;
        let _ = write!(
            s,
            r#"{{"name":"cube-{i}","mesh":{{"type":"cube","size":{size}}},"material":"mat-{i}","position":[{i},0,0]}},"#
        );
        let _ = write!(
            s,
            r#"{{"mesh":{{"type":"sphere","radius":{size}}},"material":"mat-{}","position":[0,{i},0]}}"#,
            n - 1 - i
        );
    }
    s.push_str("]}");
    s
}

/// The fastest of `runs` runs of `f` (of fewer once a run takes more than 5 s).
fn best_of(runs: usize, mut f: impl FnMut()) -> Duration {
    let mut best = Duration::MAX;
    for _ in 0..runs {
        let t = Instant::now();
        f();
        best = best.min(t.elapsed());
        if best > Duration::from_secs(5) {
            break;
        }
    }
    best
}

fn origin() -> &'static Path {
    Path::new("generated.json")
}

#[test]
fn ten_megabyte_one_line_scenes_parse_in_under_a_second() {
    let _timing = TIMING.lock().unwrap_or_else(|e| e.into_inner());
    let lights = lights_scene(10 << 20);
    let n = 40_000;
    let objects = objects_scene(n);
    assert!(objects.len() > 9 << 20, "{} bytes", objects.len());
    for (what, text) in [("lights", &lights), ("objects", &objects)] {
        let scene = luz::scene::parse(text, origin()).unwrap_or_else(|e| panic!("{what}: {e}"));
        match what {
            "lights" => assert!(scene.lights.len() > 100_000, "{}", scene.lights.len()),
            _ => {
                assert_eq!(scene.materials.len(), n);
                assert_eq!(scene.objects.len(), 2 * n);
                assert_eq!(scene.objects[1].material, n - 1);
            }
        }
        let t = best_of(3, || {
            luz::scene::parse(text, origin()).unwrap();
        });
        assert!(
            t < Duration::from_secs(1),
            "{what}: {} MB parsed in {t:?}",
            text.len() >> 20
        );
    }
}

/// A 200,000-element array and then an unknown field (2.6 MB; 2.4 MB took 35 s to be refused).
#[test]
fn errors_after_a_huge_array_are_reported_at_once() {
    let _timing = TIMING.lock().unwrap_or_else(|e| e.into_inner());
    let mut text = String::from(r#"{"lights":["#);
    for i in 0..200_000 {
        if i > 0 {
            text.push(',');
        }
        text.push_str("[0.25,0.5,1]");
    }
    text.push_str(r#"],"lihgts":1}"#);
    let t = Instant::now();
    let e = luz::scene::parse(&text, origin()).unwrap_err();
    let elapsed = t.elapsed();
    assert_eq!(e.json_path(), "lihgts");
    assert!(e.reason().contains("unknown field"), "{e}");
    assert!(
        elapsed < Duration::from_secs(1),
        "refused after {elapsed:?}"
    );

    // A syntax error at the end of the one line: its column counts characters, not bytes.
    let mut text = lights_scene(10 << 20);
    text.insert_str(0, r#"{"description":"é","x":"#);
    text.push_str(" x}");
    let t = Instant::now();
    let e = luz::scene::parse(&text, origin()).unwrap_err();
    let elapsed = t.elapsed();
    let column = text.chars().count() - 1;
    assert!(
        e.to_string()
            .ends_with(&format!("at line 1, column {column}")),
        "{e}"
    );
    assert!(
        elapsed < Duration::from_secs(2),
        "refused after {elapsed:?}"
    );

    // An unknown field with a 10 MB name (no "did you mean" search through its length).
    let text = format!(r#"{{"{}":1}}"#, "lights".repeat(10 << 20 >> 3));
    let t = Instant::now();
    let e = luz::scene::parse(&text, origin()).unwrap_err();
    let elapsed = t.elapsed();
    assert!(
        e.reason().starts_with("unknown field \"lightslights"),
        "{e}"
    );
    assert!(
        elapsed < Duration::from_secs(2),
        "refused after {elapsed:?}"
    );

    // A duplicate key at the end of an object of 200,000 fields.
    let mut text = String::from(r#"{"materials":{"#);
    for i in 0..200_000 {
        let _ = write!(text, r#""m{i}":{{}},"#);
    }
    text.push_str(r#""m7":{}}}"#);
    let t = Instant::now();
    let e = luz::scene::parse(&text, origin()).unwrap_err();
    let elapsed = t.elapsed();
    assert_eq!(e.json_path(), "materials.m7");
    assert!(e.reason().contains("duplicate field"), "{e}");
    assert!(
        elapsed < Duration::from_secs(2),
        "refused after {elapsed:?}"
    );
}

/// Prints parse times (best of 3) of 1 MB and 10 MB one-line light scenes: the JSON reader
/// alone, the whole loader (reader and decoder) and `serde_json::Value` for comparison.
/// `cargo test --release --test scene_scaling -- --ignored --nocapture`
#[test]
#[ignore]
fn parsing_speed_comparison() {
    for mb in [1, 10] {
        let text = lights_scene(mb << 20);
        let reader = best_of(3, || {
            luz::scene::json::parse(&text).unwrap();
        });
        let loader = best_of(3, || {
            luz::scene::parse(&text, origin()).unwrap();
        });
        let serde = best_of(3, || {
            serde_json::from_str::<serde_json::Value>(&text).unwrap();
        });
        println!(
            "{mb:>2} MB ({} bytes): luz::scene::json::parse {:.1} ms, luz::scene::parse {:.1} ms, \
             serde_json::from_str::<Value> {:.1} ms",
            text.len(),
            reader.as_secs_f64() * 1e3,
            loader.as_secs_f64() * 1e3,
            serde.as_secs_f64() * 1e3
        );
    }
}
