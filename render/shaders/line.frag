#version 450
#extension GL_GOOGLE_include_directive : require
#include "color_encoding.glsl"

layout(location = 0) in vec3 inColor;  // linear
layout(location = 0) out vec4 outColor;

void main() {
    outColor = encodeColor(inColor);
}
