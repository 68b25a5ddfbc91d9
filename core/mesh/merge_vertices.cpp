// mergeVertices (see topology_edits.h for the rules).
#include <algorithm>
#include <map>

#include "mesh/topology_edit_support.h"

namespace qp {

using namespace edit_support;

namespace {

// Removes repeated consecutive corners and spikes (x, y, x -> x), cyclically, until none is
// left. vs and uvs (when not empty) are edited in parallel.
void collapse(std::vector<uint32_t>& vs, std::vector<uint32_t>& uvs) {
    auto erase = [&](size_t i) {
        vs.erase(vs.begin() + i);
        if (!uvs.empty()) uvs.erase(uvs.begin() + i);
    };
    bool changed = true;
    while (changed && vs.size() >= 2) {
        changed = false;
        for (size_t i = 0; i < vs.size() && vs.size() >= 2; ++i)
            if (vs[i] == vs[(i + 1) % vs.size()]) {
                erase(i);
                changed = true;
                break;
            }
        if (changed || vs.size() < 3) continue;
        for (size_t i = 0; i < vs.size(); ++i) {
            const size_t n = vs.size(), prev = (i + n - 1) % n, next = (i + 1) % n;
            if (vs[prev] == vs[next]) {
                // Drop the spike tip and one of the two equal corners around it.
                size_t first = std::min(i, next), second = std::max(i, next);
                erase(second);
                erase(first);
                changed = true;
                break;
            }
        }
    }
}

// The cycle of a face in a canonical form: rotated to start at its smallest vertex, in the
// direction whose second vertex is smaller (so both orientations compare equal).
std::vector<uint32_t> canonicalCycle(std::span<const uint32_t> fv) {
    const size_t n = fv.size();
    const size_t start = size_t(std::min_element(fv.begin(), fv.end()) - fv.begin());
    std::vector<uint32_t> forward(n), backward(n);
    for (size_t i = 0; i < n; ++i) {
        forward[i] = fv[(start + i) % n];
        backward[i] = fv[(start + n - i) % n];
    }
    return std::min(forward, backward);
}

}  // namespace

Result<TopologyEdit> mergeVertices(const Cage& cage, const Topology& topology, std::span<const uint32_t> vertices,
                                   MergeTarget target) {
    const std::string what = "merge vertices";
    std::vector<uint32_t> merged;
    for (uint32_t v : vertices) {
        if (v >= cage.vertexCount())
            return Error{what + ": " + vertexName(v) + " does not exist (the cage has " +
                         std::to_string(cage.vertexCount()) + " vertices)"};
        std::erase(merged, v);  // a repeated vertex counts where it was last given
        merged.push_back(v);
    }
    if (merged.size() < 2) return Error{what + ": select at least two different vertices"};
    const uint32_t survivor = merged.back();
    std::vector<bool> isMerged(cage.vertexCount(), false);
    for (uint32_t v : merged) isMerged[v] = true;
    auto mapped = [&](uint32_t v) { return isMerged[v] ? survivor : v; };

    glm::vec3 position = cage.positions[survivor];
    if (target == MergeTarget::Centroid) {
        glm::vec3 sum(0.0f);
        for (uint32_t v : merged) sum += cage.positions[v];
        position = sum / float(merged.size());
    }

    // Faces touching a merged vertex are rebuilt; the others are copied.
    std::vector<bool> touched(cage.faceCount(), false);
    for (uint32_t v : merged)
        for (uint32_t k = topology.vertexFaceOffsets[v]; k < topology.vertexFaceOffsets[v + 1]; ++k)
            touched[topology.vertexFaces[k]] = true;

    TopologyEdit edit = startEdit(cage);
    edit.cage.positions[survivor] = position;
    std::map<std::vector<uint32_t>, uint32_t> cycles;  // canonical cycle of faces at the survivor
    std::vector<uint32_t> vs, uvs;
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        std::span<const uint32_t> fv = faceSpan(cage, f), fuv = faceUVs(cage, f);
        if (!touched[f]) {
            appendFace(edit, fv, fuv, f);
            continue;
        }
        vs.clear();
        for (uint32_t v : fv) vs.push_back(mapped(v));
        uvs.assign(fuv.begin(), fuv.end());
        collapse(vs, uvs);
        if (vs.size() < 3) continue;  // degenerate: removed
        for (size_t i = 0; i < vs.size(); ++i)
            if (std::count(vs.begin(), vs.end(), vs[i]) > 1)
                return Error{what + ": " + faceName(f) + " would visit " + vertexName(vs[i]) +
                             " twice after the merge (a pinched face is not defined); merge fewer vertices"};
        appendFace(edit, vs, uvs, f);
    }
    // Faces that became the same cycle: keep the lowest-numbered one. Only faces at the
    // survivor can have become duplicates.
    std::vector<bool> drop(edit.cage.faceCount(), false);
    for (uint32_t f = 0; f < edit.cage.faceCount(); ++f) {
        std::span<const uint32_t> fv = faceSpan(edit.cage, f);
        if (std::find(fv.begin(), fv.end(), survivor) == fv.end()) continue;
        if (!cycles.emplace(canonicalCycle(fv), f).second) drop[f] = true;
    }
    if (std::find(drop.begin(), drop.end(), true) != drop.end()) {
        TopologyEdit kept = startEdit(cage);
        kept.cage.positions = edit.cage.positions;
        for (uint32_t f = 0; f < edit.cage.faceCount(); ++f)
            if (!drop[f]) appendFace(kept, faceSpan(edit.cage, f), faceUVs(edit.cage, f), edit.oldFaceOf[f]);
        edit = std::move(kept);
    }
    carryHoles(cage, edit);

    // Tags: creases follow their end vertices (largest sharpness where edges become one);
    // the survivor's corner is the sharpest of the merged vertices'.
    std::map<std::pair<uint32_t, uint32_t>, float> creases;
    for (const EdgeCrease& c : cage.creases) {
        const uint32_t a = mapped(c.v0), b = mapped(c.v1);
        if (a == b) continue;
        float& s = creases[{std::min(a, b), std::max(a, b)}];
        s = std::max(s, c.sharpness);
    }
    edit.cage.creases.clear();
    for (const auto& [pair, s] : creases) edit.cage.creases.push_back({pair.first, pair.second, s});
    dropCreasesWithoutEdge(edit.cage);
    float corner = 0.0f;
    for (uint32_t v : merged) corner = std::max(corner, cage.vertexSharpness(v));
    std::erase_if(edit.cage.corners, [&](const VertexCorner& c) { return isMerged[c.vertex]; });
    edit.cage.setVertexSharpness(survivor, corner);

    std::vector<bool> remove(cage.vertexCount(), false);
    for (uint32_t v : merged) remove[v] = v != survivor;
    removeVertices(edit, remove);
    const uint32_t newSurvivor = survivor - uint32_t(std::count_if(merged.begin(), merged.end(), [&](uint32_t v) {
                                     return v < survivor;
                                 }));
    edit.resultVertices = {newSurvivor};
    if (Status s = finishTopologyEdit(cage, edit, what); !s) return s.error();
    return edit;
}

}  // namespace qp
