#version 450
// Cost baseline, NOT the exact surface: "plain B-spline patches", what a renderer drawing only
// regular bicubic patches pays per tessellated vertex. Each sub-face is ONE bicubic B-spline
// over 16 of its control points: those of its root leaf when the plan is a single regular or
// crease leaf (crease sharpness and boundary folding ignored), else simply its first 16
// stencils, which is wrong on irregular faces but costs the same. The sub-face rotation is
// ignored too. Compare its frame time with PlanPass (render/bspline_pass.h), not its pixels.
#include "plan_eval.glsl"
#include "plan_draw.glsl"

layout(quads, equal_spacing, ccw) in;
layout(location = 0) patch in uint drawn;
layout(location = 1) patch in uvec4 edgeFactor;  // from plan.tesc; unused here

layout(location = 1) out vec3 outNormal;
layout(location = 2) flat out uint outDrawn;
layout(location = 3) out vec2 outUV;

void main() {
    vec2 uv = gl_TessCoord.xy;
    Subface f = subfaces[drawn];
    uvec4 root = nodes[planHeaders[f.plan].rootNode];
    uint kind = root.x & 0xffu;
    bool leaf = kind == NODE_REGULAR || kind == NODE_CREASE;
    uint last = PLAN_CONTROL_POINT_COUNT - 1u;  // a tiny plan may have fewer than 16 stencils
    vec4 bu, du, bv, dv;
    bsplineBasis(uv.x, bu, du);
    bsplineBasis(uv.y, bv, dv);
    vec3 position = vec3(0.0), dPdu = vec3(0.0), dPdv = vec3(0.0);
    for (uint row = 0u; row < 4u; ++row) {
        vec3 along = vec3(0.0), alongDu = vec3(0.0);
        for (uint col = 0u; col < 4u; ++col) {
            uint slot = 4u * row + col;
            uint index = f.cpOffset + (leaf ? points[root.y + slot] : slot);
            vec3 cp = controlPoints[min(index, last)].xyz;
            along += bu[col] * cp;
            alongDu += du[col] * cp;
        }
        position += bv[row] * along;
        dPdu += bv[row] * alongDu;
        dPdv += dv[row] * along;
    }
    position += subfaceOrigin(drawn);  // control points are relative to it
    vec3 n = cross(dPdu, dPdv);
    float len = length(n);
    outNormal = len > 0.0 ? n / len : vec3(0.0, 0.0, 1.0);
    outDrawn = drawn;
    outUV = uv;
    gl_Position = draw.viewProjection * vec4(position, 1.0);
}
