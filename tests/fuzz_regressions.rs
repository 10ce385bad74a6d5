//! Every input the fuzzers found a crash, hang or out-of-memory with (`tests/fuzz_regressions/
//! <target>/`), every committed seed (`fuzz/seeds/<target>/`), every file of `tests/bad_inputs/`
//! and the scenes of `tests/bad_scenes/` go through the same entry points as the fuzz targets
//! (`luz::fuzzing`), which must return without panicking. `scripts/fuzz.sh` runs the fuzzers.

mod common;

use std::fmt::Write as _;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::Instant;

use common::{declared_png, root};

/// A fuzz entry point.
type Target = fn(&[u8]);

const TARGETS: [(&str, Target); 5] = [
    ("scene", luz::fuzzing::scene),
    ("obj_mtl", luz::fuzzing::obj_mtl),
    ("image", luz::fuzzing::image),
    ("diff", luz::fuzzing::diff),
    ("gltf", luz::fuzzing::gltf),
];

/// The files of `dir` (not recursive, sorted; none when it does not exist).
fn files(dir: &Path) -> Vec<PathBuf> {
    let mut out: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_file())
                .collect()
        })
        .unwrap_or_default();
    out.sort();
    out
}

/// Runs `f` on each `(name, bytes)`; panics afterwards naming every input that panicked.
fn run_all(target: &str, f: Target, inputs: Vec<(String, Vec<u8>)>) -> usize {
    let mut failed = Vec::new();
    for (name, bytes) in &inputs {
        if catch_unwind(AssertUnwindSafe(|| f(bytes))).is_err() {
            failed.push(name.clone());
        }
    }
    assert!(
        failed.is_empty(),
        "luz::fuzzing::{target} panicked on: {}",
        failed.join(", ")
    );
    inputs.len()
}

fn read(path: &Path) -> (String, Vec<u8>) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    (path.display().to_string(), bytes)
}

#[test]
fn fuzz_regressions_and_seeds_do_not_panic() {
    let mut total = 0;
    for (target, f) in TARGETS {
        let mut inputs: Vec<(String, Vec<u8>)> = Vec::new();
        for dir in [
            root().join("tests/fuzz_regressions").join(target),
            root().join("fuzz/seeds").join(target),
        ] {
            inputs.extend(files(&dir).iter().map(|p| read(p)));
        }
        total += run_all(target, f, inputs);
    }
    assert!(total > 0, "no regression inputs or seeds found");
}

/// The first byte of an `image` / `diff` input for a file's extension.
fn ext_code(path: &Path) -> Option<u8> {
    match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
        "png" => Some(0),
        "exr" => Some(1),
        "hdr" => Some(2),
        _ => None,
    }
}

