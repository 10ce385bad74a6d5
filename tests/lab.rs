//! `luz lab` end to end on a small scene: every output is written, the tessellation sweep's error
//! falls as segments grow (Phong shading against the CPU reference's exact sphere), the Pareto
//! front is marked, and validation stays silent.

mod common;

use common::{luz_command, root, run, scratch};

#[test]
fn lab_writes_results_chart_and_a_pareto_front() {
    let dir = scratch("sphere");
    let scene = dir.join("sphere.json");
    std::fs::write(
        &scene,
        r#"{
  "camera": { "position": [0, 0, 3.2], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 45 },
  "output": { "width": 96, "height": 64, "msaa": 1, "tonemap": "none", "background": [0, 0, 0] },
  "lights": [ { "type": "directional", "direction": [-0.4, -0.5, -1], "intensity": 2.5 } ],
  "materials": { "m": { "model": "metal_rough", "base_color": [0.9, 0.6, 0.3], "metallic": 0.3, "roughness": 0.4 } },
  "objects": [ { "mesh": { "type": "sphere", "radius": 1, "segments": 32, "rings": 16 }, "material": "m" } ]
}"#,
    )
    .unwrap();
    let out = dir.join("out");
    let ran = run(&mut luz_command([
        "lab",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--frames",
        "2",
        "--only",
        "tessellation",
    ]));
    let (stdout, stderr) = (&ran.stdout, &ran.stderr);
    assert!(ran.status.success(), "{stdout}\n{stderr}");
    assert!(stderr.contains("validation: 0 errors"), "{stderr}");
    for f in [
        "results.csv",
        "results.json",
        "chart.png",
        "chart.svg",
        "reference.exr",
    ] {
        assert!(out.join(f).exists(), "{f} missing");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    let results = json["results"].as_array().unwrap();
    // As written + 3 shading frequencies × 6 segment counts.
    // … and the all-features pipelines.
    assert_eq!(results.len(), 1 + 3 * 6 + 1);
    assert!(results.iter().any(|r| r["pareto"] == true));
    let flip = |label: &str| {
        results
            .iter()
            .find(|r| r["label"] == label)
            .unwrap_or_else(|| panic!("{label} missing"))["error"]["flip_mean"]
            .as_f64()
            .unwrap()
    };
    let rmse = |label: &str| {
        results.iter().find(|r| r["label"] == label).unwrap()["error"]["rmse"]
            .as_f64()
            .unwrap()
    };
    eprintln!(
        "phong 8: FLIP {:.4}, RMSE {:.4}; phong 256: FLIP {:.4}, RMSE {:.4}; flat 32: FLIP {:.4}",
        flip("phong 8"),
        rmse("phong 8"),
        flip("phong 256"),
        rmse("phong 256"),
        flip("flat 32")
    );
    assert!(
        flip("phong 256") < flip("phong 8") * 0.5,
        "more segments, less error"
    );
    // The all-features pipelines draw the same image as the specialised ones.
    let all = flip("as written, all-features pipelines");
    assert!((all - flip("as written")).abs() < 1e-3, "{all}");
    assert!(stdout.contains("all-features pipelines"), "{stdout}");
    assert!(
        flip("phong 64") < flip("flat 64"),
        "Phong shading beats flat at equal tessellation"
    );
    assert!(
        flip("phong 256") < 0.02,
        "a finely tessellated Phong sphere matches the exact one"
    );
    for r in results {
        assert_eq!(r["error"]["nan_pixels"], 0, "{r}");
        assert!(r["gpu_ms"].as_f64().unwrap() > 0.0);
    }
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + results.len());
}

