#version 450
// Shading of the limit surface: lit, or coloured by leaf kind, leaf depth or crease sharpness
// (the leaf is found again from the interpolated (u, v), a descent without evaluation).
#include "plan_eval.glsl"
#include "plan_draw.glsl"
#include "plan_lighting.glsl"
#include "color_encoding.glsl"

layout(location = 1) in vec3 inNormal;
layout(location = 2) flat in uint inDrawn;
layout(location = 3) in vec2 inUV;
layout(location = 0) out vec4 outColor;

const uint COLOR_LIT = 0u, COLOR_NODE_KIND = 1u, COLOR_DEPTH = 2u, COLOR_SHARPNESS = 3u;

vec3 ramp(float t) {  // blue -> cyan -> green -> yellow -> red
    t = clamp(t, 0.0, 1.0);
    return clamp(vec3(1.5 - abs(4.0 * t - 3.0), 1.5 - abs(4.0 * t - 2.0), 1.5 - abs(4.0 * t - 1.0)), 0.0, 1.0);
}

void main() {
    if (draw.colorMode == 0xffffffffu) {  // tessellation wireframe
        outColor = encodeColor(kWireColor);
        return;
    }
    vec3 albedo = kPlanAlbedo;
    uint mode = draw.colorMode & 0xffu;  // the bits above select the lighting (plan_lighting.glsl)
    if (mode != COLOR_LIT) {
        Subface f = subfaces[inDrawn];
        Leaf found = findLeaf(f.plan, clamp(toPlanFrame(f.rotation, inUV), 0.0, 1.0));
        uvec4 leaf = found.node;
        uint depth = found.depth;
        uint kind = leaf.x & 0xffu;
        if (mode == COLOR_NODE_KIND) {
            const vec3 kinds[5] = vec3[5](vec3(1.0), vec3(0.55, 0.75, 0.95), vec3(0.95, 0.55, 0.35),
                                          vec3(0.55, 0.85, 0.45), vec3(0.9, 0.3, 0.8));
            albedo = kinds[min(kind, 4u)];
        } else if (mode == COLOR_DEPTH) {
            albedo = ramp(float(depth) / float(max(planHeaders[f.plan].maxDepth, 1u)));
        } else {
            float sharpness = kind == NODE_CREASE ? uintBitsToFloat(leaf.z) : 0.0;
            albedo = sharpness > 0.0 ? ramp(sharpness / 10.0) : kPlanAlbedo;
        }
    }
    outColor = encodeColor(lightPlan(albedo, inNormal, gl_FrontFacing));
}
