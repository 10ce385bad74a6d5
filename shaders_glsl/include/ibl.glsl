// Image-based lighting in the forward pass (MODELS.md §7): set 1 bindings and the diffuse and
// specular environment terms, split sum or importance sampled. Included when IBL is defined.
#ifndef LUZ_IBL_GLSL
#define LUZ_IBL_GLSL

#include "env.glsl"
#include "../brdf/sampling.glsl"

#define SET_ENV 1
// Bindings 0..3: the cubes and the LUT (src/render/ibl.rs binds them in this order).
#define BINDING_ENV_CUBE 0
#define BINDING_IRRADIANCE_CUBE 1
#define BINDING_PREFILTERED_CUBE 2
#define BINDING_BRDF_LUT 3
#define BINDING_ENV_DATA 4
layout(set = SET_ENV, binding = BINDING_ENV_CUBE) uniform samplerCube env_cube;
layout(set = SET_ENV, binding = BINDING_IRRADIANCE_CUBE) uniform samplerCube irradiance_cube;
layout(set = SET_ENV, binding = BINDING_PREFILTERED_CUBE) uniform samplerCube prefiltered_cube;
layout(set = SET_ENV, binding = BINDING_BRDF_LUT) uniform sampler2DArray brdf_lut;
layout(set = SET_ENV, binding = BINDING_ENV_DATA, std140) uniform EnvData {
    vec4 sh[9];      // convolved irradiance SH: E(n) = Σ sh[i] Y_i(n)
    vec4 rotation;   // cos θ, sin θ (about +y), environment cube size, its mip count
    vec4 params;     // prefiltered mips, first LUT layers: fitted lobes, anisotropic split sum
} env;

// Specialization constants 2..5 (src/render/gpu.rs: SPEC_*).
#define SPECULAR_SPLIT_SUM 0
#define SPECULAR_IMPORTANCE 1
#define SPECULAR_FITTED_LOBES 2
layout(constant_id = 2) const int SPECULAR_METHOD = SPECULAR_SPLIT_SUM;
layout(constant_id = 3) const bool DIFFUSE_FROM_SH = true;
layout(constant_id = 4) const bool ENERGY_COMPENSATION = false;
layout(constant_id = 5) const uint IBL_SAMPLES = 64u;
layout(constant_id = 6) const bool MIP_FILTERED_SAMPLES = true;

// Irradiance E(n) from the 9 SH coefficients (Ramamoorthi-Hanrahan), evaluated in the
// environment's own frame (the coefficients were projected before rotation).
vec3 sh_irradiance(vec3 n_world) {
    float c = env.rotation.x;
    float s = env.rotation.y;
    vec3 n = vec3(c * n_world.x - s * n_world.z, n_world.y, s * n_world.x + c * n_world.z);
    vec3 e = env.sh[0].rgb * 0.282095;
    e += env.sh[1].rgb * (0.488603 * n.y);
    e += env.sh[2].rgb * (0.488603 * n.z);
    e += env.sh[3].rgb * (0.488603 * n.x);
    e += env.sh[4].rgb * (1.092548 * n.x * n.y);
    e += env.sh[5].rgb * (1.092548 * n.y * n.z);
    e += env.sh[6].rgb * (0.315392 * (3.0 * n.z * n.z - 1.0));
    e += env.sh[7].rgb * (1.092548 * n.x * n.z);
    e += env.sh[8].rgb * (0.546274 * (n.x * n.x - n.y * n.y));
    return max(e, vec3(0.0));
}

vec3 env_irradiance(vec3 n) {
    if (DIFFUSE_FROM_SH) {
        return sh_irradiance(n);
    }
    return textureLod(irradiance_cube, n, 0.0).rgb;
}

// What the split sum needs of a material: F0, the GGX roughness its lobe corresponds to, the weight
// of its specular lobe; `ok` is false for models without a microfacet lobe.
struct SplitSumInputs {
    vec3 f0;
    float f90;
    float roughness;
    float weight;
    bool ok;
};

