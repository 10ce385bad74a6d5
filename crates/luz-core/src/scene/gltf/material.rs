//! glTF materials → luz `metal_rough` materials with texture maps, and glTF images → texture
//! references (files next to the glTF, or bytes embedded in a buffer view or a data URI).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Vec2, Vec3};
use gltf::texture::{MagFilter, MinFilter, WrappingMode};

use super::ext::{Ext, Range};
use super::primitive::UvChoice;
use super::GltfError;
use crate::brdf::MetalRoughParams;
use crate::scene::{
    AlphaMode, Filter, Material, MaterialTextures, SamplerDesc, Sides, TextureRef, Wrap,
};

/// A glTF material as luz understands it.
#[derive(Debug, Clone)]
pub struct GltfMaterial {
    /// The file's name for it (or `material<i>`).
    pub name: String,
    pub material: Material,
    pub textures: MaterialTextures,
    /// The UV set and texture transform the maps read (baked into the meshes' UVs).
    pub uv: UvChoice,
}

/// The glTF default material (no `material` on a primitive): metallic 1, roughness 1, white, as
/// the specification says.
pub fn default_material() -> GltfMaterial {
    GltfMaterial {
        name: "default".into(),
        material: Material::MetalRough(MetalRoughParams::default()),
        // glTF's default material is single-sided.
        textures: MaterialTextures {
            sides: Sides::Single,
            ..MaterialTextures::default()
        },
        uv: UvChoice::default(),
    }
}

/// The images of a file: resolved once, shared by the textures that use them.
pub struct Images {
    /// Per image: a path (an external file) and, for embedded images, their bytes.
    pub sources: Vec<(PathBuf, Option<Arc<[u8]>>)>,
}

impl Images {
    /// Resolves every image: a file next to the glTF (checked to exist), a data URI (decoded) or a
    /// buffer view (copied out of its buffer).
    pub fn resolve(
        doc: &gltf::Document,
        file: &Path,
        buffers: &[Vec<u8>],
    ) -> Result<Images, GltfError> {
        let base = file.parent().unwrap_or(Path::new(""));
        let mut sources = Vec::new();
        for img in doc.images() {
            let i = img.index();
            let name = PathBuf::from(format!("{}: images[{i}]", file.display()));
            let source = match img.source() {
                gltf::image::Source::View { view, .. } => {
                    let buffer = buffers.get(view.buffer().index());
                    let bytes = buffer
                        .and_then(|b| {
                            b.get(view.offset()..view.offset().checked_add(view.length())?)
                        })
                        .ok_or_else(|| {
                            GltfError::at(
                                file,
                                format!("images[{i}].bufferView"),
                                format!(
                                    "bufferViews[{}] lies past the end of its buffer",
                                    view.index()
                                ),
                            )
                        })?;
                    (name, Some(Arc::from(bytes)))
                }
                gltf::image::Source::Uri { uri, .. } => {
                    if uri.starts_with("data:") {
                        let bytes = super::data_uri(uri)
                            .map_err(|e| GltfError::at(file, format!("images[{i}].uri"), e))?;
                        (name, Some(Arc::from(bytes)))
                    } else {
                        let path = crate::files::resolve_inside(
                            base,
                            &super::percent_decode(uri),
                            crate::files::InputBudget::current().allow_outside_uris,
                        )
                        .map_err(|e| GltfError::at(file, format!("images[{i}].uri"), e))?;
                        if !path.is_file() {
                            return Err(GltfError::at(
                                file,
                                format!("images[{i}].uri"),
                                format!("{}: no such image file", path.display()),
                            ));
                        }
                        (path, None)
                    }
                }
            };
            sources.push(source);
        }
        Ok(Images { sources })
    }
}

