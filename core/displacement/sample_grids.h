// Sample grids: the sub-faces' boundary topology (points and segments shared between sub-faces)
// and the displacement representation of scene files version 1 (docs/displacement.md).
//
// Two users:
//   - every displacement: the tiles of displacement.h are built from a SampleGridLayout's
//     corners, edges and segments (at resolution 1, which holds no samples), its point ids and
//     canonical segment directions;
//   - files of version 1, which stored D as per-sub-face grids of samples with shared boundary
//     samples, bilinear in between (multiresolution attributes, Schäfer et al. 2012): they load
//     by fitting the tiles to evaluateSampleGrids.
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
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <algorithm>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "mesh/cage.h"
#include "mesh/topology.h"

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

struct SampleGridLayout {
    uint32_t vertexCount = 0, edgeCount = 0, faceCount = 0;
    uint32_t pointCount = 0;    // V + E + F: samples[0, pointCount) are the points
    uint32_t sampleCount = 0;   // points + segment interiors + tile interiors
    std::vector<DisplacementSubface> subfaces;  // one per sub-face
    std::vector<DisplacementSegment> segments;  // cage edges (whole, or two halves) in edge order, then spokes

    uint32_t segmentSampleBegin() const { return pointCount; }
    uint32_t tileSampleBegin() const;

    bool operator==(const SampleGridLayout&) const;
};

// Layout for a cage (that passed validateCage) with every sub-face at `resolution`.
SampleGridLayout buildSampleGridLayout(const Cage& cage, const Topology& topology, uint32_t resolution);

// The same topology with new per-sub-face resolutions (each a power of two in
// 1..kMaxDisplacementResolution, one per sub-face): segment resolutions and offsets follow.
SampleGridLayout withResolutions(const SampleGridLayout& layout, std::span<const uint32_t> resolutions);

struct SampleGrids {
    SampleGridLayout layout;   // empty: no displacement at all
    std::vector<float> samples;  // layout.sampleCount values
    // The sculpting mask: empty (nothing masked) or one value in [0, 1] per sample, parallel to
    // `samples`; 1 is fully masked (brushes that change D leave the sample alone), 0 not at
    // all. Only brushes read it: renderers and exporters ignore it.
    std::vector<float> mask;

    bool empty() const { return layout.subfaces.empty(); }
    bool hasMask() const { return !mask.empty(); }
    // Equal layouts, samples and masks, where an empty mask equals one of zeros (both mask
    // nothing: undoing the first mask stroke leaves a mask of zeros, not an empty one).
    bool operator==(const SampleGrids&) const;
};

// All samples zero.
SampleGrids makeSampleGrids(const Cage& cage, const Topology& topology, uint32_t resolution);

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
DisplacementValue evaluateSampleGrids(const SampleGrids& displacement, uint32_t subface, float u, float v);

// Sample index of grid point (i, j), 0 <= i, j <= R, of a sub-face.
uint32_t gridSample(const SampleGridLayout& layout, uint32_t subface, uint32_t i, uint32_t j);
// gridSample of every grid point of a sub-face, row-major ((R+1)^2 of them, i fastest).
void gridSamples(const SampleGridLayout& layout, uint32_t subface, uint32_t* out);

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

}  // namespace qp