float f0_from_eta(float eta) {
    float r = (eta - 1.0) / (eta + 1.0);
    return r * r;
}

SplitSumInputs split_sum_inputs(BrdfParams p) {
    SplitSumInputs s;
    s.ok = true;
    s.weight = 1.0;
    s.f90 = brdf_f90(p);
    s.roughness = p.color.w;
    if (MODEL == BRDF_MODEL_METAL_ROUGH) {
        s.f0 = mix(p.spec.rgb, p.color.rgb, p.spec.w);
        s.roughness = brdf_lobe_roughness(p);
        // s.f0 is mixed with the film's at n·v by ibl_shade (it needs the view).
        if (p.sel.y == BRDF_D_BECKMANN) {
            // Beckmann m = roughness² here; GGX with α = m has a similar width.
            s.roughness = p.color.w;
        }
    } else if (MODEL == BRDF_MODEL_COOK_TORRANCE) {
        if (p.sel.w == BRDF_F_SCHLICK || p.sel.w == BRDF_F_SCHLICK_SG) {
            s.f0 = p.spec.rgb;
        } else if (p.sel.w == BRDF_F_DIELECTRIC) {
            s.f0 = vec3(f0_from_eta(p.spec.x), f0_from_eta(p.spec.y), f0_from_eta(p.spec.z));
        } else {
            vec3 eta = p.spec.rgb;
            vec3 k2 = p.kappa.rgb * p.kappa.rgb;
            s.f0 = ((eta - 1.0) * (eta - 1.0) + k2) / ((eta + 1.0) * (eta + 1.0) + k2);
        }
        s.weight = 1.0 - p.kappa.w;
        if (p.sel.y == BRDF_D_BECKMANN) {
            // Beckmann m = roughness; the GGX lobe of α = m is indexed by roughness = sqrt(m).
            s.roughness = sqrt(p.color.w);
        }
    } else if (MODEL == BRDF_MODEL_PRINCIPLED) {
        vec3 base = p.color.rgb;
        float lum = 0.3 * base.r + 0.6 * base.g + 0.1 * base.b;
        vec3 tint = lum > 0.0 ? base / lum : vec3(1.0);
        s.f0 = mix(p.p0.y * 0.08 * mix(vec3(1.0), tint, p.p0.z), base, p.spec.w);
    } else {
        s.ok = false;
        s.f0 = vec3(0.0);
    }
    return s;
}

// Diffuse albedo seen by the irradiance (the BRDF's diffuse part × π, Lambert-like).
vec3 ibl_diffuse_albedo(BrdfParams p) {
    if (MODEL == BRDF_MODEL_PHONG || MODEL == BRDF_MODEL_BLINN_PHONG) {
        return p.kappa.w * p.color.rgb * M_PI;  // the slides' k_d O_d with no 1/π: E k_d O_d
    }
    if (MODEL == BRDF_MODEL_COOK_TORRANCE) {
        return p.kappa.w * p.color.rgb;
    }
    if (MODEL == BRDF_MODEL_METAL_ROUGH) {
        return (1.0 - p.spec.w) * brdf_diffuse_keep(p) * p.color.rgb;
    }
    if (MODEL == BRDF_MODEL_PRINCIPLED) {
        return (1.0 - p.spec.w) * p.color.rgb;
    }
    return p.color.rgb;
}

