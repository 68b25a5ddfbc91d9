#version 450
// One patch per drawn sub-face: the vertex is just the sub-face index (firstVertex included).
layout(location = 0) flat out uint outDrawn;

void main() {
    outDrawn = uint(gl_VertexIndex);
    gl_Position = vec4(0.0);
}
