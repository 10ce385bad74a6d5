//! Chrome/Perfetto traces ("Trace Event Format"): a JSON object whose `traceEvents` are complete
//! events (`"ph":"X"`, `ts`/`dur` in microseconds) on two tracks, "CPU" and "GPU", named by
//! metadata events (`"ph":"M"`). Open the file in `ui.perfetto.dev` or `chrome://tracing`.
//!
//! [`check_trace`] parses such a file back and checks its structure, for tests.

use std::collections::BTreeMap;

use serde_json::{json, Value};

const PID: u64 = 1;
const CPU_TID: u64 = 1;
const GPU_TID: u64 = 2;
/// Slack of the nesting checks, in microseconds (float sums).
const NEST_EPS: f64 = 1e-3;

/// A CPU span of a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CpuSpan<'n> {
    /// Its name.
    pub name: &'n str,
    /// Start, microseconds.
    pub start_us: f64,
    /// Duration, microseconds.
    pub dur_us: f64,
}

/// A trace being built.
#[derive(Clone, Debug)]
pub struct Trace {
    events: Vec<Value>,
    /// Where the last frame's GPU span ends (µs).
    gpu_end_us: f64,
}

impl Default for Trace {
    fn default() -> Self {
        Self::new()
    }
}

impl Trace {
    /// An empty trace with the process and its "CPU" and "GPU" tracks named.
    pub fn new() -> Self {
        let meta = |name: &str, tid: u64, args: Value| json!({"ph": "M", "name": name, "pid": PID, "tid": tid, "args": args});
        Self {
            events: vec![
                meta("process_name", CPU_TID, json!({"name": "luz"})),
                meta("thread_name", CPU_TID, json!({"name": "CPU"})),
                meta("thread_name", GPU_TID, json!({"name": "GPU"})),
                meta("thread_sort_index", CPU_TID, json!({"sort_index": 0})),
                meta("thread_sort_index", GPU_TID, json!({"sort_index": 1})),
            ],
            gpu_end_us: 0.0,
        }
    }

    fn span(&mut self, tid: u64, cat: &str, name: &str, ts: f64, dur: f64, args: Option<Value>) {
        let mut e = json!({
            "ph": "X", "name": name, "cat": cat, "pid": PID, "tid": tid, "ts": ts, "dur": dur,
        });
        if let Some(a) = args {
            e["args"] = a;
        }
        self.events.push(e);
    }

    /// A span on the CPU track.
    pub fn cpu_span(&mut self, name: &str, start_us: f64, dur_us: f64) {
        self.span(CPU_TID, "cpu", name, start_us, dur_us, None);
    }

    /// Frame `index`: a CPU "frame N" span around `cpu` (when given) and a GPU "frame N" span at
    /// `gpu_start_us` holding the passes `gpu` (name, milliseconds) end to end; its duration is
    /// their sum.
    pub fn frame(
        &mut self,
        index: u64,
        cpu: &[CpuSpan<'_>],
        gpu: &[(&str, f64)],
        gpu_start_us: f64,
    ) {
        let name = format!("frame {index}");
        let args = Some(json!({ "frame": index }));
        if !cpu.is_empty() {
            let start = cpu.iter().map(|s| s.start_us).fold(f64::INFINITY, f64::min);
            let end = cpu
                .iter()
                .map(|s| s.start_us + s.dur_us)
                .fold(f64::NEG_INFINITY, f64::max);
            self.span(CPU_TID, "frame", &name, start, end - start, args.clone());
            for s in cpu {
                self.cpu_span(s.name, s.start_us, s.dur_us);
            }
        }
        let total: f64 = gpu.iter().map(|&(_, ms)| ms * 1000.0).sum();
        self.span(GPU_TID, "frame", &name, gpu_start_us, total, args);
        self.gpu_end_us = gpu_start_us + total;
        let mut t = gpu_start_us;
        for &(pass, ms) in gpu {
            let dur = ms * 1000.0;
            self.span(
                GPU_TID,
                "gpu",
                pass,
                t,
                dur,
                Some(json!({ "frame": index })),
            );
            t += dur;
        }
    }

    /// Frame `index` of a run timed frame after frame: on the CPU track from `start_us`, a span
    /// `first` of `first_us` and a span `rest` for what remains of `total_us` (none when `first`
    /// takes it all); on the GPU track the passes `gpu` from the end of `first` (the submission),
    /// or from the end of the previous frame's GPU span if that is later. Frames in flight may
    /// start on the GPU after the next recording, and GPU timestamps and the host clock differ a
    /// little, so the GPU frames are laid one after another.
    pub fn sequential_frame(
        &mut self,
        index: u64,
        start_us: f64,
        (first, first_us): (&str, f64),
        (rest, total_us): (&str, f64),
        gpu: &[(&str, f64)],
    ) {
        let cpu = [
            CpuSpan {
                name: first,
                start_us,
                dur_us: first_us,
            },
            CpuSpan {
                name: rest,
                start_us: start_us + first_us,
                dur_us: (total_us - first_us).max(0.0),
            },
        ];
        let gpu_start = (start_us + first_us).max(self.gpu_end_us);
        self.frame(index, &cpu, gpu, gpu_start);
    }

    /// The number of events (metadata included).
    pub fn len(&self) -> usize {
        self.events.len()
    }

    /// Whether only the metadata events are present.
    pub fn is_empty(&self) -> bool {
        self.events.iter().all(|e| e["ph"] == "M")
    }

    /// The trace as JSON.
    pub fn to_json(&self) -> String {
        json!({ "traceEvents": self.events, "displayTimeUnit": "ms" }).to_string()
    }
}

/// What [`check_trace`] found.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct TraceSummary {
    /// Complete events on the "CPU" track (frame spans included).
    pub cpu_spans: usize,
    /// Complete events on the "GPU" track (frame spans included).
    pub gpu_spans: usize,
    /// GPU frame spans (category "frame").
    pub gpu_frames: usize,
    /// CPU frame spans (category "frame").
    pub cpu_frames: usize,
    /// GPU pass spans inside frames.
    pub gpu_passes: usize,
}

