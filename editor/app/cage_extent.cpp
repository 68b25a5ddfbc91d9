#include "cage_extent.h"

#include <algorithm>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace qp::editor {

namespace {

// Face edge k of face f: from corner k to corner k + 1.
double faceEdgeLength(const Cage& cage, uint32_t face, uint32_t k) {
    const uint32_t* corners = cage.faceBegin(face);
    const uint32_t n = cage.faceSize(face);
    return glm::length(cage.positions[corners[k]] - cage.positions[corners[(k + 1) % n]]);
}

// Whether p lies strictly inside the box (on none of its sides).
bool strictlyInside(const glm::vec3& p, const Bounds& b) {
    return glm::all(glm::greaterThan(p, b.min)) && glm::all(glm::lessThan(p, b.max));
}

}  // namespace

CageExtent measureCage(const Cage& cage) {
    CageExtent extent;
    extent.bounds = computeBounds(cage);
    for (uint32_t f = 0; f < cage.faceCount(); ++f)
        for (uint32_t k = 0, n = cage.faceSize(f); k < n; ++k) extent.edgeLengthSum += faceEdgeLength(cage, f, k);
    extent.faceEdges = cage.faceVertices.size();
    return extent;
}

void carryExtent(CageExtent& extent, const Cage& cage, const Topology& topology, const PositionStep& step) {
    // The face edges with a moved end, each once: (face, corner) pairs.
    std::vector<std::pair<uint32_t, uint32_t>> edges;
    for (uint32_t v : step.vertices)
        for (uint32_t i = topology.vertexFaceOffsets[v]; i < topology.vertexFaceOffsets[v + 1]; ++i) {
            const uint32_t f = topology.vertexFaces[i], n = cage.faceSize(f);
            const uint32_t* corners = cage.faceBegin(f);
            for (uint32_t k = 0; k < n; ++k)
                if (corners[k] == v) {
                    edges.push_back({f, k});
                    edges.push_back({f, (k + n - 1) % n});
                }
        }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    // The old lengths: the moved ends at their old positions.
    auto positionBefore = [&](uint32_t v) {
        const auto it = std::lower_bound(step.vertices.begin(), step.vertices.end(), v);
        return it != step.vertices.end() && *it == v ? step.before[it - step.vertices.begin()] : cage.positions[v];
    };
    for (const auto& [f, k] : edges) {
        const uint32_t* corners = cage.faceBegin(f);
        const uint32_t n = cage.faceSize(f);
        extent.edgeLengthSum -= glm::length(positionBefore(corners[k]) - positionBefore(corners[(k + 1) % n]));
        extent.edgeLengthSum += faceEdgeLength(cage, f, k);
    }

    const bool onTheBox = std::any_of(step.before.begin(), step.before.end(),
                                      [&](const glm::vec3& p) { return !strictlyInside(p, extent.bounds); });
    if (onTheBox) {
        extent.bounds = computeBounds(cage);
        return;
    }
    for (uint32_t v : step.vertices) {
        extent.bounds.min = glm::min(extent.bounds.min, cage.positions[v]);
        extent.bounds.max = glm::max(extent.bounds.max, cage.positions[v]);
    }
}

}  // namespace qp::editor
