//! Host memory settings for a device that runs on the CPU (lavapipe).
//!
//! lavapipe's worker threads allocate the bins of every frame with `malloc` and free them at the
//! frame's end. glibc hands a thread arena's free top back to the kernel (`madvise(DONTNEED)`)
//! once it exceeds the trim threshold, so the next frame faults the same pages in again and the
//! kernel clears each one: on grid49 that was about a fifth of the submitting thread's time
//! (`perf`), 608 `madvise` calls in 43 frames (`strace -c`). Raising the trim threshold keeps the
//! freed memory in the process; resident memory stays at its peak instead of going up and down
//! every frame. The measured effect is in docs/performance.md ("Host memory").

/// The trim threshold set for a CPU device: 1 GiB.
pub const TRIM_THRESHOLD: i32 = 1 << 30;

/// Environment variable that turns the setting off (`LUZ_MALLOC_TUNING=0`).
pub const ENV_DISABLE: &str = "LUZ_MALLOC_TUNING";

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

/// Raises glibc's malloc trim threshold for the whole process (see the module comment), unless
/// `LUZ_MALLOC_TUNING=0`.
pub fn tune_for_cpu_device() -> MallocTuning {
    if disabled_by(std::env::var(ENV_DISABLE).ok().as_deref()) {
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
    fn the_variable_turns_it_off() {
        assert!(disabled_by(Some("0")));
        assert!(disabled_by(Some(" off ")));
        assert!(!disabled_by(Some("1")));
        assert!(!disabled_by(None));
    }
}
