#version 460
// The deferred path's geometry pass (src/render/forward/deferred.rs): per pixel, the normal
// (octahedral, two floats), the view depth and the object slot, as raw bits in an RGBA32_UINT
// image. Lighting runs afterwards once per covered pixel (deferred_light.frag), instead of once
// per 4×4 block each small triangle touches, as lavapipe runs a forward fragment shader.
#include "include/bindings.glsl"
#include "include/octahedral.glsl"

layout(location = 0) in float in_depth;
layout(location = 2) in vec3 in_normal;

layout(location = 0) out uvec4 out_gbuffer;

void main() {
    vec3 n = normalize(in_normal);
    // Double-sided materials: a back face is lit with the flipped normal.
    n = (!gl_FrontFacing && opaque(material.double_sided) != 0u) ? -n : n;
    vec2 e = oct_encode(n);
    out_gbuffer = uvec4(floatBitsToUint(e.x), floatBitsToUint(e.y), floatBitsToUint(in_depth),
                        material.object_index);
}
