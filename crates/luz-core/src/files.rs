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

/// The input budget: the most any one input may cost, checked *before* reading or allocating,
/// from file metadata, image headers and declared sizes. One process-wide value
/// ([`InputBudget::current`]), set once by the command line (`--max-file-mb`,
/// `--max-texture-mpix`, `--max-texture-mpix-total`, `--max-instances`, `--max-triangles`, `--allow-outside-uris`) and read by
/// every loader. docs/reliability.md ("Input budget") lists each limit with its default.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InputBudget {
    /// Largest file read (scene, OBJ, MTL, glTF, GLB, glTF buffer, image), and largest glTF
    /// buffer `byteLength`, in bytes.
    pub max_file_bytes: u64,
    /// Most pixels of one decoded texture (width × height from its header); decoding costs
    /// about 34 bytes a pixel with the mip chain.
    pub max_texture_pixels: u64,
    /// Most pixels of all a scene's textures together (each distinct file or embedded image
    /// once, width × height from its header, summed before any is decoded): what the decoded
    /// textures keep resident, about 5 bytes a pixel (8-bit, with mips) to 21 (float).
    pub max_texture_pixels_total: u64,
    /// Most mesh instances of one model file (glTF nodes with a mesh, once per primitive).
    pub max_instances: usize,
    /// Most triangles one model file may expand into: a glTF's meshes baked once per instance,
    /// an OBJ's faces (n − 2 for a face of n corners, counted while its text is checked, before
    /// any triangle is built).
    pub max_triangles: usize,
    /// Whether a glTF URI may name a file outside the model's folder.
    pub allow_outside_uris: bool,
}

/// 2^20 bytes.
pub const MIB: u64 = 1 << 20;
/// A megapixel of the texture budget: 2^20 pixels (1024 × 1024).
pub const MPIX: u64 = 1 << 20;

impl InputBudget {
    /// 256 MiB files, 64 Mpix textures (8192 × 8192), 256 Mpix of textures in a scene, 10,000
    /// instances, 16 Mi triangles (2^24), URIs inside the model's folder.
    pub const DEFAULT: InputBudget = InputBudget {
        max_file_bytes: 256 * MIB,
        max_texture_pixels: 64 * MPIX,
        max_texture_pixels_total: 256 * MPIX,
        max_instances: 10_000,
        max_triangles: 1 << 24,
        allow_outside_uris: false,
    };

    /// The budget in force (the default until [`InputBudget::install`]).
    pub fn current() -> InputBudget {
        *BUDGET.read().unwrap_or_else(|e| e.into_inner())
    }

    /// Makes `self` the budget of every later load in this process.
    pub fn install(self) {
        *BUDGET.write().unwrap_or_else(|e| e.into_inner()) = self;
    }
}

impl Default for InputBudget {
    fn default() -> Self {
        InputBudget::DEFAULT
    }
}

static BUDGET: std::sync::RwLock<InputBudget> = std::sync::RwLock::new(InputBudget::DEFAULT);

/// The extension of `path` in lower case (`None` without one, or when it is not UTF-8): how
/// every reader tells file kinds apart (case-insensitive).
pub fn lowercase_extension(path: &std::path::Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
}

/// `bytes` for a message: `"312 MiB"`, `"4.0 KiB"`, `"17 bytes"`.
pub fn human_bytes(bytes: u64) -> String {
    if bytes >= MIB {
        format!("{:.1} MiB", bytes as f64 / MIB as f64)
    } else if bytes >= 1024 {
        format!("{:.1} KiB", bytes as f64 / 1024.0)
    } else {
        format!("{bytes} bytes")
    }
}

/// What kind of file `meta` describes, when it is not a regular file.
fn not_regular(meta: &std::fs::Metadata) -> Option<&'static str> {
    let t = meta.file_type();
    if t.is_file() {
        return None;
    }
    if t.is_dir() {
        return Some("a directory");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return Some("a FIFO (named pipe)");
        }
        if t.is_socket() {
            return Some("a socket");
        }
        if t.is_char_device() || t.is_block_device() {
            return Some("a device");
        }
    }
    Some("not a regular file")
}

