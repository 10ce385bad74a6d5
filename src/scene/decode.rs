//! JSON tree → validated [`Scene`]. Every error carries the JSON path of the offending value.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DVec3, Vec3};

use super::error::Invalid;
use super::json::{push_key, Kind, Value};
use super::mesh::{
    Mesh, MAX_ICOSPHERE_SUBDIVISIONS, MAX_PLANE_SUBDIVISIONS, MAX_PRIMITIVE_TRIANGLES, MAX_RINGS,
    MAX_SEGMENTS,
};
use super::obj::{load_obj, ObjFile};
use super::tessellation::{self, Tessellation};
use super::{
    Camera, Falloff, Fog, Light, LightKind, Material, MeshDesc, NamedMaterial, Object, Output,
    Saturation, Scene, Shading, Transform, MAX_IMAGE_SIZE,
};
use crate::brdf::{
    dielectric_ior, metal_preset, ComplexIor, CookTorranceParams, Diffuse, Distribution, Fresnel,
    Geometry, MetalRoughParams, OrenNayarParams, PrincipledParams, SpecularSource,
    DIELECTRIC_NAMES, METAL_NAMES,
};
use crate::color::Tonemap;

type Result<T> = std::result::Result<T, Invalid>;

mod environment;
mod maps;

// ---------------------------------------------------------------------------------------------
// Typed access with paths.

fn child(path: &str, key: &str) -> String {
    let mut p = path.to_string();
    push_key(&mut p, key);
    p
}

fn index(path: &str, i: usize) -> String {
    format!("{path}[{i}]")
}

/// Shortest text that reads back as the same f32 ("-1", "0.1", "1e-7").
fn show(x: f32) -> String {
    format!("{x}")
}

/// Edit distance, for "did you mean" hints.
fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != *cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

/// Most cells of edit-distance tables one [`suggestion`] fills (about 50 ms): the options may be
/// every material name of a huge scene. Beyond it there is no "did you mean".
const SUGGESTION_WORK: usize = 50_000_000;

fn suggestion(word: &str, options: &[&str]) -> String {
    let word = word.to_lowercase();
    let word_chars = word.chars().count();
    let mut best: Option<(usize, &str)> = None;
    let mut work = 0usize;
    for o in options {
        let (o_chars, limit) = (o.chars().count(), 2.max(o.len() / 4));
        // The distance is at least the difference in length: skip what the limit rejects anyway
        // (a huge unknown key must not cost its length times every option's).
        if word_chars.abs_diff(o_chars) > limit {
            continue;
        }
        work = work.saturating_add(word_chars.saturating_mul(o_chars));
        if work > SUGGESTION_WORK {
            best = None;
            break;
        }
        let d = distance(&word, o);
        if d <= limit && d < o.len() && best.is_none_or(|b| (d, *o) < b) {
            best = Some((d, o));
        }
    }
    best.map(|(_, o)| o)
        // A field name without its unit suffix ("sigma" for "sigma_deg").
        .or_else(|| {
            options
                .iter()
                .find(|o| {
                    word.len() >= 3
                        && o.strip_prefix(word.as_str())
                            .is_some_and(|rest| rest.starts_with('_'))
                })
                .copied()
        })
        .map(|o| format!(" (did you mean \"{o}\"?)"))
        .unwrap_or_default()
}

/// "a cook_torrance material", "an oren_nayar material".
fn a_material(model: &str) -> String {
    let article = if model.starts_with(['a', 'e', 'i', 'o', 'u']) {
        "an"
    } else {
        "a"
    };
    format!("{article} {model} material")
}

fn one_of(options: &[&str]) -> String {
    options
        .iter()
        .map(|o| format!("\"{o}\""))
        .collect::<Vec<_>>()
        .join(", ")
}

/// An object's fields with the object's path.
struct Fields<'a> {
    path: String,
    fields: &'a [(String, Value)],
}

impl<'a> Fields<'a> {
    fn new(v: &'a Value, path: &str) -> Result<Self> {
        match &v.kind {
            Kind::Object(fields) => Ok(Fields {
                path: path.to_string(),
                fields,
            }),
            k => Err(Invalid::new(
                path,
                format!("expected an object {{…}}, got {}", k.describe()),
            )),
        }
    }

    /// Fails on the first field not in `allowed`; `what` names the thing for the message.
    fn allow(&self, allowed: &[&str], what: &str) -> Result<()> {
        for (key, _) in self.fields {
            if !allowed.contains(&key.as_str()) {
                return Err(Invalid::new(
                    &child(&self.path, key),
                    format!(
                        "unknown field \"{key}\"{}{}; expected one of: {}",
                        if what.is_empty() { "" } else { " for " },
                        what,
                        allowed.join(", ")
                    ) + &suggestion(key, allowed),
                ));
            }
        }
        Ok(())
    }

    fn get(&self, key: &str) -> Option<&'a Value> {
        self.fields.iter().find(|(k, _)| k == key).map(|(_, v)| v)
    }

    fn has(&self, key: &str) -> bool {
        self.get(key).is_some()
    }

    fn path(&self, key: &str) -> String {
        child(&self.path, key)
    }

    fn err(&self, key: &str, reason: impl Into<String>) -> Invalid {
        Invalid::new(&self.path(key), reason)
    }

    fn req(&self, key: &str) -> Result<&'a Value> {
        self.get(key)
            .ok_or_else(|| self.err(key, "missing required field"))
    }

    fn num(&self, key: &str, default: f32, check: Check) -> Result<f32> {
        match self.get(key) {
            None => Ok(default),
            Some(v) => number(v, &self.path(key), check),
        }
    }

    fn int(&self, key: &str, default: u32, lo: u32, hi: u32) -> Result<u32> {
        match self.get(key) {
            None => Ok(default),
            Some(v) => integer(v, &self.path(key), lo, hi),
        }
    }

    fn vec3(&self, key: &str, default: Vec3) -> Result<Vec3> {
        match self.get(key) {
            None => Ok(default),
            Some(v) => vec3(v, &self.path(key), Check::Any),
        }
    }

    fn color(&self, key: &str, default: Vec3) -> Result<Vec3> {
        match self.get(key) {
            None => Ok(default),
            Some(v) => color(v, &self.path(key)),
        }
    }

    /// A colour whose every channel passes `check` (one number means grey).
    fn color_in(&self, key: &str, default: Vec3, check: Check) -> Result<Vec3> {
        match self.get(key) {
            None => Ok(default),
            Some(v) => color_in(v, &self.path(key), check),
        }
    }

    fn boolean(&self, key: &str, default: bool) -> Result<bool> {
        match self.get(key) {
            None => Ok(default),
            Some(Value {
                kind: Kind::Bool(b),
                ..
            }) => Ok(*b),
            Some(v) => Err(self.err(
                key,
                format!("expected true or false, got {}", v.kind.describe()),
            )),
        }
    }

    /// A selector: a string from `table`, mapped to its value.
    fn select<T: Copy>(&self, key: &str, table: &[(&str, T)], default: T) -> Result<T> {
        let names: Vec<&str> = table.iter().map(|(n, _)| *n).collect();
        Ok(match self.choice(key, &names)? {
            None => default,
            Some(s) => table
                .iter()
                .find(|(n, _)| *n == s)
                .map_or(default, |(_, t)| *t),
        })
    }

    fn string(&self, key: &str) -> Result<Option<&'a str>> {
        self.get(key)
            .map(|v| string(v, &self.path(key)))
            .transpose()
    }

    /// A string field that must be one of `options`.
    fn choice(&self, key: &str, options: &[&str]) -> Result<Option<&'a str>> {
        match self.get(key) {
            None => Ok(None),
            Some(v) => choice(v, &self.path(key), options).map(Some),
        }
    }
}

