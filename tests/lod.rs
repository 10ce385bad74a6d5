//! Automatic LOD of meshes (issue 17) on lavapipe with validation on: the chain of a real model
//! built once however many objects use it, the levels chosen by distance and budget, the image
//! against full detail (FLIP), and budget 0 drawing every mesh whole.

mod common;

use common::*;

use luz::headless::{Headless, RenderOptions};
use luz::imageio::{FileFormat, LoadedImage};
use luz::scene::Scene;

/// `count` bunnies (the shared Stanford bunny, 69,451 triangles) in rows from 2 to ~60 units
/// away, some behind the camera, at `budget` px.
fn bunnies(count: usize, budget: f32) -> Option<Scene> {
    bunnies_lit(count, budget, false)
}

/// [`bunnies`], the sun casting shadows when `shadow`.
fn bunnies_lit(count: usize, budget: f32, shadow: bool) -> Option<Scene> {
    shared_dir("models/stanford-bunny.obj")?;
    let text = bunnies_text(
        count,
        budget,
        shadow,
        "../../shared/models/stanford-bunny.obj",
    );
    Some(luz::scene::parse(&text, &root().join("tests/lod.json")).expect("scene"))
}

/// The scene file of [`bunnies_lit`], the model at `model` (relative to the scene's folder, or
/// absolute).
fn bunnies_text(count: usize, budget: f32, shadow: bool, model: &str) -> String {
    let mut objects = Vec::new();
    for i in 0..count {
        let (row, col) = (i / 6, i % 6);
        objects.push(format!(
            r#"{{"mesh": {{"type": "obj", "path": "{model}"}}, "material": "m",
                "position": [{}, -0.33, {}], "rotation_deg": [0, {}, 0], "scale": [10, 10, 10]}}"#,
            (col as f32 - 2.5) * 1.8,
            4.0 - 3.5 * row as f32,
            (i * 47) % 360
        ));
    }
    format!(
        r#"{{
        "camera": {{"position": [0, 1.6, 6], "target": [0, 0.5, -10], "up": [0, 1, 0], "fov_y_deg": 50, "near": 0.1, "far": 200}},
        "output": {{"width": 320, "height": 180, "msaa": 1, "tessellation_error_px": {budget}}},
        "lights": [{{"type": "directional", "direction": [-0.4, -1, -0.5], "intensity": 2.5, "shadow": {shadow}}}],
        "ambient": [0.05, 0.05, 0.05],
        "materials": {{"m": {{"model": "lambert", "albedo": [0.7, 0.5, 0.4]}}}},
        "objects": [{}]
    }}"#,
        objects.join(",")
    )
}

fn mean_flip(scene: &Scene, a: &luz::imageio::LinearImage, b: &luz::imageio::LinearImage) -> f32 {
    let load = |img| {
        LoadedImage::from_linear(
            img,
            FileFormat::Png,
            scene.output.exposure,
            scene.output.tonemap,
        )
    };
    luz::diff::compare(&load(a), &load(b), &Default::default())
        .expect("same size")
        .flip_mean
}

/// Mean FLIP between the automatic levels and full detail, at the default budget and a loose one.
const MAX_FLIP_DEFAULT_BUDGET: f32 = 0.01;

