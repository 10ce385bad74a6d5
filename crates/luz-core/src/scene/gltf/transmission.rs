//! Issue 35's glass extensions onto a `metal_rough` material: `KHR_materials_transmission`,
//! `KHR_materials_volume`, `KHR_materials_dispersion` and `KHR_materials_diffuse_transmission`.
//! Factors outside their range or not numbers, and textures whose index names no texture, are
//! errors naming the JSON path. The textures become the material's `transmission` (R),
//! `thickness` (G), `diffuse_transmission` (A) and `diffuse_transmission_color` (RGB) maps.

use std::path::Path;

use super::ext::{Ext, Range};
use super::material::TextureSource;
use super::{GltfError, GltfMaterial};
use crate::brdf::Transmission;
use crate::scene::{Material, TextureSlot};

/// The four extensions of `m` onto `gm` (left alone when it is not `metal_rough`).
pub fn transmission(
    m: &gltf::Material,
    gm: &mut GltfMaterial,
    textures: &TextureSource,
    (file, file_name): (&Path, &str),
    warnings: &mut Vec<String>,
) -> Result<(), GltfError> {
    let i = m.index().unwrap_or(0);
    let mut t = Transmission::default();
    let ext = |name: &str| Ext::of(m, name, file);
    // (slot, the extension, its key, the channel the extension puts the value in; None = R).
    let mut maps = Vec::new();
    if let Some(e) = ext("KHR_materials_transmission")? {
        t.factor = e.number("transmissionFactor", t.factor, Range::Unit)?;
        maps.push((TextureSlot::Transmission, e, "transmissionTexture", None));
    }
    if let Some(e) = ext("KHR_materials_volume")? {
        t.thickness = e.number("thicknessFactor", t.thickness, Range::NonNegative)?;
        t.attenuation_color = e.color("attenuationColor", t.attenuation_color)?;
        if e.obj.contains_key("attenuationDistance") {
            t.attenuation_distance =
                Some(e.number("attenuationDistance", f32::INFINITY, Range::Positive)?);
        }
        maps.push((TextureSlot::Thickness, e, "thicknessTexture", Some(1)));
    }
    if let Some(e) = ext("KHR_materials_dispersion")? {
        t.dispersion = e.number("dispersion", t.dispersion, Range::NonNegative)?;
    }
    if let Some(e) = ext("KHR_materials_diffuse_transmission")? {
        t.diffuse = e.number("diffuseTransmissionFactor", t.diffuse, Range::Unit)?;
        t.diffuse_color = e.color("diffuseTransmissionColorFactor", t.diffuse_color)?;
        let key = "diffuseTransmissionColorTexture";
        maps.push((TextureSlot::DiffuseTransmissionColor, e.clone(), key, None));
        maps.push((
            TextureSlot::DiffuseTransmission,
            e,
            "diffuseTransmissionTexture",
            Some(3),
        ));
    }
    let Material::MetalRough(p) = &mut gm.material else {
        return Ok(());
    };
    p.transmission = t;
    for (slot, e, key, channel) in maps {
        super::material::attach_map(
            gm,
            textures,
            (&e, key),
            (slot, channel),
            (i, file_name),
            warnings,
        )?;
    }
    Ok(())
}
