#version 460
// The viewer's display pass: exposure, tone map and exact sRGB encode of the HDR image, written
// straight into the (8-bit UNORM) swapchain image, one fragment per pixel. The same code as
// tonemap.comp (include/color.glsl, the mirror of color.rs).
#extension GL_EXT_samplerless_texture_functions : require

#include "include/color.glsl"

// The operator (TONEMAP_*), fixed per pipeline.
layout(constant_id = 0) const uint TONEMAP = 0u;

layout(set = 0, binding = 0) uniform texture2D hdr;

layout(push_constant) uniform DisplayPush {
    float exposure_scale;  // color::exposure_scale(ev), computed on the CPU
} pc;

layout(location = 0) out vec4 out_color;

void main() {
    vec4 c = texelFetch(hdr, ivec2(gl_FragCoord.xy), 0);
    out_color = to_display_rgba8(c, pc.exposure_scale, TONEMAP) / 255.0;
}
