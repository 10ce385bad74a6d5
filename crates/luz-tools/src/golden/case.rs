//! Case files: a sidecar `<name>.golden.json` that names its scene, so a folder of goldens runs
//! as it is (`luz golden tests/golden --goldens tests/golden`), each golden beside the file that
//! says how to make it.
//!
//! Besides the tolerance fields ([`super::ToleranceOverrides`]) a case file may hold:
//!
//! * `scene`: the scene file or model (relative to the case file's folder);
//! * `width`, `height`: the output size, set on the loaded scene as it is (its automatic
//!   tessellation stays the one of the size the scene file gives);
//! * `ibl`: `"full"` or `"fast"`, the image-based lighting sizes of this case (else the run's);
//! * `mask`: a PNG of the golden's size (relative to the case file's folder) whose white pixels
//!   (grey value ≥ 128) are ignored by every check;
//! * `regions`: a list of areas with their own tolerances, each `{"name": …, "rect": [x, y, w, h]}`
//!   or `{"name": …, "mask": "FILE.png"}` (white = inside) plus any tolerance field; a pixel in
//!   several regions belongs to the first, and a region's pixels leave the case's own check;
//! * `ignore_antialiasing`: `true` forgives pixels that differ where either image is
//!   anti-aliasing (pixelmatch's detector, [`crate::diff::pixelmatch::antialiased`]).

use std::path::{Path, PathBuf};

use crate::diff::ToleranceOverrides;
use crate::scene::Scene;

/// The case fields luz reads from a sidecar besides the tolerances.
pub const CASE_FIELDS: &[&str] = &[
    "scene",
    "width",
    "height",
    "ibl",
    "mask",
    "regions",
    "ignore_antialiasing",
];

/// Where a region is.
#[derive(Debug, Clone, PartialEq)]
pub enum RegionArea {
    /// `[x, y, width, height]` in pixels from the top-left corner.
    Rect([u32; 4]),
    /// A PNG whose white pixels are the region (resolved against the case file's folder).
    Mask(PathBuf),
}

/// A region of a case file: an area with its own tolerances.
#[derive(Debug, Clone, PartialEq)]
pub struct Region {
    /// Its `name`, else `regions[i]`.
    pub name: String,
    /// `regions[i]` (for messages).
    pub field: String,
    pub area: RegionArea,
    /// Applied to the case's tolerances inside the region.
    pub tolerance: ToleranceOverrides,
}

/// What a case leaves out of its check or checks apart: its mask, its regions and whether
/// anti-aliased differences are forgiven.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Masking {
    /// The case file (for messages).
    pub case_file: PathBuf,
    pub mask: Option<PathBuf>,
    pub regions: Vec<Region>,
    pub ignore_antialiasing: bool,
}

impl Masking {
    pub fn is_empty(&self) -> bool {
        self.mask.is_none() && self.regions.is_empty() && !self.ignore_antialiasing
    }
}

/// A case file read.
#[derive(Debug, Clone, PartialEq)]
pub struct CaseFile {
    /// The case file itself.
    pub path: PathBuf,
    /// Resolved against the case file's folder (`None`: a plain sidecar of tolerances).
    pub scene: Option<PathBuf>,
    pub width: Option<u32>,
    pub height: Option<u32>,
    /// `Some(true)`: the fast IBL sizes; `Some(false)`: the full ones.
    pub fast_ibl: Option<bool>,
    pub tolerance: ToleranceOverrides,
    /// The mask, regions and anti-aliasing option.
    pub masking: Masking,
}

