//! luz's measuring tools, on top of the GPU layer: golden-image runs (`golden`), the
//! speed-against-accuracy lab (`lab`), the BRDF stability sweep (`stability`), the CPU reference
//! renderer (`reference`), scene export to other renderers (`export`) and the fuzz entry points (`fuzzing`). Re-exports the layers below so
//! that one path names one module.

pub use luz_gpu::{
    brdf, color, compare, diff, env, files, glsl, graph, headless, imageio, plot, prepare,
    profiler, progress, provenance, render, scene, stats, texture, vk,
};

pub mod export;
/// Entry points shared by the fuzz targets (`fuzz/`) and `tests/fuzz_regressions.rs`.
pub mod fuzzing;
pub mod golden;
pub mod lab;
pub mod reference;
pub mod stability;
