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
        attach_map(
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

/// Extension `e`'s texture `key` (if any) as `gm`'s `slot` map (`channel`: the channel holding
/// a single value, `None` = R). A material's maps share one UV set and transform (baked into
/// the meshes' UVs): the first map's, as for the core maps; another is one warning.
pub(super) fn attach_map(
    gm: &mut GltfMaterial,
    textures: &TextureSource,
    (e, key): (&Ext, &str),
    (slot, channel): (TextureSlot, Option<u8>),
    (i, file_name): (usize, &str),
    warnings: &mut Vec<String>,
) -> Result<(), GltfError> {
    let Some((index, uv)) = e.texture_info(key, textures.count())? else {
        return Ok(());
    };
    if gm.textures.maps().next().is_none() {
        gm.uv = uv;
    } else if uv != gm.uv {
        warnings.push(format!(
            "{file_name}: materials[{i}] (\"{}\"): {key} reads UV set {} with its own \
             transform; luz gives all maps of a material the UVs of its first map (set {})",
            gm.name, uv.set, gm.uv.set
        ));
    }
    *gm.textures.get_mut(slot) = textures.get(index, channel);
    Ok(())
}
