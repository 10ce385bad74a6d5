//! luz's frame graph: passes declare what they read and write with named [`Access`] kinds; the
//! graph checks the declarations, culls passes whose results nobody needs, derives every
//! synchronization2 barrier, pools transient images across frames, and records it all.
//!
//! Compiling yields a [`Plan`] of plain data (live passes, barriers) that tests assert on without
//! a GPU; executing records the plan through a [`Recorder`] ([`AshRecorder`] on a device).

mod access;
mod compile;
mod dot;
mod error;
mod exec;
mod graph;
mod pool;
mod resource;
mod svg;
pub mod trace;

pub use access::{Access, AccessInfo, AppliesTo, WRITE_ACCESS};
pub use compile::{BarrierInfo, BufferInfo, CompiledGraph, ImageInfo, PassPlan, Plan};
pub use error::{GraphError, PassError};
pub use exec::{
    AshRecorder, BarrierBatch, BufferBarrier, BufferRef, ExecReport, ImageBarrier, ImageRef,
    MemoryBarrier, PassTimer, RecordContext, Recorder,
};
pub use graph::{FrameGraph, PassBuilder, RecordFn, Use, UseMode};
pub use pool::{ImageFactory, PooledImage, TransientPool};
pub use resource::{
    BufferHandle, ImageDesc, ImageHandle, ImageStateBefore, ImportedImage, Resource,
    SubresourceRange,
};
pub use trace::{check_trace, CpuSpan, Trace, TraceSummary};
