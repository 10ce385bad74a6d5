//! Host memory settings for a device that runs on the CPU (lavapipe).
//!
//! lavapipe's worker threads allocate the bins of every frame with `malloc` and free them at the
//! frame's end. glibc hands a thread arena's free top back to the kernel (`madvise(DONTNEED)`)
//! once it exceeds the trim threshold, so the next frame faults the same pages in again and the
//! kernel clears each one: on grid49 that was about a fifth of the submitting thread's time
//! (`perf`), 608 `madvise` calls in 43 frames (`strace -c`). Raising the trim threshold keeps the
//! freed memory in the process; resident memory stays at its peak instead of going up and down
//! every frame. The measured effect is in docs/performance.md (issue 14's steps, step 2).
//!
//! lavapipe also reads its rasterizer thread count from `LP_NUM_THREADS` when it loads (default:
//! one per core). The `luz` binary asks for [`RASTERIZER_THREADS_PER_CORE`] per core before any
//! Vulkan call ([`rasterizer_threads`]); a value the user set stands. With more threads than cores
//! a thread that loses its core (to the window system's copy of the last frame, or to the
//! submitting thread's binning) holds back a smaller share of the bins, so the end of each pass
//! waits less for it: on grid49's windowed frame p99/p50 went from 1.37 to 1.22 (median of eight
//! runs each, same median frame; docs/performance.md, issue 14's steps, step 5). The library never
//! sets it: changing the environment of a running process is not thread-safe.

/// The trim threshold set for a CPU device: 1 GiB.
pub const TRIM_THRESHOLD: i32 = 1 << 30;

/// Environment variable that turns the setting off (`LUZ_MALLOC_TUNING=0`).
pub const ENV_DISABLE: &str = "LUZ_MALLOC_TUNING";

/// The variable lavapipe (llvmpipe) reads its rasterizer thread count from.
pub const RASTERIZER_THREADS_ENV: &str = "LP_NUM_THREADS";

/// Rasterizer threads per core the `luz` binary asks lavapipe for.
pub const RASTERIZER_THREADS_PER_CORE: usize = 3;

/// The value of `LP_NUM_THREADS` to set, given its current value and the core count: `None`
/// when the user already set it (any value stands, `0` included).
pub fn rasterizer_threads(current: Option<&str>, cores: usize) -> Option<usize> {
    match current {
        Some(_) => None,
        None => Some(cores.max(1) * RASTERIZER_THREADS_PER_CORE),
    }
}

/// What [`tune_for_cpu_device`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MallocTuning {
    /// The trim threshold was raised to [`TRIM_THRESHOLD`].
    Raised,
    /// Turned off by `LUZ_MALLOC_TUNING=0`.
    Disabled,
    /// Not a glibc target: nothing to set.
    Unsupported,
}

impl MallocTuning {
    /// One line for reports.
    pub fn describe(self) -> &'static str {
        match self {
            MallocTuning::Raised => {
                "malloc trim threshold 1 GiB (freed frame memory stays mapped; LUZ_MALLOC_TUNING=0 turns it off)"
            }
            MallocTuning::Disabled => "malloc defaults (LUZ_MALLOC_TUNING=0)",
            MallocTuning::Unsupported => "malloc defaults (not glibc)",
        }
    }
}

/// Whether `value` of [`ENV_DISABLE`] turns the setting off.
pub fn disabled_by(value: Option<&str>) -> bool {
    matches!(value.map(str::trim), Some("0" | "off" | "false" | "no"))
}

/// Raises glibc's malloc trim threshold for the whole process (see the module comment) when
/// `enabled`.
pub fn tune_for_cpu_device(enabled: bool) -> MallocTuning {
    if !enabled {
        return MallocTuning::Disabled;
    }
    set_trim_threshold()
}

#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn set_trim_threshold() -> MallocTuning {
    // SAFETY: mallopt only changes glibc's allocator parameters (thread-safe under its own lock);
    // M_TRIM_THRESHOLD takes any non-negative byte count.
    let ok = unsafe { libc::mallopt(libc::M_TRIM_THRESHOLD, TRIM_THRESHOLD) };
    if ok == 1 {
        MallocTuning::Raised
    } else {
        MallocTuning::Unsupported
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn set_trim_threshold() -> MallocTuning {
    MallocTuning::Unsupported
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rasterizer_threads_default_and_user_value() {
        assert_eq!(rasterizer_threads(None, 2), Some(6));
        assert_eq!(rasterizer_threads(None, 0), Some(3));
        assert_eq!(rasterizer_threads(Some("2"), 2), None);
        assert_eq!(rasterizer_threads(Some(""), 8), None);
    }

    #[test]
    fn the_variable_turns_it_off() {
        assert!(disabled_by(Some("0")));
        assert!(disabled_by(Some(" off ")));
        assert!(!disabled_by(Some("1")));
        assert!(!disabled_by(None));
    }
}
