#version 450
// One patch per vertex: the vertex is only the patch index (gl_VertexIndex includes the draw's
// first vertex, so split draws keep their numbering). The patch data is in a storage buffer.
layout(location = 0) flat out uint outPatch;

void main() {
    outPatch = uint(gl_VertexIndex);
    gl_Position = vec4(0.0);
}
