//! The input budget (issue 38, docs/reliability.md "Input budget"): every input bounded in memory
//! before it is read. Each case runs the real binary under a memory ceiling (`RLIMIT_AS`, set in
//! the child before `exec`) and a time limit, with its big inputs generated here (sparse files,
//! FIFOs, declared sizes), never stored; each asserts the exit status and the message naming the
//! file and the field.

mod common;

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

use common::{declared_png, scratch, Ran, LUZ};

const MIB: u64 = 1 << 20;

/// The memory ceiling of a run that must stop at a check before reading: the address space
/// `luz` needs to start, parse its arguments and load a small scene, with room to spare, but far
/// below what reading any of these inputs whole would take (gigabytes).
const CEILING: u64 = 1024 * MIB;

/// The ceiling of a run that starts Vulkan (lavapipe and LLVM reserve address space): enough
/// for a small render, a fraction of what decoding the big textures here would take.
const GPU_CEILING: u64 = 2048 * MIB;

/// `luz <args>` under an address-space ceiling of `ceiling` bytes (and a largest written file
/// of `fsize` bytes, if given), killed (and the test failed) after `timeout`.
fn luz_limited(args: &[&str], ceiling: u64, fsize: Option<u64>, timeout: Duration) -> Ran {
    let mut cmd = Command::new(LUZ);
    cmd.args(args)
        .env("LUZ_VALIDATION", "1")
        .env("MESA_SHADER_CACHE_DISABLE", "true")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped());
    common::with_limits(&mut cmd, ceiling, fsize);
    let mut child = cmd.spawn().expect("cannot start luz");
    let t0 = Instant::now();
    loop {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        if t0.elapsed() > timeout {
            let _ = child.kill();
            let _ = child.wait();
            panic!("luz {args:?} still running after {timeout:?} (blocked?)");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap();
    Ran {
        status: out.status,
        code: out.status.code().unwrap_or(-1),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// `luz render <scene> -o <tmp>/out.png` within [`CEILING`] and 60 s, expected to fail: exit 1,
/// one error line with every one of `needles`, no panic. Returns stderr.
fn render_fails(scene: &Path, extra: &[&str], needles: &[&str]) -> String {
    render_fails_within(CEILING, scene, extra, needles)
}

/// [`render_fails`] for a failure found once Vulkan is up, within [`GPU_CEILING`].
fn render_fails_on_gpu(scene: &Path, extra: &[&str], needles: &[&str]) -> String {
    render_fails_within(GPU_CEILING, scene, extra, needles)
}

/// `luz render <scene> -o <folder>/out.png <extra>` within `ceiling` that must succeed (exit 0,
/// no panic); returns stderr.
fn render_succeeds(scene: &Path, extra: &[&str]) -> String {
    let out = scene.with_file_name("out.png");
    let mut args = vec!["render", s(scene), "-o", s(&out)];
    args.extend_from_slice(extra);
    let ran = luz_limited(&args, GPU_CEILING, None, Duration::from_secs(300));
    assert_eq!(ran.code, 0, "luz {args:?}: stderr: {}", ran.stderr);
    assert!(!ran.stderr.contains("panicked"), "{}", ran.stderr);
    ran.stderr
}

fn render_fails_within(ceiling: u64, scene: &Path, extra: &[&str], needles: &[&str]) -> String {
    let out = scene.with_file_name("out.png");
    let mut args = vec!["render", s(scene), "-o", s(&out)];
    args.extend_from_slice(extra);
    let ran = luz_limited(&args, ceiling, None, Duration::from_secs(60));
    let err = &ran.stderr;
    assert_eq!(
        ran.code, 1,
        "luz {args:?}: exit {}\nstderr: {err}",
        ran.code
    );
    assert!(!err.contains("panicked"), "{err}");
    for n in needles {
        assert!(err.contains(n), "luz {args:?}: {n:?} not in stderr: {err}");
    }
    err.clone()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// One triangle's positions (36 bytes) as a glTF buffer.
fn triangle_bin() -> Vec<u8> {
    [0f32, 0., 0., 1., 0., 0., 0., 1., 0.]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect()
}

/// A glTF file of one triangle mesh placed by `nodes` nodes, its buffer at `buffer_uri`
/// declaring `byte_length` bytes; `extra` is spliced into the root object (`"key": value, `).
fn gltf(buffer_uri: &str, byte_length: u64, nodes: usize, extra: &str) -> String {
    let node_list: Vec<String> = (0..nodes)
        .map(|i| format!(r#"{{"mesh": 0, "translation": [{}, 0, 0]}}"#, i % 100))
        .collect();
    let roots: Vec<String> = (0..nodes).map(|i| i.to_string()).collect();
    format!(
        r#"{{"asset": {{"version": "2.0"}}, {extra}
 "buffers": [{{"uri": "{buffer_uri}", "byteLength": {byte_length}}}],
 "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
 "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]}}],
 "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
 "nodes": [{}],
 "scenes": [{{"nodes": [{}]}}], "scene": 0}}"#,
        node_list.join(", "),
        roots.join(", ")
    )
}

/// A small scene of one sphere with `texture` as its base colour map.
fn textured_scene(texture: &str) -> String {
    format!(
        r#"{{"output": {{"width": 8, "height": 8, "msaa": 1}},
 "materials": {{"m": {{"model": "metal_rough", "textures": {{"base_color": "{texture}"}}}}}},
 "objects": [{{"mesh": {{"type": "sphere", "segments": 8, "rings": 4}}, "material": "m"}}]}}"#
    )
}

/// A scene of the OBJ `obj`.
fn obj_scene(obj: &str) -> String {
    format!(
        r#"{{"output": {{"width": 8, "height": 8, "msaa": 1}},
 "materials": {{"m": {{"model": "lambert"}}}},
 "objects": [{{"mesh": {{"type": "obj", "path": "{obj}"}}, "material": "m"}}]}}"#
    )
}

