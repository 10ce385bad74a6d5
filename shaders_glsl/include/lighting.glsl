// Lights and the classic models of MODELS.md §1–2, shared by the vertex stage (flat, Gouraud) and the
// fragment stage (Phong shading).
#ifndef LUZ_LIGHTING_GLSL
#define LUZ_LIGHTING_GLSL

#include "bindings.glsl"

// Distance attenuation: none, inverse square, or the slides' f_at = min(1/(c1 + c2 d + c3 d²), 1).
float light_falloff(Light L, float d) {
    uint kind = uint(L.direction_falloff.w);
    if (kind == FALLOFF_INVERSE_SQUARE) {
        return 1.0 / max(d * d, 1e-8);
    }
    if (kind == FALLOFF_CLASSIC) {
        float q = L.atten.x + L.atten.y * d + L.atten.z * d * d;
        return q > 1.0 ? 1.0 / q : 1.0;
    }
    return 1.0;
}

// Direction towards the light and the irradiance it delivers on a surface facing it.
void light_incidence(Light L, vec3 P, out vec3 l, out vec3 E) {
    uint type = uint(L.position_type.w);
    if (type == LIGHT_DIRECTIONAL) {
        l = -L.direction_falloff.xyz;
        E = L.radiance.rgb;
        return;
    }
    vec3 to_light = L.position_type.xyz - P;
    float d = length(to_light);
    l = d > 0.0 ? to_light / d : vec3(0.0, 1.0, 0.0);
    E = L.radiance.rgb * light_falloff(L, d);
    if (type == LIGHT_SPOT) {
        // θ_s: angle between the spot axis and −l.
        float cos_s = dot(L.direction_falloff.xyz, -l);
        float cone = L.cone.z > 0.5 ? smoothstep(L.cone.x, L.cone.y, cos_s) : (cos_s >= L.cone.x ? 1.0 : 0.0);
        float shape = L.atten.w > 0.0 ? pow(max(cos_s, 0.0), L.atten.w) : 1.0;
        E *= cone * shape;
    }
}

// The material's parameters with the model fixed by the pipeline's specialization constant.
BrdfParams material_params() {
    BrdfParams p = material.brdf;
    p.sel.x = MODEL;
    return p;
}

// The ambient term: the slides' I_a k_a O_d for the classic models; for the others the uniform
// ambient radiance seen by the diffuse term (diffuse albedo × ambient).
vec3 ambient_term(BrdfParams p, vec3 ambient) {
    if (MODEL == BRDF_MODEL_PHONG || MODEL == BRDF_MODEL_BLINN_PHONG) {
        return ambient * p.p0.z * p.color.rgb;
    }
    if (MODEL == BRDF_MODEL_COOK_TORRANCE) {
        return ambient * p.kappa.w * p.color.rgb;
    }
    if (MODEL == BRDF_MODEL_METAL_ROUGH || MODEL == BRDF_MODEL_PRINCIPLED) {
        return ambient * (1.0 - p.spec.w) * p.color.rgb;
    }
    return ambient * p.color.rgb;
}

#ifdef IBL
#include "ibl.glsl"
#endif

// Outgoing value at P (world space) with unit normal N and tangent frame (X, Y): ambient plus
// every light, each through the CPU reference's mirror brdf_radiance.
vec3 shade(vec3 P, vec3 N, vec3 X, vec3 Y) {
    BrdfParams p = material_params();
    vec3 V = normalize(frame.camera_pos.xyz - P);
    vec3 result = ambient_term(p, frame.ambient.rgb);
    uint count = frame.counts.x;
    for (uint i = 0u; i < count; ++i) {
        vec3 l;
        vec3 E;
        light_incidence(lights[i], P, l, E);
        result += brdf_radiance(p, N, l, V, X, Y, E);
    }
#ifdef IBL
    result += ibl_shade(p, N, V, X, Y);
#endif
    return result;
}

// A tangent frame from a normal and a (possibly unnormalised, non-orthogonal) tangent with
// handedness w: Gram-Schmidt, then Y = w (N × X). Degenerate tangents fall back to any
// perpendicular vector.
void tangent_frame(vec3 N, vec4 T, out vec3 X, out vec3 Y) {
    vec3 t = T.xyz - N * dot(N, T.xyz);
    float len2 = dot(t, t);
    if (len2 < 1e-12) {
        t = abs(N.x) < 0.9 ? cross(N, vec3(1.0, 0.0, 0.0)) : cross(N, vec3(0.0, 1.0, 0.0));
        len2 = dot(t, t);
    }
    X = t * inversesqrt(len2);
    Y = cross(N, X) * (T.w < 0.0 ? -1.0 : 1.0);
}

// Depth cueing: S from the view-space depth z, then I' = (1 − S) I + S I_F.
vec3 apply_fog(vec3 c, float z) {
    if (!FOG) {
        return c;
    }
    float za = frame.fog.x;
    float zb = frame.fog.y;
    float sa = frame.fog.z;
    float sb = frame.fog.w;
    float S;
    if (z < za) {
        S = sa;
    } else if (z > zb) {
        S = sb;
    } else {
        S = zb > za ? sa + (z - za) * (sb - sa) / (zb - za) : sa;
    }
    return (1.0 - S) * c + S * frame.fog_color.rgb;
}

#endif
