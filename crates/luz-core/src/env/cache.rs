//! A stable key for caching precomputed image-based-lighting data on disk.

use std::path::Path;

use crate::scene::{EnvSource, Environment};

/// Bumped whenever [`super::load_equirect`] would produce different texels for the same input
/// (a change to the procedural environments, the resampling or the sanitising), so that old
/// cache entries stop matching.
pub const CACHE_VERSION: u32 = 1;

pub use crate::files::{fnv1a64, Fnv1a};

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
    let safe: String = name
        .chars()
        .map(crate::files::file_safe_char)
        .take(32)
        .collect();
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
