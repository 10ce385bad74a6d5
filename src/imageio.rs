//! Image files: saving rendered linear images (PNG for display, EXR for measurement), loading
//! PNG/EXR files for `luz diff` and the golden-image tests, and loading environment maps
//! (Radiance `.hdr` or `.exr`, [`load_radiance`]) for image-based lighting.
//!
//! * **PNG** is written as 8-bit sRGB **RGB** (no alpha channel): exposure → tone map → clamp →
//!   sRGB encode ([`crate::color::to_display_rgba8`]); the renderer's alpha is not stored because
//!   the display pipeline makes every pixel opaque. PNGs are read as 8- or 16-bit, grey or colour,
//!   with or without alpha, and are always interpreted as sRGB (gAMA/iCCP chunks are ignored).
//! * **EXR** is written as linear 32-bit float RGBA, untouched: no exposure, no tone map, no clamp,
//!   NaN and Inf preserved. EXRs are read as linear float RGB(A) (alpha 1 when absent).
//!
//! Declared image sizes are checked before any pixel memory is allocated: at most
//! [`MAX_DIMENSION`] per side, [`MAX_PIXELS`] in total and [`MAX_DECODE_BYTES`] of decoded data.

use std::fmt;
use std::fs::{self, File};
use std::io::{self, BufRead, BufReader, BufWriter, Cursor, Read, Seek, Write};
use std::path::{Path, PathBuf};

use image::codecs::openexr::OpenExrEncoder;
use image::codecs::png::{CompressionType, FilterType, PngEncoder};
use image::{DynamicImage, ImageDecoder, ImageFormat, ImageReader, Limits};
use serde::{Deserialize, Serialize};

use crate::color::{srgb_decode, srgb_decode_u8, to_display_rgba8, Tonemap};

/// Largest accepted width or height of a loaded image.
pub const MAX_DIMENSION: u32 = 32_768;
/// Largest accepted pixel count of a loaded image (2^30, one gigapixel).
pub const MAX_PIXELS: u64 = 1 << 30;
/// Largest accepted size of the decoded pixel data of a loaded image, in bytes (4 GiB).
pub const MAX_DECODE_BYTES: u64 = 4 << 30;
/// Largest EXR tile (decoded bytes) accepted when the tile reaches beyond the data window.
pub const MAX_OVERSIZED_TILE_BYTES: u64 = 64 << 20;

/// A linear-light RGBA float image, row-major, (0, 0) at the top left.
#[derive(Clone, PartialEq)]
pub struct LinearImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 4]>,
}

impl LinearImage {
    /// A `width × height` image filled with `rgba`.
    pub fn filled(width: u32, height: u32, rgba: [f32; 4]) -> Self {
        Self {
            width,
            height,
            pixels: vec![rgba; width as usize * height as usize],
        }
    }

    /// The pixel at column `x`, row `y` (panics when out of range).
    pub fn pixel(&self, x: u32, y: u32) -> [f32; 4] {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) out of range"
        );
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    /// Mutable access to the pixel at column `x`, row `y` (panics when out of range).
    pub fn pixel_mut(&mut self, x: u32, y: u32) -> &mut [f32; 4] {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) out of range"
        );
        &mut self.pixels[y as usize * self.width as usize + x as usize]
    }
}

impl fmt::Debug for LinearImage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("LinearImage")
            .field("width", &self.width)
            .field("height", &self.height)
            .field("pixels", &format_args!("[{} pixels]", self.pixels.len()))
            .finish()
    }
}

/// The image file formats luz reads and writes, chosen by file extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FileFormat {
    /// 8-bit sRGB for display (16-bit accepted when reading).
    Png,
    /// OpenEXR, linear 32-bit float, for measurement.
    Exr,
}

impl FileFormat {
    /// The extensions accepted, for messages.
    pub const SUPPORTED: &'static str = ".png (8-bit sRGB), .exr (linear float)";

    /// The format named by the path's extension, case-insensitive.
    pub fn from_path(path: &Path) -> Result<Self, ImageError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("png") => Ok(FileFormat::Png),
            Some("exr") => Ok(FileFormat::Exr),
            _ => Err(ImageError::UnsupportedExtension {
                path: path.to_path_buf(),
            }),
        }
    }

    /// The canonical extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            FileFormat::Png => "png",
            FileFormat::Exr => "exr",
        }
    }

    fn image_format(self) -> ImageFormat {
        match self {
            FileFormat::Png => ImageFormat::Png,
            FileFormat::Exr => ImageFormat::OpenExr,
        }
    }
}

impl fmt::Display for FileFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            FileFormat::Png => "PNG",
            FileFormat::Exr => "OpenEXR",
        })
    }
}

/// Everything that can go wrong reading or writing an image file. Every message names the file.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    #[error("{}: no such file", .path.display())]
    NotFound { path: PathBuf },
    #[error("{}: is a directory, not an image file", .path.display())]
    IsDirectory { path: PathBuf },
    #[error("cannot read {}: {source}", .path.display())]
    Read {
        path: PathBuf,
        #[source]
        source: io::Error,
    },
    #[error(
        "{}: unsupported image file extension (supported: {})",
        .path.display(),
        FileFormat::SUPPORTED
    )]
    UnsupportedExtension { path: PathBuf },
    #[error("{}: not a valid {format} file: {reason}", .path.display())]
    Corrupt {
        path: PathBuf,
        format: FileFormat,
        reason: String,
    },
    #[error("{}: unsupported kind of {format} file: {reason}", .path.display())]
    Unsupported {
        path: PathBuf,
        format: FileFormat,
        reason: String,
    },
    #[error(
        "{}: image too large ({declared}); limits are {MAX_DIMENSION} pixels per side, \
         2^30 pixels in total and 4 GiB of decoded data",
        .path.display()
    )]
    TooLarge { path: PathBuf, declared: String },
    #[error("cannot write {}: {source}", .path.display())]
    Write {
        path: PathBuf,
        #[source]
        source: io::Error,
    },
    #[error("cannot encode {}: {reason}", .path.display())]
    Encode { path: PathBuf, reason: String },
    #[error(
        "{}: unsupported environment image extension (supported: {})",
        .path.display(),
        RADIANCE_SUPPORTED
    )]
    NotRadiance { path: PathBuf },
    #[error("{}: not a valid Radiance HDR file: {reason}", .path.display())]
    CorruptHdr { path: PathBuf, reason: String },
}