/// Checks, from its metadata alone, that `path` is a regular file (not a FIFO, device, socket
/// or folder: those block or never end) within the budget's largest file; returns its size.
/// The error says why, without the path (callers name the file).
pub fn check_input(path: &std::path::Path) -> std::io::Result<u64> {
    use std::io::{Error, ErrorKind};
    let meta = std::fs::metadata(path)?;
    if let Some(kind) = not_regular(&meta) {
        let kind_of = if kind == "a directory" {
            ErrorKind::IsADirectory
        } else {
            ErrorKind::InvalidInput
        };
        return Err(Error::new(
            kind_of,
            format!("is {kind}, not a regular file"),
        ));
    }
    let limit = InputBudget::current().max_file_bytes;
    if meta.len() > limit {
        return Err(Error::new(
            ErrorKind::FileTooLarge,
            format!(
                "{} is larger than the input budget's largest file ({}; raise it with \
                 --max-file-mb)",
                human_bytes(meta.len()),
                human_bytes(limit)
            ),
        ));
    }
    Ok(meta.len())
}

/// Opens `path` for reading after [`check_input`], and checks the opened handle again (the
/// path may have changed in between).
pub fn open_input(path: &std::path::Path) -> std::io::Result<std::fs::File> {
    check_input(path)?;
    let file = std::fs::File::open(path)?;
    if let Some(kind) = not_regular(&file.metadata()?) {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("is {kind}, not a regular file"),
        ));
    }
    Ok(file)
}

/// Reads the whole of `path`, the one way every loader reads an input file: a regular file
/// within the budget ([`check_input`]), and never more than the budget even if the file grows
/// while it is read.
pub fn read_input(path: &std::path::Path) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    let size = check_input(path)?;
    let limit = InputBudget::current().max_file_bytes;
    let file = open_input(path)?;
    let mut bytes = Vec::with_capacity(size as usize);
    file.take(limit + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(std::io::Error::new(
            std::io::ErrorKind::FileTooLarge,
            format!(
                "grew beyond the input budget's largest file ({}) while read",
                human_bytes(limit)
            ),
        ));
    }
    Ok(bytes)
}

/// [`read_input`] as UTF-8 text.
pub fn read_input_text(path: &std::path::Path) -> std::io::Result<String> {
    String::from_utf8(read_input(path)?)
        .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidData, e.utf8_error()))
}

/// Longest excerpt of an input that an error message quotes, in characters.
pub const EXCERPT_CHARS: usize = 40;

/// `text` quoted in an error: whole when short, else its first [`EXCERPT_CHARS`] characters,
/// `…` and the full length, so that no message echoes a huge token.
pub fn excerpt(text: &str) -> String {
    match text.char_indices().nth(EXCERPT_CHARS) {
        None => text.to_string(),
        Some((cut, _)) => format!("{}… ({} bytes)", &text[..cut], text.len()),
    }
}

/// The file a model's relative `uri` (already percent-decoded) names, resolved against the
/// model's folder `base`. Unless `allow_outside`, the result must stay inside `base`: absolute
/// paths, `..` steps above it and symbolic links out of it are refused, before anything is
/// read. The error quotes the URI (shortened) but nothing of the file it names.
pub fn resolve_inside(
    base: &std::path::Path,
    uri: &str,
    allow_outside: bool,
) -> Result<std::path::PathBuf, String> {
    use std::path::Component;
    let rel = std::path::Path::new(uri);
    if allow_outside {
        return Ok(base.join(rel));
    }
    let outside = || {
        format!(
            "\"{}\" names a file outside the model's folder; luz reads only files inside it \
             (--allow-outside-uris allows more)",
            excerpt(uri)
        )
    };
    let mut depth = 0usize;
    for c in rel.components() {
        match c {
            Component::Normal(_) => depth += 1,
            Component::CurDir => {}
            Component::ParentDir => depth = depth.checked_sub(1).ok_or_else(outside)?,
            Component::RootDir | Component::Prefix(_) => return Err(outside()),
        }
    }
    let full = base.join(rel);
    // Symbolic links: compare real paths when both exist (a missing file is reported later).
    if let (Ok(real_base), Ok(real)) = (
        std::fs::canonicalize(if base.as_os_str().is_empty() {
            std::path::Path::new(".")
        } else {
            base
        }),
        std::fs::canonicalize(&full),
    ) {
        if !real.starts_with(&real_base) {
            return Err(outside());
        }
    }
    Ok(full)
}

/// `text` quoted for an error message as `{:?}` would, but shortened like [`excerpt`]:
/// `"1e999999…" (104857600 bytes)`.
pub fn quoted(text: &str) -> String {
    match text.char_indices().nth(EXCERPT_CHARS) {
        None => format!("{text:?}"),
        Some((cut, _)) => format!("{:?}… ({} bytes)", &text[..cut], text.len()),
    }
}

#[cfg(test)]
#[path = "files_tests.rs"]
mod tests;
