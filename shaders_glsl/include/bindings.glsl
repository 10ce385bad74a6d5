// Descriptor sets, bindings, push constants and specialization constants of the forward pass.
// The numbers here are the one source: build.rs turns every #define and constant_id into a Rust
// constant (src/render/gpu.rs: `glsl::include_bindings`); the #[repr(C)] structs are mirrored in
// src/render/gpu.rs and tested for size and offsets.
#ifndef LUZ_BINDINGS_GLSL
#define LUZ_BINDINGS_GLSL

#define SET_FRAME 0
#define BINDING_FRAME 0
#define BINDING_LIGHTS 1
#define BINDING_OBJECTS 2
// color::srgb_encode_table, read by the display output (include/output.glsl).
#define BINDING_SRGB_TABLE 3

// Light types and falloff kinds (src/render/gpu.rs: LIGHT_*, FALLOFF_*).
#define LIGHT_DIRECTIONAL 0u
#define LIGHT_POINT 1u
#define LIGHT_SPOT 2u
#define FALLOFF_NONE 0u
#define FALLOFF_INVERSE_SQUARE 1u
#define FALLOFF_CLASSIC 2u

// The layers of the glTF PBR extensions the pipeline's material uses (BRDF_LOBE_* bits of
// brdf/models.glsl; src/render/forward/variant.rs: VariantKey::lobes): the others compile out.
layout(constant_id = 23) const uint LOBES = 0u;
#define BRDF_LOBES LOBES
#include "../brdf/models.glsl"

layout(set = SET_FRAME, binding = BINDING_FRAME, std140) uniform FrameData {
    mat4 view;
    mat4 proj;
    mat4 view_proj;
    vec4 camera_pos;  // (eye, 1); orthographic: (−forward, 0) (Camera::eye_homogeneous)
    vec4 ambient;     // rgb: I_a (classic) or uniform ambient radiance (physically based)
    vec4 fog_color;   // rgb: I_F
    vec4 fog;         // z_a, z_b, s_a, s_b
    uvec4 counts;     // x: number of lights; y: area lights, z: the first's vec4 in area_data
    mat4 inv_view_proj;
    vec4 display;     // x: color::exposure_scale(ev) of the display output (include/output.glsl)
} frame;

struct Light {
    vec4 position_type;      // xyz position, w = type (as float)
    vec4 direction_falloff;  // xyz unit travel direction, w = falloff kind
    vec4 radiance;           // rgb = colour * intensity, w unused
    vec4 atten;              // c1, c2, c3, spot exponent
    vec4 cone;               // cos(umbra), cos(inner), smooth (1) or hard (0) edge, range (0: none)
};

layout(set = SET_FRAME, binding = BINDING_LIGHTS, std430) readonly buffer Lights {
    Light lights[];
};

// lavapipe 22.3 inlines a uniform (UBO or push-constant value) that alone decides a branch or a
// loop's trip count and then compiles, and leaks, a shader variant at every bind whenever that
// does not shrink the shader by half (docs/shadows.md: ~5 MB per shadowed frame). Such values go
// through opaque(): the identity for every u < 0xFFFF0000, bound to the lights buffer's length,
// which is not a uniform. Conditions that also test a per-pixel value need nothing (as long as
// they are not split by `&&`: use all()).
uint opaque(uint u) {
    return min(u, uint(lights.length()) | 0xFFFF0000u);
}

// Area lights (include/area.glsl; src/render/gpu.rs: area_data): the LTC table for GGX
// (src/brdf/ltc.rs: LTC_SIZE² entries of two vec4) when the scene has an LTC light, then
// AREA_VEC4S vec4 per light from frame.counts.z; frame.counts.y lights.
#define BINDING_AREA 8
layout(set = SET_FRAME, binding = BINDING_AREA, std430) readonly buffer AreaData {
    vec4 area_data[];
};
#define LTC_SIZE 64
#define AREA_VEC4S 5u
#define AREA_RECT 0u
#define AREA_DISK 1u
#define AREA_SPHERE 2u
#define AREA_TUBE 3u
#define AREA_LTC 0u
#define AREA_RP 1u
#define AREA_SAMPLED 2u

struct ObjectData {
    mat4 model;
    mat4 normal_matrix;  // inverse-transpose of the model matrix's upper 3x3, in a mat4
};

layout(set = SET_FRAME, binding = BINDING_OBJECTS, std430) readonly buffer Objects {
    ObjectData objects[];
};