/// An image file as loaded for comparison.
#[derive(Clone, PartialEq)]
pub struct LoadedImage {
    pub width: u32,
    pub height: u32,
    pub format: FileFormat,
    /// Linear RGBA (PNG: sRGB-decoded, alpha = code / max; EXR: as stored, alpha 1 when absent).
    pub linear: Vec<[f32; 4]>,
    /// 8-bit sRGB RGB as a display shows it: the PNG codes (16-bit rounded to 8); for EXR the
    /// linear value clamped to [0, 1] and sRGB-encoded (no exposure, no tone map, NaN → 0).
    pub display: Vec<[u8; 3]>,
    /// RGBA as stored in the file: integer codes for PNG (as f32, alpha = `encoded_max` when the
    /// file has no alpha), linear floats for EXR (identical to `linear`).
    pub encoded: Vec<[f32; 4]>,
    /// 255 for 8-bit PNG, 65535 for 16-bit PNG, 1.0 for EXR.
    pub encoded_max: f32,
}

impl LoadedImage {
    /// Exactly what [`load`] would return after [`save`] of `img` in `format` with this exposure
    /// and tone map, without touching the disk (EXR ignores exposure and tone map).
    pub fn from_linear(
        img: &LinearImage,
        format: FileFormat,
        exposure_ev: f32,
        tonemap: Tonemap,
    ) -> Self {
        match format {
            FileFormat::Png => {
                let rgba = to_display_rgba8(&img.pixels, exposure_ev, tonemap);
                let rgb: Vec<u8> = rgba
                    .chunks_exact(4)
                    .flat_map(|p| [p[0], p[1], p[2]])
                    .collect();
                from_rgb8_codes(img.width, img.height, &rgb)
            }
            FileFormat::Exr => from_linear_f32(img.width, img.height, img.pixels.clone()),
        }
    }

    /// Number of pixels holding a NaN or an infinity in any channel of `linear`.
    pub fn non_finite_pixels(&self) -> u64 {
        count_non_finite(&self.linear)
    }
}

impl fmt::Debug for LoadedImage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("LoadedImage")
            .field("width", &self.width)
            .field("height", &self.height)
            .field("format", &self.format)
            .field("encoded_max", &self.encoded_max)
            .finish_non_exhaustive()
    }
}

fn from_rgb8_codes(width: u32, height: u32, rgb: &[u8]) -> LoadedImage {
    let px = rgb.chunks_exact(3);
    LoadedImage {
        width,
        height,
        format: FileFormat::Png,
        linear: px
            .clone()
            .map(|p| {
                [
                    srgb_decode_u8(p[0]),
                    srgb_decode_u8(p[1]),
                    srgb_decode_u8(p[2]),
                    1.0,
                ]
            })
            .collect(),
        display: px.clone().map(|p| [p[0], p[1], p[2]]).collect(),
        encoded: px
            .map(|p| [p[0] as f32, p[1] as f32, p[2] as f32, 255.0])
            .collect(),
        encoded_max: 255.0,
    }
}

fn from_rgba8(width: u32, height: u32, rgba: &[u8]) -> LoadedImage {
    let px = rgba.chunks_exact(4);
    LoadedImage {
        width,
        height,
        format: FileFormat::Png,
        linear: px
            .clone()
            .map(|p| {
                [
                    srgb_decode_u8(p[0]),
                    srgb_decode_u8(p[1]),
                    srgb_decode_u8(p[2]),
                    p[3] as f32 / 255.0,
                ]
            })
            .collect(),
        display: px.clone().map(|p| [p[0], p[1], p[2]]).collect(),
        encoded: px
            .map(|p| [p[0] as f32, p[1] as f32, p[2] as f32, p[3] as f32])
            .collect(),
        encoded_max: 255.0,
    }
}

fn from_rgba16(width: u32, height: u32, rgba: &[u16]) -> LoadedImage {
    let px = rgba.chunks_exact(4);
    let dec = |v: u16| srgb_decode(v as f32 / 65535.0);
    let to8 = |v: u16| (v as f32 / 257.0).round() as u8;
    LoadedImage {
        width,
        height,
        format: FileFormat::Png,
        linear: px
            .clone()
            .map(|p| [dec(p[0]), dec(p[1]), dec(p[2]), p[3] as f32 / 65535.0])
            .collect(),
        display: px
            .clone()
            .map(|p| [to8(p[0]), to8(p[1]), to8(p[2])])
            .collect(),
        encoded: px
            .map(|p| [p[0] as f32, p[1] as f32, p[2] as f32, p[3] as f32])
            .collect(),
        encoded_max: 65535.0,
    }
}

fn from_linear_f32(width: u32, height: u32, linear: Vec<[f32; 4]>) -> LoadedImage {
    let display = to_display_rgba8(&linear, 0.0, Tonemap::None)
        .chunks_exact(4)
        .map(|p| [p[0], p[1], p[2]])
        .collect();
    LoadedImage {
        width,
        height,
        format: FileFormat::Exr,
        encoded: linear.clone(),
        linear,
        display,
        encoded_max: 1.0,
    }
}

