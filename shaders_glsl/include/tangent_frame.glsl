// The shading frame around a normal (lighting.glsl, and the deferred path's geometry pass, which
// stores the frame's X for KHR_materials_anisotropy).
#ifndef LUZ_TANGENT_FRAME_GLSL
#define LUZ_TANGENT_FRAME_GLSL

// A tangent frame from a normal and a (possibly unnormalised, non-orthogonal) tangent with
// handedness w: Gram-Schmidt, then Y = w (N × X). Degenerate tangents fall back to any
// perpendicular vector.
void tangent_frame(vec3 N, vec4 T, out vec3 X, out vec3 Y) {
    vec3 t = T.xyz - N * dot(N, T.xyz);
    float len2 = dot(t, t);
    if (len2 < 1e-12) {
        t = abs(N.x) < 0.9 ? cross(N, vec3(1.0, 0.0, 0.0)) : cross(N, vec3(0.0, 1.0, 0.0));
        len2 = dot(t, t);
    }
    X = t * inversesqrt(len2);
    Y = cross(N, X) * (T.w < 0.0 ? -1.0 : 1.0);
}

#endif
