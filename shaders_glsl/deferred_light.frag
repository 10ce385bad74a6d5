#version 460
//! variant plain:
//! variant tangent: PHONG_TANGENT
// The deferred path's lighting pass (src/render/forward/deferred.rs): a full-screen triangle at
// depth 1 tested GREATER against the geometry pass's depth, so only covered pixels run. Each reads
// its G-buffer texel, rebuilds the world position from the view depth along the pixel's ray (the
// point a forward fragment's interpolated position gives), loads its object's material and shades
// with the forward pass's code (include/lighting.glsl), fog and output included. PHONG_TANGENT
// (KHR_materials_anisotropy): the shading frame's X from a second G-buffer image; the frame's Y
// may have the opposite sign to the forward pass's on a double-sided back face, which the
// anisotropic lobe (squares of b·h, b·l, b·v) does not see.
#extension GL_EXT_samplerless_texture_functions : require
#define LUZ_FRAGMENT
#define LUZ_DEFERRED
#include "include/lighting.glsl"
#include "include/output.glsl"
#include "include/octahedral.glsl"

#define SET_GBUFFER 1
#define BINDING_GBUFFER 0
layout(set = SET_GBUFFER, binding = BINDING_GBUFFER) uniform utexture2D gbuffer;
#ifdef PHONG_TANGENT
#define BINDING_GBUFFER_TANGENT 1
layout(set = SET_GBUFFER, binding = BINDING_GBUFFER_TANGENT) uniform utexture2D gbuffer_tangent;
#endif

// src/render/gpu.rs: DeferredMaterial (std430, 224 bytes).
struct DeferredMaterial {
    BrdfParams brdf;
    uint object_index;
    uint flags;
    uint receive_shadow;
    uint double_sided;
    vec4 emissive;
    vec4 params;
    uvec4 present;
    vec4 volume;
    vec4 attenuation;
    vec4 diffuse_transmission;
};
layout(set = SET_FRAME, binding = BINDING_DEFERRED_MATERIALS, std430) readonly buffer DeferredMaterials {
    DeferredMaterial deferred_materials[];
};

layout(location = 0) out vec4 out_color;

void main() {
    uvec4 g = texelFetch(gbuffer, ivec2(gl_FragCoord.xy), 0);
    vec3 n = oct_decode(vec2(uintBitsToFloat(g.x), uintBitsToFloat(g.y)));
    float depth = uintBitsToFloat(g.z);
    DeferredMaterial m = deferred_materials[g.w];
    material.brdf = m.brdf;
    material.object_index = m.object_index;
    material.flags = m.flags;
    material.receive_shadow = m.receive_shadow;
    material.double_sided = m.double_sided;
    mat_extra.emissive = m.emissive;
    mat_extra.params = m.params;
    mat_extra.present = m.present;
    mat_extra.volume = m.volume;
    mat_extra.attenuation = m.attenuation;
    mat_extra.diffuse_transmission = m.diffuse_transmission;

    // The pixel centre's ray and the point on it at
    // the stored view depth.
    vec2 ndc = (gl_FragCoord.xy / vec2(textureSize(gbuffer, 0))) * 2.0 - 1.0;
    vec4 far = frame.inv_view_proj * vec4(ndc, 1.0, 1.0);
    vec3 ray = far.xyz / far.w - frame.camera_pos.xyz;
    vec3 forward = -vec3(frame.view[0][2], frame.view[1][2], frame.view[2][2]);
    vec3 P = frame.camera_pos.xyz + ray * (depth / dot(ray, forward));
    // An orthographic camera (camera_pos.w = 0): the pixel's parallel ray, moved from the far
    // plane point to the stored depth along the view direction.
    if (opaque(floatBitsToUint(frame.camera_pos.w)) == 0u) {
        vec3 q = far.xyz / far.w;
        P = q + forward * (depth + (frame.view * vec4(q, 1.0)).z);
    }

    vec3 x;
    vec3 y;
#ifdef PHONG_TANGENT
    uvec2 gt = texelFetch(gbuffer_tangent, ivec2(gl_FragCoord.xy), 0).xy;
    tangent_frame(n, vec4(oct_decode(vec2(uintBitsToFloat(gt.x), uintBitsToFloat(gt.y))), 1.0), x,
                  y);
#else
    tangent_frame(n, vec4(0.0, 0.0, 0.0, 1.0), x, y);
#endif
    vec3 c = shade(P, n, x, y, vec2(0.0));
    c = apply_fog(c, depth);
    if (DEBUG_VIEW == DEBUG_VIEW_NAN && (any(isnan(c)) || any(isinf(c)))) {
        c = vec3(1.0, 0.0, 1.0);
    }
    out_color = forward_output(c);
}