#[test]
fn one_chain_per_mesh_levels_by_distance_and_flip_against_full_detail() {
    let Some(full_scene) = bunnies(48, 0.0) else {
        return;
    };
    let ctx = gpu();
    let options = RenderOptions::default();
    let mut full = Headless::with_options(&ctx, &full_scene, &options).unwrap();
    // 48 objects, one mesh: one chain (no cache: built here).
    assert_eq!(
        full.lod_stats(),
        luz::scene::lod::ChainStats {
            built: 1,
            ..Default::default()
        }
    );
    // Budget 0: every object at level 0, every triangle of the objects in view drawn.
    let choices = full.lod_choices(&full_scene);
    assert_eq!(choices.len(), 48);
    assert!(
        choices.iter().all(|c| c.level == 0 && c.levels >= 5),
        "{choices:?}"
    );
    let in_view = choices.iter().filter(|c| c.visible).count() as u64;
    assert!((12..48).contains(&in_view), "{in_view} in view");
    assert_eq!(full.triangles_drawn(), in_view * 69_451);
    full.render().unwrap();
    let full_image = full.image().unwrap();

    let auto_scene = bunnies(48, luz::scene::DEFAULT_TESSELLATION_ERROR_PX).unwrap();
    let mut auto = Headless::with_options(&ctx, &auto_scene, &options).unwrap();
    let choices = auto.lod_choices(&auto_scene);
    // Farther rows, coarser levels (never finer); the nearest row is finer than the farthest.
    let level = |row: usize| choices[row * 6 + 2].level;
    for row in 2..7 {
        assert!(level(row + 1) >= level(row), "{choices:?}");
    }
    assert!(level(7) > level(2), "{choices:?}");
    for c in &choices {
        assert!(
            c.error_px <= luz::scene::DEFAULT_TESSELLATION_ERROR_PX,
            "{c:?}"
        );
    }
    let drawn = auto.triangles_drawn();
    assert!(drawn < full.triangles_drawn() / 2, "{drawn} triangles");
    auto.render().unwrap();
    let flip = mean_flip(&auto_scene, &full_image, &auto.image().unwrap());
    eprintln!(
        "default budget: {drawn} of {} triangles, mean FLIP {flip:.5} against full detail",
        full.triangles_drawn()
    );
    assert!(flip <= MAX_FLIP_DEFAULT_BUDGET, "mean FLIP {flip}");
    // A loose budget (0.2 px): far fewer triangles, a larger error (measured 0.00845 here at
    // 320x180 with the levels' placed vertices, 0.0113 with the kept ones; on the 40 M scene at
    // 1280x720 0.0068 and 0.0092, docs/performance.md).
    let loose_scene = bunnies(48, 0.2).unwrap();
    let mut loose = Headless::with_options(&ctx, &loose_scene, &options).unwrap();
    let loose_drawn = loose.triangles_drawn();
    assert!(loose_drawn < drawn, "{loose_drawn} against {drawn}");
    loose.render().unwrap();
    let flip = mean_flip(&loose_scene, &full_image, &loose.image().unwrap());
    eprintln!("0.2 px: {loose_drawn} triangles, mean FLIP {flip:.5} against full detail");
    assert!(flip <= MAX_FLIP_LOOSE_BUDGET, "mean FLIP {flip}");
    assert_no_validation_messages(&ctx);
}

/// Mean FLIP allowed at 0.2 px on this small scene: the issue's goal for the 40 M scene at
/// 1280x720, which the levels' kept vertices missed here (0.0113) and their placed ones meet
/// (0.00845; with shadows 0.00753).
const MAX_FLIP_LOOSE_BUDGET: f32 = 0.01;

/// `luz render` reports the LOD choice (summary; `--verbose`: per object and how the chain was
/// made); `luz bench --compare-budget` refuses a negative budget, naming the option.
#[test]
fn render_reports_the_levels_and_bench_checks_its_budget() {
    let Some(_) = shared_dir("models/stanford-bunny.obj") else {
        return;
    };
    let scene = root().join("assets/scenes/lod/bunnies_lab.json");
    let dir = scratch("lod-render");
    let out = dir.join("lab.png");
    let (code, stdout, stderr) = luz(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--verbose",
        "--no-cache",
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("automatic LOD (budget 0.2 px): 36 mesh object(s), 14 in view at levels"),
        "{stdout}"
    );
    assert!(stdout.contains("  bunny_0_0: out of view"), "{stdout}");
    assert!(
        stdout.contains("  bunny_1_2: level 5 of 8, 2169 of 69451 triangles"),
        "{stdout}"
    );
    assert!(
        stdout.contains("LOD chains: 1 built, 0 read from the cache, 0 failed"),
        "{stdout}"
    );
    let (code, _, stderr) = luz(&[
        "bench",
        scene.to_str().unwrap(),
        "--frames",
        "1",
        "--compare-budget=-1",
    ]);
    assert_ne!(code, 0);
    assert!(
        stderr.contains("--compare-budget: must be a number of pixels >= 0, got -1"),
        "{stderr}"
    );
}

