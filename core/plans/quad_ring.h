// QuadRing: the ordered 1-ring of a vertex in an all-quad manifold cage, the input of every
// patch construction that works per corner (ACC-1, ACC-2, Stam).
//
// Around a vertex c with faces 0 .. F-1 in counter-clockwise order, face i = (c, e_i, d_i,
// e_{i+1}): e_i are the edge neighbours, d_i the diagonal (opposite) vertices.
//   - interior vertex: F = valence = edge neighbours, indices taken modulo F;
//   - boundary vertex: F faces and F + 1 edge neighbours; e_0 and e_F are the boundary
//     neighbours, so the fan runs from boundary edge (c, e_0) to boundary edge (c, e_F).
// gatherQuadRing starts the fan so that the requested face is face `startFace` of the result
// (interior: always face 0; boundary: its position in the fan).
#pragma once

#include <cstdint>
#include <vector>

#include "mesh/cage.h"
#include "mesh/result.h"
#include "mesh/topology.h"

namespace qp {

struct QuadRing {
    uint32_t center = 0;
    bool boundary = false;
    std::vector<uint32_t> edges;      // e_i
    std::vector<uint32_t> diagonals;  // d_i, one per face
    std::vector<uint32_t> faces;      // face ids, face i = (c, e_i, d_i, e_{i+1})
    uint32_t startFace = 0;           // index (in faces) of the face the ring was gathered from

    uint32_t faceCount() const { return uint32_t(faces.size()); }
    // Interior: the valence. Boundary: twice the face count, the valence of the closed ring the
    // boundary fan is half of (a regular boundary vertex, 2 faces, counts as 4).
    uint32_t effectiveValence() const { return boundary ? 2 * faceCount() : faceCount(); }
    // e_i with i wrapped for interior rings.
    uint32_t edge(int i) const;
    uint32_t diagonal(int i) const;
};

// Requires: `face` is a quad of `cage` with `center` at its corner `corner`, every face around
// the centre is a quad, and the faces around it form one fan (manifold).
QuadRing gatherQuadRing(const Cage& cage, const Topology& topology, uint32_t face, uint32_t corner);

// Checks what gatherQuadRing needs, for every vertex: all faces are quads, no edge has more
// than two faces, and the faces around each used vertex form a single fan. The message says
// what is wrong and where.
Status checkQuadManifold(const Cage& cage, const Topology& topology, const std::string& source);

}  // namespace qp
