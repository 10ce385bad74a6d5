// The colour pipeline of src/color.rs in GLSL: exposure → tone map → clamp → sRGB encode → round.
// Same names, constants and order of operations as the Rust; keep both in step (tests/tonemap_gpu.rs
// compares them byte by byte). Constants that Rust folds in f32 (0.8 − 0.04, 1 − that, 1/2.4) are
// written here as the f32 values Rust gets, so that no folding in double precision can differ.
#ifndef LUZ_COLOR_GLSL
#define LUZ_COLOR_GLSL

// Tone-mapping operators: the push-constant ids (src/render/tonemap.rs: tonemap_id).
#define TONEMAP_NONE 0u
#define TONEMAP_REINHARD 1u
#define TONEMAP_ACES 2u
#define TONEMAP_KHRONOS_NEUTRAL 3u
#define TONEMAP_AGX 4u

// color::TONEMAP_INPUT_MAX: the largest finite half float.
const float TONEMAP_INPUT_MAX = 65504.0;

// color::srgb_encode: IEC 61966-2-1, exact piecewise curve, not clamped.
float srgb_encode(float linear) {
    if (linear <= 0.0031308) {
        return 12.92 * linear;
    }
    return 1.055 * pow(linear, 0.41666666) - 0.055;  // 0.41666666 = 1.0f32 / 2.4f32
}

// color::srgb_decode.
float srgb_decode(float encoded) {
    if (encoded <= 0.04045) {
        return encoded / 12.92;
    }
    return pow((encoded + 0.055) / 1.055, 2.4);
}

// color::srgb_encode_u8, as a float code in [0, 255]: NaN → 0, clamp, encode, ×255, round half
// away from zero (Rust's f32::round; GLSL's round() leaves ties to the implementation).
float srgb_encode_u8(float linear) {
    if (isnan(linear)) {
        return 0.0;
    }
    float v = srgb_encode(clamp(linear, 0.0, 1.0)) * 255.0;
    float r = floor(v);
    if (v - r >= 0.5) {  // exact: v ≥ 0, so v − floor(v) is representable
        r += 1.0;
    }
    return clamp(r, 0.0, 255.0);
}

// color::sanitize: NaN → 0, negatives → 0, above TONEMAP_INPUT_MAX (and +Inf) → that maximum.
vec3 sanitize(vec3 rgb) {
    vec3 o;
    for (int i = 0; i < 3; i++) {
        o[i] = isnan(rgb[i]) ? 0.0 : clamp(rgb[i], 0.0, TONEMAP_INPUT_MAX);
    }
    return o;
}

// color::aces_narkowicz (input pre-scaled by 0.6: part of the operator).
float aces_narkowicz(float x) {
    const float A = 2.51;
    const float B = 0.03;
    const float C = 2.43;
    const float D = 0.59;
    const float E = 0.14;
    x = x * 0.6;
    return clamp((x * (A * x + B)) / (x * (C * x + D) + E), 0.0, 1.0);
}

// color::khronos_pbr_neutral (KhronosGroup/ToneMapping, PBR_Neutral).
vec3 khronos_pbr_neutral(vec3 color) {
    const float START_COMPRESSION = 0.76;  // 0.8 − 0.04 in f32
    const float DESATURATION = 0.15;

    float x = min(color.r, min(color.g, color.b));
    float offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
    color = color - offset;

    float peak = max(color.r, max(color.g, color.b));
    if (peak < START_COMPRESSION) {
        return color;
    }

    const float D = 0.24000001;  // 1 − START_COMPRESSION in f32
    float new_peak = 1.0 - D * D / (peak + D - START_COMPRESSION);
    color = color * (new_peak / peak);

    float g = 1.0 - 1.0 / (DESATURATION * (peak - new_peak) + 1.0);
    return color * (1.0 - g) + new_peak * g;
}