impl CaseFile {
    /// Reads and checks `path`; every message names the file and the field.
    pub fn read(path: &Path) -> Result<Self, String> {
        let at = |field: &str, reason: String| format!("{}: {field}: {reason}", path.display());
        let text =
            crate::files::read_input_text(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut value: serde_json::Value = serde_json::from_str(&text)
            .map_err(|e| format!("{}: not valid JSON: {e}", path.display()))?;
        let obj = value
            .as_object_mut()
            .ok_or_else(|| format!("{}: a sidecar is a JSON object", path.display()))?;
        let dir = path.parent().unwrap_or(Path::new(""));
        let scene = match obj.remove("scene") {
            None => None,
            Some(serde_json::Value::String(s)) if !s.is_empty() => Some(dir.join(s)),
            Some(v) => return Err(at("scene", format!("must be a file name, not {v}"))),
        };
        let size = |v: Option<serde_json::Value>, key: &str| -> Result<Option<u32>, String> {
            match v {
                None => Ok(None),
                Some(v) => match v.as_u64() {
                    Some(n) if (1..=u64::from(crate::scene::MAX_IMAGE_SIZE)).contains(&n) => {
                        Ok(Some(n as u32))
                    }
                    _ => Err(at(
                        key,
                        format!(
                            "must be a whole number of pixels in 1..={}, not {v}",
                            crate::scene::MAX_IMAGE_SIZE
                        ),
                    )),
                },
            }
        };
        let width = size(obj.remove("width"), "width")?;
        let height = size(obj.remove("height"), "height")?;
        let fast_ibl = match obj.remove("ibl") {
            None => None,
            Some(v) => match v.as_str() {
                Some("fast") => Some(true),
                Some("full") => Some(false),
                _ => return Err(at("ibl", format!("must be \"full\" or \"fast\", not {v}"))),
            },
        };
        let mut masking = Masking {
            case_file: path.to_path_buf(),
            ..Masking::default()
        };
        masking.mask = match obj.remove("mask") {
            None => None,
            Some(serde_json::Value::String(s)) if !s.is_empty() => Some(dir.join(s)),
            Some(v) => return Err(at("mask", format!("must be a PNG file name, not {v}"))),
        };
        masking.ignore_antialiasing = match obj.remove("ignore_antialiasing") {
            None => false,
            Some(serde_json::Value::Bool(b)) => b,
            Some(v) => {
                return Err(at(
                    "ignore_antialiasing",
                    format!("must be true or false, not {v}"),
                ))
            }
        };
        if let Some(v) = obj.remove("regions") {
            let list = v
                .as_array()
                .ok_or_else(|| at("regions", format!("must be a list of regions, not {v}")))?;
            for (i, r) in list.iter().enumerate() {
                masking
                    .regions
                    .push(parse_region(r, i, dir).map_err(|(f, reason)| at(&f, reason))?);
            }
        }
        if scene.is_none() && (width.is_some() || height.is_some() || fast_ibl.is_some()) {
            return Err(at(
                "scene",
                "missing: width, height and ibl apply to the case file's own scene".into(),
            ));
        }
        let tolerance = ToleranceOverrides::parse(&value).map_err(|e| match e.field.as_str() {
            "" => format!("{}: {}", path.display(), e.reason),
            f => at(f, e.reason),
        })?;
        Ok(CaseFile {
            path: path.to_path_buf(),
            scene,
            width,
            height,
            fast_ibl,
            tolerance,
            masking,
        })
    }

    /// Loads the case's scene at the case's size.
    pub fn load_scene(&self) -> Result<Scene, String> {
        let path = self.scene.as_ref().ok_or_else(|| {
            format!(
                "{}: scene: missing (a sidecar of tolerances only)",
                self.path.display()
            )
        })?;
        let mut scene = crate::scene::load(path).map_err(|e| e.to_string())?;
        if let Some(w) = self.width {
            scene.output.width = w;
        }
        if let Some(h) = self.height {
            scene.output.height = h;
        }
        Ok(scene)
    }
}

/// One entry of `regions`; errors are (field path, reason).
fn parse_region(v: &serde_json::Value, i: usize, dir: &Path) -> Result<Region, (String, String)> {
    let field = format!("regions[{i}]");
    let mut obj = v
        .as_object()
        .ok_or_else(|| (field.clone(), format!("must be an object, not {v}")))?
        .clone();
    let name = match obj.remove("name") {
        None => field.clone(),
        Some(serde_json::Value::String(s)) if !s.is_empty() => s,
        Some(v) => {
            return Err((
                format!("{field}.name"),
                format!("must be a string, not {v}"),
            ))
        }
    };
    let rect = obj.remove("rect");
    let mask = obj.remove("mask");
    let area = match (rect, mask) {
        (Some(r), None) => {
            let nums: Option<Vec<u32>> = r.as_array().and_then(|a| {
                a.iter()
                    .map(|x| x.as_u64().and_then(|n| u32::try_from(n).ok()))
                    .collect()
            });
            match nums.as_deref() {
                Some(&[x, y, w, h]) if w > 0 && h > 0 => RegionArea::Rect([x, y, w, h]),
                _ => {
                    return Err((
                        format!("{field}.rect"),
                        format!("must be [x, y, width, height] in whole pixels (width, height ≥ 1), not {r}"),
                    ))
                }
            }
        }
        (None, Some(serde_json::Value::String(s))) if !s.is_empty() => {
            RegionArea::Mask(dir.join(s))
        }
        (None, Some(m)) => {
            return Err((
                format!("{field}.mask"),
                format!("must be a PNG file name, not {m}"),
            ))
        }
        (Some(_), Some(_)) => {
            return Err((field, "has both rect and mask: give one".into()));
        }
        (None, None) => return Err((field, "needs a rect or a mask".into())),
    };
    let tolerance = ToleranceOverrides::parse(&serde_json::Value::Object(obj)).map_err(|e| {
        let f = if e.field.is_empty() {
            field.clone()
        } else {
            format!("{field}.{}", e.field)
        };
        (f, e.reason)
    })?;
    Ok(Region {
        name,
        field,
        area,
        tolerance,
    })
}

/// Pixels of a mask PNG that are white (grey value ≥ 128), row-major; the PNG must be
/// `width × height`. Errors name the file.
pub fn read_mask(path: &Path, width: u32, height: u32) -> Result<Vec<bool>, String> {
    let bytes = crate::files::read_input(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let img = image::load_from_memory_with_format(&bytes, image::ImageFormat::Png)
        .map_err(|e| format!("{}: not a readable PNG: {e}", path.display()))?;
    if (img.width(), img.height()) != (width, height) {
        return Err(format!(
            "{}: the mask is {}×{}, the golden {width}×{height}",
            path.display(),
            img.width(),
            img.height()
        ));
    }
    Ok(img.to_luma8().pixels().map(|p| p.0[0] >= 128).collect())
}

/// Whether `path` is a case file: a sidecar with a `scene` field (read loosely; a broken one is
/// reported when its case runs).
pub fn names_a_scene(path: &Path) -> bool {
    crate::files::read_input_text(path)
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .is_some_and(|v| v.get("scene").is_some())
}
