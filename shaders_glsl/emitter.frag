#version 460
// Area-light emitters seen by the camera (issue 36; emitter.vert): the radiance L = colour ·
// intensity, depth cued as a surface at that depth, through the same output as forward.frag (the
// HDR target, or display codes with exposure and tone map).
#include "include/lighting.glsl"
#include "include/output.glsl"

layout(location = 0) in float in_depth;
layout(location = 1) flat in vec3 in_radiance;
layout(location = 0) out vec4 out_color;

void main() {
    out_color = forward_output(apply_fog(in_radiance, in_depth));
}
