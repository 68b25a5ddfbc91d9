// Watertight evaluation of tessellation vertices: a vertex on a sub-face's boundary is
// evaluated by the owner of that boundary point or segment (render/gpu_plans.h), at a
// parameter rebuilt from its integer index, so neighbours compute identical bits.
// Include after plan_eval.glsl.

struct EdgeRef {
    uint segment;
    uint flags;  // bit 0: against the segment's direction; bit 1: split at its midpoint
    uint midpoint;
    uint secondHalf;
};
struct SubfaceBoundary {
    EdgeRef edges[4];
    uint corners[4];
};
struct Segment {
    uint owner;
    uint ownerEdge;  // bits 0-1 edge; bits 2-3: 0 whole edge, 1 first half, 2 second half
    uint ownerReversed;
    uint unused;
};
struct BoundaryPoint {
    uint owner;
    uint ownerCorner;
};

#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 16) restrict readonly buffer BoundariesRef { SubfaceBoundary data[]; };
#define boundaries BoundariesRef(planBuffers.boundariesAddress).data
#else
layout(std430, set = 0, binding = 9) readonly buffer Boundaries { SubfaceBoundary boundaries[]; };
#endif
#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 16) restrict readonly buffer SegmentsRef { Segment data[]; };
#define segments SegmentsRef(planBuffers.segmentsAddress).data
#else
layout(std430, set = 0, binding = 10) readonly buffer Segments { Segment segments[]; };
#endif
#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 16) restrict readonly buffer BoundaryPointsRef { BoundaryPoint data[]; };
#define boundaryPoints BoundaryPointsRef(planBuffers.boundaryPointsAddress).data
#else
layout(std430, set = 0, binding = 11) readonly buffer BoundaryPoints { BoundaryPoint boundaryPoints[]; };
#endif

vec2 cornerUV(uint corner) {
    return vec2(corner == 1u || corner == 2u ? 1.0 : 0.0, corner >= 2u ? 1.0 : 0.0);
}

// Sub-face edge e at parameter t along its own direction (see gpu_plans.h).
vec2 edgeUV(uint e, float t) {
    if (e == 0u) return vec2(t, 0.0);
    if (e == 1u) return vec2(1.0, t);
    if (e == 2u) return vec2(t, 1.0);
    return vec2(0.0, t);
}

// Where a boundary vertex is evaluated: the owning drawn sub-face and its (u, v). Only index
// arithmetic here: the evaluator is called once, by the caller, so shaders stay small (lavapipe
// compiles them with LLVM at first use, and inlined copies of the evaluator add up fast).
struct Owner {
    uint drawn;
    vec2 uv;
};

Owner pointOwner(uint point) {
    BoundaryPoint p = boundaryPoints[point];
    return Owner(p.owner, cornerUV(p.ownerCorner));
}

// Vertex `c` of `k` along segment `segment`, counted in its canonical direction.
Owner segmentOwner(uint segment, uint c, uint k) {
    Segment s = segments[segment];
    uint edge = s.ownerEdge & 3u, halfOfEdge = (s.ownerEdge >> 2) & 3u;
    uint local = s.ownerReversed != 0u ? k - c : c;
    float t = halfOfEdge == 0u ? float(local) / float(k) : float((halfOfEdge - 1u) * k + local) / float(2u * k);
    return Owner(s.owner, edgeUV(edge, t));
}

// Vertex i of n along edge e of drawn sub-face `drawn` (a split edge has an even n).
Owner edgeVertexOwner(uint drawn, uint e, uint i, uint n) {
    EdgeRef r = boundaries[drawn].edges[e];
    if (i == 0u) return pointOwner(boundaries[drawn].corners[e == 1u ? 1u : (e == 2u ? 3u : 0u)]);
    if (i == n) return pointOwner(boundaries[drawn].corners[e == 0u ? 1u : (e == 3u ? 3u : 2u)]);
    if ((r.flags & 2u) != 0u) {
        uint k = n / 2u;
        if (i == k) return pointOwner(r.midpoint);
        if (i < k) return segmentOwner(r.segment, i, k);
        return segmentOwner(r.secondHalf, n - i, k);
    }
    return segmentOwner(r.segment, (r.flags & 1u) != 0u ? n - i : i, n);
}

// Where a tessellation vertex at `uv` of `drawn` is evaluated, whose edges 0..3 are split into
// edgeFactor[e] segments; interior vertices are the sub-face's own.
Owner tessVertexOwner(uint drawn, vec2 uv, uvec4 edgeFactor) {
    Owner o = Owner(drawn, uv);
    if (uv.y == 0.0) o = edgeVertexOwner(drawn, 0u, uint(round(uv.x * float(edgeFactor.x))), edgeFactor.x);
    else if (uv.x == 1.0) o = edgeVertexOwner(drawn, 1u, uint(round(uv.y * float(edgeFactor.y))), edgeFactor.y);
    else if (uv.y == 1.0) o = edgeVertexOwner(drawn, 2u, uint(round(uv.x * float(edgeFactor.z))), edgeFactor.z);
    else if (uv.x == 0.0) o = edgeVertexOwner(drawn, 3u, uint(round(uv.y * float(edgeFactor.w))), edgeFactor.w);
    return o;
}
