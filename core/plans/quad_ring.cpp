#include "plans/quad_ring.h"

#include <cassert>

namespace qp {

namespace {

uint32_t cornerOf(const Cage& cage, uint32_t face, uint32_t vertex) {
    const uint32_t* v = cage.faceBegin(face);
    for (uint32_t k = 0; k < cage.faceSize(face); ++k)
        if (v[k] == vertex) return k;
    return UINT32_MAX;
}

// The face other than `face` on the edge (a, b), or UINT32_MAX on a boundary.
uint32_t otherFace(const Topology& topology, uint32_t a, uint32_t b, uint32_t face) {
    uint32_t e = topology.findEdge(a, b);
    if (e == UINT32_MAX) return UINT32_MAX;
    for (uint32_t i = topology.edgeFaceOffsets[e]; i < topology.edgeFaceOffsets[e + 1]; ++i)
        if (topology.edgeFaces[i] != face) return topology.edgeFaces[i];
    return UINT32_MAX;
}

}  // namespace

uint32_t QuadRing::edge(int i) const {
    int n = int(edges.size());
    return edges[size_t(boundary ? i : ((i % n) + n) % n)];
}

uint32_t QuadRing::diagonal(int i) const {
    int n = int(diagonals.size());
    return diagonals[size_t(boundary ? i : ((i % n) + n) % n)];
}

QuadRing gatherQuadRing(const Cage& cage, const Topology& topology, uint32_t face, uint32_t corner) {
    QuadRing ring;
    const uint32_t c = cage.faceBegin(face)[corner];
    ring.center = c;
    const uint32_t faceTotal = topology.vertexFaceCount(c);

    // Walk clockwise (across the edge to the previous corner) until the start face comes back
    // (interior) or a boundary edge is hit (then the fan starts there).
    uint32_t first = face;
    for (uint32_t steps = 0; steps < faceTotal; ++steps) {
        uint32_t k = cornerOf(cage, first, c);
        if (cage.faceSize(first) != 4 || k == UINT32_MAX) break;
        uint32_t next = cage.faceBegin(first)[(k + 1) % 4];
        uint32_t before = otherFace(topology, c, next, first);
        if (before == UINT32_MAX) {
            ring.boundary = true;
            break;
        }
        if (before == face) break;
        first = before;
    }
    if (!ring.boundary) first = face;

    // Walk counter-clockwise from `first`, across the edge to the previous corner of each face.
    uint32_t f = first;
    for (uint32_t steps = 0; steps < faceTotal; ++steps) {
        const uint32_t* v = cage.faceBegin(f);
        uint32_t k = cornerOf(cage, f, c);
        assert(cage.faceSize(f) == 4 && k != UINT32_MAX);
        if (cage.faceSize(f) != 4 || k == UINT32_MAX) break;  // precondition broken: stop, never read past
        if (f == face) ring.startFace = uint32_t(ring.faces.size());
        ring.faces.push_back(f);
        ring.edges.push_back(v[(k + 1) % 4]);
        ring.diagonals.push_back(v[(k + 2) % 4]);
        uint32_t prev = v[(k + 3) % 4];
        uint32_t after = otherFace(topology, c, prev, f);
        if (after == UINT32_MAX) {
            assert(ring.boundary);
            ring.edges.push_back(prev);
            break;
        }
        if (after == first) break;
        f = after;
    }
    return ring;
}

Status checkQuadManifold(const Cage& cage, const Topology& topology, const std::string& source) {
    for (uint32_t f = 0; f < cage.faceCount(); ++f)
        if (cage.faceSize(f) != 4)
            return Error{source + ": face " + std::to_string(f) + " has " + std::to_string(cage.faceSize(f)) +
                         " vertices; this scheme needs an all-quad cage"};
    for (uint32_t e = 0; e < topology.edgeCount(); ++e)
        if (topology.edgeFaceCount(e) > 2)
            return Error{source + ": edge " + std::to_string(topology.edgeVertices[2 * e]) + "-" +
                         std::to_string(topology.edgeVertices[2 * e + 1]) + " has " +
                         std::to_string(topology.edgeFaceCount(e)) + " faces (non-manifold); not supported"};
    for (uint32_t v = 0; v < cage.vertexCount(); ++v) {
        uint32_t count = topology.vertexFaceCount(v);
        if (count == 0) continue;
        uint32_t face = topology.vertexFaces[topology.vertexFaceOffsets[v]];
        uint32_t corner = cornerOf(cage, face, v);
        // A face visiting the vertex twice, or two fans meeting at the vertex, leave faces out.
        for (uint32_t i = topology.vertexFaceOffsets[v]; i < topology.vertexFaceOffsets[v + 1]; ++i) {
            const uint32_t* fv = cage.faceBegin(topology.vertexFaces[i]);
            uint32_t hits = 0;
            for (uint32_t k = 0; k < 4; ++k) hits += fv[k] == v;
            if (hits != 1)
                return Error{source + ": face " + std::to_string(topology.vertexFaces[i]) + " visits vertex " +
                             std::to_string(v) + " twice (non-manifold); not supported"};
        }
        QuadRing ring = gatherQuadRing(cage, topology, face, corner);
        if (ring.faceCount() != count)
            return Error{source + ": the faces around vertex " + std::to_string(v) +
                         " do not form one fan (non-manifold vertex); not supported"};
    }
    return success();
}

}  // namespace qp
