// splitFace (see topology_edits.h for the rules).
#include <algorithm>

#include "mesh/topology_edit_support.h"

namespace qp {

using namespace edit_support;

Result<TopologyEdit> splitFace(const Cage& cage, const Topology& topology, uint32_t face, uint32_t a, uint32_t b) {
    const std::string what = "split face";
    if (face >= cage.faceCount())
        return Error{what + ": " + faceName(face) + " does not exist (the cage has " + std::to_string(cage.faceCount()) +
                     " faces)"};
    std::span<const uint32_t> fv = faceSpan(cage, face);
    const uint32_t n = uint32_t(fv.size());
    auto cornerOf = [&](uint32_t v, uint32_t& corner) -> Status {
        auto count = std::count(fv.begin(), fv.end(), v);
        if (count == 0) return Error{what + ": " + vertexName(v) + " is not a corner of " + faceName(face)};
        if (count > 1)
            return Error{what + ": " + faceName(face) + " visits " + vertexName(v) +
                         " twice; splitting there is not defined"};
        corner = uint32_t(std::find(fv.begin(), fv.end(), v) - fv.begin());
        return success();
    };
    uint32_t i = 0, j = 0;
    if (Status s = cornerOf(a, i); !s) return s.error();
    if (Status s = cornerOf(b, j); !s) return s.error();
    if (i == j) return Error{what + ": the two vertices must differ"};
    if ((i + 1) % n == j || (j + 1) % n == i)
        return Error{what + ": " + vertexName(a) + " and " + vertexName(b) + " are adjacent in " + faceName(face) +
                     "; pick two vertices that are not joined by an edge of the face"};
    if (topology.findEdge(a, b) != UINT32_MAX)
        return Error{what + ": " + edgeName(a, b) + " already exists in another face; splitting would make it "
                            "non-manifold"};
    if (i > j) std::swap(i, j);

    // Corners i..j form one half, j..i (wrapping through corner 0) the other. The half with
    // corner 0 keeps the face's index and starts at corner 0.
    std::span<const uint32_t> uv = faceUVs(cage, face);
    std::vector<uint32_t> keptV, keptUV, newV, newUV;
    auto take = [&](std::vector<uint32_t>& vs, std::vector<uint32_t>& uvs, uint32_t corner) {
        vs.push_back(fv[corner]);
        if (!uv.empty()) uvs.push_back(uv[corner]);
    };
    for (uint32_t k = 0; k <= i; ++k) take(keptV, keptUV, k);
    for (uint32_t k = j; k < n; ++k) take(keptV, keptUV, k);
    for (uint32_t k = i; k <= j; ++k) take(newV, newUV, k);
    if (i == 0) std::swap(keptV, newV), std::swap(keptUV, newUV);  // corner 0 is on the cut: keep 0..j

    TopologyEdit edit = startEdit(cage);
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        if (f == face) appendFace(edit, keptV, keptUV, f);
        else appendFace(edit, faceSpan(cage, f), faceUVs(cage, f), f);
    }
    appendFace(edit, newV, newUV, kNewElement);
    std::vector<uint32_t> newHoles;
    if (cage.isHole(face)) newHoles.push_back(edit.cage.faceCount() - 1);
    carryHoles(cage, edit, newHoles);

    edit.resultEdges = {makeEdgeKey(a, b)};
    edit.resultFaces = {face, edit.cage.faceCount() - 1};
    if (Status s = finishTopologyEdit(cage, edit, what); !s) return s.error();
    return edit;
}

}  // namespace qp
