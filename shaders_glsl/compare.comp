#version 460
// The viewer's A/B maps on the GPU, every frame (src/render/compare.rs): |A − B| in linear
// radiance, or LDR FLIP of B against A after exposure, tone map and the 8-bit sRGB encode (a port
// of nv-flip's separable C++ FLIP, the code `luz diff` runs), with summary figures for the panel:
// a 256-bin histogram, the maximum, the count above 0.01 and per-workgroup sums.
//! variant difference: COMPARE_DIFFERENCE LOG_BINS
//! variant flip_convert: FLIP_CONVERT
//! variant flip_h: FLIP_H
//! variant flip_v: FLIP_V
//! variant scale_difference: COMPARE_SCALE LOG_BINS
//! variant scale_flip: COMPARE_SCALE
//
// No branch or loop bound here depends on a push constant alone (lavapipe 22.3 would compile a
// variant per bind, docs/shadows.md): loop bounds are specialisation constants, the tone map is
// one, and the only push constant (exposure) is arithmetic.
#extension GL_EXT_samplerless_texture_functions : require

#include "include/color.glsl"

#ifdef COMPARE_SCALE
layout(local_size_x = 1) in;
#else
layout(local_size_x = 16, local_size_y = 16) in;
#endif

// Bindings (src/render/compare.rs reads them as luz::glsl::compare_comp::BINDING_*).
#define BINDING_A 0
#define BINDING_B 1
#define BINDING_SRGB_TABLE 2
#define BINDING_WEIGHTS 3
#define BINDING_MAP 4
#define BINDING_YCC_A 5
#define BINDING_YCC_B 6
#define BINDING_H0_A 7
#define BINDING_H1_A 8
#define BINDING_H0_B 9
#define BINDING_H1_B 10
#define BINDING_STATS 11

layout(set = 0, binding = BINDING_A) uniform texture2D hdr_a;
layout(set = 0, binding = BINDING_B) uniform texture2D hdr_b;
#define SRGB_TABLE_SET 0
#define SRGB_TABLE_BINDING BINDING_SRGB_TABLE
#include "include/srgb_lut.glsl"
// FLIP's filters (src/render/compare.rs: flip_weights): w[0] = (cmax, pccmax, 0, 0); then the
// spatial filter's 2·SPATIAL_RADIUS + 1 taps (Y, Cx, Cz first and second Gaussian); then the
// feature filter's 2·FEATURE_RADIUS + 1 taps (Gaussian, 1st and 2nd derivative, 0).
layout(set = 0, binding = BINDING_WEIGHTS, std430) readonly buffer Weights {
    vec4 w[];
};
layout(set = 0, binding = BINDING_MAP, r32f) uniform image2D map_image;
layout(set = 0, binding = BINDING_YCC_A, rgba32f) uniform image2D ycc_a;
layout(set = 0, binding = BINDING_YCC_B, rgba32f) uniform image2D ycc_b;
layout(set = 0, binding = BINDING_H0_A, rgba32f) uniform image2D h0_a;
layout(set = 0, binding = BINDING_H1_A, rgba32f) uniform image2D h1_a;
layout(set = 0, binding = BINDING_H0_B, rgba32f) uniform image2D h0_b;
layout(set = 0, binding = BINDING_H1_B, rgba32f) uniform image2D h1_b;
#define STATS_SET 0
#define STATS_BINDING BINDING_STATS
#include "include/compare_stats.glsl"

// The tone map FLIP sees both images through (TONEMAP_*), fixed per pipeline.
layout(constant_id = 0) const uint TONEMAP = 0u;
// Filter radii for the pixels per degree (src/render/compare.rs: flip_radii), at most
// MAX_RADIUS (the shared-memory tiles' apron).
layout(constant_id = 1) const int SPATIAL_RADIUS = 10;
layout(constant_id = 2) const int FEATURE_RADIUS = 9;
#define MAX_RADIUS 10
#define TILE 16u
#define APRON (TILE + 2u * uint(MAX_RADIUS))
#define TILE_N (TILE * APRON)
#if defined(FLIP_H) || defined(FLIP_V)
shared vec4 tile_a[TILE_N];
shared vec4 tile_b[TILE_N];
#endif

layout(push_constant) uniform ComparePush {
    float exposure_scale;  // color::exposure_scale(ev) of A's scene, for both images
} pc;

// --- nv-flip's colour conversions (CPP/color.h) ---
const vec3 D65 = vec3(0.950428545, 1.0, 1.088900371);
const vec3 INV_D65 = vec3(1.052156925, 1.0, 0.918357670);

float srgb_to_linear(float s) {
    return s <= 0.04045 ? s / 12.92 : pow((s + 0.055) / 1.055, 2.4);
}

