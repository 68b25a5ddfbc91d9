#version 450
// Plain shading of the limit surface (and the flat wireframe colour): plan.frag without the
// colour modes, for the grid paths, whose vertex shader then passes only the normal. Fewer
// varyings are less triangle setup for a CPU rasteriser (docs/renderer.md).
#extension GL_GOOGLE_include_directive : require
#include "plan_draw.glsl"
#include "plan_lighting.glsl"
#include "color_encoding.glsl"

layout(location = 1) in vec3 inNormal;
layout(location = 0) out vec4 outColor;

void main() {
    outColor = encodeColor(draw.colorMode == 0xffffffffu ? kWireColor : lightPlan(kPlanAlbedo, inNormal, gl_FrontFacing));
}
