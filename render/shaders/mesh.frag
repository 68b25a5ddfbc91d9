#version 450
#extension GL_GOOGLE_include_directive : require
#include "mesh_push.glsl"
#include "color_encoding.glsl"
#include "matcap.glsl"

layout(location = 0) in vec3 inNormal;
layout(location = 1) in vec3 inWorld;
layout(location = 2) in vec3 inColor;

layout(location = 0) out vec4 outColor;

// Studio: a headlight at the eye, plus a dimmer fill light from the upper left and behind, so
// that silhouettes keep some shape.
vec3 studioLight(vec3 n, vec3 toEye, out vec3 highlight) {
    float head = max(dot(n, toEye), 0.0);
    float fill = max(dot(n, normalize(vec3(-0.6, 0.7, -0.4))), 0.0);
    highlight = vec3(0.15 * pow(head, 48.0));
    return vec3(0.06 + 0.75 * head + 0.25 * fill);
}

void main() {
    if (pc.params.y > 0.5 && pc.params.y < 1.5) {  // unlit: the colour exactly
        outColor = encodeColor(inColor);
        return;
    }
    vec3 n = normalize(inNormal);
    vec3 toEye = normalize(pc.eye.xyz - inWorld);
    if (dot(n, toEye) < 0.0) n = -n;  // two-sided: open surfaces show their inside lit too
    vec3 highlight;
    vec3 light = pc.params.z > 0.5 ? matcapLight(viewNormalFrom(pc.viewProj, n), highlight) : studioLight(n, toEye, highlight);
    vec3 color;
    if (pc.params.y > 1.5) {
        // Colour streams (heat maps): the colour as the albedo under the light, with a floor so
        // that the hue stays readable against the legend in the shadows, and the form shows.
        color = inColor * (0.35 + 0.8 * light) + 0.5 * highlight;
    } else {
        color = inColor * light + highlight;
    }
    outColor = encodeColor(color);
}
