#version 450
// Evaluates the limit surface at each tessellation vertex; boundary vertices go through
// their owner so neighbouring faces produce bit-identical positions and normals. Sculpted
// displacement is evaluated there too (by the owner, at the owner's parameter), so displaced
// boundary vertices stay bit-identical.
#include "plan_eval.glsl"
#include "plan_boundary.glsl"
#include "displacement.glsl"
#include "plan_draw.glsl"

layout(quads, equal_spacing, ccw) in;
layout(location = 0) patch in uint drawn;
layout(location = 1) patch in uvec4 edgeFactor;

struct CaptureRecord {
    float u, v;
    uint drawn;
    uint edgeAndFactor;  // edge (0..3, 4 inside) | segments along it << 8
    float x, y, z;
    uint edgeIndex;
};
#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 16) restrict buffer CaptureRef {
    uint captureCount;
    uint captureCapacity;
    uint captureUnused0, captureUnused1;
    CaptureRecord records[];
};
#define captureBuffer CaptureRef(planBuffers.captureAddress)
#else
layout(std430, set = 0, binding = 14) buffer Capture {
    uint captureCount;
    uint captureCapacity;
    uint captureUnused0, captureUnused1;
    CaptureRecord records[];
} captureBuffer;
#endif

layout(location = 1) out vec3 outNormal;
layout(location = 2) flat out uint outDrawn;
layout(location = 3) out vec2 outUV;

void main() {
    vec2 uv = gl_TessCoord.xy;
    Owner o = tessVertexOwner(drawn, uv, edgeFactor);
    vec3 n;
    LimitSample s = evaluateWithNormal(o.drawn, o.uv, n);
    displaceSurfacePoint(subfaces[o.drawn].subface, o.uv, s.du, s.dv, n, s.position, n);
    outNormal = n == vec3(0.0) ? vec3(0.0, 0.0, 1.0) : n;
    outDrawn = drawn;
    outUV = uv;
    gl_Position = draw.viewProjection * vec4(s.position, 1.0);
    if (draw.capture != 0u) {
        uint edge = 4u, n = 0u;
        if (uv.y == 0.0) { edge = 0u; n = edgeFactor.x; }
        else if (uv.x == 1.0) { edge = 1u; n = edgeFactor.y; }
        else if (uv.y == 1.0) { edge = 2u; n = edgeFactor.z; }
        else if (uv.x == 0.0) { edge = 3u; n = edgeFactor.w; }
        uint index = uint(round((edge == 1u || edge == 3u ? uv.y : uv.x) * float(n)));
        uint slot = atomicAdd(captureBuffer.captureCount, 1u);
        if (slot < captureBuffer.captureCapacity)
            captureBuffer.records[slot] = CaptureRecord(uv.x, uv.y, drawn, edge | (n << 8), s.position.x, s.position.y, s.position.z, index);
    }
}
