//! Linear radiance images for image-based lighting: Radiance `.hdr` (RGBE) and OpenEXR.

use super::*;

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
            let file = open_image_file(path)?;
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

pub(super) enum RadianceKind {
    Hdr,
    Exr,
}

pub(super) fn radiance_kind(path: &Path) -> Result<RadianceKind, ImageError> {
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

pub(super) fn load_hdr<R: BufRead + Seek>(
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
        image::ImageError::IoError(source) => super::FileError::Read {
            path: path.to_path_buf(),
            source,
        }
        .into(),
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
