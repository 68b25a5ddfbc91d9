#version 450
// PN-triangles: tessellation factors of one triangle from its corners (cage vertices, shared
// by the neighbouring triangles, so shared edges get the same factor).
#include "tess_patch.glsl"

layout(vertices = 1) out;
layout(location = 0) flat in uint inPatch[];
layout(location = 0) patch out uint patchIndex;

// 16 per triangle: b300 b030 b003 b210 b120 b021 b012 b102 b201 b111, then n200 n020 n002 n110 n011 n101.
#include "tess_patch_buffers.glsl"
layout(buffer_reference, std430, buffer_reference_align = 16) restrict readonly buffer PatchesRef { vec4 data[]; };
#define points PatchesRef(tessBuffers.patchDataAddress).data

void main() {
    uint base = 16u * inPatch[0];
    vec3 p1 = points[base].xyz, p2 = points[base + 1u].xyz, p3 = points[base + 2u].xyz;
    patchIndex = inPatch[0];
    // Triangle domain: outer[0] is the edge u = 0 (p2-p3), [1] v = 0 (p3-p1), [2] w = 0 (p1-p2).
    gl_TessLevelOuter[0] = edgeFactor(p2, p3);
    gl_TessLevelOuter[1] = edgeFactor(p3, p1);
    gl_TessLevelOuter[2] = edgeFactor(p1, p2);
    gl_TessLevelInner[0] = max(max(gl_TessLevelOuter[0], gl_TessLevelOuter[1]), gl_TessLevelOuter[2]);
}