/// Shadow casters draw at levels picked from the light's projection: at budget 0 every layer
/// draws whole bunnies; at 0.2 px (texels) under half the triangles go into the maps (a third
/// measured), and the image stays within the loose budget's FLIP of full detail.
#[test]
fn shadow_casters_pick_levels_from_the_light_projection() {
    let Some(full_scene) = bunnies_lit(24, 0.0, true) else {
        return;
    };
    let ctx = gpu();
    let options = RenderOptions::default();
    let mut full = Headless::with_options(&ctx, &full_scene, &options).unwrap();
    let full_shadow = full.shadow_triangles_drawn();
    assert!(
        full_shadow >= 24 * 69_451 && full_shadow.is_multiple_of(69_451),
        "{full_shadow} triangles in the maps"
    );
    full.render().unwrap();
    let auto_scene = bunnies_lit(24, 0.2, true).unwrap();
    let mut auto = Headless::with_options(&ctx, &auto_scene, &options).unwrap();
    let auto_shadow = auto.shadow_triangles_drawn();
    eprintln!("shadow maps: {auto_shadow} triangles at 0.2 px, {full_shadow} at 0");
    assert!(
        auto_shadow * 2 < full_shadow,
        "{auto_shadow} of {full_shadow}"
    );
    assert!(auto_shadow > 0);
    auto.render().unwrap();
    let flip = mean_flip(&auto_scene, &full.image().unwrap(), &auto.image().unwrap());
    eprintln!("0.2 px with shadows: mean FLIP {flip:.5} against full detail");
    assert!(flip <= MAX_FLIP_LOOSE_BUDGET, "mean FLIP {flip}");
    assert_no_validation_messages(&ctx);
}

/// The viewer picks levels for its window's height, not the scene's output height: the same
/// bunnies in a window four times as tall draw more triangles.
#[test]
fn the_viewer_projects_errors_onto_its_window() {
    let Some(bunny) = shared_dir("models/stanford-bunny.obj") else {
        return;
    };
    let dir = scratch("lod-viewer");
    let path = dir.join("bunnies.json");
    std::fs::write(&path, bunnies_text(12, 0.5, false, bunny.to_str().unwrap())).unwrap();
    let drawn = |name: &str, script: &str| -> Option<u64> {
        let json = dir.join(name);
        let mut args = vec![
            "view",
            path.to_str().unwrap(),
            "--bench",
            "--frames",
            "7",
            "--warmup",
            "4",
            "--json",
            json.to_str().unwrap(),
        ];
        if !script.is_empty() {
            args.extend(["--script", script]);
        }
        let (code, out, err) = luz_in_window(&args)?;
        assert_eq!(code, 0, "{out}\n{err}");
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        assert_eq!(
            v["height"],
            if script.is_empty() { 180 } else { 720 },
            "{v}"
        );
        Some(v["triangles_drawn"].as_u64().expect("triangles_drawn"))
    };
    let Some(small) = drawn("small.json", "") else {
        return;
    };
    let Some(tall) = drawn("tall.json", "0:resize=1280x720") else {
        return;
    };
    assert!(
        tall as f64 > 1.5 * small as f64,
        "{small} triangles at 320×180, {tall} at 1280×720"
    );
    println!("{small} triangles drawn at 320×180, {tall} at 1280×720");
}

/// `luz lab --only lod`: every budget's row carries its mean FLIP against the group's full-detail
/// render (issue 17's measure) besides its error against the CPU reference; full detail's is 0 and
/// a loose budget's matches `luz::diff` on the same two renders.
#[test]
fn lab_lod_rows_report_flip_against_full_detail() {
    let Some(bunny) = shared_dir("models/stanford-bunny.obj") else {
        return;
    };
    let dir = scratch("lod-lab");
    let path = dir.join("bunnies.json");
    std::fs::write(&path, bunnies_text(12, 0.2, false, bunny.to_str().unwrap())).unwrap();
    let out = dir.join("out");
    let ran = run(&mut luz_command([
        "lab",
        path.to_str().unwrap(),
        "--only",
        "lod",
        "--frames",
        "1",
        "--rounds",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]));
    assert!(ran.status.success(), "{}\n{}", ran.stdout, ran.stderr);
    assert!(
        ran.stderr.contains("validation: 0 errors"),
        "{}",
        ran.stderr
    );
    assert!(ran.stdout.contains("FLIP full"), "{}", ran.stdout);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    let results = json["results"].as_array().unwrap();
    let row = |label: &str| {
        results
            .iter()
            .find(|r| r["label"] == label)
            .unwrap_or_else(|| panic!("{label} missing"))
    };
    assert_eq!(row("lod 0 px (full detail)")["flip_vs_full"], 0.0);
    for r in results {
        let v = &r["flip_vs_full"];
        if r["group"] == "lod" {
            let f = v.as_f64().unwrap_or_else(|| panic!("{r}"));
            assert!((0.0..0.2).contains(&f), "{r}");
        } else {
            assert!(v.is_null(), "{r}");
        }
    }
    let loose = row("lod 4 px")["flip_vs_full"].as_f64().unwrap();
    let fine = row("lod 0.05 px")["flip_vs_full"].as_f64().unwrap();
    assert!(loose > fine && loose > 0.0, "4 px {loose}, 0.05 px {fine}");
    // The same two renders compared here.
    let ctx = gpu();
    let scene = luz::scene::load(&path).unwrap();
    let image = |budget: f32| {
        let mut s = scene.clone();
        s.output.tessellation_error_px = budget;
        luz::scene::tessellation::resolve(&mut s);
        let mut r = Headless::with_options(&ctx, &s, &RenderOptions::default()).unwrap();
        r.render().unwrap();
        r.image().unwrap()
    };
    let here = mean_flip(&scene, &image(0.0), &image(4.0)) as f64;
    assert!((here - loose).abs() < 1e-4, "lab {loose}, here {here}");
    assert_no_validation_messages(&ctx);
}

