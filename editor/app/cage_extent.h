// The edited cage's extent: its bounds and the mean length of its face edges, which framing,
// the ground grid, pick tolerances, brush sizes and the adaptive tessellation factor read on
// every frame.
//
// Why a cache. Each of those passes over every position (12 MB at a million vertices), several
// times a frame; during a drag the positions change every frame. The extent is computed over
// the whole cage once per position revision, and after a drag step (Document::lastMove: the
// revision it started from and the moved vertices with their old positions) it is carried from
// the previous revision through the moved vertices alone:
//   - the bounds stay those of the other vertices when no moved vertex lay on the box (one of
//     them attains each side), so they become that box grown by the new positions; otherwise
//     they are computed again;
//   - the sum of face-edge lengths loses the old lengths of the face edges at a moved vertex and
//     gains their new ones (in double: what the sum drifts by, the factor choice cannot see).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "mesh/cage.h"
#include "mesh/topology.h"

namespace qp::editor {

// A step of the positions: from position revision `from` to from + 1 these vertices (sorted,
// each once) moved from `before`, and no other did (a drag step; none for a tag edit).
struct PositionStep {
    static constexpr uint64_t kNone = ~0ull;
    uint64_t from = kNone;
    std::vector<uint32_t> vertices;
    std::vector<glm::vec3> before;

    // Whether it leads from what a consumer saw (`seen`) to the present (`now`).
    bool leads(uint64_t seen, uint64_t now) const { return from != kNone && seen == from && now == from + 1; }
};

struct CageExtent {
    uint64_t revision = ~0ull;  // the position revision it describes
    uint64_t cage = ~0ull;      // and the edited cage's revision (edit mode moved to another cage)
    Bounds bounds;
    double edgeLengthSum = 0.0;  // over the face edges (an edge between two faces counts twice)
    uint64_t faceEdges = 0;

    float meanEdgeLength() const { return faceEdges ? float(edgeLengthSum / double(faceEdges)) : 1.0f; }
};

// The extent of `cage` computed over all of it.
CageExtent measureCage(const Cage& cage);

// `extent` (of the cage before `step`) carried to the cage after it (see above).
void carryExtent(CageExtent& extent, const Cage& cage, const Topology& topology, const PositionStep& step);

}  // namespace qp::editor