#[test]
fn lab_rejects_a_reference_of_the_wrong_size() {
    let dir = scratch("bad-reference");
    let small = dir.join("small.exr");
    luz::imageio::save(
        &small,
        &luz::imageio::LinearImage::filled(4, 4, [0.0; 4]),
        0.0,
        luz::color::Tonemap::None,
    )
    .unwrap();
    let ran = run(&mut luz_command([
        "lab",
        root().join("assets/scenes/default.json").to_str().unwrap(),
        "--out",
        dir.join("out").to_str().unwrap(),
        "--reference",
        small.to_str().unwrap(),
    ]));
    let stderr = &ran.stderr;
    assert!(!ran.status.success());
    assert!(
        stderr.contains("small.exr") && stderr.contains("4x4"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
}

/// The `area` group (issue 36) reduced: a rect and a sphere, large, overhead, roughness 0.25, every
/// method, against the CPU reference. Every row is finite with a positive time; the sampled
/// method's error falls from 4 to 64 samples; LTC beats 4 samples on the rect and the
/// representative point on the sphere; and validation stays silent. Figures printed
/// (`-- --nocapture`); the full sweep is `luz lab docs/lab/area.json --only area`.
#[test]
fn lab_area_group_reduced() {
    use luz::lab::area::{self, AreaSweep};
    let ctx = common::gpu();
    let base = luz::scene::load(&root().join("docs/lab/area.json")).unwrap();
    let sweep = AreaSweep {
        shapes: vec!["rect", "sphere"],
        roughness: vec![0.25],
        solid_angles: vec![area::SOLID_ANGLES[1]],
        elevations: vec![area::ELEVATIONS[0]],
        samples: vec![4, 64],
        timing_size: (96, 64),
        frames: 3,
        reference_samples: 1024,
    };
    let rows = area::measure(
        &ctx,
        &base,
        &sweep,
        &luz::headless::RenderOptions::default(),
        None,
    )
    .unwrap();
    common::assert_no_validation_messages(&ctx);
    // rect: ltc, sampled 4, sampled 64; sphere: ltc, representative point, sampled 4, 64.
    assert_eq!(rows.len(), 3 + 4);
    let err = |shape: &str, label: &str| {
        rows.iter()
            .find(|r| r.cell.shape == shape && r.label() == label)
            .unwrap_or_else(|| panic!("{shape} {label} missing"))
            .relative_l1
    };
    for r in &rows {
        eprintln!(
            "{} {}: relative L1 {:.4}, FLIP {:.4}, forward {:.3} ms ({:.2}× point)",
            r.cell.shape,
            r.label(),
            r.relative_l1,
            r.error.flip_mean,
            r.forward_ms,
            r.cost()
        );
        assert!(
            r.relative_l1.is_finite() && r.error.rmse.is_finite(),
            "{r:?}"
        );
        assert_eq!(r.error.nan_pixels, 0, "{r:?}");
        assert!(r.forward_ms > 0.0 && r.base_forward_ms > 0.0, "{r:?}");
    }
    for shape in ["rect", "sphere"] {
        assert!(
            err(shape, "sampled 64") < 0.5 * err(shape, "sampled 4"),
            "{shape}: sampled error falls with samples"
        );
    }
    assert!(err("rect", "ltc") < err("rect", "sampled 4"));
    assert!(err("sphere", "ltc") < err("sphere", "representative_point"));
    // Sampled's cost grows with its samples (at 64 × 96 px the frame is small, so only the order
    // is asserted).
    let cost = |label: &str| {
        rows.iter()
            .find(|r| r.cell.shape == "rect" && r.label() == label)
            .unwrap()
            .forward_ms
    };
    assert!(cost("sampled 64") > cost("sampled 4"));
}

/// `--only area` runs alone (its cells have their own references) and takes no `--reference`.
#[test]
fn lab_area_group_runs_alone() {
    let dir = scratch("area-alone");
    let ran = run(&mut luz_command([
        "lab",
        root().join("docs/lab/area.json").to_str().unwrap(),
        "--out",
        dir.join("out").to_str().unwrap(),
        "--only",
        "area,brdf",
    ]));
    assert!(!ran.status.success());
    assert!(ran.stderr.contains("runs alone"), "{}", ran.stderr);
    assert!(!ran.stderr.contains("panicked"), "{}", ran.stderr);
}