/// Saves `img`: PNG as 8-bit sRGB RGB after exposure and tone map; EXR as linear f32 RGBA with
/// no exposure, tone map or clamp. The format comes from the extension. A file left half
/// written by a failed encode is removed.
pub fn save(
    path: &Path,
    img: &LinearImage,
    exposure_ev: f32,
    tonemap: Tonemap,
) -> Result<(), ImageError> {
    let format = FileFormat::from_path(path)?;
    check_buffer(path, img.width, img.height, img.pixels.len())?;
    match format {
        FileFormat::Png => {
            let rgba = to_display_rgba8(&img.pixels, exposure_ev, tonemap);
            let rgb: Vec<u8> = rgba
                .chunks_exact(4)
                .flat_map(|p| [p[0], p[1], p[2]])
                .collect();
            save_png_rgb8(path, img.width, img.height, &rgb)
        }
        FileFormat::Exr => {
            let flat: Vec<f32> = img.pixels.iter().flatten().copied().collect();
            let buffer = image::Rgba32FImage::from_raw(img.width, img.height, flat)
                .expect("buffer length checked above");
            write_with(path, |w| {
                DynamicImage::ImageRgba32F(buffer).write_with_encoder(OpenExrEncoder::new(w))
            })
        }
    }
}

/// Writes tightly packed 8-bit RGB bytes as a PNG (used for FLIP heat maps and other
/// already-display-encoded images). The path must end in `.png`.
pub fn save_png_rgb8(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), ImageError> {
    if FileFormat::from_path(path)? != FileFormat::Png {
        return Err(ImageError::Encode {
            path: path.to_path_buf(),
            reason: "8-bit display images can only be written as .png".into(),
        });
    }
    if rgb.len() != width as usize * height as usize * 3 {
        return Err(ImageError::Encode {
            path: path.to_path_buf(),
            reason: format!(
                "buffer holds {} bytes but {width}×{height} RGB needs {}",
                rgb.len(),
                width as usize * height as usize * 3
            ),
        });
    }
    check_buffer(path, width, height, width as usize * height as usize)?;
    let buffer =
        image::RgbImage::from_raw(width, height, rgb.to_vec()).expect("buffer length checked");
    write_with(path, |w| {
        DynamicImage::ImageRgb8(buffer).write_with_encoder(PngEncoder::new_with_quality(
            w,
            CompressionType::Default,
            FilterType::Adaptive,
        ))
    })
}

fn check_buffer(path: &Path, width: u32, height: u32, pixels: usize) -> Result<(), ImageError> {
    let reason = if width == 0 || height == 0 {
        format!("image is empty ({width}×{height})")
    } else if pixels != width as usize * height as usize {
        format!(
            "pixel buffer holds {pixels} pixels but {width}×{height} needs {}",
            width as usize * height as usize
        )
    } else {
        return Ok(());
    };
    Err(ImageError::Encode {
        path: path.to_path_buf(),
        reason,
    })
}

fn write_with(
    path: &Path,
    encode: impl FnOnce(&mut BufWriter<File>) -> image::ImageResult<()>,
) -> Result<(), ImageError> {
    let write_err = |source| ImageError::Write {
        path: path.to_path_buf(),
        source,
    };
    let file = File::create(path).map_err(write_err)?;
    let mut writer = BufWriter::new(file);
    let result = match encode(&mut writer) {
        Ok(()) => writer.flush().map_err(write_err),
        Err(image::ImageError::IoError(e)) => Err(write_err(e)),
        Err(e) => Err(ImageError::Encode {
            path: path.to_path_buf(),
            reason: e.to_string(),
        }),
    };
    if result.is_err() {
        drop(writer);
        let _ = fs::remove_file(path);
    }
    result
}

/// Size limits of a decoder: declared size and decoded bytes, checked from the header before any
/// pixel memory is allocated. [`SizeLimits::DEFAULT`] is what every file loader of luz uses;
/// the `*_bytes` loaders take the limits as a parameter (the fuzz targets use smaller ones).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SizeLimits {
    /// Largest width or height.
    pub max_dimension: u32,
    /// Largest width × height.
    pub max_pixels: u64,
    /// Largest decoded pixel data, in bytes.
    pub max_bytes: u64,
}

impl SizeLimits {
    /// [`MAX_DIMENSION`], [`MAX_PIXELS`], [`MAX_DECODE_BYTES`].
    pub const DEFAULT: SizeLimits = SizeLimits {
        max_dimension: MAX_DIMENSION,
        max_pixels: MAX_PIXELS,
        max_bytes: MAX_DECODE_BYTES,
    };

    /// The `image` crate limits for these sizes (declared size and allocation).
    pub fn image_limits(&self) -> Limits {
        let mut limits = Limits::default();
        limits.max_image_width = Some(self.max_dimension);
        limits.max_image_height = Some(self.max_dimension);
        limits.max_alloc = Some(self.max_bytes);
        limits
    }

    /// True when a declared `width`×`height` image, `bytes` once decoded, is beyond these limits.
    pub fn exceeded(&self, width: u32, height: u32, bytes: u64) -> bool {
        width > self.max_dimension
            || height > self.max_dimension
            || u64::from(width) * u64::from(height) > self.max_pixels
            || bytes > self.max_bytes
    }
}

impl Default for SizeLimits {
    fn default() -> Self {
        SizeLimits::DEFAULT
    }
}

/// The `image` crate limits every decoder in luz runs with (declared size and allocation).
pub fn decode_limits() -> Limits {
    SizeLimits::DEFAULT.image_limits()
}

/// True when a declared `width`×`height` image, `bytes` once decoded, is beyond what luz decodes:
/// checked from the header, before any pixel is allocated.
pub fn exceeds_decode_limits(width: u32, height: u32, bytes: u64) -> bool {
    SizeLimits::DEFAULT.exceeded(width, height, bytes)
}

/// Loads a PNG (8/16-bit, decoded from sRGB to linear) or an EXR (linear). The format comes
/// from the extension; content that does not match it is reported as corrupt.
pub fn load(path: &Path) -> Result<LoadedImage, ImageError> {
    let format = FileFormat::from_path(path)?;
    let file = open_file(path)?;
    load_from(
        BufReader::new(file),
        path,
        format,
        &SizeLimits::DEFAULT,
        || declared_size(BufReader::new(File::open(path).ok()?), format),
    )
}

