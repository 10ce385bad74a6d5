// Environment helpers shared by the IBL precomputation kernels, the skybox and the forward pass:
// cube-face texel directions, the equirectangular mapping (mirrors src/env), and PDF-based LOD.
#ifndef LUZ_ENV_GLSL
#define LUZ_ENV_GLSL

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

// Direction through the centre of texel (x, y) of cube face `face` (Vulkan face order +x, −x, +y,
// −y, +z, −z; the same convention samplerCube uses).
vec3 cube_dir(uint face, uvec2 texel, uint size) {
    vec2 uv = (vec2(texel) + 0.5) / float(size) * 2.0 - 1.0;
    vec3 d;
    if (face == 0u) d = vec3(1.0, -uv.y, -uv.x);
    else if (face == 1u) d = vec3(-1.0, -uv.y, uv.x);
    else if (face == 2u) d = vec3(uv.x, 1.0, uv.y);
    else if (face == 3u) d = vec3(uv.x, -1.0, -uv.y);
    else if (face == 4u) d = vec3(uv.x, -uv.y, 1.0);
    else d = vec3(-uv.x, -uv.y, -1.0);
    return normalize(d);
}

// The mip level of the prefiltered cube (`mips` levels) holding `roughness`: level k holds
// roughness k / (mips − 1) (env::prefilter_level_roughness, which says why linear).
float prefiltered_lod(float roughness, float mips) {
    return roughness * max(mips - 1.0, 0.0);
}

// Orthonormal basis around n (Frisvad / Duff et al. 2017, branchless and exact).
void basis(vec3 n, out vec3 t, out vec3 b) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}

// Mip level for a sample of density `pdf` (per steradian) out of `count` samples, on a cube whose
// level 0 has `size`² texels per face: 0.5 log2(Ω_sample / Ω_texel) (GPU Gems 3, ch. 20).
float pdf_lod(float pdf, uint count, uint size) {
    float omega_s = 1.0 / (float(count) * max(pdf, 1e-8));
    float omega_p = 4.0 * M_PI / (6.0 * float(size) * float(size));
    return max(0.5 * log2(omega_s / omega_p), 0.0);
}

#endif
