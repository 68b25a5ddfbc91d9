// GpuPlans: the plan database and a cage's sub-face table flattened into the std430 arrays
// the plan shaders read (render/shaders/plan_eval.glsl documents the same layout).
//
// Node `first` fields are made absolute here: an internal node's children index `nodes`
// directly and a leaf's points index `points` directly, so the shaders need no per-plan
// offsets while descending. Point values are stencil indices relative to the sub-face's
// control-point base (GpuSubface::cpOffset).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec4.hpp>

#include "macro_grid.h"
#include "plans/planned_cage.h"

namespace qp {

struct GpuPlanHeader {
    uint32_t rootNode;       // index into nodes
    uint32_t weightOffset;   // index into weights of stencil 0
    uint32_t ringSize;
    uint32_t maxDepth;
    uint32_t stencilCountByLevel[12];  // [n] stencils serve factors <= 2^n; [11]: Plan::cornerTangents
};
static_assert(sizeof(GpuPlanHeader) == 64);

struct GpuNode {
    uint32_t kind_mask_edge_levels;  // kind | boundaryMask << 8 | edge << 16 | levels << 24
    uint32_t first;
    float sharpness;
    uint32_t unused;
};
static_assert(sizeof(GpuNode) == 16);

struct GpuSubface {
    uint32_t plan;
    uint32_t rotation;
    uint32_t ringOffset;  // index into rings
    uint32_t cpOffset;    // index into the control-point buffer
    uint32_t subface;     // PlannedCage sub-face (Ptex face) index
    uint32_t unused[3];
};
static_assert(sizeof(GpuSubface) == 32);

// Watertightness by ownership. A tessellation vertex on a sub-face's boundary is evaluated by
// the one sub-face that owns that boundary point or segment, at a parameter rebuilt from the
// integer tessellation index, so every face sharing it computes the same bits.
//
// Boundary points: cage vertices, midpoints of cage edges next to a non-quad, face centres of
// non-quads (ids: vertex v; edge e -> V + e; face f -> V + E + f). Segments join two points:
// a cage edge between two quads is one segment; a cage edge next to a non-quad is split at its
// midpoint into two (a quad on it sees two half segments); an n-gon's spokes are segments.
// Sub-face edges: 0 is v=0 (corner 0 -> 1), 1 is u=1 (1 -> 2), 2 is v=1 (3 -> 2), 3 is u=0
// (0 -> 3). Quad sub-face corners are the face's corners; n-gon sub-face k has corners
// (vertex k, midpoint of edge k, centre, midpoint of edge k-1).
// A split edge's first half runs from its start to the midpoint (always along the half's
// canonical direction, as midpoint ids are higher than vertex ids) and its second half from
// the midpoint to its end (always against it).
struct GpuEdgeRef {
    uint32_t segment;   // the only segment, or the first half of a split edge
    uint32_t flags;     // bit 0: runs against the segment's canonical direction; bit 1: split;
                        // bit 2: this edge is half of a cage edge (n-gon sub-face edges 0, 3)
    uint32_t midpoint;  // split and half edges: the cage edge's midpoint
    uint32_t secondHalf;  // split edges: the second half's segment
};
constexpr uint32_t kEdgeRefReversed = 1, kEdgeRefSplit = 2, kEdgeRefHalf = 4;  // GpuEdgeRef::flags

struct GpuSubfaceBoundary {
    GpuEdgeRef edges[4];
    uint32_t corners[4];  // boundary point at each corner
};
static_assert(sizeof(GpuSubfaceBoundary) == 80);

// Canonical direction: from the lower point id to the higher.
struct GpuSegment {
    uint32_t owner;      // drawn sub-face that evaluates it
    uint32_t ownerEdge;  // bits 0-1: the owner's edge; bits 2-3: 0 the whole edge, 1 its first
                         // half, 2 its second half (a quad owning half of a split edge)
    uint32_t ownerReversed;  // the owner's edge (or half) runs against the canonical direction
    uint32_t unused;
};

struct GpuPoint {
    uint32_t owner;
    uint32_t ownerCorner;
};

struct GpuPlanData {
    std::vector<GpuPlanHeader> plans;
    std::vector<GpuNode> nodes;
    std::vector<uint32_t> points;
    std::vector<float> weights;
    // Only sub-faces with a (planned) surface, one primitive each; holes are here too, evaluated
    // (they own edges their neighbours copy) but never drawn (PlanBuffers::holeDrawn), so that
    // making or filling a hole changes no other sub-face.
    std::vector<GpuSubface> subfaces;
    // The 1-rings for the device (GpuSubface::ringOffset); empty with hostEvaluation, where
    // the host reads the planned cage's (PlannedCage::subfaceRing) and the device reads none.
    std::vector<uint32_t> rings;
    uint32_t ringEntries = 0;          // the rings' total length, packed or not
    uint32_t controlPointCount = 0;    // all stencils of all drawn sub-faces

