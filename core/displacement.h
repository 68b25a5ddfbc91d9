// Displacement: a scalar offset along the unit limit normal, sculpted on the limit surface,
// stored per sub-face as a grid of samples whose boundary samples are SHARED with the
// neighbours (multiresolution attributes, Schäfer et al. 2012; docs/displacement.md says why
// this scheme and not analytic bi-quadratic tiles).
//
// Sub-faces are PlannedCage's (Ptex numbering: a quad is one, an n-gon n; face_config.h).
// Each sub-face has a power-of-two resolution R (1 .. kMaxDisplacementResolution): an
// (R+1) x (R+1) grid of samples at (i/R, j/R). Its samples live in three places of one flat
// float array, so that two faces never hold a copy of the same value:
//   - points: one sample per boundary point, indexed by the renderer's point ids
//     (render/gpu_plans.h): cage vertex v -> v, midpoint of cage edge e -> V + e, centre of
//     face f -> V + E + f (midpoints and centres exist only next to non-quads);
//   - segments: the samples strictly inside a boundary segment (a cage edge between two quads,
//     half of a cage edge next to a non-quad, or an n-gon's spoke from an edge midpoint to its
//     centre), in the segment's canonical direction, from its lower point id to its higher one;
//   - tiles: the (R-1)^2 samples strictly inside each sub-face, row-major (u fastest).
// A segment's resolution S is the finest its sub-faces need (the max rule): R for a sub-face
// edge that is the whole segment, max(R/2, 1) for each half of a quad edge split at a midpoint.
// So a sub-face's grid samples on its boundary are always stored samples, and an edge finer
// than its sub-face adds its detail through a correction that fades out over the first row of
// cells (see evaluateDisplacement).
//
// All arrays are plain structs with std430-friendly layouts (16-byte multiples, uint32 and
// float members only): what a shader needs is `subfaces`, `segments` and `samples`.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <algorithm>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "cage.h"
#include "topology.h"

namespace qp {

constexpr uint32_t kMaxDisplacementResolution = 64;  // the largest tessellation factor
constexpr uint32_t kNoSegment = UINT32_MAX;

inline bool isPowerOfTwo(uint32_t x) { return x != 0 && (x & (x - 1)) == 0; }

struct DisplacementSegment {
    uint32_t pointA, pointB;  // boundary point ids, pointA < pointB: the canonical direction
    uint32_t resolution;      // S intervals; sample k (0..S) lies at canonical t = k / S
    uint32_t offset;          // samples[offset + k - 1] holds sample k, 0 < k < S
};
static_assert(sizeof(DisplacementSegment) == 16);

// Flags of a sub-face edge.
constexpr uint32_t kEdgeReversed = 1;  // a whole edge that runs against its segment
constexpr uint32_t kEdgeSplit = 2;     // a quad edge split at a cage-edge midpoint: two segments
constexpr uint32_t kEdgeFiner = 4;     // the edge has samples between the sub-face's grid points

// Sub-face edge e runs from corner kEdgeStart[e] to corner kEdgeEnd[e]; its parameter t is
// u on edges 0 (v = 0) and 2 (v = 1), v on edges 1 (u = 1) and 3 (u = 0).
constexpr uint32_t kEdgeStart[4] = {0, 1, 3, 0};
constexpr uint32_t kEdgeEnd[4] = {1, 2, 2, 3};

struct DisplacementEdge {
    uint32_t segment;     // the whole edge, or (split) the half at the start corner
    uint32_t secondHalf;  // split: the half at the end corner; otherwise kNoSegment
    uint32_t flags;       // kEdgeReversed | kEdgeSplit | kEdgeFiner
    uint32_t unused;
};
static_assert(sizeof(DisplacementEdge) == 16);

struct DisplacementSubface {
    uint32_t resolution;      // R, a power of two
    uint32_t interiorOffset;  // samples[interiorOffset + (j-1)(R-1) + (i-1)] holds grid point (i, j)
    uint32_t unused[2];
    uint32_t corners[4];      // point id (= sample index) at corners 0..3: (0,0) (1,0) (1,1) (0,1)
    DisplacementEdge edges[4];
};
static_assert(sizeof(DisplacementSubface) == 96);

struct DisplacementLayout {
    uint32_t vertexCount = 0, edgeCount = 0, faceCount = 0;
    uint32_t pointCount = 0;    // V + E + F: samples[0, pointCount) are the points
    uint32_t sampleCount = 0;   // points + segment interiors + tile interiors
    std::vector<DisplacementSubface> subfaces;  // one per sub-face
    std::vector<DisplacementSegment> segments;  // cage edges (whole, or two halves) in edge order, then spokes