// Specular radiance from the environment by importance sampling the GGX lobe of the material's
// width, each sample weighted by the material's full specular BRDF (any model, any lobe).
vec3 ibl_specular_importance(BrdfParams p, vec3 n, vec3 v, vec3 x, vec3 y, float roughness) {
    float alpha = max(roughness * roughness, BRDF_ALPHA_MIN);
    vec3 t;
    vec3 b;
    basis(n, t, b);
    vec3 sum = vec3(0.0);
    uint size = uint(env.rotation.z);
    for (uint i = 0u; i < IBL_SAMPLES; ++i) {
        vec2 u = hammersley(i, IBL_SAMPLES);
        vec3 hs = importance_sample_ggx(u.x, u.y, alpha);
        vec3 h = hs.x * t + hs.y * b + hs.z * n;
        float v_h = dot(v, h);
        if (v_h <= 0.0) {
            continue;
        }
        vec3 l = 2.0 * v_h * h - v;
        float n_l = dot(n, l);
        if (n_l <= 0.0) {
            continue;
        }
        float pdf = d_ggx(hs.z, alpha) * hs.z / (4.0 * v_h);
        float lod = MIP_FILTERED_SAMPLES ? pdf_lod(pdf, IBL_SAMPLES, size) : 0.0;
        vec3 L = textureLod(env_cube, l, lod).rgb;
        vec3 f = brdf_eval_terms(p, n, l, v, x, y).specular;
        sum += L * f * (n_l / max(pdf, 1e-8));
    }
    return sum / float(IBL_SAMPLES);
}

// Energy compensation of the metal-rough model (brdf::energy, energy_scale): the specular lobe
// scaled by 1 + F0 (1 − E)/E (Fdez-Agüera 2019), the diffuse by 1 − E_ms, what the specular
// leaves (1 with diffuse_fresnel_weight, which already weights it per direction). The same
// factors multiply every light's terms (lighting.glsl) and the environment's.
// `coat`: KHR_materials_clearcoat's coat at the view (brdf::layers: the extension's Schlick
// weight, or with compensation the coat's compensated albedo and lobe factor).
// `sheen`: KHR_materials_sheen's albedo E_sheen at the view (sheen_albedo), 0 without a sheen.
struct EnergyScale {
    vec3 specular;
    vec3 diffuse;
    ClearcoatEnergy coat;
    float sheen;
};

// The texture coordinates at which the split-sum table holds (n·v, roughness): its texel i holds
// i/(size − 1), 0 and 1 included (brdf::lut_uv, brdf::lut_node).
vec2 lut_uv(float n_v, float roughness) {
    float n = float(textureSize(brdf_lut, 0).x);
    return (clamp(vec2(n_v, roughness), 0.0, 1.0) * (n - 1.0) + 0.5) / n;
}

// The split-sum table's entry (A, B, μ, σ) at (n·v, roughness) in the material's layer
// (split_sum_lobe).
vec4 brdf_lut_lobe(float n_v, float roughness) {
    return textureLod(brdf_lut, vec3(lut_uv(n_v, roughness), float(material.flags)), 0.0);
}

// Its (A, B).
vec2 brdf_lut_ab(float n_v, float roughness) {
    return brdf_lut_lobe(n_v, roughness).rg;
}

// KHR_materials_anisotropy's split sum (brdf::aniso_split_sum_ab): the lobe's (A, B) over
// (sqrt(n·v), roughness, 1 − cos φ, strength), φ the view's azimuth from the lobe's direction
// folded into [0, π/2], every grid holding its ends; slices k (azimuth) and m (strength) of
// ANISO_LUT_NV × ANISO_LUT_ROUGHNESS entries, two per texel (RG, BA), tiled into the LUT's
// layers from env.params.z (brdf::aniso_lut_tiles). The filter is bilinear within a slice,
// linear across slices here. Read only by pipelines with the anisotropy lobe and compensation.
#define ANISO_LUT_NV 32
#define ANISO_LUT_ROUGHNESS 32
#define ANISO_LUT_PHI 6
#define ANISO_LUT_STRENGTH 16

