#version 460
// The viewer's A/B map (compare.comp) through FLIP's magma palette, straight into the swapchain
// image (like display.frag): value / scale clamped to [0, 1], 256 sRGB colours
// (compare::color_of; the scale is the colour bar's top, computed on the GPU the same frame).

// Bindings (src/render/compare.rs reads them as luz::glsl::compare_show_frag::BINDING_*).
#define BINDING_MAP 0
#define BINDING_STATS 1
#define BINDING_PALETTE 2
layout(set = 0, binding = BINDING_MAP, r32f) uniform readonly image2D map_image;
#define STATS_SET 0
#define STATS_BINDING BINDING_STATS
#define STATS_SHOW
#include "include/compare_stats.glsl"
// compare::palette(): 0x00BBGGRR per entry.
layout(set = 0, binding = BINDING_PALETTE, std430) readonly buffer Palette {
    uint palette[256];
};

layout(location = 0) out vec4 out_color;

void main() {
    float v = imageLoad(map_image, ivec2(gl_FragCoord.xy)).r;
    float scale = stats.scale;
    // compare::color_of: NaN and ∞ are the top colour; with a zero scale, 0 is the bottom.
    float t = 1.0;
    if (v < 3.0e38) {
        t = scale > 0.0 ? clamp(v / scale, 0.0, 1.0) : (v <= 0.0 ? 0.0 : 1.0);
    }
    uint c = palette[uint(round(t * 255.0))];
    out_color = vec4(float(c & 0xFFu), float((c >> 8) & 0xFFu), float((c >> 16) & 0xFFu), 255.0) / 255.0;
}
