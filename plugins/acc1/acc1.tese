#version 450
// ACC-1: evaluates one patch as evaluateAcc1Patch does on the CPU (acc1.h): the bicubic Bezier
// geometry patch for the position, and the two tangent patches (d/du: degree 2 in u, 3 in v;
// d/dv: degree 3 in u, 2 in v) for the shading normal, their normalised cross product.
#define TESS_EVALUATION
#include "tess_patch.glsl"

layout(quads, equal_spacing, ccw) in;
layout(location = 0) patch in uint patchIndex;

#include "tess_patch_buffers.glsl"
layout(buffer_reference, std430, buffer_reference_align = 16) restrict readonly buffer PatchesRef { vec4 data[]; };
#define points PatchesRef(tessBuffers.patchDataAddress).data

vec3 bernstein2(float t) {
    float s = 1.0 - t;
    return vec3(s * s, 2.0 * t * s, t * t);
}

void main() {
    float u = gl_TessCoord.x, v = gl_TessCoord.y;
    uint base = 40u * patchIndex;
    vec4 bu, bv, unused;
    bernstein3(u, bu, unused);
    bernstein3(v, bv, unused);
    vec3 qu = bernstein2(u), qv = bernstein2(v);
    vec3 position = vec3(0.0), du = vec3(0.0), dv = vec3(0.0);
    for (uint j = 0u; j < 4u; ++j)
        for (uint i = 0u; i < 4u; ++i) position += bu[i] * bv[j] * points[base + 4u * j + i].xyz;
    for (uint j = 0u; j < 4u; ++j)
        for (uint i = 0u; i < 3u; ++i) du += qu[i] * bv[j] * points[base + 16u + 3u * j + i].xyz;
    for (uint j = 0u; j < 3u; ++j)
        for (uint i = 0u; i < 4u; ++i) dv += bu[i] * qv[j] * points[base + 28u + 4u * j + i].xyz;
    emitVertex(patchIndex, vec3(u, v, 0.0), position, unitNormal(du, dv));
}