/// A sparse file of `len` bytes: nothing written, nothing stored.
fn sparse(path: &Path, len: u64) {
    std::fs::File::create(path).unwrap().set_len(len).unwrap();
}

fn mkfifo(path: &Path) {
    let ok = Command::new("mkfifo").arg(path).status().unwrap().success();
    assert!(ok, "mkfifo {}", path.display());
}

#[test]
fn files_beyond_the_budget_are_refused_from_their_size_before_reading() {
    let dir = scratch("budget-sparse");
    // 3 GiB sparse files: reading any of them whole would pass the 1 GiB ceiling.
    for name in ["big.obj", "big.gltf", "big.glb", "big.json"] {
        let file = dir.join(name);
        sparse(&file, 3 << 30);
        render_fails(
            &file,
            &[],
            &[
                &format!("{name}: "),
                "3072.0 MiB is larger than the input budget's largest file (256.0 MiB; raise it \
                 with --max-file-mb)",
            ],
        );
    }
    // An OBJ named by a scene: the scene and the field are named too.
    sparse(&dir.join("mesh.obj"), 3 << 30);
    std::fs::write(dir.join("scene.json"), obj_scene("mesh.obj")).unwrap();
    render_fails(
        &dir.join("scene.json"),
        &[],
        &[
            "scene.json: objects[0].mesh.path",
            "mesh.obj",
            "--max-file-mb",
        ],
    );
    // The flag moves the limit: a 2 MiB scene file is refused under --max-file-mb 1 only.
    let padded = format!("{}\n{}", obj_scene("tri.obj"), " ".repeat(2 << 20));
    std::fs::write(dir.join("padded.json"), padded).unwrap();
    render_fails(
        &dir.join("padded.json"),
        &["--max-file-mb", "1"],
        &[
            "padded.json: (root): cannot read the scene file: 2.0 MiB is larger",
            "(1.0 MiB; raise it",
        ],
    );
    let err = render_fails(&dir.join("padded.json"), &[], &["tri.obj"]);
    assert!(!err.contains("--max-file-mb"), "{err}");
}

#[test]
fn gltf_buffers_are_checked_from_their_declared_length_and_kind() {
    let dir = scratch("budget-buffers");
    std::fs::write(dir.join("tri.bin"), triangle_bin()).unwrap();
    // A declared byteLength of 1 TiB: refused before the buffer is opened.
    std::fs::write(dir.join("huge.gltf"), gltf("tri.bin", 1 << 40, 1, "")).unwrap();
    render_fails(
        &dir.join("huge.gltf"),
        &[],
        &[
            "huge.gltf: buffers[0].byteLength: declares 1048576.0 MiB, more than the input \
             budget's largest file",
            "--max-file-mb",
        ],
    );
    // /dev/zero as a buffer (once grew to 23 GB): outside the folder, and not a regular file
    // when outside files are allowed.
    std::fs::write(dir.join("zero.gltf"), gltf("/dev/zero", 36, 1, "")).unwrap();
    render_fails(
        &dir.join("zero.gltf"),
        &[],
        &["zero.gltf: buffers[0].uri: \"/dev/zero\" names a file outside the model's folder"],
    );
    render_fails(
        &dir.join("zero.gltf"),
        &["--allow-outside-uris"],
        &["zero.gltf: buffers[0].uri: cannot read the buffer file /dev/zero: is a device, not a regular file"],
    );
}

