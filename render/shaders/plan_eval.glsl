// Evaluation of subdivision plans on the GPU: the same algorithm as core/plans/plan_eval.cpp and
// core/plans/patch_basis.cpp, over the flat arrays of render/gpu_plans.h (keep the three in step).
//
// The bases themselves are in patch_basis.glsl.
#include "patch_basis.glsl"
#include "plan_buffers.glsl"

struct PlanHeader {
    uint rootNode;
    uint weightOffset;
    uint ringSize;
    uint maxDepth;
    uint stencilCountByLevel[12];
};

struct Subface {
    uint plan;
    uint rotation;
    uint ringOffset;
    uint cpOffset;
    uint subface;
    uint unused0, unused1, unused2;
};

#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 16) restrict readonly buffer PlanHeadersRef { PlanHeader data[]; };
#define planHeaders PlanHeadersRef(planBuffers.planHeadersAddress).data
#else
layout(std430, set = 0, binding = 0) readonly buffer PlanHeaders { PlanHeader planHeaders[]; };
#endif
#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 16) restrict readonly buffer NodesRef { uvec4 data[]; };
#define nodes NodesRef(planBuffers.nodesAddress).data
#else
layout(std430, set = 0, binding = 1) readonly buffer Nodes { uvec4 nodes[]; };
#endif
#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 4) restrict readonly buffer PointsRef { uint data[]; };
#define points PointsRef(planBuffers.pointsAddress).data
#else
layout(std430, set = 0, binding = 2) readonly buffer Points { uint points[]; };
#endif
#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 4) restrict readonly buffer WeightsRef { float data[]; };
#define weights WeightsRef(planBuffers.weightsAddress).data
#else
layout(std430, set = 0, binding = 3) readonly buffer Weights { float weights[]; };
#endif
#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 16) restrict readonly buffer SubfacesRef { Subface data[]; };
#define subfaces SubfacesRef(planBuffers.subfacesAddress).data
#else
layout(std430, set = 0, binding = 4) readonly buffer Subfaces { Subface subfaces[]; };
#endif
#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 4) restrict readonly buffer RingsRef { uint data[]; };
#define rings RingsRef(planBuffers.ringsAddress).data
#else
layout(std430, set = 0, binding = 5) readonly buffer Rings { uint rings[]; };
#endif
#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 4) restrict readonly buffer PositionsRef { float data[]; };
#define positions PositionsRef(planBuffers.positionsAddress).data
#else
layout(std430, set = 0, binding = 6) readonly buffer Positions { float positions[]; };
#endif
#ifdef QP_BY_ADDRESS
#ifdef QP_WRITE_CONTROL_POINTS
layout(buffer_reference, std430, buffer_reference_align = 16) restrict buffer ControlPointsRef { vec4 data[]; };
#define controlPoints ControlPointsRef(planBuffers.controlPointsAddress).data
#else
layout(buffer_reference, std430, buffer_reference_align = 16) restrict readonly buffer ControlPointsRef { vec4 data[]; };
#define controlPoints ControlPointsRef(planBuffers.controlPointsAddress).data
#endif
#else
#ifdef QP_WRITE_CONTROL_POINTS
layout(std430, set = 0, binding = 7) buffer ControlPoints { vec4 controlPoints[]; };
#else
layout(std430, set = 0, binding = 7) readonly buffer ControlPoints { vec4 controlPoints[]; };
#endif
#endif

const uint NODE_INTERNAL = 0u;
const uint NODE_REGULAR = 1u;
const uint NODE_CREASE = 2u;
const uint NODE_TERMINAL = 3u;
const uint NODE_EXTRAORDINARY = 4u;

LimitSample gregoryPatch(uint pointBase, uint cpBase, float u, float v) {
    vec3 p[20];
    for (uint k = 0u; k < 20u; ++k) p[k] = controlPoints[cpBase + points[pointBase + k]].xyz;
    return gregoryBasisPatch(p, u, v);
}

// Descent to the leaf holding (u, v) in the plan's frame; on a split line take the side towards
// the face centre (matches the stencils' level assignment, core/plans/plan_builder.cpp). Returns the
// leaf and its domain's origin and size; bounded by the deepest possible plan, so damaged data
// cannot hang the device.
struct Leaf {
    uvec4 node;
    vec2 origin;
    float size;
    uint depth;
};

