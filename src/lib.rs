//! luz: a Vulkan-native renderer of classic and physically based lighting models that measures how
//! right and how fast each one is.
//!
//! The layers are crates, and arrows point down only (docs/architecture.md):
//! `luz-core` (scenes, BRDFs, environments, colour, image I/O; no Vulkan) ← `luz-gpu` (Vulkan,
//! the passes, the frame graph's frames, headless rendering) ← `luz-tools` (golden runs, the lab,
//! the stability sweep, the CPU reference) ← this crate: the viewer (feature `window`) and the
//! command line (`src/main.rs`, `src/cli/`). The library never prints progress or chooses exit
//! codes, it returns data and errors, reports progress through [`progress::Progress`] and messages
//! through the `log` facade. Every module of the layers below is re-exported here, so `luz::scene`
//! is `luz_core::scene`.

pub use luz_tools::{
    brdf, color, compare, diff, env, export, files, fuzzing, glsl, golden, graph, headless,
    imageio, lab, plot, prepare, profiler, progress, provenance, reference, render, scene,
    stability, stats, texture, vk,
};

pub mod timing;
#[cfg(feature = "window")]
pub mod window;
