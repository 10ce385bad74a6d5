//! The reflection models (MODELS.md §1, §4, §5, §6) built from [`super::terms`], their parameter
//! structs, and the dispatching [`eval`], [`eval_terms`] and [`radiance`].
//!
//! Each `*_terms` function here has a GLSL twin in `shaders_glsl/brdf/models.glsl` of the same
//! name (prefixed `brdf_`) taking the packed [`super::GpuBrdfParams`].

use glam::Vec3;
use serde::{Deserialize, Serialize};

pub mod layers;

use super::presets::{f0_from_ior, ior_from_f0, ComplexIor};
use super::terms::*;
use super::transmission::Transmission;
use crate::glsl::brdf_models as glsl;

// ---------------------------------------------------------------------------------------------
// Selectors
// ---------------------------------------------------------------------------------------------
// Their discriminants are the GLSL's codes (generated from shaders_glsl/brdf/models.glsl), so
// `as i32` gives what the shaders compare `sel` with.

/// Declares a selector enum whose discriminants are the GLSL's codes (`glsl::BRDF_*`), with the
/// derives and the snake_case serde names every selector has.
macro_rules! selectors {
    ($($(#[$meta:meta])* $name:ident { $($(#[$vmeta:meta])* $variant:ident = $code:ident,)* })*) => {$(
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
        #[serde(rename_all = "snake_case")]
        pub enum $name {
            $($(#[$vmeta])* $variant = glsl::$code as isize,)*
        }
    )*};
}

selectors! {
    /// Normal distribution selector. GPU code: `BRDF_D_*` in `models.glsl`.
    Distribution {
        /// [`d_beckmann`].
        Beckmann = BRDF_D_BECKMANN,
        /// [`d_ggx`] (GTR2).
        Ggx = BRDF_D_GGX,
    }

    /// Masking-shadowing selector. GPU code: `BRDF_G_*` in `models.glsl`.
    Geometry {
        /// [`g_cook_torrance`].
        CookTorrance = BRDF_G_COOK_TORRANCE,
        /// [`g_smith_ggx_separable`].
        SmithGgx = BRDF_G_SMITH_GGX,
        /// [`g_smith_ggx_correlated`].
        SmithGgxCorrelated = BRDF_G_SMITH_GGX_CORRELATED,
        /// [`g_schlick_ggx`] with [`k_punctual`].
        SchlickGgx = BRDF_G_SCHLICK_GGX,
        /// [`g_smith_beckmann`]: the Beckmann distribution's own Smith term (the scene format's
        /// default with `"distribution": "beckmann"` for metal_rough).
        SmithBeckmann = BRDF_G_SMITH_BECKMANN,
    }

    /// Fresnel selector. GPU code: `BRDF_F_*` in `models.glsl`.
    Fresnel {
        /// [`f_schlick`] (needs F0).
        Schlick = BRDF_F_SCHLICK,
        /// [`f_schlick_sg`] (needs F0).
        SchlickSg = BRDF_F_SCHLICK_SG,
        /// [`f_dielectric`] per channel (needs η).
        Dielectric = BRDF_F_DIELECTRIC,
        /// [`f_conductor`] (needs η and κ): the usual approximation.
        Conductor = BRDF_F_CONDUCTOR,
        /// [`f_conductor_exact`] (needs η and κ): the exact complex-index Fresnel equations.
        ConductorExact = BRDF_F_CONDUCTOR_EXACT,
    }

    /// Diffuse lobe selector of Cook-Torrance and metallic-roughness. GPU code: `BRDF_DIFFUSE_*`
    /// in `models.glsl` (packed in `p0.y`, specialization constant `SEL_DIFFUSE`).
    #[derive(Default)]
    Diffuse {
        /// [`diffuse_lambert`]: `albedo/π`.
        #[default]
        Lambert = BRDF_DIFFUSE_LAMBERT,
        /// [`diffuse_burley`]: `albedo/π · Fd` with the model's perceptual roughness (MODELS.md §5).
        Burley = BRDF_DIFFUSE_BURLEY,
    }
}

impl Diffuse {
    /// The factor on `albedo/π`: 1 for Lambert ([`diffuse_lambert`]), Burley's
    /// `Fd(n·l, n·v, l·h, roughness)` ([`fd_burley`], as in [`diffuse_burley`]) with `roughness`
    /// the perceptual roughness.
    pub fn factor(self, n_l: f32, n_v: f32, l_h: f32, roughness: f32) -> f32 {
        match self {
            Diffuse::Lambert => 1.0,
            Diffuse::Burley => fd_burley(n_l, n_v, l_h, roughness),
        }
    }
}

impl Distribution {
    /// Evaluates the selected D with width `a` (`m` for Beckmann, `α` for GGX);
    /// `sin2_h = |n × h|²` (see [`sin2_from_cos`]).
    pub fn eval(self, n_h: f32, sin2_h: f32, a: f32) -> f32 {
        match self {
            Distribution::Beckmann => d_beckmann_sin2(n_h, sin2_h, a),
            Distribution::Ggx => d_ggx_sin2(n_h, sin2_h, a),
        }
    }
}

impl Geometry {
    /// The geometry term of the split sum's table for a lobe with this G: the environment's split
    /// sum treats every lobe as GGX (a Beckmann lobe as the GGX lobe of the same width), so
    /// Beckmann's own Smith term becomes the separable Smith GGX there (with GGX samples the
    /// Beckmann G would not be a conserving pair: A + B reached 1.7 at grazing).
    pub fn for_split_sum(self) -> Geometry {
        match self {
            Geometry::SmithBeckmann => Geometry::SmithGgx,
            g => g,
        }
    }

    /// Evaluates the selected G. `a` is the width of the distribution (used by the Smith forms),
    /// `roughness` the perceptual roughness (used by Schlick-GGX's `k_punctual`).
    pub fn eval(self, n_h: f32, n_v: f32, n_l: f32, v_h: f32, a: f32, roughness: f32) -> f32 {
        match self {
            Geometry::CookTorrance => g_cook_torrance(n_h, n_v, n_l, v_h),
            Geometry::SmithGgx => g_smith_ggx_separable(n_l, n_v, a),
            Geometry::SmithGgxCorrelated => g_smith_ggx_correlated(n_l, n_v, a),
            Geometry::SchlickGgx => g_schlick_ggx(n_l, n_v, k_punctual(roughness)),
            Geometry::SmithBeckmann => g_smith_beckmann(n_l, n_v, a),
        }
    }
}

impl Fresnel {
    /// Evaluates the selected F at `v·h`. `spec` is F0 (Schlick, SchlickSg) or η (Dielectric,
    /// Conductor); `kappa` is κ (Conductor only).
    pub fn eval(self, spec: Vec3, kappa: Vec3, v_h: f32) -> Vec3 {
        match self {
            Fresnel::Schlick => f_schlick(spec, v_h),
            Fresnel::SchlickSg => f_schlick_sg(spec, v_h),
            Fresnel::Dielectric => Vec3::new(
                f_dielectric(v_h, spec.x),
                f_dielectric(v_h, spec.y),
                f_dielectric(v_h, spec.z),
            ),
            Fresnel::Conductor => f_conductor(v_h, spec, kappa),
            Fresnel::ConductorExact => f_conductor_exact(v_h, spec, kappa),
        }
    }

    /// The Fresnel inputs `(spec, kappa)` for a reflectance at normal incidence `f0`: F0 itself
    /// for the Schlick forms, `η = ior_from_f0(F0)` (and κ = 0) for the exact forms.
    pub fn inputs_from_f0(self, f0: Vec3) -> (Vec3, Vec3) {
        match self {
            Fresnel::Schlick | Fresnel::SchlickSg => (f0, Vec3::ZERO),
            Fresnel::Dielectric | Fresnel::Conductor | Fresnel::ConductorExact => (
                Vec3::new(ior_from_f0(f0.x), ior_from_f0(f0.y), ior_from_f0(f0.z)),
                Vec3::ZERO,
            ),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Parameters
// ---------------------------------------------------------------------------------------------

fn fin(x: f32, default: f32) -> f32 {
    if x.is_finite() {
        x
    } else {
        default
    }
}

fn unit(x: f32, default: f32) -> f32 {
    fin(x, default).clamp(0.0, 1.0)
}

fn colour(c: Vec3) -> Vec3 {
    Vec3::new(fin(c.x, 0.0), fin(c.y, 0.0), fin(c.z, 0.0)).max(Vec3::ZERO)
}

/// Lambert (MODELS.md §6): `f = albedo / π`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LambertParams {
    /// Diffuse albedo ρ, linear RGB. Default 0.8 grey.
    pub albedo: Vec3,
}

impl Default for LambertParams {
    fn default() -> Self {
        Self {
            albedo: Vec3::splat(0.8),
        }
    }
}

impl LambertParams {
    /// Non-finite and negative colour components become 0.
    pub fn sanitized(&self) -> Self {
        Self {
            albedo: colour(self.albedo),
        }
    }
}

/// The classic empirical model of the slides (MODELS.md §1): Lambert diffuse plus Phong
/// (`max(r·v, 0)^n`, `r = 2(n·l)n − l`) or Blinn-Phong (`max(n·h, 0)^n`) specular, with the
/// slides' intensity terms `I = I_L (k_d O_d (n·l) + k_s O_s (r·v)^n)`. Not energy conserving
/// and not reciprocal: the BRDF equivalent is `f = k_d O_d + k_s O_s (r·v)^n / (n·l)`.
/// Field names and defaults are those of the scene format (`docs/scene-format.md`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PhongParams {
    /// O_d, the object's diffuse colour. Default 0.8 grey.
    pub diffuse_color: Vec3,
    /// O_s, the object's specular colour. Default white.
    pub specular_color: Vec3,
    /// k_a, ambient coefficient (used by [`PhongParams::ambient`] only), ≥ 0. Default 0.2.
    pub ka: f32,
    /// k_d, diffuse coefficient, ≥ 0. Default 0.8.
    pub kd: f32,
    /// k_s, specular coefficient, ≥ 0. Default 0.5.
    pub ks: f32,
    /// The exponent n, [0, 10000]. Default 32.
    pub shininess: f32,
    /// Blinn-Phong (`n·h`) instead of Phong (`r·v`). Default false; the model name
    /// `"blinn_phong"` sets it.
    pub blinn: bool,
}

impl Default for PhongParams {
    fn default() -> Self {
        Self {
            diffuse_color: Vec3::splat(0.8),
            specular_color: Vec3::ONE,
            ka: 0.2,
            kd: 0.8,
            ks: 0.5,
            shininess: 32.0,
            blinn: false,
        }
    }
}

impl PhongParams {
    /// Colours and coefficients ≥ 0 (no upper bound: the classic model has none), shininess in
    /// [0, 10000]; non-finite → default.
    pub fn sanitized(&self) -> Self {
        let d = Self::default();
        Self {
            diffuse_color: colour(self.diffuse_color),
            specular_color: colour(self.specular_color),
            ka: fin(self.ka, d.ka).max(0.0),
            kd: fin(self.kd, d.kd).max(0.0),
            ks: fin(self.ks, d.ks).max(0.0),
            shininess: fin(self.shininess, d.shininess).clamp(0.0, 10_000.0),
            blinn: self.blinn,
        }
    }

    /// The slides' ambient term `I_a k_a O_d` (not part of the BRDF).
    pub fn ambient(&self, i_a: Vec3) -> Vec3 {
        let p = self.sanitized();
        i_a * p.ka * p.diffuse_color
    }
}

/// Where Cook-Torrance takes its Fresnel reflectance from.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SpecularSource {
    /// A real index of refraction η (as the seed's presets: 0.277 for gold, 1.5 for glass).
    Ior(f32),
    /// Reflectance at normal incidence, per channel.
    F0(Vec3),
    /// A complex index of refraction (see [`super::metal_preset`]).
    Complex(ComplexIor),
}

impl SpecularSource {
    fn sanitized(&self) -> Self {
        match *self {
            SpecularSource::Ior(eta) => SpecularSource::Ior(fin(eta, 1.5).max(1e-4)),
            SpecularSource::F0(f0) => SpecularSource::F0(colour(f0).min(Vec3::ONE)),
            SpecularSource::Complex(c) => SpecularSource::Complex(ComplexIor {
                eta: colour(c.eta),
                k: colour(c.k),
            }),
        }
    }

    /// The Fresnel inputs `(spec, kappa)` for the selected Fresnel term:
    /// * Schlick forms: `spec = F0` (from η by [`f0_from_ior`], from a complex index by
    ///   [`ComplexIor::f0`]);
    /// * Dielectric: `spec = η` (from F0 by [`ior_from_f0`]; a complex index's κ is ignored);
    /// * Conductor: `spec = η`, `kappa = κ` (κ = 0 for a real index or an F0).
    pub fn fresnel_inputs(&self, fresnel: Fresnel) -> (Vec3, Vec3) {
        match (fresnel, *self) {
            (Fresnel::Schlick | Fresnel::SchlickSg, SpecularSource::Ior(eta)) => {
                (Vec3::splat(f0_from_ior(eta)), Vec3::ZERO)
            }
            (Fresnel::Schlick | Fresnel::SchlickSg, SpecularSource::F0(f0)) => (f0, Vec3::ZERO),
            (Fresnel::Schlick | Fresnel::SchlickSg, SpecularSource::Complex(c)) => {
                (c.f0(), Vec3::ZERO)
            }
            (_, SpecularSource::Ior(eta)) => (Vec3::splat(eta), Vec3::ZERO),
            (f, SpecularSource::F0(f0)) => f.inputs_from_f0(f0),
            (Fresnel::Dielectric, SpecularSource::Complex(c)) => (c.eta, Vec3::ZERO),
            (_, SpecularSource::Complex(c)) => (c.eta, c.k),
        }
    }
}

/// Cook-Torrance as in seed 000 (MODELS.md §4): `f = k_d · color/π + (1 − k_d) · D F G / (4 (n·l)(n·v))`
/// (`color/π · Fd` with the Burley [`Diffuse`]).
/// Width of D: `m = roughness` for Beckmann (as the seed), `α = roughness²` for GGX; the Smith
/// G forms use the same width, Schlick-GGX uses `k_punctual(roughness)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CookTorranceParams {
    /// Diffuse albedo, linear RGB. Default 0.8 grey.
    pub color: Vec3,
    /// k_d, the diffuse/specular mix, [0, 1]. Default 0.75 (the seed's presets).
    pub kd: f32,
    /// Roughness, [0, 1]. Default 0.3.
    pub roughness: f32,
    /// Fresnel source. Default `Ior(1.5)`.
    pub specular: SpecularSource,
    /// Default Beckmann.
    pub distribution: Distribution,
    /// Default Cook-Torrance.
    pub geometry: Geometry,
    /// Default Schlick.
    pub fresnel: Fresnel,
    /// The diffuse lobe (weighted by k_d). Default Lambert (the seed's).
    pub diffuse: Diffuse,
}

impl Default for CookTorranceParams {
    fn default() -> Self {
        Self {
            color: Vec3::splat(0.8),
            kd: 0.75,
            roughness: 0.3,
            specular: SpecularSource::Ior(1.5),
            distribution: Distribution::Beckmann,
            geometry: Geometry::CookTorrance,
            fresnel: Fresnel::Schlick,
            diffuse: Diffuse::Lambert,
        }
    }
}

impl CookTorranceParams {
    /// Colour ≥ 0, k_d and roughness in [0, 1], η ≥ 1e-4, κ ≥ 0, F0 in [0, 1].
    pub fn sanitized(&self) -> Self {
        Self {
            color: colour(self.color),
            kd: unit(self.kd, 0.75),
            roughness: unit(self.roughness, 0.3),
            specular: self.specular.sanitized(),
            ..*self
        }
    }

    /// The width of D: `roughness` for Beckmann, `roughness²` for GGX, at least [`ALPHA_MIN`].
    pub fn width(&self) -> f32 {
        let a = match self.distribution {
            Distribution::Beckmann => self.roughness,
            Distribution::Ggx => self.roughness * self.roughness,
        };
        a.max(ALPHA_MIN)
    }
}

/// glTF metallic-roughness (MODELS.md §4): `c_diff = base·(1 − metallic)`,
/// `F0 = mix(dielectric_f0 (0.04), base, metallic)`, `f = c_diff/π · [Fd] · [1 − F] + D F G / (4 (n·l)(n·v))`
/// (`Fd`: Burley's factor when [`Diffuse::Burley`] is selected),
/// `α = roughness²` (also the Beckmann `m` when Beckmann is selected).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MetalRoughParams {
    /// Base colour, linear RGB. Default white (glTF).
    pub base_color: Vec3,
    /// Metallic, [0, 1]. Default 1 (glTF).
    pub metallic: f32,
    /// Perceptual roughness, [0, 1]. Default 1 (glTF).
    pub roughness: f32,
    /// Default GGX.
    pub distribution: Distribution,
    /// Default Smith GGX height-correlated.
    pub geometry: Geometry,
    /// Default Schlick.
    pub fresnel: Fresnel,
    /// Weight the diffuse by `1 − F(v·h)`. Default false.
    pub diffuse_fresnel_weight: bool,
    /// The diffuse lobe: Lambert `c_diff/π` or Burley `c_diff/π · Fd` (with the perceptual
    /// roughness). Default Lambert (glTF).
    pub diffuse: Diffuse,
    /// F0 of the dielectric part (metallic 0), linear RGB in [0, 1]. Default 0.04 (ior 1.5, as
    /// glTF's core); KHR_materials_ior and KHR_materials_specular set it
    /// (`src/scene/gltf/material.rs`).
    pub dielectric_f0: Vec3,
    /// Multi-scatter energy compensation and the diffuse weighted by what the specular leaves
    /// ([`super::energy`]). Default false. Scenes set it for every metal-rough material from
    /// their environment's `energy_compensation`, not per material.
    pub energy_compensation: bool,
    /// KHR_materials_clearcoat's `clearcoatFactor`, [0, 1]: the weight of a clear coat
    /// ([`layers`]). Default 0 (no coat).
    pub clearcoat: f32,
    /// KHR_materials_clearcoat's `clearcoatRoughnessFactor`, [0, 1]: the coat's perceptual
    /// roughness. Default 0.
    pub clearcoat_roughness: f32,
    /// KHR_materials_sheen's `sheenColorFactor`, linear RGB in [0, 1]: the sheen lobe's colour
    /// ([`layers::sheen_layer`]). Default 0 (no sheen).
    pub sheen_color: Vec3,
    /// KHR_materials_sheen's `sheenRoughnessFactor`, [0, 1]. Default 0.
    pub sheen_roughness: f32,
    /// Transmission, volume, dispersion and diffuse transmission (issue 35). Default: none.
    pub transmission: Transmission,
    /// F90 of the dielectric part, [0, 1]: KHR_materials_specular's `specularFactor` (which
    /// also scales `dielectric_f0`). The Schlick forms reach `mix(dielectric_f90, 1, metallic)`
    /// at grazing instead of 1; the exact forms ignore it. Default 1.
    pub dielectric_f90: f32,
    /// KHR_materials_anisotropy's `anisotropyStrength`, [0, 1]: the GGX lobe stretched along
    /// the anisotropy direction, `α_t = mix(α, 1, strength²)`, `α_b = α`
    /// ([`anisotropic_lobe`]). GGX only: with Beckmann it does nothing. Default 0 (isotropic).
    pub anisotropy_strength: f32,
    /// KHR_materials_anisotropy's `anisotropyRotation`, radians: the anisotropy direction is
    /// the tangent turned by this angle towards the bitangent. Default 0.
    pub anisotropy_rotation: f32,
    /// KHR_materials_iridescence's `iridescenceFactor`, [0, 1]: the weight of the thin film's
    /// Fresnel ([`super::iridescence`]) against the material's own. Default 0 (no film).
    pub iridescence: f32,
    /// KHR_materials_iridescence's `iridescenceIor`, ≥ 1: the film's index. Default 1.3.
    pub iridescence_ior: f32,
    /// KHR_materials_iridescence's `iridescenceThicknessMinimum`, nm, ≥ 0: the thickness where
    /// the thickness texture is 0 (no texture: unused). Default 100.
    pub iridescence_thickness_min: f32,
    /// KHR_materials_iridescence's `iridescenceThicknessMaximum`, nm, ≥ the minimum: the film's
    /// thickness without a texture. 0 turns the film off. Default 400.
    pub iridescence_thickness_max: f32,
    /// The film's Fresnel at the view (n·v) for every light instead of at each light's v·h:
    /// what Khronos' sample renderer and three.js do, once per pixel on the GPU
    /// (`"iridescence_angle": "view"` in scene files). Default false (v·h, the reference).
    pub iridescence_at_view: bool,
    /// The clear coat's normal at the point being shaded, world space, unit
    /// (KHR_materials_clearcoat: the `clearcoat_normal` map, else the geometric normal where a
    /// normal map bends the base's). Set per point by the maps (`surface_at`); `None`: the
    /// shading normal. Not a scene field.
    #[serde(skip)]
    pub clearcoat_normal: Option<Vec3>,
}

impl MetalRoughParams {
    /// The dielectric F0 from KHR_materials_ior's `ior` (`None`: 1.5, F0 0.04; 0 is the
    /// extension's special value, F0 = 1) and KHR_materials_specular's `specularFactor` and
    /// `specularColorFactor`, as the latter's specification computes it:
    /// `min(((ior − 1)/(ior + 1))² · specularColorFactor, 1) · specularFactor`. glTF files and
    /// scene files (`"ior"`, `"specular"` on metal_rough) both go through it.
    pub fn dielectric_f0_from(ior: Option<f32>, factor: f32, color: Vec3) -> Vec3 {
        let f0 = match ior {
            Some(ior) => Vec3::splat(((ior - 1.0) / (ior + 1.0)).powi(2)),
            None => Vec3::splat(0.04),
        };
        (f0 * color).min(Vec3::ONE) * factor
    }
}

impl Default for MetalRoughParams {
    fn default() -> Self {
        Self {
            base_color: Vec3::ONE,
            metallic: 1.0,
            roughness: 1.0,
            distribution: Distribution::Ggx,
            geometry: Geometry::SmithGgxCorrelated,
            fresnel: Fresnel::Schlick,
            diffuse_fresnel_weight: false,
            diffuse: Diffuse::Lambert,
            dielectric_f0: Vec3::splat(0.04),
            energy_compensation: false,
            clearcoat: 0.0,
            clearcoat_roughness: 0.0,
            sheen_color: Vec3::ZERO,
            sheen_roughness: 0.0,
            transmission: Transmission::default(),
            dielectric_f90: 1.0,
            anisotropy_strength: 0.0,
            anisotropy_rotation: 0.0,
            iridescence: 0.0,
            iridescence_ior: 1.3,
            iridescence_thickness_min: 100.0,
            iridescence_thickness_max: 400.0,
            iridescence_at_view: false,
            clearcoat_normal: None,
        }
    }
}

impl MetalRoughParams {
    /// Colour ≥ 0, metallic and roughness in [0, 1], dielectric F0 in [0, 1].
    pub fn sanitized(&self) -> Self {
        Self {
            dielectric_f0: colour(self.dielectric_f0).min(Vec3::ONE),
            base_color: colour(self.base_color),
            metallic: unit(self.metallic, 1.0),
            roughness: unit(self.roughness, 1.0),
            clearcoat: unit(self.clearcoat, 0.0),
            clearcoat_roughness: unit(self.clearcoat_roughness, 0.0),
            sheen_color: colour(self.sheen_color).min(Vec3::ONE),
            sheen_roughness: unit(self.sheen_roughness, 0.0),
            transmission: self.transmission.sanitized(),
            dielectric_f90: unit(self.dielectric_f90, 1.0),
            anisotropy_strength: unit(self.anisotropy_strength, 0.0),
            anisotropy_rotation: fin(self.anisotropy_rotation, 0.0),
            iridescence: unit(self.iridescence, 0.0),
            iridescence_ior: fin(self.iridescence_ior, 1.3).clamp(1.0, 10.0),
            iridescence_thickness_min: fin(self.iridescence_thickness_min, 100.0).max(0.0),
            iridescence_thickness_max: fin(self.iridescence_thickness_max, 400.0).max(0.0),
            ..*self
        }
    }
}

/// Disney "Principled" BRDF, Burley 2012, exactly as BRDF Explorer's `disney.brdf`
/// (MODELS.md §5). Defaults are `disney.brdf`'s.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PrincipledParams {
    /// Base colour, linear RGB (`Cdlin`). Default (0.82, 0.67, 0.16).
    pub base_color: Vec3,
    /// Default 0.
    pub subsurface: f32,
    /// Default 0.
    pub metallic: f32,
    /// Default 0.5 (F0 = 0.04).
    pub specular: f32,
    /// Default 0.
    pub specular_tint: f32,
    /// Default 0.5.
    pub roughness: f32,
    /// Default 0.
    pub anisotropic: f32,
    /// Default 0.
    pub sheen: f32,
    /// Default 0.5.
    pub sheen_tint: f32,
    /// Default 0.
    pub clearcoat: f32,
    /// Default 1.
    pub clearcoat_gloss: f32,
}

