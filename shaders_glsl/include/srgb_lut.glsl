// color::srgb_encode_u8_lut on the GPU: a table lookup and a compare give the same codes as the
// exact pow (color::srgb_encode_u8) in about a tenth of the time on lavapipe. The including file
// defines SRGB_TABLE_SET and SRGB_TABLE_BINDING, where color::srgb_encode_table is bound.
#ifndef LUZ_SRGB_LUT_GLSL
#define LUZ_SRGB_LUT_GLSL

// color::srgb_encode_table: per bin of [0, 1], the code at the bin's start and the value where it
// steps up by one (2.0: no step in this bin).
layout(set = SRGB_TABLE_SET, binding = SRGB_TABLE_BINDING, std430) readonly buffer SrgbEncodeTable {
    vec2 srgb_table[];
};
const float SRGB_ENCODE_BINS = 4096.0;  // color::SRGB_ENCODE_BINS

// color::srgb_encode_u8_lut, as a float code in [0, 255].
float srgb_encode_u8_lut(float linear) {
    if (isnan(linear)) {
        return 0.0;
    }
    float x = clamp(linear, 0.0, 1.0);
    vec2 e = srgb_table[min(int(x * SRGB_ENCODE_BINS), int(SRGB_ENCODE_BINS) - 1)];
    return x >= e.y ? e.x + 1.0 : e.x;
}

#endif
