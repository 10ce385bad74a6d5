//! The frame graph as users see it: `luz render --graph` draws the frame that was rendered, and
//! `luz bench --trace` writes a Chrome/Perfetto trace whose spans nest and add up. (The graph's
//! own rules — barriers, culling, refused accesses, pooling — are tested without a GPU in
//! crates/luz-graph/tests.)

mod common;

use common::{luz, luz_in_window, scratch};

/// The default scene's frame, as DOT and as SVG: every pass `luz render` timed (each with its
/// GPU ms) and the resources they use.
#[test]
fn render_writes_the_frame_graph_as_dot_and_svg() {
    let dir = scratch("frame-graph");
    let dot = dir.join("frame.dot");
    let svg = dir.join("frame.svg");
    let png = dir.join("frame.png");
    // One frame: the graph drawn is the last frame's, and a second frame reuses the shadow maps
    // (no "shadows" pass) while the timing rows are medians over both.
    let (code, out, err) = luz(&[
        "render",
        "--frames",
        "1",
        "-o",
        png.to_str().unwrap(),
        "--graph",
        dot.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}\n{err}");
    assert!(out.contains("the frame graph"), "{out}");
    let text = std::fs::read_to_string(&dot).unwrap();
    assert!(text.trim_start().starts_with("digraph"), "{text}");
    // The passes luz render printed timings for are the graph's passes.
    let rows: Vec<&str> = ["shadows", "forward", "gbuffer", "lighting", "readback"]
        .into_iter()
        .filter(|p| out.lines().any(|l| l.starts_with(&format!("GPU {p} "))))
        .collect();
    assert!(rows.contains(&"readback"), "{out}");
    assert!(rows.len() >= 2, "{out}");
    for p in &rows {
        assert!(text.contains(p), "{p} missing from the graph:\n{text}");
    }
    assert!(text.contains("ms"), "passes carry their GPU time:\n{text}");
    for resource in ["hdr color", "depth", "readback"] {
        assert!(text.contains(resource), "{resource} missing:\n{text}");
    }
    // The frame's images are the graph's transients (issue 32): the HDR colour and depth live
    // for one frame; only the readback buffer is imported.
    for image in ["headless hdr color", "headless depth"] {
        let node = text
            .lines()
            .find(|l| l.contains(image) && l.contains("shape=ellipse"))
            .unwrap_or_else(|| panic!("no node for {image}:\n{text}"));
        assert!(
            node.contains("transient"),
            "{image} is not transient: {node}"
        );
    }
    assert!(
        text.contains("TransferSrc"),
        "edges name their access:\n{text}"
    );

    let (code, out, err) = luz(&[
        "render",
        "-o",
        png.to_str().unwrap(),
        "--graph",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}\n{err}");
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(
        text.contains("<svg") && text.trim_end().ends_with("</svg>"),
        "{text}"
    );
    for p in &rows {
        assert!(text.contains(p), "{p} missing from the SVG");
    }
    // Balanced elements: as many closing tags as opening ones that are not self-closed.
    let opens = text.matches('<').count() - text.matches("</").count() - text.matches("<?").count();
    let self_closed = text.matches("/>").count();
    assert_eq!(
        opens - self_closed,
        text.matches("</").count(),
        "unbalanced SVG"
    );
}

/// `luz bench --trace`: one CPU frame and one GPU frame per timed frame; on each track the spans
/// nest and siblings do not overlap; each GPU frame lasts exactly the sum of its passes, and the
/// passes are the ones `luz bench` reports.
#[test]
fn bench_trace_spans_nest_and_add_up() {
    let dir = scratch("frame-trace");
    let trace = dir.join("trace.json");
    let (code, out, err) = luz(&[
        "bench",
        "--frames",
        "4",
        "--warmup",
        "1",
        "--trace",
        trace.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}\n{err}");
    let text = std::fs::read_to_string(&trace).unwrap();
    let summary = luz::graph::check_trace(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    assert_eq!(summary.gpu_frames, 4, "{summary:?}");
    assert_eq!(summary.cpu_frames, 4, "{summary:?}");
    assert_eq!(
        summary.cpu_spans, 12,
        "the frame, its recording and its submit + wait: {summary:?}"
    );
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let events = v["traceEvents"].as_array().unwrap();
    let passes: std::collections::BTreeSet<&str> = events
        .iter()
        .filter(|e| e["cat"] == "gpu")
        .map(|e| e["name"].as_str().unwrap())
        .collect();
    assert!(passes.contains("readback"), "{passes:?}");
    for p in &passes {
        assert!(
            out.lines().any(|l| l.starts_with(&format!("GPU {p} "))),
            "{p} is not one of bench's rows:\n{out}"
        );
    }
    // The GPU frames' durations are the frames' GPU totals, which bench's median summarises.
    let gpu_frames: Vec<f64> = events
        .iter()
        .filter(|e| e["cat"] == "frame" && e["tid"] == 2)
        .map(|e| e["dur"].as_f64().unwrap())
        .collect();
    assert_eq!(gpu_frames.len(), 4);
    assert!(gpu_frames.iter().all(|d| *d > 0.0), "{gpu_frames:?}");
}

/// A trace file that cannot be written is a clear error before any frame is rendered.
#[test]
fn unwritable_trace_is_a_clear_error() {
    let (code, _, err) = luz(&[
        "bench",
        "--frames",
        "1",
        "--trace",
        "/nonexistent-dir/trace.json",
    ]);
    assert_ne!(code, 0);
    assert!(
        err.contains("/nonexistent-dir/trace.json") && !err.contains("panicked"),
        "{err}"
    );
}

/// The viewer's profiler writes the same trace (`luz view --bench --trace`), with its passes
/// ("display", "ui" or the scene's straight into the window) from the same graph.
#[test]
fn viewer_trace_spans_nest_and_add_up() {
    let dir = scratch("frame-trace-view");
    let trace = dir.join("view.json");
    let Some((code, out, err)) = luz_in_window(&[
        "view",
        "--bench",
        "--frames",
        "6",
        "--warmup",
        "2",
        "--trace",
        trace.to_str().unwrap(),
    ]) else {
        return;
    };
    assert_eq!(code, 0, "{out}\n{err}");
    let text = std::fs::read_to_string(&trace).unwrap();
    let summary = luz::graph::check_trace(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
    // The measured frames whose timestamps were read (the last ones in flight are not).
    assert!(summary.gpu_frames >= 2, "{summary:?}");
    assert_eq!(summary.cpu_frames, summary.gpu_frames, "{summary:?}");
    assert!(summary.gpu_passes >= 2 * summary.gpu_frames, "{summary:?}");
}