/// [`load`] on a file's bytes already in memory, with explicit size limits; `name` gives the
/// format (by extension) and names the image in errors.
pub fn load_bytes(
    bytes: &[u8],
    name: &Path,
    limits: &SizeLimits,
) -> Result<LoadedImage, ImageError> {
    let format = FileFormat::from_path(name)?;
    load_from(Cursor::new(bytes), name, format, limits, || {
        declared_size(Cursor::new(bytes), format)
    })
}

/// Opens an image file for reading; a directory or a missing file is reported as such.
fn open_file(path: &Path) -> Result<File, ImageError> {
    let meta = fs::metadata(path).map_err(|e| read_error(path, e))?;
    if meta.is_dir() {
        return Err(ImageError::IsDirectory {
            path: path.to_path_buf(),
        });
    }
    File::open(path).map_err(|e| read_error(path, e))
}

/// Checks the headers of an OpenEXR stream against `limits` before the decoder sees them:
/// `Some(what was declared)` when a part's data window (or tile) with its channels is beyond
/// them. The `image` crate checks only the display window, but the `exr` decoder allocates and
/// walks the data window, and sizes each block buffer from it (found by fuzzing: a 590-byte file
/// declaring 64 × 4194304 tiles made it allocate 1.7 GB). Headers it cannot read are left to
/// the decoder to report. The reader is rewound to where it was.
pub fn exr_header_exceeds<R: Read + Seek>(reader: &mut R, limits: &SizeLimits) -> Option<String> {
    let start = reader.stream_position().ok()?;
    let found = scan_exr_headers(reader, limits);
    reader.seek(io::SeekFrom::Start(start)).ok()?;
    found
}

fn scan_exr_headers<R: Read + Seek>(r: &mut R, limits: &SizeLimits) -> Option<String> {
    fn word<R: Read>(r: &mut R) -> Option<[u8; 4]> {
        let mut b = [0u8; 4];
        r.read_exact(&mut b).ok()?;
        Some(b)
    }
    fn text<R: Read>(r: &mut R) -> Option<Vec<u8>> {
        let mut out = Vec::new();
        let mut b = [0u8; 1];
        loop {
            r.read_exact(&mut b).ok()?;
            if b[0] == 0 {
                return Some(out);
            }
            if out.len() >= 255 {
                return None;
            }
            out.push(b[0]);
        }
    }
    if word(r)? != [0x76, 0x2f, 0x31, 0x01] {
        return None;
    }
    let version = u32::from_le_bytes(word(r)?);
    let multipart = version & 0x1000 != 0;
    for _part in 0..4096 {
        let mut window: Option<(i64, i64)> = None;
        let mut tile: Option<(u64, u64)> = None;
        let mut channels: u64 = 0;
        let mut attributes = 0;
        loop {
            let name = text(r)?;
            if name.is_empty() {
                break;
            }
            attributes += 1;
            if attributes > 4096 {
                return None;
            }
            let kind = text(r)?;
            let size = i32::from_le_bytes(word(r)?);
            let size = u64::try_from(size).ok()?;
            let mut value = vec![0u8; size.min(1 << 16) as usize];
            r.read_exact(&mut value).ok()?;
            if size > 1 << 16 {
                r.seek(io::SeekFrom::Current(i64::try_from(size - (1 << 16)).ok()?))
                    .ok()?;
            }
            let int = |i: usize| -> Option<i64> {
                Some(i64::from(i32::from_le_bytes(
                    value.get(4 * i..4 * i + 4)?.try_into().ok()?,
                )))
            };
            match (name.as_slice(), kind.as_slice()) {
                (b"dataWindow", b"box2i") => {
                    let (x0, y0, x1, y1) = (int(0)?, int(1)?, int(2)?, int(3)?);
                    window = Some(((x1 - x0 + 1).max(0), (y1 - y0 + 1).max(0)));
                }
                (b"tiles", b"tiledesc") => {
                    let u = |i: usize| -> Option<u64> {
                        Some(u64::from(u32::from_le_bytes(
                            value.get(4 * i..4 * i + 4)?.try_into().ok()?,
                        )))
                    };
                    tile = Some((u(0)?, u(1)?));
                }
                (b"channels", b"chlist") => {
                    // Per channel: name\0, pixel type (i32), pLinear (u8), 3 reserved bytes,
                    // x and y sampling (i32); at most 4 bytes per pixel each. Ends with \0.
                    let mut rest = value.as_slice();
                    channels = 0;
                    while let Some(end) = rest.iter().position(|&b| b == 0) {
                        if end == 0 || rest.len() < end + 17 {
                            break;
                        }
                        channels += 1;
                        rest = &rest[end + 17..];
                    }
                }
                _ => {}
            }
        }
        let bytes_per_pixel = 4 * channels.max(1);
        if let Some((w, h)) = window {
            let (w, h) = (w as u64, h as u64);
            let too_large = w > u64::from(limits.max_dimension)
                || h > u64::from(limits.max_dimension)
                || w * h > limits.max_pixels
                || w * h * bytes_per_pixel > limits.max_bytes;
            if too_large {
                return Some(format!("declared data window {w}×{h}"));
            }
        }
        if let Some((tw, th)) = tile {
            let tile_bytes = tw.saturating_mul(th).saturating_mul(bytes_per_pixel);
            if tile_bytes > limits.max_bytes {
                return Some(format!("declared tiles of {tw}×{th}"));
            }
            // The decoder allocates whole tiles: a tile beyond the data window only wastes
            // memory (a 590-byte file with an 8×8 window and 64×4194304 tiles took 1.7 GB).
            if let Some((w, h)) = window {
                if (tw > w as u64 || th > h as u64) && tile_bytes > MAX_OVERSIZED_TILE_BYTES {
                    return Some(format!(
                        "declared tiles of {tw}×{th}, larger than the {w}×{h} data window"
                    ));
                }
            }
        }
        if !multipart {
            return None;
        }
        // A multi-part file's header list ends with an empty header.
        let mut b = [0u8; 1];
        r.read_exact(&mut b).ok()?;
        if b[0] == 0 {
            return None;
        }
        r.seek(io::SeekFrom::Current(-1)).ok()?;
    }
    None
}

