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
/// a second run reads the chain back. Every run under [`GPU_MEMORY_CEILING`].
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
        let mut cmd = luz_command(&args);
        cmd.env("LUZ_CACHE_DIR", cache);
        run(with_memory_ceiling(&mut cmd, GPU_MEMORY_CEILING)).parts()
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

/// A glTF file `instances.gltf` (with `grid.bin`) in `dir`: one mesh, a gently waved grid of
/// `n`×`n` quads (2n² triangles, normals in the file), placed by `nodes` nodes translated along
/// a row of rows in front of the camera, each also turned about y. Returns the scene that draws it.
fn instances_scene(dir: &std::path::Path, n: usize, nodes: usize) -> std::path::PathBuf {
    let mut bin: Vec<u8> = Vec::new();
    let put = |v: f32, bin: &mut Vec<u8>| bin.extend_from_slice(&v.to_le_bytes());
    let verts = (n + 1) * (n + 1);
    for j in 0..=n {
        for i in 0..=n {
            let (x, z) = (i as f32 / n as f32 - 0.5, j as f32 / n as f32 - 0.5);
            let y = 0.1 * (9.0 * x).sin() * (7.0 * z).cos();
            for v in [x, y, z] {
                put(v, &mut bin);
            }
        }
    }
    for j in 0..=n {
        for i in 0..=n {
            let (x, z) = (i as f32 / n as f32 - 0.5, j as f32 / n as f32 - 0.5);
            let (dx, dz) = (
                0.9 * (9.0 * x).cos() * (7.0 * z).cos(),
                -0.7 * (9.0 * x).sin() * (7.0 * z).sin(),
            );
            let len = (dx * dx + 1.0 + dz * dz).sqrt();
            for v in [-dx / len, 1.0 / len, -dz / len] {
                put(v, &mut bin);
            }
        }
    }
    let at = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            for v in [a, d, c, a, c, b] {
                bin.extend_from_slice(&v.to_le_bytes());
            }
        }
    }
    let (pos_len, idx_len) = (verts * 12, n * n * 6 * 4);
    std::fs::write(dir.join("grid.bin"), &bin).unwrap();
    let node_list: Vec<String> = (0..nodes)
        .map(|k| {
            let (x, z) = ((k % 40) as f32 * 1.2 - 24.0, -((k / 40) as f32) * 1.2 - 2.0);
            let angle = (k as f32 * 0.37).sin() * 0.5;
            format!(
                r#"{{"mesh": 0, "translation": [{x}, 0, {z}], "rotation": [0, {}, 0, {}]}}"#,
                angle.sin(),
                angle.cos()
            )
        })
        .collect();
    let roots: Vec<String> = (0..nodes).map(|k| k.to_string()).collect();
    let gltf = format!(
        r#"{{"asset": {{"version": "2.0"}},
 "buffers": [{{"uri": "grid.bin", "byteLength": {}}}],
 "bufferViews": [{{"buffer": 0, "byteLength": {pos_len}}},
                 {{"buffer": 0, "byteOffset": {pos_len}, "byteLength": {pos_len}}},
                 {{"buffer": 0, "byteOffset": {}, "byteLength": {idx_len}}}],
 "accessors": [{{"bufferView": 0, "componentType": 5126, "count": {verts}, "type": "VEC3",
                 "min": [-0.5, -0.1, -0.5], "max": [0.5, 0.1, 0.5]}},
               {{"bufferView": 1, "componentType": 5126, "count": {verts}, "type": "VEC3"}},
               {{"bufferView": 2, "componentType": 5125, "count": {}, "type": "SCALAR"}}],
 "meshes": [{{"name": "grid", "primitives": [{{"attributes": {{"POSITION": 0, "NORMAL": 1}}, "indices": 2}}]}}],
 "nodes": [{}],
 "scenes": [{{"nodes": [{}]}}], "scene": 0}}"#,
        bin.len(),
        2 * pos_len,
        n * n * 6,
        node_list.join(", "),
        roots.join(", ")
    );
    std::fs::write(dir.join("instances.gltf"), gltf).unwrap();
    let scene = dir.join("instances.json");
    std::fs::write(
        &scene,
        r#"{
        "camera": {"position": [0, 3, 4], "target": [0, 0, -10], "up": [0, 1, 0], "fov_y_deg": 60, "near": 0.1, "far": 100},
        "output": {"width": 96, "height": 64, "msaa": 1},
        "lights": [{"type": "directional", "direction": [-0.4, -1, -0.5], "intensity": 2}],
        "ambient": [0.1, 0.1, 0.1],
        "materials": {"m": {"model": "lambert", "albedo": [0.7, 0.5, 0.4]}},
        "objects": [{"mesh": {"type": "gltf", "path": "instances.gltf"}, "material": "m"}]
    }"#,
    )
    .unwrap();
    scene
}

