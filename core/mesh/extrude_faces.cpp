// extrudeFaces: region extrude (see topology_edits.h for the rules).
#include <algorithm>
#include <cmath>
#include <numeric>

#include <glm/geometric.hpp>

#include "mesh/topology_edit_support.h"

namespace qp {

using namespace edit_support;

namespace {

// Twice the area vector of a polygon (its direction is the face normal for any planar or
// gently non-planar polygon).
glm::vec3 areaVector(const Cage& cage, uint32_t face) {
    glm::vec3 sum(0.0f);
    const uint32_t n = cage.faceSize(face);
    const uint32_t* fv = cage.faceBegin(face);
    for (uint32_t i = 0; i < n; ++i) sum += glm::cross(cage.positions[fv[i]], cage.positions[fv[(i + 1) % n]]);
    return sum;
}

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

}  // namespace

Result<TopologyEdit> extrudeFaces(const Cage& cage, const Topology& topology, std::span<const uint32_t> faces,
                                  float distance) {
    const std::string what = "extrude";
    auto checked = checkedFaceSet(cage, faces, what);
    if (!checked) return checked.error();
    const std::vector<uint32_t>& region = *checked;
    if (!std::isfinite(distance)) return Error{what + ": the distance must be a finite number"};

    std::vector<bool> selected(cage.faceCount(), false);
    for (uint32_t f : region) {
        selected[f] = true;
        std::span<const uint32_t> fv = faceSpan(cage, f);
        for (uint32_t i = 0; i < fv.size(); ++i)
            if (std::find(fv.begin() + i + 1, fv.end(), fv[i]) != fv.end())
                return Error{what + ": " + faceName(f) + " visits " + vertexName(fv[i]) +
                             " twice; extruding a pinched face is not defined"};
    }

    // Edges: used once by the selection = region boundary (gets a side quad); twice by the
    // selection and by nothing else = region interior; anything else is ill-defined.
    std::vector<uint32_t> selectedUses(topology.edgeCount(), 0);
    for (uint32_t f : region)
        for (uint32_t i = cage.faceOffsets[f]; i < cage.faceOffsets[f + 1]; ++i) ++selectedUses[topology.faceEdges[i]];
    std::vector<bool> duplicate(cage.vertexCount(), false);
    for (uint32_t e = 0; e < topology.edgeCount(); ++e) {
        const uint32_t uses = selectedUses[e], total = topology.edgeFaceCount(e);
        const uint32_t a = topology.edgeVertices[2 * e], b = topology.edgeVertices[2 * e + 1];
        if (uses == 1) {
            duplicate[a] = duplicate[b] = true;
        } else if (uses >= 2 && !(uses == 2 && total == 2)) {
            return Error{what + ": " + edgeName(a, b) + " is shared by " + std::to_string(uses) +
                         " selected faces and " + std::to_string(total - uses) +
                         " other faces; extruding across a non-manifold edge is not defined"};
        }
    }
    // A region vertex that an unselected face also uses stays with that face.
    for (uint32_t f : region)
        for (uint32_t v : faceSpan(cage, f))
            for (uint32_t k = topology.vertexFaceOffsets[v]; k < topology.vertexFaceOffsets[v + 1] && !duplicate[v]; ++k)
                if (!selected[topology.vertexFaces[k]]) duplicate[v] = true;

    TopologyEdit edit = startEdit(cage);
    std::vector<uint32_t> copyOf(cage.vertexCount(), kNewElement);
    for (uint32_t v = 0; v < cage.vertexCount(); ++v) {
        if (!duplicate[v]) continue;
        copyOf[v] = uint32_t(edit.cage.positions.size());
        edit.cage.positions.push_back(cage.positions[v]);
        edit.oldVertexOf.push_back(kNewElement);
    }
    if (edit.cage.vertexCount() == cage.vertexCount())
        return Error{what + ": the selected faces form a closed surface with no neighbours; there is no boundary to "
                            "extrude from (move them instead)"};
    auto moved = [&](uint32_t v) { return copyOf[v] != kNewElement ? copyOf[v] : v; };

    // Every face keeps its index and corners (copied whole, not face by face: this runs in the
    // frame of every extrude); the selected faces take the copies.
    size_t sides = 0;  // at most one side quad per corner of the region
    for (uint32_t f : region) sides += cage.faceSize(f);
    edit.cage.faceVertices.reserve(cage.faceVertices.size() + 4 * sides);
    edit.cage.faceVertices.assign(cage.faceVertices.begin(), cage.faceVertices.end());
    edit.cage.faceOffsets.reserve(cage.faceOffsets.size() + sides);
    edit.cage.faceOffsets.assign(cage.faceOffsets.begin(), cage.faceOffsets.end());
    edit.cage.faceUVIndices.assign(cage.faceUVIndices.begin(), cage.faceUVIndices.end());
    edit.oldFaceOf.resize(cage.faceCount());
    std::iota(edit.oldFaceOf.begin(), edit.oldFaceOf.end(), 0u);
    for (uint32_t f : region)
        for (uint32_t i = cage.faceOffsets[f]; i < cage.faceOffsets[f + 1]; ++i)
            edit.cage.faceVertices[i] = moved(cage.faceVertices[i]);
    for (uint32_t f : region) {
        const uint32_t n = cage.faceSize(f);
        const uint32_t* fv = cage.faceBegin(f);
        std::span<const uint32_t> uv = faceUVs(cage, f);
        for (uint32_t i = 0; i < n; ++i) {
            if (selectedUses[topology.faceEdges[cage.faceOffsets[f] + i]] != 1) continue;
            const uint32_t j = (i + 1) % n, a = fv[i], b = fv[j];
            const uint32_t side[4] = {a, b, copyOf[b], copyOf[a]};
            if (uv.empty()) {
                appendFace(edit, side, {}, kNewElement);
            } else {
                const uint32_t sideUV[4] = {uv[i], uv[j], uv[j], uv[i]};
                appendFace(edit, side, sideUV, kNewElement);
            }
        }
    }

    edit.cage.creases.clear();
    for (const EdgeCrease& c : cage.creases) {
        const uint32_t uses = selectedUses[topology.findEdge(c.v0, c.v1)];
        if (uses == 2) {
            EdgeKey k = makeEdgeKey(moved(c.v0), moved(c.v1));
            edit.cage.creases.push_back({k.v0, k.v1, c.sharpness});
        } else {
            edit.cage.creases.push_back(c);
            if (uses == 1) {
                EdgeKey k = makeEdgeKey(copyOf[c.v0], copyOf[c.v1]);
                edit.cage.creases.push_back({k.v0, k.v1, c.sharpness});
            }
        }
    }
    for (const VertexCorner& c : cage.corners)
        if (duplicate[c.vertex]) edit.cage.corners.push_back({copyOf[c.vertex], c.sharpness});
    carryHoles(cage, edit);

    // Regions: selected faces connected through shared vertices; each moves along its normal.
    std::vector<uint32_t> parent(region.size());
    std::iota(parent.begin(), parent.end(), 0u);
    std::vector<uint32_t> regionAtVertex(cage.vertexCount(), kNewElement);
    for (uint32_t r = 0; r < region.size(); ++r)
        for (uint32_t v : faceSpan(cage, region[r])) {
            if (regionAtVertex[v] == kNewElement) regionAtVertex[v] = r;
            else parent[findRoot(parent, r)] = findRoot(parent, regionAtVertex[v]);
        }
    std::vector<glm::vec3> normal(region.size(), glm::vec3(0.0f));
    for (uint32_t r = 0; r < region.size(); ++r) normal[findRoot(parent, r)] += areaVector(cage, region[r]);
    std::vector<bool> isResult(edit.cage.vertexCount(), false);
    for (uint32_t r = 0; r < region.size(); ++r) {
        glm::vec3 n = normal[findRoot(parent, r)];
        if (distance != 0.0f && !(glm::length(n) > 0.0f))
            return Error{what + ": the normals of the region around " + faceName(region[r]) +
                         " cancel out; extrude with distance 0 and move the faces instead"};
        glm::vec3 offset = distance != 0.0f ? distance * glm::normalize(n) : glm::vec3(0.0f);
        for (uint32_t v : faceSpan(edit.cage, region[r])) {
            if (isResult[v]) continue;
            isResult[v] = true;
            edit.cage.positions[v] += offset;
        }
    }
    for (uint32_t v = 0; v < edit.cage.vertexCount(); ++v)
        if (isResult[v]) edit.resultVertices.push_back(v);
    edit.resultFaces = region;

    if (Status s = finishTopologyEdit(cage, edit, what); !s) return s.error();
    return edit;
}

}  // namespace qp