fn sampler(s: &gltf::texture::Sampler) -> SamplerDesc {
    let wrap = |w: WrappingMode| match w {
        WrappingMode::ClampToEdge => Wrap::Clamp,
        WrappingMode::MirroredRepeat => Wrap::Mirror,
        WrappingMode::Repeat => Wrap::Repeat,
    };
    let mut d = SamplerDesc {
        wrap_u: wrap(s.wrap_s()),
        wrap_v: wrap(s.wrap_t()),
        ..SamplerDesc::default()
    };
    if let Some(MagFilter::Nearest) = s.mag_filter() {
        d.mag = Filter::Nearest;
    }
    // luz's mip filter follows the minification filter: NEAREST_MIPMAP_LINEAR and
    // LINEAR_MIPMAP_NEAREST take their texel filter's mip filter.
    match s.min_filter() {
        None => {}
        Some(MinFilter::Nearest) => {
            d.min = Filter::Nearest;
            d.mipmaps = false;
        }
        Some(MinFilter::Linear) => d.mipmaps = false,
        Some(MinFilter::NearestMipmapNearest) | Some(MinFilter::NearestMipmapLinear) => {
            d.min = Filter::Nearest
        }
        Some(MinFilter::LinearMipmapNearest) | Some(MinFilter::LinearMipmapLinear) => {}
    }
    d
}

/// The texture reference of a glTF texture, reading `channel`.
fn texture_ref(t: &gltf::Texture, images: &Images, channel: Option<u8>) -> Option<TextureRef> {
    let (path, embedded) = images.sources.get(t.source().index())?.clone();
    Some(TextureRef {
        path,
        sampler: sampler(&t.sampler()),
        channel,
        embedded,
    })
}

/// A file's textures, for the extensions that read texture infos by index.
pub struct TextureSource<'a> {
    pub doc: &'a gltf::Document,
    pub images: &'a Images,
}

impl TextureSource<'_> {
    /// How many textures the file has.
    pub fn count(&self) -> usize {
        self.doc.textures().len()
    }

    /// Texture `index` (checked against [`TextureSource::count`] by the caller) reading
    /// `channel`.
    pub fn get(&self, index: usize, channel: Option<u8>) -> Option<TextureRef> {
        let t = self.doc.textures().nth(index)?;
        texture_ref(&t, self.images, channel)
    }
}

/// How one map reads its UVs: (set, transform).
fn uv_of(info_set: u32, tt: Option<gltf::texture::TextureTransform>) -> UvChoice {
    match tt {
        None => UvChoice {
            set: info_set,
            ..UvChoice::default()
        },
        Some(t) => UvChoice {
            set: t.tex_coord().unwrap_or(info_set),
            offset: Vec2::from_array(t.offset()),
            rotation: t.rotation(),
            scale: Vec2::from_array(t.scale()),
        },
    }
}

/// The dielectric F0 of material `m` (named `name`) from KHR_materials_ior and
/// KHR_materials_specular, as the latter's specification computes it:
/// `min(((ior − 1)/(ior + 1))² · specularColorFactor, 1) · specularFactor` (0.04 with neither).
/// Their textures are [`specular`]'s maps. Returns F0 and F90 (`specularFactor`, 1 without the
/// extension).
fn dielectric_f0(m: &gltf::Material) -> (Vec3, f32) {
    // Without either extension, exactly luz's default (0.04).
    // ior 0 is the extension's special value (F0 = 1).
    let ior = m
        .ior()
        .filter(|v| v.is_finite() && (*v >= 1.0 || *v == 0.0));
    let mut f0 = MetalRoughParams::dielectric_f0_from(ior, 1.0, Vec3::ONE);
    let mut f90 = 1.0;
    if let Some(sp) = m.specular() {
        let color = Vec3::from_array(sp.specular_color_factor());
        let color = if color.is_finite() {
            color.max(Vec3::ZERO)
        } else {
            Vec3::ONE
        };
        let factor = sp.specular_factor();
        let factor = if factor.is_finite() {
            factor.clamp(0.0, 1.0)
        } else {
            1.0
        };
        f0 = MetalRoughParams::dielectric_f0_from(ior, factor, color);
        f90 = factor;
    }
    (f0, f90)
}

