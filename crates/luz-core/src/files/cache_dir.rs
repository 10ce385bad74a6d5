//! The folder of the disk caches (precomputed IBL data at its top, LOD chains in `lod/`):
//! checked once on start ([`open`]), its stale temporary files removed, a size cap
//! ([`DEFAULT_MAX_MB`], `--cache-max-mb`) kept by removing the least recently used cache files,
//! and one warning per problem that says what it costs ([`warn_once`]).
//!
//! Every cache file is written through a temporary file next to it (`.NAME.SEQ.PID.tmp`,
//! [`temp_path`]) and a rename, so a killed run or a full disk never leaves a partial cache file;
//! the temporary file of a run that was killed is removed by the next run's [`open`].

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, SystemTime};

/// The cache's default size cap, MiB (`--cache-max-mb` sets another).
pub const DEFAULT_MAX_MB: u64 = 1024;
/// A temporary file whose process cannot be checked (not Linux) is stale after this long.
pub const STALE_AFTER: Duration = Duration::from_secs(3600);
/// What a cache that cannot be used costs, in the warnings.
pub const COST: &str = "nothing is cached, so the IBL precompute (1-4 s per environment) and the \
                        LOD simplification run again on every run";

/// File extensions of cache files (what eviction may remove): IBL data (`.ibl`), the shared LUT
/// layers (`.bin`), LOD chains (`.lod`).
const CACHE_EXTENSIONS: [&str; 3] = ["ibl", "bin", "lod"];

static MAX_BYTES: AtomicU64 = AtomicU64::new(DEFAULT_MAX_MB << 20);
/// The folder [`open`] accepted and the bytes of cache files in it as far as this process knows.
static OPENED: Mutex<Option<(PathBuf, u64)>> = Mutex::new(None);
/// The problems already reported ([`warn_once`]).
static WARNED: Mutex<Vec<String>> = Mutex::new(Vec::new());

/// Sets the size cap (`--cache-max-mb`); 0 keeps nothing between runs.
pub fn set_max_mb(mb: u64) {
    MAX_BYTES.store(mb.saturating_mul(1 << 20), Ordering::Relaxed);
}

/// The size cap in bytes.
pub fn max_bytes() -> u64 {
    MAX_BYTES.load(Ordering::Relaxed)
}

/// Calls `warn` with `message` the first time this process reports problem `key`, and not after:
/// a cache folder that cannot be written gives one warning, not one per file.
pub fn warn_once(key: &str, message: String, warn: &mut dyn FnMut(String)) {
    let mut warned = WARNED.lock().unwrap_or_else(|e| e.into_inner());
    if !warned.iter().any(|k| k == key) {
        warned.push(key.to_string());
        warn(message);
    }
}

/// The temporary file a write of `path` goes through: `.NAME.SEQ.PID.tmp` in its folder, `SEQ`
/// unique within the process (threads preparing a scene in parallel may write one entry at once;
/// each writes its own temporary file and the last rename wins, with the same bytes).
pub fn temp_path(path: &Path) -> PathBuf {
    static SEQ: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let seq = SEQ.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    path.with_file_name(format!(".{name}.{seq}.{}.tmp", std::process::id()))
}

/// What [`open`] did to the folder.
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub struct Tidied {
    /// Temporary files of runs that ended without finishing their write, removed.
    pub stale_removed: usize,
    /// Cache files removed to keep the cap, oldest used first.
    pub evicted: usize,
    /// Bytes of cache files left.
    pub bytes: u64,
}

/// Makes `dir` the cache folder: creates it, checks that it can be written, removes stale
/// temporary files and keeps the size cap. `Err(message)` (naming the folder, the problem and
/// [`COST`]) when it cannot be used: a file, a folder that cannot be created or written.
pub fn open(dir: &Path) -> Result<Tidied, String> {
    let name = dir.display();
    if dir.exists() && !dir.is_dir() {
        return Err(format!(
            "{name}: the cache folder is a file, not a folder (LUZ_CACHE_DIR?); {COST}"
        ));
    }
    std::fs::create_dir_all(dir)
        .map_err(|e| format!("{name}: cannot create the cache folder ({e}); {COST}"))?;
    let probe = temp_path(&dir.join("probe"));
    std::fs::write(&probe, b"luz")
        .map_err(|e| format!("{name}: cannot write in the cache folder ({e}); {COST}"))?;
    let _ = std::fs::remove_file(&probe);
    let mut tidied = Tidied::default();
    for folder in [dir.to_path_buf(), dir.join("lod")] {
        for entry in entries(&folder) {
            if is_stale_temp(&entry) && std::fs::remove_file(&entry.path).is_ok() {
                tidied.stale_removed += 1;
            }
        }
    }
    let (evicted, bytes) = evict(dir, max_bytes());
    tidied.evicted = evicted;
    tidied.bytes = bytes;
    *OPENED.lock().unwrap_or_else(|e| e.into_inner()) = Some((dir.to_path_buf(), bytes));
    Ok(tidied)
}