vec2 aniso_lut_slice(int k, int m, vec2 uv) {
    int q = m * ANISO_LUT_PHI + k;
    int tile = q / 2;
    int size = textureSize(brdf_lut, 0).x;
    int per_row = max(size / ANISO_LUT_NV, 1);
    int per_layer = per_row * per_row;
    int t = tile % per_layer;
    vec2 corner = vec2(float((t % per_row) * ANISO_LUT_NV),
                       float((t / per_row) * ANISO_LUT_ROUGHNESS));
    vec2 span = vec2(float(ANISO_LUT_NV - 1), float(ANISO_LUT_ROUGHNESS - 1));
    vec2 texel = corner + 0.5 + uv * span;
    vec4 c = textureLod(brdf_lut, vec3(texel / float(size), env.params.z + float(tile / per_layer)),
                        0.0);
    return (q & 1) == 0 ? c.rg : c.ba;
}

vec2 aniso_split_sum_ab(AnisotropicLobe a, float n_v, vec3 v, float roughness, float strength) {
    float x = abs(dot(a.t, v));
    float y = abs(dot(a.b, v));
    float c = x + y > 0.0 ? x / length(vec2(x, y)) : 1.0;
    vec2 uv = clamp(vec2(sqrt(n_v), roughness), 0.0, 1.0);
    float fk = clamp(1.0 - c, 0.0, 1.0) * float(ANISO_LUT_PHI - 1);
    int k = min(int(fk), ANISO_LUT_PHI - 2);
    fk -= float(k);
    float fm = clamp(strength, 0.0, 1.0) * float(ANISO_LUT_STRENGTH - 1);
    int m = min(int(fm), ANISO_LUT_STRENGTH - 2);
    fm -= float(m);
    return mix(mix(aniso_lut_slice(k, m, uv), aniso_lut_slice(k + 1, m, uv), fk),
               mix(aniso_lut_slice(k, m + 1, uv), aniso_lut_slice(k + 1, m + 1, uv), fk), fm);
}

// The split-sum entry (A, B, μ, σ) of the metal-rough base lobe at the view: the anisotropic
// lobe's own (aniso_split_sum_ab, with μ the mean Schlick angle and σ 0) in pipelines with the
// anisotropy lobe and compensation, else the isotropic table's at brdf_lobe_roughness.
vec4 base_lobe(BrdfParams p, float n_v, vec3 v, AnisotropicLobe an) {
    vec4 lobe = brdf_lut_lobe(n_v, brdf_lobe_roughness(p));
    if ((LOBES & BRDF_LOBE_ANISOTROPY) != 0u && ENERGY_COMPENSATION
        && MODEL == BRDF_MODEL_METAL_ROUGH && an.on) {
        vec2 ab = aniso_split_sum_ab(an, n_v, v, p.color.w, p.p1.z);
        lobe = vec4(ab, brdf_split_sum_mean_cos(ab), 0.0);
    }
    return lobe;
}

// The energy-compensated coat (brdf::layers::clearcoat_energy): its albedo E_ms and lobe factor
// 1 + F0 (1 − E)/E, F0 = 0.04.
ClearcoatEnergy clearcoat_energy(BrdfParams p, float n_v) {
    vec2 ab = brdf_lut_ab(n_v, p.p1.y);
    float e = max(ab.x + ab.y, 1e-4);
    ClearcoatEnergy c;
    c.specular = 1.0 + CLEARCOAT_F0 * ((1.0 - e) / e);
    c.albedo = min((CLEARCOAT_F0 * ab.x + ab.y) * c.specular, 1.0);
    return c;
}

bool energy_compensated(BrdfParams p) {
    return ENERGY_COMPENSATION && MODEL == BRDF_MODEL_METAL_ROUGH;
}

