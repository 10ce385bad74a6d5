//! Image files: saving rendered linear images (PNG for display, EXR for measurement), loading
//! PNG/EXR files for `luz diff` and the golden-image tests, and loading environment maps
//! (Radiance `.hdr` or `.exr`, [`load_radiance`]) for image-based lighting.
//!
//! * **PNG** is written as 8-bit sRGB **RGB** (no alpha channel): exposure → tone map → clamp →
//!   sRGB encode ([`crate::color::to_display_rgba8`]); the renderer's alpha is not stored because
//!   the display pipeline makes every pixel opaque. A scene with a transparent background
//!   ([`save_render`]) is written RGBA with straight alpha, its coverage. PNGs are read as 8- or 16-bit, grey or colour,
//!   with or without alpha, and are always interpreted as sRGB (gAMA/iCCP chunks are ignored).
//! * **EXR** is written as linear 32-bit float RGBA, untouched: no exposure, no tone map, no clamp,
//!   NaN and Inf preserved. EXRs are read as linear float RGB(A) (alpha 1 when absent).
//!
//! Declared image sizes are checked before any pixel memory is allocated: at most
//! [`MAX_DIMENSION`] per side, [`MAX_PIXELS`] in total and [`MAX_DECODE_BYTES`] of decoded data.

use std::fmt;
use std::fs::{self, File};
use std::io::{self, BufRead, BufReader, BufWriter, Cursor, Read, Seek};
use std::path::{Path, PathBuf};

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
        match crate::files::lowercase_extension(path).as_deref() {
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

/// An image file that could not be opened or read: what [`ImageError`] and
/// [`crate::texture::TextureError`] share. Every message names the file.
#[derive(Debug, thiserror::Error)]
pub enum FileError {
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
}

impl FileError {
    /// The error of reading `path`: [`FileError::NotFound`] for a missing file, else
    /// [`FileError::Read`].
    pub fn read(path: &Path, e: io::Error) -> Self {
        if e.kind() == io::ErrorKind::NotFound {
            FileError::NotFound {
                path: path.to_path_buf(),
            }
        } else {
            FileError::Read {
                path: path.to_path_buf(),
                source: e,
            }
        }
    }

    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            FileError::NotFound { path }
            | FileError::IsDirectory { path }
            | FileError::Read { path, .. } => path,
        }
    }
}

/// Opens an image file for reading (within the input budget, [`crate::files::open_input`]); a
/// directory or a missing file is reported as such.
pub fn open_image_file(path: &Path) -> Result<File, FileError> {
    let meta = fs::metadata(path).map_err(|e| FileError::read(path, e))?;
    if meta.is_dir() {
        return Err(FileError::IsDirectory {
            path: path.to_path_buf(),
        });
    }
    crate::files::open_input(path).map_err(|e| FileError::read(path, e))
}

/// Everything that can go wrong reading or writing an image file. Every message names the file.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    #[error(transparent)]
    File(#[from] FileError),
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
    let px = rgb.chunks_exact(3).map(|p| [p[0], p[1], p[2], 255]);
    from_srgb_codes(width, height, px, 255.0, srgb_decode_u8, |c| c)
}

fn from_rgba8(width: u32, height: u32, rgba: &[u8]) -> LoadedImage {
    let px = rgba.chunks_exact(4).map(|p| [p[0], p[1], p[2], p[3]]);
    from_srgb_codes(width, height, px, 255.0, srgb_decode_u8, |c| c)
}

fn from_rgba16(width: u32, height: u32, rgba: &[u16]) -> LoadedImage {
    let px = rgba.chunks_exact(4).map(|p| [p[0], p[1], p[2], p[3]]);
    let dec = |v: u16| srgb_decode(v as f32 / 65535.0);
    let to8 = |v: u16| (v as f32 / 257.0).round() as u8;
    from_srgb_codes(width, height, px, 65535.0, dec, to8)
}

