// Shadow-map lookups (src/render/shadow): one 2D-array depth image holds every map of the frame,
// a layer per cascade, cube face or spot; each light uses the top-left resolution² texels of its
// layers. Depth is reversed (1 at the near plane, 0 where nothing was drawn), so a receiver is lit
// where its depth ≥ the stored one. Included by lighting.glsl; code only when LIGHT_KINDS has a
// LK_SHADOW_* bit.
#ifndef LUZ_SHADOWS_GLSL
#define LUZ_SHADOWS_GLSL

#define SET_SHADOW 3
// Comparison with bilinear filtering (PCF taps), comparison at the nearest texel (hard shadows),
// and the raw depth (PCSS's blocker search): three views of the same image.
#define BINDING_SHADOW_LINEAR 0
#define BINDING_SHADOW_NEAREST 1
#define BINDING_SHADOW_DEPTH 2
#define BINDING_SHADOW_LIGHTS 3
#define BINDING_SHADOW_LAYERS 4

#define SHADOW_HARD 0
#define SHADOW_PCF 1
#define SHADOW_PCSS 2
#define SHADOW_MAX_CASCADES 4
// Layers of a light with a cube map (point lights, wide spots).
#define SHADOW_CUBE_LAYERS 6

layout(set = SET_SHADOW, binding = BINDING_SHADOW_LINEAR) uniform sampler2DArrayShadow shadow_linear;
layout(set = SET_SHADOW, binding = BINDING_SHADOW_NEAREST) uniform sampler2DArrayShadow shadow_nearest;
layout(set = SET_SHADOW, binding = BINDING_SHADOW_DEPTH) uniform sampler2DArray shadow_depth;

// Per light (indexed like lights[]; src/render/shadow: GpuShadowLight).
struct ShadowLight {
    ivec4 info;    // x: first layer (−1: no shadow), y: layers, z: SHADOW_* method, w: PCF taps per side
    vec4 params;   // x: uv scale (resolution / image size), y: 1 / image size, z: bias, w: normal bias (texels)
    vec4 size;     // x: radius (m) or tan(angular radius), y: PCSS's largest filter radius (texels)
    vec4 splits;   // far view depth of each cascade
};

// Per layer (src/render/shadow: GpuShadowLayer).
struct ShadowLayer {
    mat4 view_proj;
    vec4 params;  // x: texel size (m; per metre of distance when perspective), y: 1 perspective, z: near or depth range
    vec4 origin;  // xyz: the light's eye
    vec4 axis;    // xyz: unit view direction
};

layout(set = SET_SHADOW, binding = BINDING_SHADOW_LIGHTS, std430) readonly buffer ShadowLights {
    ShadowLight shadow_lights[];
};
layout(set = SET_SHADOW, binding = BINDING_SHADOW_LAYERS, std430) readonly buffer ShadowLayers {
    ShadowLayer shadow_layers[];
};

const uint SHADOW_KINDS = LK_SHADOW_HARD | LK_SHADOW_PCF | LK_SHADOW_PCSS;

// Explicit LOD 0 (textureGrad with zero gradients): valid in the vertex stage too, where flat and
// Gouraud shading light.
float shadow_tap(vec2 uv, float layer, float ref) {
#if defined(LUZ_FRAGMENT) || defined(LUZ_DEFERRED)
    return texture(shadow_linear, vec4(uv, layer, ref));
#else
    return textureGrad(shadow_linear, vec4(uv, layer, ref), vec2(0.0), vec2(0.0));
#endif
}

// 16 points of a Poisson disc in the unit disc (PCSS).
const vec2 SHADOW_DISC[16] = vec2[](
    vec2(-0.94201624, -0.39906216), vec2(0.94558609, -0.76890725),
    vec2(-0.09418410, -0.92938870), vec2(0.34495938, 0.29387760),
    vec2(-0.91588581, 0.45771432), vec2(-0.81544232, -0.87912464),
    vec2(-0.38277543, 0.27676845), vec2(0.97484398, 0.75648379),
    vec2(0.44323325, -0.97511554), vec2(0.53742981, -0.47373420),
    vec2(-0.26496911, -0.41893023), vec2(0.79197514, 0.19090188),
    vec2(-0.24188840, 0.99706507), vec2(-0.81409955, 0.91437590),
    vec2(0.19984126, 0.78641367), vec2(0.14383161, -0.14100790));

