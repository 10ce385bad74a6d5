//! Texture maps of a material: which maps, where their files are, how they are sampled.
//!
//! Plain data: the files are only checked to exist here (by the decoder); decoding, mipmaps and
//! downscaling are `crate::texture`'s, GPU upload the renderer's. The scene format is in
//! `docs/scene-format.md` ("Textures").

use std::path::PathBuf;

use glam::Vec3;

/// How texture coordinates outside [0, 1] are treated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Wrap {
    #[default]
    Repeat,
    /// Clamp to the edge texel.
    Clamp,
    /// Repeat, mirroring every other tile.
    Mirror,
}

/// Texel filter for magnification or minification. The filter between mip levels follows
/// `SamplerDesc::min`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Filter {
    Nearest,
    #[default]
    Linear,
}

/// Sampler settings of one texture.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SamplerDesc {
    pub wrap_u: Wrap,
    pub wrap_v: Wrap,
    pub mag: Filter,
    /// Also the filter between mip levels (nearest or linear mipmap mode).
    pub min: Filter,
    /// Generate and sample the full mip chain (default true).
    pub mipmaps: bool,
    /// Maximum anisotropy in [1, 16] (default 16); 1 turns anisotropic filtering off. The
    /// renderer clamps it to the device's limit and ignores it where the device has no
    /// anisotropic filtering; see [`SamplerDesc::anisotropy_for`].
    pub anisotropy: f32,
}

impl Default for SamplerDesc {
    fn default() -> Self {
        SamplerDesc {
            wrap_u: Wrap::Repeat,
            wrap_v: Wrap::Repeat,
            mag: Filter::Linear,
            min: Filter::Linear,
            mipmaps: true,
            anisotropy: 16.0,
        }
    }
}

impl SamplerDesc {
    /// Largest accepted `anisotropy`.
    pub const MAX_ANISOTROPY: f32 = 16.0;

    /// The anisotropy to enable on a device whose `samplerAnisotropy` feature is `supported`
    /// with limit `device_max` (`maxSamplerAnisotropy`): `None` (off) when the device lacks the
    /// feature, when `anisotropy` ≤ 1, or when minification is `nearest` (anisotropic filtering
    /// is a linear-filtering technique); otherwise `anisotropy` clamped to the device's limit.
    pub fn anisotropy_for(&self, supported: bool, device_max: f32) -> Option<f32> {
        let a = self.anisotropy.min(device_max);
        (supported && self.min == Filter::Linear && a > 1.0).then_some(a)
    }
}

/// One texture map: a file and how to sample it.
#[derive(Debug, Clone, PartialEq)]
pub struct TextureRef {
    /// Resolved against the scene file's folder (or, from an MTL file, the MTL's folder). The
    /// decoder checked that it exists and is a `.png`, `.exr` or `.hdr` (a glTF's images may
    /// also be `.jpg`).
    pub path: PathBuf,
    pub sampler: SamplerDesc,
    /// For single-value maps (metallic, roughness, occlusion): the channel holding the value,
    /// 0 = R, 1 = G, 2 = B, 3 = A. `None` means R (a greyscale file has R = G = B). The loader
    /// (`crate::texture`) copies that channel to R, G and B so a shader always reads `.r`.
    pub channel: Option<u8>,
    /// The encoded image itself (PNG or JPEG), for an image embedded in a glTF file (a buffer
    /// view or a data URI); `path` then names it in messages (`model.glb: images[0]`) and is no
    /// file. `None`: the image is the file at `path`.
    pub embedded: Option<std::sync::Arc<[u8]>>,
}

impl TextureRef {
    /// A texture with the default sampler, reading R.
    pub fn new(path: impl Into<PathBuf>) -> Self {
        TextureRef {
            path: path.into(),
            sampler: SamplerDesc::default(),
            channel: None,
            embedded: None,
        }
    }
}