/// The decoding shared by [`load`] and [`load_bytes`]; `declared` reads the size the file
/// declares (for the message when a limit is hit inside the decoder).
fn load_from<R: BufRead + Seek>(
    mut reader: R,
    path: &Path,
    format: FileFormat,
    limits: &SizeLimits,
    declared: impl Fn() -> Option<(u32, u32)>,
) -> Result<LoadedImage, ImageError> {
    // Scanned first, reported after the decoder has read (and validated) the header.
    let exr_too_large = match format {
        FileFormat::Exr => exr_header_exceeds(&mut reader, limits),
        FileFormat::Png => None,
    };
    let mut reader = ImageReader::with_format(reader, format.image_format());
    reader.limits(limits.image_limits());

    let decoder = reader
        .into_decoder()
        .map_err(|e| decode_error(path, format, e, &declared))?;
    if let Some(declared) = exr_too_large {
        return Err(ImageError::TooLarge {
            path: path.to_path_buf(),
            declared,
        });
    }
    let (width, height) = decoder.dimensions();
    let too_large = limits.exceeded(width, height, decoder.total_bytes());
    if too_large {
        return Err(ImageError::TooLarge {
            path: path.to_path_buf(),
            declared: format!("declared {width}×{height}"),
        });
    }
    if width == 0 || height == 0 {
        return Err(ImageError::Corrupt {
            path: path.to_path_buf(),
            format,
            reason: format!("empty image ({width}×{height})"),
        });
    }
    let img = DynamicImage::from_decoder(decoder)
        .map_err(|e| decode_error(path, format, e, &declared))?;

    Ok(match (format, img) {
        (FileFormat::Exr, img) => {
            let buf = img.into_rgba32f();
            let linear = buf
                .into_raw()
                .chunks_exact(4)
                .map(|p| [p[0], p[1], p[2], p[3]])
                .collect();
            from_linear_f32(width, height, linear)
        }
        (
            FileFormat::Png,
            img @ (DynamicImage::ImageLuma8(_)
            | DynamicImage::ImageLumaA8(_)
            | DynamicImage::ImageRgb8(_)
            | DynamicImage::ImageRgba8(_)),
        ) => from_rgba8(width, height, &img.into_rgba8().into_raw()),
        (
            FileFormat::Png,
            img @ (DynamicImage::ImageLuma16(_)
            | DynamicImage::ImageLumaA16(_)
            | DynamicImage::ImageRgb16(_)
            | DynamicImage::ImageRgba16(_)),
        ) => from_rgba16(width, height, &img.into_rgba16().into_raw()),
        (FileFormat::Png, img) => {
            return Err(ImageError::Unsupported {
                path: path.to_path_buf(),
                format,
                reason: format!("pixel type {:?}", img.color()),
            })
        }
    })
}

/// The extensions [`load_radiance`] accepts, for messages.
pub const RADIANCE_SUPPORTED: &str = ".hdr (Radiance RGBE), .exr (OpenEXR)";

/// Loads a linear radiance image for image-based lighting: a Radiance `.hdr` (RGBE, flat or
/// run-length encoded) or an OpenEXR `.exr`, chosen by extension (case-insensitive). Pixels are
/// returned exactly as decoded (linear, alpha 1 for `.hdr`); NaN, Inf and negative values of an
/// EXR are left for the caller to sanitise. Same size limits as [`load`].
pub fn load_radiance(path: &Path) -> Result<LinearImage, ImageError> {
    match radiance_kind(path)? {
        RadianceKind::Exr => {
            let img = load(path)?;
            Ok(LinearImage {
                width: img.width,
                height: img.height,
                pixels: img.linear,
            })
        }
        RadianceKind::Hdr => {
            let file = open_file(path)?;
            load_hdr(BufReader::new(file), path, &SizeLimits::DEFAULT)
        }
    }
}

/// [`load_radiance`] on a file's bytes already in memory, with explicit size limits; `name`
/// gives the format (by extension) and names the image in errors.
pub fn load_radiance_bytes(
    bytes: &[u8],
    name: &Path,
    limits: &SizeLimits,
) -> Result<LinearImage, ImageError> {
    match radiance_kind(name)? {
        RadianceKind::Exr => {
            let img = load_bytes(bytes, name, limits)?;
            Ok(LinearImage {
                width: img.width,
                height: img.height,
                pixels: img.linear,
            })
        }
        RadianceKind::Hdr => load_hdr(Cursor::new(bytes), name, limits),
    }
}

enum RadianceKind {
    Hdr,
    Exr,
}

fn radiance_kind(path: &Path) -> Result<RadianceKind, ImageError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("exr") => Ok(RadianceKind::Exr),
        Some("hdr") => Ok(RadianceKind::Hdr),
        _ => Err(ImageError::NotRadiance {
            path: path.to_path_buf(),
        }),
    }
}

fn load_hdr<R: BufRead + Seek>(
    reader: R,
    path: &Path,
    limits: &SizeLimits,
) -> Result<LinearImage, ImageError> {
    let corrupt = |reason: String| ImageError::CorruptHdr {
        path: path.to_path_buf(),
        reason,
    };
    let hdr_error = |e: image::ImageError| match e {
        image::ImageError::IoError(source) if source.kind() == io::ErrorKind::UnexpectedEof => {
            corrupt("file is truncated".into())
        }
        image::ImageError::IoError(source) => ImageError::Read {
            path: path.to_path_buf(),
            source,
        },
        image::ImageError::Limits(_) => ImageError::TooLarge {
            path: path.to_path_buf(),
            declared: "declared size over the limits".into(),
        },
        other => {
            let text = other.to_string();
            corrupt(match text.split_once(": ") {
                Some((head, rest)) if head.starts_with("Format error") => rest.to_string(),
                _ => text,
            })
        }
    };
    let mut reader = ImageReader::with_format(reader, ImageFormat::Hdr);
    reader.limits(limits.image_limits());
    let decoder = reader.into_decoder().map_err(hdr_error)?;
    let (width, height) = decoder.dimensions();
    // Decoded as RGB f32 here, then widened to RGBA f32: 16 bytes per pixel in the end.
    let too_large = limits.exceeded(width, height, u64::from(width) * u64::from(height) * 16);
    if too_large {
        return Err(ImageError::TooLarge {
            path: path.to_path_buf(),
            declared: format!("declared {width}×{height}"),
        });
    }
    if width == 0 || height == 0 {
        return Err(corrupt(format!("empty image ({width}×{height})")));
    }
    let img = DynamicImage::from_decoder(decoder).map_err(hdr_error)?;
    let pixels = img
        .into_rgb32f()
        .into_raw()
        .chunks_exact(3)
        .map(|p| [p[0], p[1], p[2], 1.0])
        .collect();
    Ok(LinearImage {
        width,
        height,
        pixels,
    })
}

