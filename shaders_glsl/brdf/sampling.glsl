// Low-discrepancy points and hemisphere sampling (MODELS.md §7): the GLSL mirror of the first
// functions of src/brdf/sampling.rs. Directions in a local frame with the normal along +z.
#ifndef LUZ_BRDF_SAMPLING_GLSL
#define LUZ_BRDF_SAMPLING_GLSL

#include "terms.glsl"

// Van der Corput radical inverse by integer bit reversal, 24 significant bits, in [0, 1).
float radical_inverse_vdc(uint i) {
    return float(bitfieldReverse(i) >> 8u) * (1.0 / 16777216.0);
}

// Hammersley point i of n: (i/n, radical_inverse(i)).
vec2 hammersley(uint i, uint n) {
    return vec2(float(i) / float(max(n, 1u)), radical_inverse_vdc(i));
}

// Cosine-weighted direction on the +z hemisphere (pdf cosθ/π).
vec3 sample_cosine_hemisphere(float u1, float u2) {
    float r = sqrt(clamp(u1, 0.0, 1.0));
    float phi = 2.0 * M_PI * u2;
    return vec3(r * cos(phi), r * sin(phi), sqrt(clamp(1.0 - u1, 0.0, 1.0)));
}

// GGX half vector: φ = 2π ξ1, cosθ_h = sqrt((1 − ξ2)/(1 + (α² − 1) ξ2)); pdf of h is D(h)(n·h).
vec3 importance_sample_ggx(float xi1, float xi2, float alpha) {
    float a = max(alpha, BRDF_ALPHA_MIN);
    float phi = 2.0 * M_PI * xi1;
    float den = 1.0 + (a * a - 1.0) * xi2;
    float cos_t = sqrt(clamp((1.0 - xi2) / den, 0.0, 1.0));
    // sin² = α² ξ2 / den, not 1 − cos²: exact near the peak of a narrow lobe.
    float sin_t = sqrt(clamp(a * a * xi2 / den, 0.0, 1.0));
    return vec3(sin_t * cos(phi), sin_t * sin(phi), cos_t);
}

// A visible normal of the anisotropic GGX lobe (ax, ay) seen from v (+z normal), Heitz 2018:
// its pdf is G1(v) max(v·h, 0) D(h) / (n·v). Mirror of sample_ggx_vndf_aniso in
// src/brdf/aniso_split_sum.rs.
vec3 sample_ggx_vndf_aniso(vec3 v, float ax, float ay, float u1, float u2) {
    vec3 vh = normalize(vec3(ax * v.x, ay * v.y, v.z));
    float len2 = vh.x * vh.x + vh.y * vh.y;
    vec3 t1 = len2 > 0.0 ? vec3(-vh.y, vh.x, 0.0) / sqrt(len2) : vec3(1.0, 0.0, 0.0);
    vec3 t2 = cross(vh, t1);
    float r = sqrt(u1);
    float phi = 2.0 * M_PI * u2;
    float p1 = r * cos(phi);
    float s = 0.5 * (1.0 + vh.z);
    float p2 = (1.0 - s) * sqrt(max(1.0 - p1 * p1, 0.0)) + s * r * sin(phi);
    vec3 nh = t1 * p1 + t2 * p2 + vh * sqrt(max(1.0 - p1 * p1 - p2 * p2, 0.0));
    return normalize(vec3(ax * nh.x, ay * nh.y, max(nh.z, 0.0)));
}

#endif // LUZ_BRDF_SAMPLING_GLSL