/// What a texture map feeds. The colour slots (base colour, specular colour, emissive) hold
/// sRGB-encoded colour; the others hold linear data (MODELS.md §9).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TextureSlot {
    /// Multiplies the model's main colour: `base_color` (metal_rough, principled),
    /// `diffuse_color` O_d (phong, blinn_phong), `albedo` (lambert, oren_nayar), `color`
    /// (cook_torrance). sRGB.
    BaseColor,
    /// Multiplies the classic model's `specular_color` O_s (phong, blinn_phong). sRGB.
    Specular,
    /// Multiplies `metallic` (metal_rough, principled). Linear, one channel.
    Metallic,
    /// Multiplies `roughness` (cook_torrance, metal_rough, principled). Linear, one channel.
    Roughness,
    /// Packed glTF occlusion (R), roughness (G), metallic (B). Linear.
    Orm,
    /// Tangent-space normal map, glTF convention (+X right, +Y up in the image, i.e. the
    /// "OpenGL" green-up convention), encoded as (n + 1) / 2. Linear.
    Normal,
    /// Ambient occlusion: scales the ambient (indirect) light only. Linear, one channel.
    Occlusion,
    /// Emitted radiance, multiplied by `emissive_factor`. sRGB.
    Emissive,
    /// Multiplies `transmission.transmissionFactor` (metal_rough): glTF's
    /// `KHR_materials_transmission` `transmissionTexture`, R. Linear, one channel.
    Transmission,
    /// Multiplies `volume.thicknessFactor` (metal_rough): glTF's `KHR_materials_volume`
    /// `thicknessTexture`, G. Linear, one channel.
    Thickness,
    /// Multiplies `diffuse_transmission.diffuseTransmissionFactor` (metal_rough): glTF's
    /// `diffuseTransmissionTexture`, A. Linear, one channel.
    DiffuseTransmission,
    /// Multiplies `diffuse_transmission.diffuseTransmissionColorFactor` (metal_rough): glTF's
    /// `diffuseTransmissionColorTexture`, RGB. sRGB.
    DiffuseTransmissionColor,
    /// KHR_materials_anisotropy's `anisotropyTexture` (metal_rough): RG the anisotropy direction
    /// in the tangent frame ([0, 1] → [−1, 1]), turned further by `anisotropyRotation`; B
    /// multiplies `anisotropyStrength`. Linear.
    Anisotropy,
    /// KHR_materials_clearcoat's `clearcoatTexture` (metal_rough): multiplies
    /// `clearcoat.clearcoatFactor`. glTF reads R. Linear, one channel.
    Clearcoat,
    /// KHR_materials_clearcoat's `clearcoatRoughnessTexture`: multiplies
    /// `clearcoat.clearcoatRoughnessFactor`. glTF reads G. Linear, one channel.
    ClearcoatRoughness,
    /// KHR_materials_sheen's `sheenColorTexture`: multiplies `sheen.sheenColorFactor`. sRGB.
    SheenColor,
    /// KHR_materials_sheen's `sheenRoughnessTexture`: multiplies `sheen.sheenRoughnessFactor`.
    /// glTF reads A. Linear, one channel.
    SheenRoughness,
    /// KHR_materials_specular's `specularTexture`: multiplies `specularFactor`, i.e. the
    /// dielectric F0 and F90. glTF reads A. Linear, one channel.
    SpecularFactor,
    /// KHR_materials_specular's `specularColorTexture`: multiplies the dielectric F0's colour
    /// (`specularColorFactor`). sRGB.
    SpecularColor,
    /// KHR_materials_iridescence's `iridescenceTexture`: multiplies
    /// `iridescence.iridescenceFactor`. glTF reads R. Linear, one channel.
    Iridescence,
    /// KHR_materials_iridescence's `iridescenceThicknessTexture`: the film's thickness is
    /// mix(`iridescenceThicknessMinimum`, `iridescenceThicknessMaximum`, texel). glTF reads G.
    /// Linear, one channel.
    IridescenceThickness,
    /// KHR_materials_clearcoat's `clearcoatNormalTexture`: the coat's tangent-space normal
    /// (as `Normal`, scaled by `clearcoat_normal_scale`). Without it the coat's normal is the
    /// geometric one, whatever the base's normal map. Linear.
    ClearcoatNormal,
}

impl TextureSlot {
    /// Every slot, in the order the scene format lists them.
    pub const ALL: [TextureSlot; 22] = [
        TextureSlot::BaseColor,
        TextureSlot::Specular,
        TextureSlot::Metallic,
        TextureSlot::Roughness,
        TextureSlot::Orm,
        TextureSlot::Normal,
        TextureSlot::Occlusion,
        TextureSlot::Emissive,
        TextureSlot::Transmission,
        TextureSlot::Thickness,
        TextureSlot::DiffuseTransmission,
        TextureSlot::DiffuseTransmissionColor,
        TextureSlot::Anisotropy,
        TextureSlot::Clearcoat,
        TextureSlot::ClearcoatRoughness,
        TextureSlot::SheenColor,
        TextureSlot::SheenRoughness,
        TextureSlot::SpecularFactor,
        TextureSlot::SpecularColor,
        TextureSlot::Iridescence,
        TextureSlot::IridescenceThickness,
        TextureSlot::ClearcoatNormal,
    ];