#[derive(Clone, Copy)]
enum Check {
    Any,
    NonNegative,
    Positive,
    /// Closed interval.
    In(f32, f32),
    /// Open interval.
    Between(f32, f32),
}

fn number(v: &Value, path: &str, check: Check) -> Result<f32> {
    let Kind::Number { value, raw } = &v.kind else {
        return Err(Invalid::new(
            path,
            format!("expected a number, got {}", v.kind.describe()),
        ));
    };
    if !value.is_finite() {
        return Err(Invalid::new(
            path,
            format!("must be a finite number, got {raw} (overflows)"),
        ));
    }
    let x = *value as f32;
    if !x.is_finite() {
        return Err(Invalid::new(
            path,
            format!("must be a finite number, got {raw} (too large for a 32-bit float)"),
        ));
    }
    let ok = match check {
        Check::Any => None,
        Check::NonNegative => (x < 0.0).then(|| "must be ≥ 0".to_string()),
        Check::Positive => (x <= 0.0).then(|| "must be > 0".to_string()),
        Check::In(lo, hi) => {
            (!(lo..=hi).contains(&x)).then(|| format!("must be in [{}, {}]", show(lo), show(hi)))
        }
        Check::Between(lo, hi) => {
            (x <= lo || x >= hi).then(|| format!("must be in ({}, {})", show(lo), show(hi)))
        }
    };
    match ok {
        None => Ok(x),
        Some(rule) => Err(Invalid::new(path, format!("{rule}, got {raw}"))),
    }
}

fn integer(v: &Value, path: &str, lo: u32, hi: u32) -> Result<u32> {
    let Kind::Number { value, raw } = &v.kind else {
        return Err(Invalid::new(
            path,
            format!("expected an integer, got {}", v.kind.describe()),
        ));
    };
    if value.fract() != 0.0 || !value.is_finite() {
        return Err(Invalid::new(
            path,
            format!("expected an integer, got {raw}"),
        ));
    }
    if *value < f64::from(lo) || *value > f64::from(hi) {
        return Err(Invalid::new(
            path,
            format!("must be in [{lo}, {hi}], got {raw}"),
        ));
    }
    Ok(*value as u32)
}

fn array<'a>(v: &'a Value, path: &str, what: &str) -> Result<&'a [Value]> {
    match &v.kind {
        Kind::Array(items) => Ok(items),
        k => Err(Invalid::new(
            path,
            format!("expected {what}, got {}", k.describe()),
        )),
    }
}

fn vec3(v: &Value, path: &str, check: Check) -> Result<Vec3> {
    let items = array(v, path, "an array of 3 numbers [x, y, z]")?;
    if items.len() != 3 {
        return Err(Invalid::new(
            path,
            format!(
                "expected an array of 3 numbers [x, y, z], got {} element{}",
                items.len(),
                if items.len() == 1 { "" } else { "s" }
            ),
        ));
    }
    let mut out = [0.0; 3];
    for (i, item) in items.iter().enumerate() {
        out[i] = number(item, &index(path, i), check)?;
    }
    Ok(Vec3::from_array(out))
}

/// A linear RGB colour: [r, g, b] or one number for grey; every channel ≥ 0.
fn color(v: &Value, path: &str) -> Result<Vec3> {
    color_in(v, path, Check::NonNegative)
}

/// A colour-shaped value ([r, g, b] or one number for all three) whose channels pass `check`.
fn color_in(v: &Value, path: &str, check: Check) -> Result<Vec3> {
    match &v.kind {
        Kind::Number { .. } => Ok(Vec3::splat(number(v, path, check)?)),
        Kind::Array(items) if items.len() == 3 => vec3(v, path, check),
        Kind::Array(items) => Err(Invalid::new(
            path,
            format!(
                "expected a colour [r, g, b] (or one number for grey), got {} element{}",
                items.len(),
                if items.len() == 1 { "" } else { "s" }
            ),
        )),
        k => Err(Invalid::new(
            path,
            format!(
                "expected a colour [r, g, b] (or one number for grey), got {}",
                k.describe()
            ),
        )),
    }
}

fn string<'a>(v: &'a Value, path: &str) -> Result<&'a str> {
    match &v.kind {
        Kind::String(s) => Ok(s),
        k => Err(Invalid::new(
            path,
            format!("expected a string, got {}", k.describe()),
        )),
    }
}

fn choice<'a>(v: &'a Value, path: &str, options: &[&str]) -> Result<&'a str> {
    let s = match &v.kind {
        Kind::String(s) => s.as_str(),
        k => {
            return Err(Invalid::new(
                path,
                format!("expected one of {}, got {}", one_of(options), k.describe()),
            ))
        }
    };
    if options.contains(&s) {
        Ok(s)
    } else {
        Err(Invalid::new(
            path,
            format!(
                "unknown value \"{s}\"; expected one of {}{}",
                one_of(options),
                suggestion(s, options)
            ),
        ))
    }
}

/// A unit vector from any non-zero vector (computed in f64 so huge components do not overflow).
fn unit(v: Vec3) -> Option<Vec3> {
    let d = DVec3::from(v.to_array().map(f64::from));
    let len = d.length();
    (len > 1e-12 && len.is_finite()).then(|| (d / len).as_vec3())
}

