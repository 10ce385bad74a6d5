//! A stable key for caching precomputed image-based-lighting data on disk.

use std::path::Path;

use crate::scene::{EnvSource, Environment};

/// Bumped whenever [`super::load_equirect`] would produce different texels for the same input
/// (a change to the procedural environments, the resampling or the sanitising), so that old
/// cache entries stop matching.
pub const CACHE_VERSION: u32 = 1;

/// 64-bit FNV-1a (Fowler–Noll–Vo): stable across Rust versions and platforms, unlike
/// `std::collections::hash_map::DefaultHasher`.
#[derive(Debug, Clone, Copy)]
pub struct Fnv1a(u64);

impl Fnv1a {
    const OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
    const PRIME: u64 = 0x0000_0100_0000_01b3;

    pub fn new() -> Self {
        Fnv1a(Self::OFFSET)
    }

    pub fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 ^= u64::from(*b);
            self.0 = self.0.wrapping_mul(Self::PRIME);
        }
    }

    /// Writes a length-prefixed field, so that `("ab", "c")` and `("a", "bc")` differ.
    pub fn field(&mut self, bytes: &[u8]) {
        self.write(&(bytes.len() as u64).to_le_bytes());
        self.write(bytes);
    }

    pub fn finish(&self) -> u64 {
        self.0
    }
}

impl Default for Fnv1a {
    fn default() -> Self {
        Self::new()
    }
}

/// FNV-1a 64 of `bytes`.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h = Fnv1a::new();
    h.write(bytes);
    h.finish()
}

/// A file-name-safe cache key `<name>-<16 hex digits>` for the IBL data precomputed from `env`
/// with the caller's `settings` (sizes, sample counts, method, … as text). The hash covers
/// [`CACHE_VERSION`], the source (for a file: its path as given, size and modification time —
/// not its content, so keys are cheap; an edited file gets a new mtime), `intensity` and
/// `settings`. `rotation_deg` and the rendering-only settings are *not* included: rotation is
/// applied at lookup, so rotated environments share their data. `<name>` is the file stem (or
/// the source kind), reduced to `[A-Za-z0-9_-]` and at most 32 characters.
pub fn cache_key(env: &Environment, settings: &str) -> String {
    let mut h = Fnv1a::new();
    h.field(b"luz-ibl");
    h.field(&CACHE_VERSION.to_le_bytes());
    h.field(env.source.kind_name().as_bytes());
    let name = match &env.source {
        EnvSource::Hdr(path) => {
            h.field(path.to_string_lossy().as_bytes());
            let (len, secs, nanos) = file_stamp(path);
            h.field(&len.to_le_bytes());
            h.field(&secs.to_le_bytes());
            h.field(&nanos.to_le_bytes());
            path.file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "hdr".into())
        }
        EnvSource::Uniform(c) => {
            for x in c.to_array() {
                h.field(&x.to_bits().to_le_bytes());
            }
            "uniform".into()
        }
        EnvSource::Sky {
            sun_direction,
            sun_intensity,
        } => {
            for x in sun_direction.to_array() {
                h.field(&x.to_bits().to_le_bytes());
            }
            h.field(&sun_intensity.to_bits().to_le_bytes());
            "sky".into()
        }
        EnvSource::Studio => "studio".into(),
    };
    h.field(&env.intensity.to_bits().to_le_bytes());
    h.field(settings.as_bytes());
    let safe: String = name.chars().map(crate::file_safe_char).take(32).collect();
    format!("{safe}-{:016x}", h.finish())
}

/// (size, mtime seconds, mtime nanoseconds) of a file; zeros when unknown.
fn file_stamp(path: &Path) -> (u64, u64, u32) {
    let Ok(meta) = std::fs::metadata(path) else {
        return (0, 0, 0);
    };
    let mtime = meta
        .modified()
        .ok()
        .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
        .unwrap_or_default();
    (meta.len(), mtime.as_secs(), mtime.subsec_nanos())
}
