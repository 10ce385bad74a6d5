// What the forward pass writes (forward.frag, skybox.frag): the radiance into the float HDR target,
// or — when a frame needs no whole-image operation — the display codes straight into an 8-bit
// UNORM attachment (the swapchain image): saturation by clamping, exposure, tone map and sRGB
// encode, the same code as display.frag after the float target (include/color.glsl, the mirror of
// color.rs), so both paths give the same codes. src/render/forward/mod.rs: Output.
#ifndef LUZ_OUTPUT_GLSL
#define LUZ_OUTPUT_GLSL

#include "bindings.glsl"
#include "color.glsl"

// 0: radiance to the HDR target; 1: display codes to an 8-bit UNORM target.
layout(constant_id = 14) const uint OUTPUT = 0u;
#define OUTPUT_HDR 0u
#define OUTPUT_DISPLAY 1u
// The tone-mapping operator (TONEMAP_*) of the display output.
layout(constant_id = 15) const uint OUTPUT_TONEMAP = 0u;
// Clamp each channel to 1 first (the scene's "clamp" saturation, saturate.comp's clamp kernel).
layout(constant_id = 16) const bool OUTPUT_CLAMP = false;

#define SRGB_TABLE_SET SET_FRAME
#define SRGB_TABLE_BINDING BINDING_SRGB_TABLE
#include "srgb_lut.glsl"

vec4 forward_output(vec3 c) {
    if (OUTPUT != OUTPUT_DISPLAY) {
        return vec4(c, 1.0);
    }
    vec4 p = vec4(OUTPUT_CLAMP ? min(c, vec3(1.0)) : c, 1.0);
    vec3 m = display_map(p, frame.display.x, OUTPUT_TONEMAP);
    return vec4(srgb_encode_u8_lut(m.r), srgb_encode_u8_lut(m.g), srgb_encode_u8_lut(m.b), 255.0) / 255.0;
}

#endif