#[test]
fn a_fifo_as_any_input_is_refused_at_once() {
    let dir = scratch("budget-fifo");
    for name in ["pipe.json", "pipe.obj", "pipe.gltf"] {
        mkfifo(&dir.join(name));
        render_fails(
            &dir.join(name),
            &[],
            &[name, "is a FIFO (named pipe), not a regular file"],
        );
    }
    // Named by a scene: an OBJ, a texture.
    mkfifo(&dir.join("mesh.obj"));
    std::fs::write(dir.join("obj.json"), obj_scene("mesh.obj")).unwrap();
    render_fails(
        &dir.join("obj.json"),
        &[],
        &["obj.json: objects[0].mesh.path", "mesh.obj", "FIFO"],
    );
    mkfifo(&dir.join("tex.png"));
    std::fs::write(dir.join("tex.json"), textured_scene("tex.png")).unwrap();
    render_fails(
        &dir.join("tex.json"),
        &[],
        &[
            "tex.json: materials.m",
            "tex.png: cannot read: is a FIFO (named pipe)",
        ],
    );
    // A glTF buffer.
    mkfifo(&dir.join("pipe.bin"));
    std::fs::write(dir.join("buf.gltf"), gltf("pipe.bin", 36, 1, "")).unwrap();
    render_fails(
        &dir.join("buf.gltf"),
        &[],
        &["buf.gltf: buffers[0].uri", "pipe.bin", "FIFO"],
    );
}

#[test]
fn textures_beyond_the_budget_are_refused_from_their_header() {
    let dir = scratch("budget-texture");
    // 16384² (268 Mpix): once peaked at 9.1 GB; refused from the header under a 1 GiB ceiling.
    std::fs::write(dir.join("big.png"), declared_png(16384, 16384)).unwrap();
    std::fs::write(dir.join("big.json"), textured_scene("big.png")).unwrap();
    render_fails_on_gpu(
        &dir.join("big.json"),
        &[],
        &[
            "big.png: image too large (declared 16384×16384)",
            "64 Mpix in total",
            "--max-texture-mpix",
        ],
    );
    // The flag moves the limit: 2048 × 1024 (2 Mpix) is refused under --max-texture-mpix 1;
    // under the default it is decoded (and found truncated: it holds no pixel data).
    std::fs::write(dir.join("two.png"), declared_png(2048, 1024)).unwrap();
    std::fs::write(dir.join("two.json"), textured_scene("two.png")).unwrap();
    render_fails_on_gpu(
        &dir.join("two.json"),
        &["--max-texture-mpix", "1"],
        &[
            "two.png: image too large (declared 2048×1024)",
            "1 Mpix in total",
        ],
    );
    let err = render_fails_on_gpu(&dir.join("two.json"), &[], &["two.png"]);
    assert!(!err.contains("too large"), "{err}");
}

#[test]
fn gltf_instances_and_triangles_are_capped_before_the_meshes_are_built() {
    let dir = scratch("budget-instances");
    std::fs::write(dir.join("tri.bin"), triangle_bin()).unwrap();
    // 200,000 one-triangle instances (100k once took 2.1 GB): refused at the 10,001st.
    std::fs::write(dir.join("many.gltf"), gltf("tri.bin", 36, 200_000, "")).unwrap();
    render_fails(
        &dir.join("many.gltf"),
        &[],
        &[
            "many.gltf: nodes[10000]: the file places more than 10000 mesh instances",
            "--max-instances",
        ],
    );
    render_fails(
        &dir.join("many.gltf"),
        &["--max-instances", "10"],
        &["many.gltf: nodes[10]: the file places more than 10 mesh instances"],
    );
    std::fs::write(dir.join("three.gltf"), gltf("tri.bin", 36, 3, "")).unwrap();
    render_fails(
        &dir.join("three.gltf"),
        &["--max-triangles", "2"],
        &[
            "three.gltf: nodes[2]: the file expands into more than 2 triangles",
            "--max-triangles",
        ],
    );
}

