// The shadow pass's alpha-tested casters (src/render/shadow/pipeline.rs: MaskPipelines): what
// shadow_mask.vert and shadow_mask.frag share. Set 2 is the forward pass's material set
// (src/render/material.rs; include/bindings.glsl declares the same bindings, which Rust asserts
// equal to these), bound unchanged: no texture is uploaded twice.
#ifndef LUZ_SHADOW_MASK_GLSL
#define LUZ_SHADOW_MASK_GLSL

#define SHADOW_MASK_SET 2
#define SHADOW_MASK_MAP_BASE_COLOR 0
#define SHADOW_MASK_BINDING_EXTRA 22

layout(push_constant) uniform ShadowMaskPush {
    mat4 clip_from_object;  // the layer's view-projection × the object's model matrix
    vec4 params;            // x: alpha cutoff (AlphaMode::shadow_cutoff: a mask's, 0.5 for BLEND)
} push;

#endif
