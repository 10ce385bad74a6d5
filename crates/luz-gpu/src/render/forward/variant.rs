//! Pipeline variants of the forward pass: what distinguishes one pipeline from another
//! ([`VariantKey`]: shading frequency, model, BRDF terms, fog, debug view, IBL method, maps, light
//! kinds), its name in reports, and building it (specialization constants) and the skybox.

use std::sync::Arc;

use ash::vk;

use std::collections::HashMap;

use super::{Output, TargetFormat};
use crate::brdf::{Diffuse, Distribution, Fresnel, Geometry, ModelKind};
use crate::render::gpu::{self, Vertex};
use crate::scene::Shading;
use crate::vk::pipeline::{GraphicsDesc, Pipeline, PipelineLayout};
use crate::vk::shaders::ShaderModule;
use crate::vk::{Context, VkError};

/// A quantity shown instead of the shaded radiance (specialization constant `DEBUG_VIEW`; the
/// codes are `DEBUG_VIEW_*` of `shaders_glsl/include/bindings.glsl`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub enum DebugView {
    /// The shaded radiance (no debug view).
    #[default]
    None,
    /// The material's base colour after its maps.
    BaseColor,
    /// The shading normal, (n + 1)/2.
    Normal,
    /// Metallic, as grey.
    Metallic,
    /// Roughness, as grey.
    Roughness,
    /// Ambient occlusion, as grey.
    Ao,
    /// D of the first light's half vector.
    D,
    /// G for the first light.
    G,
    /// F for the first light (RGB).
    F,
    /// The diffuse part of f for the first light.
    Diffuse,
    /// The specular part of f for the first light.
    Specular,
    /// The environment's irradiance E(n)/π.
    Irradiance,
    /// The prefiltered environment along the reflection at the material's roughness.
    Prefiltered,
    /// The shaded radiance with NaN and Inf pixels in magenta.
    Nan,
    /// Lights the fragment loops over (its cluster's, or all with the plain loop) as a heat map:
    /// blue (none) through green to red (64 or more).
    Clusters,
    /// The first shadowed light's visibility (1 lit, 0 in shadow), as grey.
    Shadow,
    /// The first shadowed light's map layer each point reads (cascade or cube face), one colour
    /// each; dark grey beyond the last cascade.
    ShadowLayers,
}

impl DebugView {
    /// Every view, in code order.
    pub const ALL: [DebugView; 17] = [
        DebugView::None,
        DebugView::BaseColor,
        DebugView::Normal,
        DebugView::Metallic,
        DebugView::Roughness,
        DebugView::Ao,
        DebugView::D,
        DebugView::G,
        DebugView::F,
        DebugView::Diffuse,
        DebugView::Specular,
        DebugView::Irradiance,
        DebugView::Prefiltered,
        DebugView::Nan,
        DebugView::Clusters,
        DebugView::Shadow,
        DebugView::ShadowLayers,
    ];

