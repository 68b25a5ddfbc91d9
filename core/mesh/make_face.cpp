// makeFace (see topology_edits.h for the rules).
#include <algorithm>

#include "mesh/topology_edit_support.h"

namespace qp {

using namespace edit_support;

Result<TopologyEdit> makeFace(const Cage& cage, const Topology& topology, std::span<const uint32_t> vertices) {
    const std::string what = "make face";
    const uint32_t n = uint32_t(vertices.size());
    if (n < 3) return Error{what + ": a face needs at least 3 vertices"};
    for (uint32_t i = 0; i < n; ++i) {
        if (vertices[i] >= cage.vertexCount())
            return Error{what + ": " + vertexName(vertices[i]) + " does not exist (the cage has " +
                         std::to_string(cage.vertexCount()) + " vertices)"};
        if (std::find(vertices.begin() + i + 1, vertices.end(), vertices[i]) != vertices.end())
            return Error{what + ": " + vertexName(vertices[i]) + " is given twice"};
    }

    // Orientation: a shared edge should run the other way in the existing face.
    uint32_t agree = 0, disagree = 0;
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t a = vertices[i], b = vertices[(i + 1) % n];
        const uint32_t e = topology.findEdge(a, b);
        if (e == UINT32_MAX) continue;
        if (topology.edgeFaceCount(e) >= 2)
            return Error{what + ": " + edgeName(a, b) + " already has " + std::to_string(topology.edgeFaceCount(e)) +
                         " faces; another one would make it non-manifold"};
        const uint32_t other = topology.edgeFaces[topology.edgeFaceOffsets[e]];
        std::span<const uint32_t> ov = faceSpan(cage, other);
        for (uint32_t k = 0; k < ov.size(); ++k)
            if (ov[k] == a && ov[(k + 1) % ov.size()] == b) ++disagree;
            else if (ov[k] == b && ov[(k + 1) % ov.size()] == a) ++agree;
    }
    if (agree > 0 && disagree > 0)
        return Error{what + ": the faces around the new face disagree on its orientation; flip them first"};
    std::vector<uint32_t> face(vertices.begin(), vertices.end());
    if (disagree > 0) std::reverse(face.begin() + 1, face.end());

    // The same cycle may exist already (possibly reversed).
    for (uint32_t k = topology.vertexFaceOffsets[face[0]]; k < topology.vertexFaceOffsets[face[0] + 1]; ++k) {
        const uint32_t g = topology.vertexFaces[k];
        std::span<const uint32_t> gv = faceSpan(cage, g);
        if (gv.size() != n) continue;
        std::vector<uint32_t> a(gv.begin(), gv.end()), b = face;
        std::sort(a.begin(), a.end());
        std::sort(b.begin(), b.end());
        if (a == b) return Error{what + ": " + faceName(g) + " already joins these vertices"};
    }

    TopologyEdit edit = startEdit(cage);
    for (uint32_t f = 0; f < cage.faceCount(); ++f) appendFace(edit, faceSpan(cage, f), faceUVs(cage, f), f);
    std::vector<uint32_t> uvs;
    if (!cage.faceUVIndices.empty()) {
        // Reuse a texture coordinate of each vertex where it has one; (0, 0) otherwise.
        for (uint32_t v : face) {
            uint32_t uv = UINT32_MAX;
            for (uint32_t k = topology.vertexFaceOffsets[v]; k < topology.vertexFaceOffsets[v + 1] && uv == UINT32_MAX; ++k) {
                const uint32_t g = topology.vertexFaces[k];
                std::span<const uint32_t> gv = faceSpan(cage, g);
                uv = faceUVs(cage, g)[std::find(gv.begin(), gv.end(), v) - gv.begin()];
            }
            if (uv == UINT32_MAX) {
                uv = uint32_t(edit.cage.uvs.size());
                edit.cage.uvs.push_back(glm::vec2(0.0f));
            }
            uvs.push_back(uv);
        }
    }
    appendFace(edit, face, uvs, kNewElement);
    carryHoles(cage, edit);
    edit.resultFaces = {edit.cage.faceCount() - 1};
    if (Status s = finishTopologyEdit(cage, edit, what); !s) return s.error();
    return edit;
}

}  // namespace qp
