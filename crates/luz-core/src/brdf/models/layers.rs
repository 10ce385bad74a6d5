//! The layers the ratified glTF PBR extensions put on the metallic-roughness model (issue 34),
//! mirrored function for function in `shaders_glsl/brdf/models.glsl`.
//!
//! KHR_materials_clearcoat: a clear dielectric coat (ior 1.5, so F0 = 0.04) over the base, with its
//! own roughness. The extension's layering is
//! `f = f_base · (1 − clearcoat · Fc) + clearcoat · f_coat`, where `f_coat = D G F / (4 (n·l)(n·v))`
//! is a microfacet lobe of width `clearcoat_roughness²` with Schlick's F (F0 0.04) at `v·h`, and
//! `Fc` is Schlick's F at the coat normal and the view, `F0 + (1 − F0)(1 − n·v)^5`. The coat takes
//! the material's distribution and geometry terms (glTF's are GGX and the height-correlated
//! Smith term, the extension's own), so its energy compensation reads the material's split-sum
//! table.
//!
//! With energy compensation on (the environment's `energy_compensation`), `Fc` is replaced by
//! the coat's compensated directional albedo `E_ms(n·v)` and the coat lobe gets the same
//! multi-scatter factor as the base's specular ([`crate::brdf::energy_scale`] with F0 0.04): the
//! base then receives exactly what the coat does not reflect, so a white furnace stays 1 whatever
//! the coat (the extension's `Fc` equals the coat's albedo only for a smooth coat).

use glam::Vec3;

use super::{MetalRoughParams, Terms};
use crate::brdf::{clamp_cos, safe_normalize, schlick_weight, ALPHA_MIN};

/// F0 of the clear coat (ior 1.5), as KHR_materials_clearcoat fixes it.
pub const CLEARCOAT_F0: f32 = 0.04;

/// What the coat takes from the base and gives its own lobe at one view.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClearcoatEnergy {
    /// The coat's reflectance at the view: the base is weighted by `1 − clearcoat · albedo`.
    pub albedo: f32,
    /// Multiplies the coat's lobe (1 without energy compensation).
    pub specular: f32,
}

impl ClearcoatEnergy {
    /// The extension's own: Schlick's Fresnel of F0 0.04 at `n_v`, the lobe unscaled.
    pub fn schlick(n_v: f32) -> Self {
        Self {
            albedo: CLEARCOAT_F0 + (1.0 - CLEARCOAT_F0) * schlick_weight(n_v),
            specular: 1.0,
        }
    }
}

/// The energy-compensated coat of `p` at `n_v`: its directional albedo `E_ms` from the split-sum
/// table and the multi-scatter factor of its lobe.
pub fn clearcoat_energy(p: &MetalRoughParams, n_v: f32) -> ClearcoatEnergy {
    let e = crate::brdf::energy_scale(
        p.geometry,
        Vec3::splat(CLEARCOAT_F0),
        n_v,
        p.clearcoat_roughness,
    );
    ClearcoatEnergy {
        albedo: 1.0 - e.diffuse.x,
        specular: e.specular.x,
    }
}

/// The coat's lobe `D G F / (4 (n·l)(n·v))` for unit `n` (the coat normal), `l` and `v` with
/// `n·l > 0` and `n·v > 0`; sanitised parameters.
pub fn clearcoat_specular(p: &MetalRoughParams, n: Vec3, l: Vec3, v: Vec3) -> f32 {
    let n_l = clamp_cos(n.dot(l));
    let n_v = clamp_cos(n.dot(v));
    let r = p.clearcoat_roughness;
    let a = (r * r).max(ALPHA_MIN);
    let h = safe_normalize(l + v);
    let n_h = n.dot(h);
    let sin2_h = n.cross(h).length_squared();
    let v_h = v.dot(h);
    let d = p.distribution.eval(n_h, sin2_h, a);
    let g = p.geometry.eval(n_h, n_v, n_l, v_h, a, r);
    let f = CLEARCOAT_F0 + (1.0 - CLEARCOAT_F0) * schlick_weight(v_h);
    f * (d * g / (4.0 * n_l * n_v))
}

/// The base's terms `t` under the coat of `p`: diffuse and specular weighted by
/// `1 − clearcoat · e.albedo`, plus `clearcoat · e.specular · f_coat` in the specular.
pub fn clearcoat_layer(
    t: Terms,
    p: &MetalRoughParams,
    n: Vec3,
    l: Vec3,
    v: Vec3,
    e: ClearcoatEnergy,
) -> Terms {
    let keep = 1.0 - p.clearcoat * e.albedo;
    let coat = p.clearcoat * e.specular * clearcoat_specular(p, n, l, v);
    Terms {
        diffuse: t.diffuse * keep,
        specular: t.specular * keep + Vec3::splat(coat),
        ..t
    }
}
