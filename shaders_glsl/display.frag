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

// color::srgb_encode_table: per bin of [0, 1], the code at the bin's start and the value where it
// steps up by one (2.0: no step in this bin).
layout(set = 0, binding = BINDING_SRGB_TABLE, std430) readonly buffer SrgbEncodeTable {
    vec2 srgb_table[];
};
const float SRGB_ENCODE_BINS = 4096.0;  // color::SRGB_ENCODE_BINS

// color::srgb_encode_u8_lut, as a float code in [0, 255].
float srgb_encode_u8_lut(float linear) {
    if (isnan(linear)) {
        return 0.0;
    }
    float x = clamp(linear, 0.0, 1.0);
    vec2 e = srgb_table[min(int(x * SRGB_ENCODE_BINS), int(SRGB_ENCODE_BINS) - 1)];
    return x >= e.y ? e.x + 1.0 : e.x;
}

layout(push_constant) uniform DisplayPush {
    float exposure_scale;  // color::exposure_scale(ev), computed on the CPU
} pc;

layout(location = 0) out vec4 out_color;

void main() {
    vec4 c = texelFetch(hdr, ivec2(gl_FragCoord.xy), 0);
    vec3 m = display_map(c, pc.exposure_scale, TONEMAP);
    out_color = vec4(srgb_encode_u8_lut(m.r), srgb_encode_u8_lut(m.g), srgb_encode_u8_lut(m.b), 255.0) / 255.0;
}
