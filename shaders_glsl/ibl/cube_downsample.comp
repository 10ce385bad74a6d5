#version 460
// One mip level of a cube from the level above: the average of the 2×2 texels it covers.
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
layout(set = 0, binding = 0, rgba16f) uniform readonly imageCube src;
layout(set = 0, binding = 1, rgba16f) uniform writeonly imageCube dst;
layout(push_constant) uniform Push {
    uint size;  // of dst
} pc;

void main() {
    uvec3 id = gl_GlobalInvocationID;
    if (id.x >= pc.size || id.y >= pc.size) {
        return;
    }
    ivec3 s = ivec3(2 * id.xy, id.z);
    vec4 c = imageLoad(src, s) + imageLoad(src, s + ivec3(1, 0, 0)) + imageLoad(src, s + ivec3(0, 1, 0)) +
             imageLoad(src, s + ivec3(1, 1, 0));
    imageStore(dst, ivec3(id), 0.25 * c);
}
