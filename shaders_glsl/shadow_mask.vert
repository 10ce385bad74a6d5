#version 460
//! variant plain:
//! variant color: VERTEX_COLOR
// The shadow pass for alpha-tested casters (MASK and BLEND materials): as shadow.vert, and the
// texture coordinates and the vertex colour's alpha for shadow_mask.frag. `color`: meshes with
// vertex colours (binding 2, linear RGBA); `plain`: without (alpha 1).

#include "include/shadow_mask.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 2) in vec2 in_uv;
#ifdef VERTEX_COLOR
layout(location = 5) in vec4 in_color;
#endif

layout(location = 0) out vec2 out_uv;
layout(location = 1) out float out_alpha;

void main() {
    gl_Position = push.clip_from_object * vec4(in_position, 1.0);
    out_uv = in_uv;
#ifdef VERTEX_COLOR
    out_alpha = in_color.a;
#else
    out_alpha = 1.0;
#endif
}