/// Records that a cache file of `bytes` was written at `path`; past the cap, the least recently
/// used files of the opened folder are removed until it fits again.
pub fn written(path: &Path, bytes: u64) {
    let mut opened = OPENED.lock().unwrap_or_else(|e| e.into_inner());
    let Some((dir, used)) = opened.as_mut() else {
        return;
    };
    if !path.starts_with(&*dir) {
        return;
    }
    *used += bytes;
    if *used > max_bytes() {
        *used = evict(dir, max_bytes()).1;
    }
}

/// Marks the cache file at `path` as just used (its modification time: eviction removes the
/// least recently used first). Best effort.
pub fn touch(path: &Path) {
    if let Ok(f) = std::fs::File::options().append(true).open(path) {
        let _ = f.set_modified(SystemTime::now());
    }
}

struct Entry {
    path: PathBuf,
    name: String,
    modified: SystemTime,
    len: u64,
}

/// The regular files directly in `folder`.
fn entries(folder: &Path) -> Vec<Entry> {
    let Ok(read) = std::fs::read_dir(folder) else {
        return Vec::new();
    };
    read.flatten()
        .filter_map(|e| {
            let meta = e.metadata().ok().filter(|m| m.is_file())?;
            Some(Entry {
                path: e.path(),
                name: e.file_name().to_string_lossy().into_owned(),
                modified: meta.modified().unwrap_or(SystemTime::UNIX_EPOCH),
                len: meta.len(),
            })
        })
        .collect()
}

/// A temporary file ([`temp_path`], or `NAME.tmpPID` of earlier versions) whose process has
/// ended (Linux: no `/proc/PID`) or, where that cannot be known, older than [`STALE_AFTER`].
fn is_stale_temp(e: &Entry) -> bool {
    let pid = if let Some(rest) = e.name.strip_suffix(".tmp") {
        rest.rsplit('.').next().and_then(|p| p.parse::<u32>().ok())
    } else {
        let ext = e.name.rsplit('.').next().unwrap_or("");
        ext.strip_prefix("tmp").and_then(|p| p.parse::<u32>().ok())
    };
    let Some(pid) = pid else {
        return false;
    };
    if pid == std::process::id() {
        return false;
    }
    if Path::new("/proc/self").exists() {
        return !Path::new(&format!("/proc/{pid}")).exists();
    }
    e.modified.elapsed().is_ok_and(|age| age > STALE_AFTER)
}

/// Removes the least recently used cache files of `dir` (and `dir/lod`) until they hold at most
/// `max` bytes: (files removed, bytes left).
fn evict(dir: &Path, max: u64) -> (usize, u64) {
    let mut files: Vec<Entry> = [dir.to_path_buf(), dir.join("lod")]
        .iter()
        .flat_map(|f| entries(f))
        .filter(|e| {
            let ext = Path::new(&e.name).extension().and_then(|x| x.to_str());
            ext.is_some_and(|x| CACHE_EXTENSIONS.contains(&x))
        })
        .collect();
    let mut total: u64 = files.iter().map(|e| e.len).sum();
    files.sort_by_key(|e| e.modified);
    let mut removed = 0;
    for e in &files {
        if total <= max {
            break;
        }
        if std::fs::remove_file(&e.path).is_ok() {
            total -= e.len;
            removed += 1;
        }
    }
    (removed, total)
}

/// The frame every cache file has: an 8-byte magic (six bytes naming the format, two its
/// version), the CRC-32 of the body (little-endian u32), four reserved bytes, the body.
pub fn frame(magic: &[u8; 8], body: &[u8]) -> Vec<u8> {
    let mut data = Vec::with_capacity(16 + body.len());
    data.extend_from_slice(magic);
    data.extend_from_slice(&crc32fast::hash(body).to_le_bytes());
    data.extend_from_slice(&[0; 4]);
    data.extend_from_slice(body);
    data
}