impl Default for PrincipledParams {
    fn default() -> Self {
        Self {
            base_color: Vec3::new(0.82, 0.67, 0.16),
            subsurface: 0.0,
            metallic: 0.0,
            specular: 0.5,
            specular_tint: 0.0,
            roughness: 0.5,
            anisotropic: 0.0,
            sheen: 0.0,
            sheen_tint: 0.5,
            clearcoat: 0.0,
            clearcoat_gloss: 1.0,
        }
    }
}

impl PrincipledParams {
    /// Colour ≥ 0, the ten scalars in [0, 1] (MODELS.md §5); non-finite → default.
    pub fn sanitized(&self) -> Self {
        let d = Self::default();
        Self {
            base_color: colour(self.base_color),
            subsurface: unit(self.subsurface, d.subsurface),
            metallic: unit(self.metallic, d.metallic),
            specular: unit(self.specular, d.specular),
            specular_tint: unit(self.specular_tint, d.specular_tint),
            roughness: unit(self.roughness, d.roughness),
            anisotropic: unit(self.anisotropic, d.anisotropic),
            sheen: unit(self.sheen, d.sheen),
            sheen_tint: unit(self.sheen_tint, d.sheen_tint),
            clearcoat: unit(self.clearcoat, d.clearcoat),
            clearcoat_gloss: unit(self.clearcoat_gloss, d.clearcoat_gloss),
        }
    }
}