/// A PNG from its RGBA codes (0 to `max`): sRGB colour that `decode` turns into linear light and
/// `to8` into the 8-bit code displayed, linear alpha.
fn from_srgb_codes<T: Copy + Into<f32>>(
    width: u32,
    height: u32,
    px: impl Iterator<Item = [T; 4]> + Clone,
    max: f32,
    decode: impl Fn(T) -> f32,
    to8: impl Fn(T) -> u8,
) -> LoadedImage {
    LoadedImage {
        width,
        height,
        format: FileFormat::Png,
        linear: px
            .clone()
            .map(|p| [decode(p[0]), decode(p[1]), decode(p[2]), p[3].into() / max])
            .collect(),
        display: px
            .clone()
            .map(|p| [to8(p[0]), to8(p[1]), to8(p[2])])
            .collect(),
        encoded: px.map(|p| p.map(Into::into)).collect(),
        encoded_max: max,
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
/// written by a failed encode is removed. The file carries [`Provenance::base`] and what this
/// call knows (size, encoding, tone map and exposure); [`save_with`] adds more.
pub fn save(
    path: &Path,
    img: &LinearImage,
    exposure_ev: f32,
    tonemap: Tonemap,
) -> Result<(), ImageError> {
    save_with(path, img, exposure_ev, tonemap, &Provenance::base())
}

/// [`save`] with provenance `meta` (the device, the scene, frame times: see
/// [`crate::provenance`]); `luz.version`, `luz.commit`, `luz.size`, `luz.encoding` and, for PNG,
/// `luz.tonemap` and `luz.exposure_ev` are filled in when `meta` lacks them.
pub fn save_with(
    path: &Path,
    img: &LinearImage,
    exposure_ev: f32,
    tonemap: Tonemap,
    meta: &Provenance,
) -> Result<(), ImageError> {
    save_as(path, img, (exposure_ev, tonemap, false), meta)
}

/// How a render becomes display codes: the scene's `output` settings
/// ([`crate::scene::Output::encoding`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Encoding {
    pub exposure_ev: f32,
    pub tonemap: Tonemap,
    /// Keep the alpha (the coverage) in PNGs: a transparent background.
    pub transparent: bool,
}

/// Saves a render with its scene's encoding: its exposure and tone map, and, when its
/// background is transparent ([`crate::scene::Output::transparent`]), its alpha,
/// which is then its coverage (0 where no object is, fractional on anti-aliased edges, the
/// colour premultiplied by it). PNG: 8-bit sRGB **RGBA** with straight alpha, each colour
/// divided by its alpha before exposure and tone map ([`to_straight_rgba8`]: an edge pixel
/// composited over white shows the object's colour blended with white, as a browser shows it);
/// EXR: linear RGBA as rendered (premultiplied, as OpenEXR defines it).
pub fn save_render(
    path: &Path,
    img: &LinearImage,
    encoding: Encoding,
    meta: &Provenance,
) -> Result<(), ImageError> {
    let Encoding {
        exposure_ev,
        tonemap,
        transparent,
    } = encoding;
    save_as(path, img, (exposure_ev, tonemap, transparent), meta)
}

/// The straight-alpha display codes of premultiplied linear pixels: colour / alpha tone-mapped,
/// alpha clamped to [0, 1] and rounded to 8 bits; alpha 0 is (0, 0, 0, 0).
pub fn to_straight_rgba8(pixels: &[[f32; 4]], exposure_ev: f32, tonemap: Tonemap) -> Vec<u8> {
    let straight: Vec<[f32; 4]> = pixels
        .iter()
        .map(|p| {
            let a = if p[3].is_nan() {
                0.0
            } else {
                p[3].clamp(0.0, 1.0)
            };
            let inv = if a > 0.0 { 1.0 / a } else { 0.0 };
            [p[0] * inv, p[1] * inv, p[2] * inv, a]
        })
        .collect();
    let mut codes = to_display_rgba8(&straight, exposure_ev, tonemap);
    for (c, p) in codes.chunks_exact_mut(4).zip(&straight) {
        c[3] = (p[3] * 255.0).round() as u8;
    }
    codes
}

fn save_as(
    path: &Path,
    img: &LinearImage,
    (exposure_ev, tonemap, transparent): (f32, Tonemap, bool),
    meta: &Provenance,
) -> Result<(), ImageError> {
    let format = FileFormat::from_path(path)?;
    check_buffer(path, img.width, img.height, img.pixels.len())?;
    let mut meta = complete(meta, img.width, img.height);
    match format {
        FileFormat::Png => {
            meta.set_default("luz.encoding", "8-bit sRGB, exposed and tone-mapped");
            meta.set_default("luz.tonemap", tonemap.name());
            meta.set_default("luz.exposure_ev", exposure_ev.to_string());
            if transparent {
                meta.set_default("luz.alpha", "coverage, straight (colour not premultiplied)");
                let rgba = to_straight_rgba8(&img.pixels, exposure_ev, tonemap);
                let size = (img.width, img.height, png::ColorType::Rgba);
                return write_with_meta(path, |w| provenance::write_png_as(w, size, &rgba, &meta));
            }
            let rgba = to_display_rgba8(&img.pixels, exposure_ev, tonemap);
            let rgb: Vec<u8> = rgba
                .chunks_exact(4)
                .flat_map(|p| [p[0], p[1], p[2]])
                .collect();
            write_with_meta(path, |w| {
                provenance::write_png(w, img.width, img.height, &rgb, &meta)
            })
        }
        FileFormat::Exr => {
            meta.set_default(
                "luz.encoding",
                "linear float32 radiance (no exposure, no tone map)",
            );
            write_with_meta(path, |w| {
                provenance::write_exr(w, img.width, img.height, &img.pixels, &meta)
            })
        }
    }
}

fn complete(meta: &Provenance, width: u32, height: u32) -> Provenance {
    let mut m = meta.clone();
    let base = Provenance::base();
    for (k, v) in base.entries.into_iter().rev() {
        if m.get(&k).is_none() {
            m.entries.insert(0, (k, v));
        }
    }
    m.set_default("luz.size", format!("{width}x{height}"));
    m
}

/// Writes tightly packed 8-bit RGB bytes as a PNG (used for FLIP heat maps and other
/// already-display-encoded images). The path must end in `.png`.
pub fn save_png_rgb8(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<(), ImageError> {
    let mut meta = Provenance::base();
    meta.set("luz.encoding", "8-bit sRGB (display image)");
    save_png_rgb8_with(path, width, height, rgb, &meta)
}

/// [`save_png_rgb8`] with provenance `meta`.
pub fn save_png_rgb8_with(
    path: &Path,
    width: u32,
    height: u32,
    rgb: &[u8],
    meta: &Provenance,
) -> Result<(), ImageError> {
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
    let meta = complete(meta, width, height);
    write_with_meta(path, |w| {
        provenance::write_png(w, width, height, rgb, &meta)
    })
}

/// Creates `path` and runs `encode` on it; an I/O failure is a write error, anything else an
/// encode error; a half-written file is removed.
fn write_with_meta(
    path: &Path,
    encode: impl FnOnce(&mut BufWriter<File>) -> Result<(), String>,
) -> Result<(), ImageError> {
    let file = File::create(path).map_err(|source| ImageError::Write {
        path: path.to_path_buf(),
        source,
    })?;
    let mut writer = BufWriter::new(file);
    let result = encode(&mut writer).map_err(|reason| ImageError::Encode {
        path: path.to_path_buf(),
        reason,
    });
    if result.is_err() {
        drop(writer);
        let _ = fs::remove_file(path);
    }
    result
}

/// The reason in `image`'s decoding error: its messages read "Format error decoding Png:
/// <reason>"; the reason is kept (the caller names the file and format).
pub(crate) fn corrupt_reason(e: &image::ImageError) -> String {
    let text = e.to_string();
    match text.split_once(": ") {
        Some((head, rest)) if head.starts_with("Format error") => rest.to_string(),
        _ => text,
    }
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
    let file = open_image_file(path)?;
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

/// The decoding shared by [`load`] and [`load_bytes`]; `declared` reads the size the file
/// declares (for the message when a limit is hit inside the decoder).
fn load_from<R: BufRead + Seek>(
    reader: R,
    path: &Path,
    format: FileFormat,
    limits: &SizeLimits,
    declared: impl Fn() -> Option<(u32, u32)>,
) -> Result<LoadedImage, ImageError> {
    let img = decode_checked(reader, format.image_format(), limits, None)
        .map_err(|p| p.image_error(path, format, &declared))?;
    let (width, height) = (img.width(), img.height());

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

/// Why an image could not be decoded, before the caller words it as its own error (the
/// file's path and format are the caller's): what [`decode_checked`] finds.
pub(crate) enum DecodeProblem {
    /// Reading the file failed.
    Read(io::Error),
    /// Over the size limits: what the file declares, found before the decoder allocates.
    TooLarge(String),
    /// Over the decoder's own limits.
    Limits(image::error::LimitError),
    /// A kind of file the decoder does not support.
    Unsupported(String),
    /// Not a valid file: why.
    Corrupt(String),
}

impl From<image::ImageError> for DecodeProblem {
    fn from(e: image::ImageError) -> Self {
        match e {
            image::ImageError::IoError(source) if source.kind() == io::ErrorKind::UnexpectedEof => {
                DecodeProblem::Corrupt("file is truncated".into())
            }
            image::ImageError::IoError(source) => DecodeProblem::Read(source),
            image::ImageError::Limits(l) => DecodeProblem::Limits(l),
            image::ImageError::Unsupported(u) => DecodeProblem::Unsupported(u.to_string()),
            other => DecodeProblem::Corrupt(corrupt_reason(&other)),
        }
    }
}

impl DecodeProblem {
    /// As an [`ImageError`]; `declared` reads the size the file declares (for the message when
    /// a limit is hit inside the decoder).
    fn image_error(
        self,
        path: &Path,
        format: FileFormat,
        declared: &dyn Fn() -> Option<(u32, u32)>,
    ) -> ImageError {
        let path = path.to_path_buf();
        match self {
            DecodeProblem::Read(source) => FileError::Read { path, source }.into(),
            DecodeProblem::TooLarge(declared) => ImageError::TooLarge { path, declared },
            DecodeProblem::Limits(_) => ImageError::TooLarge {
                declared: declared()
                    .map(|(w, h)| format!("declared {w}×{h}"))
                    .unwrap_or_else(|| "declared size over the limits".into()),
                path,
            },
            DecodeProblem::Unsupported(reason) => ImageError::Unsupported {
                path,
                format,
                reason,
            },
            DecodeProblem::Corrupt(reason) => ImageError::Corrupt {
                path,
                format,
                reason,
            },
        }
    }
}

/// Decodes an image of `format` from `reader` under `limits`, refusing an image over them before
/// any pixel memory is allocated (an EXR's headers scanned first, reported after the decoder has
/// read and validated the header; then the size the decoder reads, at `pixel_bytes` per pixel
/// when the caller widens the pixels, else the decoder's own) and an empty one: the decoding of
/// image files ([`load`]), environment images ([`load_radiance`]) and textures
/// ([`crate::texture`]).
pub(crate) fn decode_checked<R: BufRead + Seek>(
    mut reader: R,
    format: ImageFormat,
    limits: &SizeLimits,
    pixel_bytes: Option<u64>,
) -> Result<DynamicImage, DecodeProblem> {
    let exr_too_large = match format {
        ImageFormat::OpenExr => exr_header_exceeds(&mut reader, limits),
        _ => None,
    };
    let mut reader = ImageReader::with_format(reader, format);
    reader.limits(limits.image_limits());
    let decoder = reader.into_decoder()?;
    if let Some(declared) = exr_too_large {
        return Err(DecodeProblem::TooLarge(declared));
    }
    let (width, height) = decoder.dimensions();
    let bytes = match pixel_bytes {
        Some(b) => u64::from(width) * u64::from(height) * b,
        None => decoder.total_bytes(),
    };
    if limits.exceeded(width, height, bytes) {
        return Err(DecodeProblem::TooLarge(format!(
            "declared {width}×{height}"
        )));
    }
    if width == 0 || height == 0 {
        return Err(DecodeProblem::Corrupt(format!(
            "empty image ({width}×{height})"
        )));
    }
    Ok(DynamicImage::from_decoder(decoder)?)
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

mod exr;
pub mod provenance;
mod radiance;

pub use provenance::Provenance;

pub use exr::exr_header_exceeds;
pub use radiance::{load_radiance, load_radiance_bytes, RADIANCE_SUPPORTED};

#[cfg(test)]
mod tests;
