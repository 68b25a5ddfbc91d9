// Edge loops, edge rings and face loops (see edge_loops.h for the rules).
#include "edit/edge_loops.h"

#include <algorithm>

namespace qp {

namespace {

constexpr uint32_t kNone = UINT32_MAX;

uint32_t otherEnd(const Topology& t, uint32_t e, uint32_t v) { return t.edgeVertices[2 * e] + t.edgeVertices[2 * e + 1] - v; }

bool edgeHasFace(const Topology& t, uint32_t e, uint32_t f) {
    for (uint32_t k = t.edgeFaceOffsets[e]; k < t.edgeFaceOffsets[e + 1]; ++k)
        if (t.edgeFaces[k] == f) return true;
    return false;
}

bool shareFace(const Topology& t, uint32_t e0, uint32_t e1) {
    for (uint32_t k = t.edgeFaceOffsets[e0]; k < t.edgeFaceOffsets[e0 + 1]; ++k)
        if (edgeHasFace(t, e1, t.edgeFaces[k])) return true;
    return false;
}

// The edge continuing the loop from edge e through its end v, or kNone at a pole, a
// non-manifold edge or a boundary the loop does not run along.
uint32_t loopContinuation(const Topology& t, uint32_t e, uint32_t v) {
    const uint32_t edges = t.vertexEdgeCount(v), faces = t.vertexFaceCount(v);
    const bool boundaryEdge = t.edgeFaceCount(e) == 1;
    if (t.edgeFaceCount(e) > 2) return kNone;
    if (!boundaryEdge && edges == 4 && faces == 4) {
        uint32_t found = kNone;
        for (uint32_t k = t.vertexEdgeOffsets[v]; k < t.vertexEdgeOffsets[v + 1]; ++k) {
            const uint32_t other = t.vertexEdges[k];
            if (other == e || t.edgeFaceCount(other) != 2 || shareFace(t, e, other)) continue;
            if (found != kNone) return kNone;  // two candidates: not a regular fan
            found = other;
        }
        return found;
    }
    if (boundaryEdge && edges == 3 && faces == 2) {
        for (uint32_t k = t.vertexEdgeOffsets[v]; k < t.vertexEdgeOffsets[v + 1]; ++k) {
            const uint32_t other = t.vertexEdges[k];
            if (other != e && t.edgeFaceCount(other) == 1) return other;
        }
    }
    return kNone;
}

// Slot of edge e in face f (its first), or kNone.
uint32_t slotOf(const Cage& cage, const Topology& t, uint32_t f, uint32_t e) {
    for (uint32_t i = 0; i < cage.faceSize(f); ++i)
        if (t.faceEdges[cage.faceOffsets[f] + i] == e) return i;
    return kNone;
}

EdgeKey keyOf(const Topology& t, uint32_t e) { return makeEdgeKey(t.edgeVertices[2 * e], t.edgeVertices[2 * e + 1]); }

// Walks the ring from edge `start` into face `face` and on; calls visit(face, edge) for every
// quad crossed and the edge it leaves by. Stops when `seen` says an edge was reached before.
template <class Visit>
void walkRing(const Cage& cage, const Topology& t, uint32_t start, uint32_t face, std::vector<bool>& seen, Visit visit) {
    uint32_t e = start, f = face;
    while (cage.faceSize(f) == 4) {
        const uint32_t slot = slotOf(cage, t, f, e);
        if (slot == kNone) return;
        const uint32_t opposite = t.faceEdges[cage.faceOffsets[f] + (slot + 2) % 4];
        if (opposite == e) return;  // a degenerate quad using one edge twice
        visit(f, opposite);
        if (seen[opposite]) return;  // closed
        seen[opposite] = true;
        if (t.edgeFaceCount(opposite) != 2) return;
        const uint32_t* faces = &t.edgeFaces[t.edgeFaceOffsets[opposite]];
        f = faces[0] == f ? faces[1] : faces[0];
        e = opposite;
    }
}

template <class T>
void sortUnique(std::vector<T>& v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
}

}  // namespace

std::vector<EdgeKey> edgeLoop(const Cage&, const Topology& topology, EdgeKey edge) {
    const uint32_t start = topology.findEdge(edge.v0, edge.v1);
    if (start == kNone) return {};
    std::vector<bool> seen(topology.edgeCount(), false);
    seen[start] = true;
    std::vector<EdgeKey> out{keyOf(topology, start)};
    for (uint32_t end : {edge.v0, edge.v1}) {
        uint32_t e = start, v = end;
        for (;;) {
            const uint32_t next = loopContinuation(topology, e, v);
            if (next == kNone || seen[next]) break;
            seen[next] = true;
            out.push_back(keyOf(topology, next));
            v = otherEnd(topology, next, v);
            e = next;
        }
    }
    sortUnique(out);
    return out;
}

std::vector<EdgeKey> edgeRing(const Cage& cage, const Topology& topology, EdgeKey edge) {
    const uint32_t start = topology.findEdge(edge.v0, edge.v1);
    if (start == kNone) return {};
    std::vector<bool> seen(topology.edgeCount(), false);
    seen[start] = true;
    std::vector<EdgeKey> out{keyOf(topology, start)};
    if (topology.edgeFaceCount(start) <= 2)
        for (uint32_t k = topology.edgeFaceOffsets[start]; k < topology.edgeFaceOffsets[start + 1]; ++k)
            walkRing(cage, topology, start, topology.edgeFaces[k], seen,
                     [&](uint32_t, uint32_t e) { out.push_back(keyOf(topology, e)); });
    sortUnique(out);
    return out;
}

std::vector<uint32_t> faceLoop(const Cage& cage, const Topology& topology, EdgeKey edge) {
    const uint32_t start = topology.findEdge(edge.v0, edge.v1);
    if (start == kNone || topology.edgeFaceCount(start) > 2) return {};
    std::vector<bool> seen(topology.edgeCount(), false);
    seen[start] = true;
    std::vector<uint32_t> out;
    for (uint32_t k = topology.edgeFaceOffsets[start]; k < topology.edgeFaceOffsets[start + 1]; ++k)
        walkRing(cage, topology, start, topology.edgeFaces[k], seen, [&](uint32_t f, uint32_t) { out.push_back(f); });
    sortUnique(out);
    return out;
}

}  // namespace qp
