//! The default scene's environment, precomputed at the default sizes and shipped with luz, so
//! that a start with an empty cache does not spend ~0.7 s baking it on lavapipe
//! (docs/performance.md, "Cold start"). It is the cache file a run writes for that environment
//! ([`DEFAULT_ENV_FILE`]: environment cube with mips, irradiance cube, prefiltered cube),
//! deflated; when that entry is missing from the cache folder (or damaged), it is filled from
//! the shipped bytes instead of computed.
//!
//! The bytes are made on lavapipe by `cargo run --release -p luz-gpu --example default_env`
//! (`headless::bake_default_environment`, then [`deflate`]); the test `tests/ibl.rs::shipped_default_environment_regenerates`
//! bakes it again and compares every byte. Another device's bake differs by rounding: there the
//! shipped data stands in for it as the cache would.

use std::path::Path;

use super::IblSettings;

/// The cache file name of the shipped bake: the default scene's environment key at the default
/// settings.
pub const DEFAULT_ENV_FILE: &str =
    "sky-b97155bd49c8d071-env512_irr64x256_pre512x64m10_lut512x1024.ibl";

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

/// Deflates a cache file's bytes as they are shipped.
pub fn deflate(bytes: &[u8]) -> Vec<u8> {
    miniz_oxide::deflate::compress_to_vec(bytes, 6)
}
