#version 450
// IdPass (render/id_pass.h): positions under the view's matrix, each vertex's number passed on
// unchanged (flat), so every triangle carries exactly one number.

layout(push_constant) uniform IdPush {
    mat4 viewProj;
} pc;

layout(location = 0) in vec3 inPosition;
layout(location = 1) in uint inId;

layout(location = 0) flat out uint outId;

void main() {
    gl_Position = pc.viewProj * vec4(inPosition, 1.0);
    outId = inId;
}