#[test]
fn gltf_uris_stay_inside_the_model_folder_and_leak_nothing() {
    let dir = scratch("budget-uris");
    let model = dir.join("model");
    std::fs::create_dir_all(model.join("sub")).unwrap();
    // The outside file: its bytes must never reach a message.
    let secret = dir.join("secret.bin");
    std::fs::write(&secret, b"SECRETBYTES-SECRETBYTES-SECRETBYTES-SECRETBYTES").unwrap();
    std::fs::write(model.join("tri.bin"), triangle_bin()).unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink(&secret, model.join("link.bin")).unwrap();
    let absolute = secret.to_str().unwrap().to_string();
    for (name, uri) in [
        ("parent.gltf", "../secret.bin"),
        ("deeper.gltf", "sub/../../secret.bin"),
        ("escaped.gltf", "%2e%2e/secret.bin"),
        ("absolute.gltf", absolute.as_str()),
        ("link.gltf", "link.bin"),
    ] {
        std::fs::write(model.join(name), gltf(uri, 64, 1, "")).unwrap();
        let err = render_fails(
            &model.join(name),
            &[],
            &[
                &format!("{name}: buffers[0].uri: "),
                "names a file outside the model's folder",
                "--allow-outside-uris",
            ],
        );
        assert!(!err.contains("SECRET") && !err.contains("CRET"), "{err}");
    }
    // An image URI too.
    let image = r#""images": [{"uri": "../secret.png"}], "textures": [{"source": 0}],
 "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],"#;
    std::fs::write(dir.join("secret.png"), declared_png(4, 4)).unwrap();
    std::fs::write(model.join("image.gltf"), gltf("tri.bin", 36, 1, image)).unwrap();
    render_fails(
        &model.join("image.gltf"),
        &[],
        &["image.gltf: images[0].uri: \"../secret.png\" names a file outside"],
    );
    // With the flag the outside buffer is read: here it is shorter than declared, and the
    // message gives sizes, not bytes.
    let err = render_fails(
        &model.join("parent.gltf"),
        &["--allow-outside-uris"],
        &["parent.gltf: buffers[0].byteLength: declares 64 bytes, but the data has only 47"],
    );
    assert!(!err.contains("SECRET"), "{err}");
    // Inside the folder, `sub/../tri.bin` is read and rendered. The file's spot light has
    // innerConeAngle ≥ outerConeAngle: a warning (once accepted silently).
    let spot = r#""extensionsUsed": ["KHR_lights_punctual"],
 "extensions": {"KHR_lights_punctual": {"lights": [
   {"type": "spot", "spot": {"innerConeAngle": 0.7, "outerConeAngle": 0.5}}]}},"#;
    let text = gltf("sub/../tri.bin", 36, 2, spot).replace(
        r#"{"mesh": 0, "translation": [1, 0, 0]}"#,
        r#"{"translation": [0, 0, 2], "extensions": {"KHR_lights_punctual": {"light": 0}}}"#,
    );
    std::fs::write(model.join("inside.gltf"), text).unwrap();
    let err = render_succeeds(
        &model.join("inside.gltf"),
        &[
            "--width",
            "16",
            "--height",
            "16",
            "--no-cache",
            "--ibl-quality",
            "fast",
        ],
    );
    assert!(
        err.contains(
            "warning: inside.gltf: extensions.KHR_lights_punctual.lights[0].spot.innerConeAngle \
             (0.7) is not below outerConeAngle (0.5)"
        ),
        "{err}"
    );
}

