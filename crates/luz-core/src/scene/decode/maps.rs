//! Texture maps of materials: a material's `textures` block, and the maps of MTL materials.

use std::path::{Path, PathBuf};

use glam::Vec3;

use super::{
    a_material, file_name, Check, Fields, Invalid, Kind, Result, Value, MTL_DEFAULT_SHININESS, UNIT,
};
use crate::brdf::MetalRoughParams;
use crate::scene::obj::{MtlMap, MtlMaterial, TEXTURE_EXTENSIONS};
use crate::scene::Material;
use crate::scene::{
    slots_for_model, Filter, MaterialTextures, SamplerDesc, TextureRef, TextureSlot, Wrap,
};

/// The keys of a `textures` block: the maps, then their factors.
const TEXTURE_FIELDS: &[&str] = &[
    "base_color",
    "specular",
    "metallic",
    "roughness",
    "orm",
    "normal",
    "occlusion",
    "emissive",
    "transmission",
    "thickness",
    "diffuse_transmission",
    "diffuse_transmission_color",
    "anisotropy",
    "clearcoat",
    "clearcoat_roughness",
    "sheen_color",
    "sheen_roughness",
    "specular_factor",
    "specular_color",
    "iridescence",
    "iridescence_thickness",
    "clearcoat_normal",
    "normal_scale",
    "clearcoat_normal_scale",
    "occlusion_strength",
    "emissive_factor",
];

/// The keys of a texture given as an object.
const TEXTURE_REF_FIELDS: &[&str] = &[
    "path",
    "wrap",
    "wrap_u",
    "wrap_v",
    "filter",
    "mag_filter",
    "min_filter",
    "mipmaps",
    "anisotropy",
    "channel",
];

const WRAPS: &[(&str, Wrap)] = &[
    ("repeat", Wrap::Repeat),
    ("clamp", Wrap::Clamp),
    ("mirror", Wrap::Mirror),
];

const FILTERS: &[(&str, Filter)] = &[("nearest", Filter::Nearest), ("linear", Filter::Linear)];

const CHANNELS: &[(&str, u8)] = &[("r", 0), ("g", 1), ("b", 2), ("a", 3)];

/// The `textures` block of the material object `v` (at `path`, its model already validated);
/// the default (no maps) without one. Files are resolved against `base` and must exist.
pub(super) fn material_textures(v: &Value, path: &str, base: &Path) -> Result<MaterialTextures> {
    let m = Fields::new(v, path)?;
    let Some(t) = m.get("textures") else {
        return Ok(MaterialTextures::default());
    };
    let model = m.string("model")?.unwrap_or("");
    let f = Fields::new(t, &m.path("textures"))?;
    f.allow(TEXTURE_FIELDS, "a textures block")?;
    // The model was validated by the material's decoder (an unknown one would take the fewest).
    let kind = crate::brdf::ModelKind::from_name(model).unwrap_or(crate::brdf::ModelKind::Lambert);
    let takes = slots_for_model(kind);
    // What the block asks for is checked before any file is looked at.
    for slot in TextureSlot::ALL {
        if f.has(slot.name()) && !takes.contains(&slot) {
            let names: Vec<&str> = takes.iter().map(|s| s.name()).collect();
            return Err(f.err(
                slot.name(),
                format!(
                    "{} takes no \"{}\" map; the maps it takes: {}",
                    a_material(model),
                    slot.name(),
                    names.join(", ")
                ),
            ));
        }
    }
    if f.has("orm") {
        if let Some(key) = ["metallic", "roughness", "occlusion"]
            .into_iter()
            .find(|k| f.has(k))
        {
            return Err(f.err(
                key,
                format!(
                    "\"orm\" already gives occlusion (R), roughness (G) and metallic (B); give either orm or a separate {key} map, not both"
                ),
            ));
        }
    }
    let mut out = MaterialTextures::default();
    for slot in TextureSlot::ALL {
        if let Some(v) = f.get(slot.name()) {
            *out.get_mut(slot) = Some(texture_ref(v, &f.path(slot.name()), slot, base)?);
        }
    }
    if f.has("normal_scale") && out.normal.is_none() {
        return Err(f.err("normal_scale", "given without a \"normal\" map"));
    }
    out.normal_scale = f.num("normal_scale", 1.0, Check::Any)?;
    if f.has("clearcoat_normal_scale") && out.clearcoat_normal.is_none() {
        return Err(f.err(
            "clearcoat_normal_scale",
            "given without a \"clearcoat_normal\" map",
        ));
    }
    out.clearcoat_normal_scale = f.num("clearcoat_normal_scale", 1.0, Check::Any)?;
    if f.has("occlusion_strength") && out.occlusion.is_none() && out.orm.is_none() {
        return Err(f.err(
            "occlusion_strength",
            "given without an \"occlusion\" or \"orm\" map",
        ));
    }
    out.occlusion_strength = f.num("occlusion_strength", 1.0, UNIT)?;
    let emissive_default = if out.emissive.is_some() {
        Vec3::ONE
    } else {
        Vec3::ZERO
    };
    out.emissive_factor = f.color("emissive_factor", emissive_default)?;
    Ok(out)
}

