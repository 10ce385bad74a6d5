//! Per-scene tolerances: the fields of a sidecar `<name>.golden.json` and of a scene's
//! `output.golden`, each overriding some checks of a base [`Tolerance`].
//!
//! Order: the golden-image defaults (or `luz golden`'s), then the scene's `output.golden`, then a
//! sidecar, each field of a later one replacing the earlier value (the sidecar wins: it sits next
//! to the goldens, which CI owns, while the scene may come from elsewhere).

use super::Tolerance;

/// The known fields, in the order the messages list them.
pub const FIELDS: &[&str] = &[
    "max_flip_mean",
    "max_abs",
    "max_bad_pixels",
    "bad_pixel_threshold",
];

/// Which checks a sidecar or `output.golden` changes: `None` keeps the base's value,
/// `Some(None)` turns the check off.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ToleranceOverrides {
    pub max_flip_mean: Option<Option<f32>>,
    /// 8-bit steps.
    pub max_abs: Option<Option<f32>>,
    pub max_bad_pixels: Option<Option<u64>>,
    /// 8-bit steps.
    pub bad_pixel_threshold: Option<f32>,
}

/// Why overrides could not be read: the field (empty for the whole value) and the reason.
#[derive(Debug, Clone, PartialEq)]
pub struct OverrideError {
    pub field: String,
    pub reason: String,
}

impl std::fmt::Display for OverrideError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.field.is_empty() {
            write!(f, "{}", self.reason)
        } else {
            write!(f, "{}: {}", self.field, self.reason)
        }
    }
}

impl ToleranceOverrides {
    /// True when nothing is overridden.
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }

    /// `base` with these fields replaced.
    pub fn apply(&self, base: Tolerance) -> Tolerance {
        Tolerance {
            max_flip_mean: self.max_flip_mean.unwrap_or(base.max_flip_mean),
            max_abs: self.max_abs.unwrap_or(base.max_abs),
            max_bad_pixels: self.max_bad_pixels.unwrap_or(base.max_bad_pixels),
            bad_pixel_threshold: self.bad_pixel_threshold.unwrap_or(base.bad_pixel_threshold),
        }
    }

    /// Reads a JSON object with any of [`FIELDS`]: `max_flip_mean`, `max_abs` (8-bit steps),
    /// `max_bad_pixels` (a whole number), each ≥ 0 or null (no check), and
    /// `bad_pixel_threshold` (8-bit steps, a number ≥ 0). Unknown fields are errors.
    pub fn parse(value: &serde_json::Value) -> Result<Self, OverrideError> {
        let err = |field: &str, reason: String| OverrideError {
            field: field.to_string(),
            reason,
        };
        let obj = value
            .as_object()
            .ok_or_else(|| err("", "must be a JSON object of tolerances".into()))?;
        let number = |key: &str, v: &serde_json::Value| -> Result<Option<f64>, OverrideError> {
            if v.is_null() {
                return Ok(None);
            }
            match v.as_f64() {
                Some(x) if x.is_finite() && x >= 0.0 => Ok(Some(x)),
                _ => Err(err(
                    key,
                    format!("must be a number ≥ 0 or null (no check), not {v}"),
                )),
            }
        };
        let mut o = Self::default();
        for (key, v) in obj {
            match key.as_str() {
                "max_flip_mean" => o.max_flip_mean = Some(number(key, v)?.map(|x| x as f32)),
                "max_abs" => o.max_abs = Some(number(key, v)?.map(|x| x as f32)),
                "max_bad_pixels" => {
                    o.max_bad_pixels = Some(match number(key, v)? {
                        Some(x) if x.fract() == 0.0 => Some(x as u64),
                        Some(_) => {
                            return Err(err(key, format!("must be a whole number, not {v}")))
                        }
                        None => None,
                    })
                }
                "bad_pixel_threshold" => {
                    o.bad_pixel_threshold = Some(
                        number(key, v)?.ok_or_else(|| err(key, "must be a number ≥ 0".into()))?
                            as f32,
                    )
                }
                other => {
                    return Err(err(
                        "",
                        format!("unknown field {other:?} (known: {})", FIELDS.join(", ")),
                    ))
                }
            }
        }
        Ok(o)
    }

    /// The fields as JSON (for the scene encoder): only those set, null for a check turned off.
    pub fn to_json(&self) -> serde_json::Value {
        let mut m = serde_json::Map::new();
        let opt = |v: Option<f64>| v.map_or(serde_json::Value::Null, |x| serde_json::json!(x));
        if let Some(v) = self.max_flip_mean {
            m.insert("max_flip_mean".into(), opt(v.map(f64::from)));
        }
        if let Some(v) = self.max_abs {
            m.insert("max_abs".into(), opt(v.map(f64::from)));
        }
        if let Some(v) = self.max_bad_pixels {
            m.insert(
                "max_bad_pixels".into(),
                v.map_or(serde_json::Value::Null, |x| x.into()),
            );
        }
        if let Some(v) = self.bad_pixel_threshold {
            m.insert("bad_pixel_threshold".into(), serde_json::json!(v));
        }
        serde_json::Value::Object(m)
    }
}

/// Reads a sidecar: [`ToleranceOverrides::parse`] of its JSON, applied to `base`.
pub fn read_sidecar(path: &std::path::Path, base: Tolerance) -> Result<Tolerance, String> {
    let text =
        crate::files::read_input_text(path).map_err(|e| format!("{}: {e}", path.display()))?;
    parse_sidecar(&text, base).map_err(|e| format!("{}: {e}", path.display()))
}

/// [`read_sidecar`] on text.
pub fn parse_sidecar(text: &str, base: Tolerance) -> Result<Tolerance, String> {
    let value: serde_json::Value =
        serde_json::from_str(text).map_err(|e| format!("not valid JSON: {e}"))?;
    ToleranceOverrides::parse(&value)
        .map(|o| o.apply(base))
        .map_err(|e| e.to_string())
}