fn read_error(path: &Path, e: io::Error) -> ImageError {
    if e.kind() == io::ErrorKind::NotFound {
        ImageError::NotFound {
            path: path.to_path_buf(),
        }
    } else {
        ImageError::Read {
            path: path.to_path_buf(),
            source: e,
        }
    }
}

fn decode_error(
    path: &Path,
    format: FileFormat,
    e: image::ImageError,
    declared: &dyn Fn() -> Option<(u32, u32)>,
) -> ImageError {
    let path_buf = path.to_path_buf();
    match e {
        image::ImageError::IoError(source) if source.kind() == io::ErrorKind::UnexpectedEof => {
            ImageError::Corrupt {
                path: path_buf,
                format,
                reason: "file is truncated".into(),
            }
        }
        image::ImageError::IoError(source) => ImageError::Read {
            path: path_buf,
            source,
        },
        image::ImageError::Limits(_) => ImageError::TooLarge {
            declared: declared()
                .map(|(w, h)| format!("declared {w}×{h}"))
                .unwrap_or_else(|| "declared size over the limits".into()),
            path: path_buf,
        },
        image::ImageError::Unsupported(u) => ImageError::Unsupported {
            path: path_buf,
            format,
            reason: u.to_string(),
        },
        other => {
            // image's decoding errors read "Format error decoding Png: <reason>"; keep the reason.
            let text = other.to_string();
            let reason = match text.split_once(": ") {
                Some((head, rest)) if head.starts_with("Format error") => rest.to_string(),
                _ => text,
            };
            ImageError::Corrupt {
                path: path_buf,
                format,
                reason,
            }
        }
    }
}

/// The size a file declares, read from its header without decoding (for error messages).
fn declared_size<R: BufRead + Seek>(mut reader: R, format: FileFormat) -> Option<(u32, u32)> {
    match format {
        FileFormat::Png => {
            // Signature (8) + IHDR length (4) + "IHDR" (4) + width (4) + height (4), big-endian.
            let mut head = [0u8; 24];
            reader.read_exact(&mut head).ok()?;
            if &head[12..16] != b"IHDR" {
                return None;
            }
            let w = u32::from_be_bytes(head[16..20].try_into().ok()?);
            let h = u32::from_be_bytes(head[20..24].try_into().ok()?);
            Some((w, h))
        }
        FileFormat::Exr => {
            // The EXR reader parses only the header here; no pixel memory is allocated.
            let mut reader = ImageReader::with_format(reader, ImageFormat::OpenExr);
            reader.no_limits();
            reader.into_dimensions().ok()
        }
    }
}

