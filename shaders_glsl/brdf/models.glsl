// BRDF models (MODELS.md §1, §4, §5, §6): the GLSL mirror of src/brdf/models.rs.
// Parameters come packed in BrdfParams (112 bytes, filled by GpuBrdfParams::from_model in
// src/brdf/gpu.rs from sanitised parameters; layout in docs/brdf.md). Each brdf_*_terms function
// mirrors the Rust *_terms function of the same name. GLSL 4.60, no extension needed.
#ifndef LUZ_BRDF_MODELS_GLSL
#define LUZ_BRDF_MODELS_GLSL

#include "terms.glsl"
#include "sheen_albedo.glsl"
#include "sheen_lambda.glsl"

// sel.x: model
#define BRDF_MODEL_LAMBERT 0
#define BRDF_MODEL_PHONG 1
#define BRDF_MODEL_BLINN_PHONG 2
#define BRDF_MODEL_COOK_TORRANCE 3
#define BRDF_MODEL_METAL_ROUGH 4
#define BRDF_MODEL_PRINCIPLED 5
#define BRDF_MODEL_OREN_NAYAR 6
// sel.y: distribution
#define BRDF_D_BECKMANN 0
#define BRDF_D_GGX 1
// sel.z: geometry
#define BRDF_G_COOK_TORRANCE 0
#define BRDF_G_SMITH_GGX 1
#define BRDF_G_SMITH_GGX_CORRELATED 2
#define BRDF_G_SCHLICK_GGX 3
#define BRDF_G_SMITH_BECKMANN 4
// sel.w: fresnel
#define BRDF_F_SCHLICK 0
#define BRDF_F_SCHLICK_SG 1
#define BRDF_F_DIELECTRIC 2
#define BRDF_F_CONDUCTOR 3
#define BRDF_F_CONDUCTOR_EXACT 4
// p0.y (Cook-Torrance, metal-rough): diffuse, as a float
#define BRDF_DIFFUSE_LAMBERT 0
#define BRDF_DIFFUSE_BURLEY 1
// The layers of the glTF PBR extensions on metal-rough (src/brdf/models/layers.rs), bits of BRDF_LOBES.
#define BRDF_LOBE_CLEARCOAT 1u
#define BRDF_LOBE_SHEEN 2u
// Glass (issue 35; the forward pass's include/transmission.glsl): specular transmission through
// a copy of the opaque scene, one index per channel, and diffuse transmission from the far side.
#define BRDF_LOBE_TRANSMISSION 4u
#define BRDF_LOBE_DISPERSION 8u
#define BRDF_LOBE_DIFFUSE_TRANSMISSION 16u
// KHR_materials_anisotropy (anisotropic_lobe in src/brdf/models/mod.rs).
#define BRDF_LOBE_ANISOTROPY 32u
// KHR_materials_iridescence (iridescence_fresnel_of in src/brdf/models/mod.rs), two bits: a
// material of the pipeline takes the film at each light's v·h (IRIDESCENCE), or at n·v for every
// light (IRIDESCENCE_VIEW: MetalRoughParams::iridescence_at_view, packed as a negative factor;
// the lighting shaders evaluate it once per pixel, g_film_view, set by shade()). With one bit
// the other form compiles out (lavapipe would run both sides of a branch on the factor's sign
// under the lane mask); with both (a deferred lighting pass, brdf_eval.comp) the sign decides.
#define BRDF_LOBE_IRIDESCENCE 64u
#define BRDF_LOBE_IRIDESCENCE_VIEW 128u
// The lobes compiled in: the forward pass defines BRDF_LOBES as its LOBES specialization constant
// (include/bindings.glsl), so a lobe no material of the pipeline uses costs nothing; elsewhere
// (brdf_eval.comp) every lobe is compiled.
#ifndef BRDF_LOBES
#define BRDF_LOBES 0xFFFFFFFFu
#endif

// std430 / push-constant layout, 112 bytes. Slot use per model: docs/brdf.md.
struct BrdfParams {
    vec4 color;  //  0: rgb albedo / base colour / O_d; a roughness (Cook-Torrance, metal-rough, Principled)
    vec4 spec;   // 16: rgb O_s (Phong) or F0 / η (Cook-Torrance); a metallic (metal-rough, Principled)
    vec4 kappa;  // 32: rgb κ (Cook-Torrance conductor); a k_d (Phong, Cook-Torrance);
                 //     metal-rough (sheen_color, sheen_roughness)
    vec4 p0;     // 48: Phong (k_s, n, k_a, -); Cook-Torrance (-, diffuse, -, -);
                 //     metal-rough ((1-F) weight, diffuse, dielectric F90, iridescence factor);
                 //     Principled (subsurface, specular, specular_tint, anisotropic); Oren-Nayar (σ rad, -, -, -)
    vec4 p1;     // 64: Principled (sheen, sheen_tint, clearcoat, clearcoat_gloss);
                 //     metal-rough (clearcoat, clearcoat_roughness, anisotropy strength, rotation)
    ivec4 sel;   // 80: model, distribution, geometry, fresnel
    vec4 p2;     // 96: metal-rough (transmission, diffuse transmission, iridescence ior,
                 //     iridescence thickness nm)
};

// The BRDF split into terms; diffuse + specular is the BRDF value (see Terms in models.rs).
struct BrdfTerms {
    float d;
    float g;
    vec3 f;
    vec3 diffuse;
    vec3 specular;
};

BrdfTerms brdf_terms_zero() {
    BrdfTerms t;
    t.d = 0.0;
    t.g = 0.0;
    t.f = vec3(0.0);
    t.diffuse = vec3(0.0);
    t.specular = vec3(0.0);
    return t;
}

// sin2_h = |n × h|².
float brdf_distribution(int sel, float n_h, float sin2_h, float a) {
    if (sel == BRDF_D_BECKMANN) {
        return d_beckmann_sin2(n_h, sin2_h, a);
    }
    return d_ggx_sin2(n_h, sin2_h, a);
}