// Distance from the layer's eye along its axis for a stored (reversed) depth z.
float shadow_distance(ShadowLayer L, float z) {
    return L.params.y > 0.5 ? L.params.z / max(z, 1e-30) : (1.0 - z) * L.params.z;
}

// The layer light i's shadow at P is looked up in: its cube face or cascade; `beyond`: past the
// last cascade (nothing shadowed there).
int shadow_layer(uint i, ShadowLight s, vec3 P, out bool beyond) {
    int layer = s.info.x;
    beyond = false;
    bool cube = s.info.y == SHADOW_CUBE_LAYERS;
    if (cube) {
        vec3 d = P - lights[i].position_type.xyz;
        vec3 a = abs(d);
        int face = a.x >= a.y && a.x >= a.z ? (d.x >= 0.0 ? 0 : 1)
                 : (a.y >= a.z ? (d.y >= 0.0 ? 2 : 3) : (d.z >= 0.0 ? 4 : 5));
        layer += face;
    }
    bool cascaded = !cube && uint(lights[i].position_type.w) == LIGHT_DIRECTIONAL;
    if (cascaded) {
        // Cascades by view depth.
        float z = -(frame.view * vec4(P, 1.0)).z;
        int n = s.info.y;
        beyond = z > s.splits[n - 1];
        int c = 0;
        for (int k = 0; k < n - 1; ++k) {
            c += z > s.splits[k] ? 1 : 0;
        }
        layer += c;
    }
    return layer;
}

// Fixed shadow slots (src/render/shadow: fixed_slots): when a scene has at most four shadowed
// lights, each one is described whole by a specialization constant (0: slot unused): its light
// index, first layer, geometry (cascades, one perspective map, cube faces), layer count, filter
// and PCF kernel. Each light's lookup then compiles only its own layer choice, projection and
// filter (lavapipe runs both sides of every `if` under a lane mask, so the generic lookup pays
// for cube faces, cascades and every filter at each light), the PCF loops unrolled. More lights,
// or fields out of range: every slot 0 and the lookups read these from the records per pixel
// (shadow_visibility).
layout(constant_id = 19) const uint SHADOW_FIXED_0 = 0u;
layout(constant_id = 20) const uint SHADOW_FIXED_1 = 0u;
layout(constant_id = 21) const uint SHADOW_FIXED_2 = 0u;
layout(constant_id = 22) const uint SHADOW_FIXED_3 = 0u;
// Fields: bits 0–7 light index, 8–15 first layer, 16–17 geometry, 18–20 layers, 21–22 SHADOW_*
// method, 23–27 PCF taps per side; bit 31 set in every used slot.
#define SHADOW_FIXED_SLOTS 4
#define SHADOW_FIXED_USED 2147483648u
// Set in a draw's slot when the draw does not receive that light's shadow: no lookup compiled.
#define SHADOW_FIXED_SKIP 268435456u
#define SHADOW_GEOMETRY_CASCADES 0u
#define SHADOW_GEOMETRY_SINGLE 1u
#define SHADOW_GEOMETRY_CUBE 2u


float shadow_filter_of(uint kinds, ShadowLight s, ShadowLayer L, int layer, bool perspective,
                       int method, int n, vec2 uv, float ref, float dist, float texel);

