// Octahedral encoding of unit vectors in two floats (Cigolle et al., "A Survey of Efficient
// Representations for Independent Unit Vectors", JCGT 2014): the G-buffer's normal.
#ifndef LUZ_OCTAHEDRAL_GLSL
#define LUZ_OCTAHEDRAL_GLSL

vec2 oct_sign(vec2 v) {
    return vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0);
}

vec2 oct_encode(vec3 n) {
    vec2 p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    return n.z >= 0.0 ? p : (1.0 - abs(p.yx)) * oct_sign(p);
}

vec3 oct_decode(vec2 e) {
    vec3 v = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (v.z < 0.0) {
        v.xy = (1.0 - abs(v.yx)) * oct_sign(v.xy);
    }
    return normalize(v);
}

#endif
