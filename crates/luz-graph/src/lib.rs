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
mod plan;
mod pool;
mod resource;
mod svg;
pub mod trace;

pub use access::{Access, AccessInfo, AppliesTo, MemoryBarrier, WRITE_ACCESS};
pub use error::{GraphError, PassError};
pub use exec::{
    AshRecorder, BarrierBatch, BufferBarrier, BufferRef, CompiledGraph, ExecReport, ImageBarrier,
    ImageRef, PassTimer, RecordContext, RecordFn, Recorder,
};
pub use graph::{FrameGraph, PassBuilder};
pub use plan::{BarrierInfo, BufferInfo, ImageInfo, PassPlan, Plan};
pub use pool::{ImageFactory, PooledImage, TransientPool};
pub use resource::{
    BufferHandle, ImageDesc, ImageHandle, ImageStateBefore, ImportedImage, Resource,
    SubresourceRange, Use, UseMode,
};
pub use trace::{check_trace, CpuSpan, Trace, TraceSummary};