#[test]
fn error_excerpts_are_short() {
    let dir = scratch("budget-excerpt");
    // A 10 MB number on a `v` line (100 MB once came back whole in the message).
    let huge = "9".repeat(10_000_000);
    std::fs::write(
        dir.join("num.obj"),
        format!("v {huge} 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
    )
    .unwrap();
    let err = render_fails(
        &dir.join("num.obj"),
        &[],
        &[
            "num.obj: (root): line 1: vertex x: \"9999999999",
            "9\"… (10000000 bytes) is not a finite number",
        ],
    );
    assert!(err.len() < 1000, "{} bytes of stderr", err.len());
    // A face vertex of 1 MB.
    std::fs::write(
        dir.join("face.obj"),
        format!(
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3/{}\n",
            "x".repeat(1 << 20)
        ),
    )
    .unwrap();
    let err = render_fails(
        &dir.join("face.obj"),
        &[],
        &["face.obj: (root): line 4: face vertex \"3/xxx"],
    );
    assert!(err.len() < 1000, "{} bytes of stderr", err.len());
}

#[test]
fn gltf_cameras_spots_and_cycles_get_clear_messages() {
    let dir = scratch("budget-gltf-fields");
    std::fs::write(dir.join("tri.bin"), triangle_bin()).unwrap();
    // aspectRatio 1e6 once gave a 16384-pixel-wide image; 1e-6 a 1-pixel one.
    for a in ["1e6", "1e-6"] {
        let camera = format!(
            r#""cameras": [{{"type": "perspective", "perspective": {{"yfov": 0.8, "znear": 0.1, "aspectRatio": {a}}}}}],"#
        );
        let text = gltf("tri.bin", 36, 1, &camera).replace(
            r#"{"mesh": 0, "translation": [0, 0, 0]}"#,
            r#"{"mesh": 0, "camera": 0, "translation": [0, 0, 0]}"#,
        );
        std::fs::write(dir.join("aspect.gltf"), text).unwrap();
        render_fails(
            &dir.join("aspect.gltf"),
            &[],
            &["aspect.gltf: cameras[0].perspective.aspectRatio: must be between 1/16 and 16"],
        );
    }
    // Nodes that all have a parent and no scene: a cycle with no root (once an empty image
    // with exit 0).
    let cycle = gltf("tri.bin", 36, 2, "")
        .replace(
            r#""scenes": [{"nodes": [0, 1]}], "scene": 0"#,
            r#""extras": {}"#,
        )
        .replace(
            r#"{"mesh": 0, "translation": [0, 0, 0]}"#,
            r#"{"mesh": 0, "translation": [0, 0, 0], "children": [1]}"#,
        )
        .replace(
            r#"{"mesh": 0, "translation": [1, 0, 0]}"#,
            r#"{"mesh": 0, "translation": [1, 0, 0], "children": [0]}"#,
        );
    std::fs::write(dir.join("cycle.gltf"), cycle).unwrap();
    render_fails(
        &dir.join("cycle.gltf"),
        &[],
        &["cycle.gltf: nodes: the file has no scene and every node is the child of another"],
    );
}

#[test]
fn scene_fields_beyond_the_device_or_floats_name_the_file_and_field() {
    let dir = scratch("budget-scene-fields");
    // msaa 8 on lavapipe (supports 1 and 4): the file and `output.msaa`, counts as numbers,
    // no Vulkan flag names.
    std::fs::write(
        dir.join("msaa.json"),
        r#"{"output": {"width": 8, "height": 8, "msaa": 8},
 "materials": {"m": {"model": "lambert"}},
 "objects": [{"mesh": {"type": "sphere", "segments": 8, "rings": 4}, "material": "m"}]}"#,
    )
    .unwrap();
    let err = render_fails_on_gpu(
        &dir.join("msaa.json"),
        &[],
        &[
            "msaa.json: output.msaa: 8 samples are not supported by",
            "(it supports 1",
        ],
    );
    assert!(!err.contains("TYPE_"), "{err}");
    // A camera at ±3e38: target − position overflows; once "equals the camera position".
    std::fs::write(
        dir.join("far.json"),
        r#"{"camera": {"position": [3e38, 0, 0], "target": [-3e38, 0, 0]},
 "materials": {"m": {"model": "lambert"}},
 "objects": [{"mesh": {"type": "sphere"}, "material": "m"}]}"#,
    )
    .unwrap();
    let err = render_fails(
        &dir.join("far.json"),
        &[],
        &["far.json: camera.target: is too far from position"],
    );
    assert!(!err.contains("equals the camera position"), "{err}");
    // 300 point lights without a range: rendered, with a warning of the cost.
    let lights: Vec<String> = (0..300)
        .map(|i| {
            format!(
                r#"{{"type": "point", "position": [{}, 2, 2], "intensity": 0.01}}"#,
                i % 7
            )
        })
        .collect();
    std::fs::write(
        dir.join("lights.json"),
        format!(
            r#"{{"output": {{"width": 8, "height": 8, "msaa": 1}}, "lights": [{}],
 "materials": {{"m": {{"model": "lambert"}}}},
 "objects": [{{"mesh": {{"type": "sphere", "segments": 8, "rings": 4}}, "material": "m"}}]}}"#,
            lights.join(", ")
        ),
    )
    .unwrap();
    let err = render_succeeds(&dir.join("lights.json"), &[]);
    assert!(
        err.contains("warning: lights: 300 point and spot lights without a \"range\""),
        "{err}"
    );
}

