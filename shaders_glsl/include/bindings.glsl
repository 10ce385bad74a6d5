// Descriptor sets, bindings, push constants and specialization constants of the forward pass.
// Mirrored in src/render/gpu.rs (the constants and the #[repr(C)] structs); keep both in step.
#ifndef LUZ_BINDINGS_GLSL
#define LUZ_BINDINGS_GLSL

#define SET_FRAME 0
#define BINDING_FRAME 0
#define BINDING_LIGHTS 1
#define BINDING_OBJECTS 2

// Light types and falloff kinds (src/render/gpu.rs: LIGHT_*, FALLOFF_*).
#define LIGHT_DIRECTIONAL 0u
#define LIGHT_POINT 1u
#define LIGHT_SPOT 2u
#define FALLOFF_NONE 0u
#define FALLOFF_INVERSE_SQUARE 1u
#define FALLOFF_CLASSIC 2u

#include "../brdf/models.glsl"

layout(set = SET_FRAME, binding = BINDING_FRAME, std140) uniform FrameData {
    mat4 view;
    mat4 proj;
    mat4 view_proj;
    vec4 camera_pos;  // xyz
    vec4 ambient;     // rgb: I_a (classic) or uniform ambient radiance (physically based)
    vec4 fog_color;   // rgb: I_F
    vec4 fog;         // z_a, z_b, s_a, s_b
    uvec4 counts;     // x: number of lights
    mat4 inv_view_proj;
} frame;

struct Light {
    vec4 position_type;      // xyz position, w = type (as float)
    vec4 direction_falloff;  // xyz unit travel direction, w = falloff kind
    vec4 radiance;           // rgb = colour * intensity, w unused
    vec4 atten;              // c1, c2, c3, spot exponent
    vec4 cone;               // cos(umbra), cos(inner), smooth (1) or hard (0) edge, unused
};

layout(set = SET_FRAME, binding = BINDING_LIGHTS, std430) readonly buffer Lights {
    Light lights[];
};

struct ObjectData {
    mat4 model;
    mat4 normal_matrix;  // inverse-transpose of the model matrix's upper 3x3, in a mat4
};

layout(set = SET_FRAME, binding = BINDING_OBJECTS, std430) readonly buffer Objects {
    ObjectData objects[];
};

// Per-material maps (set 2; src/render/material.rs): one sampler per TextureSlot, in
// TextureSlot::ALL order, neutral 1×1 textures where a material has no map.
#define SET_MATERIAL 2
#define MAP_BASE_COLOR 0
#define MAP_SPECULAR 1
#define MAP_METALLIC 2
#define MAP_ROUGHNESS 3
#define MAP_ORM 4
#define MAP_NORMAL 5
#define MAP_OCCLUSION 6
#define MAP_EMISSIVE 7
layout(set = SET_MATERIAL, binding = 0) uniform sampler2D map_base_color;
layout(set = SET_MATERIAL, binding = 1) uniform sampler2D map_specular;
layout(set = SET_MATERIAL, binding = 2) uniform sampler2D map_metallic;
layout(set = SET_MATERIAL, binding = 3) uniform sampler2D map_roughness;
layout(set = SET_MATERIAL, binding = 4) uniform sampler2D map_orm;
layout(set = SET_MATERIAL, binding = 5) uniform sampler2D map_normal;
layout(set = SET_MATERIAL, binding = 6) uniform sampler2D map_occlusion;
layout(set = SET_MATERIAL, binding = 7) uniform sampler2D map_emissive;
layout(set = SET_MATERIAL, binding = 8, std140) uniform MaterialExtra {
    vec4 emissive;  // rgb emission factor
    vec4 params;    // normal_scale, occlusion_strength
    uvec4 present;  // x: bit MAP_* set when that map exists
} mat_extra;

// Per-material parameters (128 bytes at most; src/render/gpu.rs: MaterialPush): the packed BRDF
// parameters of src/brdf/gpu.rs (slot table in docs/brdf.md), then the object's index.
layout(push_constant) uniform MaterialPush {
    BrdfParams brdf;
    uint object_index;
    uint flags;
    uint reserved0;
    uint reserved1;
} material;

// The material model (BRDF_MODEL_*), fixed per pipeline so the driver compiles only that model.
layout(constant_id = 0) const int MODEL = BRDF_MODEL_BLINN_PHONG;
layout(constant_id = 1) const bool FOG = false;
// Debug view (src/render/forward.rs: DebugView): 0 = shaded radiance.
layout(constant_id = 7) const uint DEBUG_VIEW = 0u;
// The material's distribution, geometry and Fresnel selectors (BrdfParams.sel.yzw) fixed per
// pipeline, so only the chosen terms are compiled; -1: read them from the push constants.
layout(constant_id = 8) const int SEL_DISTRIBUTION = -1;
layout(constant_id = 9) const int SEL_GEOMETRY = -1;
layout(constant_id = 10) const int SEL_FRESNEL = -1;
// Bit MAP_* set when the material may have that map (0: no texture code at all).
layout(constant_id = 11) const uint MAPS = 0xFFu;
// The light types and falloffs the scene uses (LK_* bits): code for the others is left out.
layout(constant_id = 12) const uint LIGHT_KINDS = 63u;
// The material's diffuse selector (BRDF_DIFFUSE_*, BrdfParams.p0.y of Cook-Torrance and
// metal-rough) fixed per pipeline; -1: read it from the push constants.
layout(constant_id = 13) const int SEL_DIFFUSE = -1;
#define LK_DIRECTIONAL 1u
#define LK_POINT 2u
#define LK_SPOT 4u
#define LK_FALLOFF_NONE 8u
#define LK_FALLOFF_INVERSE_SQUARE 16u
#define LK_FALLOFF_CLASSIC 32u
#define DEBUG_NAN 13u

#endif
