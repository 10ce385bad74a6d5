//! Where a timed run writes its frames: `luz bench`'s and `luz view --bench`'s `--csv`, `--json`
//! and `--trace`, the command line's options and the viewer's ([`crate::window::ViewOptions`])
//! alike.

use std::path::PathBuf;

use clap::Args;

/// `--csv`, `--json` and `--trace`: where a timed run (`luz bench`, `luz view --bench`) writes
/// its frames.
#[derive(Args, Debug, Clone, Default)]
pub struct TimingFiles {
    /// Write one CSV line per timed frame: its CPU ms and each pass's GPU ms (`luz view` adds
    /// the frame time, the LOD budget and the triangles drawn).
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Write the summary as JSON.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Write the timed frames as a Chrome/Perfetto trace (JSON; open it in ui.perfetto.dev or
    /// chrome://tracing): per frame, the CPU's recording (the frame graph declared, compiled and
    /// recorded) and the rest of the frame, and each pass's GPU span from the graph's timers.
    #[arg(long, value_name = "FILE.json")]
    pub trace: Option<PathBuf>,
}