// ---------------------------------------------------------------------------------------------
// The scene.

const TOP: &[&str] = &[
    "description",
    "camera",
    "output",
    "ambient",
    "lights",
    "materials",
    "objects",
    "fog",
    "saturation",
    "environment",
];

pub(crate) fn decode(root: &Value, base: &Path) -> Result<Scene> {
    if !matches!(root.kind, Kind::Object(_)) {
        return Err(Invalid::new(
            "(root)",
            format!("expected a JSON object {{…}}, got {}", root.kind.describe()),
        ));
    }
    let top = Fields::new(root, "")?;
    top.allow(TOP, "a scene")?;
    let description = top.string("description")?.unwrap_or("").to_string();
    let camera = match top.get("camera") {
        Some(v) => camera(v, "camera")?,
        None => camera(&empty_object(), "camera")?,
    };
    let output = match top.get("output") {
        Some(v) => output(v, "output")?,
        None => output(&empty_object(), "output")?,
    };
    let ambient = top.color("ambient", Vec3::ZERO)?;
    let mut lights = Vec::new();
    if let Some(v) = top.get("lights") {
        for (i, item) in array(v, "lights", "an array of lights")?.iter().enumerate() {
            lights.push(light(item, &index("lights", i))?);
        }
    }
    let mut materials = Vec::new();
    if let Some(v) = top.get("materials") {
        let map = Fields::new(v, "materials")?;
        for (name, item) in map.fields {
            let path = map.path(name);
            if name.trim().is_empty() {
                return Err(Invalid::new(&path, "a material name must not be empty"));
            }
            if name.contains('/') {
                return Err(Invalid::new(
                    &path,
                    "a material name must not contain '/' (reserved for OBJ materials, \"<objfile>/<mtlname>\")",
                ));
            }
            materials.push(NamedMaterial {
                name: name.clone(),
                material: material(item, &path)?,
                textures: maps::material_textures(item, &path, base)?,
            });
        }
    }
    let fog = match top.get("fog") {
        None => None,
        Some(Value {
            kind: Kind::Null, ..
        }) => None,
        Some(v) => Some(fog(v, "fog", &camera, &output)?),
    };
    let saturation = match top.choice("saturation", &["clamp", "normalize", "none"])? {
        Some("normalize") => Saturation::Normalize,
        Some("clamp") => Saturation::Clamp,
        _ => Saturation::None,
    };
    let environment = match top.get("environment") {
        None
        | Some(Value {
            kind: Kind::Null, ..
        }) => None,
        Some(v) => Some(environment::environment(v, "environment", base)?),
    };
    let mut scene = Scene {
        source: None,
        description,
        camera,
        output,
        ambient,
        lights,
        materials,
        objects: Vec::new(),
        fog,
        saturation,
        environment,
        warnings: Vec::new(),
    };
    if let Some(v) = top.get("objects") {
        let mut ctx = Ctx {
            base,
            primitives: MeshCache::default(),
            primitive_triangles: 0,
            objs: HashMap::new(),
            mtl_materials: HashMap::new(),
            material_index: HashMap::new(),
        };
        for (i, m) in scene.materials.iter().enumerate() {
            ctx.material_index.entry(m.name.clone()).or_insert(i);
        }
        for (i, item) in array(v, "objects", "an array of objects")?
            .iter()
            .enumerate()
        {
            object(item, &index("objects", i), i, &mut ctx, &mut scene)?;
        }
    }
    tessellation::resolve(&mut scene);
    Ok(scene)
}

fn empty_object() -> Value {
    Value {
        kind: Kind::Object(Vec::new()),
        line: 0,
        column: 0,
    }
}

fn camera(v: &Value, path: &str) -> Result<Camera> {
    let f = Fields::new(v, path)?;
    f.allow(
        &["position", "target", "up", "fov_y_deg", "near", "far"],
        "the camera",
    )?;
    let position = f.vec3("position", Vec3::new(0.0, 0.0, 5.0))?;
    let target = f.vec3("target", Vec3::ZERO)?;
    let up = f.vec3("up", Vec3::Y)?;
    let fov_y_deg = f.num("fov_y_deg", 45.0, Check::Between(0.0, 180.0))?;
    let near = f.num("near", 0.1, Check::Positive)?;
    let far = f.num("far", 100.0, Check::Positive)?;
    if near >= far {
        return Err(f.err(
            "far",
            format!("must be > near ({}), got {}", show(near), show(far)),
        ));
    }
    let Some(forward) = unit(target - position) else {
        return Err(f.err("target", "equals the camera position (no view direction)"));
    };
    let Some(up) = unit(up) else {
        return Err(f.err("up", "must not be a zero-length vector"));
    };
    if forward.cross(up).length() < 1e-4 {
        return Err(f.err(
            "up",
            "is parallel to the view direction (target − position); choose another up vector",
        ));
    }
    Ok(Camera {
        position,
        target,
        up,
        fov_y_deg,
        near,
        far,
    })
}

fn output(v: &Value, path: &str) -> Result<Output> {
    let f = Fields::new(v, path)?;
    f.allow(
        &[
            "width",
            "height",
            "background",
            "exposure",
            "tonemap",
            "msaa",
            "tessellation_error_px",
        ],
        "the output",
    )?;
    let width = f.int("width", 1280, 1, MAX_IMAGE_SIZE)?;
    let height = f.int("height", 720, 1, MAX_IMAGE_SIZE)?;
    let background = f.color("background", Vec3::ZERO)?;
    let exposure = f.num("exposure", 0.0, Check::In(-64.0, 64.0))?;
    let tonemap = match f.get("tonemap") {
        None => Tonemap::default(),
        Some(v) => tonemap(v, &f.path("tonemap"))?,
    };
    let msaa = f.int("msaa", 4, 1, 8)?;
    if ![1, 2, 4, 8].contains(&msaa) {
        return Err(f.err("msaa", format!("must be 1, 2, 4 or 8, got {msaa}")));
    }
    let tessellation_error_px = f.num(
        "tessellation_error_px",
        tessellation::DEFAULT_TESSELLATION_ERROR_PX,
        Check::In(
            tessellation::MIN_TESSELLATION_ERROR_PX,
            tessellation::MAX_TESSELLATION_ERROR_PX,
        ),
    )?;
    Ok(Output {
        width,
        height,
        background,
        exposure,
        tonemap,
        msaa,
        tessellation_error_px,
    })
}

