//! Issue 35's glass extensions onto a `metal_rough` material: `KHR_materials_transmission`,
//! `KHR_materials_volume`, `KHR_materials_dispersion` and `KHR_materials_diffuse_transmission`.
//! Factors outside their range or not numbers, and textures whose index names no texture, are
//! errors naming the JSON path; the textures themselves are not read yet (one warning per file
//! and extension), their factors are.

use std::path::Path;

use glam::Vec3;
use serde_json::{Map, Value};

use super::material::warn_material;
use super::{GltfError, GltfMaterial};
use crate::brdf::Transmission;
use crate::scene::Material;

/// A number's allowed range.
#[derive(Clone, Copy)]
enum Range {
    Unit,
    NonNegative,
    Positive,
}

impl Range {
    fn check(self, x: f64) -> Result<(), String> {
        let ok = match self {
            Range::Unit => (0.0..=1.0).contains(&x),
            Range::NonNegative => x >= 0.0,
            Range::Positive => x > 0.0,
        };
        if ok && x.is_finite() {
            return Ok(());
        }
        Err(match self {
            Range::Unit => format!("must be in [0, 1], got {x}"),
            Range::NonNegative => format!("must be ≥ 0, got {x}"),
            Range::Positive => format!("must be > 0, got {x}"),
        })
    }
}

/// One extension object of one material, with errors at `materials[i].extensions.NAME.key`.
struct Ext<'a> {
    obj: &'a Map<String, Value>,
    path: String,
    file: &'a Path,
}

impl Ext<'_> {
    fn err(&self, key: &str, reason: String) -> GltfError {
        GltfError {
            file: self.file.to_path_buf(),
            path: format!("{}.{key}", self.path),
            reason,
        }
    }

    fn number(&self, key: &str, default: f32, range: Range) -> Result<f32, GltfError> {
        let Some(v) = self.obj.get(key) else {
            return Ok(default);
        };
        let x = v
            .as_f64()
            .ok_or_else(|| self.err(key, format!("expected a number, got {v}")))?;
        range.check(x).map_err(|r| self.err(key, r))?;
        Ok(x as f32)
    }

    fn color(&self, key: &str, default: Vec3) -> Result<Vec3, GltfError> {
        let Some(v) = self.obj.get(key) else {
            return Ok(default);
        };
        let items = v
            .as_array()
            .filter(|a| a.len() == 3)
            .ok_or_else(|| self.err(key, format!("expected 3 numbers, got {v}")))?;
        let mut c = [0.0f32; 3];
        for (k, item) in items.iter().enumerate() {
            let x = item.as_f64().ok_or_else(|| {
                self.err(
                    &format!("{key}[{k}]"),
                    format!("expected a number, got {item}"),
                )
            })?;
            Range::Unit
                .check(x)
                .map_err(|r| self.err(&format!("{key}[{k}]"), r))?;
            c[k] = x as f32;
        }
        Ok(Vec3::from(c))
    }

    /// Whether any of `keys` is a texture info naming an existing texture (an error when it
    /// names none or has no index).
    fn has_textures(&self, keys: &[&str], textures: usize) -> Result<bool, GltfError> {
        let mut any = false;
        for key in keys {
            let Some(info) = self.obj.get(*key) else {
                continue;
            };
            match info.get("index").and_then(|v| v.as_u64()) {
                Some(t) if (t as usize) < textures => any = true,
                Some(t) => {
                    return Err(self.err(
                        &format!("{key}.index"),
                        format!("texture {t} does not exist (the file has {textures})"),
                    ))
                }
                None => {
                    return Err(self.err(key, "expected a texture info with an \"index\"".into()))
                }
            }
        }
        Ok(any)
    }
}

/// The four extensions of `m` onto `gm` (left alone when it is not `metal_rough`).
pub fn transmission(
    m: &gltf::Material,
    gm: &mut GltfMaterial,
    textures: usize,
    (file, file_name): (&Path, &str),
    warnings: &mut Vec<String>,
) -> Result<(), GltfError> {
    let i = m.index().unwrap_or(0);
    let mut t = Transmission::default();
    let ext = |name: &str| -> Result<Option<Ext<'_>>, GltfError> {
        let Some(v) = m.extension_value(name) else {
            return Ok(None);
        };
        let path = format!("materials[{i}].extensions.{name}");
        match v.as_object() {
            Some(obj) => Ok(Some(Ext { obj, path, file })),
            None => Err(GltfError {
                file: file.to_path_buf(),
                path,
                reason: "expected an object".into(),
            }),
        }
    };
    let mut unused = Vec::new();
    if let Some(e) = ext("KHR_materials_transmission")? {
        t.factor = e.number("transmissionFactor", t.factor, Range::Unit)?;
        if e.has_textures(&["transmissionTexture"], textures)? {
            unused.push("KHR_materials_transmission's transmissionTexture");
        }
    }
    if let Some(e) = ext("KHR_materials_volume")? {
        t.thickness = e.number("thicknessFactor", t.thickness, Range::NonNegative)?;
        t.attenuation_color = e.color("attenuationColor", t.attenuation_color)?;
        if e.obj.contains_key("attenuationDistance") {
            t.attenuation_distance =
                Some(e.number("attenuationDistance", f32::INFINITY, Range::Positive)?);
        }
        if e.has_textures(&["thicknessTexture"], textures)? {
            unused.push("KHR_materials_volume's thicknessTexture");
        }
    }
    if let Some(e) = ext("KHR_materials_dispersion")? {
        t.dispersion = e.number("dispersion", t.dispersion, Range::NonNegative)?;
    }
    if let Some(e) = ext("KHR_materials_diffuse_transmission")? {
        t.diffuse = e.number("diffuseTransmissionFactor", t.diffuse, Range::Unit)?;
        t.diffuse_color = e.color("diffuseTransmissionColorFactor", t.diffuse_color)?;
        let keys = [
            "diffuseTransmissionTexture",
            "diffuseTransmissionColorTexture",
        ];
        if e.has_textures(&keys, textures)? {
            unused.push("KHR_materials_diffuse_transmission's textures");
        }
    }
    for what in unused {
        let marker = format!("{file_name}: {what} not used (luz reads their factors):");
        warn_material(warnings, marker, i, &gm.name);
    }
    if let Material::MetalRough(p) = &mut gm.material {
        p.transmission = t;
    }
    Ok(())
}