/// Qualitative Oren-Nayar (MODELS.md §6).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OrenNayarParams {
    /// ρ, linear RGB. Default 0.8 grey.
    pub albedo: Vec3,
    /// Roughness σ in degrees, [0, 90]. Default 20.
    pub sigma_deg: f32,
}

impl Default for OrenNayarParams {
    fn default() -> Self {
        Self {
            albedo: Vec3::splat(0.8),
            sigma_deg: 20.0,
        }
    }
}

impl OrenNayarParams {
    /// Colour ≥ 0, σ in [0°, 90°].
    pub fn sanitized(&self) -> Self {
        Self {
            albedo: colour(self.albedo),
            sigma_deg: fin(self.sigma_deg, 20.0).clamp(0.0, 90.0),
        }
    }
}

/// A reflection model with its parameters. Serialised with a `"model"` tag:
/// `{"model": "principled", "roughness": 0.3}`; missing fields take their defaults, unknown
/// fields are errors. `"blinn_phong"` is read as [`Model::Phong`] with `blinn = true` (and
/// written back under that name), as in the scene format.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(from = "ModelRepr", into = "ModelRepr")]
pub enum Model {
    /// See [`LambertParams`].
    Lambert(LambertParams),
    /// See [`PhongParams`] (Phong and Blinn-Phong).
    Phong(PhongParams),
    /// See [`CookTorranceParams`].
    CookTorrance(CookTorranceParams),
    /// See [`MetalRoughParams`].
    MetalRough(MetalRoughParams),
    /// See [`PrincipledParams`].
    Principled(PrincipledParams),
    /// See [`OrenNayarParams`].
    OrenNayar(OrenNayarParams),
}

