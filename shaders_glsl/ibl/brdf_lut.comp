#version 460
// Split sum, second factor (MODELS.md §7): A, B over (n·v, roughness) so that the specular
// directional albedo is F0·A + B, and the lobe's v·h mean and deviation (μ, σ). Visible normals h of the GGX lobe with α = roughness² seen
// from v (Heitz 2018), weight G/G1(v) with the G the material uses (one array layer per G);
// Fc = (1 − v·h)^5. The same computation as split_sum_lut_reference in src/brdf/split_sum.rs.
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
    // Texel i holds i/(size − 1): 0 and 1 included (lut_node; read at lut_uv in ibl.glsl).
    float last = float(max(pc.size, 2u) - 1u);
    float n_v = max(float(id.x) / last, 1e-4);
    float roughness = float(id.y) / last;
    float alpha = max(roughness * roughness, BRDF_ALPHA_MIN);
    vec3 v = vec3(sqrt(max(1.0 - n_v * n_v, 0.0)), 0.0, n_v);
    float g1 = 2.0 * n_v / (n_v + length(vec3(alpha * v.x, 0.0, n_v)));
    float a = 0.0;
    float b = 0.0;
    float m1 = 0.0;
    float m2 = 0.0;
    for (uint i = 0u; i < pc.samples; ++i) {
        // lut_point: the Hammersley point in the middle of its stratum.
        vec2 u = vec2((float(i) + 0.5) / float(pc.samples), radical_inverse_vdc(i));
        vec3 h = sample_ggx_vndf_aniso(v, alpha, alpha, u.x, u.y);
        vec3 l = 2.0 * dot(v, h) * h - v;
        float n_l = l.z;
        float n_h = h.z;
        float v_h = dot(v, h);
        if (n_l > 0.0 && v_h > 0.0 && n_h > 0.0) {
            float g;
            if (pc.geometry == BRDF_G_SCHLICK_GGX) {
                g = g_schlick_ggx(n_l, n_v, k_ibl(roughness));
            } else {
                g = brdf_geometry(pc.geometry, n_h, n_v, n_l, v_h, alpha, roughness);
            }
            float w = g / g1;
            float fc = pow(1.0 - v_h, 5.0);
            a += (1.0 - fc) * w;
            b += fc * w;
            // About n·v (the mirror's v·h), so that a narrow lobe's variance does not cancel in
            // f32 (the plain second moment lost σ to 2.6e-3 at roughness 0.05).
            float d = v_h - n_v;
            m1 += d * w;
            m2 += d * d * w;
        }
    }
    // The lobe's v·h under the same weight: mean and standard deviation (split_sum_lut_moments).
    float e = a + b;
    float d_mean = e > 0.0 ? m1 / e : 0.0;
    float mu = e > 0.0 ? n_v + d_mean : 1.0;
    float sd = e > 0.0 ? sqrt(max(m2 / e - d_mean * d_mean, 0.0)) : 0.0;
    imageStore(lut, ivec3(id, int(pc.layer)), vec4(a / float(pc.samples), b / float(pc.samples), mu, sd));
}
