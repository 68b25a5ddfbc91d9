#version 450
// ACC-1: tessellation factors of one patch from its geometry patch's corners (the limit
// positions, shared by neighbouring patches, so shared edges get the same factor).
#include "tess_patch.glsl"

layout(vertices = 1) out;
layout(location = 0) flat in uint inPatch[];
layout(location = 0) patch out uint patchIndex;

#include "tess_patch_buffers.glsl"
layout(buffer_reference, std430, buffer_reference_align = 16) restrict readonly buffer PatchesRef { vec4 data[]; };
#define points PatchesRef(tessBuffers.patchDataAddress).data  // 40 per patch (acc1.h)

void main() {
    uint base = 40u * inPatch[0];
    vec3 c0 = points[base].xyz, c1 = points[base + 3u].xyz, c2 = points[base + 15u].xyz, c3 = points[base + 12u].xyz;
    patchIndex = inPatch[0];
    // Vulkan's quad domain: outer[0] is the edge u = 0, [1] v = 0, [2] u = 1, [3] v = 1.
    gl_TessLevelOuter[0] = edgeFactor(c0, c3);
    gl_TessLevelOuter[1] = edgeFactor(c0, c1);
    gl_TessLevelOuter[2] = edgeFactor(c1, c2);
    gl_TessLevelOuter[3] = edgeFactor(c3, c2);
    float inner = max(max(gl_TessLevelOuter[0], gl_TessLevelOuter[1]), max(gl_TessLevelOuter[2], gl_TessLevelOuter[3]));
    gl_TessLevelInner[0] = inner;
    gl_TessLevelInner[1] = inner;
}