    /// The name on the command line, in scripts and in the viewer.
    pub fn name(self) -> &'static str {
        match self {
            DebugView::None => "none",
            DebugView::BaseColor => "base_color",
            DebugView::Normal => "normal",
            DebugView::Metallic => "metallic",
            DebugView::Roughness => "roughness",
            DebugView::Ao => "ao",
            DebugView::D => "d",
            DebugView::G => "g",
            DebugView::F => "f",
            DebugView::Diffuse => "diffuse",
            DebugView::Specular => "specular",
            DebugView::Irradiance => "irradiance",
            DebugView::Prefiltered => "prefiltered",
            DebugView::Nan => "nan",
            DebugView::Clusters => "clusters",
            DebugView::Shadow => "shadow",
            DebugView::ShadowLayers => "shadow_layers",
        }
    }

    /// The view named `name` (case-insensitive), if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|v| v.name().eq_ignore_ascii_case(name))
    }

    /// One line of help: what the view shows.
    pub fn help(self) -> &'static str {
        match self {
            DebugView::None => "the shaded radiance (no debug view)",
            DebugView::BaseColor => "the material's base colour after its maps",
            DebugView::Normal => "the shading normal, (n + 1)/2",
            DebugView::Metallic => "metallic, as grey",
            DebugView::Roughness => "roughness, as grey",
            DebugView::Ao => "ambient occlusion, as grey",
            DebugView::D => "D of the first light's half vector",
            DebugView::G => "G for the first light",
            DebugView::F => "F for the first light (RGB)",
            DebugView::Diffuse => "the diffuse part of f for the first light",
            DebugView::Specular => "the specular part of f for the first light",
            DebugView::Irradiance => "the environment's irradiance E(n)/π",
            DebugView::Prefiltered => {
                "the prefiltered environment along the reflection at the material's roughness"
            }
            DebugView::Nan => "the shaded radiance with NaN and Inf pixels in magenta",
            DebugView::Clusters => {
                "lights looped over per fragment (its cluster's), blue 0 to red 64 or more"
            }
            DebugView::Shadow => "the first shadowed light's visibility, 1 lit to 0 in shadow",
            DebugView::ShadowLayers => {
                "the first shadowed light's map layer per point (cascade or cube face), a colour each"
            }
        }
    }

    /// The value of the `DEBUG_VIEW` specialization constant.
    pub fn id(self) -> u32 {
        use crate::render::gpu::glsl::include_bindings as glsl;
        match self {
            DebugView::None => glsl::DEBUG_VIEW_NONE,
            DebugView::BaseColor => glsl::DEBUG_VIEW_BASE_COLOR,
            DebugView::Normal => glsl::DEBUG_VIEW_NORMAL,
            DebugView::Metallic => glsl::DEBUG_VIEW_METALLIC,
            DebugView::Roughness => glsl::DEBUG_VIEW_ROUGHNESS,
            DebugView::Ao => glsl::DEBUG_VIEW_AO,
            DebugView::D => glsl::DEBUG_VIEW_D,
            DebugView::G => glsl::DEBUG_VIEW_G,
            DebugView::F => glsl::DEBUG_VIEW_F,
            DebugView::Diffuse => glsl::DEBUG_VIEW_DIFFUSE,
            DebugView::Specular => glsl::DEBUG_VIEW_SPECULAR,
            DebugView::Irradiance => glsl::DEBUG_VIEW_IRRADIANCE,
            DebugView::Prefiltered => glsl::DEBUG_VIEW_PREFILTERED,
            DebugView::Nan => glsl::DEBUG_VIEW_NAN,
            DebugView::Clusters => glsl::DEBUG_VIEW_CLUSTERS,
            DebugView::Shadow => glsl::DEBUG_VIEW_SHADOW,
            DebugView::ShadowLayers => glsl::DEBUG_VIEW_SHADOW_LAYERS,
        }
    }
}

/// What distinguishes one pipeline from another.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct VariantKey {
    pub shading: ShadingKey,
    pub model: ModelKind,
    pub fog: bool,
    pub debug: DebugView,
    /// Image-based lighting settings, when the scene has an environment.
    pub ibl: Option<IblKey>,
    /// The material's BRDF terms, fixed in the pipeline or read at run time.
    pub terms: TermsKey,
    /// Bit i: the material has map `TextureSlot::ALL[i]` (no texture code without maps).
    pub maps: u32,
    /// The scene's light types and falloffs (`gpu::LK_*` bits).
    pub light_kinds: u32,
    /// The fragment stage loops over its cluster's lights only (`CLUSTERED`).
    pub clustered: bool,
    /// The shadowed lights, each packed in a specialization constant
    /// ([`crate::render::shadow::fixed_slots`]; all zero: looked up per pixel).
    pub shadow_slots: [u32; 4],
    /// The material's alpha mode (`ALPHA_MODE`; blending and no depth writes for `Blend`).
    pub alpha: AlphaKey,
    /// The mesh's vertex colours multiply the base colour (Phong shading only: the
    /// `*_color` modules, vertex buffer binding 2).
    pub vertex_color: bool,
    /// The glTF extension layers compiled in (`LOBES`, `BRDF_LOBE_*` bits; [`lobe_bits`]): a
    /// lobe no material of the pipeline uses costs nothing.
    pub lobes: u32,
    /// How transmissive materials are drawn (`REFRACTION`, the scene's `output.refraction`).
    pub refraction: crate::scene::Refraction,
}