/// Every mesh of the shared glTF files and OBJ models large enough to simplify gets a chain
/// (issue 38: `color_teapot_spheres.gltf`'s teapot and spheres, stored with no shared vertex, and
/// an open band of `retroufo.glb` could not be reduced): at least one level below the mesh, the
/// first with at most 90 % of its triangles.
#[test]
fn every_shared_model_gets_a_chain() {
    let (Some(gltf), Some(models)) = (shared_dir("gltf"), shared_dir("models")) else {
        return;
    };
    let mut files = Vec::new();
    let mut folders = vec![gltf, models];
    while let Some(dir) = folders.pop() {
        for e in std::fs::read_dir(&dir).unwrap() {
            let p = e.unwrap().path();
            match p.extension().and_then(|e| e.to_str()) {
                _ if p.is_dir() => folders.push(p),
                Some("gltf" | "glb" | "obj") => files.push(p),
                _ => {}
            }
        }
    }
    assert!(files.len() >= 10, "{files:?}");
    let mut meshes = 0;
    for file in &files {
        let scene = luz::scene::load(file).unwrap_or_else(|e| panic!("{e}"));
        for o in &scene.objects {
            let triangles = o.mesh.indices.len() / 3;
            if triangles < luz::scene::lod::MIN_SIMPLIFIED_TRIANGLES {
                continue;
            }
            meshes += 1;
            let chain = luz::scene::lod::build(&o.mesh)
                .unwrap_or_else(|e| panic!("{}: {}: {e}", file.display(), o.name));
            assert!(chain.levels.len() >= 2, "{}: {}", file.display(), o.name);
            let first = chain.levels[1].triangles() as usize;
            assert!(
                first * 10 <= triangles * 9,
                "{}: {}: {first} of {triangles}",
                file.display(),
                o.name
            );
        }
    }
    assert!(meshes >= 30, "{meshes} meshes");
}

/// A scene drawing a generated grid OBJ of `n`×`n` quads (2n² triangles) under a procedural sky,
/// in `dir`: its path.
fn grid_scene(dir: &std::path::Path, n: usize) -> std::path::PathBuf {
    let mut obj = String::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, z) = (i as f32 / n as f32 - 0.5, j as f32 / n as f32 - 0.5);
            let y = 0.1 * (9.0 * x).sin() * (7.0 * z).cos();
            obj += &format!("v {x} {y} {z}\n");
        }
    }
    let at = |i: usize, j: usize| j * (n + 1) + i + 1;
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            obj += &format!("f {a} {d} {c} {b}\n");
        }
    }
    std::fs::write(dir.join("grid.obj"), obj).unwrap();
    let scene = dir.join("grid.json");
    std::fs::write(
        &scene,
        r#"{
        "camera": {"position": [0, 1, 1.5], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 50, "near": 0.1, "far": 20},
        "output": {"width": 64, "height": 48, "msaa": 1},
        "environment": {"procedural": "sky", "intensity": 0.5},
        "lights": [{"type": "directional", "direction": [-0.4, -1, -0.5], "intensity": 2}],
        "materials": {"m": {"model": "lambert", "albedo": [0.7, 0.5, 0.4]}},
        "objects": [{"mesh": {"type": "obj", "path": "grid.obj"}, "material": "m"}]
    }"#,
    )
    .unwrap();
    scene
}