/// Number of pixels with a NaN or an infinity in any channel.
pub fn count_non_finite(pixels: &[[f32; 4]]) -> u64 {
    pixels
        .iter()
        .filter(|p| p.iter().any(|c| !c.is_finite()))
        .count() as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("luz-imageio-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn gradient(width: u32, height: u32) -> LinearImage {
        let mut img = LinearImage::filled(width, height, [0.0, 0.0, 0.0, 1.0]);
        for y in 0..height {
            for x in 0..width {
                let u = x as f32 / (width - 1) as f32;
                let v = y as f32 / (height - 1) as f32;
                *img.pixel_mut(x, y) = [u, v, 0.5 * u * v, 0.25 + 0.5 * u];
            }
        }
        img
    }

    /// A flat (not run-length encoded) Radiance RGBE file.
    fn write_flat_hdr(path: &Path, width: u32, height: u32, rgbe: &[[u8; 4]]) {
        let mut out = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n".to_vec();
        out.extend(format!("-Y {height} +X {width}\n").bytes());
        for p in rgbe {
            out.extend(p);
        }
        fs::write(path, out).unwrap();
    }

    #[test]
    fn radiance_hdr_loads_and_fails_clearly() {
        let dir = scratch_dir("hdr");
        let path = dir.join("tiny.hdr");
        // RGBE (128, 64, 32, 129): mantissa/256 · 2^(129 − 128) = (1, 0.5, 0.25) (+ half-ULP
        // rounding in some decoders: allow 1/256 relative).
        write_flat_hdr(&path, 2, 1, &[[128, 64, 32, 129], [0, 0, 0, 0]]);
        let img = load_radiance(&path).unwrap();
        assert_eq!((img.width, img.height), (2, 1));
        for (got, want) in img.pixels[0].iter().zip([1.0, 0.5, 0.25, 1.0]) {
            assert!((got - want).abs() <= want / 128.0, "{got} vs {want}");
        }
        assert_eq!(img.pixels[1], [0.0, 0.0, 0.0, 1.0]);

        let err = load_radiance(&dir.join("missing.hdr")).unwrap_err();
        assert!(matches!(err, ImageError::NotFound { .. }), "{err}");
        assert!(err.to_string().contains("missing.hdr"));
        let garbage = dir.join("garbage.hdr");
        fs::write(
            &garbage,
            b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 4\n\x01",
        )
        .unwrap();
        let err = load_radiance(&garbage).unwrap_err();
        assert!(err.to_string().contains("garbage.hdr"), "{err}");
        let not_hdr = dir.join("png.hdr");
        fs::write(&not_hdr, b"\x89PNG\r\n\x1a\n").unwrap();
        let err = load_radiance(&not_hdr).unwrap_err();
        assert!(
            err.to_string().contains("png.hdr") && err.to_string().contains("Radiance"),
            "{err}"
        );
        let err = load_radiance(&dir.join("x.png")).unwrap_err();
        assert!(err.to_string().contains(".hdr") && err.to_string().contains("x.png"));
        // EXR goes through the same loader.
        let exr = dir.join("env.exr");
        save(&exr, &gradient(8, 4), 0.0, Tonemap::None).unwrap();
        let img = load_radiance(&exr).unwrap();
        assert_eq!(img, gradient(8, 4));
        fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn format_from_extension() {
        assert_eq!(
            FileFormat::from_path(Path::new("a/b.PNG")).unwrap(),
            FileFormat::Png
        );
        assert_eq!(
            FileFormat::from_path(Path::new("x.Exr")).unwrap(),
            FileFormat::Exr
        );
        for bad in ["x.jpg", "x", "dir.png/x.hdr", ".png"] {
            let err = FileFormat::from_path(Path::new(bad)).unwrap_err();
            let msg = err.to_string();
            assert!(
                matches!(err, ImageError::UnsupportedExtension { .. }),
                "{bad}"
            );
            assert!(msg.contains(bad) && msg.contains(".png") && msg.contains(".exr"));
        }
    }

    #[test]
    fn exr_round_trip_is_exact() {
        let dir = scratch_dir("exr");
        let mut img = gradient(17, 9);
        *img.pixel_mut(3, 4) = [f32::NAN, f32::INFINITY, -2.5, 0.0];
        *img.pixel_mut(0, 0) = [1e5, 1e-9, 123.456, 7.0];
        let path = dir.join("round.exr");
        // Exposure and tone map must not affect EXR.
        save(&path, &img, 3.0, Tonemap::Aces).unwrap();
        let loaded = load(&path).unwrap();
        assert_eq!((loaded.width, loaded.height), (17, 9));
        assert_eq!(loaded.format, FileFormat::Exr);
        assert_eq!(loaded.encoded_max, 1.0);
        for (a, b) in loaded.linear.iter().zip(&img.pixels) {
            for (x, y) in a.iter().zip(b) {
                assert!(x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan()));
            }
        }
        assert_eq!(loaded.non_finite_pixels(), 1);
        assert_eq!(loaded.display[17 * 4 + 3], [0, 255, 0]);
        let in_memory = LoadedImage::from_linear(&img, FileFormat::Exr, 3.0, Tonemap::Aces);
        assert_eq!(in_memory.display, loaded.display);
        assert_eq!(in_memory.non_finite_pixels(), 1);
        fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn png_round_trip_within_half_lsb() {
        let dir = scratch_dir("png");
        let img = gradient(33, 20);
        let path = dir.join("round.png");
        save(&path, &img, 0.0, Tonemap::None).unwrap();
        let loaded = load(&path).unwrap();
        assert_eq!(
            (loaded.width, loaded.height, loaded.encoded_max),
            (33, 20, 255.0)
        );
        for (got, want) in loaded.linear.iter().zip(&img.pixels) {
            for c in 0..3 {
                // Compare in encoded units: re-encoding the decoded value lands within 0.5 LSB.
                let e_got = crate::color::srgb_encode(got[c]) * 255.0;
                let e_want = crate::color::srgb_encode(want[c]) * 255.0;
                assert!((e_got - e_want).abs() <= 0.5 + 1e-3, "{e_got} vs {e_want}");
            }
            assert_eq!(got[3], 1.0, "PNG is written opaque RGB");
        }
        let in_memory = LoadedImage::from_linear(&img, FileFormat::Png, 0.0, Tonemap::None);
        assert_eq!(in_memory, loaded);
        fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn png_16_bit_and_grey_alpha_load() {
        let dir = scratch_dir("png16");
        let path = dir.join("sixteen.png");
        let raw: Vec<u16> = vec![0, 32768, 65535, 65535, 65535, 257, 0, 0];
        let buf = image::ImageBuffer::<image::Rgba<u16>, _>::from_raw(2, 1, raw).unwrap();
        buf.save(&path).unwrap();
        let img = load(&path).unwrap();
        assert_eq!(img.encoded_max, 65535.0);
        assert_eq!(img.encoded[0], [0.0, 32768.0, 65535.0, 65535.0]);
        assert_eq!(img.display[0], [0, 128, 255]);
        assert_eq!(img.display[1], [255, 1, 0]);
        assert!((img.linear[0][1] - srgb_decode(32768.0 / 65535.0)).abs() < 1e-7);
        assert_eq!(img.linear[1][3], 0.0);

        let path = dir.join("grey.png");
        image::GrayAlphaImage::from_raw(1, 1, vec![188, 51])
            .unwrap()
            .save(&path)
            .unwrap();
        let img = load(&path).unwrap();
        assert_eq!(img.encoded_max, 255.0);
        assert_eq!(img.encoded[0], [188.0, 188.0, 188.0, 51.0]);
        assert_eq!(img.display[0], [188; 3]);
        assert!((img.linear[0][3] - 0.2).abs() < 1e-7);
        fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn load_errors_name_the_file() {
        let dir = scratch_dir("errors");
        let missing = dir.join("missing.png");
        let err = load(&missing).unwrap_err();
        assert!(matches!(err, ImageError::NotFound { .. }));
        assert!(err.to_string().contains("missing.png"));

        let as_dir = dir.join("folder.exr");
        fs::create_dir(&as_dir).unwrap();
        let err = load(&as_dir).unwrap_err();
        assert!(matches!(err, ImageError::IsDirectory { .. }), "{err}");
        assert!(err.to_string().contains("folder.exr"));

        let garbage = dir.join("garbage.png");
        fs::write(&garbage, b"this is not a png at all, just text").unwrap();
        let err = load(&garbage).unwrap_err();
        assert!(matches!(err, ImageError::Corrupt { .. }), "{err}");
        assert!(err.to_string().contains("garbage.png"), "{err}");

        let garbage = dir.join("garbage.exr");
        fs::write(&garbage, b"not an exr").unwrap();
        let err = load(&garbage).unwrap_err();
        assert!(matches!(err, ImageError::Corrupt { .. }), "{err}");
        assert!(err.to_string().contains("garbage.exr"), "{err}");

        // A valid PNG cut short after its header.
        let full = dir.join("full.png");
        save(&full, &gradient(64, 64), 0.0, Tonemap::None).unwrap();
        let bytes = fs::read(&full).unwrap();
        let cut = dir.join("cut.png");
        fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
        let err = load(&cut).unwrap_err();
        assert!(matches!(err, ImageError::Corrupt { .. }), "{err}");
        assert!(err.to_string().contains("cut.png"), "{err}");

        // PNG content behind an .exr name.
        let wrong = dir.join("wrong.exr");
        fs::copy(&full, &wrong).unwrap();
        let err = load(&wrong).unwrap_err();
        assert!(err.to_string().contains("wrong.exr"), "{err}");

        let err = load(&dir.join("x.tiff")).unwrap_err();
        assert!(matches!(err, ImageError::UnsupportedExtension { .. }));
        fs::remove_dir_all(dir).unwrap();
    }

    /// A PNG whose header declares `width × height` followed by a tiny IDAT and IEND.
    fn png_with_declared_size(width: u32, height: u32) -> Vec<u8> {
        fn crc32(bytes: &[u8]) -> u32 {
            let mut crc = 0xffff_ffffu32;
            for &b in bytes {
                crc ^= b as u32;
                for _ in 0..8 {
                    crc = if crc & 1 != 0 {
                        (crc >> 1) ^ 0xedb8_8320
                    } else {
                        crc >> 1
                    };
                }
            }
            !crc
        }
        fn chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
            out.extend((data.len() as u32).to_be_bytes());
            let mut body = kind.to_vec();
            body.extend(data);
            out.extend(&body);
            out.extend(crc32(&body).to_be_bytes());
        }
        let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
        let mut ihdr = Vec::new();
        ihdr.extend(width.to_be_bytes());
        ihdr.extend(height.to_be_bytes());
        ihdr.extend([8, 2, 0, 0, 0]); // 8-bit RGB
        chunk(&mut out, b"IHDR", &ihdr);
        chunk(
            &mut out,
            b"IDAT",
            &[0x78, 0x9c, 0x03, 0x00, 0x00, 0x00, 0x00, 0x01],
        );
        chunk(&mut out, b"IEND", &[]);
        out
    }

    #[test]
    fn absurd_declared_sizes_are_refused() {
        let dir = scratch_dir("huge");
        for (w, h) in [(100_000, 10), (10, 40_000), (2_000_000_000, 2_000_000_000)] {
            let path = dir.join(format!("huge-{w}x{h}.png"));
            fs::write(&path, png_with_declared_size(w, h)).unwrap();
            let err = load(&path).unwrap_err();
            assert!(matches!(err, ImageError::TooLarge { .. }), "{err}");
            let msg = err.to_string();
            assert!(msg.contains(&format!("{w}×{h}")), "{msg}");
            assert!(msg.contains(&format!("huge-{w}x{h}.png")), "{msg}");
        }
        // A size within the limits whose pixel data is missing fails as corrupt.
        let path = dir.join("ok-size-bad-data.png");
        fs::write(&path, png_with_declared_size(300, 200)).unwrap();
        let err = load(&path).unwrap_err();
        assert!(matches!(err, ImageError::Corrupt { .. }), "{err}");
        fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn save_errors() {
        let dir = scratch_dir("save");
        let img = gradient(4, 4);
        let path = dir.join("no/such/dir/out.png");
        let err = save(&path, &img, 0.0, Tonemap::None).unwrap_err();
        let msg = err.to_string();
        assert!(matches!(err, ImageError::Write { .. }));
        assert!(
            msg.starts_with("cannot write ") && msg.contains("out.png"),
            "{msg}"
        );
        assert!(msg.contains("No such file"), "{msg}");

        let as_dir = dir.join("taken.exr");
        fs::create_dir(&as_dir).unwrap();
        let err = save(&as_dir, &img, 0.0, Tonemap::None).unwrap_err();
        assert!(matches!(err, ImageError::Write { .. }), "{err}");

        let err = save(&dir.join("x.jpg"), &img, 0.0, Tonemap::None).unwrap_err();
        assert!(matches!(err, ImageError::UnsupportedExtension { .. }));

        let bad = LinearImage {
            width: 3,
            height: 3,
            pixels: vec![[0.0; 4]; 8],
        };
        let err = save(&dir.join("bad.png"), &bad, 0.0, Tonemap::None).unwrap_err();
        assert!(matches!(err, ImageError::Encode { .. }), "{err}");
        assert!(!dir.join("bad.png").exists());
        let empty = LinearImage::filled(0, 5, [0.0; 4]);
        assert!(save(&dir.join("empty.exr"), &empty, 0.0, Tonemap::None).is_err());
        fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn png_applies_exposure_and_tonemap() {
        let img = LinearImage::filled(2, 2, [0.25, 1.0, 4.0, 1.0]);
        let plain = LoadedImage::from_linear(&img, FileFormat::Png, 0.0, Tonemap::None);
        assert_eq!(plain.display[0], [137, 255, 255]);
        let exposed = LoadedImage::from_linear(&img, FileFormat::Png, 1.0, Tonemap::None);
        assert_eq!(exposed.display[0], [188, 255, 255]);
        let mapped = LoadedImage::from_linear(&img, FileFormat::Png, 0.0, Tonemap::Reinhard);
        assert_eq!(
            mapped.display[0],
            [0.2, 0.5, 0.8].map(crate::color::srgb_encode_u8)
        );
    }
}
