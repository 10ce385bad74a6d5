#version 460
// Area-light emitters seen by the camera (issue 36; docs/area-lights.md): one draw per visible
// area light, gl_InstanceIndex (the draw's first instance) its index among the area lights,
// gl_VertexIndex a vertex of its shape as a triangle list (src/render/forward/emitter.rs has the
// counts): a rect's two triangles, a disk's EMITTER_SEGMENTS-triangle fan, a sphere's
// EMITTER_STACKS × EMITTER_SEGMENTS quads, a tube's EMITTER_SEGMENTS quads (its open side, the
// surface the reference emits from). Round shapes are polygons of the round shape's area (the
// fan's radius scaled by sqrt(θ / sin θ), θ = 2π / EMITTER_SEGMENTS). A one-sided rect or disk
// seen from behind, or a sphere seen from inside, is collapsed to a point (nothing drawn), as
// the reference sees nothing there.
#include "include/lighting.glsl"

#define EMITTER_SEGMENTS 48u
#define EMITTER_STACKS 24u

layout(location = 0) out float out_depth;  // view-space depth, for depth cueing
layout(location = 1) flat out vec3 out_radiance;

// Corner k (0..5) of a quad's two triangles, as offsets in {0, 1}².
uvec2 quad_corner(uint k) {
    const uvec2 c[6] = uvec2[](uvec2(0u, 0u), uvec2(1u, 0u), uvec2(1u, 1u), uvec2(0u, 0u),
                               uvec2(1u, 1u), uvec2(0u, 1u));
    return c[k];
}

void main() {
    AreaLight a = area_light(uint(gl_InstanceIndex));
    uint v = uint(gl_VertexIndex);
    const float seg = 2.0 * M_PI / float(EMITTER_SEGMENTS);
    float round_scale = sqrt(seg / sin(seg));
    vec3 to_eye = frame.camera_pos.xyz - a.position * frame.camera_pos.w;
    bool flat_shape = a.shape == AREA_RECT || a.shape == AREA_DISK;
    bool hidden = (flat_shape && !a.two_sided && dot(to_eye, a.direction) <= 0.0)
               || (a.shape == AREA_SPHERE && frame.camera_pos.w > 0.0 && length(to_eye) <= a.radius);
    vec3 pos = a.position;
    if (a.shape == AREA_RECT) {
        vec2 c = vec2(quad_corner(v % 6u)) * 2.0 - 1.0;
        pos += a.ex * c.x + a.ey * c.y;
    } else if (a.shape == AREA_DISK) {
        uint k = v % 3u;
        if (k != 0u) {
            float phi = seg * float(v / 3u + k - 1u);
            pos += (a.ex * cos(phi) + a.ey * sin(phi)) * round_scale;
        }
    } else if (a.shape == AREA_SPHERE) {
        uvec2 c = quad_corner(v % 6u);
        uint q = v / 6u;
        float phi = seg * float(q % EMITTER_SEGMENTS + c.x);
        float theta = M_PI * float(q / EMITTER_SEGMENTS + c.y) / float(EMITTER_STACKS);
        vec3 m = vec3(sin(theta) * cos(phi), cos(theta), sin(theta) * sin(phi));
        pos += m * (a.radius * round_scale);
    } else {
        // Tube: a.ex is the half axis.
        uvec2 c = quad_corner(v % 6u);
        vec3 n = normalize(a.ex);
        vec3 t = normalize(cross(n, abs(n.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0)));
        vec3 b = cross(n, t);
        float phi = seg * float(v / 6u + c.x);
        pos += a.ex * (float(c.y) * 2.0 - 1.0) + (t * cos(phi) + b * sin(phi)) * (a.radius * round_scale);
    }
    if (hidden) {
        pos = a.position;
    }
    vec4 view_pos = frame.view * vec4(pos, 1.0);
    out_depth = -view_pos.z;
    out_radiance = a.radiance;
    gl_Position = frame.proj * view_pos;
}
