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
