// TopologyDelta: the difference between a cage and the cage a topology edit made from it,
// holding only what differs (faces removed, changed or created; vertices removed, created or
// moved; tags that differ), so that an undo history stays small. It applies in either
// direction and gives back a TopologyEdit for PlannedCage::applyTopologyEdit, so undo and redo
// re-plan only what the edit affected.
//
// It relies on the numbering rules of topology_edits.h: surviving faces and vertices keep their
// relative order. A face whose vertex list changed is stored as removed on one side and
// created on the other (re-planned either way).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "mesh/cage.h"
#include "mesh/result.h"
#include "mesh/topology_edits.h"

namespace qp {

// What only one side of the delta has, in that side's numbering.
struct CageDeltaSide {
    uint32_t faceCount = 0, vertexCount = 0;
    std::vector<uint32_t> faces;                // sorted face indices only this side has
    std::vector<uint32_t> faceOffsets{0};       // CSR: vertices of faces[i]
    std::vector<uint32_t> faceVertices;
    std::vector<uint32_t> faceUVIndices;        // parallels faceVertices when the cage has UVs
    std::vector<uint32_t> vertices;             // sorted vertex indices only this side has
    std::vector<glm::vec3> vertexPositions;
    std::vector<uint32_t> movedVertices;        // vertices of both sides whose positions differ
    std::vector<glm::vec3> movedPositions;
    std::vector<EdgeCrease> creases;            // tags only this side has
    std::vector<VertexCorner> corners;
    std::vector<uint32_t> holes;
    std::vector<glm::vec2> uvTail;              // uvs after the common prefix
    SubdivisionOptions options;

    size_t bytes() const;
};

struct TopologyDelta {
    CageDeltaSide before, after;
    uint32_t commonUVs = 0;  // length of the uv prefix both sides share

    size_t bytes() const { return sizeof(*this) + before.bytes() + after.bytes(); }
};

// The delta from `before` to edit.cage. The edit must have passed finishTopologyEdit against
// `before` (every operation of topology_edits.h does that).
TopologyDelta makeTopologyDelta(const Cage& before, const TopologyEdit& edit);

enum class DeltaDirection : uint8_t { Forward, Backward };

// Rebuilds the other side from `cage`, which must equal the delta's starting side (the
// `before` side for Forward, `after` for Backward); fails when its counts do not match.
Result<TopologyEdit> applyTopologyDelta(const Cage& cage, const TopologyDelta& delta, DeltaDirection direction);

}  // namespace qp