/// Every lobe: the generic ("all features") pipeline's [`VariantKey::lobes`].
pub const GENERIC_LOBES: u32 = u32::MAX;

/// The `BRDF_LOBE_*` bits of the layers `m` uses (issues 34, 35): clearcoat, sheen (a colour
/// that is not black), transmission, dispersion (with a volume), diffuse transmission,
/// anisotropy (GGX only) and iridescence (with a thickness above 0) when their factors are
/// above 0. The film has two bits, one per form (at each light's v·h, or at the view): a
/// pipeline compiles only the forms its materials take.
pub fn lobe_bits(m: &crate::scene::Material) -> u32 {
    use crate::glsl::brdf_models as glsl;
    let crate::brdf::Model::MetalRough(p) = m.sanitized() else {
        return 0;
    };
    let t = p.transmission;
    [
        (p.clearcoat > 0.0, glsl::BRDF_LOBE_CLEARCOAT),
        (p.sheen_color != glam::Vec3::ZERO, glsl::BRDF_LOBE_SHEEN),
        (t.factor > 0.0, glsl::BRDF_LOBE_TRANSMISSION),
        (
            t.factor > 0.0 && t.dispersion > 0.0 && !t.thin_walled(),
            glsl::BRDF_LOBE_DISPERSION,
        ),
        (t.diffuse > 0.0, glsl::BRDF_LOBE_DIFFUSE_TRANSMISSION),
        (
            p.anisotropy_strength > 0.0 && p.distribution == crate::brdf::Distribution::Ggx,
            glsl::BRDF_LOBE_ANISOTROPY,
        ),
        (
            crate::brdf::has_iridescence(&p) && !p.iridescence_at_view,
            glsl::BRDF_LOBE_IRIDESCENCE,
        ),
        (
            crate::brdf::has_iridescence(&p) && p.iridescence_at_view,
            glsl::BRDF_LOBE_IRIDESCENCE_VIEW,
        ),
    ]
    .into_iter()
    .filter(|(on, _)| *on)
    .fold(0, |bits, (_, bit)| bits | bit)
}

/// The `REFRACTION` specialization constant of `r`.
pub fn refraction_code(r: crate::scene::Refraction) -> u32 {
    use crate::glsl::include_bindings as b;
    use crate::scene::Refraction as R;
    match r {
        R::Screen => b::REFRACTION_SCREEN,
        R::ScreenFilament => b::REFRACTION_SCREEN_FILAMENT,
        R::ScreenSharp => b::REFRACTION_SCREEN_SHARP,
        R::Thin => b::REFRACTION_THIN,
        R::None => b::REFRACTION_NONE,
        R::Environment => b::REFRACTION_ENVIRONMENT,
    }
}

/// glTF's alpha mode as a pipeline sees it ([`crate::scene::AlphaMode`] without the cutoff,
/// which is material data).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum AlphaKey {
    Opaque,
    Mask,
    Blend,
}

impl AlphaKey {
    pub fn of(m: crate::scene::AlphaMode) -> Self {
        match m {
            crate::scene::AlphaMode::Opaque => Self::Opaque,
            crate::scene::AlphaMode::Mask { .. } => Self::Mask,
            crate::scene::AlphaMode::Blend => Self::Blend,
        }
    }

    /// The value of the `ALPHA_MODE` specialization constant.
    fn code(self) -> u32 {
        use crate::render::gpu::glsl::include_bindings as glsl;
        match self {
            Self::Opaque => glsl::ALPHA_OPAQUE,
            Self::Mask => glsl::ALPHA_MASK,
            Self::Blend => glsl::ALPHA_BLEND,
        }
    }
}