// color::AGX_INSET / AGX_OUTSET, row-major as in Rust: out[i] = dot(row i, v) (see mat3_mul).
const vec3 AGX_INSET[3] = vec3[3](
    vec3(0.84236416, 0.0784229, 0.07921294),
    vec3(0.04232981, 0.8785011, 0.07916906),
    vec3(0.04237768, 0.07843735, 0.87918496));
const vec3 AGX_OUTSET[3] = vec3[3](
    vec3(1.196879, -0.09802088, -0.09902974),
    vec3(-0.05289685, 1.1519031, -0.09896118),
    vec3(-0.052971635, -0.09804345, 1.1510737));
const float AGX_MIN_EV = -12.47393;
const float AGX_MAX_EV = 4.026069;

// color::mat3_mul, same summation order.
vec3 mat3_mul(const vec3 m[3], vec3 v) {
    vec3 o;
    for (int i = 0; i < 3; i++) {
        o[i] = m[i].x * v.x + m[i].y * v.y + m[i].z * v.z;
    }
    return o;
}

// color::agx_default_contrast (Wrensch's 6th-order fit).
float agx_default_contrast(float x) {
    float x2 = x * x;
    float x4 = x2 * x2;
    return 15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2 + 0.1191 * x
        - 0.00232;
}

// color::agx: inset → log2 clamped to [AGX_MIN_EV, AGX_MAX_EV] → sigmoid → outset → clamp → exact
// sRGB decode (the curve's output is display-encoded; the pipeline encodes again afterwards).
vec3 agx(vec3 rgb) {
    const float range = AGX_MAX_EV - AGX_MIN_EV;
    vec3 encoded = mat3_mul(AGX_INSET, rgb);
    for (int i = 0; i < 3; i++) {
        float c = max(encoded[i], 0.0);
        // log2(0) is −inf on the CPU, clamped to the minimum; GLSL leaves log2(0) undefined.
        float ev = c > 0.0 ? clamp(log2(c), AGX_MIN_EV, AGX_MAX_EV) : AGX_MIN_EV;
        encoded[i] = agx_default_contrast((ev - AGX_MIN_EV) / range);
    }
    vec3 o = mat3_mul(AGX_OUTSET, encoded);
    for (int i = 0; i < 3; i++) {
        o[i] = srgb_decode(clamp(o[i], 0.0, 1.0));
    }
    return o;
}

// Tonemap::apply: `op` is one of TONEMAP_*; unknown ids act as TONEMAP_NONE.
vec3 tonemap_apply(uint op, vec3 rgb) {
    switch (op) {
    case TONEMAP_REINHARD: {
        vec3 x = sanitize(rgb);
        return x / (1.0 + x);
    }
    case TONEMAP_ACES: {
        vec3 x = sanitize(rgb);
        return vec3(aces_narkowicz(x.r), aces_narkowicz(x.g), aces_narkowicz(x.b));
    }
    case TONEMAP_KHRONOS_NEUTRAL:
        return khronos_pbr_neutral(sanitize(rgb));
    case TONEMAP_AGX:
        return agx(sanitize(rgb));
    default:
        return rgb;
    }
}

// color::to_display_rgba8 for one pixel up to the encode: NaN → 0, exposure, tone map.
vec3 display_map(vec4 p, float scale, uint op) {
    vec3 rgb;
    for (int i = 0; i < 3; i++) {
        rgb[i] = isnan(p[i]) ? 0.0 : p[i] * scale;
    }
    return tonemap_apply(op, rgb);
}

// color::to_display_rgba8 for one pixel, as float codes in [0, 255]; `scale` is
// color::exposure_scale(ev) computed on the CPU. Alpha is always 255.
vec4 to_display_rgba8(vec4 p, float scale, uint op) {
    vec3 mapped = display_map(p, scale, op);
    return vec4(srgb_encode_u8(mapped.r), srgb_encode_u8(mapped.g), srgb_encode_u8(mapped.b), 255.0);
}

#endif
