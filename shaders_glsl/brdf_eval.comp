#version 460
// Evaluates the GLSL BRDF mirror (brdf/models.glsl) at arbitrary inputs, one invocation per case,
// for `luz stability` (src/stability.rs): the same brdf_eval / brdf_radiance the renderer's
// forward pass calls, fed with directions no mesh produces (grazing, l = −v, zero or non-unit
// normals, degenerate tangents).
#include "brdf/models.glsl"

layout(local_size_x = 64) in;

// 96 bytes, std430: StabilityCase in src/stability.rs.
struct BrdfCase {
    vec4 n;     // xyz: normal (any length, zero included)
    vec4 l;     // xyz: towards the light
    vec4 v;     // xyz: towards the viewer
    vec4 x;     // xyz: tangent
    vec4 y;     // xyz: bitangent
    uvec4 meta; // x: index into params[]
};

// Bindings (src/stability/gpu.rs reads them as luz::glsl::brdf_eval_comp::BINDING_*).
#define BINDING_PARAMS 0
#define BINDING_CASES 1
#define BINDING_RESULTS 2
layout(std430, set = 0, binding = BINDING_PARAMS) readonly buffer Params {
    BrdfParams params[];
};
layout(std430, set = 0, binding = BINDING_CASES) readonly buffer Cases {
    BrdfCase cases[];
};
// with_radiance == 0: one vec4 per case (f); else four: f, then the radiance at e_light.x, .y, .z.
layout(std430, set = 0, binding = BINDING_RESULTS) writeonly buffer Results {
    vec4 results[];
};

layout(push_constant) uniform Push {
    vec4 e_light;        // three white-light irradiances
    uint base;           // first case of this dispatch
    uint count;          // cases in all
    uint with_radiance;  // 0 or 1
    uint pad;
} pc;

void main() {
    uint i = pc.base + gl_GlobalInvocationID.x;
    if (i >= pc.count) {
        return;
    }
    BrdfCase c = cases[i];
    BrdfParams p = params[c.meta.x];
    vec3 f = brdf_eval(p, c.n.xyz, c.l.xyz, c.v.xyz, c.x.xyz, c.y.xyz);
    if (pc.with_radiance == 0u) {
        results[i] = vec4(f, 0.0);
        return;
    }
    uint o = 4u * i;
    results[o] = vec4(f, 0.0);
    for (int k = 0; k < 3; ++k) {
        vec3 e = vec3(pc.e_light[k]);
        results[o + 1u + uint(k)] = vec4(brdf_radiance(p, c.n.xyz, c.l.xyz, c.v.xyz, c.x.xyz, c.y.xyz, e), 0.0);
    }
}
