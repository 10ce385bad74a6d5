#version 460
// Irradiance cube E(n) = ∫ L(l) max(n·l, 0) dl by cosine-weighted Hammersley sampling with
// mip-filtered (PDF-based LOD) lookups of the environment cube.
#include "../include/env.glsl"
#include "../brdf/sampling.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(set = 0, binding = 0) uniform samplerCube env;
layout(set = 0, binding = 1, rgba16f) uniform writeonly imageCube irradiance;
layout(push_constant) uniform Push {
    uint size;
    uint samples;
    uint env_size;
    uint pad;
} pc;

void main() {
    uvec3 id = gl_GlobalInvocationID;
    if (id.x >= pc.size || id.y >= pc.size) {
        return;
    }
    vec3 n = cube_dir(id.z, id.xy, pc.size);
    vec3 t;
    vec3 b;
    basis(n, t, b);
    vec3 sum = vec3(0.0);
    for (uint i = 0u; i < pc.samples; ++i) {
        vec2 u = hammersley(i, pc.samples);
        vec3 s = sample_cosine_hemisphere(u.x, u.y);
        vec3 l = s.x * t + s.y * b + s.z * n;
        float pdf = s.z / M_PI;
        sum += textureLod(env, l, pdf_lod(pdf, pc.samples, pc.env_size)).rgb;
    }
    // Estimator of ∫ L cos: (1/N) Σ L cos / (cos/π) = π/N Σ L.
    imageStore(irradiance, ivec3(id), vec4(sum * (M_PI / float(pc.samples)), 1.0));
}