/// The serde shape of [`Model`]: like it, plus a `blinn_phong` tag.
#[derive(Serialize, Deserialize)]
#[serde(tag = "model", rename_all = "snake_case")]
enum ModelRepr {
    Lambert(LambertParams),
    Phong(PhongParams),
    BlinnPhong(PhongParams),
    CookTorrance(CookTorranceParams),
    MetalRough(MetalRoughParams),
    Principled(PrincipledParams),
    OrenNayar(OrenNayarParams),
}

impl From<ModelRepr> for Model {
    fn from(r: ModelRepr) -> Self {
        match r {
            ModelRepr::Lambert(p) => Model::Lambert(p),
            ModelRepr::Phong(p) => Model::Phong(p),
            ModelRepr::BlinnPhong(p) => Model::Phong(PhongParams { blinn: true, ..p }),
            ModelRepr::CookTorrance(p) => Model::CookTorrance(p),
            ModelRepr::MetalRough(p) => Model::MetalRough(p),
            ModelRepr::Principled(p) => Model::Principled(p),
            ModelRepr::OrenNayar(p) => Model::OrenNayar(p),
        }
    }
}

impl From<Model> for ModelRepr {
    fn from(m: Model) -> Self {
        match m {
            Model::Lambert(p) => ModelRepr::Lambert(p),
            Model::Phong(p) if p.blinn => ModelRepr::BlinnPhong(p),
            Model::Phong(p) => ModelRepr::Phong(p),
            Model::CookTorrance(p) => ModelRepr::CookTorrance(p),
            Model::MetalRough(p) => ModelRepr::MetalRough(p),
            Model::Principled(p) => ModelRepr::Principled(p),
            Model::OrenNayar(p) => ModelRepr::OrenNayar(p),
        }
    }
}

impl Model {
    /// The classic model with the format's defaults (also the material of OBJ parts without an
    /// MTL material): ka 0.2, kd 0.8, ks 0.5, shininess 32, diffuse 0.8 grey, specular white.
    pub fn default_phong(blinn: bool) -> Self {
        Model::Phong(PhongParams {
            blinn,
            ..Default::default()
        })
    }

    /// Helmholtz reciprocity `f(l, v) = f(v, l)` holds for every model but the classic
    /// Phong / Blinn-Phong (whose BRDF equivalent divides the specular by `n·l`).
    pub fn is_reciprocal(&self) -> bool {
        !matches!(self, Model::Phong(_))
    }

