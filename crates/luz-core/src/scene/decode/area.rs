//! Area lights in `lights` (issue 36): `rect`, `disk`, `sphere` and `tube` (scene::area).

use glam::Vec3;

use super::fields::*;
use super::Result;
use crate::scene::area::{
    AreaLight, AreaMethod, AreaShape, AREA_LIGHT_TYPES, DEFAULT_AREA_SAMPLES, MAX_AREA_SAMPLES,
};
use crate::scene::json::{Kind, Value};
use crate::scene::LightKind;

/// `v` decoded as an area light, or `None` when its `type` is not an area light's (the punctual
/// decoder then reads it and reports a bad or missing `type`).
pub(super) fn area_light(v: &Value, path: &str) -> Result<Option<AreaLight>> {
    let f = Fields::new(v, path)?;
    let Some(Value {
        kind: Kind::String(ty),
        ..
    }) = f.get("type")
    else {
        return Ok(None);
    };
    if !AREA_LIGHT_TYPES.contains(&ty.as_str()) {
        return Ok(None);
    }
    let common = [
        "type",
        "position",
        "color",
        "intensity",
        "visible",
        "shadow",
        "method",
        "samples",
        "range",
    ];
    let own: &[&str] = match ty.as_str() {
        "rect" => &["direction", "up", "size", "two_sided"],
        "disk" => &["direction", "radius", "two_sided"],
        "sphere" => &["radius"],
        _ => &["direction", "length", "radius"],
    };
    let allowed: Vec<&str> = common.iter().chain(own).copied().collect();
    f.allow(&allowed, &format!("a {ty} light"))?;

    let position = vec3(f.req("position")?, &f.path("position"), Check::Any)?;
    let direction = if own.contains(&"direction") {
        let d = vec3(f.req("direction")?, &f.path("direction"), Check::Any)?;
        unit(d).ok_or_else(|| f.err("direction", "must not be a zero-length vector"))?
    } else {
        Vec3::NEG_Y
    };
    // A required number > 0.
    let positive = |key: &str| number(f.req(key)?, &f.path(key), Check::Positive);
    let shape = match ty.as_str() {
        "rect" => {
            let up = vec3(f.req("up")?, &f.path("up"), Check::Any)?;
            let up = unit(up).ok_or_else(|| f.err("up", "must not be a zero-length vector"))?;
            // The part of `up` across `direction` must be large enough to make a frame from.
            if (up - direction * up.dot(direction)).length() < 1e-3 {
                return Err(f.err(
                    "up",
                    "must not be parallel to \"direction\" (the rect's height runs along up made \
                     perpendicular to direction)",
                ));
            }
            let size = f.req("size")?;
            let items = array(size, &f.path("size"), "[width, height]")?;
            if items.len() != 2 {
                return Err(f.err(
                    "size",
                    format!("expected [width, height], got {} numbers", items.len()),
                ));
            }
            let size_path = f.path("size");
            let width = number(&items[0], &index(&size_path, 0), Check::Positive)?;
            let height = number(&items[1], &index(&size_path, 1), Check::Positive)?;
            AreaShape::Rect { up, width, height }
        }
        "disk" => AreaShape::Disk {
            radius: positive("radius")?,
        },
        "sphere" => AreaShape::Sphere {
            radius: positive("radius")?,
        },
        _ => AreaShape::Tube {
            length: positive("length")?,
            radius: positive("radius")?,
        },
    };
    let method = match f.choice("method", &["ltc", "representative_point", "sampled"])? {
        None | Some("ltc") => AreaMethod::Ltc,
        Some("representative_point") => AreaMethod::RepresentativePoint,
        _ => AreaMethod::Sampled {
            samples: f.int("samples", DEFAULT_AREA_SAMPLES, 1, MAX_AREA_SAMPLES)?,
        },
    };
    if f.has("samples") && !matches!(method, AreaMethod::Sampled { .. }) {
        return Err(f.err("samples", "only the \"sampled\" method takes samples"));
    }
    let range = match f.get("range") {
        None => None,
        Some(v) => Some(number(v, &f.path("range"), Check::Positive)?),
    };
    let shadow = match f.get("shadow") {
        None => None,
        // A cube map sees every side of the emitter; the soft-shadow size is the emitter's.
        Some(v) => super::shadow::shadow(v, &f.path("shadow"), LightKind::Point, true)?,
    };
    Ok(Some(AreaLight {
        shape,
        position,
        direction,
        color: f.color("color", Vec3::ONE)?,
        intensity: f.num("intensity", 1.0, Check::NonNegative)?,
        two_sided: f.boolean("two_sided", false)?,
        visible: f.boolean("visible", true)?,
        method,
        range,
        shadow,
    }))
}