float brdf_geometry(int sel, float n_h, float n_v, float n_l, float v_h, float a, float roughness) {
    if (sel == BRDF_G_COOK_TORRANCE) {
        return g_cook_torrance(n_h, n_v, n_l, v_h);
    }
    if (sel == BRDF_G_SMITH_GGX) {
        return g_smith_ggx_separable(n_l, n_v, a);
    }
    if (sel == BRDF_G_SMITH_GGX_CORRELATED) {
        return g_smith_ggx_correlated(n_l, n_v, a);
    }
    if (sel == BRDF_G_SMITH_BECKMANN) {
        return g_smith_beckmann(n_l, n_v, a);
    }
    return g_schlick_ggx(n_l, n_v, k_punctual(roughness));
}

// spec = F0 (Schlick forms) or η (exact forms); kappa = κ (conductor).
vec3 brdf_fresnel(int sel, vec3 spec, vec3 kappa, float v_h) {
    if (sel == BRDF_F_SCHLICK) {
        return f_schlick(spec, v_h);
    }
    if (sel == BRDF_F_SCHLICK_SG) {
        return f_schlick_sg(spec, v_h);
    }
    if (sel == BRDF_F_DIELECTRIC) {
        return vec3(f_dielectric(v_h, spec.x), f_dielectric(v_h, spec.y), f_dielectric(v_h, spec.z));
    }
    if (sel == BRDF_F_CONDUCTOR_EXACT) {
        return f_conductor_exact(v_h, spec, kappa);
    }
    return f_conductor(v_h, spec, kappa);
}

// Diffuse::factor: the factor on albedo/π, 1 (Lambert) or fd_burley with the perceptual roughness.
// `code` is p0.y (a float 0 or 1).
float brdf_diffuse_factor(float code, float n_l, float n_v, float l_h, float roughness) {
    if (int(code + 0.5) == BRDF_DIFFUSE_BURLEY) {
        return fd_burley(n_l, n_v, l_h, roughness);
    }
    return 1.0;
}

// ior_from_f0 of src/brdf/presets.rs.
float brdf_ior_from_f0(float f0) {
    float s = sqrt(clamp(f0, 0.0, 0.99));
    return (1.0 + s) / (1.0 - s);
}

// Fresnel::inputs_from_f0: F0 for the Schlick forms, η = ior_from_f0(F0) for the exact forms.
vec3 brdf_fresnel_spec_from_f0(int sel, vec3 f0) {
    if (sel == BRDF_F_SCHLICK || sel == BRDF_F_SCHLICK_SG) {
        return f0;
    }
    return vec3(brdf_ior_from_f0(f0.x), brdf_ior_from_f0(f0.y), brdf_ior_from_f0(f0.z));
}

// ------------------------------------------------------------------------------------------------
// Models. Each one: zero when n·l ≤ 0 or n·v ≤ 0; n, l, v normalised first.
// ------------------------------------------------------------------------------------------------

BrdfTerms brdf_lambert_terms(BrdfParams p, vec3 n_in, vec3 l_in, vec3 v_in) {
    vec3 n = brdf_safe_normalize(n_in);
    vec3 l = brdf_safe_normalize(l_in);
    vec3 v = brdf_safe_normalize(v_in);
    BrdfTerms t = brdf_terms_zero();
    if (dot(n, l) <= 0.0 || dot(n, v) <= 0.0) {
        return t;
    }
    t.diffuse = diffuse_lambert(p.color.xyz);
    return t;
}

// max(r·v, 0)^n (Phong) or max(n·h, 0)^n (Blinn-Phong); 0 when the base is ≤ 0.
float brdf_classic_lobe(BrdfParams p, vec3 n, vec3 l, vec3 v) {
    float base;
    if (p.sel.x == BRDF_MODEL_BLINN_PHONG) {
        base = dot(n, brdf_safe_normalize(l + v));
    } else {
        vec3 r = n * (2.0 * dot(n, l)) - l;
        base = dot(r, v);
    }
    if (base <= 0.0) {
        return 0.0;
    }
    return pow(base, p.p0.y);
}

// Phong / Blinn-Phong BRDF equivalent: diffuse k_d O_d, specular k_s O_s lobe / (n·l).
BrdfTerms brdf_phong_terms(BrdfParams p, vec3 n_in, vec3 l_in, vec3 v_in) {
    vec3 n = brdf_safe_normalize(n_in);
    vec3 l = brdf_safe_normalize(l_in);
    vec3 v = brdf_safe_normalize(v_in);
    BrdfTerms t = brdf_terms_zero();
    float n_l_raw = dot(n, l);
    if (n_l_raw <= 0.0 || dot(n, v) <= 0.0) {
        return t;
    }
    float n_l = brdf_clamp_cos(n_l_raw);
    float lobe = brdf_classic_lobe(p, n, l, v);
    t.diffuse = p.color.xyz * p.kappa.w;
    t.specular = p.spec.xyz * (p.p0.x * lobe / n_l);
    return t;
}

// The slides' formula I_L (k_d O_d (n·l) + k_s O_s lobe) with I_L = e_light.
vec3 brdf_phong_radiance(BrdfParams p, vec3 n_in, vec3 l_in, vec3 v_in, vec3 e_light) {
    vec3 n = brdf_safe_normalize(n_in);
    vec3 l = brdf_safe_normalize(l_in);
    vec3 v = brdf_safe_normalize(v_in);
    float n_l_raw = dot(n, l);
    // The slides' model literally: only n·l > 0 is required (see phong_radiance in models.rs).
    if (n_l_raw <= 0.0) {
        return vec3(0.0);
    }
    float lobe = brdf_classic_lobe(p, n, l, v);
    float n_l = min(n_l_raw, 1.0);
    return e_light * (p.color.xyz * (p.kappa.w * n_l) + p.spec.xyz * (p.p0.x * lobe));
}

