// deleteFaces (see topology_edits.h for the rules).
#include "mesh/topology_edit_support.h"

namespace qp {

using namespace edit_support;

Result<TopologyEdit> deleteFaces(const Cage& cage, const Topology& topology, std::span<const uint32_t> faces,
                                 bool removeUnusedVertices) {
    const std::string what = "delete faces";
    auto checked = checkedFaceSet(cage, faces, what);
    if (!checked) return checked.error();
    if (checked->size() == cage.faceCount()) return Error{what + ": cannot delete every face of the cage"};
    std::vector<bool> deleted(cage.faceCount(), false);
    for (uint32_t f : *checked) deleted[f] = true;

    TopologyEdit edit = startEdit(cage);
    for (uint32_t f = 0; f < cage.faceCount(); ++f)
        if (!deleted[f]) appendFace(edit, faceSpan(cage, f), faceUVs(cage, f), f);
    carryHoles(cage, edit);
    dropCreasesWithoutEdge(edit.cage);

    if (removeUnusedVertices) {
        std::vector<bool> remove(cage.vertexCount(), false);
        for (uint32_t f : *checked)
            for (uint32_t v : faceSpan(cage, f)) {
                bool used = false;
                for (uint32_t k = topology.vertexFaceOffsets[v]; k < topology.vertexFaceOffsets[v + 1] && !used; ++k)
                    used = !deleted[topology.vertexFaces[k]];
                remove[v] = !used;
            }
        removeVertices(edit, remove);
    }
    if (Status s = finishTopologyEdit(cage, edit, what); !s) return s.error();
    return edit;
}

}  // namespace qp