vec3 linear_to_xyz(vec3 c) {
    return vec3(
        (10135552.0 / 24577794.0) * c.x + (8788810.0 / 24577794.0) * c.y + (4435075.0 / 24577794.0) * c.z,
        (2613072.0 / 12288897.0) * c.x + (8788810.0 / 12288897.0) * c.y + (887015.0 / 12288897.0) * c.z,
        (1425312.0 / 73733382.0) * c.x + (8788810.0 / 73733382.0) * c.y + (70074185.0 / 73733382.0) * c.z);
}

vec3 xyz_to_linear(vec3 c) {
    return vec3(
        3.241003275 * c.x - 1.537398934 * c.y - 0.498615861 * c.z,
        -0.969224334 * c.x + 1.875930071 * c.y + 0.041554224 * c.z,
        0.055639423 * c.x - 0.204011202 * c.y + 1.057148933 * c.z);
}

vec3 xyz_to_ycxcz(vec3 c) {
    c *= INV_D65;
    return vec3(116.0 * c.y - 16.0, 500.0 * (c.x - c.y), 200.0 * (c.y - c.z));
}

vec3 ycxcz_to_xyz(vec3 c) {
    float y = (c.x + 16.0) / 116.0;
    return vec3(y + c.y / 500.0, y, y - c.z / 200.0) * D65;
}

vec3 xyz_to_lab(vec3 c) {
    const float delta = 6.0 / 29.0;
    const float delta_cube = delta * delta * delta;
    const float factor = 1.0 / (3.0 * delta * delta);
    const float term = 4.0 / 29.0;
    c *= INV_D65;
    for (int i = 0; i < 3; i++) {
        c[i] = c[i] > delta_cube ? pow(c[i], 1.0 / 3.0) : factor * c[i] + term;
    }
    return vec3(116.0 * c.y - 16.0, 500.0 * (c.x - c.y), 200.0 * (c.y - c.z));
}

// A filtered YCxCz colour as Hunt-adjusted L*a*b* (clamped to [0, 1] in linear RGB first).
vec3 hunt_lab(vec3 ycxcz) {
    vec3 rgb = clamp(xyz_to_linear(ycxcz_to_xyz(ycxcz)), 0.0, 1.0);
    vec3 lab = xyz_to_lab(linear_to_xyz(rgb));
    return vec3(lab.x, 0.01 * lab.x * lab.y, 0.01 * lab.x * lab.z);
}

float hyab(vec3 a, vec3 b) {
    return abs(a.x - b.x) + length(a.yz - b.yz);
}

// One HDR pixel as FLIP's input: exposure, tone map, 8-bit sRGB code, back to linear, YCxCz.
vec3 flip_input(vec4 hdr) {
    vec3 m = display_map(hdr, pc.exposure_scale, TONEMAP);
    vec3 s = vec3(srgb_encode_u8_lut(m.r), srgb_encode_u8_lut(m.g), srgb_encode_u8_lut(m.b)) / 255.0;
    return xyz_to_ycxcz(linear_to_xyz(vec3(srgb_to_linear(s.r), srgb_to_linear(s.g), srgb_to_linear(s.b))));
}