    /// The maps metal_rough takes: every slot but `Specular` (the classic models'), the core
    /// glTF maps first, then glass's, then the layers' (anisotropy, clear coat, sheen, specular,
    /// iridescence).
    const ALL_METAL_ROUGH: [TextureSlot; 21] = {
        let mut out = [TextureSlot::BaseColor; 21];
        let (mut i, mut j) = (0, 0);
        while i < TextureSlot::ALL.len() {
            if !matches!(TextureSlot::ALL[i], TextureSlot::Specular) {
                out[j] = TextureSlot::ALL[i];
                j += 1;
            }
            i += 1;
        }
        out
    };

    /// The key in a scene file's `textures` block.
    pub fn name(self) -> &'static str {
        match self {
            TextureSlot::BaseColor => "base_color",
            TextureSlot::Specular => "specular",
            TextureSlot::Metallic => "metallic",
            TextureSlot::Roughness => "roughness",
            TextureSlot::Orm => "orm",
            TextureSlot::Normal => "normal",
            TextureSlot::Occlusion => "occlusion",
            TextureSlot::Emissive => "emissive",
            TextureSlot::Transmission => "transmission",
            TextureSlot::Thickness => "thickness",
            TextureSlot::DiffuseTransmission => "diffuse_transmission",
            TextureSlot::DiffuseTransmissionColor => "diffuse_transmission_color",
            TextureSlot::Anisotropy => "anisotropy",
            TextureSlot::Clearcoat => "clearcoat",
            TextureSlot::ClearcoatRoughness => "clearcoat_roughness",
            TextureSlot::SheenColor => "sheen_color",
            TextureSlot::SheenRoughness => "sheen_roughness",
            TextureSlot::SpecularFactor => "specular_factor",
            TextureSlot::SpecularColor => "specular_color",
            TextureSlot::Iridescence => "iridescence",
            TextureSlot::IridescenceThickness => "iridescence_thickness",
            TextureSlot::ClearcoatNormal => "clearcoat_normal",
        }
    }

    /// Whether the map holds sRGB-encoded colour (decoded to linear when sampled).
    pub fn is_srgb(self) -> bool {
        matches!(
            self,
            TextureSlot::BaseColor
                | TextureSlot::Specular
                | TextureSlot::Emissive
                | TextureSlot::DiffuseTransmissionColor
                | TextureSlot::SheenColor
                | TextureSlot::SpecularColor
        )
    }

    /// Whether the map holds one value, so a `channel` may be chosen.
    pub fn is_single_channel(self) -> bool {
        matches!(
            self,
            TextureSlot::Metallic
                | TextureSlot::Roughness
                | TextureSlot::Occlusion
                | TextureSlot::Transmission
                | TextureSlot::Thickness
                | TextureSlot::DiffuseTransmission
                | TextureSlot::Clearcoat
                | TextureSlot::ClearcoatRoughness
                | TextureSlot::SheenRoughness
                | TextureSlot::SpecularFactor
                | TextureSlot::Iridescence
                | TextureSlot::IridescenceThickness
        )
    }
}

