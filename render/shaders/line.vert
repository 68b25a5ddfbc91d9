#version 450
// Coloured line segments (cage overlay): world position and linear colour per vertex.
layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inColor;
layout(location = 0) out vec3 outColor;
layout(push_constant) uniform Push { mat4 viewProjection; } push;

void main() {
    outColor = inColor;
    gl_Position = push.viewProjection * vec4(inPosition, 1.0);
}
