//! The packed material parameters the GLSL mirror reads (`BrdfParams` in
//! `shaders_glsl/brdf/models.glsl`): 112 bytes, std430 / push-constant layout, seven 16-byte slots.
//!
//! | offset | GLSL | Lambert | Phong / Blinn | Cook-Torrance | metal-rough | Principled | Oren-Nayar |
//! |---|---|---|---|---|---|---|---|
//! | 0  | `vec4 color`  | albedo, – | O_d, – | colour, roughness | base, roughness | base, roughness | ρ, – |
//! | 16 | `vec4 spec`   | – | O_s, – | F0 or η (by `fresnel`), – | –, metallic | –, metallic | – |
//! | 32 | `vec4 kappa`  | – | –, k_d | κ, k_d | sheen_color, sheen_roughness | – | – |
//! | 48 | `vec4 p0`     | – | k_s, n, k_a, – | –, diffuse, –, – | (1−F) weight 0/1, diffuse, dielectric F90, iridescence factor (negative: at the view) | subsurface, specular, specular_tint, anisotropic | σ (radians), – |
//! | 64 | `vec4 p1`     | – | – | – | clearcoat, clearcoat_roughness, anisotropy strength, rotation | sheen, sheen_tint, clearcoat, clearcoat_gloss | – |
//! | 80 | `ivec4 sel`   | model, –, –, – | model, – | model, D, G, F | model, D, G, F | model, – | model, – |
//! | 96 | `vec4 p2`     | – | – | – | transmission, diffuse transmission, iridescence ior, iridescence thickness (nm) | – | – |
//!
//! `diffuse` is the [`Diffuse`](super::Diffuse) code as a float (0 Lambert, 1 Burley): `sel` is
//! full. The forward pass may also fix it per pipeline (specialization constant `SEL_DIFFUSE`).
//!
//! Unused slots are 0. The parameters are sanitised first ([`Model::sanitized`]), so the GLSL
//! does no range checks of its own beyond the clamps inside the terms.

use super::models::Model;

/// `BRDF_MODEL_*` codes in `sel.x`.
pub mod model_code {
    /// Lambert.
    pub const LAMBERT: i32 = crate::glsl::brdf_models::BRDF_MODEL_LAMBERT;
    /// Phong.
    pub const PHONG: i32 = crate::glsl::brdf_models::BRDF_MODEL_PHONG;
    /// Blinn-Phong.
    pub const BLINN_PHONG: i32 = crate::glsl::brdf_models::BRDF_MODEL_BLINN_PHONG;
    /// Cook-Torrance.
    pub const COOK_TORRANCE: i32 = crate::glsl::brdf_models::BRDF_MODEL_COOK_TORRANCE;
    /// glTF metallic-roughness.
    pub const METAL_ROUGH: i32 = crate::glsl::brdf_models::BRDF_MODEL_METAL_ROUGH;
    /// Disney Principled.
    pub const PRINCIPLED: i32 = crate::glsl::brdf_models::BRDF_MODEL_PRINCIPLED;
    /// Oren-Nayar.
    pub const OREN_NAYAR: i32 = crate::glsl::brdf_models::BRDF_MODEL_OREN_NAYAR;
}

/// The codes of a microfacet model's diffuse term, D, G and F (Cook-Torrance, metallic-roughness);
/// `None` for the other models.
fn microfacet_selectors(model: &Model) -> Option<(i32, i32, i32, i32)> {
    let (diffuse, d, g, f) = match model {
        Model::CookTorrance(p) => (p.diffuse, p.distribution, p.geometry, p.fresnel),
        Model::MetalRough(p) => (p.diffuse, p.distribution, p.geometry, p.fresnel),
        _ => return None,
    };
    Some((diffuse as i32, d as i32, g as i32, f as i32))
}

/// The GLSL `BrdfParams` struct, byte for byte (see the module docs for the slot table).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct GpuBrdfParams {
    /// Offset 0.
    pub color: [f32; 4],
    /// Offset 16.
    pub spec: [f32; 4],
    /// Offset 32.
    pub kappa: [f32; 4],
    /// Offset 48.
    pub p0: [f32; 4],
    /// Offset 64.
    pub p1: [f32; 4],
    /// Offset 80: model code, distribution, geometry, fresnel.
    pub sel: [i32; 4],
    /// Offset 96: metal-rough: transmission factor, diffuse transmission factor, –, –.
    pub p2: [f32; 4],
}

