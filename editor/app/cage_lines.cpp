#include "cage_lines.h"

#include <algorithm>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

namespace qp::editor {

namespace {

void setLine(std::vector<LineVertex>& set, uint32_t line, const Cage& cage, uint32_t a, uint32_t b, const glm::vec3& color) {
    set[2 * line] = {cage.positions[a], color};
    set[2 * line + 1] = {cage.positions[b], color};
}

// Removes `line` from a set by moving the last line into its place.
void removeLine(CageLines& lines, bool creased, uint32_t line) {
    std::vector<LineVertex>& set = creased ? lines.creased : lines.plain;
    std::vector<uint32_t>& edgeOf = creased ? lines.creasedEdge : lines.plainEdge;
    const uint32_t last = uint32_t(edgeOf.size()) - 1;
    if (line != last) {
        set[2 * line] = set[2 * last];
        set[2 * line + 1] = set[2 * last + 1];
        edgeOf[line] = edgeOf[last];
        lines.lineOf[edgeOf[line]] = line | (creased ? CageLines::kCreased : 0);
        (creased ? lines.changedCreased : lines.changedPlain).push_back(line);
    }
    set.resize(2 * last);
    edgeOf.pop_back();
}

}  // namespace

void rebuildCageLines(CageLines& lines, const Cage& cage, const Topology& topology,
                      const std::function<bool(uint32_t edge)>& shown) {
    lines.plain.clear();
    lines.creased.clear();
    lines.plainEdge.clear();
    lines.creasedEdge.clear();
    lines.lineOf.assign(topology.edgeCount(), CageLines::kNotShown);
    lines.plain.reserve(2 * size_t(topology.edgeCount()));
    lines.plainEdge.reserve(topology.edgeCount());
    const std::vector<float> sharpness = edgeSharpnesses(cage, topology);
    for (uint32_t e = 0; e < topology.edgeCount(); ++e) {
        if (shown && !shown(e)) continue;
        const uint32_t a = topology.edgeVertices[2 * e], b = topology.edgeVertices[2 * e + 1];
        const glm::vec3 color = cageEdgeColor(sharpness[e], topology.edgeFaceCount(e) == 1);
        const bool creased = sharpness[e] > 0.0f;
        std::vector<uint32_t>& edgeOf = creased ? lines.creasedEdge : lines.plainEdge;
        lines.lineOf[e] = uint32_t(edgeOf.size()) | (creased ? CageLines::kCreased : 0);
        edgeOf.push_back(e);
        std::vector<LineVertex>& set = creased ? lines.creased : lines.plain;
        set.push_back({cage.positions[a], color});
        set.push_back({cage.positions[b], color});
    }
    lines.changedPlain.clear();
    lines.changedCreased.clear();
    lines.wholePlain = lines.wholeCreased = true;

    std::vector<float> lengths(lines.plainEdge.size());
    for (size_t k = 0; k < lengths.size(); ++k)
        lengths[k] = glm::length(lines.plain[2 * k + 1].position - lines.plain[2 * k].position);
    lines.longPlainEdge = 0.0f;
    if (!lengths.empty()) {
        const auto percentile = lengths.begin() + std::ptrdiff_t(lengths.size() * 9 / 10);
        std::nth_element(lengths.begin(), percentile, lengths.end());
        lines.longPlainEdge = *percentile;
    }
}

bool plainLinesReadable(const CageLines& lines, const Bounds& cageBounds, const glm::mat4& viewProjection,
                        const glm::vec3& eye, float pixelsPerUnit) {
    if (lines.plain.empty() || !(cageBounds.min.x <= cageBounds.max.x)) return true;
    const glm::vec3 nearest = glm::clamp(eye, cageBounds.min, cageBounds.max);
    // Clip w is the depth along the view for a perspective camera, 1 for an orthographic one:
    // pixelsPerUnit / w is the scale at that point either way.
    const float w = (viewProjection * glm::vec4(nearest, 1.0f)).w;
    if (!(w > 0.0f)) return true;
    return lines.longPlainEdge * pixelsPerUnit / w >= kReadableEdgePixels;
}

void moveCageLines(CageLines& lines, const Cage& cage, const Topology& topology, std::span<const uint32_t> vertices) {
    for (uint32_t v : vertices)
        for (uint32_t k = topology.vertexEdgeOffsets[v]; k < topology.vertexEdgeOffsets[v + 1]; ++k) {
            const uint32_t e = topology.vertexEdges[k], line = lines.lineOf[e];
            if (line == CageLines::kNotShown) continue;
            const bool creased = line & CageLines::kCreased;
            const uint32_t index = line & ~CageLines::kCreased;
            std::vector<LineVertex>& set = creased ? lines.creased : lines.plain;
            set[2 * index].position = cage.positions[topology.edgeVertices[2 * e]];
            set[2 * index + 1].position = cage.positions[topology.edgeVertices[2 * e + 1]];
            (creased ? lines.changedCreased : lines.changedPlain).push_back(index);
        }
}

void retagCageLines(CageLines& lines, const Cage& cage, const Topology& topology, std::span<const uint32_t> faces) {
    for (uint32_t f : faces)
        for (uint32_t i = cage.faceOffsets[f]; i < cage.faceOffsets[f + 1]; ++i) {
            const uint32_t e = topology.faceEdges[i], line = lines.lineOf[e];
            if (line == CageLines::kNotShown) continue;
            const uint32_t a = topology.edgeVertices[2 * e], b = topology.edgeVertices[2 * e + 1];
            const float sharpness = cage.edgeSharpness(a, b);
            const glm::vec3 color = cageEdgeColor(sharpness, topology.edgeFaceCount(e) == 1);
            const bool wasCreased = line & CageLines::kCreased, creased = sharpness > 0.0f;
            uint32_t index = line & ~CageLines::kCreased;
            if (wasCreased != creased) {
                removeLine(lines, wasCreased, index);
                std::vector<uint32_t>& edgeOf = creased ? lines.creasedEdge : lines.plainEdge;
                index = uint32_t(edgeOf.size());
                edgeOf.push_back(e);
                lines.lineOf[e] = index | (creased ? CageLines::kCreased : 0);
                (creased ? lines.creased : lines.plain).resize(2 * (index + 1));
            }
            setLine(creased ? lines.creased : lines.plain, index, cage, a, b, color);
            (creased ? lines.changedCreased : lines.changedPlain).push_back(index);
        }
}

}  // namespace qp::editor
