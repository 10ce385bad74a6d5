//! Issue 35's glass extensions onto a `metal_rough` material: `KHR_materials_transmission`,
//! `KHR_materials_volume`, `KHR_materials_dispersion` and `KHR_materials_diffuse_transmission`.
//! Factors outside their range or not numbers, and textures whose index names no texture, are
//! errors naming the JSON path; the textures themselves are not read yet (one warning per file
//! and extension), their factors are.

use std::path::Path;

use super::ext::{Ext, Range};
use super::material::warn_material;
use super::{GltfError, GltfMaterial};
use crate::brdf::Transmission;
use crate::scene::Material;

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
    let ext = |name: &str| Ext::of(m, name, file);
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
