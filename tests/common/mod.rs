//! The one shared test harness, included by every test binary with `mod common;`:
//!
//! * paths: [`root`] (the checkout), [`shared_dir`] (`../shared` beside it, or a visible skip);
//! * [`scratch`]: a fresh folder per test under the system's temporary folder;
//! * [`process`]: the `luz` binary as a child process ([`luz`], [`luz_command`], [`run`],
//!   [`run_with_stdin`], [`luz_in_window`], [`Ran`]);
//! * [`vulkan`]: a validated lavapipe context ([`gpu`]), rendering helpers and golden-image checks
//!   ([`check_golden`]);
//! * [`shadow_judge`]: the shadow tests' classes and judge of a GPU image against the reference.
//!
//! Nothing here changes the test process's environment (tests run on parallel threads): options
//! for a child process go to its `Command` only.
#![allow(dead_code, unused_imports)]

pub mod process;
pub mod shadow_judge;
pub mod vulkan;

use std::ops::Deref;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

pub use process::*;
pub use vulkan::*;

/// The checkout (the folder of `Cargo.toml`), wherever the clone lives.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `../shared/<what>`: the folder beside the checkout with real models, environments and
/// textures (not part of the project), whether or not it exists.
pub fn shared_path(what: &str) -> PathBuf {
    root().join("..").join("shared").join(what)
}

/// [`shared_path`] when it exists, else None with a visible note (the caller skips).
pub fn shared_dir(what: &str) -> Option<PathBuf> {
    let p = shared_path(what);
    if p.exists() {
        Some(p)
    } else {
        eprintln!(
            "SKIPPED: {} not found (a fresh clone without ../shared)",
            p.display()
        );
        None
    }
}

/// A fresh, empty folder of one test (see [`scratch`]). It derefs to its [`Path`]; dropping it
/// removes the folder, unless the test is failing (then it is kept and its path printed).
pub struct Scratch {
    path: PathBuf,
}

/// A fresh, empty folder for one test: `<temp>/luz-test-<binary>-<pid>-<n>-<name>`, unique to this
/// test binary, process and call (`n` counts the calls), so parallel tests and concurrent runs of
/// the suite from any number of clones never share one. Removed when the returned [`Scratch`] is
/// dropped (kept when the test fails).
pub fn scratch(name: &str) -> Scratch {
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    let path = std::env::temp_dir().join(format!(
        "luz-test-{}-{}-{n}-{name}",
        env!("CARGO_CRATE_NAME"),
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&path);
    std::fs::create_dir_all(&path)
        .unwrap_or_else(|e| panic!("cannot create {}: {e}", path.display()));
    Scratch { path }
}

impl Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.path
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.path
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if std::thread::panicking() {
            eprintln!("kept {} (the test failed)", self.path.display());
        } else {
            let _ = std::fs::remove_dir_all(&self.path);
        }
    }
}

/// CRC-32 (PNG's, reflected 0xEDB88320) of `bytes`.
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                (c >> 1) ^ 0xEDB8_8320
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// A PNG that declares `w × h` RGBA8 pixels and holds a single empty compressed block: a few
/// dozen bytes whose full decoding would need w · h · 4 bytes and more.
pub fn declared_png(w: u32, h: u32) -> Vec<u8> {
    let chunk = |ty: &[u8], data: &[u8]| {
        let mut c = (data.len() as u32).to_be_bytes().to_vec();
        let mut body = ty.to_vec();
        body.extend_from_slice(data);
        c.extend_from_slice(&body);
        c.extend_from_slice(&crc32(&body).to_be_bytes());
        c
    };
    let mut ihdr = w.to_be_bytes().to_vec();
    ihdr.extend_from_slice(&h.to_be_bytes());
    ihdr.extend_from_slice(&[8, 6, 0, 0, 0]);
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    png.extend(chunk(b"IHDR", &ihdr));
    // zlib header, one empty stored final block, Adler-32 of nothing.
    png.extend(chunk(
        b"IDAT",
        &[0x78, 0x01, 0x01, 0, 0, 0xff, 0xff, 0, 0, 0, 1],
    ));
    png.extend(chunk(b"IEND", &[]));
    png
}
