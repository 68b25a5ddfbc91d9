#version 450
// Applies the stencil prefix of drawn sub-faces: control points for tessellation level
// `level` (factors <= 2^level). One workgroup per sub-face, threads stride over its stencils.
#define QP_WRITE_CONTROL_POINTS
#include "plan_eval.glsl"

// Literal sizes: with gl_WorkGroupSize or a constant in the layout, glslc emits LocalSizeId,
// which needs maintenance4.
const uint kGroupSize = 64u;
layout(local_size_x = 64) in;  // = kGroupSize
layout(push_constant) uniform Push {
    uint subfaceCount;  // workgroups that do work
    uint level;
    uint groupsPerRow;  // dispatch is 2D when there are more sub-faces than one row allows
    uint listOffset;    // 0xffffffff: workgroup i is drawn sub-face i; else updateList[listOffset + i]
} push;

#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 4) restrict readonly buffer UpdateListRef { uint data[]; };
#define updateList UpdateListRef(planBuffers.updateListAddress).data
#else
layout(std430, set = 0, binding = 15) readonly buffer UpdateList { uint updateList[]; };
#endif

void main() {
    uint id = gl_WorkGroupID.y * push.groupsPerRow + gl_WorkGroupID.x;
    if (id >= push.subfaceCount) return;
    uint drawn = push.listOffset == 0xffffffffu ? id : updateList[push.listOffset + id];
    Subface f = subfaces[drawn];
    uint count = planHeaders[f.plan].stencilCountByLevel[push.level];
    for (uint i = gl_LocalInvocationID.x; i < count; i += kGroupSize)
        controlPoints[f.cpOffset + i] = vec4(applyStencil(drawn, i), 1.0);
}
