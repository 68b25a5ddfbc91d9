#version 450
// osd-fas: evaluates one Far patch at the tessellation coordinate, as evaluatePatch does on the
// CPU (osd_fas_patches.cpp): bicubic B-spline with boundary edges folded, single-crease with its
// sharpness across the crease edge, or Gregory basis (patch_basis.glsl, the plans' bases), all
// relative to the patch's first control vertex (float precision at depth). On a transition edge
// the vertices are moved so each half is cut evenly (osd_fas_gpu.h).
#define TESS_EVALUATION
#include "tess_patch.glsl"
#include "osd_fas_data.glsl"
#include "patch_basis.glsl"

layout(quads, equal_spacing, ccw) in;
layout(location = 0) patch in uint patchIndex;
layout(location = 1) patch in vec4 firstHalf;

// t along an edge of `total` segments whose first half has `first` of them (t from the edge's
// start).
float splitParameter(float t, float first, float total) {
    float i = round(t * total);
    return i <= first ? 0.5 * i / first : 0.5 + 0.5 * (i - first) / (total - first);
}

// Far's edges 0 (v=0) and 1 (u=1) run with u, v; 2 (v=1) and 3 (u=0) against them.
void splitTransitionEdges(inout float u, inout float v) {
    if (v == 0.0 && firstHalf[0] > 0.0) u = splitParameter(u, firstHalf[0], gl_TessLevelOuter[1]);
    if (u == 1.0 && firstHalf[1] > 0.0) v = splitParameter(v, firstHalf[1], gl_TessLevelOuter[2]);
    if (v == 1.0 && firstHalf[2] > 0.0) u = 1.0 - splitParameter(1.0 - u, firstHalf[2], gl_TessLevelOuter[3]);
    if (u == 0.0 && firstHalf[3] > 0.0) v = 1.0 - splitParameter(1.0 - v, firstHalf[3], gl_TessLevelOuter[0]);
}

LimitSample bsplinePatch(uint p, vec3 origin, float u, float v) {
    vec4 bu, du, bv, dv;
    bsplineBasis(u, bu, du);
    bsplineBasis(v, bv, dv);
    uint boundary = patchBoundary(p);
    if (patchWord(p, PATCH_KIND) == KIND_SINGLE_CREASE) {
        // Far marks the crease edge with the boundary bit; across it the crease basis.
        float sharpness = uintBitsToFloat(patchWord(p, PATCH_SHARPNESS));
        if (boundary == 1u) creaseBasis(v, sharpness, bv, dv);
        else if (boundary == 4u) creaseBasisFar(v, sharpness, bv, dv);
        else if (boundary == 8u) creaseBasis(u, sharpness, bu, du);
        else creaseBasisFar(u, sharpness, bu, du);
    } else {
        if ((boundary & 1u) != 0u) { bv = foldNear(bv); dv = foldNear(dv); }
        if ((boundary & 4u) != 0u) { bv = foldFar(bv); dv = foldFar(dv); }
        if ((boundary & 8u) != 0u) { bu = foldNear(bu); du = foldNear(du); }
        if ((boundary & 2u) != 0u) { bu = foldFar(bu); du = foldFar(du); }
    }
    LimitSample r = LimitSample(vec3(0.0), vec3(0.0), vec3(0.0));
    for (uint row = 0u; row < 4u; ++row)
        for (uint col = 0u; col < 4u; ++col)
            addBezier(r, patchControlVertex(p, 4u * row + col) - origin, bu[col], du[col], bv[row], dv[row]);
    return r;
}

void main() {
    float u = gl_TessCoord.x, v = gl_TessCoord.y;
    splitTransitionEdges(u, v);
    uint p = patchIndex;
    vec3 origin = patchControlVertex(p, 0u);
    LimitSample s;
    if (patchWord(p, PATCH_KIND) == KIND_GREGORY_BASIS) {
        vec3 points[20];
        for (uint k = 0u; k < 20u; ++k) points[k] = patchControlVertex(p, k) - origin;
        s = gregoryBasisPatch(points, u, v);
    } else {
        s = bsplinePatch(p, origin, u, v);
    }
    emitVertex(p, vec3(u, v, 0.0), origin + s.position, unitNormal(s.du, s.dv));
}