EnergyScale energy_scale(BrdfParams p, vec3 n, vec3 v, AnisotropicLobe an) {
    EnergyScale es;
    es.specular = vec3(1.0);
    es.diffuse = vec3(1.0);
    es.sheen = has_sheen(p) ? sheen_albedo(clamp(dot(n, v), 1e-4, 1.0), p.kappa.w) : 0.0;
    if ((LOBES & BRDF_LOBE_CLEARCOAT) != 0u) {
        float c_v = clamp(dot(brdf_coat_normal(n), v), 1e-4, 1.0);
        es.coat = energy_compensated(p) ? clearcoat_energy(p, c_v) : clearcoat_energy_schlick(c_v);
    }
    if (!energy_compensated(p)) {
        return es;
    }
    float n_v = clamp(dot(n, v), 1e-4, 1.0);
    vec4 lobe = base_lobe(p, n_v, v, an);
    vec2 ab = lobe.xy;
    vec3 f0 = brdf_iridescence_f0_lobe(p, mix(p.spec.rgb, p.color.rgb, p.spec.w), lobe);
    float e = max(ab.x + ab.y, 1e-4);
    es.specular = vec3(1.0) + max(f0, vec3(0.0)) * ((1.0 - e) / e);
    vec3 e_ms = (f0 * ab.x + brdf_f90(p) * ab.y) * es.specular;
    es.diffuse = p.p0.x != 0.0 ? vec3(1.0) : max(vec3(1.0) - e_ms, vec3(0.0));
    return es;
}

// KHR_materials_clearcoat under the environment: the base's diffuse and specular weighted by
// 1 − clearcoat · albedo, plus the coat's split sum (its own roughness, F0 0.04, along its
// mirror direction). With importance sampling the base's specular samples already hold the
// coat (brdf_eval_terms), so only the diffuse is weighted.
vec3 ibl_clearcoat(BrdfParams p, vec3 n, vec3 v, vec3 diffuse, vec3 spec, ClearcoatEnergy e) {
    float keep = 1.0 - p.p1.x * e.albedo;
    if (SPECULAR_METHOD == SPECULAR_IMPORTANCE) {
        return diffuse * keep + spec;
    }
    vec3 nc = brdf_coat_normal(n);
    float n_v = clamp(dot(nc, v), 1e-4, 1.0);
    vec2 ab = brdf_lut_ab(n_v, p.p1.y);
    vec3 r = reflect(-v, nc);
    vec3 pre = textureLod(prefiltered_cube, r, prefiltered_lod(p.p1.y, env.params.x)).rgb;
    vec3 coat = pre * (CLEARCOAT_F0 * ab.x + ab.y) * e.specular;
    return (diffuse + spec) * keep + p.p1.x * coat;
}

