#version 450
// PN-triangles (Vlachos et al. 2001): the cubic Bezier triangle for the position and the
// quadratic normal patch for the shading normal, at the barycentric tessellation coordinate
// (weights of p1, p2, p3), as evaluatePnTriangle does on the CPU (pn.h).
#define TESS_EVALUATION
#include "tess_patch.glsl"

layout(triangles, equal_spacing, ccw) in;
layout(location = 0) patch in uint patchIndex;

#include "tess_patch_buffers.glsl"
layout(buffer_reference, std430, buffer_reference_align = 16) restrict readonly buffer PatchesRef { vec4 data[]; };
#define points PatchesRef(tessBuffers.patchDataAddress).data

void main() {
    vec3 b = gl_TessCoord;
    uint base = 16u * patchIndex;
    vec3 c[10];
    for (uint i = 0u; i < 10u; ++i) c[i] = points[base + i].xyz;
    float x = b.x, y = b.y, z = b.z;
    vec3 position = x * x * x * c[0] + y * y * y * c[1] + z * z * z * c[2] + 3.0 * x * x * y * c[3] +
                    3.0 * x * y * y * c[4] + 3.0 * y * y * z * c[5] + 3.0 * y * z * z * c[6] + 3.0 * x * z * z * c[7] +
                    3.0 * x * x * z * c[8] + 6.0 * x * y * z * c[9];
    vec3 n = x * x * points[base + 10u].xyz + y * y * points[base + 11u].xyz + z * z * points[base + 12u].xyz +
             2.0 * x * y * points[base + 13u].xyz + 2.0 * y * z * points[base + 14u].xyz +
             2.0 * x * z * points[base + 15u].xyz;
    float len = length(n);
    emitVertex(patchIndex, b, position, len > 0.0 ? n / len : vec3(0.0));
}