Leaf findLeaf(uint plan, vec2 uv) {
    Leaf leaf = Leaf(nodes[planHeaders[plan].rootNode], vec2(0.0), 1.0, 0u);
    while ((leaf.node.x & 0xffu) == NODE_INTERNAL && leaf.depth < 16u) {
        leaf.size *= 0.5;
        vec2 mid = leaf.origin + leaf.size;
        bool highU = uv.x > mid.x || (uv.x == mid.x && mid.x < 0.5);
        bool highV = uv.y > mid.y || (uv.y == mid.y && mid.y < 0.5);
        leaf.node = nodes[leaf.node.y + (highU ? 1u : 0u) + (highV ? 2u : 0u)];
        if (highU) leaf.origin.x = mid.x;
        if (highV) leaf.origin.y = mid.y;
        ++leaf.depth;
    }
    return leaf;
}

vec2 toPlanFrame(uint rotation, vec2 uv) {
    if (rotation == 1u) return vec2(uv.y, 1.0 - uv.x);
    if (rotation == 2u) return vec2(1.0 - uv.x, 1.0 - uv.y);
    if (rotation == 3u) return vec2(1.0 - uv.y, uv.x);
    return uv;
}

// (u, v) in the plan's own frame. Every leaf kind funnels into one bicubic B-spline path or one
// Gregory path (B16 §6), so each basis appears once in the compiled shader.
LimitSample evaluatePlan(uint plan, uint cpBase, vec2 uv) {
    Leaf leaf = findLeaf(plan, clamp(uv, 0.0, 1.0));
    uvec4 node = leaf.node;
    float size = leaf.size;
    float s = clamp((clamp(uv.x, 0.0, 1.0) - leaf.origin.x) / size, 0.0, 1.0);
    float t = clamp((clamp(uv.y, 0.0, 1.0) - leaf.origin.y) / size, 0.0, 1.0);
    uint kind = node.x & 0xffu;
    vec2 scale = vec2(1.0 / size);  // d(patch coordinate) / d(u, v), sign included
    uint pointBase = node.y;
    bool gregory = kind == NODE_EXTRAORDINARY;
    bool quadrant = false;  // a terminal node's regular quadrant: points on its 5x5 grid
    uint qx = 0u, qy = 0u;

    if (kind == NODE_TERMINAL) {
        // Find the level whose regular quadrant holds (s, t), or the Gregory patch at the
        // bottom of the chain, in a frame mirrored so the extraordinary vertex is at the origin.
        uint corner = (node.x >> 16) & 0xffu, levels = node.x >> 24;
        bool mirrorU = corner == 1u || corner == 2u, mirrorV = corner == 2u || corner == 3u;
        float a = mirrorU ? 1.0 - s : s, b = mirrorV ? 1.0 - t : t, levelScale = 1.0;
        uint level = 0u;
        for (; level < levels && max(a, b) < 0.5; ++level) {
            a *= 2.0;
            b *= 2.0;
            levelScale *= 2.0;
        }
        if (level < levels) {
            quadrant = true;
            qx = a >= 0.5 ? 1u : 0u;
            qy = b >= 0.5 ? 1u : 0u;
            s = 2.0 * a - float(qx);
            t = 2.0 * b - float(qy);
            scale *= 2.0 * levelScale * vec2(mirrorU ? -1.0 : 1.0, mirrorV ? -1.0 : 1.0);
            pointBase = node.y + 24u * level;
        } else {
            gregory = true;
            s = mirrorU ? 1.0 - a : a;
            t = mirrorV ? 1.0 - b : b;
            scale *= levelScale;
            pointBase = node.y + 24u * levels;
        }
    }

    LimitSample r;
    if (gregory) {
        r = gregoryPatch(pointBase, cpBase, s, t);
    } else {
        vec4 bu, du, bv, dv;
        bsplineBasis(s, bu, du);
        bsplineBasis(t, bv, dv);
        uint mask = (node.x >> 8) & 0xffu, edge = (node.x >> 16) & 0xffu;
        if (kind == NODE_CREASE) {
            float sharpness = uintBitsToFloat(node.z);
            if (edge == 0u) creaseBasis(t, sharpness, bv, dv);
            else if (edge == 2u) creaseBasisFar(t, sharpness, bv, dv);
            else if (edge == 3u) creaseBasis(s, sharpness, bu, du);
            else creaseBasisFar(s, sharpness, bu, du);
        }
        if (!quadrant) {
            if ((mask & 1u) != 0u) { bv = foldNear(bv); dv = foldNear(dv); }
            if ((mask & 4u) != 0u) { bv = foldFar(bv); dv = foldFar(dv); }
            if ((mask & 8u) != 0u) { bu = foldNear(bu); du = foldNear(du); }
            if ((mask & 2u) != 0u) { bu = foldFar(bu); du = foldFar(du); }
        }
        r = LimitSample(vec3(0.0), vec3(0.0), vec3(0.0));
        for (uint row = 0u; row < 4u; ++row) {
            vec3 along = vec3(0.0), alongDu = vec3(0.0);
            for (uint col = 0u; col < 4u; ++col) {
                uint slot = quadrant ? (qy + row) * 5u + qx + col - 1u : 4u * row + col;
                vec3 cp = controlPoints[cpBase + points[pointBase + slot]].xyz;
                along += bu[col] * cp;
                alongDu += du[col] * cp;
            }
            r.position += bv[row] * along;
            r.du += bv[row] * alongDu;
            r.dv += dv[row] * along;
        }
    }
    r.du *= scale.x;
    r.dv *= scale.y;
    // At a corner whose exact tangent plane the plan carries (Plan::cornerTangents: two
    // tangents in its first control points), du and dv lose their part along its normal.
    uint tangents = planHeaders[plan].stencilCountByLevel[11];
    if (tangents != 0u && (uv.x == 0.0 || uv.x == 1.0) && (uv.y == 0.0 || uv.y == 1.0)) {
        uint corner = uv.y == 0.0 ? (uv.x == 0.0 ? 0u : 1u) : (uv.x == 1.0 ? 2u : 3u);
        if ((tangents & (1u << corner)) != 0u) {
            uint first = 2u * uint(bitCount(tangents & ((1u << corner) - 1u)));
            vec3 n = cross(controlPoints[cpBase + first].xyz, controlPoints[cpBase + first + 1u].xyz);
            float length2 = dot(n, n);
            if (length2 > 0.0) {
                n *= inversesqrt(length2);
                r.du -= dot(r.du, n) * n;
                r.dv -= dot(r.dv, n) * n;
            }
        }
    }
    return r;
}