// Per slot, in the slot's draw order: the object (index into objects[]) of each instance. A draw
// of N objects sharing mesh, LOD level, pipeline and material is one instanced draw whose
// firstInstance is its first entry here (src/render/forward/instances.rs), so the vertex stage
// reads objects[instances[gl_InstanceIndex]].
#define BINDING_INSTANCES 7
layout(set = SET_FRAME, binding = BINDING_INSTANCES, std430) readonly buffer Instances {
    uint instances[];
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
#define MAP_TRANSMISSION 8
#define MAP_THICKNESS 9
#define MAP_DIFFUSE_TRANSMISSION 10
#define MAP_DIFFUSE_TRANSMISSION_COLOR 11
#define MAP_ANISOTROPY 12
#define MAP_CLEARCOAT 13
#define MAP_CLEARCOAT_ROUGHNESS 14
#define MAP_SHEEN_COLOR 15
#define MAP_SHEEN_ROUGHNESS 16
#define MAP_SPECULAR_FACTOR 17
#define MAP_SPECULAR_COLOR 18
#define MAP_IRIDESCENCE 19
#define MAP_IRIDESCENCE_THICKNESS 20
#define MAP_CLEARCOAT_NORMAL 21
#define BINDING_MATERIAL_EXTRA 22
layout(set = SET_MATERIAL, binding = MAP_BASE_COLOR) uniform sampler2D map_base_color;
layout(set = SET_MATERIAL, binding = MAP_SPECULAR) uniform sampler2D map_specular;
layout(set = SET_MATERIAL, binding = MAP_METALLIC) uniform sampler2D map_metallic;
layout(set = SET_MATERIAL, binding = MAP_ROUGHNESS) uniform sampler2D map_roughness;
layout(set = SET_MATERIAL, binding = MAP_ORM) uniform sampler2D map_orm;
layout(set = SET_MATERIAL, binding = MAP_NORMAL) uniform sampler2D map_normal;
layout(set = SET_MATERIAL, binding = MAP_OCCLUSION) uniform sampler2D map_occlusion;
layout(set = SET_MATERIAL, binding = MAP_EMISSIVE) uniform sampler2D map_emissive;
layout(set = SET_MATERIAL, binding = MAP_TRANSMISSION) uniform sampler2D map_transmission;
layout(set = SET_MATERIAL, binding = MAP_THICKNESS) uniform sampler2D map_thickness;
layout(set = SET_MATERIAL, binding = MAP_DIFFUSE_TRANSMISSION) uniform sampler2D map_diffuse_transmission;
layout(set = SET_MATERIAL, binding = MAP_DIFFUSE_TRANSMISSION_COLOR) uniform sampler2D map_diffuse_transmission_color;
layout(set = SET_MATERIAL, binding = MAP_ANISOTROPY) uniform sampler2D map_anisotropy;
layout(set = SET_MATERIAL, binding = MAP_CLEARCOAT) uniform sampler2D map_clearcoat;
layout(set = SET_MATERIAL, binding = MAP_CLEARCOAT_ROUGHNESS) uniform sampler2D map_clearcoat_roughness;
layout(set = SET_MATERIAL, binding = MAP_SHEEN_COLOR) uniform sampler2D map_sheen_color;
layout(set = SET_MATERIAL, binding = MAP_SHEEN_ROUGHNESS) uniform sampler2D map_sheen_roughness;
layout(set = SET_MATERIAL, binding = MAP_SPECULAR_FACTOR) uniform sampler2D map_specular_factor;
layout(set = SET_MATERIAL, binding = MAP_SPECULAR_COLOR) uniform sampler2D map_specular_color;
layout(set = SET_MATERIAL, binding = MAP_IRIDESCENCE) uniform sampler2D map_iridescence;
layout(set = SET_MATERIAL, binding = MAP_IRIDESCENCE_THICKNESS) uniform sampler2D map_iridescence_thickness;
layout(set = SET_MATERIAL, binding = MAP_CLEARCOAT_NORMAL) uniform sampler2D map_clearcoat_normal;
#ifndef LUZ_DEFERRED
layout(set = SET_MATERIAL, binding = BINDING_MATERIAL_EXTRA, std140) uniform MaterialExtra {
    vec4 emissive;  // rgb emission factor
    vec4 params;    // normal_scale, occlusion_strength, alpha factor, alpha cutoff
    uvec4 present;  // x: bit MAP_* set when that map exists
    // Glass (include/transmission.glsl; src/render/material.rs: MaterialExtra::glass):
    vec4 volume;        // thickness (mesh units), dispersion, iridescence thickness minimum (nm), -
    vec4 attenuation;   // rgb: σ per unit length (KHR_materials_volume), w: clear coat normal scale
    vec4 diffuse_transmission;  // rgb: diffuseTransmissionColorFactor, -
} mat_extra;

// Per-material parameters (128 bytes at most; src/render/gpu.rs: MaterialPush): the packed BRDF
// parameters of src/brdf/gpu.rs (slot table in docs/brdf.md), then the object slot of the draw's
// deferred material (the first instance's: every instance of a draw has the same material data;
// the vertex stage finds each instance's object through instances[] above).
layout(push_constant) uniform MaterialPush {
    BrdfParams brdf;
    uint object_index;
    uint flags;
    uint receive_shadow;  // 1: the shadow maps darken this object
    uint double_sided;    // 1: a back face is lit with the flipped normal (glTF doubleSided)
} material;
#else
// The deferred lighting pass (deferred_light.frag) shades every pixel in one draw: the same two
// blocks, as globals it fills per pixel from the per-object array below (src/render/gpu.rs:
// DeferredMaterial) before calling shade().
struct MaterialExtraData {
    vec4 emissive;
    vec4 params;
    uvec4 present;
    vec4 volume;
    vec4 attenuation;
    vec4 diffuse_transmission;
};
struct MaterialPushData {
    BrdfParams brdf;
    uint object_index;
    uint flags;
    uint receive_shadow;
    uint double_sided;
};
MaterialExtraData mat_extra;
MaterialPushData material;
#endif
// Per object slot: its material's push constants and extra block, for the deferred lighting pass.
#define BINDING_DEFERRED_MATERIALS 4
// Clustered light culling (src/render/forward/clusters.rs): the grid and each cluster's
// (base, count), then (with area lights) each cluster's area (base, count); and the light index
// list (lights without a range first, in every cluster; then area lights without a range).
#define BINDING_CLUSTERS 5
#define BINDING_CLUSTER_LIGHTS 6
#ifdef LUZ_FRAGMENT
layout(set = SET_FRAME, binding = BINDING_CLUSTERS, std430) readonly buffer Clusters {
    uvec4 cluster_dims;   // tiles x, tiles y, depth slices, lights in every cluster
    vec4 cluster_xy;      // column = floor(x/d · x + y), row = floor(y/d · z + w); view space, d = −z
    vec4 cluster_depth;   // slice = floor(ln d · x + y); z = 1: orthographic (x, y for x/d, y/d)
    uvec4 cluster_area;   // area lights in every cluster, where they start in cluster_lights
    // (base, count): light k is cluster_lights[k < always ? k : base + k]; clusters[cells + i]:
    // cluster i's area lights, area light k is cluster_lights[k < x ? y + k : base + k] (x, y
    // of cluster_area).
    uvec2 clusters[];
};
layout(set = SET_FRAME, binding = BINDING_CLUSTER_LIGHTS, std430) readonly buffer ClusterLights {
    uint cluster_lights[];
};
#endif

// The material model (BRDF_MODEL_*), fixed per pipeline so the driver compiles only that model.
layout(constant_id = 0) const int MODEL = BRDF_MODEL_BLINN_PHONG;
layout(constant_id = 1) const bool FOG = false;
// Debug view (src/render/forward.rs: DebugView, codes DEBUG_VIEW_*): 0 = shaded radiance.
layout(constant_id = 7) const uint DEBUG_VIEW = 0u;
#define DEBUG_VIEW_NONE 0u
#define DEBUG_VIEW_BASE_COLOR 1u
#define DEBUG_VIEW_NORMAL 2u
#define DEBUG_VIEW_METALLIC 3u
#define DEBUG_VIEW_ROUGHNESS 4u
#define DEBUG_VIEW_AO 5u
#define DEBUG_VIEW_D 6u
#define DEBUG_VIEW_G 7u
#define DEBUG_VIEW_F 8u
#define DEBUG_VIEW_DIFFUSE 9u
#define DEBUG_VIEW_SPECULAR 10u
#define DEBUG_VIEW_IRRADIANCE 11u
#define DEBUG_VIEW_PREFILTERED 12u
#define DEBUG_VIEW_NAN 13u
#define DEBUG_VIEW_CLUSTERS 14u
#define DEBUG_VIEW_SHADOW 15u
#define DEBUG_VIEW_SHADOW_LAYERS 16u
// The material's distribution, geometry and Fresnel selectors (BrdfParams.sel.yzw) fixed per
// pipeline, so only the chosen terms are compiled; -1: read them from the push constants.
layout(constant_id = 8) const int SEL_DISTRIBUTION = -1;
layout(constant_id = 9) const int SEL_GEOMETRY = -1;
layout(constant_id = 10) const int SEL_FRESNEL = -1;
// Bit MAP_* set when the material may have that map (0: no texture code at all).
layout(constant_id = 11) const uint MAPS = 0xFFu;
// The light types and falloffs the scene uses (LK_* bits): code for the others is left out.
layout(constant_id = 12) const uint LIGHT_KINDS = 524287u;
// The material's diffuse selector (BRDF_DIFFUSE_*, BrdfParams.p0.y of Cook-Torrance and
// metal-rough) fixed per pipeline; -1: read it from the push constants.
layout(constant_id = 13) const int SEL_DIFFUSE = -1;
// glTF's alphaMode (src/scene/textures.rs: AlphaMode): ALPHA_OPAQUE ignores alpha, ALPHA_MASK
// discards fragments whose alpha is below the cutoff (MaterialExtra.params.w), ALPHA_BLEND writes
// alpha for the pipeline's "over" blending. Alpha = MaterialExtra.params.z × the base colour map's
// alpha × the vertex colour's alpha.
layout(constant_id = 18) const uint ALPHA_MODE = 0u;
#define ALPHA_OPAQUE 0u
#define ALPHA_MASK 1u
#define ALPHA_BLEND 2u
// The fragment stage loops over its cluster's lights only (Clusters above) instead of all of them;
// the vertex stage (flat, Gouraud) always loops over all.
layout(constant_id = 17) const bool CLUSTERED = false;
#define LK_DIRECTIONAL 1u
#define LK_POINT 2u
#define LK_SPOT 4u
#define LK_FALLOFF_NONE 8u
#define LK_FALLOFF_INVERSE_SQUARE 16u
#define LK_FALLOFF_CLASSIC 32u
// Some point or spot light has a range (Light.cone.w > 0): the range window applies.
#define LK_RANGE 64u
// Some light has a shadow filtered this way (include/shadows.glsl); none: no shadow code at all.
#define LK_SHADOW_HARD 128u
#define LK_SHADOW_PCF 256u
#define LK_SHADOW_PCSS 512u
// Some area light is shaded by this method (include/area.glsl); none: no area-light code at all.
// LK_AREA_LTC: a rect, disk or sphere by LTC (the polygon form); LK_AREA_LTC_TUBE: a tube by LTC
// (its facing ribbon's polygon and end disks).
#define LK_AREA_LTC 1024u
#define LK_AREA_RP 2048u
#define LK_AREA_SAMPLED 4096u
#define LK_AREA_LTC_TUBE 524288u
#define LK_AREA (LK_AREA_LTC | LK_AREA_RP | LK_AREA_SAMPLED | LK_AREA_LTC_TUBE)
// Some area light has this shape (rects need no bit: their code is the smallest).
#define LK_AREA_SPHERE 8192u
#define LK_AREA_TUBE 16384u
#define LK_AREA_DISK 32768u
// Some area light has a shadow filtered this way (include/area.glsl: area_shadow; the punctual
// lights' LK_SHADOW_* bits shifted left by LK_AREA_SHADOW_SHIFT); none: no area shadow code.
#define LK_AREA_SHADOW_HARD 65536u
#define LK_AREA_SHADOW_PCF 131072u
#define LK_AREA_SHADOW_PCSS 262144u
#define LK_AREA_SHADOW_SHIFT 9u

// Glass (include/transmission.glsl): the copy of the opaque scene's HDR colour, with its mips,
// that transmissive draws sample (a 1×1 stand-in when the scene has none), and how
// (src/scene: Refraction; REFRACTION_* codes).
#define BINDING_TRANSMISSION 9
layout(constant_id = 24) const uint REFRACTION = 0u;
#define REFRACTION_SCREEN 0u
#define REFRACTION_SCREEN_FILAMENT 1u
#define REFRACTION_SCREEN_SHARP 2u
#define REFRACTION_THIN 3u
#define REFRACTION_NONE 4u
#define REFRACTION_ENVIRONMENT 5u

#endif
