// MacroFaces: base faces gathered into rectangles that a renderer can draw as one unit when
// their faces are small on screen (Brainerd et al. 2016 §7.3; docs/renderer.md, macro faces).
//
// A macro face is a W x H block of quads that meet as a piece of the regular grid: cell (i, j)
// covers the lattice square [i, i+1] x [j, j+1], and its face has corner `rotation` at lattice
// point (i, j), then (rotation + 1) & 3 at (i+1, j), (rotation + 2) & 3 at (i+1, j+1) and
// (rotation + 3) & 3 at (i, j+1) (faces wind counter-clockwise, so the lattice's u runs along
// each face's edges in their own order). Sides: 0 is j = 0, 1 is i = W, 2 is j = H, 3 is i = 0.
//
// Two partitions, as the paper gives:
//   - Rectangular: the cage cut along separatrices, the edge lines that run straight from every
//     singular vertex (interior valence != 4, boundary valence != 3, or a corner of a non-quad)
//     through regular vertices until they reach another singular vertex, the boundary or a line
//     already traced. The pieces are rectangles whose sides meet whole: no T-junctions. Regions
//     longer than `maxSpan` faces, and regions that close on themselves (a torus or cylinder of
//     regular faces), are cut by further full lines through regular vertices, so the property holds.
//   - Quartets: 2 x 2 blocks of regular faces (every corner an interior valence-4 vertex) around
//     a shared vertex: first aligned ones (each connected set of regular faces laid on the lattice,
//     blocks at even coordinates, so that neighbouring quartets share whole sides), then any left
//     around a regular vertex, greedily in vertex order.
// And one of this project's: aligned blocks, the quartets' rule with blocks of 2^k x 2^k quads up
// to `maxSpan` (largest first, then quartets of regular faces left around regular vertices), for
// cages whose singular vertices are too many for separatrices to leave large rectangles (every
// separatrix runs on until it meets a singular vertex). A block's members may have extraordinary
// corners on its border, never inside. Blocks of one size beside each other share whole sides; a
// bigger block beside smaller ones meets each along a span of its side.
// Faces in no macro face (non-quads, faces near singular vertices, leftovers) are drawn alone.
// Only topology is read: sharpness and holes do not change the partition (a renderer draws a
// macro face with a hole in it as single faces).
#pragma once

#include <cstdint>
#include <vector>

#include "mesh/cage.h"
#include "mesh/topology.h"

namespace qp {

struct MacroCell {
    uint32_t face;
    uint32_t rotation;  // the face's corner at the cell's lattice point (i, j)
};

// A stretch of a macro face's side with one neighbour across: the same edges as a stretch of
// another macro face's side (that face has the same span id), or edges whose faces across are in
// no macro face.
struct MacroSpan {
    uint32_t id;
    uint32_t start, length;  // along the side (sides run along +u and +v), in faces
};

struct MacroFace {
    uint32_t width = 0, height = 0;
    uint32_t firstCell = 0;      // cell (i, j) is cells[firstCell + j * width + i]
    uint32_t spanBegin[5] = {};  // side s: spans[spanBegin[s] .. spanBegin[s + 1]), in order along it
};

struct MacroFaces {
    std::vector<MacroFace> faces;
    std::vector<MacroCell> cells;
    std::vector<MacroSpan> spans;
    std::vector<uint8_t> spanShared;  // per span id: 1 when two macro faces have it

    uint32_t facesInMacroFaces() const { return uint32_t(cells.size()); }
    uint32_t spanCount() const { return uint32_t(spanShared.size()); }
};

inline constexpr uint32_t kDefaultMacroSpan = 16;  // the paper's largest (64 / 16 = factor 4 per face)

// Requires a cage that passed validateCage and its topology. O(faces) per pass; a few passes.
MacroFaces rectangularMacroFaces(const Cage& cage, const Topology& topology, uint32_t maxSpan = kDefaultMacroSpan);
MacroFaces quartetMacroFaces(const Cage& cage, const Topology& topology);
MacroFaces blockMacroFaces(const Cage& cage, const Topology& topology, uint32_t maxSpan = kDefaultMacroSpan);

// The cage vertex at lattice point (a, b) of macro face `m` (0 <= a <= width, 0 <= b <= height).
uint32_t macroLatticeVertex(const Cage& cage, const MacroFaces& macros, uint32_t m, uint32_t a, uint32_t b);

}  // namespace qp
