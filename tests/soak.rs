//! Soak: 10 000 frames through `luz bench` with validation on; resident memory and the GPU
//! allocator's live allocations, sampled every 1 000 frames, must stay flat.

use std::process::Command;

#[test]
fn ten_thousand_frames_keep_memory_flat() {
    let dir = std::env::temp_dir().join(format!("luz-soak-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let json = dir.join("soak.json");
    let out = Command::new(env!("CARGO_BIN_EXE_luz"))
        .args([
            "bench",
            "--frames",
            "10000",
            "--warmup",
            "20",
            "--width",
            "64",
            "--height",
            "36",
            "--memory-every",
            "1000",
            "--max-memory-growth-mib",
            "4",
            "--json",
            json.to_str().unwrap(),
        ])
        .env("LUZ_VALIDATION", "1")
        .output()
        .expect("run luz bench");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    eprintln!("{stdout}");
    assert!(
        out.status.success(),
        "luz bench soak failed ({:?}):\n{stdout}\n{stderr}",
        out.status.code()
    );
    assert!(
        stderr.contains("validation: 0 errors, 0 warnings"),
        "validation must be silent: {stderr}"
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
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