impl VariantKey {
    /// This variant with the lookups of the fixed shadow slots whose bit is clear in `lights`
    /// skipped (`SHADOW_FIXED_SKIP`: no lookup compiled), the others kept: what a draw that only
    /// those lights' shadows can reach needs (`ForwardPass::receive_slots`).
    pub fn receiving(&self, lights: u32) -> VariantKey {
        let skip = crate::render::shadow::FIXED_SKIP;
        let mut v = *self;
        for (k, code) in v.shadow_slots.iter_mut().enumerate() {
            if *code != 0 {
                *code = if lights & (1 << k) == 0 {
                    *code | skip
                } else {
                    *code & !skip
                };
            }
        }
        v
    }

    /// This variant with every fixed shadow slot skipped: no lookup compiled (where no shadow
    /// can fall on a draw).
    pub fn unshadowed(&self) -> VariantKey {
        self.receiving(0)
    }

    /// Whether a Phong-shaded pipeline interpolates the tangent and texture coordinates too
    /// (`forward.vert`'s `PHONG_MAPS`): only with texture maps, or for a model that reads the
    /// tangent frame (Principled's anisotropy). The lean variant saves lavapipe's triangle setup
    /// six of thirteen interpolated floats.
    pub fn phong_maps(&self) -> bool {
        self.maps != 0 || self.model == ModelKind::Principled || self.vertex_color
    }

    /// Whether a Phong-shaded pipeline without maps interpolates the tangent's direction only
    /// (`PHONG_TANGENT`, three floats instead of the maps' six): for KHR_materials_anisotropy.
    pub fn phong_tangent(&self) -> bool {
        self.shading == ShadingKey::Phong
            && !self.phong_maps()
            && self.lobes & crate::glsl::brdf_models::BRDF_LOBE_ANISOTROPY != 0
    }

    /// The `forward.vert` / `forward.frag` variant this key's pipeline is built from.
    pub fn module_variant(&self) -> String {
        let mut s = self.shading.name().to_string();
        if self.shading == ShadingKey::Phong && self.phong_maps() {
            s.push_str("_maps");
            if self.vertex_color {
                s.push_str("_color");
            }
        } else if self.phong_tangent() {
            s.push_str("_tangent");
        }
        if self.ibl.is_some() {
            s.push_str("_ibl");
        }
        s
    }

    /// Whether the vertex stage reads the texture coordinates and tangent attributes.
    fn reads_uv_tangent(&self) -> bool {
        self.shading != ShadingKey::Phong || self.phong_maps()
    }
}

/// The model and the BRDF terms of a material, as its pipeline variant is specialised.
pub fn material_key(m: &crate::scene::Material) -> (crate::brdf::ModelKind, TermsKey) {
    (m.kind(), TermsKey::of(m))
}

/// The BRDF terms a pipeline is specialised for (`SEL_DISTRIBUTION`, `SEL_GEOMETRY`,
/// `SEL_FRESNEL`, `SEL_DIFFUSE`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum TermsKey {
    /// "All features": the shader reads the selectors from the push constants (-1).
    Generic,
    /// The model has no selectable terms (the shader ignores the selectors; 0, and -1 for the
    /// diffuse).
    Unused,
    /// Cook-Torrance and metallic-roughness: D, G, F and the diffuse lobe, compiled in.
    Fixed(Distribution, Geometry, Fresnel, Diffuse),
}

impl TermsKey {
    /// The terms of `m` as its pipeline is specialised.
    pub fn of(m: &crate::scene::Material) -> Self {
        use crate::brdf::Model;
        match m.sanitized() {
            Model::CookTorrance(p) => Self::Fixed(p.distribution, p.geometry, p.fresnel, p.diffuse),
            Model::MetalRough(p) => Self::Fixed(p.distribution, p.geometry, p.fresnel, p.diffuse),
            _ => Self::Unused,
        }
    }

    /// The values of the `SEL_DISTRIBUTION`, `SEL_GEOMETRY`, `SEL_FRESNEL` and `SEL_DIFFUSE`
    /// specialization constants.
    pub fn spec_values(self) -> [i32; 4] {
        match self {
            Self::Generic => [-1; 4],
            Self::Unused => [0, 0, 0, -1],
            Self::Fixed(d, g, f, diffuse) => [d as i32, g as i32, f as i32, diffuse as i32],
        }
    }

