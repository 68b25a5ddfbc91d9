#version 450
// Grid paths, plain shading and wireframe: the evaluated vertices as they are (see
// plan_grid.vert for the colour modes).
#extension GL_GOOGLE_include_directive : require
#include "plan_draw.glsl"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 1) out vec3 outNormal;

void main() {
    outNormal = inNormal;
    gl_Position = draw.viewProjection * vec4(inPosition, 1.0);
}