#[test]
fn bad_inputs_through_the_fuzz_entry_points() {
    let dir = root().join("tests/bad_inputs");
    let all = files(&dir);
    let with_ext = |e: &str| -> Vec<&PathBuf> {
        all.iter()
            .filter(|p| p.extension().is_some_and(|x| x == e))
            .collect()
    };

    // The malformed scenes of tests/bad_scenes, from their own folder (so their OBJ, MTL and
    // image files are found).
    let bad_scenes = files(&root().join("tests/bad_scenes"));
    let mut count = 0;
    for p in bad_scenes
        .iter()
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
    {
        let (name, bytes) = read(p);
        let ok = catch_unwind(AssertUnwindSafe(|| luz::fuzzing::scene_at(&bytes, p))).is_ok();
        assert!(ok, "luz::fuzzing::scene_at panicked on {name}");
        count += 1;
    }
    assert!(count > 0, "no scenes in tests/bad_scenes");

    let scenes: Vec<_> = with_ext("json")
        .into_iter()
        .filter(|p| !p.ends_with("EXPECTATIONS.json"))
        .map(|p| read(p))
        .collect();
    assert!(run_all("scene", luz::fuzzing::scene, scenes) > 0);

    let mut objs = Vec::new();
    for p in with_ext("obj") {
        let (name, mut bytes) = read(p);
        let mtl = p.with_extension("mtl");
        if mtl.is_file() {
            let text = String::from_utf8_lossy(&bytes).into_owned();
            let renamed: Vec<String> = text
                .lines()
                .map(|l| {
                    if l.starts_with("mtllib ") {
                        "mtllib m.mtl".to_string()
                    } else {
                        l.to_string()
                    }
                })
                .collect();
            bytes = renamed.join("\n").into_bytes();
            bytes.extend_from_slice(luz::fuzzing::SPLIT);
            bytes.extend(std::fs::read(&mtl).unwrap());
        }
        objs.push((name, bytes));
    }
    assert!(run_all("obj_mtl", luz::fuzzing::obj_mtl, objs) > 0);

    let mut images = Vec::new();
    let mut diffs = Vec::new();
    for p in &all {
        let Some(code) = ext_code(p) else { continue };
        let (name, bytes) = read(p);
        // sRGB with mipmaps; linear, channel R; normal map without mipmaps.
        for opts in [code, code | 4 | 16, code | 8 | 128] {
            let mut input = vec![opts];
            input.extend_from_slice(&bytes);
            images.push((format!("{name} (options {opts})"), input));
        }
        if code < 2 {
            let mut input = vec![code | 2 | 4 | 16];
            input.extend_from_slice(&bytes);
            diffs.push((name, input));
        }
    }
    assert!(run_all("image", luz::fuzzing::image, images) > 0);
    assert!(run_all("diff", luz::fuzzing::diff, diffs) > 0);

    let gltfs: Vec<_> = with_ext("gltf")
        .into_iter()
        .chain(with_ext("glb"))
        .map(|p| read(p))
        .collect();
    assert!(run_all("gltf", luz::fuzzing::gltf, gltfs) > 0);
}

/// The `diff` fuzzer's out-of-memory: a 590-byte EXR whose display window is small but whose
/// tiles (64 × 4194304) sized the decoder's block buffer (1.7 GB). It must be refused from its
/// header, with the fuzzers' limits and with the file loaders' defaults (`luz diff`, textures):
/// tiles beyond the data window may not exceed `MAX_OVERSIZED_TILE_BYTES`.
#[test]
fn exr_with_huge_tiles_is_refused_before_decoding() {
    let input =
        std::fs::read(root().join("tests/fuzz_regressions/diff/oom-exr-block-size-1.7GB")).unwrap();
    let (expected, _) = luz::fuzzing::split(&input);
    let exr = &expected[1..];
    let name = Path::new("huge.exr");
    for limits in [
        luz::fuzzing::FUZZ_LIMITS,
        luz::fuzzing::DIFF_LIMITS,
        luz::imageio::SizeLimits::DEFAULT,
    ] {
        match luz::imageio::load_bytes(exr, name, &limits) {
            Err(luz::imageio::ImageError::TooLarge { declared, .. }) => {
                assert!(declared.starts_with("declared "), "{declared}")
            }
            other => panic!("expected TooLarge, got {other:?}"),
        }
        match luz::texture::decode_bytes(exr, name, &limits) {
            Err(luz::texture::TextureError::TooLarge { .. }) => {}
            other => panic!("expected TooLarge, got {:?}", other.map(|_| ())),
        }
    }
}

