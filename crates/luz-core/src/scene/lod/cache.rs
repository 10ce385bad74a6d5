//! LOD chains on disk: `<cache dir>/lod/<key>.lod`, one file per mesh content.
//!
//! Format: the magic `LUZLOD03`, the CRC-32 of everything after the 16-byte header
//! (little-endian u32), four reserved bytes, then the body: the key (u64), the mesh's vertex and
//! index counts (u32 each), the number of simplified levels (u32), the number of moved vertices
//! (u32), per level its index count (u32) and error (f32 bits), then every simplified level's
//! indices (u32), then per moved vertex its origin (u32), position (3 f32), normal (3 f32) and,
//! when the mesh has UVs, UV (2 f32). Level 0 (the mesh's own indices) is not stored. All
//! little-endian. A mesh whose simplification failed is stored too, so that the next run does not
//! pay for it again: its level count is `u32::MAX`, followed by the reason's length in bytes (u32)
//! and the reason (UTF-8, zero-padded to 4 bytes).
//!
//! On load the checksum is verified first: a file whose bytes changed (a flipped bit, a partial
//! copy, an empty or zeroed file) is [`Read::Corrupt`], rebuilt with one warning and replaced. A
//! file of another version (`LUZLOD` and other digits) or another mesh (the key or the counts
//! differ) is a quiet miss; indices beyond the vertices, origins beyond the mesh's, a non-finite
//! error or vertex value count as corrupt even under a matching checksum. An entry that cannot be
//! read (a folder in its place, no permission) is [`Read::Unreadable`]: one warning, as it costs a
//! simplification on every run.

use std::path::{Path, PathBuf};

use super::{LodChain, LodLevel, LOD_VERSION};
use crate::files::cache_dir::Framed;
use crate::files::Fnv1a;
use crate::scene::Mesh;
use glam::{Vec2, Vec3};

const MAGIC: &[u8; 8] = b"LUZLOD03";
/// Level count of a file that records a failed simplification.
const FAILED: u32 = u32::MAX;

/// The cache key of `mesh`: FNV-1a 64 over [`LOD_VERSION`], the simplifier's settings and the
/// mesh's positions, normals, UVs and indices (its contents, not its file: an edited model gets a
/// new key, the same model under another name shares one).
pub fn key(mesh: &Mesh) -> u64 {
    let mut h = Fnv1a::new();
    h.field(b"luz-lod");
    h.field(&LOD_VERSION.to_le_bytes());
    for x in [
        super::LEVEL_RATIO,
        super::NORMAL_WEIGHT,
        super::UV_WEIGHT,
        super::MAX_LEVELS as f32,
        super::MIN_TRIANGLES as f32,
    ] {
        h.field(&x.to_bits().to_le_bytes());
    }
    h.field(bytemuck::cast_slice(&mesh.positions));
    h.field(bytemuck::cast_slice(&mesh.normals));
    h.field(bytemuck::cast_slice(&mesh.uvs));
    h.field(bytemuck::cast_slice(&mesh.indices));
    h.finish()
}

/// The file of `key` under `dir`.
pub fn path(dir: &Path, key: u64) -> PathBuf {
    dir.join("lod").join(format!("{key:016x}.lod"))
}

/// What reading a cache file found.
#[derive(Debug, PartialEq)]
pub enum Read {
    Hit(LodChain),
    /// An earlier run could not simplify this mesh, for this reason.
    Failed(String),
    /// No file, or one for another version or mesh.
    Miss,
    /// The file at this path does not match its checksum or holds impossible data.
    Corrupt(PathBuf),
    /// The entry at this path cannot be read (why): a folder, no permission.
    Unreadable(PathBuf, String),
}

