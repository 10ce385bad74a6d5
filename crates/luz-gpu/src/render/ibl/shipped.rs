//! The default scene's environment, precomputed at the default sizes and shipped with luz, so
//! that a start with an empty cache does not spend ~0.7 s baking it on lavapipe
//! (docs/performance.md, "Cold start"). It is the cache file a run writes for that environment
//! ([`DEFAULT_ENV_FILE`]: environment cube with mips, irradiance cube, prefiltered cube),
//! deflated; when that entry is missing from the cache folder (or damaged), it is filled from
//! the shipped bytes instead of computed.
//!
//! The bytes are made on lavapipe by `cargo run --release -p luz-gpu --example default_env`
//! (`headless::bake_default_environment`, then [`deflate`]); the test
//! `tests/ibl.rs::shipped_default_environment_regenerates` bakes it again and compares every
//! texel ([`max_difference`]): lavapipe is deterministic on one machine but not across CPUs
//! (its JIT picks the CPU's instructions), so the check is a tolerance, not byte equality.
//! Another device's bake differs by rounding: there the shipped data stands in for it as the
//! cache would.

use std::path::Path;

use super::IblSettings;

/// The cache file name of the shipped bake: the default scene's environment key at the default
/// settings.
pub const DEFAULT_ENV_FILE: &str =
    "sky-fd1e2ad182d3f726-env512_irr64x256_pre512x1024m8_lut512x1024.ibl";

/// Where the generator writes the deflated bake, relative to the luz-gpu crate.
pub const DEFAULT_ENV_DATA: &str = "data/default_env.ibl.deflate";

static DEFAULT_ENV: &[u8] = include_bytes!("../../../data/default_env.ibl.deflate");

/// The largest inflated size accepted (the default bake is 33.8 MB).
const MAX_INFLATED: usize = 64 << 20;

/// The shipped cache file's bytes when `cache_file` is the shipped entry and `s` allows it.
pub(super) fn environment(cache_file: &Path, s: &IblSettings) -> Option<Vec<u8>> {
    if !s.shipped || cache_file.file_name()? != DEFAULT_ENV_FILE {
        return None;
    }
    shipped_bytes()
}

/// The shipped bake, inflated (None, with a warning, if it does not inflate).
pub fn shipped_bytes() -> Option<Vec<u8>> {
    match miniz_oxide::inflate::decompress_to_vec_with_limit(DEFAULT_ENV, MAX_INFLATED) {
        Ok(bytes) => Some(bytes),
        Err(e) => {
            log::warn!("the shipped environment data does not inflate ({e:?}); computing it");
            None
        }
    }
}

/// The largest difference between two IBL cache files of the same layout, texel by texel (every
/// blob is RGBA16F: [`super::CUBE_FORMAT`]), relative to max(1, |shipped value|); `None` when
/// either is damaged or their blobs differ in number or size.
pub fn max_difference(fresh: &[u8], shipped: &[u8]) -> Option<f32> {
    use crate::files::cache_dir::{unframe, Framed};
    const MAGIC: &[u8; 8] = b"LUZIBL02";
    let (Framed::Body(a), Framed::Body(b)) = (unframe(fresh, MAGIC), unframe(shipped, MAGIC))
    else {
        return None;
    };
    if a.len() != b.len() {
        return None;
    }
    let (mut pos, mut worst) = (0usize, 0f32);
    while pos < a.len() {
        let len = |d: &[u8]| {
            d.get(pos..pos + 8)
                .map(|l| u64::from_le_bytes(l.try_into().unwrap()))
        };
        let n = len(a)?;
        if len(b)? != n || n % 2 != 0 {
            return None;
        }
        let range = pos + 8..pos + 8 + n as usize;
        let (ta, tb) = (a.get(range.clone())?, b.get(range)?);
        for (x, y) in ta.chunks_exact(2).zip(tb.chunks_exact(2)) {
            let f = |c: &[u8]| half::f16::from_le_bytes([c[0], c[1]]).to_f32();
            let (x, y) = (f(x), f(y));
            let d = if x == y {
                0.0
            } else {
                (x - y).abs() / y.abs().max(1.0)
            };
            worst = worst.max(if d.is_nan() { f32::INFINITY } else { d });
        }
        pos += 8 + n as usize;
    }
    Some(worst)
}

/// Deflates a cache file's bytes as they are shipped.
pub fn deflate(bytes: &[u8]) -> Vec<u8> {
    miniz_oxide::deflate::compress_to_vec(bytes, 6)
}
