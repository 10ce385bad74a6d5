//! `luz fidelity` (issue 39): the Khronos glTF Render Fidelity generator's offline-renderer
//! contract. Hand-written scenarios for the models in ../shared/gltf render to their PNG (the
//! camera, size, background and environment as docs/fidelity.md says); the output equals
//! `luz render` of the equivalent luz scene, hand-written here; bad scenarios are errors naming
//! the JSON path, exit 1, never a panic.

mod common;

use std::path::Path;

use common::{luz, scratch, shared_dir};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn fidelity(args: &[&str]) -> (i32, String, String) {
    let mut all = vec!["fidelity"];
    all.extend_from_slice(args);
    let (code, out, err) = luz(&all);
    assert!(!err.contains("panicked"), "{err}");
    (code, out, err)
}

/// The PNG's 8-bit RGBA bytes, and whether the file has an alpha channel.
fn rgba(p: &Path) -> (u32, u32, Vec<[u8; 4]>, bool) {
    let img = image::open(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    let alpha = img.color().has_alpha();
    let img = img.to_rgba8();
    let px = img.pixels().map(|p| p.0).collect();
    (img.width(), img.height(), px, alpha)
}

/// One scenario per model of ../shared/gltf, written by hand as the generator's config.json
/// would hold it (orbit in degrees, radius in the model's units), at a small size: each writes
/// its PNG at twice the size (the device pixel ratio), with the model in the middle and, without
/// a skybox, a white background; with a skybox the corners show the environment.
#[test]
fn scenarios_for_the_shared_models_write_their_png() {
    let Some(gltf) = shared_dir("gltf") else {
        return;
    };
    let Some(envs) = shared_dir("environments") else {
        return;
    };
    let hdr = envs.join("newport_loft.hdr");
    let dir = scratch("fidelity-models");
    let cases = [
        (
            "cesiumman",
            "CesiumMan/glTF-Binary/CesiumMan.glb",
            r#""target": {"y": 0.75}, "orbit": {"radius": 2}"#,
        ),
        (
            "teapots",
            "color_teapot_spheres.gltf",
            r#""orbit": {"radius": 1.8, "theta": 20, "phi": 70}"#,
        ),
        (
            "deer",
            "deer.gltf",
            r#""orbit": {"radius": 3.5, "theta": -30, "phi": 80}"#,
        ),
        (
            "retroufo",
            "retroufo.glb",
            r#""orbit": {"radius": 200, "theta": 35, "phi": 65}"#,
        ),
        (
            "venus",
            "venus.gltf",
            r#""orbit": {"radius": 2.5, "theta": 0, "phi": 90}"#,
        ),
    ];
    for (name, model, view) in cases {
        let out = dir.join(format!("{name}.png"));
        let config = format!(
            r#"{{"scenario": {{"name": "{name}", "model": "{}", "lighting": "{}",
                "dimensions": {{"width": 40, "height": 30}}, {view}}},
                "outputFile": "{}"}}"#,
            s(&gltf.join(model)),
            s(&hdr),
            s(&out)
        );
        let (code, stdout, err) = fidelity(&[&config, "--ibl-quality", "fast"]);
        assert_eq!(code, 0, "{name}: {stdout}\n{err}");
        assert!(err.contains("validation: 0 errors, 0 warnings"), "{err}");
        assert!(
            stdout.contains(&format!("wrote {} (80×60)", out.display())),
            "{stdout}"
        );
        let (w, h, px, has_alpha) = rgba(&out);
        assert_eq!((w, h), (80, 60), "{name}");
        assert!(has_alpha, "{name}: without a skybox the PNG is RGBA");
        assert_eq!(
            px[0], [0; 4],
            "{name}: the background without a skybox is transparent"
        );
        let covered = px.iter().filter(|p| p[3] == 255).count();
        let edges = px.iter().filter(|p| p[3] > 0 && p[3] < 255).count();
        assert!(
            covered > 80 * 60 / 50,
            "{name}: the model covers {covered} pixels"
        );
        assert!(
            edges > 0 && edges < covered,
            "{name}: {edges} anti-aliased edge pixels have a fractional alpha ({covered} opaque)"
        );
    }
    // renderSkybox: the environment is the background.
    let out = dir.join("sky.png");
    let config = format!(
        r#"{{"scenario": {{"model": "{}", "lighting": "{}", "renderSkybox": true,
            "dimensions": {{"width": 40, "height": 30}}, "target": {{"y": 0.75}}, "orbit": {{"radius": 2}}}},
            "outputFile": "{}"}}"#,
        s(&gltf.join("CesiumMan/glTF-Binary/CesiumMan.glb")),
        s(&hdr),
        s(&out)
    );
    let (code, stdout, err) = fidelity(&[&config, "--ibl-quality", "fast"]);
    assert_eq!(code, 0, "{stdout}\n{err}");
    let (_, _, px, has_alpha) = rgba(&out);
    assert!(!has_alpha, "with a skybox the PNG is opaque RGB");
    assert_ne!(px[0], [255; 4], "the corner shows the environment");
}

