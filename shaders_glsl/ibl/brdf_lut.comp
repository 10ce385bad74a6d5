#version 460
// Split sum, second factor (MODELS.md §7): A, B over (n·v, roughness) so that the specular
// directional albedo is F0·A + B. GGX sampling of h with α = roughness²; Fc = (1 − v·h)^5;
// G_vis = G (v·h)/((n·h)(n·v)) with the G the material uses (one array layer per G).
#include "../brdf/models.glsl"
#include "../brdf/sampling.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(set = 0, binding = 0, rgba32f) uniform writeonly image2DArray lut;
layout(push_constant) uniform Push {
    uint size;
    uint samples;
    int geometry;  // BRDF_G_*
    uint layer;
} pc;

void main() {
    uvec2 id = gl_GlobalInvocationID.xy;
    if (id.x >= pc.size || id.y >= pc.size) {
        return;
    }
    float n_v = (float(id.x) + 0.5) / float(pc.size);
    float roughness = (float(id.y) + 0.5) / float(pc.size);
    float alpha = max(roughness * roughness, BRDF_ALPHA_MIN);
    vec3 v = vec3(sqrt(max(1.0 - n_v * n_v, 0.0)), 0.0, n_v);
    float a = 0.0;
    float b = 0.0;
    for (uint i = 0u; i < pc.samples; ++i) {
        vec2 u = hammersley(i, pc.samples);
        vec3 h = importance_sample_ggx(u.x, u.y, alpha);
        vec3 l = 2.0 * dot(v, h) * h - v;
        float n_l = l.z;
        float n_h = h.z;
        float v_h = dot(v, h);
        if (n_l > 0.0 && v_h > 0.0) {
            float g;
            if (pc.geometry == BRDF_G_SCHLICK_GGX) {
                g = g_schlick_ggx(n_l, n_v, k_ibl(roughness));
            } else {
                g = brdf_geometry(pc.geometry, n_h, n_v, n_l, v_h, alpha, roughness);
            }
            float g_vis = g * v_h / (n_h * n_v);
            float fc = pow(1.0 - v_h, 5.0);
            a += (1.0 - fc) * g_vis;
            b += fc * g_vis;
        }
    }
    imageStore(lut, ivec3(id, int(pc.layer)), vec4(a / float(pc.samples), b / float(pc.samples), 0.0, 1.0));
}