// Cook-Torrance: k_d color/π + (1 − k_d) D F G / (4 (n·l)(n·v)).
BrdfTerms brdf_cook_torrance_terms(BrdfParams p, vec3 n_in, vec3 l_in, vec3 v_in) {
    vec3 n = brdf_safe_normalize(n_in);
    vec3 l = brdf_safe_normalize(l_in);
    vec3 v = brdf_safe_normalize(v_in);
    BrdfTerms t = brdf_terms_zero();
    float n_l_raw = dot(n, l);
    float n_v_raw = dot(n, v);
    if (n_l_raw <= 0.0 || n_v_raw <= 0.0) {
        return t;
    }
    float n_l = brdf_clamp_cos(n_l_raw);
    float n_v = brdf_clamp_cos(n_v_raw);
    float roughness = p.color.w;
    float kd = p.kappa.w;
    float a = p.sel.y == BRDF_D_BECKMANN ? roughness : roughness * roughness;
    a = max(a, BRDF_ALPHA_MIN);
    vec3 h = brdf_safe_normalize(l + v);
    float n_h = dot(n, h);
    vec3 n_x_h = cross(n, h);
    float sin2_h = dot(n_x_h, n_x_h);
    float v_h = dot(v, h);
    t.d = brdf_distribution(p.sel.y, n_h, sin2_h, a);
    t.g = brdf_geometry(p.sel.z, n_h, n_v, n_l, v_h, a, roughness);
    t.f = brdf_fresnel(p.sel.w, p.spec.xyz, p.kappa.xyz, v_h);
    vec3 spec_brdf = t.f * (t.d * t.g / (4.0 * n_l * n_v));
    // l·h = v·h (h is the half vector).
    t.diffuse = p.color.xyz * (kd * M_1_PI * brdf_diffuse_factor(p.p0.y, n_l, n_v, v_h, roughness));
    t.specular = spec_brdf * (1.0 - kd);
    return t;
}

// The share of metal-rough's diffuse that KHR_materials_transmission and _diffuse_transmission
// leave it: (1 − transmission)(1 − diffuse transmission) (1 for the other models).
float brdf_diffuse_keep(BrdfParams p) {
    return p.sel.x == BRDF_MODEL_METAL_ROUGH ? (1.0 - p.p2.x) * (1.0 - p.p2.y) : 1.0;
}

// KHR_materials_anisotropy's lobe (AnisotropicLobe in src/brdf/models/mod.rs): direction t
// (the frame's x turned by the rotation p1.w towards y), b = n × t, widths α_t = mix(α, 1, s²),
// α_b = α; on = false for an isotropic material or a non-GGX distribution.
struct AnisotropicLobe {
    vec3 t;
    vec3 b;
    float alpha_t;
    float alpha_b;
    bool on;
};

AnisotropicLobe brdf_anisotropic_lobe(BrdfParams p, vec3 n, vec3 x, vec3 y) {
    AnisotropicLobe a;
    a.on = (BRDF_LOBES & BRDF_LOBE_ANISOTROPY) != 0u && p.sel.x == BRDF_MODEL_METAL_ROUGH
        && p.p1.z > 0.0 && p.sel.y == BRDF_D_GGX;
    vec3 tx = brdf_tangent_x(n, x, y);
    vec3 ty = cross(n, tx);
    a.t = brdf_safe_normalize(tx * cos(p.p1.w) + ty * sin(p.p1.w));
    a.b = cross(n, a.t);
    float r = p.color.w;
    a.alpha_b = max(r * r, BRDF_ALPHA_MIN);
    a.alpha_t = a.alpha_b + (1.0 - a.alpha_b) * p.p1.z * p.p1.z;
    return a;
}

// KHR_materials_specular's F90 of the mixed material, mix(p0.z, 1, metallic) (MetalRoughParams::f90).
float brdf_f90(BrdfParams p) {
    return p.sel.x == BRDF_MODEL_METAL_ROUGH ? mix(p.p0.z, 1.0, p.spec.w) : 1.0;
}

// The Schlick forms with F90 in place of 1: F0 + (F − F0)(F90 − F0)/(1 − F0) (with_f90).
vec3 brdf_with_f90(int sel, vec3 f, vec3 f0, float f90) {
    if (sel != BRDF_F_SCHLICK && sel != BRDF_F_SCHLICK_SG) {
        return f;
    }
    vec3 room = vec3(1.0) - f0;
    vec3 g = f0 + (f - f0) * ((vec3(f90) - f0) / max(room, vec3(1e-6)));
    return mix(f, g, greaterThan(room, vec3(1e-6)));
}

// Whether p has KHR_materials_iridescence's film (has_iridescence): factor |p0.w| and thickness
// p2.w above 0.
bool brdf_has_iridescence(BrdfParams p) {
    return (BRDF_LOBES & (BRDF_LOBE_IRIDESCENCE | BRDF_LOBE_IRIDESCENCE_VIEW)) != 0u
        && p.sel.x == BRDF_MODEL_METAL_ROUGH && p.p0.w != 0.0 && p.p2.w > 0.0;
}

// The film's factor, and whether its Fresnel is taken at the view (the factor's sign).
float brdf_film_factor(BrdfParams p) {
    return abs(p.p0.w);
}

bool brdf_film_at_view(BrdfParams p) {
    const uint forms = BRDF_LOBES & (BRDF_LOBE_IRIDESCENCE | BRDF_LOBE_IRIDESCENCE_VIEW);
    if (forms == BRDF_LOBE_IRIDESCENCE_VIEW) {
        return true;
    }
    return forms != BRDF_LOBE_IRIDESCENCE && p.p0.w < 0.0;
}

// p's film and its two bases, the dielectric F0 and the base colour (iridescence_fresnel_of):
// what the film's Fresnel needs whatever the angle.
struct MaterialFilm {
    Film film;
    FilmBase dielectric;
    FilmBase metal;
};

MaterialFilm brdf_material_film(BrdfParams p) {
    MaterialFilm m;
    // The outside is air, or the clear coat's 1.5 mixed by its factor (iridescence_outside_ior).
    float coat = (BRDF_LOBES & BRDF_LOBE_CLEARCOAT) != 0u ? p.p1.x : 0.0;
    m.film = film_of(1.0 + 0.5 * coat, p.p2.z, p.p2.w);
    // Only the bases metallic mixes in (a material's metallic is the same over a draw, so
    // lavapipe skips the side no lane takes).
    float metallic = p.spec.w;
    if (metallic < 1.0) {
        m.dielectric = film_base(m.film, p.spec.rgb);
    }
    if (metallic > 0.0) {
        m.metal = film_base(m.film, p.color.rgb);
    }
    return m;
}