    /// The parameters with non-finite values replaced and ranges clamped (what [`eval`] and
    /// [`super::GpuBrdfParams::from_model`] use).
    pub fn sanitized(&self) -> Self {
        match self {
            Model::Lambert(p) => Model::Lambert(p.sanitized()),
            Model::Phong(p) => Model::Phong(p.sanitized()),
            Model::CookTorrance(p) => Model::CookTorrance(p.sanitized()),
            Model::MetalRough(p) => Model::MetalRough(p.sanitized()),
            Model::Principled(p) => Model::Principled(p.sanitized()),
            Model::OrenNayar(p) => Model::OrenNayar(p.sanitized()),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Evaluation
// ---------------------------------------------------------------------------------------------

/// A BRDF split into its terms, for debug views. `d`, `g` and `f` are those of the main specular
/// lobe (0 for models without one); `g` is the masking-shadowing G itself, not a visibility term.
/// `diffuse + specular` is the BRDF value.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Terms {
    /// Normal distribution D(h).
    pub d: f32,
    /// Masking-shadowing G(l, v).
    pub g: f32,
    /// Fresnel F(v·h).
    pub f: Vec3,
    /// The diffuse part of f (with sheen for Principled), already weighted (k_d, 1 − metallic, …).
    pub diffuse: Vec3,
    /// The specular part of f (with clearcoat for Principled), already weighted.
    pub specular: Vec3,
}

impl Terms {
    /// All zero.
    pub const ZERO: Terms = Terms {
        d: 0.0,
        g: 0.0,
        f: Vec3::ZERO,
        diffuse: Vec3::ZERO,
        specular: Vec3::ZERO,
    };

    /// The BRDF value `diffuse + specular`.
    pub fn total(&self) -> Vec3 {
        self.diffuse + self.specular
    }
}

/// Normalised directions and clamped cosines shared by every model.
struct Setup {
    n: Vec3,
    l: Vec3,
    v: Vec3,
    /// `n·l` clamped to `[COS_EPS, 1]`.
    n_l: f32,
    /// `n·v` clamped to `[COS_EPS, 1]`.
    n_v: f32,
}

/// `None` when `n·l ≤ 0` or `n·v ≤ 0` (including zero vectors).
fn setup(n: Vec3, l: Vec3, v: Vec3) -> Option<Setup> {
    let n = safe_normalize(n);
    let l = safe_normalize(l);
    let v = safe_normalize(v);
    let n_l = n.dot(l);
    let n_v = n.dot(v);
    if n_l <= 0.0 || n_v <= 0.0 {
        return None;
    }
    Some(Setup {
        n,
        l,
        v,
        n_l: clamp_cos(n_l),
        n_v: clamp_cos(n_v),
    })
}

/// Lambert, as terms.
pub fn lambert_terms(p: &LambertParams, n: Vec3, l: Vec3, v: Vec3) -> Terms {
    let p = p.sanitized();
    if setup(n, l, v).is_none() {
        return Terms::ZERO;
    }
    Terms {
        diffuse: diffuse_lambert(p.albedo),
        ..Terms::ZERO
    }
}

/// Lambert: `albedo / π`.
pub fn lambert(p: &LambertParams, n: Vec3, l: Vec3, v: Vec3) -> Vec3 {
    lambert_terms(p, n, l, v).total()
}

/// The specular power of the classic models: `max(r·v, 0)^n` (Phong) or `max(n·h, 0)^n`
/// (Blinn-Phong); 0 when the base is `≤ 0`.
fn classic_lobe(p: &PhongParams, s: &Setup) -> f32 {
    let base = if p.blinn {
        s.n.dot(safe_normalize(s.l + s.v))
    } else {
        let r = s.n * (2.0 * s.n.dot(s.l)) - s.l;
        r.dot(s.v)
    };
    if base <= 0.0 {
        0.0
    } else {
        base.powf(p.shininess)
    }
}

/// Phong or Blinn-Phong (by `p.blinn`) as terms: `diffuse = k_d O_d`,
/// `specular = k_s O_s lobe / (n·l)`.
pub fn phong_terms(p: &PhongParams, n: Vec3, l: Vec3, v: Vec3) -> Terms {
    let p = p.sanitized();
    let Some(s) = setup(n, l, v) else {
        return Terms::ZERO;
    };
    let lobe = classic_lobe(&p, &s);
    Terms {
        diffuse: p.diffuse_color * p.kd,
        specular: p.specular_color * (p.ks * lobe / s.n_l),
        ..Terms::ZERO
    }
}

/// Classic Phong BRDF equivalent (`r·v` lobe whatever `p.blinn` says).
pub fn phong(p: &PhongParams, n: Vec3, l: Vec3, v: Vec3) -> Vec3 {
    phong_terms(&PhongParams { blinn: false, ..*p }, n, l, v).total()
}

/// Classic Blinn-Phong BRDF equivalent (`n·h` lobe whatever `p.blinn` says).
pub fn blinn_phong(p: &PhongParams, n: Vec3, l: Vec3, v: Vec3) -> Vec3 {
    phong_terms(&PhongParams { blinn: true, ..*p }, n, l, v).total()
}

/// The slides' formula: `I_L (k_d O_d (n·l) + k_s O_s lobe)` with `I_L = e_light`; 0 when
/// `n·l ≤ 0` or `n·v ≤ 0`. Light attenuation `f_at` is the caller's (fold it into `e_light`).
pub fn phong_radiance(p: &PhongParams, n: Vec3, l: Vec3, v: Vec3, e_light: Vec3) -> Vec3 {
    let p = p.sanitized();
    // The slides' model literally: only n·l > 0 is required (no condition on n·v), so
    // interpolated normals at silhouettes keep their diffuse light as in the figures.
    let (n, l, v) = (safe_normalize(n), safe_normalize(l), safe_normalize(v));
    let n_l = n.dot(l);
    if n_l <= 0.0 {
        return Vec3::ZERO;
    }
    let s = Setup {
        n,
        l,
        v,
        n_l: clamp_cos(n_l),
        n_v: clamp_cos(n.dot(v).max(0.0)),
    };
    let lobe = classic_lobe(&p, &s);
    let n_l = n_l.min(1.0);
    e_light * (p.diffuse_color * (p.kd * n_l) + p.specular_color * (p.ks * lobe))
}

/// Cook-Torrance as terms.
pub fn cook_torrance_terms(p: &CookTorranceParams, n: Vec3, l: Vec3, v: Vec3) -> Terms {
    let p = p.sanitized();
    let Some(s) = setup(n, l, v) else {
        return Terms::ZERO;
    };
    let a = p.width();
    let (spec, kappa) = p.specular.fresnel_inputs(p.fresnel);
    let h = safe_normalize(s.l + s.v);
    let n_h = s.n.dot(h);
    let sin2_h = s.n.cross(h).length_squared();
    let v_h = s.v.dot(h);
    let d = p.distribution.eval(n_h, sin2_h, a);
    let g = p.geometry.eval(n_h, s.n_v, s.n_l, v_h, a, p.roughness);
    let f = p.fresnel.eval(spec, kappa, v_h);
    let spec_brdf = f * (d * g / (4.0 * s.n_l * s.n_v));
    // l·h = v·h (h is the half vector).
    Terms {
        d,
        g,
        f,
        diffuse: p.color * (p.kd * INV_PI * p.diffuse.factor(s.n_l, s.n_v, v_h, p.roughness)),
        specular: spec_brdf * (1.0 - p.kd),
    }
}

/// Cook-Torrance: `k_d · color/π + (1 − k_d) · D F G / (4 (n·l)(n·v))`.
pub fn cook_torrance(p: &CookTorranceParams, n: Vec3, l: Vec3, v: Vec3) -> Vec3 {
    cook_torrance_terms(p, n, l, v).total()
}

/// glTF metallic-roughness as terms, with KHR_materials_sheen's sheen over the base
/// ([`layers::sheen_layer`]) and the clear coat of KHR_materials_clearcoat on top
/// ([`layers::clearcoat_layer`]; the coat's normal is `n`), the extensions' order.
/// An anisotropic material (KHR_materials_anisotropy) needs the tangent frame:
/// [`metal_rough_terms_frame`]; here it is built from `n` alone.
pub fn metal_rough_terms(p: &MetalRoughParams, n: Vec3, l: Vec3, v: Vec3) -> Terms {
    metal_rough_terms_frame(p, n, l, v, Vec3::ZERO, Vec3::ZERO)
}

/// KHR_materials_anisotropy's lobe at a point: the anisotropy direction `t` (the tangent
/// frame's `x` turned by `anisotropy_rotation` towards `y`), `b = n × t`, and the widths
/// `α_t = mix(α, 1, strength²)`, `α_b = α` (`α = roughness²`, clamped to [`ALPHA_MIN`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnisotropicLobe {
    pub t: Vec3,
    pub b: Vec3,
    pub alpha_t: f32,
    pub alpha_b: f32,
}

impl AnisotropicLobe {
    /// The perceptual roughness of an isotropic lobe of about the same directional albedo,
    /// `((α_t² + α_b²)/2)^¼`: the GPU's prefiltered-cube mip for the lobe (`brdf_lobe_roughness`).
    /// At normal view it is within 0.02 of the isotropic roughness whose albedo equals the
    /// anisotropic lobe's (integrated: 0.42 for 0.43, 0.84 for 0.82, 0.48 for 0.49); towards
    /// grazing the albedo depends on the view's azimuth, which one roughness cannot follow, so
    /// energy compensation reads the lobe's own split sum ([`super::aniso_split_sum_ab`]).
    pub fn equivalent_roughness(&self) -> f32 {
        ((self.alpha_t * self.alpha_t + self.alpha_b * self.alpha_b) * 0.5)
            .sqrt()
            .sqrt()
    }
}

/// The anisotropic lobe of sanitised `p` at unit normal `n` with tangent frame `(x, y)`
/// (degenerate ones are rebuilt, [`tangent_frame`]); `None` when the material is isotropic
/// (strength 0) or its distribution is not GGX.
pub fn anisotropic_lobe(
    p: &MetalRoughParams,
    n: Vec3,
    x: Vec3,
    y: Vec3,
) -> Option<AnisotropicLobe> {
    if p.anisotropy_strength <= 0.0 || p.distribution != Distribution::Ggx {
        return None;
    }
    let (tx, ty) = tangent_frame(n, x, y);
    let (sin, cos) = p.anisotropy_rotation.sin_cos();
    let t = safe_normalize(tx * cos + ty * sin);
    let a = (p.roughness * p.roughness).max(ALPHA_MIN);
    let s2 = p.anisotropy_strength * p.anisotropy_strength;
    Some(AnisotropicLobe {
        t,
        b: n.cross(t),
        alpha_t: a + (1.0 - a) * s2,
        alpha_b: a,
    })
}

impl MetalRoughParams {
    /// The F90 of the mixed material: `mix(dielectric_f90, 1, metallic)` (KHR_materials_specular
    /// scales the dielectric only).
    pub fn f90(&self) -> f32 {
        self.dielectric_f90 + (1.0 - self.dielectric_f90) * self.metallic
    }
}

/// The Schlick forms' `F = F0 + (1 − F0) w` with F90 in place of 1: `F0 + (F90 − F0) w`
/// (`w = (F − F0)/(1 − F0)`, each form's own weight); the exact forms unchanged.
pub fn with_f90(fresnel: Fresnel, f: Vec3, f0: Vec3, f90: f32) -> Vec3 {
    if !matches!(fresnel, Fresnel::Schlick | Fresnel::SchlickSg) {
        return f;
    }
    let mut out = f;
    for i in 0..3 {
        let room = 1.0 - f0[i];
        if room > 1e-6 {
            out[i] = f0[i] + (f[i] - f0[i]) * ((f90 - f0[i]) / room);
        }
    }
    out
}

/// KHR_materials_iridescence's rules that the scene decoder and the glTF reader both apply:
/// why `iridescenceIor` is refused (the film's index is at least 1), if it is.
pub fn film_ior_error(ior: f32) -> Option<String> {
    (ior < 1.0).then(|| format!("a film's index is at least 1, got {ior}"))
}

/// Why `iridescenceThicknessMinimum` is refused (a reversed range), if it is.
pub fn film_range_error(min: f32, max: f32) -> Option<String> {
    (min > max).then(|| {
        format!("the thickness range is reversed: minimum {min} nm is above the maximum {max} nm")
    })
}

/// Whether sanitised `p` has KHR_materials_iridescence's film: a factor above 0 and a
/// thickness above 0.
pub fn has_iridescence(p: &MetalRoughParams) -> bool {
    p.iridescence > 0.0 && p.iridescence_thickness_max > 0.0
}

/// KHR_materials_iridescence's Fresnel of sanitised `p` at `cos` (v·h; n·v for the
/// environment): the film over the dielectric's F0 and over the metal's base colour, mixed by
/// metallic (one evaluation when metallic is 0 or 1), as the extension's dielectric and metal
/// BRDFs mix. Under a clear coat the film is seen from inside the coat, at the refracted angle
/// ([`iridescence_outside_ior`], [`iridescence_cos_above`]).
pub fn iridescence_fresnel_of(p: &MetalRoughParams, cos: f32) -> Vec3 {
    iridescence_fresnel_with(p, &material_film(p), cos)
}

/// The film of sanitised `p` whatever the angle (what [`iridescence_fresnel_with`] takes).
fn material_film(p: &MetalRoughParams) -> super::iridescence::Film {
    super::iridescence::film_of(
        iridescence_outside_ior(p),
        p.iridescence_ior,
        p.iridescence_thickness_max,
    )
}

/// [`iridescence_fresnel_of`] with `p`'s film `m` made already, for several angles of one
/// material.
pub fn iridescence_fresnel_with(
    p: &MetalRoughParams,
    m: &super::iridescence::Film,
    cos: f32,
) -> Vec3 {
    use super::iridescence::{film_at, film_base, film_over};
    let at = film_at(m, iridescence_cos_above(p, cos));
    let film = |f0: Vec3| film_over(at.as_ref(), &film_base(m, f0));
    if p.metallic <= 0.0 {
        film(p.dielectric_f0)
    } else if p.metallic >= 1.0 {
        film(p.base_color)
    } else {
        mix3(film(p.dielectric_f0), film(p.base_color), p.metallic)
    }
}

/// The index above the film: air (1), or under KHR_materials_clearcoat the coat's (1.5, the
/// extension's "outside IOR"), mixed by the coat's factor: `1 + 0.5 · clearcoat`, continuous as
/// the factor (or its texture) goes to 0.
pub fn iridescence_outside_ior(p: &MetalRoughParams) -> f32 {
    1.0 + 0.5 * p.clearcoat
}

/// The cosine at which light meets the film: `cos` (from air) without a coat; under one, the
/// angle refracted into the coat, `sqrt(1 − (1 − cos²)/n₀²)` with n₀ = [`iridescence_outside_ior`].
/// Snell's law into the film is then the same as from air (n₀ sin θ₀ = sin θ), so a coat never
/// makes total internal reflection in the film (taking 1.5 at the air's angle did: a white
/// furnace of 1.64); the first interface's reflectance is the film's against the coat.
pub fn iridescence_cos_above(p: &MetalRoughParams, cos: f32) -> f32 {
    if p.clearcoat <= 0.0 {
        return cos;
    }
    let n0 = iridescence_outside_ior(p);
    let c = cos.clamp(0.0, 1.0);
    (1.0 - (1.0 - c * c) / (n0 * n0)).max(0.0).sqrt()
}

/// The F0 that the split sum and energy compensation take for an iridescent material over a
/// split-sum entry `[A, B, μ, σ]` ([`super::split_sum_lut_moments`]), mixed with `f0` by the
/// iridescence factor: `F0·A + B` is the lobe's mean film Fresnel times `A + B`, that mean
/// taken as
/// * the film's Fresnel at the mean Schlick angle `c` = [`split_sum_mean_cos`] (exact for any
///   Schlick curve: the extension's sample renderer's `Schlick_to_F0` takes `c` = n·v), plus
/// * the mean over the lobe of the film's difference from the Schlick curve through that point
///   (reaching the film's own grazing value: 1 in air, far less under a coat), taken at `μ` and
///   `μ ± √3 σ` with weights 2/3, 1/6, 1/6: the film's curvature over the lobe, which a Schlick
///   curve does not follow. Without it a white dielectric of roughness 0.6 with a 300 nm film
///   returned 1.0197 in a compensated white furnace at 85° (its mean Fresnel in green 0.181
///   where the lobe's is 0.159); with it 0.155.
///
/// Below 0 where the film stays under Schlick's curve (under a clear coat it does not reach 1 at
/// grazing): `F0·A + B` is then still the mean exactly (clamped at 0, a coated film 85° off the
/// normal left 17 % of a white furnace's energy out); [`super::energy_scale_ab`]'s
/// multiple-scattering factor takes it at 0 or above. An anisotropic lobe's table holds `(A, B)`
/// only: it passes `μ` = `c`, `σ` = 0, where the correction is 0.
pub fn iridescence_f0_lobe(p: &MetalRoughParams, f0: Vec3, lobe: [f32; 4]) -> Vec3 {
    if !has_iridescence(p) {
        return f0;
    }
    let [a, b, mu, sd] = lobe;
    let c = split_sum_mean_cos(a, b);
    let w = schlick_weight(c.clamp(0.0, 1.0));
    let k = 1.0 / (1.0 - w).max(1e-4);
    let m = material_film(p);
    let f = iridescence_fresnel_with(p, &m, c);
    // Schlick's curve through F(c) that reaches the film's own grazing value (1 in air; under a
    // coat the film stays far below it).
    let f90 = iridescence_fresnel_with(p, &m, 0.0);
    let through = (f - f90 * w) * k;
    let off_schlick = |x: f32| {
        let x = x.clamp(0.0, 1.0);
        let s = schlick_weight(x);
        iridescence_fresnel_with(p, &m, x) - (through + (f90 - through) * s)
    };
    // Three points of the lobe's v·h, exact for a cubic difference if the lobe were symmetric.
    let h = 3f32.sqrt() * sd;
    let mean = f
        + (off_schlick(mu - h) + off_schlick(mu + h)) * (1.0 / 6.0)
        + off_schlick(mu) * (2.0 / 3.0);
    let film_f0 = ((mean - Vec3::splat(w)) * k).min(Vec3::ONE);
    mix3(f0, film_f0, p.iridescence)
}

/// The v·h at which Schlick's weight (1 − v·h)⁵ is the lobe's mean weight over a split-sum entry
/// (A, B): B / (A + B). Schlick's F there times A + B is exactly F0·A + B, so a Fresnel of another
/// shape (the film's) taken there carries the lobe's albedo; n·v would be exact for a mirror only
/// (the white furnace with the film at roughness 1, 85°: 2.8 % off at n·v).
pub fn split_sum_mean_cos(a: f32, b: f32) -> f32 {
    1.0 - (b / (a + b).max(1e-6)).clamp(0.0, 1.0).powf(0.2)
}

/// [`metal_rough_terms`] with the tangent frame `(x, y)` that KHR_materials_anisotropy turns
/// its direction from.
pub fn metal_rough_terms_frame(
    p: &MetalRoughParams,
    n: Vec3,
    l: Vec3,
    v: Vec3,
    x: Vec3,
    y: Vec3,
) -> Terms {
    let p = p.sanitized();
    let Some(s) = setup(n, l, v) else {
        return Terms::ZERO;
    };
    let lobe = anisotropic_lobe(&p, s.n, x, y);
    let mut t = metal_rough_base_terms(&p, &s, lobe.as_ref());
    if p.sheen_color != Vec3::ZERO {
        let e = layers::sheen_albedo(s.n_v, p.sheen_roughness);
        t = layers::sheen_layer(t, &p, s.n, s.l, s.v, e);
    }
    if p.clearcoat <= 0.0 {
        return t;
    }
    // The coat's own normal: its lobe and what it takes at its own angles, its cosine instead of
    // the base's (the caller multiplies by n·l).
    let nc = p.clearcoat_normal.unwrap_or(s.n);
    let (nc_v, nc_l) = (nc.dot(s.v), nc.dot(s.l));
    let c_v = clamp_cos(nc_v);
    let coat = if p.energy_compensation {
        layers::clearcoat_energy(&p, c_v)
    } else {
        layers::ClearcoatEnergy::schlick(c_v)
    };
    // 1 without a coat normal of its own (as the GPU: the same cosine over itself, clamped or
    // not); else the raw cosines' ratio, as the GPU takes it.
    let cosines = match p.clearcoat_normal {
        None => 1.0,
        Some(_) if nc_l > 0.0 && nc_v > 0.0 => nc_l / s.n.dot(s.l),
        Some(_) => 0.0,
    };
    layers::clearcoat_layer(t, &p, (nc, cosines), s.l, s.v, coat)
}

/// The metallic-roughness terms without layers, of sanitised parameters; `lobe`: the
/// anisotropic GGX lobe that replaces D and G (KHR_materials_anisotropy).
fn metal_rough_base_terms(
    p: &MetalRoughParams,
    s: &Setup,
    lobe: Option<&AnisotropicLobe>,
) -> Terms {
    let a = (p.roughness * p.roughness).max(ALPHA_MIN);
    let f0 = mix3(p.dielectric_f0, p.base_color, p.metallic);
    // KHR_materials_transmission and _diffuse_transmission: the specular and the diffuse BTDF
    // take those shares of the dielectric's diffuse (what goes through is the reference's, not
    // this BRDF's).
    let t = p.transmission;
    let c_diff = p.base_color * (1.0 - p.metallic) * (1.0 - t.factor) * (1.0 - t.diffuse);
    let (spec, kappa) = p.fresnel.inputs_from_f0(f0);
    let h = safe_normalize(s.l + s.v);
    let n_h = s.n.dot(h);
    let sin2_h = s.n.cross(h).length_squared();
    let v_h = s.v.dot(h);
    let (d, g) = match lobe {
        None => (
            p.distribution.eval(n_h, sin2_h, a),
            p.geometry.eval(n_h, s.n_v, s.n_l, v_h, a, p.roughness),
        ),
        Some(an) => (
            d_gtr2_aniso(n_h, an.t.dot(h), an.b.dot(h), an.alpha_t, an.alpha_b),
            g_smith_ggx_correlated_aniso(
                s.n_l,
                s.n_v,
                an.t.dot(s.l),
                an.b.dot(s.l),
                an.t.dot(s.v),
                an.b.dot(s.v),
                an.alpha_t,
                an.alpha_b,
            ),
        ),
    };
    let mut f = p.fresnel.eval(spec, kappa, v_h);
    let f90 = p.f90();
    if f90 < 1.0 {
        f = with_f90(p.fresnel, f, f0, f90);
    }
    if has_iridescence(p) {
        // KHR_materials_iridescence: the film's Fresnel at v·h (or at n·v, once per pixel on the
        // GPU, with `iridescence_at_view`), weighted by its factor.
        let c = if p.iridescence_at_view { s.n_v } else { v_h };
        f = mix3(f, iridescence_fresnel_of(p, c), p.iridescence);
    }
    let weight = if p.diffuse_fresnel_weight {
        Vec3::ONE - f
    } else {
        Vec3::ONE
    };
    let energy = if p.energy_compensation {
        // The split sum's (A, B) of the lobe: the isotropic table's, or for
        // KHR_materials_anisotropy the anisotropic lobe's own at the view's azimuth in its frame.
        let entry = match lobe {
            None => super::split_sum_lobe(p.geometry, s.n_v, p.roughness),
            Some(an) => {
                let phi = super::aniso_azimuth(an.t.dot(s.v), an.b.dot(s.v));
                let (a, b) =
                    super::aniso_split_sum_ab(s.n_v, phi, p.roughness, p.anisotropy_strength);
                [a, b, split_sum_mean_cos(a, b), 0.0]
            }
        };
        let f0 = iridescence_f0_lobe(p, f0, entry);
        super::energy_scale_ab(f0, f90, entry[0], entry[1])
    } else {
        super::EnergyScale::NONE
    };
    // With `diffuse_fresnel_weight` the diffuse is already weighted per direction.
    let diffuse_energy = if p.diffuse_fresnel_weight {
        Vec3::ONE
    } else {
        energy.diffuse
    };
    Terms {
        d,
        g,
        f,
        // l·h = v·h (h is the half vector); Burley takes the perceptual roughness.
        diffuse: c_diff
            * INV_PI
            * p.diffuse.factor(s.n_l, s.n_v, v_h, p.roughness)
            * weight
            * diffuse_energy,
        specular: f * (d * g / (4.0 * s.n_l * s.n_v)) * energy.specular,
    }
}

/// glTF metallic-roughness: `c_diff/π · [1 − F] + D F G / (4 (n·l)(n·v))`.
pub fn metal_rough(p: &MetalRoughParams, n: Vec3, l: Vec3, v: Vec3) -> Vec3 {
    metal_rough_terms(p, n, l, v).total()
}

/// Disney Principled as terms (`d = Ds`, `g = Gs · 4 (n·l)(n·v)`, `f = Fs`; sheen is in
/// `diffuse`, clearcoat in `specular`).
pub fn principled_terms(
    p: &PrincipledParams,
    n: Vec3,
    l: Vec3,
    v: Vec3,
    x: Vec3,
    y: Vec3,
) -> Terms {
    let p = p.sanitized();
    let Some(s) = setup(n, l, v) else {
        return Terms::ZERO;
    };
    let (tx, ty) = tangent_frame(s.n, x, y);
    let h = safe_normalize(s.l + s.v);
    let n_h = s.n.dot(h);
    let sin2_h = s.n.cross(h).length_squared();
    let l_h = s.l.dot(h);

    let cdlin = p.base_color;
    let cdlum = 0.3 * cdlin.x + 0.6 * cdlin.y + 0.1 * cdlin.z;
    let ctint = if cdlum > 0.0 {
        cdlin / cdlum
    } else {
        Vec3::ONE
    };
    let cspec0 = mix3(
        mix3(Vec3::ONE, ctint, p.specular_tint) * (p.specular * 0.08),
        cdlin,
        p.metallic,
    );
    let csheen = mix3(Vec3::ONE, ctint, p.sheen_tint);

    // Diffuse (Fd) and Hanrahan-Krueger subsurface (ss).
    let fd = fd_burley(s.n_l, s.n_v, l_h, p.roughness);
    let ss = ss_hanrahan_krueger(s.n_l, s.n_v, l_h, p.roughness);

    // Specular.
    let aspect = (1.0 - p.anisotropic * 0.9).sqrt();
    let r2 = p.roughness * p.roughness;
    let ax = (r2 / aspect).max(ALPHA_MIN);
    let ay = (r2 * aspect).max(ALPHA_MIN);
    let ds = d_gtr2_aniso(n_h, h.dot(tx), h.dot(ty), ax, ay);
    let fh = schlick_weight(l_h);
    let fs = mix3(cspec0, Vec3::ONE, fh);
    let gs = vis_smith_ggx_aniso(s.n_l, s.l.dot(tx), s.l.dot(ty), ax, ay)
        * vis_smith_ggx_aniso(s.n_v, s.v.dot(tx), s.v.dot(ty), ax, ay);

    // Sheen.
    let fsheen = csheen * (fh * p.sheen);

    // Clearcoat (ior = 1.5 → F0 = 0.04).
    let dr = d_gtr1_sin2(n_h, sin2_h, mix(0.1, 0.001, p.clearcoat_gloss));
    let fr = mix(0.04, 1.0, fh);
    let gr = vis_smith_ggx_iso(s.n_l, 0.25) * vis_smith_ggx_iso(s.n_v, 0.25);

    Terms {
        d: ds,
        g: gs * 4.0 * s.n_l * s.n_v,
        f: fs,
        diffuse: (cdlin * (INV_PI * mix(fd, ss, p.subsurface)) + fsheen) * (1.0 - p.metallic),
        specular: fs * (gs * ds) + Vec3::splat(0.25 * p.clearcoat * gr * fr * dr),
    }
}

/// Disney Principled BRDF value.
pub fn principled(p: &PrincipledParams, n: Vec3, l: Vec3, v: Vec3, x: Vec3, y: Vec3) -> Vec3 {
    principled_terms(p, n, l, v, x, y).total()
}

/// Oren-Nayar as terms.
pub fn oren_nayar_terms(p: &OrenNayarParams, n: Vec3, l: Vec3, v: Vec3) -> Terms {
    let p = p.sanitized();
    let Some(s) = setup(n, l, v) else {
        return Terms::ZERO;
    };
    let sigma = p.sigma_deg.to_radians();
    let cos_phi = cos_phi_diff(s.n, s.l, s.v);
    Terms {
        diffuse: diffuse_oren_nayar(p.albedo, sigma, s.n_l, s.n_v, cos_phi),
        ..Terms::ZERO
    }
}

/// Qualitative Oren-Nayar BRDF value.
pub fn oren_nayar(p: &OrenNayarParams, n: Vec3, l: Vec3, v: Vec3) -> Vec3 {
    oren_nayar_terms(p, n, l, v).total()
}

/// The BRDF split into terms (see [`Terms`]).
pub fn eval_terms(model: &Model, n: Vec3, l: Vec3, v: Vec3, x: Vec3, y: Vec3) -> Terms {
    match model {
        Model::Lambert(p) => lambert_terms(p, n, l, v),
        Model::Phong(p) => phong_terms(p, n, l, v),
        Model::CookTorrance(p) => cook_torrance_terms(p, n, l, v),
        Model::MetalRough(p) => metal_rough_terms_frame(p, n, l, v, x, y),
        Model::Principled(p) => principled_terms(p, n, l, v, x, y),
        Model::OrenNayar(p) => oren_nayar_terms(p, n, l, v),
    }
}

/// The BRDF value `f(l, v)` (not multiplied by `n·l`). `x`, `y`: tangent and bitangent (only
/// anisotropic Principled uses them; degenerate ones are rebuilt).
pub fn eval(model: &Model, n: Vec3, l: Vec3, v: Vec3, x: Vec3, y: Vec3) -> Vec3 {
    eval_terms(model, n, l, v, x, y).total()
}

/// Reflected radiance from one light of irradiance `e_light` (at normal incidence):
/// `f · E · max(n·l, 0)`; for the classic Phong / Blinn-Phong, the slides' formula
/// [`phong_radiance`] with `I_L = e_light`.
pub fn radiance(model: &Model, n: Vec3, l: Vec3, v: Vec3, x: Vec3, y: Vec3, e_light: Vec3) -> Vec3 {
    if let Model::Phong(p) = model {
        return phong_radiance(p, n, l, v, e_light);
    }
    let n_l = safe_normalize(n).dot(safe_normalize(l)).clamp(0.0, 1.0);
    eval(model, n, l, v, x, y) * e_light * n_l
}