    uint32_t segmentSampleBegin() const { return pointCount; }
    uint32_t tileSampleBegin() const;

    bool operator==(const DisplacementLayout&) const;
};

// Layout for a cage (that passed validateCage) with every sub-face at `resolution`.
DisplacementLayout buildDisplacementLayout(const Cage& cage, const Topology& topology, uint32_t resolution);

// The same topology with new per-sub-face resolutions (each a power of two in
// 1..kMaxDisplacementResolution, one per sub-face): segment resolutions and offsets follow.
DisplacementLayout withResolutions(const DisplacementLayout& layout, std::span<const uint32_t> resolutions);

struct Displacement {
    DisplacementLayout layout;   // empty: no displacement at all
    std::vector<float> samples;  // layout.sampleCount values
    // The sculpting mask: empty (nothing masked) or one value in [0, 1] per sample, parallel to
    // `samples`; 1 is fully masked (brushes that change D leave the sample alone), 0 not at
    // all. Only brushes read it: renderers and exporters ignore it.
    std::vector<float> mask;

    bool empty() const { return layout.subfaces.empty(); }
    bool hasMask() const { return !mask.empty(); }
    // Equal layouts, samples and masks, where an empty mask equals one of zeros (both mask
    // nothing: undoing the first mask stroke leaves a mask of zeros, not an empty one).
    bool operator==(const Displacement&) const;
};

// All samples zero.
Displacement makeDisplacement(const Cage& cage, const Topology& topology, uint32_t resolution);

struct DisplacementValue {
    float value = 0.0f;
    float du = 0.0f, dv = 0.0f;  // derivatives in the sub-face's (u, v)
};

// D(u, v) on a sub-face, (u, v) in [0, 1]^2 (clamped), with its derivatives.
// Inside: bilinear over the sub-face's grid, plus, in the first row of cells along an edge
// whose segment is finer than the grid, (E(t) - L(t)) * (1 - distance * R) where E is the
// edge function and L its grid's linear reconstruction, so D meets the edge exactly.
// On an edge (u or v exactly 0 or 1) the value is the edge function alone, evaluated in the
// segment's canonical direction from the segment's samples only, with the canonical parameter
// snapped to a multiple of 2^-14: both sides of an edge then get BIT-IDENTICAL values for the
// same point, also when their parameters differ in the last bit (t and 1 - t, or i/n from
// either end for any tessellation factor n <= 64; docs/displacement.md has the proof).
// Derivatives are those of the inside formula (one-sided on edges).
DisplacementValue evaluateDisplacement(const Displacement& displacement, uint32_t subface, float u, float v);

// The pieces of evaluateDisplacement that a sub-face's inside shares with its fast path
// (SubfaceDisplacement): which grid cell (u, v) falls in, and the bilinear interpolant there.
struct DisplacementCell {
    uint32_t i, j;   // the cell's corner (i, j); 0 <= i, j < R
    float fx, fy;    // position inside the cell, in [0, 1]
};
inline DisplacementCell displacementCell(uint32_t resolution, float u, float v) {
    const float Rf = float(resolution);
    const float x = u * Rf, y = v * Rf;
    const uint32_t i = std::min(uint32_t(x), resolution - 1), j = std::min(uint32_t(y), resolution - 1);
    return {i, j, x - float(i), y - float(j)};
}
inline float displacementLerp(float a, float b, float f) { return (1.0f - f) * a + f * b; }
// Grid values g_ij at the cell's corners, R the resolution.
inline DisplacementValue bilinearDisplacement(float g00, float g10, float g01, float g11, const DisplacementCell& c,
                                              float Rf) {
    DisplacementValue out;
    out.value = displacementLerp(displacementLerp(g00, g10, c.fx), displacementLerp(g01, g11, c.fx), c.fy);
    out.du = Rf * displacementLerp(g10 - g00, g11 - g01, c.fy);
    out.dv = Rf * displacementLerp(g01 - g00, g11 - g10, c.fx);
    return out;
}

// One sub-face's D for evaluating it at many points (a renderer's grid): its (R+1)^2 grid
// samples gathered once, and inside the sub-face, away from edges finer than the grid, the
// bilinear interpolant inline. evaluate(u, v) has evaluateDisplacement's bits. Holds
// references to the displacement, whose samples must not change meanwhile.
class SubfaceDisplacement {
public:
    // `samples`: the sub-face's gridSamples, when the caller has them already.
    SubfaceDisplacement(const Displacement& displacement, uint32_t subface, const uint32_t* samples = nullptr);