/// One map: a file name, or an object with the file's `path` and sampler settings.
fn texture_ref(v: &Value, path: &str, slot: TextureSlot, base: &Path) -> Result<TextureRef> {
    match &v.kind {
        Kind::String(_) => Ok(TextureRef::new(texture_file(v, path, base)?)),
        Kind::Object(_) => {
            let f = Fields::new(v, path)?;
            f.allow(TEXTURE_REF_FIELDS, "a texture")?;
            for (both, each) in [("wrap", ["wrap_u", "wrap_v"]), ("filter", ["mag_filter", "min_filter"])] {
                if let Some(k) = each.iter().find(|k| f.has(k)).filter(|_| f.has(both)) {
                    return Err(f.err(
                        k,
                        format!("\"{both}\" sets both {0} and {1}; give either {both} or {0}/{1}, not both", each[0], each[1]),
                    ));
                }
            }
            let d = SamplerDesc::default();
            let wrap = f.select("wrap", WRAPS, d.wrap_u)?;
            let filter = f.select("filter", FILTERS, d.min)?;
            let sampler = SamplerDesc {
                wrap_u: f.select("wrap_u", WRAPS, wrap)?,
                wrap_v: f.select("wrap_v", WRAPS, wrap)?,
                mag: f.select("mag_filter", FILTERS, filter)?,
                min: f.select("min_filter", FILTERS, filter)?,
                mipmaps: f.boolean("mipmaps", d.mipmaps)?,
                anisotropy: f.num(
                    "anisotropy",
                    d.anisotropy,
                    Check::In(1.0, SamplerDesc::MAX_ANISOTROPY),
                )?,
            };
            let channel = match f.get("channel") {
                None => None,
                Some(_) if !slot.is_single_channel() => {
                    return Err(f.err(
                        "channel",
                        format!(
                            "a {} map uses all its channels; \"channel\" applies to single-value maps (metallic, roughness, occlusion, transmission, thickness, diffuse_transmission)",
                            slot.name()
                        ),
                    ))
                }
                Some(_) => Some(f.select("channel", CHANNELS, 0)?),
            };
            Ok(TextureRef {
                path: texture_file(f.req("path")?, &f.path("path"), base)?,
                sampler,
                channel,
                embedded: None,
            })
        }
        k => Err(Invalid::new(
            path,
            format!(
                "expected a file name (\"albedo.png\") or an object {{\"path\": \"albedo.png\", \"wrap\": …}}, got {}",
                k.describe()
            ),
        )),
    }
}

/// A texture file name: `.png`, `.exr` or `.hdr`, resolved against `base`, an existing file.
fn texture_file(v: &Value, path: &str, base: &Path) -> Result<PathBuf> {
    let (file, ext) = file_name(v, path, base)?;
    let ext = ext.unwrap_or_default();
    if !TEXTURE_EXTENSIONS.contains(&ext.as_str()) {
        let shown = if ext.is_empty() {
            "no extension".to_string()
        } else {
            format!("\".{ext}\"")
        };
        return Err(Invalid::new(
            path,
            format!(
                "{}: unsupported texture file type ({shown}); expected .png (8 or 16-bit), .exr or .hdr",
                file.display()
            ),
        ));
    }
    // A regular file within the input budget (a FIFO would block the renderer later).
    match crate::files::check_input(&file) {
        Err(e) if e.kind() == std::io::ErrorKind::IsADirectory => Err(Invalid::new(
            path,
            format!("{}: is a directory, not an image file", file.display()),
        )),
        Ok(_) => Ok(file),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Err(Invalid::new(
            path,
            format!(
                "{}: no such file (texture paths are relative to the scene file's folder)",
                file.display()
            ),
        )),
        Err(e) => Err(Invalid::new(
            path,
            format!("{}: cannot read: {e}", file.display()),
        )),
    }
}

