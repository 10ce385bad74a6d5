#version 460
// Equirectangular radiance → cube map level 0, with the environment's rotation about +y.
#include "../include/env.glsl"
#include "../include/equirect.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(set = 0, binding = 0) uniform sampler2D equirect;
layout(set = 0, binding = 1, rgba16f) uniform writeonly imageCube cube;
layout(push_constant) uniform Push {
    float rot_cos;  // rotation of the environment about +y (world = R · env)
    float rot_sin;
    uint size;
    uint pad;
} pc;

void main() {
    uvec3 id = gl_GlobalInvocationID;
    if (id.x >= pc.size || id.y >= pc.size) {
        return;
    }
    vec3 d = cube_dir(id.z, id.xy, pc.size);
    // World direction → the environment's own frame: rotate by −θ about +y.
    vec3 e = vec3(pc.rot_cos * d.x - pc.rot_sin * d.z, d.y, pc.rot_sin * d.x + pc.rot_cos * d.z);
    vec4 c = textureLod(equirect, equirect_uv(e), 0.0);
    imageStore(cube, ivec3(id), vec4(max(c.rgb, vec3(0.0)), 1.0));
}