const _: () = assert!(std::mem::size_of::<GpuBrdfParams>() == GpuBrdfParams::SIZE);
const _: () = assert!(GpuBrdfParams::SIZE <= 128);

impl GpuBrdfParams {
    /// Size in bytes (112).
    pub const SIZE: usize = 112;

    /// Packs a (sanitised) model.
    pub fn from_model(model: &Model) -> Self {
        let mut g = GpuBrdfParams::default();
        let model = model.sanitized();
        match &model {
            Model::Lambert(p) => {
                g.color = p.albedo.extend(0.0).to_array();
                g.sel[0] = model_code::LAMBERT;
            }
            Model::Phong(p) => {
                g.color = p.diffuse_color.extend(0.0).to_array();
                g.spec = p.specular_color.extend(0.0).to_array();
                g.kappa[3] = p.kd;
                g.p0 = [p.ks, p.shininess, p.ka, 0.0];
                g.sel[0] = if p.blinn {
                    model_code::BLINN_PHONG
                } else {
                    model_code::PHONG
                };
            }
            Model::CookTorrance(p) => {
                let (spec, kappa) = p.specular.fresnel_inputs(p.fresnel);
                g.color = p.color.extend(p.roughness).to_array();
                g.spec = spec.extend(0.0).to_array();
                g.kappa = kappa.extend(p.kd).to_array();
                g.sel[0] = model_code::COOK_TORRANCE;
            }
            Model::MetalRough(p) => {
                g.color = p.base_color.extend(p.roughness).to_array();
                g.spec = p.dielectric_f0.extend(p.metallic).to_array();
                g.p0[0] = if p.diffuse_fresnel_weight { 1.0 } else { 0.0 };
                g.p0[2] = p.dielectric_f90;
                // The sign: the film at the view (`iridescence_at_view`).
                g.p0[3] = if p.iridescence_at_view {
                    -p.iridescence
                } else {
                    p.iridescence
                };
                g.kappa = p.sheen_color.extend(p.sheen_roughness).to_array();
                g.p1 = [
                    p.clearcoat,
                    p.clearcoat_roughness,
                    p.anisotropy_strength,
                    p.anisotropy_rotation,
                ];
                g.p2 = [
                    p.transmission.factor,
                    p.transmission.diffuse,
                    p.iridescence_ior,
                    p.iridescence_thickness_max,
                ];
                g.sel[0] = model_code::METAL_ROUGH;
            }
            Model::Principled(p) => {
                g.color = p.base_color.extend(p.roughness).to_array();
                g.spec[3] = p.metallic;
                g.p0 = [p.subsurface, p.specular, p.specular_tint, p.anisotropic];
                g.p1 = [p.sheen, p.sheen_tint, p.clearcoat, p.clearcoat_gloss];
                g.sel[0] = model_code::PRINCIPLED;
            }
            Model::OrenNayar(p) => {
                g.color = p.albedo.extend(0.0).to_array();
                g.p0[0] = p.sigma_deg.to_radians();
                g.sel[0] = model_code::OREN_NAYAR;
            }
        }
        if let Some((diffuse, d, geometry, f)) = microfacet_selectors(&model) {
            g.p0[1] = diffuse as f32;
            g.sel[1..].copy_from_slice(&[d, geometry, f]);
        }
        g
    }

    /// The diffuse selector (`Diffuse` code) of the models that have one (Cook-Torrance,
    /// metallic-roughness), `None` for the others: what `SEL_DIFFUSE` is specialised to.
    pub fn diffuse_selector(model: &Model) -> Option<i32> {
        microfacet_selectors(model).map(|(diffuse, ..)| diffuse)
    }

    /// The 112 bytes in native (little-endian on every Vulkan target luz runs on) order, ready for
    /// `vkCmdPushConstants` or a uniform/storage buffer.
    pub fn to_bytes(&self) -> [u8; Self::SIZE] {
        let mut out = [0u8; Self::SIZE];
        let words = self
            .color
            .iter()
            .chain(&self.spec)
            .chain(&self.kappa)
            .chain(&self.p0)
            .chain(&self.p1)
            .map(|f| f.to_bits())
            .chain(self.sel.iter().map(|&i| i as u32))
            .chain(self.p2.iter().map(|f| f.to_bits()));
        for (chunk, w) in out.chunks_exact_mut(4).zip(words) {
            chunk.copy_from_slice(&w.to_ne_bytes());
        }
        out
    }
}