/// What a cache file's [`frame`] holds.
#[derive(Debug, PartialEq)]
pub enum Framed<'a> {
    /// The body, its checksum verified.
    Body(&'a [u8]),
    /// Another version of the same format: a quiet miss.
    OtherVersion,
    /// Empty, zeroed, truncated, another program's data or a body that does not match its
    /// checksum: damaged (one warning, computed again).
    Damaged,
}

/// The body of the cache file `data` framed with `magic` ([`frame`]).
pub fn unframe<'a>(data: &'a [u8], magic: &[u8; 8]) -> Framed<'a> {
    if !data.starts_with(magic) {
        return if data.len() >= 8 && data.starts_with(&magic[..6]) {
            Framed::OtherVersion
        } else {
            Framed::Damaged
        };
    }
    match (data.get(8..12), data.get(16..)) {
        (Some(crc), Some(body)) if crc == crc32fast::hash(body).to_le_bytes() => Framed::Body(body),
        _ => Framed::Damaged,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("luz-cache-dir-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("lod")).unwrap();
        dir
    }

    fn age(path: &Path, seconds_ago: u64) {
        let f = std::fs::File::options().append(true).open(path).unwrap();
        f.set_modified(SystemTime::now() - Duration::from_secs(seconds_ago))
            .unwrap();
    }

    /// Past the cap the oldest used files go first, until the rest fits; files that are not
    /// cache files (a user's notes) are never removed.
    #[test]
    fn the_cap_evicts_the_least_recently_used_files() {
        let dir = scratch("evict");
        let kib = vec![0u8; 1024];
        for (i, name) in ["a.ibl", "lod/b.lod", "c.bin", "lod/d.lod"]
            .iter()
            .enumerate()
        {
            let path = dir.join(name);
            std::fs::write(&path, &kib).unwrap();
            age(&path, 1000 - 100 * i as u64);
        }
        std::fs::write(dir.join("notes.txt"), vec![0u8; 8192]).unwrap();
        age(&dir.join("notes.txt"), 5000);
        // a.ibl is the oldest written but was just read.
        touch(&dir.join("a.ibl"));
        assert_eq!(evict(&dir, 4096), (0, 4096));
        assert_eq!(evict(&dir, 2500), (2, 2048));
        let left = |p: &str| dir.join(p).exists();
        assert!(left("a.ibl") && left("lod/d.lod") && left("notes.txt"));
        assert!(!left("lod/b.lod") && !left("c.bin"));
        assert_eq!(evict(&dir, 0), (2, 0));
        assert!(left("notes.txt"));
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// `open` removes the temporary files of processes that no longer run, both namings, in the
    /// folder and in `lod/`, and keeps this process's and other files.
    #[test]
    fn open_removes_stale_temporary_files() {
        let dir = scratch("stale");
        // No process has this id (beyond Linux's pid_max).
        let dead = 4_194_999u32;
        let me = std::process::id();
        let stale = [
            format!(".x.ibl.{dead}.tmp"),
            format!("lod/.0123.lod.{dead}.tmp"),
            format!("lod/0123.tmp{dead}"),
        ];
        let kept = [
            format!(".y.ibl.{me}.tmp"),
            "lod/0123.lod".to_string(),
            "readme.tmp".to_string(),
        ];
        for f in stale.iter().chain(&kept) {
            std::fs::write(dir.join(f), b"part").unwrap();
        }
        let tidied = open(&dir).unwrap();
        assert_eq!(tidied.stale_removed, 3);
        for f in &stale {
            assert!(!dir.join(f).exists(), "{f}");
        }
        for f in &kept {
            assert!(dir.join(f).exists(), "{f}");
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A file where the folder should be, and a folder that cannot be made: an error naming it
    /// and what it costs.
    #[test]
    fn a_file_as_the_cache_folder_is_refused_with_its_cost() {
        let dir = scratch("file");
        let file = dir.join("cache");
        std::fs::write(&file, b"").unwrap();
        let e = open(&file).unwrap_err();
        assert!(
            e.contains("is a file, not a folder") && e.contains(COST),
            "{e}"
        );
        let e = open(&file.join("sub")).unwrap_err();
        assert!(
            e.contains("cannot create the cache folder") && e.contains(COST),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn each_problem_is_reported_once() {
        let mut got = Vec::new();
        for _ in 0..3 {
            warn_once("test:a", "a".into(), &mut |m| got.push(m));
            warn_once("test:b", "b".into(), &mut |m| got.push(m));
        }
        assert_eq!(got, ["a", "b"]);
    }
}
