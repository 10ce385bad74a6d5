#version 460
// The viewer's display pass: exposure, tone map and exact sRGB encode of the HDR image, written
// straight into the (8-bit UNORM) swapchain image, one fragment per pixel. The same code as
// tonemap.comp (include/color.glsl, the mirror of color.rs), except the sRGB encode: a table
// lookup and a compare (color::srgb_encode_u8_lut) give the same codes as its pow, in about a
// tenth of the time on lavapipe.
#extension GL_EXT_samplerless_texture_functions : require

#include "include/color.glsl"

// The operator (TONEMAP_*), fixed per pipeline.
layout(constant_id = 0) const uint TONEMAP = 0u;

// Bindings (src/render/display.rs reads them as luz::glsl::display_frag::BINDING_*).
#define BINDING_HDR 0
#define BINDING_SRGB_TABLE 1
layout(set = 0, binding = BINDING_HDR) uniform texture2D hdr;

#define SRGB_TABLE_SET 0
#define SRGB_TABLE_BINDING BINDING_SRGB_TABLE
#include "include/srgb_lut.glsl"

layout(push_constant) uniform DisplayPush {
    float exposure_scale;  // color::exposure_scale(ev), computed on the CPU
} pc;

layout(location = 0) out vec4 out_color;

void main() {
    vec4 c = texelFetch(hdr, ivec2(gl_FragCoord.xy), 0);
    vec3 m = display_map(c, pc.exposure_scale, TONEMAP);
    out_color = vec4(srgb_encode_u8_lut(m.r), srgb_encode_u8_lut(m.g), srgb_encode_u8_lut(m.b), 255.0) / 255.0;
}