/// The warnings of a run (stderr lines starting `warning: `).
fn warnings(stderr: &str) -> Vec<&str> {
    stderr
        .lines()
        .filter(|l| l.starts_with("warning: "))
        .collect()
}

/// Cache problems through the binary, each with one warning saying what it costs (issue 38):
/// `LUZ_CACHE_DIR` naming a file, a folder that cannot be written, a zeroed cache file. A usable
/// folder loses its stale temporary files and keeps the `--cache-max-mb` cap (oldest first), and
/// a second run reads the chain back.
#[test]
fn the_cache_folder_is_checked_tidied_and_capped() {
    let dir = scratch("lod-cache-dir");
    let scene = grid_scene(&dir, 48);
    let out = dir.join("out.png");
    let render = |cache: &std::path::Path, extra: &[&str]| {
        let mut args = vec![
            "render",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--ibl-quality",
            "fast",
            "--verbose",
        ];
        args.extend_from_slice(extra);
        run(luz_command(&args).env("LUZ_CACHE_DIR", cache)).parts()
    };
    // A file, and a folder that cannot be written (/proc, even for root): one warning, a render.
    let file = dir.join("not-a-folder");
    std::fs::write(&file, b"x").unwrap();
    for (cache, what) in [
        (file.as_path(), "is a file, not a folder"),
        (
            std::path::Path::new("/proc"),
            "cannot write in the cache folder",
        ),
    ] {
        let (code, _, stderr) = render(cache, &[]);
        assert_eq!(code, 0, "{stderr}");
        let w = warnings(&stderr);
        assert_eq!(w.len(), 1, "{stderr}");
        assert!(
            w[0].contains(what) && w[0].contains("nothing is cached"),
            "{stderr}"
        );
    }
    // A folder with temporary files of runs that were killed and an old 3 MiB cache file.
    let cache = dir.join("cache");
    std::fs::create_dir_all(cache.join("lod")).unwrap();
    let dead = 4_194_999; // beyond Linux's largest process id
    let stale = [
        cache.join(format!(".a.ibl.{dead}.tmp")),
        cache.join(format!("lod/.b.lod.{dead}.tmp")),
    ];
    for f in &stale {
        std::fs::write(f, vec![1u8; 1000]).unwrap();
    }
    let old = cache.join("lod/00000000000000ff.lod");
    std::fs::write(&old, vec![0u8; 3 << 20]).unwrap();
    let f = std::fs::File::options().append(true).open(&old).unwrap();
    f.set_modified(std::time::SystemTime::now() - std::time::Duration::from_secs(86400))
        .unwrap();
    let (code, stdout, stderr) = render(&cache, &["--cache-max-mb", "1"]);
    assert_eq!(code, 0, "{stderr}");
    assert!(warnings(&stderr).is_empty(), "{stderr}");
    assert!(stdout.contains("LOD chains: 1 built"), "{stdout}");
    assert!(stale.iter().all(|f| !f.exists()) && !old.exists());
    let files: Vec<std::path::PathBuf> = ["", "lod"]
        .iter()
        .flat_map(|d| std::fs::read_dir(cache.join(d)).unwrap())
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .collect();
    let total: u64 = files.iter().map(|p| p.metadata().unwrap().len()).sum();
    assert!(total <= 1 << 20, "{total} bytes: {files:?}");
    // The default cap keeps the chain: the next run reads it back.
    let (code, _, stderr) = render(&cache, &[]);
    assert_eq!(code, 0, "{stderr}");
    let (code, stdout, stderr) = render(&cache, &[]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("0 built, 1 read from the cache"),
        "{stdout}"
    );
    let lod: Vec<_> = std::fs::read_dir(cache.join("lod"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(lod.len(), 1, "{lod:?}");
    // Zeroed (a crash of the disk, not of luz): one warning, rebuilt and replaced.
    let len = lod[0].metadata().unwrap().len() as usize;
    std::fs::write(&lod[0], vec![0u8; len]).unwrap();
    let (code, stdout, stderr) = render(&cache, &[]);
    assert_eq!(code, 0, "{stderr}");
    let w = warnings(&stderr);
    assert_eq!(w.len(), 1, "{stderr}");
    assert!(w[0].contains("is damaged"), "{stderr}");
    assert!(stdout.contains("LOD chains: 1 built"), "{stdout}");
}
