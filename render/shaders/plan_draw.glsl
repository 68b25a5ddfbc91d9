// Push constants shared by the plan drawing stages (128 bytes at most on lavapipe).
#include "plan_buffers.glsl"
layout(push_constant) uniform DrawPush {
    mat4 viewProjection;
    float uniformFactor;      // > 0: every quad edge gets this factor; 0: adaptive
    float pixelsPerSegment;   // adaptive: target screen length of one tessellated segment
    float pixelsPerUnit;      // projection scale: pixels per unit at w = 1 (viewport height / 2 * P[1][1])
    uint colorMode;           // low byte: see plan.frag; bit 8: matcap (plan_lighting.glsl)
    uint capture;             // tessellated path: 1 records every evaluated vertex
    vec4 keyLight;            // xyz: toward the studio key light, in the cage's coordinates
    vec4 fillLight;           // xyz: toward the fill light
} draw;

#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 16) restrict readonly buffer PointPositionsRef { vec4 data[]; };
#define pointPositions PointPositionsRef(planBuffers.pointPositionsAddress).data
#else
layout(std430, set = 0, binding = 13) readonly buffer PointPositions { vec4 pointPositions[]; };
#endif

// Segments needed for a sphere (centre, radius) to be pixelsPerSegment long on screen:
// rotation-invariant and the same from both faces of an edge. One for a sphere wholly behind the
// eye (render/grid_layout.cpp sphereFactor, which this matches).
float sphereFactor(vec3 centre, float radius) {
    if (draw.uniformFactor > 0.0) return draw.uniformFactor;
    mat4 m = draw.viewProjection;
    float w = (m * vec4(centre, 1.0)).w;
    if (w + 2.0 * radius * length(vec3(m[0][3], m[1][3], m[2][3])) < 0.0) return 1.0;
    return clamp(2.0 * radius * draw.pixelsPerUnit / max(w, 1e-4) / draw.pixelsPerSegment, 1.0, 64.0);
}
