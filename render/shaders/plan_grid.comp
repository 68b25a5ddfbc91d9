#version 450
// Fills the grid path's vertex slots (render/grid_layout.h), one workgroup per drawn sub-face.
// Phase 0 evaluates the slots whose source is themselves at their own (u, v); phase 1 copies
// every other slot from its source, the owner's evaluated slot (a dispatch later, after a
// barrier). Each evaluated slot depends on its own sub-face's control points only, so an
// update may run both phases over a list of sub-faces instead of the whole cage. With sculpted
// displacement, evaluated slots hold the displaced point and its shading normal; copies carry
// them to the neighbours unchanged.
#include "plan_eval.glsl"
#include "displacement.glsl"

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

#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 4) restrict buffer GridRef { float data[]; };  // position, normal
#define grid GridRef(planBuffers.gridAddress).data
#else
layout(std430, set = 0, binding = 8) buffer Grid { float grid[]; };  // position, normal
#endif
#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 8) restrict readonly buffer SubfaceGridRef { uvec2 data[]; };  // n, first slot
#define subfaceGrid SubfaceGridRef(planBuffers.subfaceGridAddress).data
#else
layout(std430, set = 0, binding = 12) readonly buffer SubfaceGrid { uvec2 subfaceGrid[]; };  // n, first slot
#endif
#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 4) restrict readonly buffer UpdateListRef { uint data[]; };
#define updateList UpdateListRef(planBuffers.updateListAddress).data
#else
layout(std430, set = 0, binding = 15) readonly buffer UpdateList { uint updateList[]; };
#endif
#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 4) restrict readonly buffer GridSourceRef { uint data[]; };
#define gridSource GridSourceRef(planBuffers.gridSourceAddress).data
#else
layout(std430, set = 0, binding = 16) readonly buffer GridSource { uint gridSource[]; };
#endif

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
            vec3 normal;
            LimitSample s = evaluateWithNormal(drawn, uv, normal);
            vec3 position = s.position;
            displaceSurfacePoint(subfaces[drawn].subface, uv, s.du, s.dv, normal, position, normal);
            uint o = 6u * slot;
            grid[o] = position.x;
            grid[o + 1u] = position.y;
            grid[o + 2u] = position.z;
            grid[o + 3u] = normal.x;
            grid[o + 4u] = normal.y;
            grid[o + 5u] = normal.z;
        } else if (push.phase == 1u && source != slot) {
            for (uint k = 0u; k < 6u; ++k) grid[6u * slot + k] = grid[6u * source + k];
        }
    }
}