#[derive(Debug)]
struct Span {
    name: String,
    cat: String,
    ts: f64,
    dur: f64,
}

/// Field `key` of event `i` read with `get` (e.g. [`Value::as_str`]); an error naming the event
/// and the field when it is missing or of another type.
fn field<'v, T>(
    e: &'v Value,
    i: usize,
    key: &str,
    get: impl FnOnce(&'v Value) -> Option<T>,
) -> Result<T, String> {
    e.get(key)
        .and_then(get)
        .ok_or_else(|| format!("event {i}: no {key}"))
}

/// Parses a trace and checks it: every complete event has a name, a timestamp and a
/// non-negative duration; on each track spans nest (children within parents, siblings not
/// overlapping); every GPU frame span lasts the sum of its pass spans (within 1 µs).
pub fn check_trace(json: &str) -> Result<TraceSummary, String> {
    let v: Value = serde_json::from_str(json).map_err(|e| format!("not JSON: {e}"))?;
    let events = v
        .get("traceEvents")
        .and_then(Value::as_array)
        .ok_or("no traceEvents array")?;
    let mut names: BTreeMap<(u64, u64), String> = BTreeMap::new();
    let mut tracks: BTreeMap<(u64, u64), Vec<Span>> = BTreeMap::new();
    for (i, e) in events.iter().enumerate() {
        let ph = field(e, i, "ph", Value::as_str)?;
        let pid = field(e, i, "pid", Value::as_u64)?;
        let tid = field(e, i, "tid", Value::as_u64)?;
        let name = field(e, i, "name", Value::as_str)?;
        match ph {
            "M" => {
                if name == "thread_name" {
                    let n = e["args"]["name"]
                        .as_str()
                        .ok_or(format!("event {i}: thread_name without args.name"))?;
                    names.insert((pid, tid), n.to_string());
                }
            }
            "X" => {
                let ts = field(e, i, "ts", Value::as_f64)?;
                let dur = field(e, i, "dur", Value::as_f64)?;
                if !(ts.is_finite() && dur.is_finite() && dur >= 0.0) {
                    return Err(format!("event {i} (\"{name}\"): bad ts {ts} / dur {dur}"));
                }
                let cat = e
                    .get("cat")
                    .and_then(Value::as_str)
                    .unwrap_or("")
                    .to_string();
                tracks.entry((pid, tid)).or_default().push(Span {
                    name: name.to_string(),
                    cat,
                    ts,
                    dur,
                });
            }
            other => return Err(format!("event {i}: unexpected ph \"{other}\"")),
        }
    }

    let mut summary = TraceSummary::default();
    for (key, mut spans) in tracks {
        let track = names
            .get(&key)
            .cloned()
            .ok_or(format!("track {key:?} has no thread_name"))?;
        spans.sort_by(|a, b| a.ts.total_cmp(&b.ts).then(b.dur.total_cmp(&a.dur)));
        // Parent of each span (index into `spans`), by a stack of open spans.
        let mut stack: Vec<usize> = Vec::new();
        let mut child_sum = vec![0.0f64; spans.len()];
        let mut children = vec![0usize; spans.len()];
        for i in 0..spans.len() {
            let s = &spans[i];
            while let Some(&top) = stack.last() {
                if spans[top].ts + spans[top].dur <= s.ts + NEST_EPS {
                    stack.pop();
                } else {
                    break;
                }
            }
            if let Some(&top) = stack.last() {
                let p = &spans[top];
                if s.ts + s.dur > p.ts + p.dur + NEST_EPS {
                    return Err(format!(
                        "{track} track: \"{}\" [{}, {}] overlaps \"{}\" [{}, {}] without nesting",
                        s.name,
                        s.ts,
                        s.ts + s.dur,
                        p.name,
                        p.ts,
                        p.ts + p.dur
                    ));
                }
                child_sum[top] += s.dur;
                children[top] += 1;
            }
            stack.push(i);
        }
        for (i, s) in spans.iter().enumerate() {
            let frame = s.cat == "frame";
            match track.as_str() {
                "GPU" => {
                    summary.gpu_spans += 1;
                    if frame {
                        summary.gpu_frames += 1;
                        summary.gpu_passes += children[i];
                        if (child_sum[i] - s.dur).abs() > 1.0 {
                            return Err(format!(
                                "GPU track: \"{}\" lasts {} µs but its passes sum to {} µs",
                                s.name, s.dur, child_sum[i]
                            ));
                        }
                    }
                }
                "CPU" => {
                    summary.cpu_spans += 1;
                    if frame {
                        summary.cpu_frames += 1;
                    }
                }
                _ => {}
            }
        }
    }
    Ok(summary)
}
