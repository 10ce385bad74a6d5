//! The on-disk cache of precomputed data: file keys, the blob format, image readback and upload.

use std::sync::Arc;

use ash::vk;

use crate::vk::cmd::{read_to_host, CommandPool};
use crate::vk::{Context, Image, VkError};

use super::bake::COMPUTE_RW;
use super::{IblInputs, IblSettings};

/// The file holding stages 1–3 of this environment at these settings (None without a cache).
pub(super) fn env_file(inputs: &IblInputs<'_>, s: &IblSettings) -> Option<std::path::PathBuf> {
    inputs
        .cache
        .as_ref()
        .map(|(dir, key)| dir.join(format!("{key}-{}.ibl", s.describe().replace(' ', "_"))))
}

/// The file holding the LUT layer of geometry selector `g` (shared by every environment).
pub(super) fn lut_file(
    inputs: &IblInputs<'_>,
    s: &IblSettings,
    g: i32,
) -> Option<std::path::PathBuf> {
    inputs.cache.as_ref().map(|(dir, _)| {
        dir.join(format!(
            "lut-moments-{}-{}-g{g}.bin",
            s.lut_size, s.lut_samples
        ))
    })
}

/// Bytes of every mip level of `image` (all layers per level, level-major), RGBA16F or RGBA32F.
fn image_bytes(image: &Image) -> Vec<(u32, u64)> {
    let d = image.desc;
    let texel = match d.format {
        vk::Format::R16G16B16A16_SFLOAT => 8u64,
        _ => 16u64,
    };
    (0..d.mip_levels)
        .map(|m| {
            let w = (d.width >> m).max(1) as u64;
            let h = (d.height >> m).max(1) as u64;
            (m, w * h * d.layers as u64 * texel)
        })
        .collect()
}

fn copy_regions(image: &Image) -> (Vec<vk::BufferImageCopy>, u64) {
    let d = image.desc;
    let mut offset = 0u64;
    let regions = image_bytes(image)
        .into_iter()
        .map(|(m, len)| {
            let r = vk::BufferImageCopy {
                buffer_offset: offset,
                image_subresource: vk::ImageSubresourceLayers {
                    aspect_mask: vk::ImageAspectFlags::COLOR,
                    mip_level: m,
                    base_array_layer: 0,
                    layer_count: d.layers,
                },
                image_extent: vk::Extent3D {
                    width: (d.width >> m).max(1),
                    height: (d.height >> m).max(1),
                    depth: 1,
                },
                ..Default::default()
            };
            offset += len;
            r
        })
        .collect();
    (regions, offset)
}

/// Reads every level and layer of an image kept in GENERAL layout.
pub(super) fn read_image(
    ctx: &Arc<Context>,
    pool: &CommandPool,
    image: &Image,
) -> Result<Vec<u8>, VkError> {
    let (regions, total) = copy_regions(image);
    let general = (vk::ImageLayout::GENERAL, COMPUTE_RW.0, COMPUTE_RW.1);
    read_to_host(
        ctx,
        pool,
        image,
        general,
        (&regions, total),
        "ibl cache readback",
    )
}

/// Fills every level and layer of a fresh image from `bytes` and leaves it in GENERAL layout.
pub(super) fn write_image(
    ctx: &Arc<Context>,
    pool: &CommandPool,
    image: &Image,
    bytes: &[u8],
) -> Result<(), VkError> {
    let (regions, total) = copy_regions(image);
    upload_regions(
        ctx,
        pool,
        image,
        bytes,
        total,
        &regions,
        vk::ImageLayout::UNDEFINED,
        image.subresource_range(),
    )
}

/// Fills one layer of the LUT (kept in GENERAL layout).
pub(super) fn write_lut_layer(
    ctx: &Arc<Context>,
    pool: &CommandPool,
    lut: &Image,
    layer: u32,
    bytes: &[u8],
) -> Result<(), VkError> {
    let d = lut.desc;
    let region = vk::BufferImageCopy {
        image_subresource: vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: layer,
            layer_count: 1,
        },
        image_extent: vk::Extent3D {
            width: d.width,
            height: d.height,
            depth: 1,
        },
        ..Default::default()
    };
    let range = vk::ImageSubresourceRange {
        base_array_layer: layer,
        layer_count: 1,
        ..lut.subresource_range()
    };
    upload_regions(
        ctx,
        pool,
        lut,
        bytes,
        bytes.len() as u64,
        &[region],
        vk::ImageLayout::GENERAL,
        range,
    )
}