/// An MTL map as a scene texture: `-clamp on` clamps, otherwise the default sampler.
fn mtl_texture(m: &MtlMap) -> TextureRef {
    let mut t = TextureRef::new(m.path.clone());
    if m.clamp {
        t.sampler.wrap_u = Wrap::Clamp;
        t.sampler.wrap_v = Wrap::Clamp;
    }
    t.channel = m.channel;
    t
}

/// Blender's mapping of MTL `Ns` to roughness (its OBJ importer): 1 − √(Ns / 1000).
fn roughness_from_ns(ns: f32) -> f32 {
    (1.0 - (ns / 1000.0).max(0.0).sqrt()).clamp(0.0, 1.0)
}

/// The material of an MTL entry and its maps.
///
/// * With the PBR extension (any of `Pr`, `Pm`, `map_Pr`, `map_Pm`): `metal_rough` with
///   base_color = Kd (clamped to [0, 1]), metallic = Pm, roughness = Pr. Without the scalar, a
///   factor is 1 when its map is given (the map alone decides, as glTF); otherwise metallic 0
///   and roughness from Ns (Blender's 1 − √(Ns/1000)), or 0.5 without Ns. `map_Ks` and `Ka` are
///   not used (warned).
/// * Otherwise the classic `phong`: Kd → O_d with kd = 1, Ks → O_s with ks = 1, Ns → n, Ka → ka
///   as its largest channel; `map_Kd` multiplies O_d and `map_Ks` O_s.
///
/// Either way Kd defaults to 1 with a `map_Kd` (the map shows as it is) and 0.8 without, Ks to
/// 1 with a `map_Ks` and 0 without; `map_Bump` (and its variants) is the normal map with
/// normal_scale = `-bm` (1 by default); Ke is the emissive factor (1 with a `map_Ke` and no Ke).
pub(super) fn mtl_material(
    m: &MtlMaterial,
    warnings: &mut Vec<String>,
) -> (Material, MaterialTextures) {
    let maps = &m.maps;
    let pbr = maps.has_pbr() || m.roughness.is_some() || m.metallic.is_some();
    let diffuse = m.diffuse.map_or(
        Vec3::splat(if maps.diffuse.is_some() { 1.0 } else { 0.8 }),
        Vec3::from_array,
    );
    let mut textures = MaterialTextures {
        base_color: maps.diffuse.as_ref().map(mtl_texture),
        normal: maps.normal.as_ref().map(mtl_texture),
        normal_scale: maps
            .normal
            .as_ref()
            .and_then(|n| n.bump_multiplier)
            .unwrap_or(1.0),
        emissive: maps.emissive.as_ref().map(mtl_texture),
        emissive_factor: m.emissive.map_or(
            if maps.emissive.is_some() {
                Vec3::ONE
            } else {
                Vec3::ZERO
            },
            Vec3::from_array,
        ),
        ..MaterialTextures::default()
    };
    let material = if pbr {
        if let Some(s) = &maps.specular {
            warnings.push(format!(
                "{}:{}: map_Ks: material \"{}\" uses the PBR extension (metal_rough), which has no specular colour; ignored",
                s.mtl.display(),
                s.line,
                m.name
            ));
        }
        textures.metallic = maps.metallic.as_ref().map(mtl_texture);
        textures.roughness = maps.roughness.as_ref().map(mtl_texture);
        let metallic = m
            .metallic
            .unwrap_or(if maps.metallic.is_some() { 1.0 } else { 0.0 });
        let roughness = m.roughness.unwrap_or(if maps.roughness.is_some() {
            1.0
        } else {
            m.shininess.map_or(0.5, roughness_from_ns)
        });
        Material::MetalRough(MetalRoughParams {
            base_color: diffuse.clamp(Vec3::ZERO, Vec3::ONE),
            metallic,
            roughness,
            ..MetalRoughParams::default()
        })
    } else {
        textures.specular = maps.specular.as_ref().map(mtl_texture);
        Material::Phong(crate::brdf::PhongParams {
            blinn: false,
            ka: m.ambient.map_or(0.0, |a| a[0].max(a[1]).max(a[2])),
            kd: 1.0,
            ks: 1.0,
            shininess: m.shininess.unwrap_or(MTL_DEFAULT_SHININESS),
            diffuse_color: diffuse,
            specular_color: m.specular.map_or(
                Vec3::splat(if maps.specular.is_some() { 1.0 } else { 0.0 }),
                Vec3::from_array,
            ),
        })
    };
    (material, textures)
}