/// Reads the chain of `mesh` (key `key`) from `dir`; a hit marks the file as just used (the
/// cache's eviction removes the least recently used files first).
pub fn read(dir: &Path, key: u64, mesh: &Mesh) -> Read {
    let path = path(dir, key);
    if path.is_dir() {
        return Read::Unreadable(path, "a folder is in its place".into());
    }
    let data = match std::fs::read(&path) {
        Ok(data) => data,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Read::Miss,
        Err(e) => return Read::Unreadable(path, e.to_string()),
    };
    let read = match parse(&data, key, mesh) {
        Parsed::Hit(chain) => Read::Hit(chain),
        Parsed::Failed(reason) => Read::Failed(reason),
        Parsed::Miss => Read::Miss,
        Parsed::Corrupt => Read::Corrupt(path.clone()),
    };
    if matches!(read, Read::Hit(_) | Read::Failed(_)) {
        crate::files::cache_dir::touch(&path);
    }
    read
}

enum Parsed {
    Hit(LodChain),
    Failed(String),
    Miss,
    Corrupt,
}

fn parse(data: &[u8], key: u64, mesh: &Mesh) -> Parsed {
    let body = match crate::files::cache_dir::unframe(data, MAGIC) {
        Framed::Body(body) => body,
        Framed::OtherVersion => return Parsed::Miss,
        Framed::Damaged => return Parsed::Corrupt,
    };
    let mut words = body
        .chunks_exact(4)
        .map(|w| u32::from_le_bytes(w.try_into().expect("4 bytes")));
    if !body.len().is_multiple_of(4) || body.len() < 24 {
        return Parsed::Corrupt;
    }
    let (lo, hi) = (words.next(), words.next());
    let file_key = u64::from(lo.unwrap_or(0)) | (u64::from(hi.unwrap_or(0)) << 32);
    let (vertices, indices) = (words.next(), words.next());
    if file_key != key
        || vertices != Some(mesh.positions.len() as u32)
        || indices != Some(mesh.indices.len() as u32)
    {
        return Parsed::Miss;
    }
    let count = words.next().unwrap_or(0);
    let moved = words.next().unwrap_or(0) as usize;
    if count == FAILED {
        let len = moved;
        let text = body.get(24..24 + len).map(|b| String::from_utf8_lossy(b));
        return match text {
            Some(t) if body.len() == 24 + len.next_multiple_of(4) => Parsed::Failed(t.into()),
            _ => Parsed::Corrupt,
        };
    }
    let count = count as usize;
    // Each moved vertex is used by some level's triangle: no more of them than indices.
    let uv = mesh.uvs.len() == mesh.positions.len();
    let vertex_words = if uv { 9 } else { 7 };
    if count > super::MAX_LEVELS || body.len() < 24 + count * 8 {
        return Parsed::Corrupt;
    }
    // The file holds the simplified levels; level 0 is the mesh's triangles in cache order.
    let mut chain = LodChain::full(mesh);
    chain.cache_order(0, mesh.positions.len());
    let mut total = 0usize;
    let mut sizes = Vec::with_capacity(count);
    for _ in 0..count {
        let (n, e) = (
            words.next().unwrap_or(0),
            f32::from_bits(words.next().unwrap_or(0)),
        );
        if !n.is_multiple_of(3) || n == 0 || !e.is_finite() || e < 0.0 {
            return Parsed::Corrupt;
        }
        total += n as usize;
        sizes.push((n, e));
    }
    if moved > total || body.len() != 24 + count * 8 + total * 4 + moved * vertex_words * 4 {
        return Parsed::Corrupt;
    }
    let n = mesh.positions.len();
    let all = (n + moved) as u32;
    for (count, error) in sizes {
        let first = chain.indices.len() as u32;
        for _ in 0..count {
            let i = words.next().unwrap_or(u32::MAX);
            if i >= all {
                return Parsed::Corrupt;
            }
            chain.indices.push(i);
        }
        chain.levels.push(LodLevel {
            first_index: first,
            index_count: count,
            error,
        });
    }
    let mut float = || f32::from_bits(words.next().unwrap_or(0));
    let m = &mut chain.moved;
    for _ in 0..moved {
        let origin = float().to_bits();
        let p = Vec3::new(float(), float(), float());
        let normal = Vec3::new(float(), float(), float());
        if origin as usize >= n || !p.is_finite() || !normal.is_finite() {
            return Parsed::Corrupt;
        }
        m.origin.push(origin);
        m.positions.push(p);
        m.normals.push(normal);
        if uv {
            let t = Vec2::new(float(), float());
            if !t.is_finite() {
                return Parsed::Corrupt;
            }
            m.uvs.push(t);
        }
    }
    Parsed::Hit(chain)
}

