//! Frame-time profiler: a rolling window of the last frames with order statistics, per-pass GPU
//! medians and a stutter count. Used by the viewer (its profiler panel) and by `luz bench`.
//!
//! Plain Rust, no window or GPU code: the caller measures, this module keeps the numbers.
//!
//! **Stutter rule.** A frame is a stutter when its `frame_ms` exceeds [`STUTTER_FACTOR`] times the
//! median `frame_ms` of the window *before* it, judged only once that window holds at least
//! [`STUTTER_MIN_FRAMES`] frames. [`Profiler::push`] and [`stutter_count`] apply the same rule
//! (the same function), so a profiler of capacity [`DEFAULT_CAPACITY`] fed a series counts what
//! `stutter_count` counts on it.

use std::collections::VecDeque;

use crate::stats::quantile;

/// A frame is a stutter when it takes more than this many times the window's median.
pub const STUTTER_FACTOR: f64 = 2.0;
/// Frames the window must hold before a stutter can be judged.
pub const STUTTER_MIN_FRAMES: usize = 8;
/// The window of [`stutter_count`], and a sensible capacity for a [`Profiler`] (5 s at 60 Hz).
pub const DEFAULT_CAPACITY: usize = 300;

/// The timings of one frame.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FrameSample {
    /// Wall-clock time from this frame's start to the next one's (what the user sees), ms.
    pub frame_ms: f64,
    /// CPU time spent recording and submitting the frame, ms.
    pub cpu_ms: f64,
    /// GPU time per pass (timestamp queries), ms, in pass order; empty when unknown.
    pub gpu_ms: Vec<(&'static str, f64)>,
}

/// Statistics over a [`Profiler`]'s window (`frames` and `stutters` are running totals).
/// Quantiles follow [`crate::stats::quantile`]; every field is NaN when the window is empty
/// (serialised as `null` by serde_json).
#[derive(serde::Serialize, Clone, Debug)]
pub struct ProfilerStats {
    /// Frames pushed since the profiler was made (not only those in the window).
    pub frames: u64,
    /// Frames in the window the statistics below are taken over.
    pub window: u64,
    /// 1000 / mean `frame_ms` over the window.
    pub fps: f64,
    /// Median `frame_ms`.
    pub p50: f64,
    pub p95: f64,
    pub p99: f64,
    pub max: f64,
    /// Stutters since the profiler was made (see the module documentation).
    pub stutters: u64,
    /// Median `cpu_ms`.
    pub cpu_p50: f64,
    /// Median over the window's frames of the sum of their GPU passes; NaN when no frame has GPU
    /// times.
    pub gpu_p50: f64,
}

/// Whether `frame_ms` is a stutter after the frames `window` (oldest first, not including it).
fn is_stutter(window: &[f64], frame_ms: f64) -> bool {
    if window.len() < STUTTER_MIN_FRAMES {
        return false;
    }
    // NaN median (a window of NaNs) or NaN frame: the comparison is false, no stutter.
    frame_ms > STUTTER_FACTOR * quantile(window, 0.5)
}

/// Stutters in a whole series of frame times (oldest first), judging each frame against the
/// [`DEFAULT_CAPACITY`] frames before it, exactly as a [`Profiler`] of that capacity does.
pub fn stutter_count(frame_ms: &[f64]) -> u64 {
    stutter_count_with_window(frame_ms, DEFAULT_CAPACITY)
}

/// [`stutter_count`] with a window of `capacity` frames (at least 1), as a
/// [`Profiler::new`]`(capacity)`.
pub fn stutter_count_with_window(frame_ms: &[f64], capacity: usize) -> u64 {
    let capacity = capacity.max(1);
    let mut count = 0;
    for (i, &x) in frame_ms.iter().enumerate() {
        let window = &frame_ms[i.saturating_sub(capacity)..i];
        count += u64::from(is_stutter(window, x));
    }
    count
}

