//! Provenance: the text metadata every PNG and EXR luz writes carries (PNG `iTXt` chunks, EXR
//! header text attributes), and reading it back (`luz info`, and `luz diff`/`luz golden` saying
//! where two images' origins differ).
//!
//! Keys start with `luz.`: always `luz.version` and `luz.commit` (the build's
//! `LUZ_GIT_COMMIT`, else `unknown`), `luz.size`, `luz.encoding`; renders add the device,
//! driver and Vulkan version, the scene path and a hash of its file, tone map, exposure and
//! frame-time medians ([`crate::provenance`]).

use std::fs::File;
use std::io::{BufReader, BufWriter, Write};
use std::path::Path;

use super::{FileFormat, ImageError};

/// Ordered `key = value` text pairs.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Provenance {
    pub entries: Vec<(String, String)>,
}

/// The commit luz was built from: `LUZ_GIT_COMMIT` at build time, else `unknown`.
pub fn build_commit() -> &'static str {
    option_env!("LUZ_GIT_COMMIT").unwrap_or("unknown")
}

impl Provenance {
    /// `luz.version` and `luz.commit`.
    pub fn base() -> Self {
        let mut p = Self::default();
        p.set("luz.version", env!("CARGO_PKG_VERSION"));
        p.set("luz.commit", build_commit());
        p
    }

    /// Sets `key` (replacing an earlier value, keeping its place).
    pub fn set(&mut self, key: &str, value: impl Into<String>) {
        let value = value.into();
        match self.entries.iter_mut().find(|(k, _)| k == key) {
            Some(e) => e.1 = value,
            None => self.entries.push((key.to_string(), value)),
        }
    }

    /// Sets `key` only when it is not set yet.
    pub fn set_default(&mut self, key: &str, value: impl Into<String>) {
        if self.get(key).is_none() {
            self.set(key, value);
        }
    }