// p's film where the lighting shaders shade a pixel with the film per light
// (BRDF_LOBE_IRIDESCENCE): shade() sets it once for every light and the environment
// (brdf_material_film); elsewhere it is made per call.
MaterialFilm g_material_film;

// The film's Fresnel at cos (iridescence_fresnel_of): over the dielectric F0 and over the base
// colour, mixed by metallic (one base at metallic 0 or 1: the branches are uniform over a
// draw, and lavapipe skips a side no lane takes; always mixing both cost the film at the view
// 1.18 → 1.27× base on grid49).
// p's film for an evaluation here: the pixel's (g_material_film) where each light takes the
// film; the film at the view alone is one evaluation per pixel, made in place.
MaterialFilm brdf_pixel_film(BrdfParams p) {
#ifdef LUZ_FRAGMENT
    return (BRDF_LOBES & BRDF_LOBE_IRIDESCENCE) != 0u ? g_material_film : brdf_material_film(p);
#else
    return brdf_material_film(p);
#endif
}

// brdf_iridescence_fresnel_of with the material's film m made already (iridescence_fresnel_with).
vec3 brdf_iridescence_fresnel_with(BrdfParams p, MaterialFilm m, float c) {
    // Under a coat the film is met at the angle refracted into it (iridescence_cos_above).
    float n0 = m.film.outside_ior;
    float cc = clamp(c, 0.0, 1.0);
    float c_above = n0 > 1.0 ? sqrt(max(1.0 - (1.0 - cc * cc) / (n0 * n0), 0.0)) : c;
    FilmAt f = film_at(m.film, c_above);
    float metallic = p.spec.w;
    if (metallic <= 0.0) {
        return film_over(f, m.dielectric);
    }
    if (metallic >= 1.0) {
        return film_over(f, m.metal);
    }
    return mix(film_over(f, m.dielectric), film_over(f, m.metal), metallic);
}

vec3 brdf_iridescence_fresnel_of(BrdfParams p, float c) {
    return brdf_iridescence_fresnel_with(p, brdf_pixel_film(p), c);
}

// The film's Fresnel at the view, once per pixel, where the pipeline takes it at n·v
// (BRDF_LOBE_IRIDESCENCE_VIEW): shade() sets it before the light loop.
vec3 g_film_view = vec3(0.0);

// The v·h whose Schlick weight is the lobe's mean over a split-sum entry (A, B)
// (split_sum_mean_cos): B / (A + B) = (1 − c)⁵.
float brdf_split_sum_mean_cos(vec2 ab) {
    return 1.0 - pow(clamp(ab.y / max(ab.x + ab.y, 1e-6), 0.0, 1.0), 0.2);
}

// The F0 the split sum and energy compensation take for p over a split-sum entry (A, B, μ, σ)
// (iridescence_f0_lobe): f0, or mixed with the F0 that makes F0·A + B the lobe's mean film
// Fresnel times A + B, that mean taken as the film's Fresnel at the mean Schlick angle c plus
// the film's difference from the Schlick curve through it (reaching the film's own grazing
// value) at μ and μ ± √3 σ, weighted 2/3, 1/6, 1/6. Below 0 where the film stays under
// Schlick's curve (under a coat).
vec3 brdf_iridescence_f0_lobe(BrdfParams p, vec3 f0, vec4 lobe) {
    if (!brdf_has_iridescence(p)) {
        return f0;
    }
    // The film made once for its five evaluations here.
    MaterialFilm m = brdf_pixel_film(p);
    float c = brdf_split_sum_mean_cos(lobe.xy);
    float w = brdf_schlick_weight(clamp(c, 0.0, 1.0));
    float k = 1.0 / max(1.0 - w, 1e-4);
    vec3 f = brdf_iridescence_fresnel_with(p, m, c);
    vec3 f90 = brdf_iridescence_fresnel_with(p, m, 0.0);
    vec3 through = (f - f90 * w) * k;
    float h = sqrt(3.0) * lobe.w;
    vec3 off = vec3(0.0);
    float xs[3] = float[3](lobe.z - h, lobe.z, lobe.z + h);
    float ws[3] = float[3](1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0);
    for (int i = 0; i < 3; ++i) {
        float x = clamp(xs[i], 0.0, 1.0);
        float s = brdf_schlick_weight(x);
        off += ws[i] * (brdf_iridescence_fresnel_with(p, m, x) - (through + (f90 - through) * s));
    }
    vec3 film_f0 = min((f + off - vec3(w)) * k, vec3(1.0));
    return mix(f0, film_f0, brdf_film_factor(p));
}

// p's roughness, or for an anisotropic lobe the roughness of an isotropic lobe of about the same
// albedo, ((α_t² + α_b²)/2)^¼ (AnisotropicLobe::equivalent_roughness): what the energy and
// split-sum tables are indexed by.
float brdf_lobe_roughness(BrdfParams p) {
    AnisotropicLobe a = brdf_anisotropic_lobe(p, vec3(0.0, 0.0, 1.0), vec3(1.0, 0.0, 0.0),
                                              vec3(0.0, 1.0, 0.0));
    return a.on ? sqrt(sqrt(0.5 * (a.alpha_t * a.alpha_t + a.alpha_b * a.alpha_b))) : p.color.w;
}

