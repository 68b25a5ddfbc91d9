#version 450
// Grid paths, colour modes: draws the vertices the grid pass evaluated (render/grid_layout.h;
// the index buffer holds slots) with the sub-face and (u, v) plan.frag colours by, looked up
// from the slot. Plain shading uses plan_grid_lit.vert.
#include "plan_eval.glsl"
#include "plan_draw.glsl"

layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;

#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 8) restrict readonly buffer SubfaceGridRef { uvec2 data[]; };  // n, first slot
#define subfaceGrid SubfaceGridRef(planBuffers.subfaceGridAddress).data
#else
layout(std430, set = 0, binding = 12) readonly buffer SubfaceGrid { uvec2 subfaceGrid[]; };  // n, first slot
#endif
#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 4) restrict readonly buffer SlotSubfaceRef { uint data[]; };
#define slotSubface SlotSubfaceRef(planBuffers.slotSubfaceAddress).data
#else
layout(std430, set = 0, binding = 17) readonly buffer SlotSubface { uint slotSubface[]; };
#endif

layout(location = 1) out vec3 outNormal;
layout(location = 2) flat out uint outDrawn;
layout(location = 3) out vec2 outUV;

void main() {
    uint index = uint(gl_VertexIndex);
    uint drawn = slotSubface[index];
    uvec2 g = subfaceGrid[drawn];
    uint local = index - g.y, side = g.x + 1u;
    outNormal = inNormal;
    outDrawn = drawn;
    outUV = vec2(float(local % side), float(local / side)) / float(g.x);
    gl_Position = draw.viewProjection * vec4(inPosition, 1.0);
}
