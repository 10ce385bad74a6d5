// Lights and the classic models of MODELS.md §1–2, shared by the vertex stage (flat, Gouraud) and the
// fragment stage (Phong shading).
#ifndef LUZ_LIGHTING_GLSL
#define LUZ_LIGHTING_GLSL

#include "bindings.glsl"

const float PI = 3.14159265358979323846;

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

// The slides' model for one light: I_L (k_d O_d (n·l) + k_s O_s (r·v)^n); 0 where n·l <= 0.
vec3 classic_light(vec3 N, vec3 V, vec3 l, vec3 E, bool blinn) {
    float n_l = dot(N, l);
    if (n_l <= 0.0) {
        return vec3(0.0);
    }
    vec3 Od = material.c0.rgb;
    vec3 Os = material.c1.rgb;
    float kd = material.c1.w;
    float ks = material.p0.x;
    float n = material.p0.y;
    float s;
    if (blinn) {
        vec3 h = l + V;
        float hl = length(h);
        s = hl > 0.0 ? max(dot(N, h / hl), 0.0) : 0.0;
    } else {
        vec3 r = 2.0 * n_l * N - l;
        s = max(dot(r, V), 0.0);
    }
    float spec = s > 0.0 ? pow(s, n) : (n == 0.0 ? 1.0 : 0.0);
    return E * (kd * Od * n_l + ks * Os * spec);
}

// Outgoing value at P (world space) with unit normal N: ambient plus every light.
vec3 shade(vec3 P, vec3 N) {
    vec3 V = normalize(frame.camera_pos.xyz - P);
    vec3 result;
    if (MODEL == MODEL_LAMBERT) {
        result = material.c0.rgb * frame.ambient.rgb;
    } else {
        result = frame.ambient.rgb * material.c0.w * material.c0.rgb;
    }
    uint count = frame.counts.x;
    for (uint i = 0u; i < count; ++i) {
        vec3 l;
        vec3 E;
        light_incidence(lights[i], P, l, E);
        if (MODEL == MODEL_LAMBERT) {
            result += material.c0.rgb / PI * E * max(dot(N, l), 0.0);
        } else {
            result += classic_light(N, V, l, E, MODEL == MODEL_BLINN_PHONG);
        }
    }
    return result;
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