// glTF metallic-roughness: c_diff/π [1 − F] + D F G / (4 (n·l)(n·v)).
// The metallic-roughness terms without layers, for unit n, l and v (metal_rough_base_terms), with
// the anisotropic lobe `an` replacing D and G when it is on.
BrdfTerms brdf_metal_rough_base_terms_lobe(BrdfParams p, vec3 n, vec3 l, vec3 v, AnisotropicLobe an) {
    BrdfTerms t = brdf_terms_zero();
    float n_l_raw = dot(n, l);
    float n_v_raw = dot(n, v);
    if (n_l_raw <= 0.0 || n_v_raw <= 0.0) {
        return t;
    }
    float n_l = brdf_clamp_cos(n_l_raw);
    float n_v = brdf_clamp_cos(n_v_raw);
    vec3 base = p.color.xyz;
    float roughness = p.color.w;
    float metallic = p.spec.w;
    float a = max(roughness * roughness, BRDF_ALPHA_MIN);
    vec3 f0 = mix(p.spec.rgb, base, metallic);  // spec.rgb: the dielectric F0 (0.04)
    // KHR_materials_transmission and _diffuse_transmission take their shares of the diffuse.
    vec3 c_diff = base * ((1.0 - metallic) * (1.0 - p.p2.x) * (1.0 - p.p2.y));
    vec3 spec = brdf_fresnel_spec_from_f0(p.sel.w, f0);
    vec3 h = brdf_safe_normalize(l + v);
    float n_h = dot(n, h);
    vec3 n_x_h = cross(n, h);
    float sin2_h = dot(n_x_h, n_x_h);
    float v_h = dot(v, h);
    if (an.on) {
        t.d = d_gtr2_aniso(n_h, dot(an.t, h), dot(an.b, h), an.alpha_t, an.alpha_b);
        t.g = g_smith_ggx_correlated_aniso(n_l, n_v, dot(an.t, l), dot(an.b, l), dot(an.t, v),
                                           dot(an.b, v), an.alpha_t, an.alpha_b);
    } else {
        t.d = brdf_distribution(p.sel.y, n_h, sin2_h, a);
        t.g = brdf_geometry(p.sel.z, n_h, n_v, n_l, v_h, a, roughness);
    }
    t.f = brdf_fresnel(p.sel.w, spec, vec3(0.0), v_h);
    float f90 = brdf_f90(p);
    if (f90 < 1.0) {
        t.f = brdf_with_f90(p.sel.w, t.f, f0, f90);
    }
    if (brdf_has_iridescence(p)) {
        vec3 film;
        if (brdf_film_at_view(p)) {
#ifdef LUZ_FRAGMENT
            film = g_film_view;
#else
            film = brdf_iridescence_fresnel_of(p, n_v);
#endif
        } else {
            film = brdf_iridescence_fresnel_of(p, v_h);
        }
        t.f = mix(t.f, film, brdf_film_factor(p));
    }
    vec3 weight = p.p0.x != 0.0 ? vec3(1.0) - t.f : vec3(1.0);
    t.diffuse = c_diff * M_1_PI * brdf_diffuse_factor(p.p0.y, n_l, n_v, v_h, roughness) * weight;
    t.specular = t.f * (t.d * t.g / (4.0 * n_l * n_v));
    return t;
}

// The clear coat's normal where the lighting shaders shade a pixel (shade() sets g_coat_n: the
// geometric normal, or the coat's normal map's); elsewhere the shading normal n.
vec3 g_coat_n = vec3(0.0, 0.0, 1.0);

vec3 brdf_coat_normal(vec3 n) {
#ifdef LUZ_FRAGMENT
    return g_coat_n;
#else
    return n;
#endif
}

// KHR_materials_clearcoat (src/brdf/models/layers.rs): F0 of the coat, what it takes from the base and
// gives its lobe at one view (albedo: the base is weighted by 1 − clearcoat · albedo; specular:
// multiplies the coat's lobe), the extension's own Schlick form of it.
#define CLEARCOAT_F0 0.04
struct ClearcoatEnergy {
    float albedo;
    float specular;
};

ClearcoatEnergy clearcoat_energy_schlick(float n_v) {
    ClearcoatEnergy e;
    e.albedo = CLEARCOAT_F0 + (1.0 - CLEARCOAT_F0) * brdf_schlick_weight(n_v);
    e.specular = 1.0;
    return e;
}

// The coat's lobe D G F / (4 (n·l)(n·v)) for unit n (the coat normal), l and v with n·l > 0 and
// n·v > 0: the material's D and G at the width clearcoat_roughness², Schlick's F of F0 0.04.
float clearcoat_specular(BrdfParams p, vec3 n, vec3 l, vec3 v) {
    float n_l = brdf_clamp_cos(dot(n, l));
    float n_v = brdf_clamp_cos(dot(n, v));
    float r = p.p1.y;
    float a = max(r * r, BRDF_ALPHA_MIN);
    vec3 h = brdf_safe_normalize(l + v);
    float n_h = dot(n, h);
    vec3 n_x_h = cross(n, h);
    float sin2_h = dot(n_x_h, n_x_h);
    float v_h = dot(v, h);
    float d = brdf_distribution(p.sel.y, n_h, sin2_h, a);
    float g = brdf_geometry(p.sel.z, n_h, n_v, n_l, v_h, a, r);
    float f = CLEARCOAT_F0 + (1.0 - CLEARCOAT_F0) * brdf_schlick_weight(v_h);
    return f * (d * g / (4.0 * n_l * n_v));
}

// The base's terms t under the coat of p: weighted by 1 − clearcoat · e.albedo, plus
// clearcoat · e.specular · clearcoat_specular · (n_c·l)/(n·l) in the specular, at the coat's
// normal n_c (brdf_coat_normal; the ratio turns the caller's cosine into the coat's). n·l > 0.
BrdfTerms clearcoat_layer(BrdfTerms t, BrdfParams p, vec3 n, vec3 l, vec3 v, ClearcoatEnergy e) {
    float keep = 1.0 - p.p1.x * e.albedo;
    vec3 nc = brdf_coat_normal(n);
    float nc_l = dot(nc, l);
    float coat = nc_l > 0.0 && dot(nc, v) > 0.0
        ? p.p1.x * e.specular * clearcoat_specular(p, nc, l, v) * (nc_l / dot(n, l)) : 0.0;
    t.diffuse *= keep;
    t.specular = t.specular * keep + vec3(coat);
    return t;
}

// KHR_materials_sheen (src/brdf/models/layers.rs): the Charlie distribution, the specification's
// visibility term, and the lobe's directional albedo from the fit of sheen_albedo.glsl; the
// base is weighted by 1 − max(sheenColor) · E_sheen(n·v), the sheen goes in the diffuse.
#define SHEEN_ROUGHNESS_MIN 0.07

float sheen_alpha(float sheen_roughness) {
    float r = max(sheen_roughness, SHEEN_ROUGHNESS_MIN);
    return r * r;
}

