// Evaluation of subdivision plans on the GPU: the same algorithm as core/plan_eval.cpp and
// core/patch_basis.cpp, over the flat arrays of render/gpu_plans.h (keep the three in step).
//
// Boundary folding and semi-sharp creases change only the 1D basis across the edge they sit
// on (every rule is a tensor product on a regular patch), so they are applied to the 1D
// basis vectors instead of to 16 weights.

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

layout(std430, set = 0, binding = 0) readonly buffer PlanHeaders { PlanHeader planHeaders[]; };
layout(std430, set = 0, binding = 1) readonly buffer Nodes { uvec4 nodes[]; };
layout(std430, set = 0, binding = 2) readonly buffer Points { uint points[]; };
layout(std430, set = 0, binding = 3) readonly buffer Weights { float weights[]; };
layout(std430, set = 0, binding = 4) readonly buffer Subfaces { Subface subfaces[]; };
layout(std430, set = 0, binding = 5) readonly buffer Rings { uint rings[]; };
layout(std430, set = 0, binding = 6) readonly buffer Positions { float positions[]; };
#ifdef QP_WRITE_CONTROL_POINTS
layout(std430, set = 0, binding = 7) buffer ControlPoints { vec4 controlPoints[]; };
#else
layout(std430, set = 0, binding = 7) readonly buffer ControlPoints { vec4 controlPoints[]; };
#endif

const uint NODE_INTERNAL = 0u;
const uint NODE_REGULAR = 1u;
const uint NODE_CREASE = 2u;
const uint NODE_TERMINAL = 3u;
const uint NODE_EXTRAORDINARY = 4u;

struct LimitSample {
    vec3 position;
    vec3 du;
    vec3 dv;
};

void bsplineBasis(float x, out vec4 b, out vec4 d) {
    float y = 1.0 - x, x2 = x * x, x3 = x2 * x;
    b = vec4(y * y * y, 3.0 * x3 - 6.0 * x2 + 4.0, -3.0 * x3 + 3.0 * x2 + 3.0 * x + 1.0, x3) / 6.0;
    d = vec4(-0.5 * y * y, 1.5 * x2 - 2.0 * x, -1.5 * x2 + x + 0.5, 0.5 * x2);
}

void bernsteinBasis(float x, out vec4 b, out vec4 d) {
    float y = 1.0 - x;
    b = vec4(y * y * y, 3.0 * x * y * y, 3.0 * x * x * y, x * x * x);
    d = vec4(-3.0 * y * y, 3.0 * y * (y - 2.0 * x), 3.0 * x * (2.0 * y - x), 3.0 * x * x);
}

// 1D basis across a semi-sharp crease through point 1 (point 0 beyond it); see
// core/patch_basis.h for the derivation.
void creaseBasis(float x, float sharpness, out vec4 b, out vec4 d) {
    vec4 bx, dx;
    bsplineBasis(x, bx, dx);
    float c = bx.x, dc = dx.x;
    if (sharpness >= 10.0) {
        c = 0.0;
        dc = 0.0;
    } else if (sharpness > 0.0) {
        float n = floor(sharpness), f = sharpness - n;
        float h = exp2(-n - 1.0);
        float a0 = h, a1 = (1.0 - f) * h * 0.25;
        float t = x / h;
        vec4 bt, dt;
        c = 0.0;
        dc = 0.0;
        if (t < 1.0) {
            bsplineBasis(t, bt, dt);
            c = a0 * bt.x + a1 * bt.y;
            dc = (a0 * dt.x + a1 * dt.y) / h;
        } else if (t < 2.0) {
            bsplineBasis(t - 1.0, bt, dt);
            c = a1 * bt.x;
            dc = a1 * dt.x / h;
        }
    }
    b = vec4(c, bx.y + 2.0 * bx.x - 2.0 * c, bx.z - bx.x + c, bx.w);
    d = vec4(dc, dx.y + 2.0 * dx.x - 2.0 * dc, dx.z - dx.x + dc, dx.w);
}

// The same crease on the far edge (through point 2, point 3 beyond it).
void creaseBasisFar(float x, float sharpness, out vec4 b, out vec4 d) {
    vec4 rb, rd;
    creaseBasis(1.0 - x, sharpness, rb, rd);
    b = rb.wzyx;
    d = -rd.wzyx;
}

