//! Texture images on the CPU: decoding, colour spaces, downscaling and mipmaps, ready for upload.
//!
//! * **Files.** PNG (8 or 16-bit; grey, grey + alpha, RGB, RGBA), OpenEXR and Radiance HDR. The
//!   declared size is checked against [`crate::imageio`]'s limits before any pixel memory is
//!   allocated.
//! * **Colour spaces** (MODELS.md §9). Colour maps (base colour, specular colour, emissive) are
//!   sRGB-encoded: 8-bit ones become [`TexFormat::Rgba8Srgb`] and the GPU decodes them when
//!   sampling; 16-bit ones are decoded here and stored as linear half floats. Data maps
//!   (metallic, roughness, occlusion, normal) are linear. EXR and HDR files are linear whatever
//!   the slot. Alpha is always linear.
//! * **Formats.** 8-bit PNG → `Rgba8Srgb` / `Rgba8Unorm` (level 0 holds the file's exact
//!   bytes); 16-bit PNG, EXR and HDR → [`TexFormat::Rgba16F`] (half floats filter linearly on
//!   every Vulkan device, 32-bit floats need an optional format feature; values beyond the half
//!   range are clamped to ±65504 and NaN becomes 0, with a warning).
//! * **Too large for the device.** An image whose width or height exceeds `max_dimension`
//!   (`maxImageDimension2D`) is downscaled with an area (box) filter to fit, keeping its aspect
//!   ratio, and a warning names the file and both sizes. Rendering with a smaller texture is
//!   better than refusing the scene, and the warning says it happened.
//! * **Mipmaps.** The full chain down to 1×1 (level k is max(1, ⌊w/2^k⌋) × max(1, ⌊h/2^k⌋), as
//!   Vulkan expects), each level an area-weighted box filter of the one above computed in
//!   linear light and in float: sRGB texels are decoded, averaged and re-encoded (a black and
//!   white checker gives 0.5 linear, code 188, not 128). Odd sizes use exact area weights (a
//!   5-texel row becomes 2 texels of weights 0.4, 0.4, 0.2). Normal-map levels are
//!   renormalised: texels are decoded to vectors (2c − 1), averaged, normalised and re-encoded.
//! * **Channels.** A single-value map with a chosen channel (`TextureRef::channel`) has that
//!   channel copied to R, G and B (alpha 1), so a shader reads `.r` whatever the file's layout.
//!
//! Also: procedural images for tests ([`checker`], [`noise_normal_map`]).

use std::io::{self, BufReader};
use std::path::{Path, PathBuf};

use glam::Vec3;
use image::{DynamicImage, ImageFormat};
use rayon::prelude::*;

use crate::color::{srgb_decode, srgb_decode_table};
use crate::imageio::{decode_checked, open_image_file, DecodeProblem, FileError, MAX_DIMENSION};
use crate::scene::{TextureRef, TextureSlot};

/// How a texture's texels are encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ColorSpace {
    /// sRGB-encoded colour (base colour, specular colour, emissive); mips averaged in linear.
    Srgb,
    /// Linear data (metallic, roughness, occlusion, packed ORM).
    Linear,
    /// Linear, a tangent-space normal encoded as (n + 1) / 2; mip levels are renormalised.
    NormalMap,
}

impl ColorSpace {
    /// The encoding of the maps in `slot`.
    pub fn for_slot(slot: TextureSlot) -> ColorSpace {
        if slot == TextureSlot::Normal {
            ColorSpace::NormalMap
        } else if slot.is_srgb() {
            ColorSpace::Srgb
        } else {
            ColorSpace::Linear
        }
    }
}

/// Texel formats of [`TextureData`] (the Vulkan format names without the `R8G8B8A8_` noise).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TexFormat {
    /// `R8G8B8A8_SRGB`: 4 bytes per texel.
    Rgba8Srgb,
    /// `R8G8B8A8_UNORM`: 4 bytes per texel.
    Rgba8Unorm,
    /// `R16G16B16A16_SFLOAT`: 8 bytes per texel, little-endian IEEE half floats, linear.
    Rgba16F,
    /// `R32G32B32A32_SFLOAT`: 16 bytes per texel, little-endian, linear. Never produced by
    /// [`load_texture`] (linear filtering of 32-bit floats is optional in Vulkan); for callers
    /// that build textures themselves.
    Rgba32F,
}

