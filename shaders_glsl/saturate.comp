#version 460
// Saturation policy of the classic model (MODELS.md §1): clamp each channel to 1, or divide the whole
// image by its largest channel value (a reduction, then a scale).
//! variant clamp: SATURATE_CLAMP
//! variant reduce: SATURATE_REDUCE
//! variant normalize: SATURATE_NORMALIZE

layout(local_size_x = 16, local_size_y = 16) in;
// Bindings (src/render/saturate.rs reads them as luz::glsl::saturate_comp::BINDING_*).
#define BINDING_HDR 0
#define BINDING_REDUCTION 1
layout(set = 0, binding = BINDING_HDR, rgba32f) uniform image2D hdr;
layout(set = 0, binding = BINDING_REDUCTION, std430) buffer Reduction {
    uint max_bits;  // float bits of the largest channel value; non-negative floats order like uints
} red;

#ifdef SATURATE_REDUCE
shared float partial[256];
#endif

void main() {
    ivec2 size = imageSize(hdr);
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    bool inside = p.x < size.x && p.y < size.y;
#if defined(SATURATE_CLAMP)
    if (inside) {
        vec4 c = imageLoad(hdr, p);
        imageStore(hdr, p, vec4(min(c.rgb, vec3(1.0)), c.a));
    }
#elif defined(SATURATE_REDUCE)
    float m = 0.0;
    if (inside) {
        vec3 c = imageLoad(hdr, p).rgb;
        m = max(max(c.r, c.g), max(c.b, 0.0));
        // NaN and Inf are not "intensities": leave them to the NaN counters.
        if (isnan(m) || isinf(m)) {
            m = 0.0;
        }
    }
    uint i = gl_LocalInvocationIndex;
    partial[i] = m;
    barrier();
    for (uint s = 128u; s > 0u; s >>= 1u) {
        if (i < s) {
            partial[i] = max(partial[i], partial[i + s]);
        }
        barrier();
    }
    if (i == 0u) {
        atomicMax(red.max_bits, floatBitsToUint(partial[0]));
    }
#else
    if (inside) {
        float m = uintBitsToFloat(red.max_bits);
        if (m > 1.0) {
            vec4 c = imageLoad(hdr, p);
            imageStore(hdr, p, vec4(c.rgb / m, c.a));
        }
    }
#endif
}