fn tonemap(v: &Value, path: &str) -> Result<Tonemap> {
    use serde::de::IntoDeserializer;
    use serde::Deserialize;
    let s = string(v, path)?;
    let de: serde::de::value::StrDeserializer<'_, serde::de::value::Error> = s.into_deserializer();
    Tonemap::deserialize(de).map_err(|e| Invalid::new(path, e.to_string()))
}

fn light(v: &Value, path: &str) -> Result<Light> {
    let f = Fields::new(v, path)?;
    let kind = match choice(
        f.req("type")?,
        &f.path("type"),
        &["directional", "point", "spot"],
    )? {
        "directional" => LightKind::Directional,
        "point" => LightKind::Point,
        _ => LightKind::Spot,
    };
    let (allowed, what): (&[&str], _) = match kind {
        LightKind::Directional => (
            &[
                "type",
                "direction",
                "target",
                "position",
                "color",
                "intensity",
            ],
            "a directional light",
        ),
        LightKind::Point => (
            &["type", "position", "color", "intensity", "falloff"],
            "a point light",
        ),
        LightKind::Spot => (
            &[
                "type",
                "position",
                "direction",
                "target",
                "color",
                "intensity",
                "falloff",
                "umbra_deg",
                "inner_deg",
                "exponent",
            ],
            "a spot light",
        ),
    };
    f.allow(allowed, what)?;
    let position = match kind {
        LightKind::Point | LightKind::Spot => {
            vec3(f.req("position")?, &f.path("position"), Check::Any)?
        }
        LightKind::Directional => f.vec3("position", Vec3::ZERO)?,
    };
    let direction = match kind {
        LightKind::Point => Vec3::NEG_Y,
        _ => match (f.get("direction"), f.get("target")) {
            (Some(_), Some(_)) => {
                return Err(f.err("target", "give either direction or target, not both"))
            }
            (Some(d), None) => {
                let d = vec3(d, &f.path("direction"), Check::Any)?;
                unit(d).ok_or_else(|| f.err("direction", "must not be a zero-length vector"))?
            }
            (None, Some(t)) => {
                if kind == LightKind::Directional && !f.has("position") {
                    return Err(f.err(
                        "target",
                        "a directional light aimed with target also needs a position (direction = target − position)",
                    ));
                }
                let t = vec3(t, &f.path("target"), Check::Any)?;
                unit(t - position).ok_or_else(|| {
                    f.err(
                        "target",
                        "equals the light's position (zero-length direction)",
                    )
                })?
            }
            (None, None) => {
                return Err(f.err("direction", "missing required field (or give target)"))
            }
        },
    };
    let color = f.color("color", Vec3::ONE)?;
    let intensity = f.num("intensity", 1.0, Check::NonNegative)?;
    let falloff = match (kind, f.get("falloff")) {
        (LightKind::Directional, _) => Falloff::None,
        (_, None) => Falloff::InverseSquare,
        (_, Some(v)) => falloff(v, &f.path("falloff"))?,
    };
    let (umbra_deg, inner_deg, exponent) = if kind == LightKind::Spot {
        let umbra = f.num("umbra_deg", 30.0, Check::Positive)?;
        if umbra > 90.0 {
            return Err(f.err(
                "umbra_deg",
                format!("must be in (0, 90], got {}", show(umbra)),
            ));
        }
        let inner = match f.get("inner_deg") {
            None => None,
            Some(v) => {
                let inner = number(v, &f.path("inner_deg"), Check::NonNegative)?;
                if inner >= umbra {
                    return Err(f.err(
                        "inner_deg",
                        format!("must be < umbra_deg ({}), got {}", show(umbra), show(inner)),
                    ));
                }
                Some(inner)
            }
        };
        (umbra, inner, f.num("exponent", 0.0, Check::NonNegative)?)
    } else {
        (180.0, None, 0.0)
    };
    Ok(Light {
        kind,
        direction,
        position,
        color,
        intensity,
        falloff,
        umbra_deg,
        inner_deg,
        exponent,
    })
}

fn falloff(v: &Value, path: &str) -> Result<Falloff> {
    match &v.kind {
        Kind::String(_) => Ok(match choice(v, path, &["inverse_square", "none"])? {
            "none" => Falloff::None,
            _ => Falloff::InverseSquare,
        }),
        Kind::Object(_) => {
            let f = Fields::new(v, path)?;
            f.allow(&["c1", "c2", "c3"], "a classic falloff")?;
            Ok(Falloff::Classic {
                c1: f.num("c1", 1.0, Check::NonNegative)?,
                c2: f.num("c2", 0.0, Check::NonNegative)?,
                c3: f.num("c3", 0.0, Check::NonNegative)?,
            })
        }
        k => Err(Invalid::new(
            path,
            format!(
                "expected \"inverse_square\", \"none\" or {{\"c1\": …, \"c2\": …, \"c3\": …}}, got {}",
                k.describe()
            ),
        )),
    }
}

// ---------------------------------------------------------------------------------------------
// Materials. One decoder per model; add new models to this table.

type MaterialDecoder = fn(&Fields, &str) -> Result<Material>;

const MATERIAL_MODELS: &[(&str, MaterialDecoder)] = &[
    ("phong", phong),
    ("blinn_phong", phong),
    ("lambert", lambert),
    ("cook_torrance", cook_torrance),
    ("metal_rough", metal_rough),
    ("principled", principled),
    ("oren_nayar", oren_nayar),
];

/// The `distribution` selector (the names are `brdf::Distribution::name`).
pub(crate) const DISTRIBUTIONS: &[(&str, Distribution)] = &Distribution::NAMED;

/// The `geometry` selector.
pub(crate) const GEOMETRIES: &[(&str, Geometry)] = &Geometry::NAMED;

/// The `fresnel` selector.
pub(crate) const FRESNELS: &[(&str, Fresnel)] = &Fresnel::NAMED;

/// The `diffuse` selector (Cook-Torrance and metal_rough).
pub(crate) const DIFFUSES: &[(&str, Diffuse)] = &Diffuse::NAMED;

/// Cook-Torrance's specular (Fresnel) sources; a material gives at most one.
const SPECULAR_SOURCES: &[&str] = &["ior", "f0", "complex_ior", "preset"];

/// Every unit-range parameter in [0, 1].
const UNIT: Check = Check::In(0.0, 1.0);

