//! Scenes to other renderers' formats, for cross-checks against an independent renderer
//! (issue 37): Mitsuba 3 XML with PLY meshes ([`mitsuba`]). Every mapping and its conversion is
//! documented in `docs/export.md`; whatever has no like-for-like counterpart is exported as the
//! closest thing (or dropped) and listed in [`ExportReport::approximations`].
//!
//! No CLI code here: the binary's `luz export` parses the arguments and prints.

pub mod mitsuba;
mod ply;

use std::path::{Path, PathBuf};

pub use ply::ply_bytes;

/// How the exported scene integrates light.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Integrator {
    /// Direct illumination only (Mitsuba's `direct`): what luz's GPU and CPU reference compute.
    Direct,
    /// Path tracing up to `max_depth` bounces (Mitsuba's `path`; 2 is direct illumination).
    Path { max_depth: u32 },
}

/// What [`export_mitsuba`] writes besides the scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ExportOptions {
    pub integrator: Integrator,
    /// Samples per pixel of the exported sampler.
    pub spp: u32,
}

impl Default for ExportOptions {
    fn default() -> Self {
        ExportOptions {
            integrator: Integrator::Direct,
            spp: 256,
        }
    }
}

/// What an export wrote.
#[derive(Debug, Clone, Default)]
pub struct ExportReport {
    /// `DIR/scene.xml`.
    pub scene_file: PathBuf,
    /// Every file written (the scene first, then meshes, textures, the environment).
    pub files: Vec<PathBuf>,
    /// Everything without a like-for-like counterpart, one phrase each (what it is and what the
    /// export did instead).
    pub approximations: Vec<String>,
}

impl ExportReport {
    /// The one warning listing every approximation, or `None` when the export is exact.
    pub fn warning(&self) -> Option<String> {
        if self.approximations.is_empty() {
            return None;
        }
        Some(format!(
            "{} thing{} without a like-for-like Mitsuba counterpart (approximated or left out; docs/export.md): {}",
            self.approximations.len(),
            if self.approximations.len() == 1 { "" } else { "s" },
            self.approximations.join("; ")
        ))
    }
}

/// Why an export failed: the file or folder at fault and the reason.
#[derive(Debug, thiserror::Error)]
#[error("{}: {reason}", .path.display())]
pub struct ExportError {
    pub path: PathBuf,
    pub reason: String,
}

impl ExportError {
    pub(crate) fn new(path: &Path, reason: impl std::fmt::Display) -> Self {
        ExportError {
            path: path.to_path_buf(),
            reason: reason.to_string(),
        }
    }
}

pub use mitsuba::export as export_mitsuba;