#[allow(clippy::too_many_arguments)]
fn upload_regions(
    ctx: &Arc<Context>,
    pool: &CommandPool,
    image: &Image,
    bytes: &[u8],
    total: u64,
    regions: &[vk::BufferImageCopy],
    from_layout: vk::ImageLayout,
    range: vk::ImageSubresourceRange,
) -> Result<(), VkError> {
    if bytes.len() as u64 != total {
        return Err(VkError::Setup(format!(
            "cached IBL data has {} bytes, expected {total}",
            bytes.len()
        )));
    }
    let from = if from_layout == vk::ImageLayout::UNDEFINED {
        (
            vk::ImageLayout::UNDEFINED,
            vk::PipelineStageFlags2::TOP_OF_PIPE,
            vk::AccessFlags2::NONE,
        )
    } else {
        (from_layout, COMPUTE_RW.0, COMPUTE_RW.1)
    };
    // GENERAL, visible to the compute kernels and to the forward pass's shaders.
    let to = (
        vk::ImageLayout::GENERAL,
        COMPUTE_RW.0
            | vk::PipelineStageFlags2::FRAGMENT_SHADER
            | vk::PipelineStageFlags2::VERTEX_SHADER,
        COMPUTE_RW.1,
    );
    crate::vk::image::upload(ctx, pool, image, bytes, regions, range, from, to)
}

/// Cache files: this magic, the CRC-32 of everything after the header (little-endian u32), four
/// reserved bytes, then each blob as its length (u64, little-endian) and its bytes. Version 02 added
/// the checksum: a file whose bytes changed inside an intact header (a flipped bit on disk, a
/// partial copy) used to load as it was and change the image.
const BLOB_MAGIC: &[u8; 8] = b"LUZIBL02";

/// What reading a cache file found.
#[derive(Debug, PartialEq)]
pub(super) enum Cached {
    /// The blobs, checksum verified.
    Hit(Vec<Vec<u8>>),
    /// No file, another format version or other sizes (other settings): compute it quietly.
    Miss,
    /// The file is damaged (empty, zeroed, truncated, not matching its checksum): compute it
    /// again and replace it, with a warning.
    Corrupt,
    /// The entry cannot be read (why): a folder in its place, no permission.
    Unreadable(String),
}

/// What a cache entry that cannot be used costs, in its warning.
const COST: &str = "the IBL precompute (1-4 s) runs again on every run until it is removed";

impl Cached {
    /// The blobs on a hit; a damaged or unreadable entry is logged (one warning naming it and
    /// what it costs) and treated as a miss.
    pub(super) fn hit(self, path: &std::path::Path) -> Option<Vec<Vec<u8>>> {
        match self {
            Cached::Hit(blobs) => {
                crate::files::cache_dir::touch(path);
                Some(blobs)
            }
            Cached::Miss => None,
            Cached::Corrupt => {
                log::warn!(
                    "{}: cached IBL data is damaged (empty, zeroed or not matching its \
                     checksum); computing it again and replacing the file",
                    path.display()
                );
                None
            }
            Cached::Unreadable(why) => {
                crate::files::cache_dir::warn_once(
                    &format!("folder:{}", path.display()),
                    format!(
                        "{}: cached IBL data cannot be read ({why}); {COST}",
                        path.display()
                    ),
                    &mut |w| log::warn!("{w}"),
                );
                None
            }
        }
    }
}

/// Reads a cache file whose blobs must have the sizes `expected` (bytes each).
pub(super) fn read_blobs(path: &std::path::Path, expected: &[u64]) -> Cached {
    if path.is_dir() {
        return Cached::Unreadable("a folder is in its place".into());
    }
    match std::fs::read(path) {
        Ok(data) => parse_blobs(&data, expected),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Cached::Miss,
        Err(e) => Cached::Unreadable(e.to_string()),
    }
}

fn parse_blobs(data: &[u8], expected: &[u64]) -> Cached {
    use crate::files::cache_dir::{unframe, Framed};
    let body = match unframe(data, BLOB_MAGIC) {
        Framed::Body(body) => body,
        Framed::OtherVersion => return Cached::Miss,
        Framed::Damaged => return Cached::Corrupt,
    };
    // Other sizes under an intact checksum are other settings, not damage.
    let mut out = Vec::with_capacity(expected.len());
    let mut pos = 0usize;
    for &want in expected {
        let len = body
            .get(pos..pos + 8)
            .map(|b| u64::from_le_bytes(b.try_into().expect("8 bytes")));
        match body.get(pos + 8..).and_then(|b| b.get(..want as usize)) {
            Some(bytes) if len == Some(want) => out.push(bytes.to_vec()),
            _ => return Cached::Miss,
        }
        pos += 8 + want as usize;
    }
    if pos == body.len() {
        Cached::Hit(out)
    } else {
        Cached::Miss
    }
}

/// The bytes of a cache file holding `blobs`.
fn blob_file(blobs: &[&[u8]]) -> Vec<u8> {
    let mut body = Vec::with_capacity(blobs.iter().map(|b| b.len() + 8).sum());
    for b in blobs {
        body.extend_from_slice(&(b.len() as u64).to_le_bytes());
        body.extend_from_slice(b);
    }
    crate::files::cache_dir::frame(BLOB_MAGIC, &body)
}

/// The cached images of one environment, if the file exists, its checksum holds and every size
/// matches.
pub(super) fn read_blob(path: &std::path::Path, images: &[&Image]) -> Option<Vec<Vec<u8>>> {
    let expected: Vec<u64> = images
        .iter()
        .map(|image| image_bytes(image).iter().map(|(_, n)| n).sum())
        .collect();
    read_blobs(path, &expected).hit(path)
}