impl TexFormat {
    /// Bytes per texel.
    pub fn bytes_per_texel(self) -> usize {
        match self {
            TexFormat::Rgba8Srgb | TexFormat::Rgba8Unorm => 4,
            TexFormat::Rgba16F => 8,
            TexFormat::Rgba32F => 16,
        }
    }
}

/// A decoded texture with its mip chain, ready for upload.
#[derive(Debug, Clone, PartialEq)]
pub struct TextureData {
    /// Size of level 0.
    pub width: u32,
    pub height: u32,
    pub format: TexFormat,
    /// Level 0 first; level k is [`mip_extent`]`(width, height, k)`, rows top to bottom, tightly
    /// packed. One level when the sampler has `mipmaps: false`, otherwise the full chain.
    pub mips: Vec<Vec<u8>>,
}

impl TextureData {
    /// Size of mip level `level`.
    pub fn level_extent(&self, level: usize) -> (u32, u32) {
        mip_extent(self.width, self.height, level as u32)
    }

    /// Total bytes of all levels.
    pub fn byte_size(&self) -> usize {
        self.mips.iter().map(Vec::len).sum()
    }

    /// Texel (x, y) of `level` as linear RGBA floats (sRGB decoded, halves widened); for tests
    /// and tools, not for speed. `None` outside the level.
    pub fn texel(&self, level: usize, x: u32, y: u32) -> Option<[f32; 4]> {
        let (w, h) = self.level_extent(level);
        let data = self.mips.get(level)?;
        if x >= w || y >= h {
            return None;
        }
        let bpt = self.format.bytes_per_texel();
        let i = (y as usize * w as usize + x as usize) * bpt;
        let t = data.get(i..i + bpt)?;
        Some(match self.format {
            TexFormat::Rgba8Srgb => {
                let lut = srgb_decode_table();
                [
                    lut[t[0] as usize],
                    lut[t[1] as usize],
                    lut[t[2] as usize],
                    t[3] as f32 / 255.0,
                ]
            }
            TexFormat::Rgba8Unorm => std::array::from_fn(|c| t[c] as f32 / 255.0),
            TexFormat::Rgba16F => {
                std::array::from_fn(|c| f16_to_f32(u16::from_le_bytes([t[2 * c], t[2 * c + 1]])))
            }
            TexFormat::Rgba32F => std::array::from_fn(|c| {
                f32::from_le_bytes([t[4 * c], t[4 * c + 1], t[4 * c + 2], t[4 * c + 3]])
            }),
        })
    }
}

/// Number of levels of a full mip chain: ⌊log2(max(width, height))⌋ + 1.
pub fn mip_count(width: u32, height: u32) -> u32 {
    32 - width.max(height).max(1).leading_zeros()
}

/// Size of mip level `level`: max(1, ⌊w / 2^level⌋) × max(1, ⌊h / 2^level⌋).
pub fn mip_extent(width: u32, height: u32, level: u32) -> (u32, u32) {
    let s = |v: u32| v.checked_shr(level).unwrap_or(0).max(1);
    (s(width), s(height))
}

/// Why a texture could not be loaded. Every message names the file.
#[derive(Debug, thiserror::Error)]
pub enum TextureError {
    #[error(transparent)]
    File(#[from] FileError),
    #[error("{}: unsupported texture file extension (supported: .png, .jpg, .exr, .hdr)", .path.display())]
    UnsupportedExtension { path: PathBuf },
    #[error("{}: not a valid {format} file: {reason}", .path.display())]
    Corrupt {
        path: PathBuf,
        format: &'static str,
        reason: String,
    },
    #[error("{}: unsupported kind of {format} file: {reason}", .path.display())]
    Unsupported {
        path: PathBuf,
        format: &'static str,
        reason: String,
    },
    #[error(
        "{}: image too large ({declared}); textures are limited to {MAX_DIMENSION} pixels per \
         side and {} Mpix in total (1 Mpix = 1024 × 1024 pixels; raise it with \
         --max-texture-mpix)",
        .path.display(),
        crate::files::InputBudget::current().max_texture_pixels / crate::files::MPIX
    )]
    TooLarge { path: PathBuf, declared: String },
}