float d_charlie(float alpha, float sin2_h) {
    float inv_r = 1.0 / alpha;
    return (2.0 + inv_r) * pow(max(sin2_h, 0.0), 0.5 * inv_r) * (0.5 * M_1_PI);
}

// Λ_sheen from a polynomial (layers::sheen_lambda_fit, layers::lambda_sheen_of; the exact
// lambda_sheen of layers.rs is the reference; docs/brdf.md, "`BrdfParams`", the sheen):
// log2 Λ = P(q) below cos θ = 0.5 and 2 P(1) − P(q) above, P of degree 6 in
// q = w^(1/8) · SHEEN_LAMBDA_Q_SCALE + SHEEN_LAMBDA_Q_OFFSET (w = min(cos θ, 1 − cos θ) clamped
// to [SHEEN_LAMBDA_W_MIN, 0.5]; q = 1 at w = 0.5), its seven coefficients cubics in
// 2 (1 − α)² − 1, made once per pixel (sheen_lambda_fit). Three square roots, six multiply-adds
// and an exp2 per call, instead of the specification's fit's pow, division and exp. The
// constants: sheen_lambda.glsl, written by the Rust generator.

struct SheenFit {
    float c0;
    float c1;
    float c2;
    float c3;
    float c4;
    float c5;
    float c6;
    float l_half;
};

#define SHEEN_LAMBDA_CUBIC(j, s) \
    (((SHEEN_LAMBDA_FIT[4 * j + 3] * s + SHEEN_LAMBDA_FIT[4 * j + 2]) * s \
      + SHEEN_LAMBDA_FIT[4 * j + 1]) * s + SHEEN_LAMBDA_FIT[4 * j])

SheenFit sheen_lambda_fit(float alpha) {
    float s = 2.0 * (1.0 - alpha) * (1.0 - alpha) - 1.0;
    SheenFit f;
    f.c0 = SHEEN_LAMBDA_CUBIC(0, s);
    f.c1 = SHEEN_LAMBDA_CUBIC(1, s);
    f.c2 = SHEEN_LAMBDA_CUBIC(2, s);
    f.c3 = SHEEN_LAMBDA_CUBIC(3, s);
    f.c4 = SHEEN_LAMBDA_CUBIC(4, s);
    f.c5 = SHEEN_LAMBDA_CUBIC(5, s);
    f.c6 = SHEEN_LAMBDA_CUBIC(6, s);
    f.l_half = f.c0 + f.c1 + f.c2 + f.c3 + f.c4 + f.c5 + f.c6;
    return f;
}

// One polynomial per call: both sides of a branch would run under the lane mask, so the branch
// picks the exponent's sign instead. (No GLSL lambda_sheen: the Rust one is the specification's
// exact Λ, which this approximates.)
float lambda_sheen_of(float cos_theta, SheenFit f) {
    bool low = cos_theta < 0.5;
    float w = clamp(min(cos_theta, 1.0 - cos_theta), SHEEN_LAMBDA_W_MIN, 0.5);
    float q = sqrt(sqrt(sqrt(w))) * SHEEN_LAMBDA_Q_SCALE + SHEEN_LAMBDA_Q_OFFSET;
    float p = ((((((f.c6 * q + f.c5) * q + f.c4) * q + f.c3) * q + f.c2) * q + f.c1) * q + f.c0);
    return exp2(low ? p : 2.0 * f.l_half - p);
}

// Per pixel: Λ_sheen at the view and the fit at the sheen's alpha. The lighting shaders'
// shade() sets them for its one (n, v, sheen roughness) before anything evaluates the sheen,
// and every fragment-stage sheen reads them; elsewhere (brdf_eval.comp) both are computed per
// call. The same values either way. (A run-time choice between the two would cost both under
// lavapipe's lane mask: the fit's seven cubics, and Λ(n·v)'s polynomial and exp2, per light.)
float g_sheen_lambda_v = -1.0;
SheenFit g_sheen_fit;
// Per pixel too (fragment stage, shade(): sheen_view): D_Charlie's factor (2 + 1/α)/(2π) and
// exponent 1/(2α), and 4 n·v, so that a light's lobe reads them instead of computing them.
float g_sheen_d_scale;
float g_sheen_d_exp;
float g_sheen_nv4;

float v_sheen(float n_l, float n_v, float alpha) {
#ifdef LUZ_FRAGMENT
    SheenFit f = g_sheen_fit;
    float lambda_v = g_sheen_lambda_v;
#else
    SheenFit f = sheen_lambda_fit(alpha);
    float lambda_v = lambda_sheen_of(n_v, f);
#endif
    float denom = (1.0 + lambda_v + lambda_sheen_of(n_l, f)) * (4.0 * n_v * n_l);
    return clamp(1.0 / denom, 0.0, 1.0);
}

// The sheen's values at one pixel that no light changes (the g_sheen_* above), for sheen
// roughness r and n·v (clamped): shade() calls it once, before anything evaluates the sheen.
void sheen_view(float r, float n_v) {
    float alpha = sheen_alpha(r);
    float inv_r = 1.0 / alpha;
    g_sheen_fit = sheen_lambda_fit(alpha);
    g_sheen_lambda_v = lambda_sheen_of(n_v, g_sheen_fit);
    g_sheen_d_scale = (2.0 + inv_r) * (0.5 * M_1_PI);
    g_sheen_d_exp = 0.5 * inv_r;
    g_sheen_nv4 = 4.0 * n_v;
}

// The white sheen lobe D_Charlie · V_sheen for unit n, l and v with n·l > 0 and n·v > 0.
float sheen_specular(float r, vec3 n, vec3 l, vec3 v) {
    vec3 h = brdf_safe_normalize(l + v);
    vec3 n_x_h = cross(n, h);
    float sin2_h = dot(n_x_h, n_x_h);
    float n_l = brdf_clamp_cos(dot(n, l));
#ifdef LUZ_FRAGMENT
    // d_charlie · v_sheen from the pixel's values (sheen_view), in one division:
    // clamp(1/denom, 0, 1) = 1/max(denom, 1), denom > 0.
    float denom = (1.0 + g_sheen_lambda_v + lambda_sheen_of(n_l, g_sheen_fit))
        * (g_sheen_nv4 * n_l);
    return g_sheen_d_scale * pow(max(sin2_h, 0.0), g_sheen_d_exp) / max(denom, 1.0);
#else
    float alpha = sheen_alpha(r);
    return d_charlie(alpha, sin2_h) * v_sheen(n_l, brdf_clamp_cos(dot(n, v)), alpha);
#endif
}

