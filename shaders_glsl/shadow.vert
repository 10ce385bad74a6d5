#version 460
// The shadow pass (src/render/shadow): depth only, no fragment stage. Each draw pushes the layer's
// view-projection times the object's model matrix (reversed depth: 1 at the light's near plane).

layout(location = 0) in vec3 in_position;

layout(push_constant) uniform ShadowPush {
    mat4 clip_from_object;
} push;

void main() {
    gl_Position = push.clip_from_object * vec4(in_position, 1.0);
}
