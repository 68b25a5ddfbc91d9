#version 450
// One patch per vertex: the vertex is only the patch index, read from the pass's patch list at
// gl_VertexIndex (which includes the draw's first vertex, so split draws keep their place): the
// identity, or the patches a culled draw keeps (tess_patch_pass.h). The patch data is in a
// storage buffer.
layout(location = 0) flat out uint outPatch;

#include "tess_patch_buffers.glsl"
layout(buffer_reference, std430, buffer_reference_align = 16) restrict readonly buffer PatchListRef { uint data[]; };
#define patchList PatchListRef(tessBuffers.patchListAddress).data

void main() {
    outPatch = patchList[gl_VertexIndex];
    gl_Position = vec4(0.0);
}
