#version 460
//! variant plain:
//! variant tangent: PHONG_TANGENT
// The deferred path's geometry pass (src/render/forward/deferred.rs): per pixel, the normal
// (octahedral, two floats), the view depth and the object slot, as raw bits in an RGBA32_UINT
// image. Lighting runs afterwards once per covered pixel (deferred_light.frag), instead of once
// per 4×4 block each small triangle touches, as lavapipe runs a forward fragment shader.
// PHONG_TANGENT (KHR_materials_anisotropy, no maps): a second RG32_UINT image keeps the shading
// frame's X (octahedral, two floats), made from the interpolated tangent as forward.frag makes it.
#include "include/bindings.glsl"
#include "include/octahedral.glsl"
#include "include/tangent_frame.glsl"

layout(location = 0) in float in_depth;
layout(location = 2) in vec3 in_normal;
#ifdef PHONG_TANGENT
layout(location = 3) in vec3 in_tangent;
#endif

layout(location = 0) out uvec4 out_gbuffer;
#ifdef PHONG_TANGENT
layout(location = 1) out uvec2 out_tangent;
#endif

void main() {
    vec3 n = normalize(in_normal);
    // Double-sided materials: a back face is lit with the flipped normal (and frame).
    bool flip = !gl_FrontFacing && opaque(material.double_sided) != 0u;
#ifdef PHONG_TANGENT
    vec3 x;
    vec3 y;
    tangent_frame(n, vec4(in_tangent, 1.0), x, y);
    vec2 t = oct_encode(flip ? -x : x);
    out_tangent = uvec2(floatBitsToUint(t.x), floatBitsToUint(t.y));
#endif
    n = flip ? -n : n;
    vec2 e = oct_encode(n);
    out_gbuffer = uvec4(floatBitsToUint(e.x), floatBitsToUint(e.y), floatBitsToUint(in_depth),
                        material.object_index);
}
