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
//! variant gbuffer: SHADING_PHONG GBUFFER
//! variant gbuffer_tangent: SHADING_PHONG GBUFFER PHONG_TANGENT

// Phong shading interpolates only what the fragment stage reads: lavapipe sets up every triangle
// on the CPU, at a cost that grows with the number of outputs. Without PHONG_MAPS (no texture
// maps, a model without a tangent frame) that is the view depth, world position and normal; with
// it also the tangent and the texture coordinates. GBUFFER (the deferred path's geometry pass):
// only the view depth and the normal, and with PHONG_TANGENT the tangent's direction. VERTEX_COLOR (Phong with maps only): the vertex colours
// (binding 2) are interpolated too. PHONG_TANGENT (no maps, a material whose lobe reads the
// tangent frame: KHR_materials_anisotropy): the tangent's direction only, three floats.

#include "include/lighting.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
#if !defined(SHADING_PHONG) || defined(PHONG_MAPS)
layout(location = 2) in vec2 in_uv;
layout(location = 3) in vec4 in_tangent;
#elif defined(PHONG_TANGENT)
layout(location = 3) in vec4 in_tangent;
#endif
#ifdef SHADING_FLAT
layout(location = 4) in vec3 in_centroid;  // triangle centroid, object space (binding 1)
#endif
#ifdef VERTEX_COLOR
layout(location = 5) in vec4 in_color;  // linear RGBA (binding 2)
layout(location = 5) out vec4 out_vertex_color;
#endif

layout(location = 0) out float out_depth;  // view-space depth, for depth cueing
#if defined(SHADING_FLAT) || defined(SHADING_GOURAUD)
// Texture coordinates for the fragment stage's alpha (the base colour map's cut-outs and blending
// are per pixel whatever the shading frequency); unused, and dropped, with ALPHA_OPAQUE.
layout(location = 4) out vec2 out_alpha_uv;
#endif
#if defined(SHADING_FLAT)
layout(location = 1) flat out vec3 out_color;
#elif defined(SHADING_GOURAUD)
layout(location = 1) out vec3 out_color;
#elif defined(GBUFFER)
layout(location = 2) out vec3 out_normal;
#ifdef PHONG_TANGENT
layout(location = 3) out vec3 out_tangent;
#endif
#else
layout(location = 1) out vec3 out_world;
layout(location = 2) out vec3 out_normal;
#ifdef PHONG_MAPS
layout(location = 3) out vec4 out_tangent;
layout(location = 4) out vec2 out_uv;
#elif defined(PHONG_TANGENT)
layout(location = 3) out vec3 out_tangent;
#endif
#endif

void main() {
    ObjectData obj = objects[instances[gl_InstanceIndex]];
    vec4 world = obj.model * vec4(in_position, 1.0);
    vec4 view_pos = frame.view * world;
    out_depth = -view_pos.z;
    gl_Position = frame.proj * view_pos;
    vec3 n = normalize(mat3(obj.normal_matrix) * in_normal);
#if !defined(SHADING_PHONG) || defined(PHONG_MAPS)
    vec4 t = vec4(mat3(obj.model) * in_tangent.xyz, in_tangent.w);
#endif
#ifdef VERTEX_COLOR
    out_vertex_color = in_color;
#endif
#if defined(SHADING_FLAT) || defined(SHADING_GOURAUD)
    out_alpha_uv = in_uv;
    // Double-sided materials light a back face with the flipped normal: in the vertex stage, the
    // side of the (face, for flat shading) normal the camera is on decides.
    if (dot(n, frame.camera_pos.xyz - world.xyz * frame.camera_pos.w) < 0.0 && opaque(material.double_sided) != 0u) {
        n = -n;
        t = vec4(-t.xyz, t.w);
    }
#endif
#if defined(SHADING_FLAT)
    // Lighting once per polygon, at its centroid, with the face normal.
    vec3 c = (obj.model * vec4(in_centroid, 1.0)).xyz;
    vec3 x;
    vec3 y;
    tangent_frame(n, t, x, y);
    out_color = shade(c, n, x, y, in_uv);
#elif defined(SHADING_GOURAUD)
    vec3 x;
    vec3 y;
    tangent_frame(n, t, x, y);
    out_color = shade(world.xyz, n, x, y, in_uv);
#elif defined(GBUFFER)
    out_normal = n;
#ifdef PHONG_TANGENT
    out_tangent = mat3(obj.model) * in_tangent.xyz;
#endif
#else
    out_world = world.xyz;
    out_normal = n;
#ifdef PHONG_MAPS
    out_tangent = t;
    out_uv = in_uv;
#elif defined(PHONG_TANGENT)
    out_tangent = mat3(obj.model) * in_tangent.xyz;
#endif
#endif
}
