//! Soak: 10 000 frames through `luz bench` with validation on, of a scene with every feature on;
//! resident memory and the GPU allocator's live allocations, sampled every 1 000 frames, must stay
//! flat.
//!
//! Flat and Gouraud shading and shadows are in: on this machine's lavapipe (Mesa 22.3.6) they once
//! grew resident memory every frame (a shader variant compiled and leaked per bind, from uniform
//! inlining; `opaque()` in include/bindings.glsl), and `shadowed_and_vertex_lit_frames_keep_memory_flat`
//! below guards that in seconds.

mod common;

use std::path::Path;

use common::{luz_command, run, scratch};

/// A scene with every feature of luz on, written into `dir` with its textures and OBJ + MTL:
/// all seven material models (principled with anisotropy, clearcoat, sheen and subsurface), every
/// texture map (base colour, normal, roughness, metallic, occlusion, emissive, and an `orm`
/// pack), directional, point (both falloffs) and spot lights, every primitive and an OBJ with an
/// MTL, the three shading frequencies, automatic tessellation, fog, normalize saturation, a
/// shadowed sun (PCF cascades), MSAA 4x, a tone map, and a procedural sky environment with
/// split-sum specular.
fn every_feature_scene(dir: &Path) -> std::path::PathBuf {
    luz::texture::checker(32, 4, [230, 200, 40, 255], [30, 60, 200, 255])
        .save(dir.join("checker.png"))
        .unwrap();
    luz::texture::noise_normal_map(32, 7, 0.6)
        .save(dir.join("normal.png"))
        .unwrap();
    luz::texture::checker(16, 2, [200, 120, 60, 255], [90, 220, 250, 255])
        .save(dir.join("orm.png"))
        .unwrap();
    std::fs::write(
        dir.join("quad.obj"),
        "mtllib quad.mtl\nv -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\n\
         vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 1 0\nusemtl tile\n\
         f 1/1/1 4/4/1 3/3/1 2/2/1\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("quad.mtl"),
        "newmtl tile\nKd 0.8 0.8 0.8\nKs 0.2 0.2 0.2\nNs 40\nmap_Kd checker.png\nmap_Bump normal.png\n",
    )
    .unwrap();
    let scene = r#"{
  "description": "every feature on (tests/soak.rs)",
  "camera": {"position": [0, 3, 9], "target": [0, 0.5, 0], "fov_y_deg": 50},
  "output": {"width": 64, "height": 36, "msaa": 4, "tonemap": "aces", "exposure": 0.5},
  "ambient": [0.05, 0.05, 0.05],
  "lights": [
    {"type": "directional", "direction": [-0.3, -1, -0.4], "intensity": 2, "color": [1, 0.95, 0.9], "shadow": {"resolution": 256, "cascades": 2}},
    {"type": "point", "position": [2, 3, 2], "intensity": 8, "falloff": "inverse_square"},
    {"type": "point", "position": [-3, 2, 1], "intensity": 2, "falloff": {"c1": 1, "c2": 0.1, "c3": 0.01}},
    {"type": "spot", "position": [0, 5, 3], "target": [0, 0, 0], "intensity": 20, "umbra_deg": 30, "inner_deg": 20, "exponent": 1}
  ],
  "materials": {
    "phong": {"model": "phong", "diffuse_color": [0.8, 0.2, 0.2], "shininess": 30,
              "textures": {"base_color": "checker.png", "specular": "checker.png", "normal": "normal.png"}},
    "blinn": {"model": "blinn_phong", "diffuse_color": [0.2, 0.8, 0.2], "shininess": 60},
    "lambert": {"model": "lambert", "albedo": [0.6, 0.6, 0.7], "textures": {"occlusion": "orm.png"}},
    "oren": {"model": "oren_nayar", "albedo": [0.7, 0.5, 0.3], "sigma_deg": 30},
    "ct": {"model": "cook_torrance", "color": [0.9, 0.6, 0.3], "roughness": 0.3,
           "textures": {"roughness": "orm.png"}},
    "gold": {"model": "metal_rough", "base_color": [1, 0.78, 0.34], "metallic": 1, "roughness": 0.4,
             "textures": {"base_color": "checker.png", "normal": "normal.png", "roughness": {"path": "orm.png", "channel": "g"},
                          "metallic": {"path": "orm.png", "channel": "b"}, "occlusion": "orm.png",
                          "emissive": "checker.png", "emissive_factor": [0.2, 0.2, 0.2]}},
    "packed": {"model": "metal_rough", "base_color": [0.5, 0.5, 0.9], "textures": {"orm": "orm.png"}},
    "disney": {"model": "principled", "base_color": [0.3, 0.5, 0.8], "roughness": 0.5, "anisotropic": 0.6,
               "clearcoat": 1, "clearcoat_gloss": 0.8, "sheen": 1, "sheen_tint": 0.5, "subsurface": 0.7,
               "specular_tint": 0.3, "metallic": 0.2, "specular": 0.5}
  },
  "objects": [
    {"mesh": {"type": "plane", "size": [12, 12], "subdivisions": 4}, "material": "lambert"},
    {"mesh": {"type": "sphere", "radius": 0.6}, "material": "gold", "position": [-2.5, 0.6, 0]},
    {"mesh": {"type": "icosphere", "radius": 0.6, "subdivisions": 2}, "material": "disney", "position": [-1, 0.6, 0]},
    {"mesh": {"type": "cube", "size": 1}, "material": "phong", "position": [0.5, 0.5, 0], "rotation_deg": [0, 30, 0]},
    {"mesh": {"type": "cone", "radius": 0.5, "height": 1}, "material": "blinn", "position": [2, 0.5, 0], "shading": "gouraud"},
    {"mesh": {"type": "cylinder", "radius": 0.4, "height": 1, "segments": 24}, "material": "oren", "position": [3.2, 0.5, 0], "shading": "flat"},
    {"mesh": {"type": "sphere", "radius": 0.5, "segments": 32, "rings": 16}, "material": "ct", "position": [0, 0.5, 2]},
    {"mesh": {"type": "sphere", "radius": 0.4}, "material": "packed", "position": [1.5, 0.4, 2]},
    {"mesh": {"type": "obj", "path": "quad.obj"}, "position": [-1.5, 0.01, 2], "scale": 0.8}
  ],
  "fog": {"z_a": 4, "z_b": 20, "s_a": 0.1, "s_b": 0.9, "color": [0.3, 0.35, 0.4]},
  "saturation": "normalize",
  "environment": {"procedural": "sky", "sun_direction": [-0.4, -0.75, -0.5], "sun_intensity": 3,
                  "specular_method": "split_sum", "diffuse_method": "sh9", "energy_compensation": true}
}"#;
    let path = dir.join("every_feature.json");
    std::fs::write(&path, scene).unwrap();
    path
}

