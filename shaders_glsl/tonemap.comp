#version 460
// Display conversion of the HDR image (src/render/tonemap.rs): exposure → tone map → clamp → sRGB
// encode → 8-bit, exactly as color::to_display_rgba8. The destination is a UNORM storage image
// (storage images of *_SRGB formats are not allowed), so the sRGB curve is applied here and the
// rounded code is written as code/255, which every UNORM conversion maps back to the same code.
#extension GL_EXT_samplerless_texture_functions : require

#include "include/color.glsl"

// Mirrored in src/render/tonemap.rs (BINDING_SOURCE, BINDING_DESTINATION, TonemapPush).
#define BINDING_SOURCE 0
#define BINDING_DESTINATION 1

layout(local_size_x = 16, local_size_y = 16) in;
// A sampled image read with texelFetch: valid in GENERAL and SHADER_READ_ONLY_OPTIMAL alike.
layout(set = 0, binding = BINDING_SOURCE) uniform texture2D hdr;
layout(set = 0, binding = BINDING_DESTINATION, rgba8) uniform writeonly image2D display;

// The operator (TONEMAP_*), fixed per pipeline so only its code is compiled.
layout(constant_id = 0) const uint TONEMAP = 0u;

layout(push_constant) uniform TonemapPush {
    float exposure_scale;  // color::exposure_scale(ev), computed on the CPU
    uint tonemap;          // TONEMAP_*
} pc;

void main() {
    // Both bounds: a source smaller than the destination leaves the rest untouched, never reads
    // out of bounds.
    ivec2 size = min(imageSize(display), textureSize(hdr, 0));
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= size.x || p.y >= size.y) {
        return;
    }
    vec4 c = texelFetch(hdr, p, 0);
    vec4 codes = to_display_rgba8(c, pc.exposure_scale, TONEMAP);
    imageStore(display, p, codes / 255.0);
}
