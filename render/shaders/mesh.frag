#version 450
#extension GL_GOOGLE_include_directive : require
#include "mesh_push.glsl"
#include "color_encoding.glsl"

layout(location = 0) in vec3 inNormal;
layout(location = 1) in vec3 inWorld;
layout(location = 2) in vec3 inColor;

layout(location = 0) out vec4 outColor;

void main() {
    vec3 color = inColor;
    if (pc.params.y < 0.5 || pc.params.y > 1.5) {
        vec3 n = normalize(inNormal);
        vec3 toEye = normalize(pc.eye.xyz - inWorld);
        if (dot(n, toEye) < 0.0) n = -n;  // two-sided: open surfaces show their inside lit too
        // A headlight at the eye, plus a dimmer fill light from the upper left and behind, so
        // that silhouettes keep some shape.
        float head = max(dot(n, toEye), 0.0);
        float fill = max(dot(n, normalize(vec3(-0.6, 0.7, -0.4))), 0.0);
        if (pc.params.y > 1.5) {
            // Colour-stream meshes (heat maps): mostly the colour itself, a little shape.
            color = color * (0.62 + 0.38 * head);
        } else {
            float specular = pow(head, 48.0);
            color = color * (0.06 + 0.75 * head + 0.25 * fill) + vec3(0.15 * specular);
        }
    }
    outColor = encodeColor(color);
}
