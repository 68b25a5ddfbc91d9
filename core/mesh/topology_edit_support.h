// Helpers shared by the topology edit operations (topology_edits.h); not part of the public API.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "mesh/topology_edits.h"

namespace qp::edit_support {

// 1-based names, as every user-facing message in the project spells them.
inline std::string faceName(uint32_t face) { return "face " + std::to_string(face + 1); }
inline std::string vertexName(uint32_t vertex) { return "vertex " + std::to_string(vertex + 1); }
inline std::string edgeName(uint32_t a, uint32_t b) {
    return "edge " + std::to_string(a + 1) + "-" + std::to_string(b + 1);
}

// The texture-coordinate indices of a face's corners; empty when the cage has no UVs.
inline std::span<const uint32_t> faceUVs(const Cage& cage, uint32_t face) {
    if (cage.faceUVIndices.empty()) return {};
    return {cage.faceUVIndices.data() + cage.faceOffsets[face], cage.faceSize(face)};
}
inline std::span<const uint32_t> faceSpan(const Cage& cage, uint32_t face) {
    return {cage.faceBegin(face), cage.faceSize(face)};
}

// An edit whose cage has the input's vertices, tags and options but no faces yet; vertex map
// identity, face map empty. Operations then append faces (appendFace) and fix up tags.
TopologyEdit startEdit(const Cage& cage);

// Appends a face and records where it came from. `uvIndices` must be given (one per corner)
// exactly when the cage has per-corner UV indices, and be empty otherwise.
void appendFace(TopologyEdit& edit, std::span<const uint32_t> vertices, std::span<const uint32_t> uvIndices,
                uint32_t oldFace);

// Faces of the input that are in `faces`, validated (in range) and de-duplicated, sorted.
Result<std::vector<uint32_t>> checkedFaceSet(const Cage& cage, std::span<const uint32_t> faces, const std::string& what);

// Drops creases on vertex pairs that no face of the cage has as an edge.
void dropCreasesWithoutEdge(Cage& cage);

// Re-derives the hole list: the new face f is a hole when oldFaceOf[f] was one, or when
// `newHoles` (sorted new indices) names it.
void carryHoles(const Cage& before, TopologyEdit& edit, const std::vector<uint32_t>& newHoles = {});

// Removes the flagged vertices, which no face may use: compacts positions, renumbers faces,
// creases, corners and edit.oldVertexOf, and drops tags on removed vertices.
void removeVertices(TopologyEdit& edit, const std::vector<bool>& remove);

}  // namespace qp::edit_support