/// Maps glTF material `m` onto `metal_rough` with maps; sentences about what is not used go to
/// `warnings`.
pub fn material(
    m: &gltf::Material,
    images: &Images,
    file_name: &str,
    warnings: &mut Vec<String>,
) -> GltfMaterial {
    let i = m.index().unwrap_or(0);
    let name = m
        .name()
        .filter(|n| !n.trim().is_empty())
        .map(str::to_string)
        .unwrap_or_else(|| format!("material{i}"));
    let pbr = m.pbr_metallic_roughness();
    let [r, g, b, alpha] = pbr.base_color_factor();
    let clamp = |v: f32| {
        if v.is_finite() {
            v.clamp(0.0, 1.0)
        } else {
            0.0
        }
    };
    let (dielectric_f0, dielectric_f90) = dielectric_f0(m);
    let params = MetalRoughParams {
        base_color: Vec3::new(clamp(r), clamp(g), clamp(b)),
        metallic: clamp(pbr.metallic_factor()),
        roughness: clamp(pbr.roughness_factor()),
        dielectric_f0,
        dielectric_f90,
        ..MetalRoughParams::default()
    };
    let mut t = MaterialTextures {
        alpha: clamp(alpha),
        alpha_mode: match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask {
                cutoff: m
                    .alpha_cutoff()
                    .filter(|c| c.is_finite())
                    .unwrap_or(0.5)
                    .max(0.0),
            },
            gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        },
        sides: if m.double_sided() {
            Sides::Double
        } else {
            Sides::Single
        },
        ..MaterialTextures::default()
    };
    // (uv of each map present, in priority order: base colour first).
    let mut uvs: Vec<(&str, UvChoice)> = Vec::new();
    if let Some(info) = pbr.base_color_texture() {
        t.base_color = texture_ref(&info.texture(), images, None);
        uvs.push((
            "baseColorTexture",
            uv_of(info.tex_coord(), info.texture_transform()),
        ));
    }
    let occlusion = m.occlusion_texture();
    if let Some(info) = pbr.metallic_roughness_texture() {
        let tex = info.texture();
        let same_as_occlusion = occlusion
            .as_ref()
            .is_some_and(|o| o.texture().index() == tex.index());
        if same_as_occlusion {
            // Packed occlusion (R), roughness (G), metallic (B): luz's `orm` map.
            t.orm = texture_ref(&tex, images, None);
        } else {
            t.roughness = texture_ref(&tex, images, Some(1));
            t.metallic = texture_ref(&tex, images, Some(2));
        }
        uvs.push((
            "metallicRoughnessTexture",
            uv_of(info.tex_coord(), info.texture_transform()),
        ));
    }
    if let Some(n) = m.normal_texture() {
        t.normal = texture_ref(&n.texture(), images, None);
        let s = n.scale();
        t.normal_scale = if s.is_finite() { s } else { 1.0 };
        uvs.push(("normalTexture", uv_of(n.tex_coord(), None)));
    }
    if let Some(o) = &occlusion {
        if t.orm.is_none() {
            t.occlusion = texture_ref(&o.texture(), images, Some(0));
        }
        t.occlusion_strength = clamp(o.strength());
        uvs.push(("occlusionTexture", uv_of(o.tex_coord(), None)));
    }
    let strength = m.emissive_strength().filter(|s| s.is_finite() && *s >= 0.0);
    let [er, eg, eb] = m.emissive_factor();
    let nonneg = |v: f32| if v.is_finite() { v.max(0.0) } else { 0.0 };
    t.emissive_factor = Vec3::new(nonneg(er), nonneg(eg), nonneg(eb)) * strength.unwrap_or(1.0);
    if let Some(info) = m.emissive_texture() {
        t.emissive = texture_ref(&info.texture(), images, None);
        uvs.push((
            "emissiveTexture",
            uv_of(info.tex_coord(), info.texture_transform()),
        ));
    }
    let uv = uvs.first().map(|(_, u)| *u).unwrap_or_default();
    if let Some((map, other)) = uvs.iter().find(|(_, u)| *u != uv) {
        let first = uvs[0].0;
        warnings.push(uv_set_warning(
            (file_name, i, &name),
            map,
            other.set,
            (first, uv.set),
        ));
    }
    GltfMaterial {
        name,
        material: Material::MetalRough(params),
        textures: t,
        uv,
    }
}

