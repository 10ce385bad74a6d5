#version 460
// The environment as the background: the view ray through the pixel, looked up in the cube (an
// orthographic camera's rays are parallel: the environment along the view direction, one colour).
#define IBL
#include "include/lighting.glsl"
#include "include/output.glsl"

layout(location = 0) in vec2 in_ndc;
layout(location = 0) out vec4 out_color;

void main() {
    vec4 far = frame.inv_view_proj * vec4(in_ndc, 1.0, 1.0);
    // camera_pos: (eye, 1), or (−forward, 0) for an orthographic camera.
    vec3 dir = normalize(far.xyz / far.w * frame.camera_pos.w - frame.camera_pos.xyz);
    out_color = forward_output(textureLod(env_cube, dir, 0.0).rgb);
}