/// A rolling window of the last `capacity` frames plus running totals.
#[derive(Debug, Clone)]
pub struct Profiler {
    /// What the last frame drew: triangles, and the LOD levels in use (the viewer's panel).
    geometry: Option<(u64, String)>,
    /// The mesh LOD budget in use and why (the viewer's frame-time target).
    lod_budget: Option<String>,
    capacity: usize,
    samples: VecDeque<FrameSample>,
    total_frames: u64,
    stutters: u64,
    /// Reused buffer for the window's frame times (the stutter test needs a slice).
    scratch: Vec<f64>,
}

impl Default for Profiler {
    fn default() -> Self {
        Self::new(DEFAULT_CAPACITY)
    }
}

impl Profiler {
    /// An empty profiler keeping the last `capacity` frames (at least 1).
    pub fn new(capacity: usize) -> Self {
        let capacity = capacity.max(1);
        Profiler {
            geometry: None,
            lod_budget: None,
            capacity,
            samples: VecDeque::with_capacity(capacity),
            total_frames: 0,
            stutters: 0,
            scratch: Vec::with_capacity(capacity),
        }
    }

    /// Adds a frame, counting it as a stutter when it takes more than [`STUTTER_FACTOR`] × the
    /// median of the window before it (once that holds [`STUTTER_MIN_FRAMES`] frames), then drops
    /// the oldest frame when the window is full.
    pub fn push(&mut self, s: FrameSample) {
        self.scratch.clear();
        self.scratch.extend(self.samples.iter().map(|f| f.frame_ms));
        if is_stutter(&self.scratch, s.frame_ms) {
            self.stutters += 1;
        }
        self.total_frames += 1;
        if self.samples.len() == self.capacity {
            self.samples.pop_front();
        }
        self.samples.push_back(s);
    }

    /// Statistics over the window.
    /// Records what the frame being drawn holds: `triangles` drawn and the LOD `levels` in use
    /// ([`crate::scene::lod::levels_in_use`]).
    pub fn set_geometry(&mut self, triangles: u64, levels: String) {
        self.geometry = Some((triangles, levels));
    }

    /// Records the mesh LOD budget the frame being drawn uses, described
    /// (`crate::window::lod_target::LodTarget::describe`); `None` when no mesh has simplified
    /// levels (the budget changes nothing drawn).
    pub fn set_lod_budget(&mut self, text: Option<String>) {
        self.lod_budget = text;
    }

    /// The last [`Profiler::set_lod_budget`].
    pub fn lod_budget(&self) -> Option<&str> {
        self.lod_budget.as_deref()
    }

    /// The last [`Profiler::set_geometry`].
    pub fn geometry(&self) -> Option<&(u64, String)> {
        self.geometry.as_ref()
    }

    pub fn stats(&self) -> ProfilerStats {
        let frame: Vec<f64> = self.frame_history().collect();
        let cpu: Vec<f64> = self.samples.iter().map(|s| s.cpu_ms).collect();
        let gpu: Vec<f64> = self
            .samples
            .iter()
            .filter(|s| !s.gpu_ms.is_empty())
            .map(|s| s.gpu_ms.iter().map(|(_, ms)| ms).sum())
            .collect();
        let finite: Vec<f64> = frame.iter().copied().filter(|x| x.is_finite()).collect();
        let mean = finite.iter().sum::<f64>() / finite.len() as f64;
        ProfilerStats {
            frames: self.total_frames,
            window: self.samples.len() as u64,
            fps: if mean > 0.0 { 1000.0 / mean } else { f64::NAN },
            p50: quantile(&frame, 0.5),
            p95: quantile(&frame, 0.95),
            p99: quantile(&frame, 0.99),
            max: quantile(&frame, 1.0),
            stutters: self.stutters,
            cpu_p50: quantile(&cpu, 0.5),
            gpu_p50: quantile(&gpu, 0.5),
        }
    }