    std::vector<GpuSubfaceBoundary> boundaries;  // parallels subfaces
    std::vector<GpuSegment> segments;
    std::vector<GpuPoint> boundaryPoints;        // indexed by boundary point id

    // Not uploaded: macro faces for drawing far-away regions (macro_grid.h): uploadPlans builds
    // them (packPlans leaves them empty), repacks that renumber sub-faces build them again.
    MacroGrid macros;

    // Evaluated on the host (the CPU grid path): the plans' stencils (points and weights) are
    // not packed, PlannedCage evaluates from the plan database that holds them, and the device
    // keeps no copy of them, of the rings and cage positions its evaluation reads, or of what
    // the tessellator's factors read (boundaries, segments, boundary points and their
    // positions): uploadPlans. Headers, nodes and sub-faces stay, for the colour modes. 1 GiB
    // less at a million faces (bench scale's peak 3,970 -> 2,971 MiB with the stencils alone).
    bool hostEvaluation = false;

    // Not uploaded; for incremental updates. CSR: cage vertex -> the drawn sub-faces whose
    // 1-ring holds it (whose control points move with it), ascending.
    std::vector<uint32_t> vertexSubfaceOffsets, vertexSubfaces;
};

// Sorted, duplicate-free drawn sub-faces whose 1-ring holds one of `vertices`.
std::vector<uint32_t> subfacesAround(const GpuPlanData& data, std::span<const uint32_t> vertices);

// Ids of the boundary points whose position depends on one of `vertices`: the vertices, the
// midpoints of their edges and the centres of their faces (see boundaryPointPositions).
std::vector<uint32_t> boundaryPointsAround(const PlannedCage& planned, std::span<const uint32_t> vertices);

// Positions of every boundary point (for tessellation factors), from the cage positions; a
// cage-edge midpoint has the radius of that edge's bounding sphere in w, other points 1.
std::vector<glm::vec4> boundaryPointPositions(const PlannedCage& planned);
// The cage's vertex positions as the positions buffer holds them (x, y, z per vertex, packed).
std::vector<float> cagePositions(const PlannedCage& planned);
glm::vec4 boundaryPointPosition(const PlannedCage& planned, uint32_t id);

GpuPlanData packPlans(const PlannedCage& planned, bool hostEvaluation = false);

// The sub-face part of packPlans (sub-faces, rings, control-point offsets, boundaries, segments,
// boundary points), replacing what `gpu` had; the plan tables stay (they must hold every plan
// the cage uses: appendPlanTables). The ring users are left to buildRingUsers or
// renumberRingUsers.
void packSubfaces(GpuPlanData& gpu, const PlannedCage& planned);

// The ring users (vertexSubfaceOffsets, vertexSubfaces) of the drawn sub-faces' 1-rings in
// `planned` (the ones packSubfaces packed), by counting sort.
void buildRingUsers(GpuPlanData& gpu, const PlannedCage& planned);

// Whether drawn sub-face `drawn`'s 1-ring, as the ring users list it (as packed, before an
// edit), holds the vertices of `ring`, each as many times.
bool ringUsersMatch(const GpuPlanData& gpu, uint32_t drawn, std::span<const uint32_t> ring);

// The same from the ring users before a change of the drawn set that kept every ring (holes):
// each vertex's list renumbered through `oldOf` (drawn sub-face now -> before, or UINT32_MAX for
// one drawn only now, whose ring joins). One pass in vertex order instead of a scatter over
// every ring.
void renumberRingUsers(GpuPlanData& gpu, const PlannedCage& planned, const std::vector<uint32_t>& oldOffsets,
                       const std::vector<uint32_t>& oldUsers, const std::vector<uint32_t>& oldOf, uint32_t oldCount);

// Appends the database's plans that `gpu` does not have yet (ids gpu.plans.size() onwards): the
// plan tables only ever grow, so plan ids stay the database's. With gpu.hostEvaluation their
// stencils are left out.
void appendPlanTables(GpuPlanData& gpu, const PlanDatabase& database);

}  // namespace qp