/// `luz fidelity` equals `luz render` of the equivalent luz scene written by hand from
/// docs/fidelity.md: the scenario {target y 0.75, orbit radius 2 (theta 0, phi 90), 40×30,
/// verticalFoV 45} is a camera at (0, 0.75, 2) looking along −z with +y up, 80×60 pixels, ACES at
/// +0.4618 EV, the HDR at intensity 1 turned by −90° without background, a transparent
/// background, the model with its lights. The scene `--scene-out` writes renders the same
/// pixels (and alpha) too.
#[test]
fn fidelity_equals_luz_render_of_the_equivalent_scene() {
    let Some(gltf) = shared_dir("gltf") else {
        return;
    };
    let Some(envs) = shared_dir("environments") else {
        return;
    };
    let model = gltf.join("CesiumMan/glTF-Binary/CesiumMan.glb");
    let hdr = envs.join("newport_loft.hdr");
    let dir = scratch("fidelity-equal");
    let out = dir.join("fidelity.png");
    let config = format!(
        r#"{{"scenario": {{"model": "{}", "lighting": "{}", "dimensions": {{"width": 40, "height": 30}},
            "target": {{"y": 0.75}}, "orbit": {{"radius": 2}}}}, "outputFile": "{}"}}"#,
        s(&model),
        s(&hdr),
        s(&out)
    );
    let written = dir.join("written.json");
    let (code, stdout, err) =
        fidelity(&[&config, "--ibl-quality", "fast", "--scene-out", s(&written)]);
    assert_eq!(code, 0, "{stdout}\n{err}");
    let by_hand = format!(
        r#"{{
  "camera": {{"position": [0, 0.75, 2], "target": [0, 0.75, 1], "up": [0, 1, 0],
              "fov_y_deg": 45, "near": 0.004, "far": 400}},
  "output": {{"width": 80, "height": 60, "exposure": 0.4618, "tonemap": "aces", "msaa": 4,
              "background": [0, 0, 0], "transparent": true}},
  "ambient": [0, 0, 0],
  "environment": {{"hdr": "{}", "intensity": 1, "rotation_deg": -90, "show_background": false}},
  "objects": [{{"mesh": {{"type": "gltf", "path": "{}", "lights": true}}}}]
}}"#,
        s(&hdr),
        s(&model)
    );
    let hand = dir.join("hand.json");
    std::fs::write(&hand, by_hand).unwrap();
    let reference = rgba(&out);
    for scene in [&hand, &written] {
        let rendered = dir.join("render.png");
        let (code, stdout, err) = luz(&[
            "render",
            s(scene),
            "-o",
            s(&rendered),
            "--ibl-quality",
            "fast",
        ]);
        assert_eq!(code, 0, "{stdout}\n{err}");
        assert!(err.contains("validation: 0 errors, 0 warnings"), "{err}");
        let got = rgba(&rendered);
        assert_eq!((got.0, got.1, got.3), (reference.0, reference.1, true));
        let differing = got
            .2
            .iter()
            .zip(&reference.2)
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(
            differing,
            0,
            "{}: {differing} pixels differ",
            scene.display()
        );
    }
}