/// KHR_materials_ior's `ior` checked (its value is read by [`dielectric_f0`]): a number, 0 (the
/// extension's special value) or at least 1; anything else is an error naming the JSON path.
pub fn ior(
    m: &gltf::Material,
    _gm: &mut GltfMaterial,
    _textures: &TextureSource,
    (file, _file_name): (&Path, &str),
    _warnings: &mut Vec<String>,
) -> Result<(), GltfError> {
    // The gltf crate reads the extension itself (`ior()`), so the check is on its value.
    match m.ior() {
        Some(ior) if !ior.is_finite() || ior < 0.0 || (ior > 0.0 && ior < 1.0) => {
            let i = m.index().unwrap_or(0);
            Err(GltfError {
                file: file.to_path_buf(),
                path: format!("materials[{i}].extensions.KHR_materials_ior.ior"),
                reason: format!(
                    "must be 0 (the extension's special value) or at least 1, got {ior}"
                ),
            })
        }
        _ => Ok(()),
    }
}

/// KHR_materials_clearcoat's factors onto `gm` (a `metal_rough` material). Factors outside
/// [0, 1] or not numbers, and textures whose index names no texture, are errors naming the JSON
/// path. `clearcoatTexture` (R), `clearcoatRoughnessTexture` (G) and `clearcoatNormalTexture`
/// (with its `scale`) become the `clearcoat`, `clearcoat_roughness` and `clearcoat_normal`
/// maps.
pub fn clearcoat(
    m: &gltf::Material,
    gm: &mut GltfMaterial,
    textures: &TextureSource,
    (file, file_name): (&Path, &str),
    warnings: &mut Vec<String>,
) -> Result<(), GltfError> {
    let Some(e) = Ext::of(m, "KHR_materials_clearcoat", file)? else {
        return Ok(());
    };
    let (coat, roughness) = (
        e.number("clearcoatFactor", 0.0, Range::Unit)?,
        e.number("clearcoatRoughnessFactor", 0.0, Range::Unit)?,
    );
    // The coat normal's scale, as normalTexture's (a number; 1 without one).
    let scale = match e
        .obj
        .get("clearcoatNormalTexture")
        .and_then(|t| t.get("scale"))
    {
        None => 1.0,
        Some(v) => v.as_f64().filter(|s| s.is_finite()).ok_or_else(|| {
            e.err(
                "clearcoatNormalTexture.scale",
                format!("expected a number, got {v}"),
            )
        })? as f32,
    };
    let Material::MetalRough(p) = &mut gm.material else {
        return Ok(());
    };
    p.clearcoat = coat;
    p.clearcoat_roughness = roughness;
    use crate::scene::TextureSlot as S;
    attach_maps(
        (m, gm, textures, &e),
        &[
            ("clearcoatTexture", S::Clearcoat, None),
            ("clearcoatRoughnessTexture", S::ClearcoatRoughness, Some(1)),
            ("clearcoatNormalTexture", S::ClearcoatNormal, None),
        ],
        file_name,
        warnings,
    )?;
    gm.textures.clearcoat_normal_scale = scale;
    Ok(())
}

