//! A light's `"shadow"`: `true`, `false` or an object of settings (scene::shadow).

use super::fields::*;
use super::Result;
use crate::scene::error::Invalid;
use crate::scene::json::{Kind, Value};
use crate::scene::shadow::{MAX_CASCADES, MAX_PCF_KERNEL, MAX_RESOLUTION, MIN_RESOLUTION};
use crate::scene::{CascadeSplit, LightKind, Shadow, ShadowMethod};

/// The shadow of a light of `kind` from `v` (at JSON path `path`); `has_size`: the light has a
/// radius or angular radius (PCSS needs one).
pub(super) fn shadow(
    v: &Value,
    path: &str,
    kind: LightKind,
    has_size: bool,
) -> Result<Option<Shadow>> {
    let mut s = Shadow::default_for(kind);
    match &v.kind {
        Kind::Bool(false) => return Ok(None),
        Kind::Bool(true) => return Ok(Some(s)),
        Kind::Object(_) => {}
        other => {
            return Err(Invalid::new(
                path,
                format!(
                    "expected true, false or an object of shadow settings, got {}",
                    other.describe()
                ),
            ))
        }
    }
    let f = Fields::new(v, path)?;
    let mut allowed = vec![
        "method",
        "resolution",
        "bias",
        "normal_bias",
        "slope_bias",
        "pcf_kernel",
    ];
    if kind == LightKind::Directional {
        allowed.extend(["cascades", "split", "split_lambda", "max_distance"]);
    }
    f.allow(
        &allowed,
        match kind {
            LightKind::Directional => "a directional light's shadow",
            LightKind::Point => "a point light's shadow",
            LightKind::Spot => "a spot light's shadow",
        },
    )?;
    let names: Vec<&str> = ShadowMethod::ALL.iter().map(|m| m.name()).collect();
    if let Some(m) = f.choice("method", &names)? {
        s.method = ShadowMethod::from_name(m).unwrap_or(s.method);
    }
    if s.method == ShadowMethod::Pcss && !has_size {
        return Err(f.err(
            "method",
            match kind {
                LightKind::Directional => {
                    "\"pcss\" needs the light's angular size: give it \"angular_radius_deg\" > 0 \
                     (the sun: 0.27)"
                }
                _ => "\"pcss\" needs the light's size: give it \"radius\" > 0 (metres)",
            },
        ));
    }
    s.resolution = f.int("resolution", s.resolution, MIN_RESOLUTION, MAX_RESOLUTION)?;
    s.bias = f.num("bias", s.bias, Check::NonNegative)?;
    s.normal_bias = f.num("normal_bias", s.normal_bias, Check::NonNegative)?;
    s.slope_bias = f.num("slope_bias", s.slope_bias, Check::NonNegative)?;
    s.pcf_kernel = f.int("pcf_kernel", s.pcf_kernel, 1, MAX_PCF_KERNEL)?;
    if kind == LightKind::Directional {
        s.cascades = f.int("cascades", s.cascades, 1, MAX_CASCADES)?;
        let lambda = f.num("split_lambda", 0.75, Check::In(0.0, 1.0))?;
        s.split = match f.choice("split", &["practical", "uniform", "logarithmic"])? {
            Some("uniform") => CascadeSplit::Uniform,
            Some("logarithmic") => CascadeSplit::Logarithmic,
            _ => CascadeSplit::Practical { lambda },
        };
        if f.has("split_lambda") && !matches!(s.split, CascadeSplit::Practical { .. }) {
            return Err(f.err(
                "split_lambda",
                "only the \"practical\" split takes a lambda",
            ));
        }
        s.max_distance = match f.get("max_distance") {
            None => None,
            Some(v) => Some(number(v, &f.path("max_distance"), Check::Positive)?),
        };
    }
    Ok(Some(s))
}