fn material(v: &Value, path: &str) -> Result<Material> {
    let f = Fields::new(v, path)?;
    let names: Vec<&str> = MATERIAL_MODELS.iter().map(|(n, _)| *n).collect();
    let model = choice(f.req("model")?, &f.path("model"), &names)?;
    let decoder = MATERIAL_MODELS
        .iter()
        .find(|(n, _)| *n == model)
        .map(|(_, d)| *d)
        .unwrap_or(phong);
    decoder(&f, model)
}

fn phong(f: &Fields, model: &str) -> Result<Material> {
    f.allow(
        &[
            "model",
            "textures",
            "ka",
            "kd",
            "ks",
            "shininess",
            "diffuse_color",
            "specular_color",
        ],
        &a_material(model),
    )?;
    // Start from the documented defaults and override what the file gives.
    let mut m = Material::default_phong(model == "blinn_phong");
    if let Material::Phong(crate::brdf::PhongParams {
        ka,
        kd,
        ks,
        shininess,
        diffuse_color,
        specular_color,
        ..
    }) = &mut m
    {
        *ka = f.num("ka", *ka, Check::NonNegative)?;
        *kd = f.num("kd", *kd, Check::NonNegative)?;
        *ks = f.num("ks", *ks, Check::NonNegative)?;
        *shininess = f.num("shininess", *shininess, Check::NonNegative)?;
        *diffuse_color = f.color("diffuse_color", *diffuse_color)?;
        *specular_color = f.color("specular_color", *specular_color)?;
    }
    Ok(m)
}

fn lambert(f: &Fields, model: &str) -> Result<Material> {
    f.allow(&["model", "albedo", "textures"], &a_material(model))?;
    let albedo = f.color("albedo", Vec3::splat(0.8))?;
    if albedo.max_element() > 1.0 {
        return Err(f.err(
            "albedo",
            format!(
                "every channel must be in [0, 1] (energy conservation), got [{}, {}, {}]",
                show(albedo.x),
                show(albedo.y),
                show(albedo.z)
            ),
        ));
    }
    Ok(Material::Lambert(crate::brdf::LambertParams { albedo }))
}

/// Cook-Torrance (seed 000). Defaults are `brdf::CookTorranceParams::default()`.
fn cook_torrance(f: &Fields, model: &str) -> Result<Material> {
    f.allow(
        &[
            "model",
            "textures",
            "color",
            "kd",
            "roughness",
            "ior",
            "f0",
            "complex_ior",
            "preset",
            "distribution",
            "geometry",
            "fresnel",
            "diffuse",
        ],
        &a_material(model),
    )?;
    let d = CookTorranceParams::default();
    let color = f.color_in("color", d.color, UNIT)?;
    let kd = f.num("kd", d.kd, UNIT)?;
    let roughness = f.num("roughness", d.roughness, UNIT)?;
    let distribution = f.select("distribution", DISTRIBUTIONS, d.distribution)?;
    let geometry = f.select("geometry", GEOMETRIES, d.geometry)?;
    let fresnel = f.select("fresnel", FRESNELS, d.fresnel)?;
    let diffuse = f.select("diffuse", DIFFUSES, d.diffuse)?;
    let source = specular_source(f)?;
    let name = |s: &Option<(&str, SpecularSource)>| match s {
        Some(("preset", _)) => format!(
            "preset \"{}\"",
            f.string("preset").ok().flatten().unwrap_or("")
        ),
        Some((key, _)) => format!("\"{key}\""),
        None => "the default ior 1.5".to_string(),
    };
    match (fresnel, &source) {
        (Fresnel::Conductor, Some((_, SpecularSource::Complex(_)))) => {}
        (Fresnel::Conductor, s) => {
            return Err(f.err(
                "fresnel",
                format!(
                    "the \"conductor\" Fresnel needs a complex index of refraction (η and κ), got {}; give complex_ior {{\"eta\": [r, g, b], \"k\": [r, g, b]}} or a metal preset ({})",
                    name(s),
                    METAL_NAMES.join(", ")
                ),
            ))
        }
        (Fresnel::Dielectric, s @ Some((_, SpecularSource::Complex(_)))) => {
            return Err(f.err(
                "fresnel",
                format!(
                    "the \"dielectric\" Fresnel takes a real index of refraction, but {} is a complex one (its κ would be dropped); give ior or f0, or use fresnel \"conductor\" or \"schlick\"",
                    name(s)
                ),
            ))
        }
        _ => {}
    }
    Ok(Material::CookTorrance(CookTorranceParams {
        color,
        kd,
        roughness,
        specular: source.map_or(d.specular, |(_, s)| s),
        distribution,
        geometry,
        fresnel,
        diffuse,
    }))
}

/// The one specular source of a Cook-Torrance material (`None`: not given), with its key.
fn specular_source(f: &Fields) -> Result<Option<(&'static str, SpecularSource)>> {
    let mut given = f
        .fields
        .iter()
        .filter_map(|(k, _)| SPECULAR_SOURCES.iter().find(|s| **s == k.as_str()).copied());
    let Some(key) = given.next() else {
        return Ok(None);
    };
    if let Some(second) = given.next() {
        return Err(f.err(
            second,
            format!(
                "\"{key}\" and \"{second}\" both give the Fresnel reflectance; keep exactly one of: {}",
                SPECULAR_SOURCES.join(", ")
            ),
        ));
    }
    let v = f.get(key).unwrap_or(&NULL);
    let path = f.path(key);
    let source = match key {
        "ior" => SpecularSource::Ior(number(v, &path, Check::Positive)?),
        "f0" => SpecularSource::F0(color_in(v, &path, UNIT)?),
        "complex_ior" => SpecularSource::Complex(complex_ior(v, &path)?),
        _ => {
            let name = string(v, &path)?;
            if let Some(c) = metal_preset(name) {
                SpecularSource::Complex(c)
            } else if let Some(eta) = dielectric_ior(name) {
                SpecularSource::Ior(eta)
            } else {
                let all: Vec<&str> = METAL_NAMES
                    .iter()
                    .chain(&DIELECTRIC_NAMES)
                    .copied()
                    .collect();
                return Err(Invalid::new(
                    &path,
                    format!(
                        "unknown preset \"{name}\"; metals: {}; dielectrics: {}{}",
                        METAL_NAMES.join(", "),
                        DIELECTRIC_NAMES.join(", "),
                        suggestion(name, &all)
                    ),
                ));
            }
        }
    };
    Ok(Some((key, source)))
}

const NULL: Value = Value {
    kind: Kind::Null,
    line: 0,
    column: 0,
};

