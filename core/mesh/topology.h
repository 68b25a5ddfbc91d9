// Topology: adjacency derived from a Cage (edges, edge->faces, vertex->faces), and the
// statistics `quadplan info` prints.
//
// Everything is flat CSR arrays built in O(faces * face size). Edges are numbered in the order
// of their (first, second) vertex pairs, the order of Cage::creases.
// Edge i of face f runs from faceBegin(f)[i] to faceBegin(f)[(i+1) % n]; faceEdges parallels
// Cage::faceVertices with that edge's index.
#pragma once

#include <compare>
#include <cstdint>
#include <map>
#include <vector>

#include "mesh/cage.h"

namespace qp {

// An edge named by its end vertices (v0 < v1), like EdgeCrease: stays meaningful across
// topology edits that renumber edges.
struct EdgeKey {
    uint32_t v0 = 0, v1 = 0;
    auto operator<=>(const EdgeKey&) const = default;
};
inline EdgeKey makeEdgeKey(uint32_t a, uint32_t b) { return a < b ? EdgeKey{a, b} : EdgeKey{b, a}; }

struct Topology {
    std::vector<uint32_t> edgeVertices;  // 2 per edge, first < second
    std::vector<uint32_t> faceEdges;     // parallels Cage::faceVertices

    std::vector<uint32_t> edgeFaceOffsets;  // CSR: faces of edge e
    std::vector<uint32_t> edgeFaces;
    std::vector<uint32_t> vertexFaceOffsets;  // CSR: faces around vertex v
    std::vector<uint32_t> vertexFaces;
    std::vector<uint32_t> vertexEdgeOffsets;  // CSR: edges at vertex v
    std::vector<uint32_t> vertexEdges;

    uint32_t edgeCount() const { return uint32_t(edgeVertices.size() / 2); }
    uint32_t edgeFaceCount(uint32_t e) const { return edgeFaceOffsets[e + 1] - edgeFaceOffsets[e]; }
    uint32_t vertexFaceCount(uint32_t v) const { return vertexFaceOffsets[v + 1] - vertexFaceOffsets[v]; }
    uint32_t vertexEdgeCount(uint32_t v) const { return vertexEdgeOffsets[v + 1] - vertexEdgeOffsets[v]; }

    // Index of the edge between a and b, or UINT32_MAX when no face has it.
    uint32_t findEdge(uint32_t a, uint32_t b) const;
};

// Requires a cage that passed validateCage.
Topology buildTopology(const Cage& cage);

// Per edge of `topology` (the cage's own), its sharpness (0: none): one walk along the creases.
std::vector<float> edgeSharpnesses(const Cage& cage, const Topology& topology);

struct CageStats {
    uint32_t vertices = 0, faces = 0, edges = 0;
    std::map<uint32_t, uint32_t> faceSizeHistogram;  // face size -> count
    std::map<uint32_t, uint32_t> valenceHistogram;   // edges at vertex -> count (isolated: 0)
    uint32_t boundaryEdges = 0;      // exactly one face
    uint32_t nonManifoldEdges = 0;   // more than two faces, or two faces with the same winding
    uint32_t nonManifoldVertices = 0;  // faces around it do not form one fan
    uint32_t isolatedVertices = 0;   // used by no face
    uint32_t creasedEdges = 0, infinitelySharpEdges = 0;
    uint32_t cornerVertices = 0;
    uint32_t holes = 0;
    uint32_t extraordinaryVertices = 0;  // interior valence != 4, or boundary valence != 3
};

CageStats computeStats(const Cage& cage, const Topology& topology);

}  // namespace qp
