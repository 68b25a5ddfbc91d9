#version 450
// mesh.vert with a per-vertex colour stream instead of the push-constant colour.
#extension GL_GOOGLE_include_directive : require
#include "mesh_push.glsl"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 2) in vec3 inColor;  // per-vertex linear colour (mesh_pass.h: colour stream)

layout(location = 0) out vec3 outNormal;
layout(location = 1) out vec3 outWorld;
layout(location = 2) out vec3 outColor;

void main() {
    gl_Position = pc.viewProj * vec4(inPosition, 1.0);
    // The wireframe overlay is pulled slightly toward the eye so that it wins the depth test
    // against the surface it outlines (LESS_OR_EQUAL alone z-fights along the triangles).
    gl_Position.z -= pc.params.x * gl_Position.w;
    outNormal = inNormal;
    outWorld = inPosition;
    outColor = inColor;
}