/// The environment lies where three.js, the Sample Viewer and the generator's Blender script put
/// it: an equirectangular image of four colour quarters in u (red, green, blue, grey), seen as
/// the skybox from four orbits, shows at each corner of the picture the quarter three.js's
/// `equirectUv` (u = 0.5 + atan2(z, x)/2π, v = 0 up) gives for that corner's view ray. The model
/// (CesiumMan, 20 m away) stays in the middle.
#[test]
fn environment_orientation_is_three_js_equirect() {
    let Some(gltf) = shared_dir("gltf") else {
        return;
    };
    let dir = scratch("fidelity-orientation");
    let hdr = dir.join("quarters.hdr");
    const QUARTERS: [[f32; 3]; 4] = [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.5, 0.5, 0.5],
    ];
    image::Rgb32FImage::from_fn(256, 128, |x, _| image::Rgb(QUARTERS[(x / 64) as usize]))
        .save(&hdr)
        .unwrap();
    let model = gltf.join("CesiumMan/glTF-Binary/CesiumMan.glb");
    let (w, h) = (32u32, 32u32);
    for theta in [-90.0f64, 0.0, 90.0, 180.0] {
        let out = dir.join(format!("theta{theta}.png"));
        let config = format!(
            r#"{{"scenario": {{"model": "{}", "lighting": "{}", "renderSkybox": true,
                "dimensions": {{"width": {}, "height": {}}}, "orbit": {{"radius": 20, "theta": {theta}}}}},
                "outputFile": "{}"}}"#,
            s(&model),
            s(&hdr),
            w / 2,
            h / 2,
            s(&out)
        );
        let (code, stdout, err) = fidelity(&[&config, "--ibl-quality", "fast"]);
        assert_eq!(code, 0, "{stdout}\n{err}");
        let (_, _, px, _) = rgba(&out);
        // The camera at r·(sin θ, 0, cos θ) looks along −that; right = forward × up.
        let t = theta.to_radians();
        let forward = [-t.sin(), 0.0, -t.cos()];
        let right = [-forward[2], 0.0, forward[0]];
        let half = (22.5f64).to_radians().tan();
        for (cx, cy) in [(1u32, 1u32), (w - 2, 1), (1, h - 2), (w - 2, h - 2)] {
            let nx = ((cx as f64 + 0.5) / w as f64) * 2.0 - 1.0;
            let ny = 1.0 - ((cy as f64 + 0.5) / h as f64) * 2.0;
            let d: Vec<f64> = (0..3)
                .map(|i| forward[i] + nx * half * right[i] + ny * half * [0.0, 1.0, 0.0][i])
                .collect();
            let u = 0.5 + d[2].atan2(d[0]) / std::f64::consts::TAU;
            let quarter = ((u * 4.0).floor() as usize).min(3);
            let p = px[(cy * w + cx) as usize];
            let got = if p[0].abs_diff(p[1]) < 8 && p[1].abs_diff(p[2]) < 8 {
                3
            } else {
                (0..3).max_by_key(|&c| p[c]).unwrap()
            };
            assert_eq!(
                got, quarter,
                "theta {theta}: pixel ({cx}, {cy}) is {p:?}, three.js's u there is {u:.3}"
            );
        }
    }
}

