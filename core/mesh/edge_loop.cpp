// insertEdgeLoop (see topology_edits.h for the rules).
#include <algorithm>
#include <cmath>
#include <map>

#include "mesh/topology_edit_support.h"

namespace qp {

using namespace edit_support;

namespace {

struct Cut {
    uint32_t from = 0;          // the new vertex sits at from + t (to - from)
    uint32_t vertex = 0;        // the new vertex (new numbering)
};

struct RingFace {
    uint32_t face, entrySlot, exitSlot;
};

bool isSimpleQuad(const Cage& cage, uint32_t f) {
    if (cage.faceSize(f) != 4) return false;
    const uint32_t* v = cage.faceBegin(f);
    return v[0] != v[2] && v[1] != v[3];  // consecutive repeats are invalid anyway
}

// Slot of edge e in face f, or UINT32_MAX when f does not have it exactly once.
uint32_t slotOf(const Cage& cage, const Topology& t, uint32_t f, uint32_t e) {
    uint32_t found = UINT32_MAX;
    for (uint32_t i = 0; i < cage.faceSize(f); ++i)
        if (t.faceEdges[cage.faceOffsets[f] + i] == e) {
            if (found != UINT32_MAX) return UINT32_MAX;
            found = i;
        }
    return found;
}

}  // namespace

Result<TopologyEdit> insertEdgeLoop(const Cage& cage, const Topology& topology, uint32_t a, uint32_t b, float t) {
    const std::string what = "insert edge loop";
    const uint32_t startEdge = topology.findEdge(a, b);
    if (startEdge == UINT32_MAX) return Error{what + ": there is no " + edgeName(a, b)};
    if (!(t > 0.0f && t < 1.0f)) return Error{what + ": the position along the edge must be strictly between 0 and 1"};
    if (topology.edgeFaceCount(startEdge) > 2)
        return Error{what + ": " + edgeName(a, b) + " is non-manifold (" + std::to_string(topology.edgeFaceCount(startEdge)) +
                     " faces); a loop through it would branch"};

    std::map<uint32_t, Cut> cuts;  // by edge
    std::vector<RingFace> ring;
    std::vector<bool> inRing(cage.faceCount(), false);
    uint32_t nextVertex = cage.vertexCount();
    auto cut = [&](uint32_t e, uint32_t from) { cuts.emplace(e, Cut{from, nextVertex++}); };

    cut(startEdge, a);
    // Walks from edge e (cut, with its `from` side) into face f and on across the ring.
    auto walk = [&](uint32_t f, uint32_t e, uint32_t from) {
        while (!inRing[f] && isSimpleQuad(cage, f)) {
            const uint32_t entry = slotOf(cage, topology, f, e);
            if (entry == UINT32_MAX) return;
            const uint32_t* fv = cage.faceBegin(f);
            const uint32_t exit = (entry + 2) % 4;
            // The exit edge runs fv[exit] -> fv[exit + 1]; fv[exit + 1] neighbours fv[entry].
            const uint32_t exitFrom = from == fv[entry] ? fv[(entry + 3) % 4] : fv[exit];
            const uint32_t exitEdge = topology.faceEdges[cage.faceOffsets[f] + exit];
            inRing[f] = true;
            ring.push_back({f, entry, exit});
            if (cuts.count(exitEdge)) return;  // the ring closed on itself
            cut(exitEdge, exitFrom);
            if (topology.edgeFaceCount(exitEdge) != 2) return;  // boundary or non-manifold
            const uint32_t* faces = &topology.edgeFaces[topology.edgeFaceOffsets[exitEdge]];
            f = faces[0] == f ? faces[1] : faces[0];
            e = exitEdge;
            from = exitFrom;
        }
    };
    for (uint32_t k = topology.edgeFaceOffsets[startEdge]; k < topology.edgeFaceOffsets[startEdge + 1]; ++k)
        walk(topology.edgeFaces[k], startEdge, a);
    if (ring.empty())
        return Error{what + ": there is no quad next to " + edgeName(a, b) + " to cut across"};

    TopologyEdit edit = startEdit(cage);
    Cage& out = edit.cage;
    out.positions.resize(nextVertex);
    edit.oldVertexOf.resize(nextVertex, kNewElement);
    for (const auto& [e, c] : cuts) {
        const uint32_t to = topology.edgeVertices[2 * e] + topology.edgeVertices[2 * e + 1] - c.from;
        out.positions[c.vertex] = cage.positions[c.from] + t * (cage.positions[to] - cage.positions[c.from]);
    }

    // Texture coordinates of new corners: interpolated per (from, to) pair of UV indices, so
    // faces that share UVs across the cut edge share the new one too.
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> newUV;
    auto uvBetween = [&](uint32_t uvFrom, uint32_t uvTo) {
        auto [it, inserted] = newUV.try_emplace({uvFrom, uvTo}, uint32_t(out.uvs.size()));
        if (inserted) out.uvs.push_back(cage.uvs[uvFrom] + t * (cage.uvs[uvTo] - cage.uvs[uvFrom]));
        return it->second;
    };

    // Every face with its cut edges' new vertices inserted; ring faces are then split between
    // the new vertices of their entry and exit edges.
    std::vector<uint32_t> ringSlot(cage.faceCount(), UINT32_MAX);
    for (uint32_t r = 0; r < ring.size(); ++r) ringSlot[ring[r].face] = r;
    struct Pending {
        std::vector<uint32_t> vertices, uvs;
        bool hole;
    };
    std::vector<Pending> appended;
    std::vector<uint32_t> vs, uvs, slotPosition;
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        const uint32_t n = cage.faceSize(f);
        const uint32_t* fv = cage.faceBegin(f);
        std::span<const uint32_t> fuv = faceUVs(cage, f);
        vs.clear();
        uvs.clear();
        slotPosition.assign(n, UINT32_MAX);
        for (uint32_t i = 0; i < n; ++i) {
            vs.push_back(fv[i]);
            if (!fuv.empty()) uvs.push_back(fuv[i]);
            auto it = cuts.find(topology.faceEdges[cage.faceOffsets[f] + i]);
            if (it == cuts.end()) continue;
            slotPosition[i] = uint32_t(vs.size());
            vs.push_back(it->second.vertex);
            if (!fuv.empty()) {
                const bool forward = it->second.from == fv[i];
                const uint32_t j = (i + 1) % n;
                uvs.push_back(forward ? uvBetween(fuv[i], fuv[j]) : uvBetween(fuv[j], fuv[i]));
            }
        }
        if (ringSlot[f] == UINT32_MAX) {
            appendFace(edit, vs, uvs, f);
            continue;
        }
        const RingFace& rf = ring[ringSlot[f]];
        uint32_t p = slotPosition[rf.entrySlot], q = slotPosition[rf.exitSlot];
        if (p > q) std::swap(p, q);
        // p < q: positions 0..p and q..end hold corner 0; p..q is the other half.
        std::vector<uint32_t> keptV(vs.begin(), vs.begin() + p + 1), otherV(vs.begin() + p, vs.begin() + q + 1);
        keptV.insert(keptV.end(), vs.begin() + q, vs.end());
        std::vector<uint32_t> keptUV, otherUV;
        if (!uvs.empty()) {
            keptUV.assign(uvs.begin(), uvs.begin() + p + 1);
            keptUV.insert(keptUV.end(), uvs.begin() + q, uvs.end());
            otherUV.assign(uvs.begin() + p, uvs.begin() + q + 1);
        }
        appendFace(edit, keptV, keptUV, f);
        appended.push_back({std::move(otherV), std::move(otherUV), cage.isHole(f)});
        edit.resultEdges.push_back(makeEdgeKey(vs[p], vs[q]));
    }
    std::vector<uint32_t> newHoles;
    for (Pending& p : appended) {
        if (p.hole) newHoles.push_back(out.faceCount());
        appendFace(edit, p.vertices, p.uvs, kNewElement);
    }
    carryHoles(cage, edit, newHoles);

    // A cut creased edge passes its sharpness to both halves.
    for (const auto& [e, c] : cuts) {
        const uint32_t v0 = topology.edgeVertices[2 * e], v1 = topology.edgeVertices[2 * e + 1];
        const float sharpness = cage.edgeSharpness(v0, v1);
        if (sharpness <= 0.0f) continue;
        out.setEdgeSharpness(v0, v1, 0.0f);
        out.setEdgeSharpness(v0, c.vertex, sharpness);
        out.setEdgeSharpness(c.vertex, v1, sharpness);
    }

    for (const auto& [e, c] : cuts) edit.resultVertices.push_back(c.vertex);
    std::sort(edit.resultVertices.begin(), edit.resultVertices.end());
    std::sort(edit.resultEdges.begin(), edit.resultEdges.end());
    if (Status s = finishTopologyEdit(cage, edit, what); !s) return s.error();
    return edit;
}

}  // namespace qp