#[test]
fn argument_errors_exit_2_as_documented() {
    let ran = luz_limited(
        &["render", "--no-such-option"],
        CEILING,
        None,
        Duration::from_secs(60),
    );
    assert_eq!(ran.code, 2, "{}", ran.stderr);
    assert!(ran.stderr.contains("--no-such-option"), "{}", ran.stderr);
    let docs = std::fs::read_to_string(common::root().join("docs/cli.md")).unwrap();
    assert!(
        docs.contains("| 2 | a command-line usage error"),
        "docs/cli.md"
    );
    // The budget flags are in --help.
    let ran = luz_limited(
        &["render", "--help"],
        CEILING,
        None,
        Duration::from_secs(60),
    );
    for flag in [
        "--max-file-mb",
        "--max-texture-mpix",
        "--max-texture-mpix-total",
        "--max-instances",
        "--max-triangles",
        "--allow-outside-uris",
    ] {
        assert!(
            ran.stdout.contains(flag),
            "{flag} not in --help: {}",
            ran.stdout
        );
        assert!(docs.contains(flag), "{flag} not in docs/cli.md");
    }
}

#[test]
fn golden_bless_killed_mid_write_keeps_the_old_golden() {
    use std::os::unix::process::ExitStatusExt;
    let dir = scratch("budget-bless");
    let scenes = dir.join("scenes");
    let goldens = dir.join("goldens");
    std::fs::create_dir_all(&scenes).unwrap();
    std::fs::create_dir_all(&goldens).unwrap();
    std::fs::write(
        scenes.join("ball.json"),
        r#"{"output": {"width": 96, "height": 64, "msaa": 1},
 "lights": [{"type": "directional", "direction": [-0.4, -0.5, -0.8], "intensity": 1}],
 "materials": {"m": {"model": "lambert", "albedo": [0.8, 0.2, 0.1]}},
 "objects": [{"mesh": {"type": "sphere", "segments": 32, "rings": 16}, "material": "m"}]}"#,
    )
    .unwrap();
    let old = b"the old golden, whatever its bytes".to_vec();
    let golden = goldens.join("ball.png");
    std::fs::write(&golden, &old).unwrap();
    let args = [
        "golden",
        s(&scenes),
        "--goldens",
        s(&goldens),
        "--bless",
        "--no-cache",
    ];
    // Files may not grow past 512 bytes: the kernel kills luz (SIGXFSZ) in the middle of
    // writing the new golden, as `kill -9` would.
    let ran = luz_limited(&args, GPU_CEILING, Some(512), Duration::from_secs(300));
    assert!(
        ran.status.signal() == Some(libc::SIGXFSZ),
        "expected death by SIGXFSZ mid-write: {:?}\n{}",
        ran.status,
        ran.stderr
    );
    // The write had begun (a partial temporary file beside the golden)…
    let partial: Vec<_> = std::fs::read_dir(&goldens)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".ball.png.bless-"))
        .collect();
    assert_eq!(partial.len(), 1, "{partial:?}");
    // …and the golden is untouched.
    assert_eq!(std::fs::read(&golden).unwrap(), old);
    // Without the limit the golden is replaced, whole.
    let ran = luz_limited(&args, GPU_CEILING, None, Duration::from_secs(300));
    assert_eq!(ran.code, 0, "{}", ran.stderr);
    let new = luz::imageio::load(&golden).unwrap();
    assert_eq!((new.width, new.height), (96, 64));
    // The stale temporary file of the killed run is gone too.
    let left = std::fs::read_dir(&goldens).unwrap().count();
    assert_eq!(left, 1, "only ball.png stays in {}", goldens.display());
}

