#version 450
// Evaluates every drawn sub-face on a uniform grid and writes positions and normals: the
// "evaluate, then draw triangles" path, and the GPU side of the CPU/GPU tests.
// Quads use `factor` segments per side, n-gon sub-faces (half the size) factor / 2, so edges
// shared between them line up (factor is even whenever the cage has non-quads).
#include "plan_eval.glsl"
#include "plan_boundary.glsl"

// Literal sizes: with gl_WorkGroupSize or a constant in the layout, glslc emits LocalSizeId,
// which needs maintenance4.
const uint kGroupSize = 64u;
layout(local_size_x = 64) in;  // = kGroupSize
layout(push_constant) uniform Push {
    uint subfaceCount;
    uint factor;
    uint groupsPerRow;
    uint vertexStride;  // vertices reserved per sub-face: (factor + 1)^2
} push;

layout(std430, set = 0, binding = 8) writeonly buffer Grid { float grid[]; };  // position, normal

layout(std430, set = 0, binding = 12) readonly buffer SubfaceFactors { uint subfaceFactor[]; };

void main() {
    uint drawn = gl_WorkGroupID.y * push.groupsPerRow + gl_WorkGroupID.x;
    if (drawn >= push.subfaceCount) return;
    uint n = subfaceFactor[drawn], side = n + 1u;
    for (uint i = gl_LocalInvocationID.x; i < side * side; i += kGroupSize) {
        vec2 uv = vec2(float(i % side), float(i / side)) / float(n);
        LimitSample s = evaluateTessVertex(drawn, uv, uvec4(n));
        vec3 normal = cross(s.du, s.dv);
        float len = length(normal);
        normal = len > 0.0 ? normal / len : vec3(0.0);
        uint o = 6u * (drawn * push.vertexStride + i);
        grid[o] = s.position.x;
        grid[o + 1u] = s.position.y;
        grid[o + 2u] = s.position.z;
        grid[o + 3u] = normal.x;
        grid[o + 4u] = normal.y;
        grid[o + 5u] = normal.z;
    }
}