/// `luz bench SCENE ARGS… --json`: asserts it succeeded with the validation layer silent, and
/// returns its JSON report.
fn bench_report(scene: &Path, json: &Path, args: &[&str]) -> serde_json::Value {
    let mut all = vec!["bench", scene.to_str().unwrap()];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--json", json.to_str().unwrap()]);
    let out = run(&mut luz_command(all));
    let (stdout, stderr) = (&out.stdout, &out.stderr);
    eprintln!("{stdout}");
    assert!(
        out.status.success(),
        "luz bench failed ({:?}):\n{stdout}\n{stderr}",
        out.status.code()
    );
    assert!(
        stderr.contains("validation: 0 errors, 0 warnings"),
        "validation must be silent: {stderr}"
    );
    serde_json::from_str(&std::fs::read_to_string(json).unwrap()).unwrap()
}

#[test]
fn ten_thousand_frames_keep_memory_flat() {
    let dir = scratch("soak");
    let scene = every_feature_scene(&dir);
    let json = dir.join("soak.json");
    let report = bench_report(
        &scene,
        &json,
        &[
            "--frames",
            "10000",
            "--warmup",
            "20",
            "--memory-every",
            "1000",
            "--max-memory-growth-mib",
            "4",
        ],
    );
    let memory = report["memory"].as_array().expect("memory series");
    assert_eq!(
        memory.len(),
        11,
        "a sample before the run and every 1 000 frames"
    );
    assert_eq!(memory.last().unwrap()["frame"], 10000);
    let allocations: Vec<u64> = memory[1..]
        .iter()
        .map(|m| m["gpu_allocations"].as_u64().unwrap())
        .collect();
    assert!(
        allocations.windows(2).all(|w| w[0] == w[1]),
        "GPU allocations change during the soak: {allocations:?}"
    );
    let rss: Vec<f64> = memory[1..]
        .iter()
        .map(|m| m["rss_mib"].as_f64().unwrap())
        .collect();
    let growth = rss.last().unwrap() - rss[0];
    assert!(growth < 4.0, "resident memory grows: {rss:?}");
    assert_eq!(report["frames"], 10000);
}

