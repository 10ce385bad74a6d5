//! The on-disk cache of precomputed data: file keys, the blob format, image readback and upload.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use crate::vk::cmd::{memory_barrier, transition, CommandPool, Transition};
use crate::vk::{Buffer, Context, Image, VkError};

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
    inputs
        .cache
        .as_ref()
        .map(|(dir, _)| dir.join(format!("lut-{}-{}-g{g}.bin", s.lut_size, s.lut_samples)))
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
    let buf = Buffer::new(
        ctx,
        "ibl cache readback",
        total,
        vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuToCpu,
    )?;
    let d = &ctx.device;
    let general = (vk::ImageLayout::GENERAL, COMPUTE_RW.0, COMPUTE_RW.1);
    let src = (
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        vk::PipelineStageFlags2::COPY,
        vk::AccessFlags2::TRANSFER_READ,
    );
    let (raw, range) = (image.raw, image.subresource_range());
    pool.one_shot(|cmd| {
        transition(
            d,
            cmd,
            &[Transition {
                image: raw,
                range,
                from: general,
                to: src,
            }],
        );
        // SAFETY: the image is in TRANSFER_SRC_OPTIMAL (transitioned above), `buf` is a live
        // TRANSFER_DST buffer large enough for every region, and the command buffer is recording.
        unsafe {
            d.cmd_copy_image_to_buffer(
                cmd,
                raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                buf.raw,
                &regions,
            )
        };
        transition(
            d,
            cmd,
            &[Transition {
                image: raw,
                range,
                from: src,
                to: general,
            }],
        );
        memory_barrier(
            d,
            cmd,
            (
                vk::PipelineStageFlags2::COPY,
                vk::AccessFlags2::TRANSFER_WRITE,
            ),
            (vk::PipelineStageFlags2::HOST, vk::AccessFlags2::HOST_READ),
        );
        Ok(())
    })?;
    Ok(buf.mapped()?[..total as usize].to_vec())
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

const BLOB_MAGIC: &[u8; 8] = b"LUZIBL01";

/// The cached images of one environment, if the file exists and every size matches.
pub(super) fn read_blob(path: &std::path::Path, images: &[&Image]) -> Option<Vec<Vec<u8>>> {
    let data = std::fs::read(path).ok()?;
    let rest = data.strip_prefix(BLOB_MAGIC.as_slice())?;
    let mut out = Vec::new();
    let mut pos = 0usize;
    for image in images {
        let expected: u64 = image_bytes(image).iter().map(|(_, n)| n).sum();
        let len = u64::from_le_bytes(rest.get(pos..pos + 8)?.try_into().ok()?);
        if len != expected {
            return None;
        }
        pos += 8;
        out.push(rest.get(pos..pos + len as usize)?.to_vec());
        pos += len as usize;
    }
    (pos == rest.len()).then_some(out)
}

pub(super) fn write_blob(path: &std::path::Path, blobs: &[Vec<u8>]) {
    let mut data = BLOB_MAGIC.to_vec();
    for b in blobs {
        data.extend_from_slice(&(b.len() as u64).to_le_bytes());
        data.extend_from_slice(b);
    }
    write_file_atomically(path, &data);
}

/// Best effort: a cache that cannot be written is only slower next time.
pub(super) fn write_file_atomically(path: &std::path::Path, bytes: &[u8]) {
    if let Some(dir) = path.parent() {
        let _ = std::fs::create_dir_all(dir);
    }
    let tmp = path.with_extension(format!("tmp{}", std::process::id()));
    if std::fs::write(&tmp, bytes).is_ok() && std::fs::rename(&tmp, path).is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
}

/// The directory luz keeps precomputed IBL data in: `$LUZ_CACHE_DIR`, else
/// `$XDG_CACHE_HOME/luz`, else `$HOME/.cache/luz`.
pub fn default_cache_dir() -> Option<std::path::PathBuf> {
    if let Some(d) = std::env::var_os("LUZ_CACHE_DIR") {
        return Some(d.into());
    }
    if let Some(d) = std::env::var_os("XDG_CACHE_HOME") {
        return Some(std::path::PathBuf::from(d).join("luz"));
    }
    std::env::var_os("HOME").map(|h| std::path::PathBuf::from(h).join(".cache/luz"))
}