/// Issue 38, item 5: 1,000 nodes placing one mesh (translated and turned) leave one LOD cache
/// file, not 1,000: the chain is keyed on the mesh's local form and carried through each node's
/// transform. The first run builds it once and reads it 999 times; a second run reads it 1,000
/// times and draws the same pixels. Both under [`GPU_MEMORY_CEILING`].
#[test]
fn nodes_placing_one_mesh_share_one_cache_file() {
    let dir = scratch("lod-instances");
    let scene = instances_scene(&dir, 16, 1000);
    let cache = dir.join("cache");
    let render = |out: &str| {
        let out = dir.join(out);
        let args = [
            "render",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--ibl-quality",
            "fast",
            "--verbose",
        ];
        let mut cmd = luz_command(args);
        cmd.env("LUZ_CACHE_DIR", &cache);
        let (code, stdout, stderr) = run(with_memory_ceiling(&mut cmd, GPU_MEMORY_CEILING)).parts();
        assert_ran_clean(code, &stdout, &stderr);
        // The pixels (the file's provenance holds the run's own figures).
        let image = luz::imageio::load(&out).unwrap();
        (stdout, (image.width, image.height, image.display))
    };
    let (first, image) = render("a.png");
    assert!(
        first.contains("LOD chains: 1 built, 999 read from the cache"),
        "{first}"
    );
    let lod: Vec<_> = std::fs::read_dir(cache.join("lod"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(lod.len(), 1, "{lod:?}");
    let (second, again) = render("b.png");
    assert!(
        second.contains("LOD chains: 0 built, 1000 read from the cache"),
        "{second}"
    );
    assert!(image == again, "the image from cached chains differs");
    // Drawn at several levels (not all whole, not all coarsest).
    assert!(first.contains("automatic LOD (budget"), "{first}");
    assert_eq!(std::fs::read_dir(cache.join("lod")).unwrap().count(), 1);
}

/// Issue 38, items 2, 6 and 10 through the binary, each run under [`GPU_MEMORY_CEILING`] and a
/// time limit (these inputs once never finished):
/// - a generated 4.5 MB OBJ of 500,000 zero-area triangles and a 40,000-triangle polygon fan are
///   drawn whole, reported in one summary line, and their failures are cached (the second run
///   simplifies nothing);
/// - a run killed mid-write (SIGXFSZ from a 4 KiB largest-file limit, as a crash or `kill -9`
///   would) leaves its temporary file; the next run removes it and writes the cache whole;
/// - a folder in place of a cache entry gives one warning that says what it costs.
#[test]
fn simplifier_and_cache_problems_under_a_memory_ceiling() {
    let dir = scratch("lod-ceiling");
    // 2,000 vertices on one line, 500,000 triangles between them: no triangle has an area.
    let mut obj = String::new();
    for i in 0..2000 {
        obj += &format!("v {} {} 0\n", i as f32 * 0.001, i as f32 * 0.002);
    }
    for k in 0..500_000u64 {
        let a = k % 1997 + 1;
        obj += &format!("f {} {} {}\n", a, a + 1, a + 3);
    }
    assert!(obj.len() > 4 << 20, "{}", obj.len());
    std::fs::write(dir.join("degenerate.obj"), &obj).unwrap();
    // A disc of 40,000 triangles fanned around its centre (one polygon, valence 40,000).
    let mut fan = String::from("v 0 0 0\n");
    let n = 40_000;
    for i in 0..=n {
        let a = std::f32::consts::TAU * i as f32 / n as f32;
        fan += &format!("v {} {} 0\n", a.cos(), a.sin());
    }
    for i in 0..n {
        fan += &format!("f 1 {} {}\n", i + 2, i + 3);
    }
    std::fs::write(dir.join("fan.obj"), &fan).unwrap();
    let scene = dir.join("problems.json");
    std::fs::write(
        &scene,
        r#"{
        "camera": {"position": [0, 0, 4], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 50, "near": 0.1, "far": 20},
        "output": {"width": 64, "height": 48, "msaa": 1},
        "lights": [{"type": "directional", "direction": [-0.4, -1, -0.5], "intensity": 2}],
        "materials": {"m": {"model": "lambert", "albedo": [0.7, 0.5, 0.4]}},
        "objects": [{"mesh": {"type": "obj", "path": "degenerate.obj"}, "material": "m"},
                    {"mesh": {"type": "obj", "path": "fan.obj"}, "material": "m", "position": [0.5, 0, 0]}]
    }"#,
    )
    .unwrap();
    let out = dir.join("out.png");
    let cache = dir.join("cache");
    let render = |scene: &std::path::Path, file_limit: Option<u64>| {
        let args = [
            "render",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--ibl-quality",
            "fast",
            "--verbose",
        ];
        let mut cmd = luz_command(args);
        cmd.env("LUZ_CACHE_DIR", &cache);
        with_limits(&mut cmd, GPU_MEMORY_CEILING, file_limit);
        run_within(&mut cmd, std::time::Duration::from_secs(300))
    };
    let ran = render(&scene, None);
    assert_ran_clean(ran.code, &ran.stdout, &ran.stderr);
    let w = warnings(&ran.stderr);
    assert_eq!(w.len(), 1, "{}", ran.stderr);
    assert!(
        w[0].contains(
            "automatic LOD: 2 mesh(es) drawn at full detail because their simplification failed"
        ) && w[0].contains("all 500000 triangles are degenerate")
            && w[0].contains("and 1 more"),
        "{}",
        ran.stderr
    );
    assert!(
        ran.stdout
            .contains("LOD chains: 0 built, 0 read from the cache, 2 failed"),
        "{}",
        ran.stdout
    );
    let ran = render(&scene, None);
    assert_ran_clean(ran.code, &ran.stdout, &ran.stderr);
    assert!(
        ran.stdout
            .contains("LOD chains: 0 built, 2 read from the cache, 2 failed"),
        "{}",
        ran.stdout
    );
    // Killed mid-write: a grid whose chain file is larger than the 4 KiB limit.
    let grid = grid_scene(&dir, 48);
    std::fs::remove_dir_all(&cache).unwrap();
    let killed = render(&grid, Some(4096));
    use std::os::unix::process::ExitStatusExt;
    assert_eq!(
        killed.status.signal(),
        Some(libc::SIGXFSZ),
        "{:?}: {}",
        killed.status,
        killed.stderr
    );
    let temps = |d: &std::path::Path| -> Vec<std::path::PathBuf> {
        ["", "lod"]
            .iter()
            .flat_map(|s| std::fs::read_dir(d.join(s)).into_iter().flatten())
            .map(|e| e.unwrap().path())
            .filter(|p| p.to_string_lossy().ends_with(".tmp"))
            .collect()
    };
    assert!(!temps(&cache).is_empty(), "the kill left no temporary file");
    let ran = render(&grid, None);
    assert_ran_clean(ran.code, &ran.stdout, &ran.stderr);
    assert!(warnings(&ran.stderr).is_empty(), "{}", ran.stderr);
    assert!(temps(&cache).is_empty(), "{:?}", temps(&cache));
    let lod: Vec<_> = std::fs::read_dir(cache.join("lod"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(lod.len(), 1, "{lod:?}");
    // A folder in place of the entry: one warning with its cost, the image still drawn.
    std::fs::remove_file(&lod[0]).unwrap();
    std::fs::create_dir(&lod[0]).unwrap();
    let ran = render(&grid, None);
    assert_ran_clean(ran.code, &ran.stdout, &ran.stderr);
    let w = warnings(&ran.stderr);
    assert_eq!(w.len(), 1, "{}", ran.stderr);
    assert!(
        w[0].contains("a folder is in its place") && w[0].contains("simplified again on every run"),
        "{}",
        ran.stderr
    );
}

/// Issue 38, item 6 (a full disk) through the binary under [`GPU_MEMORY_CEILING`]: with every
/// file the run writes limited to 64 KiB and SIGXFSZ ignored, the cache writes fail half way
/// (EFBIG, as ENOSPC would); the run still draws its image (a small PNG), warns once per cache
/// that cannot be written, saying what it costs, and leaves no temporary file behind.
#[test]
fn a_full_disk_leaves_no_temporary_file_and_one_warning() {
    let dir = scratch("lod-full-disk");
    let scene = grid_scene(&dir, 48);
    let out = dir.join("out.png");
    let cache = dir.join("cache");
    let args = [
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--ibl-quality",
        "fast",
    ];
    let mut cmd = luz_command(args);
    cmd.env("LUZ_CACHE_DIR", &cache);
    with_limits(&mut cmd, GPU_MEMORY_CEILING, Some(64 << 10));
    as_if_the_disk_were_full(&mut cmd);
    let ran = run_within(&mut cmd, std::time::Duration::from_secs(300));
    assert_ran_clean(ran.code, &ran.stdout, &ran.stderr);
    assert!(out.is_file());
    let w = warnings(&ran.stderr);
    assert!(!w.is_empty(), "{}", ran.stderr);
    assert!(
        w.iter().all(|l| l.contains("cannot write")
            && (l.contains("simplified again on every run") || l.contains("every run"))),
        "{}",
        ran.stderr
    );
    assert!(
        w.iter().any(|l| l.contains("cannot write LOD cache files")),
        "{}",
        ran.stderr
    );
    let left: Vec<std::path::PathBuf> = ["", "lod"]
        .iter()
        .flat_map(|s| std::fs::read_dir(cache.join(s)).into_iter().flatten())
        .map(|e| e.unwrap().path())
        .filter(|p| p.to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}