/// A scene of one sphere per texture of `textures`, each its own material's base colour map.
fn many_textures_scene(textures: &[&str]) -> String {
    let materials: Vec<String> = textures
        .iter()
        .enumerate()
        .map(|(i, t)| {
            format!(r#""m{i}": {{"model": "metal_rough", "textures": {{"base_color": "{t}"}}}}"#)
        })
        .collect();
    let objects: Vec<String> = (0..textures.len())
        .map(|i| {
            format!(
                r#"{{"mesh": {{"type": "sphere", "segments": 8, "rings": 4}}, "material": "m{i}", "position": [{i}, 0, 0]}}"#
            )
        })
        .collect();
    format!(
        r#"{{"output": {{"width": 8, "height": 8, "msaa": 1}},
 "materials": {{{}}},
 "objects": [{}]}}"#,
        materials.join(", "),
        objects.join(", ")
    )
}

/// Issue 38: all a scene's textures together within the budget (`--max-texture-mpix-total`,
/// default 256 Mpix), counted from their headers when the scene is loaded, before any is
/// decoded: five 8192² PNGs (64 Mpix each, each within the per-texture limit; decoded they would
/// take about 10 GiB) are refused at the fifth under a 1 GiB ceiling, naming it and the budget.
/// An image used by several materials counts once.
#[test]
fn a_scenes_textures_together_are_capped_from_their_headers() {
    let dir = scratch("budget-texture-total");
    let names: Vec<String> = (0..5).map(|i| format!("t{i}.png")).collect();
    for n in &names {
        std::fs::write(dir.join(n), declared_png(8192, 8192)).unwrap();
    }
    let refs: Vec<&str> = names.iter().map(String::as_str).collect();
    std::fs::write(dir.join("five.json"), many_textures_scene(&refs)).unwrap();
    render_fails(
        &dir.join("five.json"),
        &[],
        &[
            "five.json: material \"m4\": ",
            "t4.png: its 64.0 Mpix bring the scene's textures to 320.0 Mpix, beyond the input \
             budget's total of 256 Mpix",
            "--max-texture-mpix-total",
        ],
    );
    // The flag moves it: under a total of 200 Mpix the fourth is refused.
    std::fs::write(dir.join("four.json"), many_textures_scene(&refs[..4])).unwrap();
    render_fails(
        &dir.join("four.json"),
        &["--max-texture-mpix-total", "200"],
        &["t3.png: its 64.0 Mpix", "total of 200 Mpix"],
    );
    // 2 Mpix used by three materials is 2 Mpix, not 6: within a total of 3 (and then found
    // truncated when decoded, on the GPU's side: it holds no pixel data).
    std::fs::write(dir.join("two.png"), declared_png(2048, 1024)).unwrap();
    std::fs::write(
        dir.join("shared.json"),
        many_textures_scene(&["two.png", "two.png", "two.png"]),
    )
    .unwrap();
    let err = render_fails_on_gpu(
        &dir.join("shared.json"),
        &["--max-texture-mpix-total", "3"],
        &["two.png"],
    );
    assert!(!err.contains("--max-texture-mpix-total"), "{err}");
}

/// Issue 38: an OBJ's triangles are counted while its text is checked, before tobj builds any
/// (n − 2 per face of n corners), and refused beyond `--max-triangles` with the file and line:
/// a generated 4.8 MB OBJ of 600,000 faces under `--max-triangles 500000`, and one face of 17
/// million corners (34 MB, one line) under the default 2^24; each under a 1 GiB ceiling.
#[test]
fn obj_triangles_are_counted_before_they_are_built() {
    let dir = scratch("budget-obj-triangles");
    let mut many = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    many.push_str(&"f 1 2 3\n".repeat(600_000));
    std::fs::write(dir.join("many.obj"), &many).unwrap();
    std::fs::write(dir.join("many.json"), obj_scene("many.obj")).unwrap();
    render_fails(
        &dir.join("many.json"),
        &["--max-triangles", "500000"],
        &[
            "many.obj:500004: the file expands into more than 500000 triangles",
            "--max-triangles",
        ],
    );
    let mut fan = String::from("v 0 0 0\nv 1 0 0\nv 0 1 0\nf");
    fan.push_str(&" 1 2".repeat(8_500_000));
    fan.push('\n');
    std::fs::write(dir.join("fan.obj"), &fan).unwrap();
    std::fs::write(dir.join("fan.json"), obj_scene("fan.obj")).unwrap();
    render_fails(
        &dir.join("fan.json"),
        &[],
        &[
            "fan.obj:4: the file expands into more than 16777216 triangles",
            "--max-triangles",
        ],
    );
}
