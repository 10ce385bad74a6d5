//! The CPU reference BRDFs: every reflection model the renderer has, term by term, in `f32`.
//!
//! The formulas are those of `MODELS.md` (§1 classic, §3 Fresnel, §4 microfacet, §5 Disney
//! "Principled", §6 diffuse). `shaders_glsl/brdf/terms.glsl` and `shaders_glsl/brdf/models.glsl`
//! mirror this module function for function, with the same names, clamps and epsilons, so that a
//! GPU frame can be compared with the CPU per pixel.
//!
//! Conventions: `n` normal, `l` towards the light, `v` towards the viewer, `x`/`y` tangent and
//! bitangent, `h = normalize(l + v)`. [`eval`] returns the BRDF value `f` (not multiplied by
//! `n·l`); [`radiance`] returns `f · E · max(n·l, 0)`.
//!
//! Robustness rules, shared with the GLSL (see `docs/brdf.md`):
//! * `f = 0` when `n·l ≤ 0` or `n·v ≤ 0` (also when `n`, `l` or `v` is a zero vector);
//! * afterwards `n·l` and `n·v` are clamped to `[COS_EPS, 1]` wherever they are divided by;
//! * every D clamps its width (`α`, `α_x`, `α_y`, `m`) to at least [`ALPHA_MIN`];
//! * `h` is the zero vector when `|l + v|² ≤ LEN2_EPS` (`l = −v`), which zeroes every D;
//! * degenerate tangents are rebuilt from the normal ([`tangent_frame`]);
//! * parameters are sanitised (non-finite → default, unit-range parameters clamped to [0, 1]).

mod albedo;
mod aniso_split_sum;
mod energy;
mod gpu;
pub mod iridescence;
mod ltc;
mod ltc_line;
mod models;
mod names;
mod presets;
mod sampling;
mod shipped_lut;
mod split_sum;
mod terms;
mod transmission;

#[cfg(test)]
mod tests;

pub use albedo::{
    directional_albedo, directional_albedo_dir, integrate_hemisphere, sampling_lobes, Lobe,
};
pub use aniso_split_sum::{
    aniso_azimuth, aniso_lut, aniso_lut_coords, aniso_lut_index, aniso_lut_layers, aniso_lut_table,
    aniso_lut_tiles, aniso_split_sum_ab, aniso_split_sum_reference, aniso_widths,
    generate_aniso_lut, sample_ggx_vndf_aniso, shipped_aniso_lut, ANISO_LUT_FILE, ANISO_LUT_NV,
    ANISO_LUT_PHI, ANISO_LUT_ROUGHNESS, ANISO_LUT_SAMPLES, ANISO_LUT_STRENGTH,
};
pub use energy::{
    energy_scale, energy_scale_ab, energy_scale_f90, split_sum_ab, split_sum_lobe, EnergyScale,
};
pub use gpu::{model_code, GpuBrdfParams};
pub use ltc::{
    fit_entry, fit_table, generate_ltc_table, ltc_table, refit_shipped_entry, shipped_lobe,
    LtcEntry, LTC_ENTRY, LTC_FILE, LTC_FIT_SAMPLES, LTC_SIZE,
};
pub use ltc_line::{area_edge, ltc_ribbon, ltc_tube, ltc_tube_caps};
pub use models::layers::{
    clearcoat_energy, clearcoat_layer, clearcoat_specular, d_charlie, fit_sheen_albedo,
    fit_sheen_lambda, lambda_sheen, lambda_sheen_of, sheen_albedo, sheen_albedo_fit,
    sheen_albedo_glsl_source, sheen_albedo_integrated, sheen_fit_variables, sheen_lambda_constants,
    sheen_lambda_fit, sheen_lambda_fit_error, sheen_lambda_fit_of, sheen_lambda_glsl_source,
    sheen_layer, sheen_specular, v_sheen, ClearcoatEnergy, SheenFit, SheenLambdaConstants,
    SheenLambdaError, CLEARCOAT_F0, SHEEN_FIT_S, SHEEN_FIT_X, SHEEN_LAMBDA_DEGREE,
    SHEEN_LAMBDA_DEGREE_S, SHEEN_LAMBDA_GLSL, SHEEN_LAMBDA_W_MIN, SHEEN_ROUGHNESS_MIN,
};
pub use models::{
    anisotropic_lobe, blinn_phong, cook_torrance, cook_torrance_terms, eval, eval_terms,
    film_ior_error, film_range_error, has_iridescence, iridescence_f0_lobe, iridescence_fresnel_of,
    iridescence_fresnel_with, lambert, lambert_terms, metal_rough, metal_rough_terms,
    metal_rough_terms_frame, oren_nayar, oren_nayar_terms, phong, phong_radiance, phong_terms,
    principled, principled_terms, radiance, split_sum_mean_cos, AnisotropicLobe,
    CookTorranceParams, Diffuse, Distribution, Fresnel, Geometry, LambertParams, MetalRoughParams,
    Model, OrenNayarParams, PhongParams, PrincipledParams, SpecularSource, Terms,
};
pub(crate) use names::selector_names;
pub use names::ModelKind;
pub use presets::{
    dielectric_ior, f0_from_ior, ior_from_f0, metal_preset, ComplexIor, DIELECTRIC_NAMES,
    METAL_NAMES,
};
pub use sampling::{
    hammersley, importance_sample_ggx, ortho_basis, radical_inverse_vdc, sample_beckmann_h,
    sample_cosine_hemisphere, sample_ggx_aniso_h, sample_gtr1_h, sample_power_cosine,
    sample_uniform_hemisphere,
};
pub use shipped_lut::{
    generate_shipped_lut, shipped_lut, shipped_lut_bytes, SHIPPED_LUT_FILE, SHIPPED_LUT_GEOMETRY,
    SHIPPED_LUT_SAMPLES, SHIPPED_LUT_SIZE,
};
pub use split_sum::{
    g_ibl, lut_node, lut_point, lut_uv, split_sum_lut_moments, split_sum_lut_reference,
    split_sum_lut_table,
};
pub use terms::*;
pub use transmission::{
    attenuation_coefficient, beer_lambert, refract, DielectricSample, RoughDielectric, Transmission,
};