    /// "d/g/f/diffuse" in a variant's name, for the models with selectable terms ("?" where the
    /// pipeline reads them at run time).
    fn names(self, model: ModelKind) -> Option<String> {
        if !model.has_terms() {
            return None;
        }
        Some(match self {
            Self::Fixed(d, g, f, diffuse) => {
                format!("{}/{}/{}/{}", d.name(), g.name(), f.name(), diffuse.name())
            }
            Self::Generic | Self::Unused => "?/?/?".to_string(),
        })
    }
}

/// The environment settings that select shader code (specialization constants).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct IblKey {
    pub importance: bool,
    /// `fitted_lobes` (two prefiltered lookups from the fitted table) instead of the split sum.
    pub fitted_lobes: bool,
    pub samples: u32,
    pub diffuse_sh: bool,
    pub energy_compensation: bool,
    pub mip_filtered: bool,
}

impl IblKey {
    pub fn from_env(e: &crate::scene::Environment) -> Self {
        Self {
            importance: e.specular_method == crate::scene::SpecularMethod::Importance,
            fitted_lobes: e.specular_method == crate::scene::SpecularMethod::FittedLobes,
            samples: e.samples,
            diffuse_sh: e.diffuse_method == crate::scene::DiffuseMethod::Sh9,
            energy_compensation: e.energy_compensation,
            mip_filtered: e.mip_filtered_samples,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ShadingKey {
    Flat,
    Gouraud,
    Phong,
}

impl ShadingKey {
    pub(super) fn from_shading(s: Shading) -> Self {
        match s {
            Shading::Flat => Self::Flat,
            Shading::Gouraud => Self::Gouraud,
            Shading::Phong => Self::Phong,
        }
    }
    pub(super) fn name(self) -> &'static str {
        match self {
            Self::Flat => "flat",
            Self::Gouraud => "gouraud",
            Self::Phong => "phong",
        }
    }
}

impl std::fmt::Display for VariantKey {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "forward[shading={}, model={}, fog={}",
            self.shading.name(),
            self.model.name(),
            if self.fog { "on" } else { "off" }
        )?;
        if let Some(terms) = self.terms.names(self.model) {
            write!(f, ", terms={terms}")?;
        }
        if self.maps != 0 {
            write!(f, ", maps={:#04x}", self.maps)?;
        }
        if let Some(i) = &self.ibl {
            if i.importance {
                write!(
                    f,
                    ", ibl=importance({}{})",
                    i.samples,
                    if i.mip_filtered { ", mip-filtered" } else { "" }
                )?;
            } else if i.fitted_lobes {
                write!(f, ", ibl=fitted_lobes")?;
            } else {
                write!(f, ", ibl=split_sum")?;
            }
            write!(
                f,
                ", diffuse={}",
                if i.diffuse_sh { "sh9" } else { "cubemap" }
            )?;
            if i.energy_compensation {
                write!(f, ", energy_compensation")?;
            }
        }
        if self.clustered {
            write!(f, ", clustered")?;
        }
        if self.alpha != AlphaKey::Opaque {
            write!(f, ", alpha={:?}", self.alpha)?;
        }
        if self.lobes != 0 && self.lobes != GENERIC_LOBES {
            write!(f, ", lobes={:#x}", self.lobes)?;
        }
        if self.lobes & crate::glsl::brdf_models::BRDF_LOBE_TRANSMISSION != 0
            && self.refraction != crate::scene::Refraction::default()
        {
            write!(f, ", refraction={}", self.refraction.name())?;
        }
        if self.vertex_color {
            write!(f, ", vertex_color")?;
        }
        if self.debug != DebugView::None {
            write!(f, ", debug={:?}", self.debug)?;
        }
        write!(f, "]")
    }
}

