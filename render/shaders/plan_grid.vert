#version 450
// Grid paths: fetches the vertex the grid pass evaluated (no vertex input state; the index
// buffer holds slots, render/grid_layout.h), and the sub-face and (u, v) plan.frag colours by.
#include "plan_eval.glsl"
#include "plan_draw.glsl"

layout(std430, set = 0, binding = 8) readonly buffer Grid { float grid[]; };  // 6 floats per vertex
layout(std430, set = 0, binding = 12) readonly buffer SubfaceGrid { uvec2 subfaceGrid[]; };  // n, first slot
layout(std430, set = 0, binding = 17) readonly buffer SlotSubface { uint slotSubface[]; };

layout(location = 1) out vec3 outNormal;
layout(location = 2) flat out uint outDrawn;
layout(location = 3) out vec2 outUV;

void main() {
    uint index = uint(gl_VertexIndex);
    uint drawn = slotSubface[index];
    uvec2 g = subfaceGrid[drawn];
    uint local = index - g.y, side = g.x + 1u;
    vec3 p = vec3(grid[6u * index], grid[6u * index + 1u], grid[6u * index + 2u]);
    outNormal = vec3(grid[6u * index + 3u], grid[6u * index + 4u], grid[6u * index + 5u]);
    outDrawn = drawn;
    outUV = vec2(float(local % side), float(local / side)) / float(g.x);
    gl_Position = draw.viewProjection * vec4(p, 1.0);
}