impl TextureError {
    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            TextureError::File(e) => e.path(),
            TextureError::UnsupportedExtension { path }
            | TextureError::Corrupt { path, .. }
            | TextureError::Unsupported { path, .. }
            | TextureError::TooLarge { path, .. } => path,
        }
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum FileKind {
    Png,
    Exr,
    Hdr,
    Jpeg,
}

impl FileKind {
    fn from_path(path: &Path) -> Option<FileKind> {
        match crate::files::lowercase_extension(path)?.as_str() {
            "png" => Some(FileKind::Png),
            "exr" => Some(FileKind::Exr),
            "hdr" => Some(FileKind::Hdr),
            "jpg" | "jpeg" => Some(FileKind::Jpeg),
            _ => None,
        }
    }

    fn name(self) -> &'static str {
        match self {
            FileKind::Png => "PNG",
            FileKind::Exr => "OpenEXR",
            FileKind::Hdr => "Radiance HDR",
            FileKind::Jpeg => "JPEG",
        }
    }

    fn image_format(self) -> ImageFormat {
        match self {
            FileKind::Png => ImageFormat::Png,
            FileKind::Exr => ImageFormat::OpenExr,
            FileKind::Hdr => ImageFormat::Hdr,
            FileKind::Jpeg => ImageFormat::Jpeg,
        }
    }
}

/// Loads the texture `r` for a map encoded as `space`: decode, pick the channel, downscale to
/// fit `max_dimension` per side (with a warning through `on_warning`), build the mip chain
/// (unless `r.sampler.mipmaps` is false). See the module documentation for every rule.
pub fn load_texture(
    r: &TextureRef,
    space: ColorSpace,
    max_dimension: u32,
    on_warning: &mut dyn FnMut(String),
) -> Result<TextureData, TextureError> {
    let img = match &r.embedded {
        Some(bytes) => decode_embedded(bytes, &r.path, &texture_limits())?,
        None => decode_file(&r.path)?,
    };
    texture_from_image(
        &img,
        &r.path,
        space,
        r.channel,
        r.sampler.mipmaps,
        max_dimension,
        on_warning,
    )
}

/// The decoding limits of a texture: [`crate::imageio`]'s per side, and the input budget's
/// pixels ([`crate::files::InputBudget::max_texture_pixels`], 16 bytes a pixel at most), checked
/// from the header before any pixel memory is allocated.
pub fn texture_limits() -> crate::imageio::SizeLimits {
    let pixels = crate::files::InputBudget::current().max_texture_pixels;
    crate::imageio::SizeLimits {
        max_dimension: MAX_DIMENSION,
        max_pixels: pixels,
        max_bytes: pixels.saturating_mul(16),
    }
}

/// Decodes an image file (PNG, EXR or HDR by extension) with [`texture_limits`] (a regular file
/// within the input budget).
pub fn decode_file(path: &Path) -> Result<DynamicImage, TextureError> {
    let kind = file_kind(path)?;
    let file = open_image_file(path)?;
    decode_from(BufReader::new(file), path, kind, &texture_limits())
}

/// [`decode_file`] on a file's bytes already in memory, with explicit size limits; `name` gives
/// the format (by extension) and names the image in errors.
pub fn decode_bytes(
    bytes: &[u8],
    name: &Path,
    limits: &crate::imageio::SizeLimits,
) -> Result<DynamicImage, TextureError> {
    let kind = file_kind(name)?;
    decode_from(io::Cursor::new(bytes), name, kind, limits)
}

/// Decodes an image embedded in a model file (PNG or JPEG, told apart by their signatures) with
/// size limits; `name` names it in errors.
pub fn decode_embedded(
    bytes: &[u8],
    name: &Path,
    limits: &crate::imageio::SizeLimits,
) -> Result<DynamicImage, TextureError> {
    let kind = if bytes.starts_with(b"\x89PNG") {
        FileKind::Png
    } else if bytes.starts_with(&[0xFF, 0xD8, 0xFF]) {
        FileKind::Jpeg
    } else {
        return Err(TextureError::Unsupported {
            path: name.to_path_buf(),
            format: "embedded image",
            reason: "neither PNG nor JPEG data".into(),
        });
    };
    decode_from(io::Cursor::new(bytes), name, kind, limits)
}

fn file_kind(path: &Path) -> Result<FileKind, TextureError> {
    FileKind::from_path(path).ok_or_else(|| TextureError::UnsupportedExtension {
        path: path.to_path_buf(),
    })
}

