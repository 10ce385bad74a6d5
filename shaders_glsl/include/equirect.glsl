// The equirectangular mapping of src/env (keep the two identical).
#ifndef LUZ_EQUIRECT_GLSL
#define LUZ_EQUIRECT_GLSL

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

// u = 0.5 + atan(x, −z)/(2π) (u = 0.5 looks down −z, increasing towards +x); v = acos(y)/π (v = 0 is +y).
vec2 equirect_uv(vec3 d) {
    return vec2(0.5 + atan(d.x, -d.z) / (2.0 * M_PI), acos(clamp(d.y, -1.0, 1.0)) / M_PI);
}

#endif