/// `{"eta": [r, g, b], "k": [r, g, b]}` (either may be one number for all channels).
fn complex_ior(v: &Value, path: &str) -> Result<ComplexIor> {
    let f = Fields::new(v, path)?;
    f.allow(&["eta", "k"], "a complex index of refraction")?;
    let eta = color_in(f.req("eta")?, &f.path("eta"), Check::Positive)?;
    let k = color_in(f.req("k")?, &f.path("k"), Check::NonNegative)?;
    Ok(ComplexIor { eta, k })
}

/// glTF metallic-roughness (seed 001). Defaults are `brdf::MetalRoughParams::default()` (glTF's).
fn metal_rough(f: &Fields, model: &str) -> Result<Material> {
    f.allow(
        &[
            "model",
            "textures",
            "base_color",
            "metallic",
            "roughness",
            "preset",
            "distribution",
            "geometry",
            "fresnel",
            "diffuse_fresnel_weight",
            "diffuse",
        ],
        &a_material(model),
    )?;
    let d = MetalRoughParams::default();
    let (base_color, metallic) = match f.string("preset")? {
        None => (
            f.color_in("base_color", d.base_color, UNIT)?,
            f.num("metallic", d.metallic, UNIT)?,
        ),
        Some(name) => {
            for key in ["base_color", "metallic"] {
                if f.has(key) {
                    return Err(f.err(
                        key,
                        format!("a preset sets base_color and metallic; give either the preset \"{name}\" or {key}, not both"),
                    ));
                }
            }
            let Some(c) = metal_preset(name) else {
                let reason = if dielectric_ior(name).is_some() {
                    format!("\"{name}\" is a dielectric; metal_rough presets are metals (a dielectric is metallic 0 with its F0 fixed at 0.04): {}", METAL_NAMES.join(", "))
                } else {
                    format!(
                        "unknown metal preset \"{name}\"; expected one of: {}{}",
                        METAL_NAMES.join(", "),
                        suggestion(name, &METAL_NAMES)
                    )
                };
                return Err(f.err("preset", reason));
            };
            (c.f0(), 1.0)
        }
    };
    Ok(Material::MetalRough(MetalRoughParams {
        base_color,
        metallic,
        roughness: f.num("roughness", d.roughness, UNIT)?,
        distribution: f.select("distribution", DISTRIBUTIONS, d.distribution)?,
        geometry: f.select("geometry", GEOMETRIES, d.geometry)?,
        fresnel: f.select("fresnel", FRESNELS, d.fresnel)?,
        diffuse_fresnel_weight: f.boolean("diffuse_fresnel_weight", d.diffuse_fresnel_weight)?,
        diffuse: f.select("diffuse", DIFFUSES, d.diffuse)?,
    }))
}

/// Disney "Principled". Defaults are `brdf::PrincipledParams::default()` (`disney.brdf`'s).
fn principled(f: &Fields, model: &str) -> Result<Material> {
    f.allow(
        &[
            "model",
            "textures",
            "base_color",
            "subsurface",
            "metallic",
            "specular",
            "specular_tint",
            "roughness",
            "anisotropic",
            "sheen",
            "sheen_tint",
            "clearcoat",
            "clearcoat_gloss",
        ],
        &a_material(model),
    )?;
    let d = PrincipledParams::default();
    Ok(Material::Principled(PrincipledParams {
        base_color: f.color_in("base_color", d.base_color, UNIT)?,
        subsurface: f.num("subsurface", d.subsurface, UNIT)?,
        metallic: f.num("metallic", d.metallic, UNIT)?,
        specular: f.num("specular", d.specular, UNIT)?,
        specular_tint: f.num("specular_tint", d.specular_tint, UNIT)?,
        roughness: f.num("roughness", d.roughness, UNIT)?,
        anisotropic: f.num("anisotropic", d.anisotropic, UNIT)?,
        sheen: f.num("sheen", d.sheen, UNIT)?,
        sheen_tint: f.num("sheen_tint", d.sheen_tint, UNIT)?,
        clearcoat: f.num("clearcoat", d.clearcoat, UNIT)?,
        clearcoat_gloss: f.num("clearcoat_gloss", d.clearcoat_gloss, UNIT)?,
    }))
}

/// Qualitative Oren-Nayar. Defaults are `brdf::OrenNayarParams::default()`.
fn oren_nayar(f: &Fields, model: &str) -> Result<Material> {
    f.allow(
        &["model", "albedo", "sigma_deg", "textures"],
        &a_material(model),
    )?;
    let d = OrenNayarParams::default();
    Ok(Material::OrenNayar(OrenNayarParams {
        albedo: f.color_in("albedo", d.albedo, UNIT)?,
        sigma_deg: f.num("sigma_deg", d.sigma_deg, Check::In(0.0, 90.0))?,
    }))
}

// ---------------------------------------------------------------------------------------------
// Fog.

fn fog(v: &Value, path: &str, camera: &Camera, output: &Output) -> Result<Fog> {
    let f = Fields::new(v, path)?;
    f.allow(&["z_a", "z_b", "s_a", "s_b", "color"], "fog")?;
    let z_a = f.num("z_a", camera.near, Check::NonNegative)?;
    let z_b = f.num("z_b", camera.far, Check::NonNegative)?;
    if z_b <= z_a {
        return Err(f.err(
            "z_b",
            format!("must be > z_a ({}), got {}", show(z_a), show(z_b)),
        ));
    }
    Ok(Fog {
        z_a,
        z_b,
        s_a: f.num("s_a", 0.0, Check::In(0.0, 1.0))?,
        s_b: f.num("s_b", 1.0, Check::In(0.0, 1.0))?,
        color: f.color("color", output.background)?,
    })
}

// ---------------------------------------------------------------------------------------------
// Objects.

/// Most triangles of all distinct built-in meshes of one scene (2^25, about 1.9 GB of vertices
/// and indices): a small file must not make the loader build gigabytes.
pub const MAX_SCENE_PRIMITIVE_TRIANGLES: u64 = 1 << 25;

struct Ctx<'a> {
    base: &'a Path,
    /// Built primitives, shared between objects with equal descriptions.
    primitives: MeshCache,
    /// Triangles of the distinct primitives built so far ([`MAX_SCENE_PRIMITIVE_TRIANGLES`]).
    primitive_triangles: u64,
    /// Loaded OBJ files by (resolved path, with materials).
    objs: HashMap<(PathBuf, bool), Arc<LoadedObj>>,
    /// (resolved OBJ path, MTL material index or None for the default) → scene material index.
    mtl_materials: HashMap<(PathBuf, Option<usize>), usize>,
    /// Index in `scene.materials` by name (the scene's materials, then the MTL ones as added).
    material_index: HashMap<String, usize>,
}