/// The decoding shared by [`decode_file`] and [`decode_bytes`].
fn decode_from<R: io::BufRead + io::Seek>(
    reader: R,
    path: &Path,
    kind: FileKind,
    limits: &crate::imageio::SizeLimits,
) -> Result<DynamicImage, TextureError> {
    decode_checked(reader, kind.image_format(), limits, None).map_err(|p| {
        let (path, format) = (path.to_path_buf(), kind.name());
        match p {
            DecodeProblem::Read(source) => FileError::Read { path, source }.into(),
            DecodeProblem::TooLarge(declared) => TextureError::TooLarge { path, declared },
            DecodeProblem::Limits(l) => TextureError::TooLarge {
                path,
                declared: l.to_string(),
            },
            DecodeProblem::Unsupported(reason) => TextureError::Unsupported {
                path,
                format,
                reason,
            },
            DecodeProblem::Corrupt(reason) => TextureError::Corrupt {
                path,
                format,
                reason,
            },
        }
    })
}

/// The texels as the pipeline sees them: the file's 8-bit codes (kept exactly for level 0) or
/// floats.
enum Source {
    /// 8-bit RGBA codes.
    Bytes(Vec<u8>),
    /// RGBA floats: 16-bit PNG codes / 65535 (still sRGB-encoded for colour maps) or EXR/HDR
    /// linear values.
    Floats {
        texels: Vec<[f32; 4]>,
        encoded: bool,
    },
}