/// Shadows and vertex lighting, the two features that made lavapipe 22.3 compile and leak a
/// shader variant per bind (uniform inlining of the light loop's count; include/lighting.glsl's
/// `opaque()` in include/bindings.glsl): ~5 MB per shadowed frame and ~200 KB per Gouraud object per frame before the
/// fix. 150 frames of a small scene with both must keep resident memory flat (≤ 2 MiB from
/// frame 50 to 150, where the old growth was ~500 MiB).
#[test]
fn shadowed_and_vertex_lit_frames_keep_memory_flat() {
    let dir = scratch("soak_shadows");
    let scene = dir.join("shadowed_gouraud.json");
    std::fs::write(
        &scene,
        r#"{
  "description": "shadows and vertex lighting (tests/soak.rs)",
  "camera": {"position": [0, 2.5, 6], "target": [0, 0.5, 0], "fov_y_deg": 50},
  "output": {"width": 64, "height": 36, "msaa": 1},
  "lights": [
    {"type": "directional", "direction": [-0.4, -1, -0.5], "intensity": 2, "shadow": {"resolution": 256, "cascades": 2}},
    {"type": "point", "position": [1.5, 2.5, 1], "intensity": 6, "falloff": "inverse_square", "shadow": {"resolution": 128}}
  ],
  "materials": {
    "floor": {"model": "lambert", "albedo": [0.7, 0.7, 0.7]},
    "red": {"model": "blinn_phong", "diffuse_color": [0.8, 0.2, 0.2], "shininess": 40}
  },
  "objects": [
    {"mesh": {"type": "plane", "size": [10, 10], "subdivisions": 4}, "material": "floor"},
    {"mesh": {"type": "sphere", "radius": 0.6}, "material": "red", "position": [-1.2, 0.6, 0], "shading": "gouraud"},
    {"mesh": {"type": "sphere", "radius": 0.6}, "material": "red", "position": [0, 0.6, 0], "shading": "flat"},
    {"mesh": {"type": "sphere", "radius": 0.6}, "material": "red", "position": [1.2, 0.6, 0]}
  ]
}"#,
    )
    .unwrap();
    let json = dir.join("soak_shadows.json");
    let report = bench_report(
        &scene,
        &json,
        &["--frames", "150", "--warmup", "5", "--memory-every", "50"],
    );
    let memory = report["memory"].as_array().expect("memory series");
    assert_eq!(
        memory.len(),
        4,
        "a sample before the run and every 50 frames"
    );
    let rss: Vec<f64> = memory
        .iter()
        .map(|m| m["rss_mib"].as_f64().unwrap())
        .collect();
    let growth = rss[3] - rss[1];
    assert!(
        growth <= 2.0,
        "resident memory grows {growth:.1} MiB from frame 50 to 150: {rss:?}"
    );
}
