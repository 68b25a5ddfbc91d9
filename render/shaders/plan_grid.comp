#version 450
// Fills the grid path's vertex slots (render/grid_layout.h), one workgroup per drawn sub-face.
// Phase 0 evaluates the slots whose source is themselves at their own (u, v); phase 1 copies
// every other slot from its source, the owner's evaluated slot (a dispatch later, after a
// barrier). Each evaluated slot depends on its own sub-face's control points only, so an
// update may run both phases over a list of sub-faces instead of the whole cage.
#include "plan_eval.glsl"

// Literal sizes: with gl_WorkGroupSize or a constant in the layout, glslc emits LocalSizeId,
// which needs maintenance4.
const uint kGroupSize = 64u;
layout(local_size_x = 64) in;  // = kGroupSize
layout(push_constant) uniform Push {
    uint subfaceCount;  // workgroups that do work
    uint phase;         // 0 evaluate, 1 copy
    uint groupsPerRow;  // dispatch is 2D when there are more sub-faces than one row allows
    uint listOffset;    // 0xffffffff: workgroup i is drawn sub-face i; else updateList[listOffset + i]
} push;

layout(std430, set = 0, binding = 8) buffer Grid { float grid[]; };  // position, normal
layout(std430, set = 0, binding = 12) readonly buffer SubfaceGrid { uvec2 subfaceGrid[]; };  // n, first slot
layout(std430, set = 0, binding = 15) readonly buffer UpdateList { uint updateList[]; };
layout(std430, set = 0, binding = 16) readonly buffer GridSource { uint gridSource[]; };

void main() {
    uint id = gl_WorkGroupID.y * push.groupsPerRow + gl_WorkGroupID.x;
    if (id >= push.subfaceCount) return;
    uint drawn = push.listOffset == 0xffffffffu ? id : updateList[push.listOffset + id];
    uvec2 g = subfaceGrid[drawn];
    uint n = g.x, side = n + 1u;
    for (uint i = gl_LocalInvocationID.x; i < side * side; i += kGroupSize) {
        uint slot = g.y + i, source = gridSource[slot];
        if (push.phase == 0u && source == slot) {
            vec2 uv = vec2(float(i % side), float(i / side)) / float(n);
            LimitSample s = evaluateSubface(drawn, uv);
            vec3 normal = cross(s.du, s.dv);
            float len = length(normal);
            normal = len > 0.0 ? normal / len : vec3(0.0);
            uint o = 6u * slot;
            grid[o] = s.position.x;
            grid[o + 1u] = s.position.y;
            grid[o + 2u] = s.position.z;
            grid[o + 3u] = normal.x;
            grid[o + 4u] = normal.y;
            grid[o + 5u] = normal.z;
        } else if (push.phase == 1u && source != slot) {
            for (uint k = 0u; k < 6u; ++k) grid[6u * slot + k] = grid[6u * source + k];
        }
    }
}
