#version 450
// One patch per vertex: the vertex is only the patch index, read from the pass's patch list at
// gl_VertexIndex (which includes the draw's first vertex, so split draws keep their place): the
// identity, or the patches a culled draw keeps (tess_patch_pass.h). The patch data is in a
// storage buffer.
layout(location = 0) flat out uint outPatch;

layout(std430, set = 0, binding = 2) readonly buffer PatchList { uint patchList[]; };

void main() {
    outPatch = patchList[gl_VertexIndex];
    gl_Position = vec4(0.0);
}
