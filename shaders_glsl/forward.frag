#version 460
//! variant flat: SHADING_FLAT
//! variant gouraud: SHADING_GOURAUD
//! variant phong: SHADING_PHONG
//! variant phong_maps: SHADING_PHONG PHONG_MAPS
//! variant flat_ibl: SHADING_FLAT IBL
//! variant gouraud_ibl: SHADING_GOURAUD IBL
//! variant phong_ibl: SHADING_PHONG IBL
//! variant phong_maps_ibl: SHADING_PHONG PHONG_MAPS IBL
//! variant phong_maps_color: SHADING_PHONG PHONG_MAPS VERTEX_COLOR
//! variant phong_maps_color_ibl: SHADING_PHONG PHONG_MAPS VERTEX_COLOR IBL
//! variant phong_tangent: SHADING_PHONG PHONG_TANGENT
//! variant phong_tangent_ibl: SHADING_PHONG PHONG_TANGENT IBL

#define LUZ_FRAGMENT
#include "include/lighting.glsl"
#include "include/output.glsl"

layout(location = 0) in float in_depth;
#if defined(SHADING_FLAT)
layout(location = 1) flat in vec3 in_color;
layout(location = 4) in vec2 in_alpha_uv;
#elif defined(SHADING_GOURAUD)
layout(location = 1) in vec3 in_color;
layout(location = 4) in vec2 in_alpha_uv;
#else
layout(location = 1) in vec3 in_world;
layout(location = 2) in vec3 in_normal;
#ifdef PHONG_MAPS
layout(location = 3) in vec4 in_tangent;
layout(location = 4) in vec2 in_uv;
#elif defined(PHONG_TANGENT)
layout(location = 3) in vec3 in_tangent;
#endif
#endif
#ifdef VERTEX_COLOR
layout(location = 5) in vec4 in_vertex_color;
#endif

layout(location = 0) out vec4 out_color;

void main() {
#ifdef VERTEX_COLOR
    g_vertex_color = in_vertex_color;
#endif
#ifdef PHONG_MAPS
    vec2 uv = in_uv;
#elif defined(SHADING_FLAT) || defined(SHADING_GOURAUD)
    // Flat and Gouraud shading light per polygon or vertex but cut out and blend per pixel:
    // the factor × the base colour map's alpha (they have no vertex colours).
    vec2 uv = in_alpha_uv;
#else
    // Lean Phong (no maps) reads the alpha factor only.
    const vec2 uv = vec2(0.0);
#endif
    float alpha = 1.0;
    if (ALPHA_MODE != ALPHA_OPAQUE) {
#if defined(PHONG_MAPS) || defined(SHADING_FLAT) || defined(SHADING_GOURAUD)
        alpha = base_alpha(uv);
#else
        alpha = mat_extra.params.z;
#endif
        if (ALPHA_MODE == ALPHA_MASK) {
            if (alpha < uintBitsToFloat(opaque(floatBitsToUint(mat_extra.params.w)))) {
                discard;
            }
            alpha = 1.0;
        }
    }
#if defined(SHADING_FLAT) || defined(SHADING_GOURAUD)
    vec3 c = in_color;
#else
    vec3 n = normalize(in_normal);
    vec3 x;
    vec3 y;
#ifdef PHONG_MAPS
    tangent_frame(n, in_tangent, x, y);
#elif defined(PHONG_TANGENT)
    // The anisotropic lobe reads the tangent's direction; the bitangent's sign does not matter
    // to it (it uses squares of b·h, b·l, b·v).
    tangent_frame(n, vec4(in_tangent, 1.0), x, y);
#else
    // No maps and a model without a tangent frame: any frame around n (unused by the model).
    tangent_frame(n, vec4(0.0, 0.0, 0.0, 1.0), x, y);
#endif
    // Double-sided materials: a back face is lit with the flipped normal and tangent frame.
    if (!gl_FrontFacing && opaque(material.double_sided) != 0u) {
        n = -n;
        x = -x;
        y = -y;
    }
    vec3 c = shade(in_world, n, x, y, uv);
#endif
    c = apply_fog(c, in_depth);
    if (DEBUG_VIEW == DEBUG_VIEW_NAN && (any(isnan(c)) || any(isinf(c)))) {
        c = vec3(1.0, 0.0, 1.0);
    }
    out_color = forward_output(c);
    if (ALPHA_MODE == ALPHA_BLEND) {
        out_color.a = alpha;
    }
}
