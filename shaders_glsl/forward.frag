#version 460
//! variant flat: SHADING_FLAT
//! variant gouraud: SHADING_GOURAUD
//! variant phong: SHADING_PHONG
//! variant flat_ibl: SHADING_FLAT IBL
//! variant gouraud_ibl: SHADING_GOURAUD IBL
//! variant phong_ibl: SHADING_PHONG IBL

#define LUZ_FRAGMENT
#include "include/lighting.glsl"

layout(location = 0) in float in_depth;
#if defined(SHADING_FLAT)
layout(location = 1) flat in vec3 in_color;
#elif defined(SHADING_GOURAUD)
layout(location = 1) in vec3 in_color;
#else
layout(location = 1) in vec3 in_world;
layout(location = 2) in vec3 in_normal;
layout(location = 3) in vec4 in_tangent;
layout(location = 4) in vec2 in_uv;
#endif

layout(location = 0) out vec4 out_color;

void main() {
#if defined(SHADING_FLAT) || defined(SHADING_GOURAUD)
    vec3 c = in_color;
#else
    vec3 n = normalize(in_normal);
    vec3 x;
    vec3 y;
    tangent_frame(n, in_tangent, x, y);
    vec3 c = shade(in_world, n, x, y, in_uv);
#endif
    c = apply_fog(c, in_depth);
    if (DEBUG_VIEW == DEBUG_VIEW_NAN && (any(isnan(c)) || any(isinf(c)))) {
        c = vec3(1.0, 0.0, 1.0);
    }
    out_color = vec4(c, 1.0);
}
