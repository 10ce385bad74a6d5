//! OpenEXR headers checked against the size limits before the decoder allocates anything.

use super::*;

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

pub(super) fn scan_exr_headers<R: Read + Seek>(r: &mut R, limits: &SizeLimits) -> Option<String> {
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