/// The blobs of a whole cache file's bytes `data` holding `images`, if its checksum holds and
/// every size matches.
pub(super) fn blobs_of(data: &[u8], images: &[&Image]) -> Option<Vec<Vec<u8>>> {
    let expected: Vec<u64> = images
        .iter()
        .map(|image| image_bytes(image).iter().map(|(_, n)| n).sum())
        .collect();
    match parse_blobs(data, &expected) {
        Cached::Hit(blobs) => Some(blobs),
        _ => None,
    }
}

/// Writes a cache file holding `blobs` (atomically: a temporary file and a rename). A write that
/// fails gives one warning per folder and problem (a folder in the file's place, one per entry),
/// saying what it costs.
pub(super) fn write_blob(path: &std::path::Path, blobs: &[&[u8]]) {
    write_file(path, &blob_file(blobs));
}

/// Writes the bytes of a whole cache file, as [`write_blob`].
pub(super) fn write_file(path: &std::path::Path, data: &[u8]) {
    match crate::files::try_write_file_atomically(path, data) {
        Ok(()) => crate::files::cache_dir::written(path, data.len() as u64),
        Err(e) => {
            let (key, at) = if path.is_dir() {
                (format!("folder:{}", path.display()), path)
            } else {
                let folder = path.parent().unwrap_or(path);
                (format!("write:{}:{:?}", folder.display(), e.kind()), folder)
            };
            crate::files::cache_dir::warn_once(
                &key,
                format!(
                    "{}: cannot write IBL cache files ({e}); {COST}",
                    at.display()
                ),
                &mut |w| log::warn!("{w}"),
            );
        }
    }
}

/// The directory luz keeps precomputed IBL data and LOD chains in: `$LUZ_CACHE_DIR`, else
/// `$XDG_CACHE_HOME/luz`, else `$HOME/.cache/luz`; checked and tidied once per process
/// (`files::cache_dir::open`: stale temporary files removed, the size cap kept). `None`, with one
/// warning saying what it costs, when it cannot be used (a file, a read-only folder).
pub fn default_cache_dir() -> Option<std::path::PathBuf> {
    static DIR: std::sync::OnceLock<Option<std::path::PathBuf>> = std::sync::OnceLock::new();
    DIR.get_or_init(|| {
        let dir = if let Some(d) = std::env::var_os("LUZ_CACHE_DIR") {
            std::path::PathBuf::from(d)
        } else if let Some(d) = std::env::var_os("XDG_CACHE_HOME") {
            std::path::PathBuf::from(d).join("luz")
        } else {
            std::path::PathBuf::from(std::env::var_os("HOME")?).join(".cache/luz")
        };
        match crate::files::cache_dir::open(&dir) {
            Ok(tidied) => {
                if tidied.stale_removed + tidied.evicted > 0 {
                    log::info!(
                        "{}: removed {} stale temporary file(s) and {} cache file(s) beyond the \
                         {} MiB cap",
                        dir.display(),
                        tidied.stale_removed,
                        tidied.evicted,
                        crate::files::cache_dir::max_bytes() >> 20
                    );
                }
                Some(dir)
            }
            Err(warning) => {
                log::warn!("{warning}");
                None
            }
        }
    })
    .clone()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bytes before a file's body: magic, checksum, reserved.
    const HEADER: usize = 16;

    /// A file round-trips; a byte flipped anywhere after the magic is caught by the checksum
    /// (header, lengths or contents); other sizes or another version are a quiet miss.
    #[test]
    fn checksummed_blobs() {
        let a: Vec<u8> = (0..1000u32).map(|i| (i * 7 % 251) as u8).collect();
        let b = vec![3u8; 64];
        let file = blob_file(&[&a, &b]);
        assert_eq!(
            parse_blobs(&file, &[1000, 64]),
            Cached::Hit(vec![a.clone(), b.clone()])
        );
        for at in [8, 11, HEADER, HEADER + 3, HEADER + 500, file.len() - 1] {
            for bit in [0, 7] {
                let mut bad = file.clone();
                bad[at] ^= 1 << bit;
                let got = parse_blobs(&bad, &[1000, 64]);
                // The four reserved bytes are not covered.
                if (12..HEADER).contains(&at) {
                    continue;
                }
                assert_eq!(got, Cached::Corrupt, "byte {at} bit {bit}");
            }
        }
        assert_eq!(parse_blobs(&file, &[1000, 65]), Cached::Miss);
        assert_eq!(parse_blobs(&file, &[1000]), Cached::Miss);
        assert_eq!(
            parse_blobs(&file[..file.len() - 1], &[1000, 64]),
            Cached::Corrupt
        );
        let mut old = file.clone();
        old[..8].copy_from_slice(b"LUZIBL01");
        assert_eq!(parse_blobs(&old, &[1000, 64]), Cached::Miss);
        // Truncated in its header, empty, zeroed: damaged (one warning, computed again).
        assert_eq!(parse_blobs(b"LUZIBL02", &[1]), Cached::Corrupt);
        assert_eq!(parse_blobs(&[], &[1]), Cached::Corrupt);
        assert_eq!(parse_blobs(&[0; 4096], &[1]), Cached::Corrupt);
    }
}