/// Bad scenarios: one line naming the JSON path, exit 1, no panic, nothing rendered.
#[test]
fn bad_scenarios_name_the_json_path() {
    let dir = scratch("fidelity-bad");
    let model = dir.join("m.gltf");
    let hdr = dir.join("env.hdr");
    std::fs::write(&model, "{}").unwrap();
    std::fs::write(&hdr, "").unwrap();
    let out = dir.join("out.png");
    let with = |scenario: &str| {
        format!(
            r#"{{"scenario": {{"model": "{}", "lighting": "{}"{scenario}}}, "outputFile": "{}"}}"#,
            s(&model),
            s(&hdr),
            s(&out)
        )
    };
    let cases = [
        (with(r#", "orbit": {"radius": -1}"#), "scenario.orbit.radius: must be ≥ 0, not -1"),
        (with(r#", "colour": 1"#), "scenario.colour: unknown field (known: name, model,"),
        (with(r#", "orbit": {"rho": 1}"#), "scenario.orbit.rho: unknown field (known: theta, phi, radius)"),
        (with(r#", "orbit": {"theta": "left"}"#), "scenario.orbit.theta: must be a finite number"),
        (with(r#", "dimensions": {"width": 0}"#), "scenario.dimensions.width: must be a whole number"),
        (with(r#", "target": [0, 1, 0]"#), "scenario.target: must be a JSON object"),
        (with(r#", "verticalFoV": 180"#), "scenario.verticalFoV: must be in (0, 180)"),
        (with(r#", "renderSkybox": "yes""#), "scenario.renderSkybox: must be true or false"),
        (
            format!(r#"{{"scenario": {{"lighting": "{}"}}, "outputFile": "{}"}}"#, s(&hdr), s(&out)),
            "scenario.model: missing",
        ),
        (
            format!(r#"{{"scenario": {{"model": "{}/nope.glb"}}, "outputFile": "{}"}}"#, s(&dir), s(&out)),
            "scenario.model: ",
        ),
        (
            format!(r#"{{"scenario": {{"model": "{}"}}, "outputFile": "{}"}}"#, s(&model), s(&out)),
            // Relative to outputFile's folder, as the generator's paths are.
            &*Box::leak(
                format!(
                    "scenario.lighting: {}/../../../environments/lightroom_14b.hdr: no such file (the generator's default",
                    s(&dir)
                )
                .into_boxed_str(),
            ),
        ),
        (
            format!(r#"{{"scenario": {{"model": "{}", "lighting": "{}"}}, "outputFile": "x.jpg"}}"#, s(&model), s(&hdr)),
            "outputFile: must name a .png file",
        ),
        (
            format!(r#"{{"scenario": {{"model": "{}", "lighting": "{}"}}}}"#, s(&model), s(&hdr)),
            "outputFile: missing",
        ),
        (
            format!(r#"{{"scenario": {{"model": "{}", "lighting": "{}"}}, "outputFile": "{}"}}"#, s(&model), s(&model), s(&out)),
            "scenario.lighting: ",
        ),
        (r#"{"scenario": {}, "output": "x.png"}"#.to_string(), "output: unknown field (known: scenario, outputFile)"),
        ("{\"scenario\": ".to_string(), "not valid JSON"),
    ];
    for (config, needle) in cases {
        let (code, stdout, err) = fidelity(&[&config]);
        assert_eq!(code, 1, "{config}: {stdout}\n{err}");
        assert!(
            err.contains(&format!("luz: error: luz fidelity: {needle}")),
            "{config}: expected {needle:?} in {err}"
        );
        assert!(!stdout.contains("device:"), "nothing is rendered: {stdout}");
        assert!(!out.exists());
    }
    // The missing model's message names the file.
    let config = format!(
        r#"{{"scenario": {{"model": "{}/nope.glb"}}, "outputFile": "{}"}}"#,
        s(&dir),
        s(&out)
    );
    let (_, _, err) = fidelity(&[&config]);
    assert!(err.contains("nope.glb: no such file"), "{err}");
}

/// The real generator's layout (docs/fidelity.md, "Run through the real generator"): it runs
/// luz in its checkout's root with an absolute `outputFile` in `test/goldens/<scenario>/` and
/// `model`/`lighting` written `../../../…` for a folder two levels below `test/`. Without
/// `--root`, luz resolves them against `outputFile`'s folder, from any working folder.
#[test]
fn generator_relative_paths_resolve_against_the_output_folder() {
    let Some(gltf) = shared_dir("gltf") else {
        return;
    };
    let Some(envs) = shared_dir("environments") else {
        return;
    };
    let dir = scratch("fidelity-layout");
    let goldens = dir.join("test/goldens/luz-CesiumMan");
    std::fs::create_dir_all(&goldens).unwrap();
    std::fs::create_dir_all(dir.join("assets")).unwrap();
    std::fs::copy(
        gltf.join("CesiumMan/glTF-Binary/CesiumMan.glb"),
        dir.join("assets/CesiumMan.glb"),
    )
    .unwrap();
    std::fs::copy(envs.join("newport_loft.hdr"), dir.join("assets/loft.hdr")).unwrap();
    let out = goldens.join("luz-golden.png");
    let config = format!(
        r#"{{"scenario": {{"name": "luz-CesiumMan", "model": "../../../assets/CesiumMan.glb",
            "lighting": "../../../assets/loft.hdr", "dimensions": {{"width": 24, "height": 24}},
            "target": {{"y": 0.75}}, "orbit": {{"radius": 2}}, "exclude": ["vray"]}},
            "outputFile": "{}"}}"#,
        s(&out)
    );
    // The test runs in the crate's folder, where none of the relative paths exist.
    let (code, stdout, err) = fidelity(&[&config, "--ibl-quality", "fast"]);
    assert_eq!(code, 0, "{stdout}\n{err}");
    let (w, h, _, alpha) = rgba(&out);
    assert_eq!((w, h, alpha), (48, 48, true));
    // --root still overrides: against the scratch folder itself the `../../../` leave it.
    let (code, _, err) = fidelity(&[&config, "--ibl-quality", "fast", "--root", s(&dir)]);
    assert_eq!(code, 1);
    assert!(err.contains("scenario.model: "), "{err}");
}