/// The shader modules pipelines are built from, loaded on first use and kept for later outputs.
#[derive(Default)]
pub(super) struct Modules {
    forward: HashMap<String, (ShaderModule, ShaderModule)>,
    skybox: Option<(ShaderModule, ShaderModule)>,
}

impl Modules {
    /// `forward.vert` and `forward.frag` in the variant `v` needs.
    pub(super) fn forward(
        &mut self,
        ctx: &Arc<Context>,
        v: VariantKey,
    ) -> Result<&(ShaderModule, ShaderModule), VkError> {
        let name = v.module_variant();
        if !self.forward.contains_key(&name) {
            let pair = (
                ShaderModule::new(ctx, &format!("forward.vert:{name}"))?,
                ShaderModule::new(ctx, &format!("forward.frag:{name}"))?,
            );
            self.forward.insert(name.clone(), pair);
        }
        Ok(&self.forward[&name])
    }

    pub(super) fn skybox(
        &mut self,
        ctx: &Arc<Context>,
    ) -> Result<&(ShaderModule, ShaderModule), VkError> {
        if self.skybox.is_none() {
            self.skybox = Some((
                ShaderModule::new(ctx, "skybox.vert")?,
                ShaderModule::new(ctx, "skybox.frag")?,
            ));
        }
        Ok(self.skybox.as_ref().expect("loaded above"))
    }
}

/// The vertex buffers and attributes a variant's vertex stage reads.
pub(super) fn vertex_input(
    v: VariantKey,
) -> (
    Vec<vk::VertexInputBindingDescription>,
    Vec<vk::VertexInputAttributeDescription>,
) {
    let stride = std::mem::size_of::<Vertex>() as u32;
    let mut bindings = vec![vk::VertexInputBindingDescription {
        binding: 0,
        stride,
        input_rate: vk::VertexInputRate::VERTEX,
    }];
    let mut attributes = vec![
        vk::VertexInputAttributeDescription {
            location: 0,
            binding: 0,
            format: vk::Format::R32G32B32_SFLOAT,
            offset: 0,
        },
        vk::VertexInputAttributeDescription {
            location: 1,
            binding: 0,
            format: vk::Format::R32G32B32_SFLOAT,
            offset: 12,
        },
    ];
    if v.phong_tangent() {
        attributes.push(vk::VertexInputAttributeDescription {
            location: 3,
            binding: 0,
            format: vk::Format::R32G32B32A32_SFLOAT,
            offset: 32,
        });
    }
    if v.reads_uv_tangent() {
        attributes.extend([
            vk::VertexInputAttributeDescription {
                location: 2,
                binding: 0,
                format: vk::Format::R32G32_SFLOAT,
                offset: 24,
            },
            vk::VertexInputAttributeDescription {
                location: 3,
                binding: 0,
                format: vk::Format::R32G32B32A32_SFLOAT,
                offset: 32,
            },
        ]);
    }
    if v.vertex_color {
        let (binding, attribute) = crate::render::gpu::vertex_color_input();
        bindings.push(binding);
        attributes.push(attribute);
    }
    if v.shading == ShadingKey::Flat {
        bindings.push(vk::VertexInputBindingDescription {
            binding: 1,
            stride: 12,
            input_rate: vk::VertexInputRate::VERTEX,
        });
        attributes.push(vk::VertexInputAttributeDescription {
            location: 4,
            binding: 1,
            format: vk::Format::R32G32B32_SFLOAT,
            offset: 0,
        });
    }
    (bindings, attributes)
}

