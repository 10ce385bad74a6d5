#version 460
// The shadow pass for alpha-tested casters: no colour output, only a discard where the base
// colour's alpha (the material's factor × the base colour map's alpha × the vertex colour's alpha,
// as the forward pass's base_alpha) is below the cutoff, so the light passes through the cut-outs.
// The map is read at its full resolution (level 0), as the CPU reference's shadow rays read it:
// averaged mip levels would thin out a mask's coverage with the distance to the light.

#include "include/shadow_mask.glsl"

layout(set = SHADOW_MASK_SET, binding = SHADOW_MASK_MAP_BASE_COLOR) uniform sampler2D map_base_color;
layout(set = SHADOW_MASK_SET, binding = SHADOW_MASK_BINDING_EXTRA, std140) uniform MaterialExtra {
    vec4 emissive;
    vec4 params;    // normal_scale, occlusion_strength, alpha factor, alpha cutoff
    uvec4 present;
} mat_extra;

layout(location = 0) in vec2 in_uv;
layout(location = 1) in float in_alpha;

void main() {
    // Materials without a base colour map bind a white 1×1 texture (alpha 1).
    float alpha = mat_extra.params.z * in_alpha * textureLod(map_base_color, in_uv, 0.0).a;
    if (alpha < push.params.x) {
        discard;
    }
}