/// KHR_materials_sheen onto `gm` (a `metal_rough` material), checked like the clear coat;
/// `sheenColorTexture` (RGB) and `sheenRoughnessTexture` (A) become the `sheen_color` and
/// `sheen_roughness` maps.
pub fn sheen(
    m: &gltf::Material,
    gm: &mut GltfMaterial,
    textures: &TextureSource,
    (file, file_name): (&Path, &str),
    warnings: &mut Vec<String>,
) -> Result<(), GltfError> {
    let Some(e) = Ext::of(m, "KHR_materials_sheen", file)? else {
        return Ok(());
    };
    let (color, roughness) = (
        e.color("sheenColorFactor", Vec3::ZERO)?,
        e.number("sheenRoughnessFactor", 0.0, Range::Unit)?,
    );
    let Material::MetalRough(p) = &mut gm.material else {
        return Ok(());
    };
    p.sheen_color = color;
    p.sheen_roughness = roughness;
    use crate::scene::TextureSlot as S;
    attach_maps(
        (m, gm, textures, &e),
        &[
            ("sheenColorTexture", S::SheenColor, None),
            ("sheenRoughnessTexture", S::SheenRoughness, Some(3)),
        ],
        file_name,
        warnings,
    )
}

/// KHR_materials_anisotropy onto `gm` (a `metal_rough` material): strength in [0, 1], rotation
/// any finite angle in radians, and `anisotropyTexture` as the `anisotropy` map (RG direction,
/// B strength).
pub fn anisotropy(
    m: &gltf::Material,
    gm: &mut GltfMaterial,
    textures: &TextureSource,
    (file, file_name): (&Path, &str),
    warnings: &mut Vec<String>,
) -> Result<(), GltfError> {
    let Some(e) = Ext::of(m, "KHR_materials_anisotropy", file)? else {
        return Ok(());
    };
    let (strength, rotation) = (
        e.number("anisotropyStrength", 0.0, Range::Unit)?,
        e.number("anisotropyRotation", 0.0, Range::Finite)?,
    );
    let Material::MetalRough(p) = &mut gm.material else {
        return Ok(());
    };
    p.anisotropy_strength = strength;
    p.anisotropy_rotation = rotation;
    let i = m.index().unwrap_or(0);
    attach_map(
        gm,
        textures,
        (&e, "anisotropyTexture"),
        (crate::scene::TextureSlot::Anisotropy, None),
        (i, file_name),
        warnings,
    )
}

/// KHR_materials_iridescence's factors onto `gm` (a `metal_rough` material): factor in [0, 1],
/// ior ≥ 1, thicknesses ≥ 0 (nm) with the minimum not above the maximum; `iridescenceTexture`
/// (R) and `iridescenceThicknessTexture` (G) become the `iridescence` and
/// `iridescence_thickness` maps (without a thickness texture the film is
/// `iridescenceThicknessMaximum` thick, as the extension says).
pub fn iridescence(
    m: &gltf::Material,
    gm: &mut GltfMaterial,
    textures: &TextureSource,
    (file, file_name): (&Path, &str),
    warnings: &mut Vec<String>,
) -> Result<(), GltfError> {
    let Some(e) = Ext::of(m, "KHR_materials_iridescence", file)? else {
        return Ok(());
    };
    let d = crate::brdf::MetalRoughParams::default();
    let factor = e.number("iridescenceFactor", 0.0, Range::Unit)?;
    let ior = e.number("iridescenceIor", d.iridescence_ior, Range::Positive)?;
    if let Some(why) = crate::brdf::film_ior_error(ior) {
        return Err(e.err("iridescenceIor", why));
    }
    let min = e.number(
        "iridescenceThicknessMinimum",
        d.iridescence_thickness_min,
        Range::NonNegative,
    )?;
    let max = e.number(
        "iridescenceThicknessMaximum",
        d.iridescence_thickness_max,
        Range::NonNegative,
    )?;
    if let Some(why) = crate::brdf::film_range_error(min, max) {
        return Err(e.err("iridescenceThicknessMinimum", why));
    }
    let Material::MetalRough(p) = &mut gm.material else {
        return Ok(());
    };
    p.iridescence = factor;
    p.iridescence_ior = ior;
    p.iridescence_thickness_min = min;
    p.iridescence_thickness_max = max;
    use crate::scene::TextureSlot as S;
    attach_maps(
        (m, gm, textures, &e),
        &[
            ("iridescenceTexture", S::Iridescence, None),
            (
                "iridescenceThicknessTexture",
                S::IridescenceThickness,
                Some(1),
            ),
        ],
        file_name,
        warnings,
    )
}

