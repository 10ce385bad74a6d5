//! How long library work reports its progress. The library never draws: the binary turns these
//! calls into progress bars (`src/cli/common.rs`), the viewer into its status line, tests ignore
//! them.

use std::fmt;
use std::sync::Arc;

/// Receives the progress of long work (IBL precomputation, reference rows, lab variants).
pub trait Progress: Send + Sync {
    /// `done` of `total` steps are complete; `stage` names what is being done now.
    fn update(&self, stage: &str, done: u64, total: u64);
    /// The work is over (a bar is cleared).
    fn finish(&self) {}
}

/// A shareable [`Progress`] for option structs (`Debug`, `Clone`).
#[derive(Clone)]
pub struct ProgressSink(pub Arc<dyn Progress>);

impl ProgressSink {
    pub fn new(p: impl Progress + 'static) -> Self {
        Self(Arc::new(p))
    }
}

impl fmt::Debug for ProgressSink {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("ProgressSink")
    }
}

impl std::ops::Deref for ProgressSink {
    type Target = dyn Progress;
    fn deref(&self) -> &Self::Target {
        &*self.0
    }
}

/// Calls `update` and, when dropped, `finish` (so an early `?` return still clears a bar).
pub struct Reporting<'a>(pub Option<&'a dyn Progress>);

impl Reporting<'_> {
    pub fn update(&self, stage: &str, done: u64, total: u64) {
        if let Some(p) = self.0 {
            p.update(stage, done, total);
        }
    }
}

impl Drop for Reporting<'_> {
    fn drop(&mut self) {
        if let Some(p) = self.0 {
            p.finish();
        }
    }
}
