//! luz: a Vulkan-native renderer of classic and physically based lighting models that measures how
//! right and how fast each one is.
//!
//! Layers (arrows point down only): `cli` → `headless` → `render` → `vk`; `scene`, `brdf`, `color`,
//! `imageio` and `diff` know nothing of Vulkan. The window viewer (feature `window`) sits on top.

pub mod brdf;
pub mod brdf_cli;
pub mod cli;
pub mod color;
pub mod diff;
pub mod env;
/// Entry points shared by the fuzz targets (`fuzz/`) and `tests/fuzz_regressions.rs`.
pub mod fuzzing;
pub mod headless;
pub mod imageio;
pub mod lab;
pub mod plot;
pub mod profiler;
pub mod reference;
pub mod render;
pub mod scene;
pub mod stability;
pub mod stats;
pub mod texture;
pub mod vk;
#[cfg(feature = "window")]
pub mod window;