// E_sheen(n·v) at sheen roughness r: the fit of sheen_albedo.glsl at its variables
// (layers::sheen_albedo, layers::sheen_fit_variables).
float sheen_albedo(float n_v, float r) {
    float s = log(clamp(r, SHEEN_ROUGHNESS_MIN, 1.0));
    return sheen_albedo_fit(2.0 * sqrt(clamp(n_v, 0.0, 1.0)) - 1.0,
                            1.0 - 2.0 * s / log(SHEEN_ROUGHNESS_MIN));
}

// The base's terms t under the sheen of p (kappa: sheen colour, sheen roughness).
BrdfTerms sheen_layer(BrdfTerms t, BrdfParams p, vec3 n, vec3 l, vec3 v, float e_sheen) {
    vec3 color = p.kappa.rgb;
    // At least 0: E_sheen exceeds 1 near grazing for a smooth sheen (layers::sheen_layer).
    float keep = max(1.0 - max(color.r, max(color.g, color.b)) * e_sheen, 0.0);
    t.diffuse = t.diffuse * keep + color * sheen_specular(p.kappa.w, n, l, v);
    t.specular *= keep;
    return t;
}

// Whether p has a sheen (metal-rough only: kappa is other models' κ).
bool has_sheen(BrdfParams p) {
    return (BRDF_LOBES & BRDF_LOBE_SHEEN) != 0u && p.sel.x == BRDF_MODEL_METAL_ROUGH
        && any(greaterThan(p.kappa.rgb, vec3(0.0)));
}

// E_sheen at the view for p's sheen (0 without one): what brdf_metal_rough_terms_unit_es takes,
// so that a loop over lights evaluates the fit once per pixel, not once per light.
float brdf_sheen_albedo_at(BrdfParams p, vec3 n, vec3 v) {
    return has_sheen(p) ? sheen_albedo(brdf_clamp_cos(dot(n, v)), p.kappa.w) : 0.0;
}

// metal_rough_terms for unit n, l and v (no renormalisation), E_sheen(n·v) given: the base,
// then its layers.
BrdfTerms brdf_metal_rough_terms_lobe_es(BrdfParams p, vec3 n, vec3 l, vec3 v, AnisotropicLobe an,
                                         float e_sheen) {
    BrdfTerms t = brdf_metal_rough_base_terms_lobe(p, n, l, v, an);
#ifdef LUZ_FRAGMENT
    // In the lighting shaders without the per-pixel branch on n·l and n·v (lavapipe runs its
    // code under the lane mask anyway): the layer everywhere, kept where both are positive
    // (the same values up to rounding: the layer is finite, and mix by 0 or 1 picks one side;
    // docs/performance.md, "Where the sheen's cost is").
    if (has_sheen(p)) {
        float on = dot(n, l) > 0.0 && dot(n, v) > 0.0 ? 1.0 : 0.0;
        BrdfTerms s = sheen_layer(t, p, n, l, v, e_sheen);
        t.diffuse = mix(t.diffuse, s.diffuse, on);
        t.specular = mix(t.specular, s.specular, on);
    }
#else
    if (has_sheen(p) && dot(n, l) > 0.0 && dot(n, v) > 0.0) {
        t = sheen_layer(t, p, n, l, v, e_sheen);
    }
#endif
    if ((BRDF_LOBES & BRDF_LOBE_CLEARCOAT) != 0u && dot(n, l) > 0.0 && dot(n, v) > 0.0) {
        t = clearcoat_layer(t, p, n, l, v,
                            clearcoat_energy_schlick(brdf_clamp_cos(dot(brdf_coat_normal(n), v))));
    }
    return t;
}

// metal_rough_terms_frame for unit n, l and v (no renormalisation) and tangent frame (x, y).
BrdfTerms brdf_metal_rough_terms_unit(BrdfParams p, vec3 n, vec3 l, vec3 v, vec3 x, vec3 y) {
    return brdf_metal_rough_terms_lobe_es(p, n, l, v, brdf_anisotropic_lobe(p, n, x, y),
                                          brdf_sheen_albedo_at(p, n, v));
}

BrdfTerms brdf_metal_rough_terms(BrdfParams p, vec3 n_in, vec3 l_in, vec3 v_in, vec3 x, vec3 y) {
    return brdf_metal_rough_terms_unit(
        p, brdf_safe_normalize(n_in), brdf_safe_normalize(l_in), brdf_safe_normalize(v_in), x, y);
}

