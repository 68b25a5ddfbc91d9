// VertexSubfaceIndex: for each cage vertex, the sub-faces (of a chosen list) whose 1-ring holds
// it. The limit surface over a sub-face depends on its 1-ring only (PlannedCage), so after a
// vertex move exactly these sub-faces change: the heat map and the limit picker refresh just them.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "plans/planned_cage.h"

namespace qp::editor {

class VertexSubfaceIndex {
public:
    VertexSubfaceIndex() = default;
    // `subfaces` in the order callers number them; entries are positions in that list.
    VertexSubfaceIndex(const PlannedCage& planned, std::span<const uint32_t> subfaces);

    // Positions (into the list given at construction) of the sub-faces seeing any of the
    // vertices, sorted and unique. Vertices out of range are ignored.
    std::vector<uint32_t> touched(std::span<const uint32_t> vertices) const;

private:
    std::vector<uint32_t> offsets_, entries_;  // CSR per vertex
};

// The vertices whose positions differ between the two arrays (same length), sorted.
std::vector<uint32_t> movedVertices(std::span<const glm::vec3> before, std::span<const glm::vec3> after);

}  // namespace qp::editor