/// [`load_texture`] on an image already in memory; `name` names it in warnings and errors.
pub fn texture_from_image(
    img: &DynamicImage,
    name: &Path,
    space: ColorSpace,
    channel: Option<u8>,
    mipmaps: bool,
    max_dimension: u32,
    on_warning: &mut dyn FnMut(String),
) -> Result<TextureData, TextureError> {
    let (width, height) = (img.width(), img.height());
    if width == 0 || height == 0 {
        return Err(TextureError::Corrupt {
            path: name.to_path_buf(),
            format: "image",
            reason: format!("empty image ({width}×{height})"),
        });
    }
    let grey = !img.color().has_color();
    if space == ColorSpace::NormalMap && grey {
        on_warning(format!(
            "{}: a greyscale image used as a normal map (is it a height/bump map? luz reads \
             normal maps only: RGB = (n + 1) / 2, tangent space)",
            name.display()
        ));
    }
    let channel = channel.map(|c| usize::from(c.min(3)));
    let source = match img {
        DynamicImage::ImageLuma8(_)
        | DynamicImage::ImageLumaA8(_)
        | DynamicImage::ImageRgb8(_)
        | DynamicImage::ImageRgba8(_) => {
            let mut bytes = img.to_rgba8().into_raw();
            if let Some(c) = channel {
                bytes.par_chunks_exact_mut(4).for_each(|t| {
                    let v = t[c];
                    t.copy_from_slice(&[v, v, v, 255]);
                });
            }
            Source::Bytes(bytes)
        }
        DynamicImage::ImageLuma16(_)
        | DynamicImage::ImageLumaA16(_)
        | DynamicImage::ImageRgb16(_)
        | DynamicImage::ImageRgba16(_) => {
            let raw = img.to_rgba16().into_raw();
            let texels = raw
                .par_chunks_exact(4)
                .map(|t| pick(std::array::from_fn(|c| f32::from(t[c]) / 65535.0), channel))
                .collect();
            Source::Floats {
                texels,
                encoded: true,
            }
        }
        DynamicImage::ImageRgb32F(_) | DynamicImage::ImageRgba32F(_) => {
            let raw = img.to_rgba32f().into_raw();
            let mut bad = 0usize;
            let texels: Vec<[f32; 4]> = raw
                .chunks_exact(4)
                .map(|t| {
                    let t: [f32; 4] = std::array::from_fn(|c| {
                        let v = t[c];
                        if v.is_nan() {
                            bad += 1;
                            0.0
                        } else if v.abs() > F16_MAX {
                            bad += 1;
                            v.clamp(-F16_MAX, F16_MAX)
                        } else {
                            v
                        }
                    });
                    pick(t, channel)
                })
                .collect();
            if bad > 0 {
                on_warning(format!(
                    "{}: {bad} channel values are NaN or beyond the half-float range (±65504); \
                     NaN became 0 and the others were clamped",
                    name.display()
                ));
            }
            Source::Floats {
                texels,
                encoded: false,
            }
        }
        other => {
            return Err(TextureError::Unsupported {
                path: name.to_path_buf(),
                format: "image",
                reason: format!("pixel type {:?}", other.color()),
            })
        }
    };

    let format = match (&source, space) {
        (Source::Bytes(_), ColorSpace::Srgb) => TexFormat::Rgba8Srgb,
        (Source::Bytes(_), _) => TexFormat::Rgba8Unorm,
        (Source::Floats { .. }, _) => TexFormat::Rgba16F,
    };
    let codec = Codec { format };

    // Level 0 in float (linear light; normal maps keep their [0, 1] encoding).
    let mut level: Vec<[f32; 4]> = match &source {
        Source::Bytes(bytes) => {
            let lut = srgb_decode_table();
            bytes
                .par_chunks_exact(4)
                .map(|t| match space {
                    ColorSpace::Srgb => [
                        lut[t[0] as usize],
                        lut[t[1] as usize],
                        lut[t[2] as usize],
                        t[3] as f32 / 255.0,
                    ],
                    _ => std::array::from_fn(|c| t[c] as f32 / 255.0),
                })
                .collect()
        }
        Source::Floats { texels, encoded } => {
            if *encoded && space == ColorSpace::Srgb {
                texels
                    .par_iter()
                    .map(|t| {
                        [
                            srgb_decode(t[0]),
                            srgb_decode(t[1]),
                            srgb_decode(t[2]),
                            t[3],
                        ]
                    })
                    .collect()
            } else {
                texels.clone()
            }
        }
    };

    let max_dimension = max_dimension.max(1);
    let (mut w, mut h) = (width, height);
    let level0 = if width > max_dimension || height > max_dimension {
        let scale = f64::from(max_dimension) / f64::from(width.max(height));
        let nw = ((f64::from(width) * scale).round() as u32).clamp(1, max_dimension);
        let nh = ((f64::from(height) * scale).round() as u32).clamp(1, max_dimension);
        on_warning(format!(
            "{}: {width}×{height} is larger than the device allows ({max_dimension} per side); \
             downscaled to {nw}×{nh} (area filter)",
            name.display()
        ));
        level = resample(&level, w, h, nw, nh);
        if space == ColorSpace::NormalMap {
            renormalise(&mut level);
        }
        (w, h) = (nw, nh);
        codec.encode(&level)
    } else {
        match source {
            Source::Bytes(bytes) => bytes,
            Source::Floats { .. } => codec.encode(&level),
        }
    };

    let (width, height) = (w, h);
    let mut mips = vec![level0];
    if mipmaps {
        for _ in 1..mip_count(width, height) {
            let (nw, nh) = mip_extent(w, h, 1);
            level = resample(&level, w, h, nw, nh);
            if space == ColorSpace::NormalMap {
                renormalise(&mut level);
            }
            mips.push(codec.encode(&level));
            (w, h) = (nw, nh);
        }
    }
    Ok(TextureData {
        width,
        height,
        format,
        mips,
    })
}

/// Copies channel `c` to R, G and B (alpha 1).
fn pick(t: [f32; 4], channel: Option<usize>) -> [f32; 4] {
    match channel {
        Some(c) => [t[c], t[c], t[c], 1.0],
        None => t,
    }
}

/// Float texels → the bytes of a level.
#[derive(Clone, Copy)]
struct Codec {
    format: TexFormat,
}

impl Codec {
    fn encode(self, texels: &[[f32; 4]]) -> Vec<u8> {
        let bpt = self.format.bytes_per_texel();
        let mut out = vec![0u8; texels.len() * bpt];
        out.par_chunks_exact_mut(bpt)
            .zip(texels.par_iter())
            .for_each(|(o, t)| match self.format {
                TexFormat::Rgba8Srgb => {
                    for c in 0..3 {
                        o[c] = srgb_encode_code(t[c]);
                    }
                    o[3] = unorm8(t[3]);
                }
                TexFormat::Rgba8Unorm => {
                    for c in 0..4 {
                        o[c] = unorm8(t[c]);
                    }
                }
                TexFormat::Rgba16F => {
                    for c in 0..4 {
                        o[2 * c..2 * c + 2].copy_from_slice(&f32_to_f16(t[c]).to_le_bytes());
                    }
                }
                TexFormat::Rgba32F => {
                    for c in 0..4 {
                        o[4 * c..4 * c + 4].copy_from_slice(&t[c].to_le_bytes());
                    }
                }
            });
        out
    }
}

