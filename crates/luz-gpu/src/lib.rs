//! luz's GPU layer: Vulkan on raw `ash` (`vk`), the passes (`render`), the frames they make up as
//! frame graphs (`render::frame`, on [`luz_graph`]), offscreen rendering and readback
//! (`headless`), what a render records about itself (`provenance`), and the shader build
//! (`build.rs`). It stands on `luz-core`, whose modules it re-exports so that `luz_gpu::scene` and
//! `luz_core::scene` are one module.

pub use luz_core::{
    brdf, color, compare, diff, env, files, glsl, imageio, plot, prepare, profiler, progress,
    scene, stats, texture,
};
/// The frame graph: passes, resources, barriers, timers ([`luz_graph`]).
pub use luz_graph as graph;

pub mod headless;
pub mod provenance;
pub mod render;
pub mod vk;