// Environment lighting at a point: diffuse from irradiance, specular by the chosen method.
vec3 ibl_shade(BrdfParams p, vec3 n, vec3 v, vec3 x, vec3 y, EnergyScale es) {
    vec3 result = ibl_diffuse_albedo(p) * env_irradiance(n) / M_PI * es.diffuse;
    SplitSumInputs s = split_sum_inputs(p);
    if (!s.ok) {
        return result;
    }
    float n_v = clamp(dot(n, v), 1e-4, 1.0);
    vec4 lobe = brdf_lut_lobe(n_v, s.roughness);
    // KHR_materials_anisotropy: the prefiltered cube is read around the bent normal of the
    // extension's sample renderer (the normal leaned towards the plane across the anisotropy
    // direction, the more the stronger and smoother the lobe); the LUT keeps n·v, and with
    // compensation the split sum is the lobe's own at the view's azimuth (base_lobe).
    vec3 n_r = n;
    if (MODEL == BRDF_MODEL_METAL_ROUGH && SPECULAR_METHOD != SPECULAR_IMPORTANCE) {
        AnisotropicLobe an = brdf_anisotropic_lobe(p, n, x, y);
        if ((LOBES & BRDF_LOBE_ANISOTROPY) != 0u && ENERGY_COMPENSATION) {
            lobe = base_lobe(p, n_v, v, an);
        }
        if (an.on) {
            vec3 across = cross(an.b, v);
            vec3 n_a = cross(across, an.b);
            float bend = 1.0 - p.p1.z * (1.0 - p.color.w);
            bend *= bend;
            n_r = brdf_safe_normalize(mix(n_a, n, bend * bend));
            if (dot(n_r, v) <= 0.0) {
                n_r = n;
            }
        }
    }
    if (MODEL == BRDF_MODEL_METAL_ROUGH) {
        // The film's F0 over this entry's lobe (brdf_iridescence_f0_lobe).
        s.f0 = brdf_iridescence_f0_lobe(p, s.f0, lobe);
    }
    vec2 ab = lobe.xy;
    vec3 spec;
    if (SPECULAR_METHOD == SPECULAR_IMPORTANCE) {
        spec = ibl_specular_importance(p, n, v, x, y, s.roughness);
    } else if (SPECULAR_METHOD == SPECULAR_FITTED_LOBES) {
        // Two lookups of the prefiltered cube fitted to the real lobe (env::lobes,
        // env::fitted_lobes_specular): (φ1, r1, φ2, r2) and w2 at (n·v, roughness) in the LUT's
        // last two layers; d = cos φ n − sin φ t, t the part of v across n.
        vec4 fit = textureLod(brdf_lut, vec3(n_v, s.roughness, env.params.y), 0.0);
        float w2 = textureLod(brdf_lut, vec3(n_v, s.roughness, env.params.y + 1.0), 0.0).x;
        vec3 t = v - n_r * dot(n_r, v);
        float t_len = length(t);
        t = t_len > 1e-6 ? t / t_len : vec3(0.0);
        vec3 d1 = normalize(cos(fit.x) * n_r - sin(fit.x) * t);
        vec3 d2 = normalize(cos(fit.z) * n_r - sin(fit.z) * t);
        float mips = env.params.x;
        vec3 pre = mix(textureLod(prefiltered_cube, d1, prefiltered_lod(fit.y, mips)).rgb,
                       textureLod(prefiltered_cube, d2, prefiltered_lod(fit.w, mips)).rgb, w2);
        spec = s.weight * pre * (s.f0 * ab.x + s.f90 * ab.y);
    } else {
        vec3 r = 2.0 * dot(n_r, v) * n_r - v;
        // Frostbite's dominant direction (Lagarde & de Rousiers 2014, §4.9.3; env::reference::
        // specular_dominant_direction): the lobe leans towards n as it widens, which the n = v = r
        // assumption of the prefiltered cube ignores.
        float a = s.roughness * s.roughness;
        float k = (1.0 - a) * (sqrt(1.0 - a) + a);
        r = normalize(mix(n_r, r, k));
        float lod = prefiltered_lod(s.roughness, env.params.x);
        vec3 pre = textureLod(prefiltered_cube, r, lod).rgb;
        spec = s.weight * pre * (s.f0 * ab.x + s.f90 * ab.y);
    }
    if (ENERGY_COMPENSATION && !energy_compensated(p)) {
        // Other models: only the specular's multi-scatter factor 1 + F0 (1 − E)/E, E = A + B.
        float e = max(ab.x + ab.y, 1e-4);
        spec *= 1.0 + s.f0 * (1.0 - e) / e;
    }
    spec *= es.specular;
    if (has_sheen(p)) {
        // KHR_materials_sheen under the environment: the base weighted by 1 − max(sheenColor) ·
        // E_sheen(n·v), plus sheenColor · E_sheen · irradiance/π (the lobe's albedo times the
        // cosine-weighted mean radiance: exact in a uniform environment, the furnace). With
        // importance sampling the specular samples are already weighted (brdf_eval_terms).
        float keep = max(1.0 - max(p.kappa.r, max(p.kappa.g, p.kappa.b)) * es.sheen, 0.0);
        result = result * keep + p.kappa.rgb * es.sheen * env_irradiance(n) / M_PI;
        if (SPECULAR_METHOD != SPECULAR_IMPORTANCE) {
            spec *= keep;
        }
    }
    if ((LOBES & BRDF_LOBE_CLEARCOAT) != 0u && MODEL == BRDF_MODEL_METAL_ROUGH) {
        return ibl_clearcoat(p, n, v, result, spec, es.coat);
    }
    return result + spec;
}

#endif
