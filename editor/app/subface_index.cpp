#include "subface_index.h"

#include <algorithm>

namespace qp::editor {

VertexSubfaceIndex::VertexSubfaceIndex(const PlannedCage& planned, std::span<const uint32_t> subfaces) {
    const uint32_t vertexCount = planned.cage().vertexCount();
    offsets_.assign(vertexCount + 1, 0);
    for (uint32_t s : subfaces)
        for (uint32_t v : planned.subfaceRing(s)) ++offsets_[v + 1];
    for (uint32_t v = 0; v < vertexCount; ++v) offsets_[v + 1] += offsets_[v];
    entries_.resize(offsets_.back());
    std::vector<uint32_t> next(offsets_.begin(), offsets_.end() - 1);
    for (uint32_t i = 0; i < subfaces.size(); ++i)
        for (uint32_t v : planned.subfaceRing(subfaces[i])) entries_[next[v]++] = i;
}

std::vector<uint32_t> VertexSubfaceIndex::touched(std::span<const uint32_t> vertices) const {
    std::vector<uint32_t> out;
    for (uint32_t v : vertices)
        if (v + 1 < offsets_.size()) out.insert(out.end(), entries_.begin() + offsets_[v], entries_.begin() + offsets_[v + 1]);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

std::vector<uint32_t> movedVertices(std::span<const glm::vec3> before, std::span<const glm::vec3> after) {
    std::vector<uint32_t> moved;
    const size_t n = std::min(before.size(), after.size());
    for (size_t i = 0; i < n; ++i)
        if (before[i] != after[i]) moved.push_back(uint32_t(i));
    return moved;
}

}  // namespace qp::editor