// The fraction of light i that reaches P through layer record L (its index `layer`; `beyond`:
// past the last cascade), filtered by `method` with `n` PCF taps per side (unit normal N, unit
// direction l towards the light); `kinds`: the LK_SHADOW_* filters compiled (a constant: the
// punctual lights' LIGHT_KINDS, or the area lights' bits shifted, area.glsl).
float shadow_lookup_of(uint kinds, ShadowLight s, ShadowLayer L, int layer, bool beyond,
                       bool perspective, int method, int n, vec3 P, vec3 N, vec3 l) {
    float dist = dot(P - L.origin.xyz, L.axis.xyz);
    float texel = perspective ? L.params.x * dist : L.params.x;
    // Normal offset (more at grazing light) and an offset towards the light, in texels; wider
    // PCF kernels reach farther over a tilted receiver, so their offsets grow with them.
    float cos_t = clamp(dot(N, l), 0.0, 1.0);
    float sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
    float reach = method == SHADOW_PCF ? max(1.0, 0.5 * float(n - 1)) : 1.0;
    vec3 Po = P + (N * (s.params.w * sin_t) + l * s.params.z) * (texel * reach);
    vec4 clip = L.view_proj * vec4(Po, 1.0);
    if (clip.w <= 0.0) {
        return 1.0;
    }
    vec3 ndc = clip.xyz / clip.w;
    vec2 uv = ndc.xy * 0.5 + 0.5;
    if (beyond || any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) {
        return 1.0;
    }
    return shadow_filter_of(kinds, s, L, layer, perspective, method, n, uv, ndc.z, dist, texel);
}

// shadow_lookup_of for the punctual lights' filters.
float shadow_lookup(ShadowLight s, ShadowLayer L, int layer, bool beyond, bool perspective,
                    int method, int n, vec3 P, vec3 N, vec3 l) {
    return shadow_lookup_of(LIGHT_KINDS, s, L, layer, beyond, perspective, method, n, P, N, l);
}

// The filtered comparison of shadow_lookup at layer-local uv (0–1) and reversed depth ref.
float shadow_filter_of(uint kinds, ShadowLight s, ShadowLayer L, int layer, bool perspective,
                       int method, int n, vec2 uv, float ref, float dist, float texel) {
    float scale = s.params.x;
    float inv_size = s.params.y;
    // Taps stay inside the light's own texels of the layer.
    vec2 lo = vec2(0.5 * inv_size);
    vec2 hi = vec2(scale - 0.5 * inv_size);
    uv *= scale;
    float fl = float(layer);
    if ((kinds & LK_SHADOW_HARD) != 0u && method == SHADOW_HARD) {
        return textureGrad(shadow_nearest, vec4(clamp(uv, lo, hi), fl, ref), vec2(0.0), vec2(0.0));
    }
    if ((kinds & LK_SHADOW_PCSS) != 0u && method == SHADOW_PCSS) {
        float dr = perspective ? dist : (1.0 - ref) * L.params.z;
        // Blocker search over the light's footprint seen from P, at most the largest filter.
        float max_r = s.size.y;
        float search = perspective ? s.size.x : s.size.x * dr;
        float search_texels = clamp(search / texel, 1.0, max_r);
        float blockers = 0.0;
        float count = 0.0;
        for (int k = 0; k < 16; ++k) {
            vec2 p = clamp(uv + SHADOW_DISC[k] * search_texels * inv_size, lo, hi);
            float z = textureLod(shadow_depth, vec3(p, fl), 0.0).r;
            if (z > ref) {
                blockers += shadow_distance(L, z);
                count += 1.0;
            }
        }
        if (count == 0.0) {
            return 1.0;
        }
        float db = blockers / count;
        // Penumbra width at P from similar triangles (disc of radius R at the light, or the
        // angular radius's tangent for a directional light).
        float w = perspective ? s.size.x * max(dr - db, 0.0) / max(db, 1e-30)
                              : s.size.x * max(dr - db, 0.0);
        float r = clamp(w / texel, 0.5, max_r);
        float sum = 0.0;
        for (int k = 0; k < 16; ++k) {
            sum += shadow_tap(clamp(uv + SHADOW_DISC[k] * r * inv_size, lo, hi), fl, ref);
        }
        return sum / 16.0;
    }
    // PCF: n² bilinear comparisons one texel apart, centred on the point (n = 2: a 3×3-texel
    // tent from four taps).
    float c0 = 0.5 * float(n - 1);
    float sum = 0.0;
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            sum += shadow_tap(clamp(uv + (vec2(x, y) - c0) * inv_size, lo, hi), fl, ref);
        }
    }
    return sum / float(n * n);
}