/// A one-line (machine-written) scene of point lights, about `bytes` long.
fn one_line_lights(bytes: usize) -> String {
    let mut s = String::from(r#"{"lights":["#);
    let mut i = 0u32;
    while s.len() < bytes {
        if i > 0 {
            s.push(',');
        }
        let f = i as f32 * 0.001;
        let _ = write!(
            s,
            r#"{{"type":"point","position":[{f},1,-{f}],"color":[1,0.5,0.25],"intensity":{}}}"#,
            1.0 + f
        );
        i += 1;
    }
    s.push_str("]}");
    s
}

/// The scene fuzz target is linear in the size of its input: its time per megabyte of one-line
/// scenes does not grow from 1 KB to 10 MB (the JSON reader used to count every value's column
/// from the start of its line: 200,000 lights on one line took 301 s to load). Each size's time
/// is the best of 3 batches of about 2 MB (a loaded machine only makes times longer); a larger
/// size's time per MB may be at most 4 times a smaller one's plus 50 ms.
#[test]
fn scene_fuzz_target_time_per_megabyte_is_flat() {
    const MIB: f64 = 1048576.0;
    let mut per_mb = Vec::new();
    for bytes in [1 << 10, 10 << 10, 100 << 10, 1 << 20, 10 << 20] {
        let text = one_line_lights(bytes);
        let scene = luz::scene::parse(&text, Path::new("lights.json")).unwrap();
        assert!(
            scene.lights.len() * 100 > bytes,
            "{} lights",
            scene.lights.len()
        );
        let reps = ((2 << 20) / bytes).max(1) as u32;
        let best = (0..3)
            .map(|_| {
                let t = Instant::now();
                for _ in 0..reps {
                    luz::fuzzing::scene(text.as_bytes());
                }
                t.elapsed() / reps
            })
            .min()
            .unwrap_or_default();
        per_mb.push((text.len(), best.as_secs_f64() * MIB / text.len() as f64));
    }
    let report: Vec<String> = per_mb
        .iter()
        .map(|(n, s)| format!("{n} bytes: {:.1} ms/MB", s * 1e3))
        .collect();
    println!("luz::fuzzing::scene: {}", report.join(", "));
    for (i, &(small, small_per_mb)) in per_mb.iter().enumerate() {
        for &(large, large_per_mb) in &per_mb[i + 1..] {
            assert!(
                large_per_mb <= 4.0 * small_per_mb + 0.05,
                "time per MB grows with size ({small} vs {large} bytes): {}",
                report.join(", ")
            );
        }
    }
}

/// The size-amplifying inputs of [`size_amplifying_inputs_stay_within_a_memory_ceiling`], made
/// here (never stored): small files that declare huge counts, and a few megabytes that expand.
fn amplifying_inputs() -> Vec<(&'static str, Target, Vec<u8>)> {
    use base64::Engine as _;
    let b64 = |b: &[u8]| base64::engine::general_purpose::STANDARD.encode(b);
    let tri: Vec<u8> = [0f32, 0., 0., 1., 0., 0., 0., 1., 0.]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let buffer = format!(
        r#""buffers": [{{"uri": "data:application/octet-stream;base64,{}", "byteLength": 36}}],
 "bufferViews": [{{"buffer": 0, "byteLength": 36}}]"#,
        b64(&tri)
    );
    let scene_tail = r#""nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0"#;
    // Accessors of 2^31 elements over 36 bytes (positions, indices, and one without a view).
    let accessor_count = format!(
        r#"{{"asset": {{"version": "2.0"}}, {buffer},
 "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 2147483648, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}},
               {{"bufferView": 0, "componentType": 5125, "count": 2147483648, "type": "SCALAR"}},
               {{"componentType": 5126, "count": 2147483647, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}}],
 "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1}}, {{"attributes": {{"POSITION": 2}}}}]}}],
 {scene_tail}}}"#
    );
    // An embedded PNG declaring 65535² RGBA8 (16 GiB decoded) as a base colour map.
    let png = declared_png(65535, 65535);
    let png_header = format!(
        r#"{{"asset": {{"version": "2.0"}}, {buffer},
 "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}}],
 "images": [{{"uri": "data:image/png;base64,{}"}}], "textures": [{{"source": 0}}],
 "materials": [{{"pbrMetallicRoughness": {{"baseColorTexture": {{"index": 0}}}}}}],
 "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "material": 0}}]}}],
 {scene_tail}}}"#,
        b64(&png)
    );
    // 200,000 nodes placing one mesh in a 6 MB file (the loader caps instances at 10,000).
    let nodes: Vec<String> = (0..200_000)
        .map(|i| format!(r#"{{"mesh": 0, "translation": [{}, 0, 0]}}"#, i % 100))
        .collect();
    let roots: Vec<String> = (0..200_000).map(|i| i.to_string()).collect();
    let instances = format!(
        r#"{{"asset": {{"version": "2.0"}}, {buffer},
 "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}}],
 "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
 "nodes": [{}], "scenes": [{{"nodes": [{}]}}], "scene": 0}}"#,
        nodes.join(","),
        roots.join(",")
    );
    // One OBJ face of 20 million corners (40 MB, one line): beyond the 2^24 triangles.
    let mut face = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\nf");
    face.push_str(&" 1 2".repeat(10_000_000));
    face.push('\n');
    // A scene whose JSON holds a 2-million-element array (4 MB), and one of 1,000 spheres of
    // 4096 × 4096 segments declared in 90 KB.
    let mut array = String::from(r#"{"ambient": ["#);
    array.push_str(&"0,".repeat(2_000_000));
    array.push_str("0]}");
    let spheres: Vec<&str> = (0..1000)
        .map(|_| r#"{"mesh": {"type": "sphere", "segments": 4096, "rings": 4096}}"#)
        .collect();
    let spheres = format!(r#"{{"objects": [{}]}}"#, spheres.join(","));
    let mut image = vec![0u8];
    image.extend_from_slice(&png);
    vec![
        (
            "gltf accessor count 2^31",
            luz::fuzzing::gltf as Target,
            accessor_count.into_bytes(),
        ),
        (
            "gltf PNG header 65535²",
            luz::fuzzing::gltf,
            png_header.into_bytes(),
        ),
        (
            "gltf 200,000 instances",
            luz::fuzzing::gltf,
            instances.into_bytes(),
        ),
        ("image PNG header 65535²", luz::fuzzing::image, image),
        (
            "OBJ face of 20M corners",
            luz::fuzzing::obj_mtl,
            face.into_bytes(),
        ),
        (
            "scene array of 2M numbers",
            luz::fuzzing::scene,
            array.into_bytes(),
        ),
        (
            "scene 1,000 huge spheres",
            luz::fuzzing::scene,
            spheres.into_bytes(),
        ),
    ]
}

/// Issue 38 ("the fuzz targets include size-amplifying inputs"): inputs that declare far more
/// than they hold go through the fuzz entry points in a child process (this test binary again,
/// this test alone) under a 1 GiB address-space ceiling (`RLIMIT_AS`): each returns (no panic,
/// no abort on a failed allocation), and the child reports every one done.
#[test]
fn size_amplifying_inputs_stay_within_a_memory_ceiling() {
    const NAME: &str = "size_amplifying_inputs_stay_within_a_memory_ceiling";
    if std::env::var_os("LUZ_TEST_AMPLIFY_CHILD").is_some() {
        for (what, f, bytes) in amplifying_inputs() {
            let t = Instant::now();
            f(&bytes);
            println!(
                "amplified: {what} ({} bytes) done in {:.2} s",
                bytes.len(),
                t.elapsed().as_secs_f64()
            );
        }
        println!("amplified: all done");
        return;
    }
    let mut cmd = std::process::Command::new(std::env::current_exe().unwrap());
    cmd.args([NAME, "--exact", "--nocapture", "--test-threads", "1"])
        .env("LUZ_TEST_AMPLIFY_CHILD", "1");
    let ran = common::run(common::with_memory_ceiling(&mut cmd, 1 << 30));
    assert_eq!(
        ran.code, 0,
        "stdout: {}\nstderr: {}",
        ran.stdout, ran.stderr
    );
    assert!(ran.stdout.contains("amplified: all done"), "{}", ran.stdout);
    assert_eq!(
        ran.stdout.matches("amplified: ").count(),
        8,
        "{}",
        ran.stdout
    );
}