// Phantom point 0 = 2 p1 - p2 (boundary at the near edge), or 3 = 2 p2 - p1 (far edge).
vec4 foldNear(vec4 b) { return vec4(0.0, b.y + 2.0 * b.x, b.z - b.x, b.w); }
vec4 foldFar(vec4 b) { return vec4(b.x, b.y - b.w, b.z + 2.0 * b.w, 0.0); }

// One Bezier point's share of a sample: value, and derivatives along u and v.
void addBezier(inout LimitSample r, vec3 cp, float bu, float du, float bv, float dv) {
    r.position += bu * bv * cp;
    r.du += du * bv * cp;
    r.dv += bu * dv * cp;
}

// Weight of a corner's Fp point against its Fm point (s, t: distances along Ep's and Em's edges).
float gregoryWeight(float s, float t) {
    float st = s + t;
    return st > 0.0 ? s / st : 0.5;
}

// Gregory patch in OpenSubdiv's GREGORY_BASIS order (corner k: P, Ep, Em, Fp, Fm), written out
// per corner: as a loop over corners with tables of Bezier indices it took about half of the
// grid compute pass on lavapipe, although few samples reach it (docs/renderer.md).
LimitSample gregoryPatch(uint pointBase, uint cpBase, float u, float v) {
    vec4 bu, du, bv, dv;
    bernsteinBasis(u, bu, du);
    bernsteinBasis(v, bv, dv);
    vec3 p[20];
    for (uint k = 0u; k < 20u; ++k) p[k] = controlPoints[cpBase + points[pointBase + k]].xyz;
    float g0 = gregoryWeight(u, v), g1 = gregoryWeight(v, 1.0 - u);
    float g2 = gregoryWeight(1.0 - u, 1.0 - v), g3 = gregoryWeight(1.0 - v, u);
    LimitSample r = LimitSample(vec3(0.0), vec3(0.0), vec3(0.0));
    // Corner 0 at Bezier (0, 0): P (0, 0), Ep (1, 0), Em (0, 1), F (1, 1).
    addBezier(r, p[0], bu.x, du.x, bv.x, dv.x);
    addBezier(r, p[1], bu.y, du.y, bv.x, dv.x);
    addBezier(r, p[2], bu.x, du.x, bv.y, dv.y);
    addBezier(r, g0 * p[3] + (1.0 - g0) * p[4], bu.y, du.y, bv.y, dv.y);
    // Corner 1 at (3, 0): P (3, 0), Ep (3, 1), Em (2, 0), F (2, 1).
    addBezier(r, p[5], bu.w, du.w, bv.x, dv.x);
    addBezier(r, p[6], bu.w, du.w, bv.y, dv.y);
    addBezier(r, p[7], bu.z, du.z, bv.x, dv.x);
    addBezier(r, g1 * p[8] + (1.0 - g1) * p[9], bu.z, du.z, bv.y, dv.y);
    // Corner 2 at (3, 3): P (3, 3), Ep (2, 3), Em (3, 2), F (2, 2).
    addBezier(r, p[10], bu.w, du.w, bv.w, dv.w);
    addBezier(r, p[11], bu.z, du.z, bv.w, dv.w);
    addBezier(r, p[12], bu.w, du.w, bv.z, dv.z);
    addBezier(r, g2 * p[13] + (1.0 - g2) * p[14], bu.z, du.z, bv.z, dv.z);
    // Corner 3 at (0, 3): P (0, 3), Ep (0, 2), Em (1, 3), F (1, 2).
    addBezier(r, p[15], bu.x, du.x, bv.w, dv.w);
    addBezier(r, p[16], bu.x, du.x, bv.z, dv.z);
    addBezier(r, p[17], bu.y, du.y, bv.w, dv.w);
    addBezier(r, g3 * p[18] + (1.0 - g3) * p[19], bu.y, du.y, bv.z, dv.z);
    return r;
}

// Descent to the leaf holding (u, v) in the plan's frame; on a split line take the side towards
// the face centre (matches the stencils' level assignment, core/plan_builder.cpp). Returns the
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
    return r;
}

// A sub-face's control points are relative to its origin, its first 1-ring vertex, as on the
// CPU (core/planned_cage.h): deep derivatives keep float's precision of the face's size.
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
