#version 450
// IdPass (render/id_pass.h): the number + 1 in the low 24 bits of an RGBA8 UNORM pixel (red
// lowest), so the cleared black reads as "no number". k / 255 stores as the byte k exactly.

layout(location = 0) flat in uint inId;
layout(location = 0) out vec4 outColor;

void main() {
    uint code = inId + 1u;
    outColor = vec4(float(code & 255u), float((code >> 8) & 255u), float((code >> 16) & 255u), 255.0) / 255.0;
}
