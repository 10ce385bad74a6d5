//! The Perfetto trace writer and checker.

use luz_graph::trace::*;
use serde_json::Value;

fn three_frames() -> Trace {
    let mut t = Trace::new();
    for f in 0..3u64 {
        let base = f as f64 * 16_000.0;
        t.frame(
            f,
            &[
                CpuSpan {
                    name: "record",
                    start_us: base,
                    dur_us: 800.0,
                },
                CpuSpan {
                    name: "submit",
                    start_us: base + 800.0,
                    dur_us: 100.0,
                },
            ],
            &[
                ("shadow", 0.3),
                ("forward", 1.7),
                ("saturate", 0.1),
                ("display", 0.25),
            ],
            base + 1000.0,
        );
    }
    t.cpu_span("load scene", 60_000.0, 5_000.0);
    t
}

#[test]
fn trace_round_trips() {
    let json = three_frames().to_json();
    let v: Value = serde_json::from_str(&json).unwrap();
    let events = v["traceEvents"].as_array().unwrap();
    assert!(events
        .iter()
        .any(|e| e["ph"] == "M" && e["args"]["name"] == "GPU"));
    let frame = events
        .iter()
        .find(|e| e["tid"] == 2 && e["name"] == "frame 1")
        .unwrap();
    assert!((frame["dur"].as_f64().unwrap() - 2350.0).abs() < 1e-6);
    assert_eq!(frame["ts"].as_f64().unwrap(), 17_000.0);
    let s = check_trace(&json).unwrap();
    assert_eq!(
        s,
        TraceSummary {
            cpu_spans: 3 * 3 + 1,
            gpu_spans: 3 * 5,
            gpu_frames: 3,
            cpu_frames: 3,
            gpu_passes: 12,
        }
    );
}

/// Rewrites the event matching `pred` with `f`.
fn edit(json: &str, pred: impl Fn(&Value) -> bool, f: impl Fn(&mut Value)) -> String {
    let mut v: Value = serde_json::from_str(json).unwrap();
    let e = v["traceEvents"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .find(|e| pred(e))
        .unwrap();
    f(e);
    v.to_string()
}

#[test]
fn broken_traces_are_rejected() {
    let json = three_frames().to_json();

    // Overlapping siblings: "forward" of frame 0 starts inside "shadow" but ends after it.
    let broken = edit(
        &json,
        |e| e["name"] == "forward" && e["args"]["frame"] == 0,
        |e| e["ts"] = Value::from(e["ts"].as_f64().unwrap() - 100.0),
    );
    let err = check_trace(&broken).unwrap_err();
    assert!(err.contains("overlaps"), "{err}");

    // A GPU frame whose duration is not the sum of its passes.
    let broken = edit(
        &json,
        |e| e["name"] == "frame 2" && e["tid"] == 2,
        |e| e["dur"] = Value::from(e["dur"].as_f64().unwrap() + 50.0),
    );
    let err = check_trace(&broken).unwrap_err();
    assert!(err.contains("sum"), "{err}");

    // A CPU span poking out of its frame.
    let mut t = three_frames();
    t.cpu_span("straddles", 16_500.0, 1_000.0);
    assert!(check_trace(&t.to_json()).is_err());

    // Not a trace at all.
    assert!(check_trace("{}").is_err());
    assert!(check_trace("[1, 2").is_err());
    let broken = edit(&json, |e| e["ph"] == "X", |e| e["dur"] = Value::from(-1.0));
    assert!(check_trace(&broken).is_err());
}

/// `sequential_frame`: two CPU spans per frame, and GPU frames laid end to end when a frame's
/// GPU work would start before the previous one's ended.
#[test]
fn sequential_frames_queue_on_the_gpu() {
    let mut t = Trace::new();
    // Frame 0: recording 1000 µs of 3000; 5 ms of GPU work from 1000 to 6000.
    t.sequential_frame(
        0,
        0.0,
        ("record", 1000.0),
        ("rest", 3000.0),
        &[("a", 2.0), ("b", 3.0)],
    );
    // Frame 1: submitted at 3500, but the GPU is busy until 6000.
    t.sequential_frame(
        1,
        3000.0,
        ("record", 500.0),
        ("rest", 3000.0),
        &[("a", 1.0)],
    );
    // Frame 2: submitted at 10200, after the GPU went idle at 7000; the recording takes longer
    // than the whole frame was measured, so its second span is empty.
    t.sequential_frame(
        2,
        10_000.0,
        ("record", 200.0),
        ("rest", 150.0),
        &[("a", 1.0)],
    );
    let json = t.to_json();
    let v: Value = serde_json::from_str(&json).unwrap();
    let events = v["traceEvents"].as_array().unwrap();
    let span = |tid: u64, name: &str, nth: usize| {
        let e = events
            .iter()
            .filter(|e| e["tid"] == tid && e["name"] == name)
            .nth(nth)
            .unwrap();
        (e["ts"].as_f64().unwrap(), e["dur"].as_f64().unwrap())
    };
    assert_eq!(span(2, "frame 0", 0), (1000.0, 5000.0));
    assert_eq!(span(2, "frame 1", 0), (6000.0, 1000.0));
    assert_eq!(span(2, "frame 2", 0), (10_200.0, 1000.0));
    assert_eq!(span(1, "record", 1), (3000.0, 500.0));
    assert_eq!(span(1, "rest", 1), (3500.0, 2500.0));
    assert_eq!(span(1, "rest", 2), (10_200.0, 0.0));
    let s = check_trace(&json).unwrap();
    assert_eq!((s.gpu_frames, s.cpu_frames, s.gpu_passes), (3, 3, 4));
}