/// The texture maps of a material; every map is optional.
///
/// Factors multiply as in glTF: the shaded base colour is the material's colour × the base
/// colour map, metallic = `metallic` × map, roughness = `roughness` × map (a packed `orm` map
/// gives occlusion in R, roughness in G and metallic in B, and excludes the separate
/// `metallic`, `roughness` and `occlusion` maps).
#[derive(Debug, Clone, PartialEq)]
pub struct MaterialTextures {
    /// sRGB.
    pub base_color: Option<TextureRef>,
    /// sRGB; the classic models' O_s only.
    pub specular: Option<TextureRef>,
    /// Linear; channel selectable (default R).
    pub metallic: Option<TextureRef>,
    /// Linear; channel selectable (default R).
    pub roughness: Option<TextureRef>,
    /// Packed: R = occlusion, G = roughness, B = metallic (glTF). Linear.
    pub orm: Option<TextureRef>,
    /// Tangent space, linear.
    pub normal: Option<TextureRef>,
    /// n = normalize((2·texel − 1) · (normal_scale, normal_scale, 1)), as glTF. Default 1.
    pub normal_scale: f32,
    /// Linear; channel selectable (default R).
    pub occlusion: Option<TextureRef>,
    /// ambient × (1 + occlusion_strength · (occlusion − 1)), as glTF; in [0, 1], default 1.
    pub occlusion_strength: f32,
    /// sRGB.
    pub emissive: Option<TextureRef>,
    /// Glass (metal_rough's `transmission`, `volume`, `diffuse_transmission`): linear, channel
    /// selectable (default R; glTF's files give R, G, A).
    pub transmission: Option<TextureRef>,
    pub thickness: Option<TextureRef>,
    pub diffuse_transmission: Option<TextureRef>,
    /// sRGB.
    pub diffuse_transmission_color: Option<TextureRef>,
    /// KHR_materials_anisotropy's direction (RG) and strength (B). Linear.
    pub anisotropy: Option<TextureRef>,
    /// The layers' maps (KHR_materials_clearcoat, _sheen, _specular, _iridescence), each
    /// multiplying its factor ([`TextureSlot`]); the colours sRGB, the others linear with a
    /// selectable channel.
    pub clearcoat: Option<TextureRef>,
    pub clearcoat_roughness: Option<TextureRef>,
    pub sheen_color: Option<TextureRef>,
    pub sheen_roughness: Option<TextureRef>,
    pub specular_factor: Option<TextureRef>,
    pub specular_color: Option<TextureRef>,
    pub iridescence: Option<TextureRef>,
    pub iridescence_thickness: Option<TextureRef>,
    /// Tangent space, linear: the coat's normal.
    pub clearcoat_normal: Option<TextureRef>,
    /// The coat normal's scale, as `normal_scale` (glTF's `clearcoatNormalTexture.scale`).
    /// Default 1.
    pub clearcoat_normal_scale: f32,
    /// Emitted radiance = emissive_factor × emissive map (× 1 without a map). Linear RGB.
    /// Default: [1, 1, 1] with an emissive map, [0, 0, 0] without one.
    pub emissive_factor: Vec3,
    /// How the base colour's alpha (`alpha` × the base colour map's alpha × the vertex colours'
    /// alpha) covers: glTF's `alphaMode`. Default opaque.
    pub alpha_mode: AlphaMode,
    /// Base colour alpha factor (glTF `baseColorFactor[3]`), in [0, 1]; default 1.
    pub alpha: f32,
    /// Which faces are drawn and how back faces are lit (glTF's `doubleSided`).
    pub sides: Sides,
}

/// glTF's `alphaMode`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum AlphaMode {
    /// Alpha is ignored.
    #[default]
    Opaque,
    /// Fully opaque where alpha ≥ `cutoff`, not there at all below it.
    Mask { cutoff: f32 },
    /// Composited over what is behind ("over", straight alpha): drawn after the opaque objects,
    /// back to front by object, without writing depth.
    Blend,
}

/// Alpha at or above which a BLEND surface casts a shadow ([`AlphaMode::shadow_cutoff`]).
pub const BLEND_SHADOW_CUTOFF: f32 = 0.5;

impl AlphaMode {
    /// The alpha below which a surface casts no shadow, or `None` when alpha does not matter
    /// (opaque): a mask's cutoff; for BLEND [`BLEND_SHADOW_CUTOFF`], an approximation (a
    /// shadow map holds one depth per texel, not a fraction of the light: docs/shadows.md#alpha).
    /// The GPU's depth pass and the CPU reference's shadow rays both use it.
    pub fn shadow_cutoff(self) -> Option<f32> {
        match self {
            AlphaMode::Opaque => None,
            AlphaMode::Mask { cutoff } => Some(cutoff),
            AlphaMode::Blend => Some(BLEND_SHADOW_CUTOFF),
        }
    }
}

/// Which faces of a material's meshes are drawn, and how back faces are lit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Sides {
    /// luz's own rule for scene files: closed primitives (sphere, cube, …) cull back faces; open
    /// ones (planes, OBJ and glTF meshes) draw both sides and light a back face with its front
    /// normal.
    #[default]
    Auto,
    /// glTF `doubleSided: false`: back faces are culled.
    Single,
    /// glTF `doubleSided: true`: both sides drawn, a back face lit with the flipped normal
    /// (and tangent frame).
    Double,
}