/// The bytes of the file recording that `mesh` (key `key`) could not be simplified (`reason`).
fn failure_file(key: u64, mesh: &Mesh, reason: &str) -> Vec<u8> {
    let mut body: Vec<u8> = [
        key as u32,
        (key >> 32) as u32,
        mesh.positions.len() as u32,
        mesh.indices.len() as u32,
        FAILED,
        reason.len() as u32,
    ]
    .iter()
    .flat_map(|w| w.to_le_bytes())
    .collect();
    body.extend_from_slice(reason.as_bytes());
    body.resize(body.len().next_multiple_of(4), 0);
    crate::files::cache_dir::frame(MAGIC, &body)
}

/// The bytes of the file holding `chain` (of `mesh`, key `key`).
fn file(key: u64, mesh: &Mesh, chain: &LodChain) -> Vec<u8> {
    let simplified = &chain.levels[1..];
    let mut body: Vec<u32> = vec![
        key as u32,
        (key >> 32) as u32,
        mesh.positions.len() as u32,
        mesh.indices.len() as u32,
        simplified.len() as u32,
        chain.moved.len() as u32,
    ];
    for l in simplified {
        body.extend_from_slice(&[l.index_count, l.error.to_bits()]);
    }
    for i in 1..chain.levels.len() {
        body.extend_from_slice(chain.level_indices(i));
    }
    let m = &chain.moved;
    for k in 0..m.len() {
        body.push(m.origin[k]);
        let uv = m.uvs.get(k).map(|t| t.to_array());
        let floats = m.positions[k].to_array().into_iter();
        let floats = floats
            .chain(m.normals[k].to_array())
            .chain(uv.into_iter().flatten());
        body.extend(floats.map(f32::to_bits));
    }
    let body: Vec<u8> = body.iter().flat_map(|w| w.to_le_bytes()).collect();
    crate::files::cache_dir::frame(MAGIC, &body)
}

/// Writes the chain of `mesh` under `dir`, or the reason it could not be simplified (atomically:
/// through a temporary file and a rename). A write that fails is only slower next time:
/// `Err(warning)` (saying so) the first time this process meets that problem, else `Ok`.
pub fn write(
    dir: &Path,
    key: u64,
    mesh: &Mesh,
    chain: Result<&LodChain, &String>,
) -> Result<(), String> {
    let path = path(dir, key);
    let data = match chain {
        Ok(chain) => file(key, mesh, chain),
        Err(reason) => failure_file(key, mesh, reason),
    };
    match crate::files::try_write_file_atomically(&path, &data) {
        Ok(()) => {
            crate::files::cache_dir::written(&path, data.len() as u64);
            Ok(())
        }
        Err(e) => {
            let (key, at) = if path.is_dir() {
                (format!("folder:{}", path.display()), path.clone())
            } else {
                let folder = path.parent().unwrap_or(dir);
                (
                    format!("write:{}:{:?}", folder.display(), e.kind()),
                    folder.into(),
                )
            };
            let mut warning = None;
            crate::files::cache_dir::warn_once(
                &key,
                format!(
                    "{}: cannot write LOD cache files ({e}); meshes are simplified again on \
                     every run",
                    at.display()
                ),
                &mut |w| warning = Some(w),
            );
            warning.map_or(Ok(()), Err)
        }
    }
}