void main() {
#ifdef COMPARE_SCALE
    finish_stats();
#else
    ivec2 size = imageSize(map_image);
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    bool inside = all(lessThan(p, size));
    ivec2 q = min(p, size - 1);
    float value = 0.0;
#if defined(COMPARE_DIFFERENCE)
    vec3 d = abs(texelFetch(hdr_a, q, 0).rgb - texelFetch(hdr_b, q, 0).rgb);
    value = max(max(d.r, d.g), d.b);
    if (any(isnan(d))) {
        value = uintBitsToFloat(0x7F800000u);  // a NaN channel counts as +∞ (compare::difference_map)
    }
#elif defined(FLIP_CONVERT)
    if (inside) {
        imageStore(ycc_a, p, vec4(flip_input(texelFetch(hdr_a, p, 0)), 0.0));
        imageStore(ycc_b, p, vec4(flip_input(texelFetch(hdr_b, p, 0)), 0.0));
    }
#elif defined(FLIP_H)
    // Horizontal pass (CPP/image.h: computeColorDifference's and
    // computeFeatureDifferenceAndFinalError's x loops), both images at once, from a tile of the
    // workgroup's rows with MAX_RADIUS columns either side in shared memory (one image load per
    // texel instead of one per tap: image loads are what lavapipe is slow at).
    uvec2 g = gl_WorkGroupID.xy * TILE;
    for (uint i = gl_LocalInvocationIndex; i < TILE_N; i += TILE * TILE) {
        ivec2 s = ivec2(clamp(int(g.x) - MAX_RADIUS + int(i % APRON), 0, size.x - 1),
                        clamp(int(g.y + i / APRON), 0, size.y - 1));
        tile_a[i] = imageLoad(ycc_a, s);
        tile_b[i] = imageLoad(ycc_b, s);
    }
    barrier();
    int row = int(gl_LocalInvocationID.y) * int(APRON) + int(gl_LocalInvocationID.x) + MAX_RADIUS;
    vec4 ca = vec4(0.0), cb = vec4(0.0), fa = vec4(0.0), fb = vec4(0.0);
    for (int i = -SPATIAL_RADIUS; i <= SPATIAL_RADIUS; i++) {
        vec4 k = w[1 + SPATIAL_RADIUS + i];
        vec3 a = tile_a[row + i].xyz;
        vec3 b = tile_b[row + i].xyz;
        ca += vec4(k.x * a.x, k.y * a.y, k.z * a.z, k.w * a.z);
        cb += vec4(k.x * b.x, k.y * b.y, k.z * b.z, k.w * b.z);
    }
    const int feature0 = 2 + 2 * SPATIAL_RADIUS + FEATURE_RADIUS;
    for (int i = -FEATURE_RADIUS; i <= FEATURE_RADIUS; i++) {
        vec3 k = w[feature0 + i].xyz;
        float a = tile_a[row + i].x * (1.0 / 116.0) + 16.0 / 116.0;
        float b = tile_b[row + i].x * (1.0 / 116.0) + 16.0 / 116.0;
        fa += vec4(k.y * a, k.z * a, k.x * a, 0.0);
        fb += vec4(k.y * b, k.z * b, k.x * b, 0.0);
    }
    if (inside) {
        imageStore(h0_a, p, ca);
        imageStore(h0_b, p, cb);
        imageStore(h1_a, p, fa);
        imageStore(h1_b, p, fb);
    }
#elif defined(FLIP_V)
    // Vertical pass, from a tile of the workgroup's columns with MAX_RADIUS rows above and
    // below: first the colour results of the horizontal pass, then (same shared memory) its
    // feature results.
    uvec2 g = gl_WorkGroupID.xy * TILE;
    for (uint i = gl_LocalInvocationIndex; i < TILE_N; i += TILE * TILE) {
        ivec2 s = ivec2(clamp(int(g.x + i % TILE), 0, size.x - 1),
                        clamp(int(g.y) - MAX_RADIUS + int(i / TILE), 0, size.y - 1));
        tile_a[i] = imageLoad(h0_a, s);
        tile_b[i] = imageLoad(h0_b, s);
    }
    barrier();
    int col = (int(gl_LocalInvocationID.y) + MAX_RADIUS) * int(TILE) + int(gl_LocalInvocationID.x);
    vec4 ca = vec4(0.0), cb = vec4(0.0);
    for (int i = -SPATIAL_RADIUS; i <= SPATIAL_RADIUS; i++) {
        vec4 k = w[1 + SPATIAL_RADIUS + i];
        vec4 a = tile_a[col + i * int(TILE)];
        vec4 b = tile_b[col + i * int(TILE)];
        ca += vec4(k.x * a.x, k.y * a.y, k.z * a.z, k.w * a.w);
        cb += vec4(k.x * b.x, k.y * b.y, k.z * b.z, k.w * b.w);
    }
    barrier();
    for (uint i = gl_LocalInvocationIndex; i < TILE_N; i += TILE * TILE) {
        ivec2 s = ivec2(clamp(int(g.x + i % TILE), 0, size.x - 1),
                        clamp(int(g.y) - MAX_RADIUS + int(i / TILE), 0, size.y - 1));
        tile_a[i] = imageLoad(h1_a, s);
        tile_b[i] = imageLoad(h1_b, s);
    }
    barrier();
    float cmax = w[0].x;
    float pccmax = w[0].y;
    float color = pow(hyab(hunt_lab(vec3(ca.xy, ca.z + ca.w)), hunt_lab(vec3(cb.xy, cb.z + cb.w))), 0.7);
    color = color < pccmax ? color * (0.95 / pccmax) : 0.95 + ((color - pccmax) / (cmax - pccmax)) * 0.05;
    // (dx, ddx, dy, ddy) of each image.
    vec4 fa = vec4(0.0), fb = vec4(0.0);
    const int feature0 = 2 + 2 * SPATIAL_RADIUS + FEATURE_RADIUS;
    for (int i = -FEATURE_RADIUS; i <= FEATURE_RADIUS; i++) {
        vec3 k = w[feature0 + i].xyz;
        vec3 a = tile_a[col + i * int(TILE)].xyz;
        vec3 b = tile_b[col + i * int(TILE)].xyz;
        fa += vec4(k.x * a.x, k.x * a.y, k.y * a.z, k.z * a.z);
        fb += vec4(k.x * b.x, k.x * b.y, k.y * b.z, k.z * b.z);
    }
    float edge = abs(length(fa.xz) - length(fb.xz));
    float point = abs(length(fa.yw) - length(fb.yw));
    float feature = pow(max(edge, point) / sqrt(2.0), 0.5);
    // powf(0, 0) is 1 in C++; GLSL leaves pow(0, 0) undefined.
    value = feature >= 1.0 ? 1.0 : pow(color, 1.0 - feature);
#endif
#if defined(COMPARE_DIFFERENCE) || defined(FLIP_V)
    if (inside) {
        imageStore(map_image, p, vec4(value));
    }
    accumulate_stats(inside, value);
#endif
#endif
}