impl Default for MaterialTextures {
    fn default() -> Self {
        MaterialTextures {
            base_color: None,
            specular: None,
            metallic: None,
            roughness: None,
            orm: None,
            normal: None,
            normal_scale: 1.0,
            occlusion: None,
            occlusion_strength: 1.0,
            emissive: None,
            transmission: None,
            thickness: None,
            diffuse_transmission: None,
            diffuse_transmission_color: None,
            anisotropy: None,
            clearcoat: None,
            clearcoat_roughness: None,
            sheen_color: None,
            sheen_roughness: None,
            specular_factor: None,
            specular_color: None,
            iridescence: None,
            iridescence_thickness: None,
            clearcoat_normal: None,
            clearcoat_normal_scale: 1.0,
            emissive_factor: Vec3::ZERO,
            alpha_mode: AlphaMode::Opaque,
            alpha: 1.0,
            sides: Sides::Auto,
        }
    }
}

impl MaterialTextures {
    /// The map in `slot`.
    pub fn get(&self, slot: TextureSlot) -> Option<&TextureRef> {
        match slot {
            TextureSlot::BaseColor => self.base_color.as_ref(),
            TextureSlot::Specular => self.specular.as_ref(),
            TextureSlot::Metallic => self.metallic.as_ref(),
            TextureSlot::Roughness => self.roughness.as_ref(),
            TextureSlot::Orm => self.orm.as_ref(),
            TextureSlot::Normal => self.normal.as_ref(),
            TextureSlot::Occlusion => self.occlusion.as_ref(),
            TextureSlot::Emissive => self.emissive.as_ref(),
            TextureSlot::Transmission => self.transmission.as_ref(),
            TextureSlot::Thickness => self.thickness.as_ref(),
            TextureSlot::DiffuseTransmission => self.diffuse_transmission.as_ref(),
            TextureSlot::DiffuseTransmissionColor => self.diffuse_transmission_color.as_ref(),
            TextureSlot::Anisotropy => self.anisotropy.as_ref(),
            TextureSlot::Clearcoat => self.clearcoat.as_ref(),
            TextureSlot::ClearcoatRoughness => self.clearcoat_roughness.as_ref(),
            TextureSlot::SheenColor => self.sheen_color.as_ref(),
            TextureSlot::SheenRoughness => self.sheen_roughness.as_ref(),
            TextureSlot::SpecularFactor => self.specular_factor.as_ref(),
            TextureSlot::SpecularColor => self.specular_color.as_ref(),
            TextureSlot::Iridescence => self.iridescence.as_ref(),
            TextureSlot::IridescenceThickness => self.iridescence_thickness.as_ref(),
            TextureSlot::ClearcoatNormal => self.clearcoat_normal.as_ref(),
        }
    }

    /// Mutable access to the map in `slot`.
    pub fn get_mut(&mut self, slot: TextureSlot) -> &mut Option<TextureRef> {
        match slot {
            TextureSlot::BaseColor => &mut self.base_color,
            TextureSlot::Specular => &mut self.specular,
            TextureSlot::Metallic => &mut self.metallic,
            TextureSlot::Roughness => &mut self.roughness,
            TextureSlot::Orm => &mut self.orm,
            TextureSlot::Normal => &mut self.normal,
            TextureSlot::Occlusion => &mut self.occlusion,
            TextureSlot::Emissive => &mut self.emissive,
            TextureSlot::Transmission => &mut self.transmission,
            TextureSlot::Thickness => &mut self.thickness,
            TextureSlot::DiffuseTransmission => &mut self.diffuse_transmission,
            TextureSlot::DiffuseTransmissionColor => &mut self.diffuse_transmission_color,
            TextureSlot::Anisotropy => &mut self.anisotropy,
            TextureSlot::Clearcoat => &mut self.clearcoat,
            TextureSlot::ClearcoatRoughness => &mut self.clearcoat_roughness,
            TextureSlot::SheenColor => &mut self.sheen_color,
            TextureSlot::SheenRoughness => &mut self.sheen_roughness,
            TextureSlot::SpecularFactor => &mut self.specular_factor,
            TextureSlot::SpecularColor => &mut self.specular_color,
            TextureSlot::Iridescence => &mut self.iridescence,
            TextureSlot::IridescenceThickness => &mut self.iridescence_thickness,
            TextureSlot::ClearcoatNormal => &mut self.clearcoat_normal,
        }
    }