/// Built meshes by description, shared between objects with equal descriptions: a hash of the
/// fields picks a short list searched with `==` (one list searched linearly made scenes of many
/// distinct meshes quadratic).
#[derive(Default)]
pub(crate) struct MeshCache {
    by_key: HashMap<[u32; 5], Vec<(MeshDesc, Arc<Mesh>)>>,
}

impl MeshCache {
    /// Equal descriptions have equal keys (−0 counts as 0; a NaN never equals, as with `==`).
    fn key(desc: &MeshDesc) -> [u32; 5] {
        let f = |x: f32| if x == 0.0 { 0 } else { x.to_bits() };
        match *desc {
            MeshDesc::Sphere {
                radius,
                segments,
                rings,
            } => [0, f(radius), segments, rings, 0],
            MeshDesc::Icosphere {
                radius,
                subdivisions,
            } => [1, f(radius), subdivisions, 0, 0],
            MeshDesc::Plane { size, subdivisions } => [2, f(size[0]), f(size[1]), subdivisions, 0],
            MeshDesc::Cube { size } => [3, f(size), 0, 0, 0],
            MeshDesc::Cone {
                radius,
                height,
                segments,
            } => [4, f(radius), f(height), segments, 0],
            MeshDesc::Cylinder {
                radius,
                height,
                segments,
            } => [5, f(radius), f(height), segments, 0],
            MeshDesc::Obj { .. } => [6, 0, 0, 0, 0],
        }
    }

    /// The mesh built for a description equal to `desc`.
    pub(crate) fn get(&self, desc: &MeshDesc) -> Option<&Arc<Mesh>> {
        self.by_key
            .get(&Self::key(desc))?
            .iter()
            .find(|(d, _)| d == desc)
            .map(|(_, m)| m)
    }

    pub(crate) fn insert(&mut self, desc: MeshDesc, mesh: Arc<Mesh>) {
        self.by_key
            .entry(Self::key(&desc))
            .or_default()
            .push((desc, mesh));
    }
}

struct LoadedObj {
    file: ObjFile,
    meshes: Vec<Arc<Mesh>>,
}

const MESH_TYPES: &[&str] = &[
    "sphere",
    "icosphere",
    "plane",
    "cube",
    "cone",
    "cylinder",
    "obj",
];

fn object(v: &Value, path: &str, i: usize, ctx: &mut Ctx, scene: &mut Scene) -> Result<()> {
    let f = Fields::new(v, path)?;
    f.allow(
        &[
            "name",
            "mesh",
            "material",
            "position",
            "rotation_deg",
            "scale",
            "shading",
        ],
        "an object",
    )?;
    let name = f.string("name")?.map(str::to_string);
    let (desc, tessellation) = mesh_desc(f.req("mesh")?, &f.path("mesh"), ctx.base)?;
    let material = match f.get("material") {
        Some(m) => {
            let name = string(m, &f.path("material"))?;
            let found = ctx.material_index.get(name).copied();
            Some(found.ok_or_else(|| {
                let defined: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
                f.err(
                    "material",
                    format!(
                        "unknown material \"{name}\"; defined: {}{}",
                        if defined.is_empty() {
                            "none (add it under \"materials\")".to_string()
                        } else {
                            defined.join(", ")
                        },
                        suggestion(name, &defined)
                    ),
                )
            })?)
        }
        None if matches!(desc, MeshDesc::Obj { .. }) => None,
        None => return Err(f.err(
            "material",
            "missing required field (only OBJ meshes may take their materials from an MTL file)",
        )),
    };
    let position = f.vec3("position", Vec3::ZERO)?;
    let rotation_deg = f.vec3("rotation_deg", Vec3::ZERO)?;
    let scale = match f.get("scale") {
        None => Vec3::ONE,
        Some(
            v @ Value {
                kind: Kind::Number { .. },
                ..
            },
        ) => Vec3::splat(number(v, &f.path("scale"), Check::Positive)?),
        Some(v) => vec3(v, &f.path("scale"), Check::Positive)?,
    };
    let shading = match f.choice("shading", &["flat", "gouraud", "phong"])? {
        Some("flat") => Shading::Flat,
        Some("gouraud") => Shading::Gouraud,
        _ => Shading::Phong,
    };
    let transform = Transform {
        position,
        rotation_deg,
        scale,
    };

    if let MeshDesc::Obj { path: obj_path } = &desc {
        let with_materials = material.is_none();
        let key = (obj_path.clone(), with_materials);
        let loaded = match ctx.objs.get(&key) {
            Some(l) => l.clone(),
            None => {
                let file = load_obj(obj_path, with_materials).map_err(|e| Invalid {
                    path: f.path("mesh") + ".path",
                    reason: e.reason,
                    mesh: Some((e.file, e.line)),
                })?;
                scene.warnings.extend(file.warnings.iter().cloned());
                let meshes = file
                    .parts
                    .iter()
                    .map(|p| Arc::new(p.mesh.clone()))
                    .collect();
                let l = Arc::new(LoadedObj { file, meshes });
                ctx.objs.insert(key, l.clone());
                l
            }
        };
        let file_name = obj_path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| obj_path.display().to_string());
        let stem = obj_path
            .file_stem()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| file_name.clone());
        let single = loaded.file.parts.len() == 1;
        for (part, mesh) in loaded.file.parts.iter().zip(&loaded.meshes) {
            let part_material = match material {
                Some(m) => m,
                None => mtl_material(
                    ctx,
                    scene,
                    obj_path,
                    &file_name,
                    &loaded.file,
                    part.material,
                ),
            };
            let base = name.clone().unwrap_or_else(|| stem.clone());
            scene.objects.push(Object {
                name: if single {
                    base
                } else {
                    format!("{base}/{}", part.name)
                },
                desc: desc.clone(),
                mesh: mesh.clone(),
                material: part_material,
                transform,
                shading,
                tessellation,
            });
        }
        return Ok(());
    }

    // Automatic tessellation builds its mesh once the whole scene is known (resolve).
    let mesh = match ctx.primitives.get(&desc) {
        _ if tessellation != Tessellation::Given => Arc::new(Mesh::default()),
        Some(m) => m.clone(),
        None => {
            let n = desc.triangle_count().unwrap_or(0);
            ctx.primitive_triangles += n;
            if ctx.primitive_triangles > MAX_SCENE_PRIMITIVE_TRIANGLES {
                return Err(f.err(
                    "mesh",
                    format!(
                        "the scene's built-in meshes would have {} triangles with this one ({n}); \
                         the limit per scene is {MAX_SCENE_PRIMITIVE_TRIANGLES} (objects with equal \
                         meshes share one)",
                        ctx.primitive_triangles
                    ),
                ));
            }
            let m = Arc::new(desc.build().unwrap_or_default());
            ctx.primitives.insert(desc.clone(), m.clone());
            m
        }
    };
    let kind = match &desc {
        MeshDesc::Sphere { .. } => "sphere",
        MeshDesc::Icosphere { .. } => "icosphere",
        MeshDesc::Plane { .. } => "plane",
        MeshDesc::Cube { .. } => "cube",
        MeshDesc::Cone { .. } => "cone",
        MeshDesc::Cylinder { .. } => "cylinder",
        MeshDesc::Obj { .. } => "obj",
    };
    scene.objects.push(Object {
        name: name.unwrap_or_else(|| format!("{kind}{i}")),
        desc,
        mesh,
        material: material.unwrap_or(0),
        transform,
        shading,
        tessellation,
    });
    Ok(())
}

