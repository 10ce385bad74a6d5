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
    match crate::files::lowercase_extension(path).as_deref() {
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
    let path_buf = path.to_path_buf();
    // Decoded as RGB f32 here, then widened to RGBA f32: 16 bytes per pixel in the end.
    let img = decode_checked(reader, ImageFormat::Hdr, limits, Some(16)).map_err(|p| match p {
        DecodeProblem::Read(source) => FileError::Read {
            path: path_buf,
            source,
        }
        .into(),
        DecodeProblem::TooLarge(declared) => ImageError::TooLarge {
            path: path_buf,
            declared,
        },
        DecodeProblem::Limits(_) => ImageError::TooLarge {
            path: path_buf,
            declared: "declared size over the limits".into(),
        },
        DecodeProblem::Unsupported(reason) | DecodeProblem::Corrupt(reason) => {
            ImageError::CorruptHdr {
                path: path_buf,
                reason,
            }
        }
    })?;
    let (width, height) = (img.width(), img.height());
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
