// Analytic displacement tiles (Nießner & Loop 2013; STAR §4.4.2, seed digest §3): per sub-face a
// scalar bi-quadratic uniform B-spline whose knots are the lines of an n x n grid of cells, so that
// D and its cross-edge derivative are continuous across every sub-face edge, and normals follow
// from D's derivatives with nothing stored per normal.
//
// Coefficients. A tile of n cells per side has (n + 2)^2 coefficients c(i, j), -1 <= i, j <= n,
// row-major in a padded block; coefficient c(i, j) belongs to the basis function centred on
// cell (i, j)'s centre ((i + 0.5) / n, (j + 0.5) / n). The n^2 cells are the tile's OWN
// coefficients; the ring around them is the OVERLAP: the coefficients of the neighbours' cells
// next to each edge (and, at a regular corner, of the diagonal neighbour's corner cell). A value
// is stored once at its HOME (an own cell) and COPIED into every overlap that shows it; after a
// home changes, propagateCopies brings the copies along. Evaluating a tile then reads only its
// own padded block (9 coefficients per point), which is what a shader wants.
//
// Spacing. Quads have n = R cells per side; an n-gon's sub-faces (half of each cage edge, Ptex
// numbering) have R / 2, so cells have the same size on both sides of every edge, split cage
// edges included: the B-spline across an edge is then one uniform spline and C1 by construction.
// R is a power of two, at least 2 on cages with non-quads.
//
// Corners. A tile corner is REGULAR where the cells around it form a regular grid: four tile
// corners (valence 4), two tile corners on the straight edge of a third tile (the midpoint of a
// cage edge split next to an n-gon), or on the boundary one tile corner or two meeting along an
// edge. Elsewhere (extraordinary vertices, n-gon centres, boundary vertices of other valences,
// non-manifold vertices) every tile's corner cell and padded corner hold ONE shared value, so D's
// gradient vanishes there as the paper prescribes: D is C1 away from such corners and has a
// flat spot at them.
//
// Boundaries. Across a boundary or non-manifold edge the overlap mirrors the tile's own row
// (zero cross derivative).
//
// The arrays are plain and GPU-ready: `tiles` (16 bytes each) and the coefficient floats.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "displacement.h"

namespace qp {

struct DisplacementTile {
    uint32_t cells;   // n cells per side
    uint32_t offset;  // first coefficient: c(-1, -1); c(i, j) at offset + (j + 1)(n + 2) + (i + 1)
    uint32_t unused[2];
};
static_assert(sizeof(DisplacementTile) == 16);

struct TileLayout {
    uint32_t resolution = 0;              // R: cells along a quad's side
    std::vector<DisplacementTile> tiles;  // one per sub-face
    // Per coefficient: its home (itself for a home). Homes are own cells.
    std::vector<uint32_t> home;
    // CSR over coefficients: the copies of each home (empty for copies).
    std::vector<uint32_t> copyOffsets, copies;
    // Per home shared by several tiles at an irregular corner: the tile and corner it is sited at
    // (brushes evaluate it at the vertex); kNoTileCorner for every other coefficient.
    std::vector<uint64_t> sharedCorner;

    uint32_t coefficientCount() const { return uint32_t(home.size()); }
    uint32_t index(uint32_t tile, int i, int j) const {
        const DisplacementTile& t = tiles[tile];
        return t.offset + uint32_t(j + 1) * (t.cells + 2) + uint32_t(i + 1);
    }
};
inline constexpr uint64_t kNoTileCorner = UINT64_MAX;

// Across tile edges: the cell of the neighbour next to a tile edge's cell (0 <= along < n), through
// the segments the sub-faces share; nothing on a boundary, a non-manifold edge or where the cells
// differ in size. `along` counts in the edge's own direction (u on edges 0 and 2, v on 1 and 3).
struct TileEdgeCell {
    uint32_t tile, edge;
    int along;
};
class TileAdjacency {
public:
    TileAdjacency(const DisplacementLayout& adjacency, const TileLayout& tiles);
    std::optional<TileEdgeCell> across(uint32_t tile, uint32_t edge, int along) const;

private:
    template <class F>
    void forEachReference(const F& f) const;

    const DisplacementLayout& adjacency_;
    const TileLayout& tiles_;
    std::vector<uint32_t> refOffsets_, refs_;  // CSR: segment -> 4 * tile + edge
};

// The smallest R the cage allows (2 with non-quads, else 1).
uint32_t minimumTileResolution(const DisplacementLayout& adjacency);

// Tiles for the sub-faces of `adjacency` (a layout of the same cage at any resolution: only
// its corners, edges and segments are read) with R = `resolution` (a power of two, at least
// minimumTileResolution).
TileLayout buildTileLayout(const DisplacementLayout& adjacency, uint32_t resolution);

// D and its derivatives at (u, v) of a sub-face (clamped to [0, 1]).
DisplacementValue evaluateTile(const TileLayout& layout, std::span<const float> coefficients, uint32_t subface, float u,
                               float v);

// D(u, v) for a displaced POSITION: inside the tile evaluateTile's value; on a tile edge the same
// bits from every tile that has the point. Along an edge the three pair sums (own cell + overlap,
// the same two numbers on both sides) are added in the edge segment's canonical direction at
// the canonical parameter snapped to 2^-14; at a knot crossing on the edge (a corner, a split
// edge's midpoint, a cell boundary) the four cells meeting there are added sorted.
// `adjacency` is the layout the tiles were built from.
float evaluateTileValue(const TileLayout& layout, const DisplacementLayout& adjacency, std::span<const float> coefficients,
                        uint32_t subface, float u, float v);

// Copies every home in `homes` (any order, repeats allowed) to its copies.
void propagateCopies(const TileLayout& layout, std::span<float> coefficients, std::span<const uint32_t> homes);
// The same for every home.
void propagateAllCopies(const TileLayout& layout, std::span<float> coefficients);

// The tile a coefficient (home or copy) belongs to.
uint32_t tileOfCoefficient(const TileLayout& layout, uint32_t coefficient);
// The tiles whose D reads one of `homes` (any order, repeats allowed): each home's own tile and
// every tile holding a copy of it, sorted, each once. What a renderer re-evaluates after a dab.
std::vector<uint32_t> tilesReadingHomes(const TileLayout& layout, std::span<const uint32_t> homes);

// Where a home lies on its tile: its cell centre, or for a shared corner home the corner.
struct CoefficientSite {
    uint32_t subface;
    float u, v;
};
CoefficientSite homeSite(const TileLayout& layout, uint32_t home);

// Coefficients approximating f (a function on the sub-faces that agrees along shared edges):
// the quasi-interpolant 2 f(centre) - (f(left) + f(right)) / 2 per direction (exact for
// polynomials of degree 2 in each variable inside a tile whose overlap holds them too), shared
// corner homes f at the vertex. Copies are filled.
std::vector<float> fitTiles(const TileLayout& layout, const std::function<float(uint32_t, float, float)>& f);

// The tiles' coefficients for a displacement of today's sample grids (file version 1): fitTiles
// of its D. Copies are filled.
std::vector<float> fitSampleGrids(const TileLayout& layout, const Displacement& grids);

}  // namespace qp