    /// The maps present, in [`TextureSlot::ALL`] order.
    pub fn maps(&self) -> impl Iterator<Item = (TextureSlot, &TextureRef)> {
        TextureSlot::ALL
            .into_iter()
            .filter_map(|s| self.get(s).map(|t| (s, t)))
    }

    /// True when no map is given and nothing is emitted.
    pub fn is_empty(&self) -> bool {
        self.maps().next().is_none() && self.emissive_factor == Vec3::ZERO
    }
}

/// The maps a material model takes. Metallic, roughness and packed maps need the parameters they
/// multiply; every model takes a base colour (its main colour), a normal map, an occlusion map
/// and emission.
pub fn slots_for_model(model: crate::brdf::ModelKind) -> &'static [TextureSlot] {
    use crate::brdf::ModelKind as K;
    use TextureSlot::*;
    match model {
        K::Phong | K::BlinnPhong => &[BaseColor, Specular, Normal, Occlusion, Emissive],
        K::CookTorrance => &[BaseColor, Roughness, Normal, Occlusion, Emissive],
        // Every slot but the classic models' specular colour; principled has no glass.
        K::MetalRough => &TextureSlot::ALL_METAL_ROUGH,
        K::Principled => &TextureSlot::ALL_METAL_ROUGH[..7],
        K::Lambert | K::OrenNayar => &[BaseColor, Normal, Occlusion, Emissive],
    }
}

/// Width × height that the header of `r`'s image declares (PNG, JPEG, EXR, HDR), read without
/// decoding a pixel; None when the header cannot be read (decoding reports that later, naming
/// the file).
pub fn declared_pixels(r: &TextureRef) -> Option<u64> {
    use image::ImageReader;
    let (w, h) = match &r.embedded {
        Some(bytes) => ImageReader::new(std::io::Cursor::new(&bytes[..]))
            .with_guessed_format()
            .ok()?
            .into_dimensions()
            .ok()?,
        None => {
            let file = crate::files::open_input(&r.path).ok()?;
            ImageReader::new(std::io::BufReader::new(file))
                .with_guessed_format()
                .ok()?
                .into_dimensions()
                .ok()?
        }
    };
    Some(u64::from(w) * u64::from(h))
}

/// The scene's textures against the input budget's total
/// ([`crate::files::InputBudget::max_texture_pixels_total`]): each distinct image (a file by
/// path, an embedded image by its bytes) counted once from its header, before any is decoded.
/// Images beyond the one-texture limit are left to the decoder (its message names that limit).
/// `Err((material, reason))` names the material and the image that passes the budget.
pub fn check_total_pixels(materials: &[super::NamedMaterial]) -> Result<u64, (String, String)> {
    let budget = crate::files::InputBudget::current();
    let (one, all) = (budget.max_texture_pixels, budget.max_texture_pixels_total);
    let mut seen = std::collections::HashSet::new();
    let mut total = 0u64;
    for m in materials {
        for slot in TextureSlot::ALL {
            let Some(r) = m.textures.get(slot) else {
                continue;
            };
            let id = match &r.embedded {
                Some(bytes) => (PathBuf::new(), bytes.as_ptr() as usize),
                None => (r.path.clone(), 0),
            };
            if !seen.insert(id) {
                continue;
            }
            // An image beyond the one-texture limit is refused by the decoder, with its own
            // message and flag.
            let Some(pixels) = declared_pixels(r).filter(|&p| p <= one) else {
                continue;
            };
            total = total.saturating_add(pixels);
            if total > all {
                let mpix = |p: u64| p as f64 / crate::files::MPIX as f64;
                return Err((
                    m.name.clone(),
                    format!(
                        "{}: its {:.1} Mpix bring the scene's textures to {:.1} Mpix, beyond \
                         the input budget's total of {:.0} Mpix (1 Mpix = 1024 × 1024 pixels; \
                         raise it with --max-texture-mpix-total)",
                        r.path.display(),
                        mpix(pixels),
                        mpix(total),
                        mpix(all)
                    ),
                ));
            }
        }
    }
    Ok(total)
}