// A sub-face's control points are relative to its origin, its first 1-ring vertex, as on the
// CPU (core/plans/planned_cage.h): deep derivatives keep float's precision of the face's size.
vec3 subfaceOrigin(uint drawn) {
    uint vtx = rings[subfaces[drawn].ringOffset];
    return vec3(positions[3u * vtx], positions[3u * vtx + 1u], positions[3u * vtx + 2u]);
}

// (u, v) in the sub-face's own frame (quads: u from corner 0 to 1, v from corner 0 to 3).
LimitSample evaluateSubface(uint drawn, vec2 uv) {
    Subface f = subfaces[drawn];
    LimitSample r = evaluatePlan(f.plan, f.cpOffset, toPlanFrame(f.rotation, uv));
    r.position += subfaceOrigin(drawn);
    vec3 du = r.du, dv = r.dv;
    if (f.rotation == 1u) { r.du = -dv; r.dv = du; }
    else if (f.rotation == 2u) { r.du = -du; r.dv = -dv; }
    else if (f.rotation == 3u) { r.du = dv; r.dv = -du; }
    return r;
}

// Control point `index` of drawn sub-face `drawn`: its stencil applied to the 1-ring, relative
// to the sub-face's origin.
vec3 applyStencil(uint drawn, uint index) {
    Subface f = subfaces[drawn];
    PlanHeader h = planHeaders[f.plan];
    uint w = h.weightOffset + index * h.ringSize;
    vec3 sum = vec3(0.0), origin = subfaceOrigin(drawn);
    for (uint j = 0u; j < h.ringSize; ++j) {
        uint vtx = rings[f.ringOffset + j];
        sum += weights[w + j] * (vec3(positions[3u * vtx], positions[3u * vtx + 1u], positions[3u * vtx + 2u]) - origin);
    }
    return sum;
}
