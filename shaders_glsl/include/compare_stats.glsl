// Summary figures of a comparison map (shaders compare.comp and compare_show.frag; decoded by
// src/render/compare.rs: GpuMapStats). The including file defines STATS_SET and STATS_BINDING,
// and LOG_BINS for a radiance difference (bins per 1/6 octave from 2^-26; bin 0: exactly 0)
// instead of FLIP's 256 equal bins of [0, 1].
#ifndef LUZ_COMPARE_STATS_GLSL
#define LUZ_COMPARE_STATS_GLSL

#ifdef STATS_SHOW
#define STATS_ACCESS readonly
#else
#define STATS_ACCESS
#endif
layout(set = STATS_SET, binding = STATS_BINDING, std430) STATS_ACCESS buffer Stats {
    uint hist[256];
    uint max_bits;  // float bits of the largest value (non-negative floats order like uints)
    uint above;     // values > 0.01
    float scale;    // the colour bar's top: 1 (FLIP), else the 99th percentile (max when it is 0)
    uint pad;
    float partial[];  // one sum per workgroup (the CPU adds them for the mean)
} stats;

#define STATS_BINS 256
#define LOG_BIN_OFFSET 26.0
#define LOG_BINS_PER_OCTAVE 6.0

uint stats_bin(float v) {
#ifdef LOG_BINS
    if (v <= 0.0) {
        return 0u;
    }
    if (!(v < 3.0e38)) {
        return 255u;
    }
    return uint(clamp(int(floor((log2(v) + LOG_BIN_OFFSET) * LOG_BINS_PER_OCTAVE)) + 1, 1, 255));
#else
    return uint(clamp(int(v * 256.0), 0, 255));
#endif
}

// The largest value bin `b` holds (values above the top bin's edge also land in it).
float stats_bin_top(int b) {
#ifdef LOG_BINS
    return b == 0 ? 0.0 : exp2(float(b) / LOG_BINS_PER_OCTAVE - LOG_BIN_OFFSET);
#else
    return float(b + 1) / 256.0;
#endif
}

#if defined(STATS_SHOW)
// The display reads `scale` only.
#elif !defined(COMPARE_SCALE)
shared uint s_hist[STATS_BINS];
shared float s_sum[256];
shared uint s_max;
shared uint s_above;

// Adds this invocation's value (when `inside`) to the workgroup's figures and those to the
// buffer's (a 16×16 workgroup: one bin per invocation).
void accumulate_stats(bool inside, float value) {
    uint i = gl_LocalInvocationIndex;
    s_hist[i] = 0u;
    s_sum[i] = inside ? value : 0.0;
    if (i == 0u) {
        s_max = 0u;
        s_above = 0u;
    }
    barrier();
    if (inside) {
        atomicAdd(s_hist[stats_bin(value)], 1u);
        atomicMax(s_max, floatBitsToUint(value));
        if (value > 0.01) {
            atomicAdd(s_above, 1u);
        }
    }
    for (uint s = 128u; s > 0u; s >>= 1u) {
        barrier();
        if (i < s) {
            s_sum[i] += s_sum[i + s];
        }
    }
    barrier();
    if (s_hist[i] != 0u) {
        atomicAdd(stats.hist[i], s_hist[i]);
    }
    if (i == 0u) {
        atomicMax(stats.max_bits, s_max);
        atomicAdd(stats.above, s_above);
        stats.partial[gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x] = s_sum[0];
    }
}
#else
// One invocation: the colour bar's top from the histogram and the maximum.
void finish_stats() {
#ifdef LOG_BINS
    uint total = 0u;
    for (int b = 0; b < STATS_BINS; b++) {
        total += stats.hist[b];
    }
    uint target = max(uint(ceil(0.99 * float(total))), 1u);
    uint acc = 0u;
    int found = STATS_BINS - 1;
    for (int b = STATS_BINS - 1; b >= 0; b--) {
        // The first bin (from the bottom) where the count reaches the rank: scanning down, the
        // last one whose count from the bottom still reaches it.
        if (total - acc >= target) {
            found = b;
        }
        acc += stats.hist[b];
    }
    float top = uintBitsToFloat(stats.max_bits);
    float p99 = min(stats_bin_top(found), top);
    stats.scale = p99 > 0.0 ? p99 : top;
#else
    stats.scale = 1.0;
#endif
}
#endif

#endif