// The fraction of light i that reaches P (unit normal N, unit direction l towards the light);
// the caller skips lights without a shadow (info.x < 0).
float shadow_visibility(uint i, vec3 P, vec3 N, vec3 l) {
    ShadowLight s = shadow_lights[i];
    bool beyond;
    int layer = shadow_layer(i, s, P, beyond);
    ShadowLayer L = shadow_layers[layer];
    return shadow_lookup(s, L, layer, beyond, L.params.y > 0.5, s.info.z, s.info.w, P, N, l);
}

// shadow_visibility for the light fixed slot `code` describes; N as there.
float shadow_fixed(uint code, vec3 P, vec3 N) {
    uint i = code & 255u;
    int first = int((code >> 8u) & 255u);
    uint geometry = (code >> 16u) & 3u;
    int count = int((code >> 18u) & 7u);
    int method = int((code >> 21u) & 3u);
    int n = int((code >> 23u) & 31u);
    ShadowLight s = shadow_lights[i];
    vec3 v = lights[i].position_type.xyz;
    vec3 l = -lights[i].direction_falloff.xyz;
    int pick = 0;
    bool beyond = false;
    if (geometry != SHADOW_GEOMETRY_CASCADES) {
        vec3 d = v - P;
        float len = length(d);
        l = len > 0.0 ? d / len : vec3(0.0, 1.0, 0.0);
    }
    if (geometry == SHADOW_GEOMETRY_CUBE) {
        vec3 d = P - v;
        vec3 a = abs(d);
        pick = a.x >= a.y && a.x >= a.z ? (d.x >= 0.0 ? 0 : 1)
             : (a.y >= a.z ? (d.y >= 0.0 ? 2 : 3) : (d.z >= 0.0 ? 4 : 5));
    }
    if (geometry == SHADOW_GEOMETRY_CASCADES) {
        float z = -(frame.view * vec4(P, 1.0)).z;
        beyond = z > s.splits[count - 1];
        for (int j = 0; j < count - 1; ++j) {
            pick += z > s.splits[j] ? 1 : 0;
        }
    }
    // The chosen layer's record by a per-pixel index (cheaper on lavapipe than reading every
    // layer at a constant index and selecting: docs/shadows.md#cost).
    ShadowLayer L = shadow_layers[first + pick];
    return shadow_lookup(s, L, first + pick, beyond, geometry != SHADOW_GEOMETRY_CASCADES,
                         method, n, P, N, l);
}

// Every fixed slot's visibility at P (1 where the slot is unused).
vec4 shadow_fixed_all(vec3 P, vec3 N) {
    vec4 v = vec4(1.0);
    if (SHADOW_FIXED_0 != 0u && (SHADOW_FIXED_0 & SHADOW_FIXED_SKIP) == 0u) v.x = shadow_fixed(SHADOW_FIXED_0, P, N);
    if (SHADOW_FIXED_1 != 0u && (SHADOW_FIXED_1 & SHADOW_FIXED_SKIP) == 0u) v.y = shadow_fixed(SHADOW_FIXED_1, P, N);
    if (SHADOW_FIXED_2 != 0u && (SHADOW_FIXED_2 & SHADOW_FIXED_SKIP) == 0u) v.z = shadow_fixed(SHADOW_FIXED_2, P, N);
    if (SHADOW_FIXED_3 != 0u && (SHADOW_FIXED_3 & SHADOW_FIXED_SKIP) == 0u) v.w = shadow_fixed(SHADOW_FIXED_3, P, N);
    return v;
}

// Light i's entry of shadow_fixed_all (1: no fixed slot).
float shadow_fixed_pick(uint i, vec4 v) {
    float f = 1.0;
    f = SHADOW_FIXED_0 != 0u && i == (SHADOW_FIXED_0 & 255u) ? v.x : f;
    f = SHADOW_FIXED_1 != 0u && i == (SHADOW_FIXED_1 & 255u) ? v.y : f;
    f = SHADOW_FIXED_2 != 0u && i == (SHADOW_FIXED_2 & 255u) ? v.z : f;
    f = SHADOW_FIXED_3 != 0u && i == (SHADOW_FIXED_3 & 255u) ? v.w : f;
    return f;
}

#endif