    uint32_t resolution() const { return resolution_; }
    DisplacementValue evaluate(float u, float v) const {
        u = std::clamp(u, 0.0f, 1.0f);
        v = std::clamp(v, 0.0f, 1.0f);
        const DisplacementCell c = displacementCell(resolution_, u, v);
        return isBilinear(c, u, v) ? bilinear(c) : evaluateNearEdges(u, v);
    }
    // For callers that find the cell themselves (u, v in [0, 1], c = displacementCell(R, u, v)):
    // where evaluate() is the bilinear interpolant alone (inside the sub-face, off the strips of
    // edges finer than the grid), and that interpolant.
    bool isBilinear(const DisplacementCell& c, float u, float v) const {
        return isBilinearAlongU(c.i, u) && isBilinearAlongV(c.j, v);
    }
    DisplacementValue bilinear(const DisplacementCell& c) const {
        const float* g = grid_ + c.j * (resolution_ + 1) + c.i;
        return bilinearDisplacement(g[0], g[1], g[resolution_ + 1], g[resolution_ + 2], c, float(resolution_));
    }
    // isBilinear's conditions on u (cell column i) and on v (cell row j), and the grid values,
    // row-major ((R+1)^2, i fastest), for callers that interpolate many points at once.
    bool isBilinearAlongU(uint32_t i, float u) const {
        return u != 0.0f && u != 1.0f && !(i == resolution_ - 1 && (finer_ & 2)) && !(i == 0 && (finer_ & 8));
    }
    bool isBilinearAlongV(uint32_t j, float v) const {
        return v != 0.0f && v != 1.0f && !(j == 0 && (finer_ & 1)) && !(j == resolution_ - 1 && (finer_ & 4));
    }
    const float* grid() const { return grid_; }

private:
    DisplacementValue evaluateNearEdges(float u, float v) const;  // evaluateDisplacement's whole formula