/// The specialization constants of a variant (model, terms, fog, debug view, maps, light kinds,
/// IBL settings), without the output's.
pub(super) fn variant_spec(v: VariantKey) -> Vec<(u32, u32)> {
    let sel = v.terms.spec_values();
    let mut spec = vec![
        (gpu::SPEC_MODEL, v.model.code() as u32),
        (gpu::SPEC_FOG, v.fog as u32),
        (gpu::SPEC_DEBUG_VIEW, v.debug.id()),
        (gpu::SPEC_SEL_DISTRIBUTION, sel[0] as u32),
        (gpu::SPEC_SEL_GEOMETRY, sel[1] as u32),
        (gpu::SPEC_SEL_FRESNEL, sel[2] as u32),
        (gpu::SPEC_SEL_DIFFUSE, sel[3] as u32),
        (gpu::SPEC_MAPS, v.maps),
        (gpu::SPEC_LIGHT_KINDS, v.light_kinds),
        (gpu::SPEC_CLUSTERED, v.clustered as u32),
        (gpu::SPEC_ALPHA_MODE, v.alpha.code()),
        (gpu::SPEC_LOBES, v.lobes),
        (gpu::SPEC_REFRACTION, refraction_code(v.refraction)),
    ];
    let slots = [
        gpu::SPEC_SHADOW_FIXED_0,
        gpu::SPEC_SHADOW_FIXED_1,
        gpu::SPEC_SHADOW_FIXED_2,
        gpu::SPEC_SHADOW_FIXED_3,
    ];
    spec.extend(slots.into_iter().zip(v.shadow_slots));
    if let Some(i) = v.ibl {
        spec.extend([
            (gpu::SPEC_SPECULAR_METHOD, specular_method_code(i)),
            (gpu::SPEC_DIFFUSE_FROM_SH, i.diffuse_sh as u32),
            (gpu::SPEC_ENERGY_COMPENSATION, i.energy_compensation as u32),
            (gpu::SPEC_IBL_SAMPLES, i.samples.max(1)),
            (gpu::SPEC_MIP_FILTERED, i.mip_filtered as u32),
        ]);
    }
    spec
}

/// The shader's `SPECULAR_METHOD` (shaders_glsl/include/ibl.glsl) for `i`.
fn specular_method_code(i: IblKey) -> u32 {
    use crate::render::gpu::glsl::include_ibl as g;
    if i.importance {
        g::SPECULAR_IMPORTANCE as u32
    } else if i.fitted_lobes {
        g::SPECULAR_FITTED_LOBES as u32
    } else {
        g::SPECULAR_SPLIT_SUM as u32
    }
}

pub(super) fn create_pipeline(
    ctx: &Arc<Context>,
    layout: &PipelineLayout,
    target: TargetFormat,
    v: VariantKey,
    output: Output,
    vs: &ShaderModule,
    fs: &ShaderModule,
) -> Result<Pipeline, VkError> {
    let (bindings, attributes) = vertex_input(v);
    let mut spec = variant_spec(v);
    spec.extend(output.spec());
    let name = match output {
        Output::Hdr => v.to_string(),
        Output::Display { format, .. } => format!("{v} → {format:?}"),
    };
    Pipeline::graphics(
        ctx,
        layout,
        &GraphicsDesc {
            name: &name,
            vertex: vs,
            fragment: fs,
            spec: &spec,
            vertex_bindings: &bindings,
            vertex_attributes: &attributes,
            color_formats: &[output.color_format(target.color)],
            depth_format: Some(target.depth),
            samples: target.samples,
            cull: vk::CullModeFlags::NONE,
            depth_test: true,
            // Blended surfaces do not hide what is drawn after them (other blended ones).
            depth_write: v.alpha != AlphaKey::Blend,
            depth_compare: vk::CompareOp::LESS,
            blend: v.alpha == AlphaKey::Blend,
        },
    )
}

pub(super) fn create_skybox(
    ctx: &Arc<Context>,
    layout: &PipelineLayout,
    target: TargetFormat,
    output: Output,
    vs: &ShaderModule,
    fs: &ShaderModule,
) -> Result<Pipeline, VkError> {
    Pipeline::graphics(
        ctx,
        layout,
        &GraphicsDesc {
            name: "skybox",
            vertex: vs,
            fragment: fs,
            spec: &output.spec(),
            vertex_bindings: &[],
            vertex_attributes: &[],
            color_formats: &[output.color_format(target.color)],
            depth_format: Some(target.depth),
            samples: target.samples,
            cull: vk::CullModeFlags::NONE,
            depth_test: true,
            depth_write: false,
            depth_compare: vk::CompareOp::LESS_OR_EQUAL,
            blend: false,
        },
    )
}
