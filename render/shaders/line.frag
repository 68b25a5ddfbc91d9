#version 450
layout(location = 0) in vec3 inColor;
layout(location = 0) out vec4 outColor;

void main() {
    outColor = vec4(pow(inColor, vec3(1.0 / 2.2)), 1.0);  // UNORM targets: encode like plan.frag
}