    const Displacement& displacement_;
    const DisplacementSubface& subface_;
    uint32_t resolution_;
    uint32_t finer_;  // bit e: edge e is finer than the grid (kEdgeFiner)
    float grid_[(kMaxDisplacementResolution + 1) * (kMaxDisplacementResolution + 1)];  // row-major, u fastest
};

// Value of segment `segment` at canonical parameter t in [0, 1] (no snapping), and d/dt.
DisplacementValue evaluateSegment(const Displacement& displacement, uint32_t segment, float t);

// Sample index of grid point (i, j), 0 <= i, j <= R, of a sub-face.
uint32_t gridSample(const DisplacementLayout& layout, uint32_t subface, uint32_t i, uint32_t j);
// gridSample of every grid point of a sub-face, row-major ((R+1)^2 of them, i fastest).
void gridSamples(const DisplacementLayout& layout, uint32_t subface, uint32_t* out);

// Sample index of sample k (0..S) of a segment.
inline uint32_t segmentSample(const DisplacementSegment& s, uint32_t k) {
    return k == 0 ? s.pointA : k == s.resolution ? s.pointB : s.offset + k - 1;
}

// Segment samples of a sub-face edge, as (segment, canonical sample k of S) for the sub-face
// edge's own parameter t = i / n, 0 <= i <= n, when n intervals on this edge land on samples.
struct EdgeSite {
    uint32_t segment;
    uint32_t k, intervals;  // canonical index and interval count on that segment
};
// Splits sub-face edge point i of n (n intervals over the whole sub-face edge; n even for a
// split edge) into its segment and the canonical index on it.
EdgeSite edgeSite(const DisplacementSubface& subface, uint32_t edge, uint32_t i, uint32_t n);

// Parameter along sub-face edge `edge` (in its own direction) of canonical point k of m
// intervals on its segment `half` (0: the whole edge, or the first half of a split edge; 1:
// the second half), computed from integers so that every user gets the same float.
float edgeParameter(const DisplacementEdge& edge, uint32_t half, uint32_t k, uint32_t m);

// (u, v) of parameter t on sub-face edge e.
glm::vec2 edgePoint(uint32_t edge, float t);
constexpr float kCornerU[4] = {0.0f, 1.0f, 1.0f, 0.0f};
constexpr float kCornerV[4] = {0.0f, 0.0f, 1.0f, 1.0f};

// Resampled copy with new per-sub-face resolutions that keeps the shape: every new sample
// takes the old D at its position. Raising reproduces the old surface (bilinear refines
// bilinear exactly, up to the boundary strips of edges finer than the old grid); lowering
// keeps the old values at the samples that remain (injection), so raise-then-lower gives back
// the original bit for bit. Unchanged segments and tiles are copied. A mask is resampled the
// same way (it interpolates like D; values stay in [0, 1]); an empty mask stays empty.
Displacement resampleDisplacement(const Displacement& displacement, std::span<const uint32_t> resolutions);

// Per-sub-face resolutions of a layout.
std::vector<uint32_t> subfaceResolutions(const DisplacementLayout& layout);

// Tessellation factors a renderer needs so that no stored sample is skipped: the inside
// factor is R; edge e needs the intervals of its segment, and a cage edge split at its
// midpoint needs k = the finer half's intervals on each n-gon sub-face and 2k on the quad
// side (the renderer's convention), so both sides of every edge ask for the same.
// With power-of-two factors at least these, every sample is a tessellation vertex.
uint32_t requiredEdgeFactor(const DisplacementLayout& layout, uint32_t subface, uint32_t edge);
uint32_t requiredTessellationFactor(const DisplacementLayout& layout, uint32_t subface);

// The displaced point s + D N and its shading normal. The normal's own derivatives are
// dropped (Blinn's approximation, as Nießner & Loop's fast variant): f_u ~ s_u + D_u N, which
// needs no second derivatives of the limit surface (the plan evaluators give none) and errs
// by the factor (1 + D kappa) on the tangents, i.e. not at all where the surface is flat.
struct DisplacedPoint {
    glm::vec3 position, normal;
};
// Inline: renderers call it for every vertex of a grid.
inline DisplacedPoint displacePoint(const glm::vec3& position, const glm::vec3& du, const glm::vec3& dv,
                                    const glm::vec3& unitNormal, const DisplacementValue& d) {
    DisplacedPoint out;
    out.position = position + d.value * unitNormal;
    const glm::vec3 fu = du + d.du * unitNormal, fv = dv + d.dv * unitNormal;
    const glm::vec3 n = glm::cross(fu, fv);
    const float length = glm::length(n);
    out.normal = length > 0.0f ? n / length : unitNormal;
    return out;
}

}  // namespace qp
