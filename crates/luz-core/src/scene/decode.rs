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
    Camera, Falloff, Fog, Light, LightKind, Material, MeshDesc, NamedMaterial, Object,
    ObjectShadow, Output, Projection, Saturation, Scene, Shading, Transform, MAX_IMAGE_SIZE,
};
use crate::brdf::{
    dielectric_ior, metal_preset, ComplexIor, CookTorranceParams, Diffuse, Distribution, Fresnel,
    Geometry, MetalRoughParams, OrenNayarParams, PrincipledParams, SpecularSource,
    DIELECTRIC_NAMES, METAL_NAMES,
};
use crate::color::Tonemap;

type Result<T> = std::result::Result<T, Invalid>;

mod area;
mod environment;
mod fields;
mod gltf_object;
mod maps;
mod material;
mod object;
mod shadow;

pub(crate) use super::mesh_cache::MeshCache;
use fields::*;
pub use material::MATERIAL_MODELS;
use material::*;
pub(crate) use material::{DIFFUSES, DISTRIBUTIONS, FILM_ANGLES, FRESNELS, GEOMETRIES};
use object::*;

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
    let mut area_lights = Vec::new();
    if let Some(v) = top.get("lights") {
        for (i, item) in array(v, "lights", "an array of lights")?.iter().enumerate() {
            let path = index("lights", i);
            match area::area_light(item, &path)? {
                Some(a) => area_lights.push(a),
                None => lights.push(light(item, &path)?),
            }
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
        area_lights,
        materials,
        objects: Vec::new(),
        fog,
        saturation,
        environment,
        warnings: Vec::new(),
        cameras: Vec::new(),
    };
    if let Some(v) = top.get("objects") {
        let mut ctx = Ctx {
            base,
            primitives: MeshCache::default(),
            primitive_triangles: 0,
            objs: HashMap::new(),
            gltfs: HashMap::new(),
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
    let unbounded = scene
        .lights
        .iter()
        .filter(|l| l.kind != LightKind::Directional && l.range.is_none())
        .count();
    if unbounded > MANY_UNBOUNDED_LIGHTS {
        scene.warnings.push(format!(
            "lights: {unbounded} point and spot lights without a \"range\": each is shaded at \
             every pixel (10,000 took about 50 s a frame at 1280×720 on lavapipe); give them a \
             range so that the clustered light loop can skip them where they do not reach"
        ));
    }
    for (i, a) in scene.area_lights.iter().enumerate() {
        use super::area::{AreaMethod, AreaShape};
        let what = format!("area light {i} ({})", a.shape.name());
        if let (AreaShape::Rect { .. } | AreaShape::Disk { .. }, AreaMethod::RepresentativePoint) =
            (a.shape, a.method)
        {
            scene.warnings.push(format!(
                "lights: {what}: representative point is for spheres and tubes; the GPU shades \
                 this one by LTC"
            ))
        }
    }
    // Every material is known now (the scene's, then the MTL and glTF files'): their textures
    // together within the input budget, from the images' headers, before any is decoded.
    if let Err((material, reason)) = super::textures::check_total_pixels(&scene.materials) {
        return Err(Invalid::new(&format!("material \"{material}\""), reason));
    }
    tessellation::resolve(&mut scene);
    Ok(scene)
}

/// More point and spot lights without a range than this get a warning: each costs every pixel.
const MANY_UNBOUNDED_LIGHTS: usize = 256;

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
        &[
            "position",
            "target",
            "up",
            "fov_y_deg",
            "near",
            "far",
            "projection",
            "ortho_half_height",
        ],
        "the camera",
    )?;
    let projection = match f.choice("projection", &["perspective", "orthographic"])? {
        Some("orthographic") => {
            if f.has("fov_y_deg") {
                return Err(f.err(
                    "fov_y_deg",
                    "is for perspective cameras; an orthographic camera takes ortho_half_height",
                ));
            }
            let Some(v) = f.get("ortho_half_height") else {
                return Err(f.err(
                    "ortho_half_height",
                    "missing required field (an orthographic camera's half view height)",
                ));
            };
            let half_height = number(v, &f.path("ortho_half_height"), Check::Positive)?;
            Projection::Orthographic { half_height }
        }
        _ => {
            if f.has("ortho_half_height") {
                return Err(f.err(
                    "ortho_half_height",
                    "is for orthographic cameras; add \"projection\": \"orthographic\"",
                ));
            }
            Projection::Perspective
        }
    };
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
    if !(target - position).is_finite() {
        return Err(f.err(
            "target",
            "is too far from position: target − position overflows 32-bit floats",
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
        projection,
    })
}

fn output(v: &Value, path: &str) -> Result<Output> {
    let f = Fields::new(v, path)?;
    f.allow(
        &[
            "width",
            "height",
            "background",
            "transparent",
            "exposure",
            "tonemap",
            "msaa",
            "tessellation_error_px",
            "golden",
            "refraction",
        ],
        "the output",
    )?;
    let width = f.int("width", 1280, 1, MAX_IMAGE_SIZE)?;
    let height = f.int("height", 720, 1, MAX_IMAGE_SIZE)?;
    let background = f.color("background", Vec3::ZERO)?;
    let transparent = f.boolean("transparent", false)?;
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
        Check::In(0.0, tessellation::MAX_TESSELLATION_ERROR_PX),
    )?;
    // 0 is full detail (meshes unsimplified, primitives at the most segments); a positive budget
    // below the smallest is a typo rather than a wish.
    if tessellation_error_px > 0.0
        && tessellation_error_px < tessellation::MIN_TESSELLATION_ERROR_PX
    {
        return Err(f.err(
            "tessellation_error_px",
            format!(
                "must be 0 (full detail) or at least {}, got {tessellation_error_px}",
                tessellation::MIN_TESSELLATION_ERROR_PX
            ),
        ));
    }
    let golden = match f.get("golden") {
        None => crate::diff::ToleranceOverrides::default(),
        Some(v) => crate::diff::ToleranceOverrides::parse(&to_serde(v)).map_err(|e| {
            let at = f.path("golden");
            match e.field.as_str() {
                "" => Invalid::new(&at, e.reason),
                field => Invalid::new(&format!("{at}.{field}"), e.reason),
            }
        })?,
    };
    let names = super::Refraction::ALL.map(super::Refraction::name);
    let refraction = f
        .choice("refraction", &names)?
        .and_then(super::Refraction::from_name)
        .unwrap_or_default();
    Ok(Output {
        width,
        height,
        background,
        transparent,
        exposure,
        tonemap,
        msaa,
        tessellation_error_px,
        golden,
        refraction,
    })
}

