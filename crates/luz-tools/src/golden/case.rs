//! Case files: a sidecar `<name>.golden.json` that names its scene, so a folder of goldens runs
//! as it is (`luz golden tests/golden --goldens tests/golden`), each golden beside the file that
//! says how to make it.
//!
//! Besides the tolerance fields ([`super::ToleranceOverrides`]) a case file may hold:
//!
//! * `scene`: the scene file or model (relative to the case file's folder);
//! * `width`, `height`: the output size, set on the loaded scene as it is (its automatic
//!   tessellation stays the one of the size the scene file gives);
//! * `ibl`: `"full"` or `"fast"`, the image-based lighting sizes of this case (else the run's).

use std::path::{Path, PathBuf};

use crate::diff::ToleranceOverrides;
use crate::scene::Scene;

/// The case fields luz reads from a sidecar besides the tolerances.
pub const CASE_FIELDS: &[&str] = &["scene", "width", "height", "ibl"];

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

/// Whether `path` is a case file: a sidecar with a `scene` field (read loosely; a broken one is
/// reported when its case runs).
pub fn names_a_scene(path: &Path) -> bool {
    crate::files::read_input_text(path)
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .is_some_and(|v| v.get("scene").is_some())
}