fn unorm8(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0).round() as u8
}

/// The 8-bit sRGB code nearest (in encoded space) to a linear value: a binary search of the
/// 255 decision thresholds decode((k + 0.5) / 255), exactly `round(encode(v) · 255)` but
/// without a `powf` per channel.
fn srgb_encode_code(v: f32) -> u8 {
    static THRESHOLDS: std::sync::OnceLock<[f32; 255]> = std::sync::OnceLock::new();
    let t = THRESHOLDS.get_or_init(|| {
        std::array::from_fn(|k| {
            let e = (k as f64 + 0.5) / 255.0;
            let l = if e <= 0.040_45 {
                e / 12.92
            } else {
                ((e + 0.055) / 1.055).powf(2.4)
            };
            l as f32
        })
    });
    if v.is_nan() {
        return 0;
    }
    // Number of thresholds ≤ v: the code.
    t.partition_point(|&x| x <= v) as u8
}

/// Renormalises normal-map texels in their (n + 1) / 2 encoding; a zero average becomes +z.
fn renormalise(texels: &mut [[f32; 4]]) {
    texels.par_iter_mut().for_each(|t| {
        let n = Vec3::new(t[0], t[1], t[2]) * 2.0 - Vec3::ONE;
        let n = n.try_normalize().unwrap_or(Vec3::Z);
        let e = (n + Vec3::ONE) * 0.5;
        t[0] = e.x;
        t[1] = e.y;
        t[2] = e.z;
    });
}

/// Per destination index along one axis: the first source index and the weights of the source
/// texels its footprint covers (area-weighted, summing to 1).
fn area_weights(src: u32, dst: u32) -> Vec<(usize, Vec<f32>)> {
    let scale = f64::from(src) / f64::from(dst);
    (0..dst)
        .map(|i| {
            let a = f64::from(i) * scale;
            let b = (f64::from(i + 1) * scale).min(f64::from(src));
            let first = a.floor() as usize;
            let last = (b.ceil() as usize).clamp(first + 1, src as usize);
            let weights = (first..last)
                .map(|j| {
                    let lo = a.max(j as f64);
                    let hi = b.min(j as f64 + 1.0);
                    ((hi - lo).max(0.0) / (b - a)) as f32
                })
                .collect();
            (first, weights)
        })
        .collect()
}

/// Area (box) resampling of an RGBA float image from sw×sh to dw×dh (separable: rows, then
/// columns). With a factor of exactly 2 it is the 2×2 box filter.
fn resample(src: &[[f32; 4]], sw: u32, sh: u32, dw: u32, dh: u32) -> Vec<[f32; 4]> {
    let (sw_, dw_) = (sw as usize, dw as usize);
    let xw = area_weights(sw, dw);
    let yw = area_weights(sh, dh);
    // Horizontal pass: sh rows of dw texels.
    let mut tmp = vec![[0.0f32; 4]; dw_ * sh as usize];
    tmp.par_chunks_exact_mut(dw_)
        .zip(src.par_chunks_exact(sw_))
        .for_each(|(out, row)| {
            for (o, (first, ws)) in out.iter_mut().zip(&xw) {
                let mut acc = [0.0f32; 4];
                for (k, &w) in ws.iter().enumerate() {
                    let t = row[first + k];
                    for c in 0..4 {
                        acc[c] += w * t[c];
                    }
                }
                *o = acc;
            }
        });
    // Vertical pass.
    let mut out = vec![[0.0f32; 4]; dw_ * dh as usize];
    out.par_chunks_exact_mut(dw_)
        .zip(yw.par_iter())
        .for_each(|(row, (first, ws))| {
            for (k, &w) in ws.iter().enumerate() {
                let src_row = &tmp[(first + k) * dw_..(first + k + 1) * dw_];
                for (o, t) in row.iter_mut().zip(src_row) {
                    for c in 0..4 {
                        o[c] += w * t[c];
                    }
                }
            }
        });
    out
}

mod half;
mod patterns;

use half::F16_MAX;
pub use half::{f16_to_f32, f32_to_f16};
pub use patterns::{checker, noise_normal_map};

#[cfg(test)]
mod tests;