/// The scene parser's value as `serde_json`'s (a number `serde_json` cannot hold, such as
/// `1e999`, becomes its text, which the readers then reject by name).
fn to_serde(v: &Value) -> serde_json::Value {
    use super::json::Kind;
    match &v.kind {
        Kind::Null => serde_json::Value::Null,
        Kind::Bool(b) => serde_json::Value::Bool(*b),
        Kind::Number { value, raw } => serde_json::Number::from_f64(*value).map_or_else(
            || serde_json::Value::String(raw.clone()),
            serde_json::Value::Number,
        ),
        Kind::String(s) => serde_json::Value::String(s.clone()),
        Kind::Array(a) => serde_json::Value::Array(a.iter().map(to_serde).collect()),
        Kind::Object(o) => {
            serde_json::Value::Object(o.iter().map(|(k, v)| (k.clone(), to_serde(v))).collect())
        }
    }
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
        &[
            "directional",
            "point",
            "spot",
            "rect",
            "disk",
            "sphere",
            "tube",
        ],
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
                "shadow",
                "angular_radius_deg",
            ],
            "a directional light",
        ),
        LightKind::Point => (
            &[
                "type",
                "position",
                "color",
                "intensity",
                "falloff",
                "range",
                "shadow",
                "radius",
            ],
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
                "range",
                "umbra_deg",
                "inner_deg",
                "exponent",
                "shadow",
                "radius",
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
    // Directional lights do not allow the key (`allow` above names it as unknown for them).
    let range = match f.get("range") {
        None => None,
        Some(v) => Some(number(v, &f.path("range"), Check::Positive)?),
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
    // Keys a kind does not take were refused by `allow` above.
    let radius = f.num("radius", 0.0, Check::NonNegative)?;
    let angular_radius_deg = f.num("angular_radius_deg", 0.0, Check::In(0.0, 45.0))?;
    let shadow = match f.get("shadow") {
        None => None,
        Some(v) => shadow::shadow(
            v,
            &f.path("shadow"),
            kind,
            radius > 0.0 || angular_radius_deg > 0.0,
        )?,
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
        range,
        shadow,
        radius,
        angular_radius_deg,
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