// Disney Principled, exactly as BRDF Explorer's disney.brdf (MODELS.md §5).
BrdfTerms brdf_principled_terms(BrdfParams p, vec3 n_in, vec3 l_in, vec3 v_in, vec3 x_in, vec3 y_in) {
    vec3 n = brdf_safe_normalize(n_in);
    vec3 l = brdf_safe_normalize(l_in);
    vec3 v = brdf_safe_normalize(v_in);
    BrdfTerms t = brdf_terms_zero();
    float n_l_raw = dot(n, l);
    float n_v_raw = dot(n, v);
    if (n_l_raw <= 0.0 || n_v_raw <= 0.0) {
        return t;
    }
    float n_l = brdf_clamp_cos(n_l_raw);
    float n_v = brdf_clamp_cos(n_v_raw);
    vec3 tx = brdf_tangent_x(n, x_in, y_in);
    vec3 ty = cross(n, tx);
    vec3 h = brdf_safe_normalize(l + v);
    float n_h = dot(n, h);
    vec3 n_x_h = cross(n, h);
    float sin2_h = dot(n_x_h, n_x_h);
    float l_h = dot(l, h);

    vec3 cdlin = p.color.xyz;
    float roughness = p.color.w;
    float metallic = p.spec.w;
    float subsurface = p.p0.x;
    float specular = p.p0.y;
    float specular_tint = p.p0.z;
    float anisotropic = p.p0.w;
    float sheen = p.p1.x;
    float sheen_tint = p.p1.y;
    float clearcoat = p.p1.z;
    float clearcoat_gloss = p.p1.w;

    float cdlum = 0.3 * cdlin.x + 0.6 * cdlin.y + 0.1 * cdlin.z;
    vec3 ctint = cdlum > 0.0 ? cdlin / cdlum : vec3(1.0);
    vec3 cspec0 = mix(mix(vec3(1.0), ctint, specular_tint) * (specular * 0.08), cdlin, metallic);
    vec3 csheen = mix(vec3(1.0), ctint, sheen_tint);

    float fd = fd_burley(n_l, n_v, l_h, roughness);
    float ss = ss_hanrahan_krueger(n_l, n_v, l_h, roughness);

    float aspect = sqrt(1.0 - anisotropic * 0.9);
    float r2 = roughness * roughness;
    float ax = max(r2 / aspect, BRDF_ALPHA_MIN);
    float ay = max(r2 * aspect, BRDF_ALPHA_MIN);
    float ds = d_gtr2_aniso(n_h, dot(h, tx), dot(h, ty), ax, ay);
    float fh = brdf_schlick_weight(l_h);
    vec3 fs = mix(cspec0, vec3(1.0), fh);
    float gs = vis_smith_ggx_aniso(n_l, dot(l, tx), dot(l, ty), ax, ay)
             * vis_smith_ggx_aniso(n_v, dot(v, tx), dot(v, ty), ax, ay);

    vec3 fsheen = csheen * (fh * sheen);

    float dr = d_gtr1_sin2(n_h, sin2_h, mix(0.1, 0.001, clearcoat_gloss));
    float fr = mix(0.04, 1.0, fh);
    float gr = vis_smith_ggx_iso(n_l, 0.25) * vis_smith_ggx_iso(n_v, 0.25);

    t.d = ds;
    t.g = gs * 4.0 * n_l * n_v;
    t.f = fs;
    t.diffuse = (cdlin * (M_1_PI * mix(fd, ss, subsurface)) + fsheen) * (1.0 - metallic);
    t.specular = fs * (gs * ds) + vec3(0.25 * clearcoat * gr * fr * dr);
    return t;
}

// Qualitative Oren-Nayar, σ (radians) in p0.x.
BrdfTerms brdf_oren_nayar_terms(BrdfParams p, vec3 n_in, vec3 l_in, vec3 v_in) {
    vec3 n = brdf_safe_normalize(n_in);
    vec3 l = brdf_safe_normalize(l_in);
    vec3 v = brdf_safe_normalize(v_in);
    BrdfTerms t = brdf_terms_zero();
    float n_l_raw = dot(n, l);
    float n_v_raw = dot(n, v);
    if (n_l_raw <= 0.0 || n_v_raw <= 0.0) {
        return t;
    }
    float n_l = brdf_clamp_cos(n_l_raw);
    float n_v = brdf_clamp_cos(n_v_raw);
    float cos_phi = cos_phi_diff(n, l, v);
    t.diffuse = diffuse_oren_nayar(p.color.xyz, p.p0.x, n_l, n_v, cos_phi);
    return t;
}

// ------------------------------------------------------------------------------------------------
// Dispatch
// ------------------------------------------------------------------------------------------------

BrdfTerms brdf_eval_terms(BrdfParams p, vec3 n, vec3 l, vec3 v, vec3 x, vec3 y) {
    int m = p.sel.x;
    if (m == BRDF_MODEL_LAMBERT) {
        return brdf_lambert_terms(p, n, l, v);
    }
    if (m == BRDF_MODEL_PHONG || m == BRDF_MODEL_BLINN_PHONG) {
        return brdf_phong_terms(p, n, l, v);
    }
    if (m == BRDF_MODEL_COOK_TORRANCE) {
        return brdf_cook_torrance_terms(p, n, l, v);
    }
    if (m == BRDF_MODEL_METAL_ROUGH) {
        return brdf_metal_rough_terms(p, n, l, v, x, y);
    }
    if (m == BRDF_MODEL_PRINCIPLED) {
        return brdf_principled_terms(p, n, l, v, x, y);
    }
    if (m == BRDF_MODEL_OREN_NAYAR) {
        return brdf_oren_nayar_terms(p, n, l, v);
    }
    return brdf_terms_zero();
}

// The BRDF value f(l, v), not multiplied by n·l.
vec3 brdf_eval(BrdfParams p, vec3 n, vec3 l, vec3 v, vec3 x, vec3 y) {
    BrdfTerms t = brdf_eval_terms(p, n, l, v, x, y);
    return t.diffuse + t.specular;
}

// Reflected radiance from one light of irradiance e_light: f E max(n·l, 0); for Phong and
// Blinn-Phong the slides' formula with I_L = e_light.
vec3 brdf_radiance(BrdfParams p, vec3 n, vec3 l, vec3 v, vec3 x, vec3 y, vec3 e_light) {
    if (p.sel.x == BRDF_MODEL_PHONG || p.sel.x == BRDF_MODEL_BLINN_PHONG) {
        return brdf_phong_radiance(p, n, l, v, e_light);
    }
    float n_l = clamp(dot(brdf_safe_normalize(n), brdf_safe_normalize(l)), 0.0, 1.0);
    return brdf_eval(p, n, l, v, x, y) * e_light * n_l;
}

// brdf_radiance for unit n, l and v, as the renderer's shade() has them (n and v normalised once
// per fragment, l once per light): the metallic-roughness model skips the five renormalisations
// brdf_radiance and its terms make per light; the values differ by rounding only (the GPU-vs-CPU
// tests bound both paths).
vec3 brdf_radiance_unit(BrdfParams p, vec3 n, vec3 l, vec3 v, vec3 x, vec3 y, vec3 e_light) {
    if (p.sel.x == BRDF_MODEL_METAL_ROUGH) {
        BrdfTerms t = brdf_metal_rough_terms_unit(p, n, l, v, x, y);
        return (t.diffuse + t.specular) * e_light * clamp(dot(n, l), 0.0, 1.0);
    }
    return brdf_radiance(p, n, l, v, x, y, e_light);
}

#endif // LUZ_BRDF_MODELS_GLSL
