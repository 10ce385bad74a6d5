#version 460
// Split sum, first factor (MODELS.md §7): the environment prefiltered with the GGX lobe of one
// roughness per mip, assuming n = v = r, weighted by n·l; PDF-based LOD on the source cube.
#include "../include/env.glsl"
#include "../brdf/sampling.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(set = 0, binding = 0) uniform samplerCube env;
layout(set = 0, binding = 1, rgba16f) uniform writeonly imageCube dst;
layout(push_constant) uniform Push {
    float roughness;
    uint size;  // of this mip
    uint samples;
    uint env_size;
} pc;

void main() {
    uvec3 id = gl_GlobalInvocationID;
    if (id.x >= pc.size || id.y >= pc.size) {
        return;
    }
    vec3 r = cube_dir(id.z, id.xy, pc.size);
    float alpha = pc.roughness * pc.roughness;
    if (alpha <= BRDF_ALPHA_MIN) {
        imageStore(dst, ivec3(id), vec4(textureLod(env, r, 0.0).rgb, 1.0));
        return;
    }
    vec3 t;
    vec3 b;
    basis(r, t, b);
    vec3 sum = vec3(0.0);
    float weight = 0.0;
    for (uint i = 0u; i < pc.samples; ++i) {
        vec2 u = hammersley(i, pc.samples);
        vec3 hs = importance_sample_ggx(u.x, u.y, alpha);
        vec3 h = hs.x * t + hs.y * b + hs.z * r;
        vec3 l = 2.0 * dot(r, h) * h - r;
        float n_l = dot(r, l);
        if (n_l > 0.0) {
            // pdf(l) = D(h)(n·h)/(4 v·h) with n = v: D/4.
            float n_h = hs.z;
            float pdf = d_ggx(n_h, alpha) * 0.25;
            sum += textureLod(env, l, pdf_lod(pdf, pc.samples, pc.env_size)).rgb * n_l;
            weight += n_l;
        }
    }
    imageStore(dst, ivec3(id), vec4(weight > 0.0 ? sum / weight : vec3(0.0), 1.0));
}