    pub fn get(&self, key: &str) -> Option<&str> {
        self.entries
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Keys whose values differ between `self` (expected) and `other` (actual), in order of first
    /// appearance, with both values (`None`: absent on that side). Frame times (`luz.frame.*`)
    /// always differ and are left out.
    pub fn differences(&self, other: &Provenance) -> Vec<(String, Option<String>, Option<String>)> {
        let mut keys: Vec<&str> = self.entries.iter().map(|(k, _)| k.as_str()).collect();
        for (k, _) in &other.entries {
            if !keys.contains(&k.as_str()) {
                keys.push(k);
            }
        }
        keys.into_iter()
            .filter(|k| !k.starts_with("luz.frame."))
            .filter_map(|k| {
                let (a, b) = (self.get(k), other.get(k));
                (a != b).then(|| (k.to_string(), a.map(String::from), b.map(String::from)))
            })
            .collect()
    }

    /// [`Provenance::differences`] as lines `key: expected … | actual …`.
    pub fn difference_lines(&self, other: &Provenance) -> Vec<String> {
        self.differences(other)
            .into_iter()
            .map(|(k, a, b)| {
                format!(
                    "{k}: expected {} | actual {}",
                    a.as_deref().unwrap_or("(none)"),
                    b.as_deref().unwrap_or("(none)")
                )
            })
            .collect()
    }
}

/// FNV-1a, 64 bits, as 16 hex digits: the content hash of a scene file in provenance.
pub fn content_hash(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("fnv1a64:{h:016x}")
}

/// Writes 8-bit RGB as a PNG with `meta` as `iTXt` chunks.
pub(super) fn write_png(
    w: &mut BufWriter<File>,
    width: u32,
    height: u32,
    rgb: &[u8],
    meta: &Provenance,
) -> Result<(), String> {
    write_png_as(w, (width, height, png::ColorType::Rgb), rgb, meta)
}

/// [`write_png`] of 8-bit `bytes` in colour type `color` (RGB or RGBA).
pub(super) fn write_png_as(
    w: &mut BufWriter<File>,
    (width, height, color): (u32, u32, png::ColorType),
    bytes: &[u8],
    meta: &Provenance,
) -> Result<(), String> {
    let mut enc = png::Encoder::new(&mut *w, width, height);
    enc.set_color(color);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_compression(png::Compression::Balanced);
    enc.set_filter(png::Filter::Adaptive);
    for (k, v) in &meta.entries {
        enc.add_itxt_chunk(k.clone(), v.clone())
            .map_err(|e| e.to_string())?;
    }
    let mut writer = enc.write_header().map_err(|e| e.to_string())?;
    writer.write_image_data(bytes).map_err(|e| e.to_string())?;
    writer.finish().map_err(|e| e.to_string())?;
    w.flush().map_err(|e| e.to_string())
}

/// Writes linear RGBA f32 as an EXR with `meta` as header text attributes.
pub(super) fn write_exr(
    w: &mut BufWriter<File>,
    width: u32,
    height: u32,
    pixels: &[[f32; 4]],
    meta: &Provenance,
) -> Result<(), String> {
    use exr::prelude::*;
    let (wu, hu) = (width as usize, height as usize);
    let channels = SpecificChannels::rgba(|p: Vec2<usize>| {
        let px = pixels[p.y() * wu + p.x()];
        (px[0], px[1], px[2], px[3])
    });
    let mut image = Image::from_channels((wu, hu), channels);
    for (k, v) in &meta.entries {
        let (Some(key), Some(value)) = (Text::new_or_none(k), Text::new_or_none(v)) else {
            continue;
        };
        image
            .layer_data
            .attributes
            .other
            .insert(key, exr::meta::attribute::AttributeValue::Text(value));
    }
    image
        .write()
        .to_buffered(&mut *w)
        .map_err(|e| e.to_string())?;
    w.flush().map_err(|e| e.to_string())
}

/// The provenance stored in a PNG or EXR file (empty when it has none).
pub fn read(path: &Path) -> Result<Provenance, ImageError> {
    let format = FileFormat::from_path(path)?;
    let file = super::open_image_file(path)?;
    let corrupt = |reason: String| ImageError::Corrupt {
        path: path.to_path_buf(),
        format,
        reason,
    };
    let mut out = Provenance::default();
    match format {
        FileFormat::Png => {
            let decoder = png::Decoder::new(BufReader::new(file));
            let reader = decoder.read_info().map_err(|e| corrupt(e.to_string()))?;
            let info = reader.info();
            for t in &info.uncompressed_latin1_text {
                out.set(&t.keyword, t.text.clone());
            }
            for t in &info.compressed_latin1_text {
                if let Ok(text) = t.get_text() {
                    out.set(&t.keyword, text);
                }
            }
            for t in &info.utf8_text {
                if let Ok(text) = t.get_text() {
                    out.set(&t.keyword, text);
                }
            }
        }
        FileFormat::Exr => {
            let meta = exr::meta::MetaData::read_from_buffered(BufReader::new(file), false)
                .map_err(|e| corrupt(e.to_string()))?;
            if let Some(header) = meta.headers.first() {
                let mut pairs: Vec<(String, String)> = header
                    .own_attributes
                    .other
                    .iter()
                    .chain(header.shared_attributes.other.iter())
                    .filter_map(|(k, v)| match v {
                        exr::meta::attribute::AttributeValue::Text(t) => {
                            Some((k.to_string(), t.to_string()))
                        }
                        _ => None,
                    })
                    .collect();
                // A hash map: luz's keys in a stable order.
                pairs.sort();
                for (k, v) in pairs {
                    out.set(&k, v);
                }
            }
        }
    }
    Ok(out)
}

/// The id of the `<metadata>` element luz writes into its SVG charts.
const SVG_METADATA_ID: &str = "luz-provenance";

/// `svg` with a `<metadata id="luz-provenance">` element holding `meta` as `key: value` lines
/// (XML-escaped), right after the root element's start tag.
pub fn svg_with_metadata(svg: &str, meta: &Provenance) -> String {
    let escape = |s: &str| {
        s.replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;")
            .replace('\n', " ")
    };
    let mut block = format!("\n<metadata id=\"{SVG_METADATA_ID}\">\n");
    for (k, v) in &meta.entries {
        block.push_str(&format!("{}: {}\n", escape(k), escape(v)));
    }
    block.push_str("</metadata>");
    match svg
        .find("<svg")
        .and_then(|i| svg[i..].find('>').map(|j| i + j + 1))
    {
        Some(at) => format!("{}{block}{}", &svg[..at], &svg[at..]),
        None => svg.to_string(),
    }
}

/// The provenance [`svg_with_metadata`] wrote into an SVG file (empty when it has none).
pub fn read_svg(path: &Path) -> Result<Provenance, std::io::Error> {
    let text = crate::files::read_input_text(path)?;
    let mut out = Provenance::default();
    let open = format!("<metadata id=\"{SVG_METADATA_ID}\">");
    let Some(start) = text.find(&open).map(|i| i + open.len()) else {
        return Ok(out);
    };
    let end = text[start..]
        .find("</metadata>")
        .map_or(text.len(), |j| start + j);
    let unescape = |s: &str| {
        s.replace("&lt;", "<")
            .replace("&gt;", ">")
            .replace("&amp;", "&")
    };
    for line in text[start..end].lines() {
        if let Some((k, v)) = line.split_once(": ") {
            out.set(&unescape(k), unescape(v));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::Tonemap;
    use crate::imageio::{save, save_png_rgb8, save_with, LinearImage};

    #[test]
    fn png_and_exr_carry_provenance() {
        let dir = std::env::temp_dir().join(format!("luz-provenance-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let img = LinearImage::filled(5, 3, [0.25, 0.5, 1.5, 1.0]);
        let mut meta = Provenance::base();
        meta.set("luz.device", "llvmpipe × test"); // not Latin-1: iTXt keeps it
        meta.set("luz.scene", "a/b.json");
        for ext in ["png", "exr"] {
            let path = dir.join(format!("p.{ext}"));
            save_with(&path, &img, 1.0, Tonemap::Reinhard, &meta).unwrap();
            let read = read(&path).unwrap();
            assert_eq!(read.get("luz.device"), Some("llvmpipe × test"), "{ext}");
            assert_eq!(read.get("luz.scene"), Some("a/b.json"), "{ext}");
            assert_eq!(read.get("luz.version"), Some(env!("CARGO_PKG_VERSION")));
            assert_eq!(read.get("luz.commit"), Some(build_commit()));
            assert_eq!(read.get("luz.size"), Some("5x3"), "{ext}");
            // The pixels are untouched by the metadata.
            let loaded = crate::imageio::load(&path).unwrap();
            assert_eq!((loaded.width, loaded.height), (5, 3));
            if ext == "exr" {
                assert_eq!(loaded.linear[0], [0.25, 0.5, 1.5, 1.0]);
                assert!(read.get("luz.encoding").unwrap().contains("linear"));
            } else {
                assert_eq!(read.get("luz.tonemap"), Some("reinhard"));
                assert_eq!(read.get("luz.exposure_ev"), Some("1"));
            }
        }
        // Plain saves and heat maps carry the base.
        let plain = dir.join("plain.png");
        save(&plain, &img, 0.0, Tonemap::None).unwrap();
        assert_eq!(read(&plain).unwrap().get("luz.tonemap"), Some("none"));
        let heat = dir.join("heat.png");
        save_png_rgb8(&heat, 1, 1, &[1, 2, 3]).unwrap();
        assert!(read(&heat).unwrap().get("luz.commit").is_some());
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn differences_leave_out_frame_times() {
        let mut a = Provenance::base();
        a.set("luz.driver", "Mesa 22.3.6");
        a.set("luz.frame.cpu_median_ms", "1.0");
        let mut b = a.clone();
        b.set("luz.driver", "Mesa 24.0.1");
        b.set("luz.frame.cpu_median_ms", "2.0");
        b.set("luz.scene", "x.json");
        assert_eq!(
            a.difference_lines(&b),
            [
                "luz.driver: expected Mesa 22.3.6 | actual Mesa 24.0.1",
                "luz.scene: expected (none) | actual x.json"
            ]
        );
        assert!(a.differences(&a).is_empty());
        assert_eq!(content_hash(b""), "fnv1a64:cbf29ce484222325");
    }
}