/// Extension `e`'s textures `(key, slot, channel)` of material `m` attached with [`attach_map`].
fn attach_maps(
    (m, gm, textures, e): (&gltf::Material, &mut GltfMaterial, &TextureSource, &Ext),
    maps: &[(&str, crate::scene::TextureSlot, Option<u8>)],
    file_name: &str,
    warnings: &mut Vec<String>,
) -> Result<(), GltfError> {
    let i = m.index().unwrap_or(0);
    for &(key, slot, channel) in maps {
        attach_map(
            gm,
            textures,
            (e, key),
            (slot, channel),
            (i, file_name),
            warnings,
        )?;
    }
    Ok(())
}

/// KHR_materials_specular's textures onto `gm` (its factors are [`dielectric_f0`]'s):
/// `specularTexture` (A) and `specularColorTexture` (RGB, sRGB) become the `specular_factor` and
/// `specular_color` maps.
pub fn specular(
    m: &gltf::Material,
    gm: &mut GltfMaterial,
    textures: &TextureSource,
    (_file, file_name): (&Path, &str),
    warnings: &mut Vec<String>,
) -> Result<(), GltfError> {
    let Some(sp) = m.specular() else {
        return Ok(());
    };
    if !matches!(gm.material, Material::MetalRough(_)) {
        return Ok(());
    }
    use crate::scene::TextureSlot as S;
    let i = m.index().unwrap_or(0);
    for (key, info, slot, channel) in [
        (
            "specularTexture",
            sp.specular_texture(),
            S::SpecularFactor,
            Some(3),
        ),
        (
            "specularColorTexture",
            sp.specular_color_texture(),
            S::SpecularColor,
            None,
        ),
    ] {
        let Some(info) = info else { continue };
        let uv = uv_of(info.tex_coord(), info.texture_transform());
        let index = info.texture().index();
        attach(
            gm,
            textures,
            (index, uv),
            (slot, channel),
            (i, file_name, key),
            warnings,
        );
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
    (slot, channel): (crate::scene::TextureSlot, Option<u8>),
    (i, file_name): (usize, &str),
    warnings: &mut Vec<String>,
) -> Result<(), GltfError> {
    let Some((index, uv)) = e.texture_info(key, textures.count())? else {
        return Ok(());
    };
    attach(
        gm,
        textures,
        (index, uv),
        (slot, channel),
        (i, file_name, key),
        warnings,
    );
    Ok(())
}

/// The warning for material `i` of `file_name` named `name` whose `map` reads UV set `set` (with
/// its own transform) where the material's maps take `first`'s, set `first_set`: luz gives every
/// map of a material one UV set and transform.
fn uv_set_warning(
    (file_name, i, name): (&str, usize, &str),
    map: &str,
    set: u32,
    (first, first_set): (&str, u32),
) -> String {
    format!(
        "{file_name}: materials[{i}] (\"{name}\"): {map} reads UV set {set} with its own \
         transform; luz gives all maps of a material the UVs of its {first} (set {first_set})"
    )
}

/// Texture `index` read through `uv` as `gm`'s `slot` map (`key` names it in the warning when
/// its UVs differ from the material's first map's).
fn attach(
    gm: &mut GltfMaterial,
    textures: &TextureSource,
    (index, uv): (usize, UvChoice),
    (slot, channel): (crate::scene::TextureSlot, Option<u8>),
    (i, file_name, key): (usize, &str, &str),
    warnings: &mut Vec<String>,
) {
    if gm.textures.maps().next().is_none() {
        gm.uv = uv;
    } else if uv != gm.uv {
        warnings.push(uv_set_warning(
            (file_name, i, &gm.name),
            key,
            uv.set,
            ("first map", gm.uv.set),
        ));
    }
    *gm.textures.get_mut(slot) = textures.get(index, channel);
}
