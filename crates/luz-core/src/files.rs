//! Leaf helpers every layer may use: the stable hash of the disk caches, file-name-safe
//! characters, atomic writes and the disk caches' folder ([`cache_dir`]). Nothing here imports
//! another luz module.

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

/// `c` where it is safe in a file name on every system (ASCII letters, digits, `-`, `_`), else
/// `_`: file names made from scene and case names (the IBL cache, `luz golden`'s report).
pub fn file_safe_char(c: char) -> char {
    if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
        c
    } else {
        '_'
    }
}

/// Writes `bytes` to `path` through a temporary file and a rename, creating its folder (best
/// effort: the disk caches (IBL data, LOD chains) are only slower next time when it fails).
pub fn write_file_atomically(path: &std::path::Path, bytes: &[u8]) {
    let _ = try_write_file_atomically(path, bytes);
}

/// [`write_file_atomically`] with its error: the temporary file (next to `path`,
/// [`cache_dir::temp_path`]) is removed whatever fails (a full disk leaves nothing behind), and
/// `path` is either its old contents or `bytes`, never a part of them.
pub fn try_write_file_atomically(path: &std::path::Path, bytes: &[u8]) -> std::io::Result<()> {
    write_atomically_with(path, bytes, |tmp, bytes| std::fs::write(tmp, bytes))
}

/// [`try_write_file_atomically`] with the temporary file written by `write` (tests: a full disk).
fn write_atomically_with(
    path: &std::path::Path,
    bytes: &[u8],
    write: impl FnOnce(&std::path::Path, &[u8]) -> std::io::Result<()>,
) -> std::io::Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    let tmp = cache_dir::temp_path(path);
    let done = write(&tmp, bytes).and_then(|()| std::fs::rename(&tmp, path));
    if done.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    done
}

/// The disk caches' folder: its checks on start, stale temporary files, the size cap.
pub mod cache_dir;

#[cfg(test)]
mod tests {
    use super::*;

    /// A write that fails half way (a full disk: ENOSPC after part of the bytes) leaves neither
    /// its temporary file nor a part of the file; the old contents stay.
    #[test]
    fn a_failed_write_leaves_nothing_behind() {
        let dir = std::env::temp_dir().join(format!("luz-files-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.lod");
        try_write_file_atomically(&path, b"old").unwrap();
        let full = write_atomically_with(&path, &[7u8; 1 << 20], |tmp, bytes| {
            std::fs::write(tmp, &bytes[..bytes.len() / 2])?;
            Err(std::io::Error::from_raw_os_error(28)) // ENOSPC
        });
        assert_eq!(full.unwrap_err().raw_os_error(), Some(28));
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["a.lod"]);
        assert_eq!(std::fs::read(&path).unwrap(), b"old");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
