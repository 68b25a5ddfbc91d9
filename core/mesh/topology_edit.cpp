// finishTopologyEdit and the helpers shared by the topology edit operations.
#include <algorithm>
#include <cassert>
#include <unordered_set>

#include "mesh/topology_edit_support.h"

namespace qp {

namespace edit_support {

TopologyEdit startEdit(const Cage& cage) {
    TopologyEdit edit;
    Cage& out = edit.cage;
    out.positions = cage.positions;
    out.creases = cage.creases;
    out.corners = cage.corners;
    out.options = cage.options;
    out.uvs = cage.uvs;
    out.faceOffsets = {0};
    out.faceVertices.reserve(cage.faceVertices.size());
    if (!cage.faceUVIndices.empty()) out.faceUVIndices.reserve(cage.faceUVIndices.size());
    edit.oldVertexOf.resize(cage.vertexCount());
    for (uint32_t v = 0; v < cage.vertexCount(); ++v) edit.oldVertexOf[v] = v;
    return edit;
}

void appendFace(TopologyEdit& edit, std::span<const uint32_t> vertices, std::span<const uint32_t> uvIndices,
                uint32_t oldFace) {
    Cage& out = edit.cage;
    out.faceVertices.insert(out.faceVertices.end(), vertices.begin(), vertices.end());
    out.faceOffsets.push_back(uint32_t(out.faceVertices.size()));
    if (!uvIndices.empty()) {
        assert(uvIndices.size() == vertices.size());
        out.faceUVIndices.insert(out.faceUVIndices.end(), uvIndices.begin(), uvIndices.end());
    }
    edit.oldFaceOf.push_back(oldFace);
}

Result<std::vector<uint32_t>> checkedFaceSet(const Cage& cage, std::span<const uint32_t> faces, const std::string& what) {
    if (faces.empty()) return Error{what + ": no faces are selected"};
    std::vector<uint32_t> set(faces.begin(), faces.end());
    std::sort(set.begin(), set.end());
    set.erase(std::unique(set.begin(), set.end()), set.end());
    if (set.back() >= cage.faceCount())
        return Error{what + ": " + faceName(set.back()) + " does not exist (the cage has " +
                     std::to_string(cage.faceCount()) + " faces)"};
    return set;
}

void dropCreasesWithoutEdge(Cage& cage) {
    if (cage.creases.empty()) return;
    std::unordered_set<uint64_t> edges;
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        const uint32_t n = cage.faceSize(f);
        const uint32_t* fv = cage.faceBegin(f);
        for (uint32_t i = 0; i < n; ++i) {
            EdgeKey k = makeEdgeKey(fv[i], fv[(i + 1) % n]);
            edges.insert(uint64_t(k.v0) << 32 | k.v1);
        }
    }
    std::erase_if(cage.creases, [&](const EdgeCrease& c) { return !edges.count(uint64_t(c.v0) << 32 | c.v1); });
}

void carryHoles(const Cage& before, TopologyEdit& edit, const std::vector<uint32_t>& newHoles) {
    edit.cage.holes.clear();
    for (uint32_t f = 0; f < edit.cage.faceCount(); ++f) {
        uint32_t old = edit.oldFaceOf[f];
        if ((old != kNewElement && before.isHole(old)) || std::binary_search(newHoles.begin(), newHoles.end(), f))
            edit.cage.holes.push_back(f);
    }
}

void removeVertices(TopologyEdit& edit, const std::vector<bool>& remove) {
    Cage& cage = edit.cage;
    std::vector<uint32_t> newIndex(cage.vertexCount(), kNewElement);
    uint32_t next = 0;
    for (uint32_t v = 0; v < cage.vertexCount(); ++v) {
        if (remove[v]) continue;
        newIndex[v] = next;
        cage.positions[next] = cage.positions[v];
        edit.oldVertexOf[next] = edit.oldVertexOf[v];
        ++next;
    }
    cage.positions.resize(next);
    edit.oldVertexOf.resize(next);
    for (uint32_t& v : cage.faceVertices) {
        assert(newIndex[v] != kNewElement);
        v = newIndex[v];
    }
    std::erase_if(cage.creases, [&](const EdgeCrease& c) { return remove[c.v0] || remove[c.v1]; });
    for (EdgeCrease& c : cage.creases) {
        c.v0 = newIndex[c.v0];
        c.v1 = newIndex[c.v1];
    }
    std::erase_if(cage.corners, [&](const VertexCorner& c) { return remove[c.vertex]; });
    for (VertexCorner& c : cage.corners) c.vertex = newIndex[c.vertex];
}

}  // namespace edit_support

using namespace edit_support;

Status finishTopologyEdit(const Cage& before, TopologyEdit& edit, const std::string& what) {
    Cage& after = edit.cage;
    if (edit.oldFaceOf.size() != after.faceCount() || edit.oldVertexOf.size() != after.vertexCount())
        return Error{what + ": the face or vertex map does not match the edited cage"};
    auto checkMap = [&](const std::vector<uint32_t>& map, uint32_t oldCount, const char* kind) -> Status {
        uint32_t previous = kNewElement;
        for (uint32_t old : map) {
            if (old == kNewElement) continue;
            if (old >= oldCount || (previous != kNewElement && old <= previous))
                return Error{what + ": surviving " + kind + " must keep their relative order (internal error)"};
            previous = old;
        }
        return success();
    };
    if (Status s = checkMap(edit.oldFaceOf, before.faceCount(), "faces"); !s) return s;
    if (Status s = checkMap(edit.oldVertexOf, before.vertexCount(), "vertices"); !s) return s;
    if (after.faceCount() == 0) return Error{what + ": the edit would leave the cage without faces"};

    normalizeTags(after);
    if (Status valid = validateCage(after, what); !valid) return valid;

    std::vector<uint32_t> newVertexOf(before.vertexCount(), kNewElement);
    for (uint32_t v = 0; v < after.vertexCount(); ++v)
        if (edit.oldVertexOf[v] != kNewElement) newVertexOf[edit.oldVertexOf[v]] = v;
    std::vector<bool> survives(before.faceCount(), false);
    edit.changedFaces.clear();
    edit.removedFaces.clear();
    for (uint32_t f = 0; f < after.faceCount(); ++f) {
        uint32_t old = edit.oldFaceOf[f];
        bool same = old != kNewElement && before.faceSize(old) == after.faceSize(f);
        for (uint32_t i = 0; same && i < after.faceSize(f); ++i)
            same = newVertexOf[before.faceBegin(old)[i]] == after.faceBegin(f)[i];
        if (!same) edit.changedFaces.push_back(f);
        if (old != kNewElement) survives[old] = true;
    }
    for (uint32_t g = 0; g < before.faceCount(); ++g)
        if (!survives[g]) edit.removedFaces.push_back(g);
    return success();
}

}  // namespace qp