    /// `frame_ms` of the window's frames, oldest to newest.
    pub fn frame_history(&self) -> impl Iterator<Item = f64> + '_ {
        self.samples.iter().map(|s| s.frame_ms)
    }

    /// The window's frames, oldest to newest.
    pub fn samples(&self) -> impl Iterator<Item = &FrameSample> + '_ {
        self.samples.iter()
    }

    /// The median GPU time of every pass over the window, in the order the passes first appear
    /// (frames without that pass do not count towards its median).
    pub fn pass_history(&self) -> Vec<(&'static str, f64)> {
        let mut passes: Vec<(&'static str, Vec<f64>)> = Vec::new();
        for s in &self.samples {
            for &(name, ms) in &s.gpu_ms {
                match passes.iter_mut().find(|(n, _)| *n == name) {
                    Some((_, v)) => v.push(ms),
                    None => passes.push((name, vec![ms])),
                }
            }
        }
        passes
            .into_iter()
            .map(|(name, v)| (name, quantile(&v, 0.5)))
            .collect()
    }

    /// The newest frame, if any.
    pub fn last(&self) -> Option<&FrameSample> {
        self.samples.back()
    }

    /// Frames in the window (at most [`Profiler::capacity`]).
    pub fn len(&self) -> usize {
        self.samples.len()
    }

    /// True before the first frame.
    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }

    /// The window's size.
    pub fn capacity(&self) -> usize {
        self.capacity
    }

    /// Frames pushed since the profiler was made.
    pub fn total_frames(&self) -> u64 {
        self.total_frames
    }

    /// Stutters since the profiler was made.
    pub fn stutters(&self) -> u64 {
        self.stutters
    }

    /// Forgets every frame and resets the totals (e.g. after loading another scene).
    pub fn clear(&mut self) {
        self.samples.clear();
        self.total_frames = 0;
        self.stutters = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(ms: f64) -> FrameSample {
        FrameSample {
            frame_ms: ms,
            cpu_ms: ms / 4.0,
            gpu_ms: vec![("forward", ms / 2.0), ("tonemap", 0.5)],
        }
    }

    /// A steady ~16.7 ms series with ±0.5 ms deterministic jitter.
    fn steady(n: usize) -> Vec<f64> {
        (0..n)
            .map(|i| 16.7 + 0.5 * ((i * 7919 % 101) as f64 / 50.0 - 1.0))
            .collect()
    }

    fn feed(p: &mut Profiler, series: &[f64]) {
        for &ms in series {
            p.push(frame(ms));
        }
    }

    #[test]
    fn quantiles_of_a_known_series() {
        let mut p = Profiler::new(1000);
        let series: Vec<f64> = (1..=100).map(f64::from).collect();
        feed(&mut p, &series);
        let s = p.stats();
        assert_eq!(s.frames, 100);
        assert_eq!(s.window, 100);
        assert!((s.p50 - 50.5).abs() < 1e-9, "{}", s.p50);
        assert!((s.p95 - 95.05).abs() < 1e-9, "{}", s.p95);
        assert!((s.p99 - 99.01).abs() < 1e-9, "{}", s.p99);
        assert_eq!(s.max, 100.0);
        assert!((s.cpu_p50 - 50.5 / 4.0).abs() < 1e-9);
        // Per frame: ms/2 + 0.5.
        assert!((s.gpu_p50 - (50.5 / 2.0 + 0.5)).abs() < 1e-9);
        let passes = p.pass_history();
        assert_eq!(passes.len(), 2);
        assert_eq!(passes[0].0, "forward");
        assert!((passes[0].1 - 25.25).abs() < 1e-9);
        assert_eq!(passes[1], ("tonemap", 0.5));
        // Increasing series: never more than twice the median of what came before... except
        // early on, when the window is short: frame 9 (9 ms) after 1..=8 (median 4.5) is not
        // > 9, frame 10 after 1..=9 (median 5) is not > 10: no stutters at all.
        assert_eq!(s.stutters, 0);
    }

    #[test]
    fn three_spikes_are_three_stutters() {
        let mut series = steady(400);
        for i in [50, 180, 333] {
            series[i] = 45.0;
        }
        // A spike inside the first STUTTER_MIN_FRAMES frames is not judged.
        series[3] = 80.0;
        let mut p = Profiler::new(DEFAULT_CAPACITY);
        feed(&mut p, &series);
        assert_eq!(p.stutters(), 3);
        assert_eq!(p.stats().stutters, 3);
        assert_eq!(stutter_count(&series), 3);
        // Just at 2 × median is not a stutter (strictly greater).
        let mut flat = vec![10.0; 20];
        flat[15] = 20.0;
        assert_eq!(stutter_count(&flat), 0);
        flat[15] = 20.001;
        assert_eq!(stutter_count(&flat), 1);
    }

    #[test]
    fn steady_series_has_no_stutters() {
        let series = steady(10_000);
        let mut p = Profiler::new(DEFAULT_CAPACITY);
        feed(&mut p, &series);
        assert_eq!(p.stutters(), 0);
        assert_eq!(stutter_count(&series), 0);
        assert_eq!(p.total_frames(), 10_000);
    }

    #[test]
    fn push_and_stutter_count_agree() {
        // A series whose level changes: the rolling window matters.
        let mut series = steady(1000);
        for (i, x) in series.iter_mut().enumerate() {
            if i >= 400 {
                *x *= 3.0; // a level change counts once or more until the median catches up
            }
            if i % 97 == 0 {
                *x *= 2.5;
            }
        }
        for cap in [1, 8, 9, 50, DEFAULT_CAPACITY] {
            let mut p = Profiler::new(cap);
            feed(&mut p, &series);
            assert_eq!(
                p.stutters(),
                stutter_count_with_window(&series, cap),
                "{cap}"
            );
        }
        let mut p = Profiler::default();
        feed(&mut p, &series);
        assert_eq!(p.stutters(), stutter_count(&series));
        assert!(p.stutters() > 0);
    }

    #[test]
    fn window_rolls_over() {
        let mut p = Profiler::new(10);
        let series: Vec<f64> = (1..=25).map(f64::from).collect();
        feed(&mut p, &series);
        assert_eq!(p.len(), 10);
        assert_eq!(p.capacity(), 10);
        assert_eq!(p.total_frames(), 25);
        let history: Vec<f64> = p.frame_history().collect();
        assert_eq!(history, (16..=25).map(f64::from).collect::<Vec<_>>());
        let s = p.stats();
        assert_eq!(s.frames, 25);
        assert_eq!(s.window, 10);
        assert_eq!(s.max, 25.0);
        assert_eq!(s.p50, 20.5);
        assert_eq!(p.last().map(|f| f.frame_ms), Some(25.0));
        p.clear();
        assert!(p.is_empty());
        assert_eq!(p.total_frames(), 0);
    }

    #[test]
    fn fps_is_1000_over_the_mean() {
        let mut p = Profiler::new(100);
        assert!(p.stats().fps.is_nan());
        assert!(p.stats().p50.is_nan());
        feed(&mut p, &[10.0; 10]);
        assert!((p.stats().fps - 100.0).abs() < 1e-9);
        let mut p = Profiler::new(100);
        feed(&mut p, &[10.0, 30.0, 10.0, 30.0]);
        assert!((p.stats().fps - 50.0).abs() < 1e-9);
    }

    #[test]
    fn gpu_p50_is_nan_without_gpu_times() {
        let mut p = Profiler::new(16);
        for _ in 0..5 {
            p.push(FrameSample {
                frame_ms: 16.0,
                cpu_ms: 2.0,
                gpu_ms: Vec::new(),
            });
        }
        let s = p.stats();
        assert!(s.gpu_p50.is_nan());
        assert_eq!(s.cpu_p50, 2.0);
        assert!(p.pass_history().is_empty());
        // NaN serialises as null.
        let json = serde_json::to_string(&s).unwrap();
        assert!(json.contains("\"gpu_p50\":null"), "{json}");
    }
}