/// Shininess of an MTL material without `Ns`.
const MTL_DEFAULT_SHININESS: f32 = 32.0;

/// The scene material for an OBJ part's MTL material (appended on first use).
fn mtl_material(
    ctx: &mut Ctx,
    scene: &mut Scene,
    obj_path: &Path,
    file_name: &str,
    file: &ObjFile,
    which: Option<usize>,
) -> usize {
    let key = (obj_path.to_path_buf(), which);
    if let Some(&i) = ctx.mtl_materials.get(&key) {
        return i;
    }
    let (mtl_name, material, textures) = match which.and_then(|i| file.materials.get(i)) {
        // The MTL's model (classic, or metal_rough with the PBR extension) and its maps.
        Some(m) => {
            let (material, textures) = maps::mtl_material(m, &mut scene.warnings);
            (m.name.clone(), material, textures)
        }
        None => (
            "default".to_string(),
            Material::default_phong(false),
            super::MaterialTextures::default(),
        ),
    };
    let mut name = format!("{file_name}/{mtl_name}");
    let mut n = 2;
    while ctx.material_index.contains_key(&name) {
        name = format!("{file_name}/{mtl_name}#{n}");
        n += 1;
    }
    let i = scene.materials.len();
    ctx.material_index.insert(name.clone(), i);
    scene.materials.push(NamedMaterial {
        name,
        material,
        textures,
    });
    ctx.mtl_materials.insert(key, i);
    i
}

/// The mesh description and whether its segments are left to [`tessellation::resolve`] (then
/// the description holds placeholder counts until the scene is resolved).
fn mesh_desc(v: &Value, path: &str, base: &Path) -> Result<(MeshDesc, Tessellation)> {
    let f = Fields::new(v, path)?;
    let kind = choice(f.req("type")?, &f.path("type"), MESH_TYPES)?;
    let seg = |f: &Fields, default| f.int("segments", default, 3, MAX_SEGMENTS);
    let tessellation =
        if matches!(kind, "sphere" | "cone" | "cylinder") && f.get("segments").is_none() {
            Tessellation::Auto {
                projected_radius_px: 0.0,
                rings_given: f.get("rings").is_some(),
            }
        } else {
            Tessellation::Given
        };
    let desc = match kind {
        "sphere" => {
            f.allow(&["type", "radius", "segments", "rings"], "a sphere")?;
            MeshDesc::Sphere {
                radius: f.num("radius", 1.0, Check::Positive)?,
                segments: seg(&f, 64)?,
                rings: f.int("rings", 32, 2, MAX_RINGS)?,
            }
        }
        "icosphere" => {
            f.allow(&["type", "radius", "subdivisions"], "an icosphere")?;
            MeshDesc::Icosphere {
                radius: f.num("radius", 1.0, Check::Positive)?,
                subdivisions: f.int("subdivisions", 3, 0, MAX_ICOSPHERE_SUBDIVISIONS)?,
            }
        }
        "plane" => {
            f.allow(&["type", "size", "subdivisions"], "a plane")?;
            let size = match f.get("size") {
                None => [10.0, 10.0],
                Some(v) => {
                    let p = f.path("size");
                    let items = array(v, &p, "an array [x, z] of 2 numbers")?;
                    if items.len() != 2 {
                        return Err(Invalid::new(
                            &p,
                            format!(
                                "expected an array [x, z] of 2 numbers, got {} elements",
                                items.len()
                            ),
                        ));
                    }
                    [
                        number(&items[0], &index(&p, 0), Check::Positive)?,
                        number(&items[1], &index(&p, 1), Check::Positive)?,
                    ]
                }
            };
            MeshDesc::Plane {
                size,
                subdivisions: f.int("subdivisions", 1, 1, MAX_PLANE_SUBDIVISIONS)?,
            }
        }
        "cube" => {
            f.allow(&["type", "size"], "a cube")?;
            MeshDesc::Cube {
                size: f.num("size", 1.0, Check::Positive)?,
            }
        }
        "cone" | "cylinder" => {
            f.allow(
                &["type", "radius", "height", "segments"],
                &format!("a {kind}"),
            )?;
            let radius = f.num("radius", 0.5, Check::Positive)?;
            let height = f.num("height", 1.0, Check::Positive)?;
            let segments = seg(&f, 64)?;
            if kind == "cone" {
                MeshDesc::Cone {
                    radius,
                    height,
                    segments,
                }
            } else {
                MeshDesc::Cylinder {
                    radius,
                    height,
                    segments,
                }
            }
        }
        _ => {
            f.allow(&["type", "path"], "an OBJ mesh")?;
            let p = string(f.req("path")?, &f.path("path"))?;
            if p.trim().is_empty() {
                return Err(f.err("path", "must not be empty"));
            }
            return Ok((MeshDesc::Obj { path: base.join(p) }, Tessellation::Given));
        }
    };
    if let Some(n) = desc.triangle_count() {
        if n > MAX_PRIMITIVE_TRIANGLES {
            return Err(Invalid::new(
                path,
                format!(
                    "too finely tessellated: {n} triangles, the limit per primitive is {MAX_PRIMITIVE_TRIANGLES}"
                ),
            ));
        }
    }
    Ok((desc, tessellation))
}
