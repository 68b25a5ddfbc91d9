// Displacement: a scalar offset D along the unit limit normal, sculpted on the limit surface, as
// analytic tiles (Nießner & Loop 2013; STAR §4.4.2, seed digest §3): per sub-face a scalar
// bi-quadratic uniform B-spline whose knots are the lines of an n x n grid of cells, so that D and
// its cross-edge derivative are continuous across every sub-face edge, and normals follow from
// D's derivatives with nothing stored per normal (docs/displacement.md).
//
// Sub-faces are PlannedCage's (Ptex numbering: a quad is one, an n-gon n; face_config.h).
//
// Coefficients. A tile of n cells per side reads (n + 2)^2 coefficients c(i, j), -1 <= i, j <= n,
// row-major in its PADDED block; c(i, j) belongs to the basis function centred on cell (i, j)'s
// centre ((i + 0.5) / n, (j + 0.5) / n). The n^2 cells are the tile's own; the ring around them is
// the overlap: the neighbours' cells next to each edge (and, at a regular corner, the diagonal
// neighbour's corner cell). Each value is stored ONCE, as a SAMPLE (the brushes' unit, at the cell
// centre of the tile that owns it), and the padded blocks hold sample indices: `padded` maps
// every padded coefficient of every tile to its sample, which is what a shader reads.
//
// Spacing. Quads have n = R cells per side; an n-gon's sub-faces (half of each cage edge) have
// R / 2, so cells have the same size on both sides of every edge, split cage edges included: the
// B-spline across an edge is one uniform spline and C1 by construction. R is one power of two per
// object (C1 needs equal cells on both sides of every edge), and every tile has at least 2 cells
// per side (R >= 2, and R >= 4 on cages with non-quads): with one cell, a tile's single sample
// would be the corner cell of all four corners and join every irregular corner's shared sample.
//
// Corners. A tile corner is REGULAR where the cells around it form a regular grid: four tile
// corners (valence 4), two tile corners on the straight edge of a third tile (the midpoint of a
// cage edge split next to an n-gon), or on the boundary one tile corner or two meeting along an
// edge. Elsewhere (extraordinary vertices, n-gon centres, boundary vertices of other valences,
// non-manifold vertices) every tile's corner cell and padded corner are ONE shared sample, so D's
// gradient vanishes there as the paper prescribes: D is C1 away from such corners and has a flat
// spot at them. Across a boundary or non-manifold edge the overlap mirrors the tile's own row
// (zero cross derivative).
//
// Bits on shared edges. Displaced positions on both sides of an edge must be the same bits (no
// cracks). On a tile edge D depends on the tile's own row and its overlap only, which hold the
// same samples on both sides. evaluateDisplacement adds each pair (own + overlap, commutative)
// and sums the pairs in the edge segment's canonical direction at the canonical parameter snapped
// to 2^-14; at a knot crossing on the edge (a cell boundary, a corner, a split edge's midpoint)
// it takes the mean of the four samples meeting there, added sorted. Every tile that has the
// point then computes the same bits, whichever parameters it reaches it with.
//
// The arrays are plain and GPU-ready: `tiles` (16 bytes each), `padded` and the sample floats.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "displacement/sample_grids.h"

namespace qp {

struct DisplacementTile {
    uint32_t cells;      // n cells per side
    uint32_t offset;     // padded[offset + (j + 1)(n + 2) + (i + 1)] is c(i, j)'s sample
    uint32_t edgeFlags;  // bits 4e.. of edge e: kEdgeReversed | kEdgeSplit (the canonical direction)
    uint32_t unused;
};
static_assert(sizeof(DisplacementTile) == 16);

// Where a sample lives: cell (i, j) of tile `tile`, or, for a sample shared by the corner cells
// around an irregular corner, `corner` (0..3) of one of those tiles (-1 otherwise).
struct SampleHome {
    uint32_t tile;
    int16_t i, j;
    int32_t corner;
};

struct DisplacementLayout {
    SampleGridLayout adjacency;  // the sub-faces' corners, edges and segments (resolution 1)
    uint32_t resolution = 0;     // R: cells along a quad's side
    uint32_t sampleCount = 0;
    std::vector<DisplacementTile> tiles;  // one per sub-face
    std::vector<uint32_t> padded;         // per padded coefficient of every tile: its sample
    std::vector<SampleHome> homes;        // per sample

    uint32_t paddedIndex(uint32_t tile, int i, int j) const {
        const DisplacementTile& t = tiles[tile];
        return t.offset + uint32_t(j + 1) * (t.cells + 2) + uint32_t(i + 1);
    }
    uint32_t sampleAt(uint32_t tile, int i, int j) const { return padded[paddedIndex(tile, i, j)]; }
    bool operator==(const DisplacementLayout&) const;
};

struct Displacement {
    DisplacementLayout layout;   // empty: no displacement at all
    std::vector<float> samples;  // layout.sampleCount coefficients
    // The sculpting mask: empty (nothing masked) or one value in [0, 1] per sample, parallel to
    // `samples`; 1 is fully masked (brushes that change D leave the sample alone), 0 not at
    // all. Only brushes read it: renderers and exporters ignore it.
    std::vector<float> mask;

    bool empty() const { return layout.tiles.empty(); }
    bool hasMask() const { return !mask.empty(); }
    uint32_t resolution() const { return layout.resolution; }
    // Equal layouts, samples and masks, where an empty mask equals one of zeros (both mask
    // nothing: undoing the first mask stroke leaves a mask of zeros, not an empty one).
    bool operator==(const Displacement&) const;
};

// The smallest R a cage allows: 4 with non-quads (their sub-faces have R / 2 cells), else 2.
uint32_t minimumDisplacementResolution(const Cage& cage);

// Tiles for a cage (that passed validateCage) at R = max(resolution, the cage's minimum), a
// power of two up to kMaxDisplacementResolution.
DisplacementLayout buildDisplacementLayout(const Cage& cage, const Topology& topology, uint32_t resolution);

// All samples zero.
Displacement makeDisplacement(const Cage& cage, const Topology& topology, uint32_t resolution);

// The same cage's tiles at another R (at least the cage's minimum; a rebuild from layout.adjacency).
DisplacementLayout withResolution(const DisplacementLayout& layout, uint32_t resolution);

// D(u, v) on a sub-face, (u, v) in [0, 1]^2 (clamped), with its derivatives in (u, v). On an edge
// the value has the shared-edge bits described above; derivatives are the tile's (C0 across
// edges like D_u along them, C1 across them as the cross derivative).
DisplacementValue evaluateDisplacement(const Displacement& displacement, uint32_t subface, float u, float v);

// One sub-face's D for evaluating it at many points (a renderer's grid): its padded block
// gathered once. evaluate(u, v) has evaluateDisplacement's bits; inside(u, v) is the same
// away from edges (0 < u, v < 1) for callers that know they are inside.
class SubfaceDisplacement {
public:
    SubfaceDisplacement(const Displacement& displacement, uint32_t subface);

    uint32_t cells() const { return cells_; }
    DisplacementValue evaluate(float u, float v) const;
    DisplacementValue inside(float u, float v) const;

private:
    const Displacement& displacement_;
    uint32_t subface_;
    uint32_t cells_;
    float block_[(kMaxDisplacementResolution + 2) * (kMaxDisplacementResolution + 2)];  // row-major, i fastest
};

// Where a sample lies on the surface: the centre of its home cell, or a shared corner's vertex.
constexpr uint32_t kNoSite = UINT32_MAX;
struct SampleSite {
    uint32_t subface = kNoSite;
    float u = 0.0f, v = 0.0f;
};
SampleSite sampleSite(const DisplacementLayout& layout, uint32_t sample);

// Samples approximating f (a function on the sub-faces that agrees along shared edges): per cell
// the quasi-interpolant 2 f(centre) - (f(left) + f(right)) / 2 in each direction, which a tile
// reproduces exactly for polynomials of degree 2 in each variable; a shared corner sample takes f
// at its vertex.
std::vector<float> fitSamples(const DisplacementLayout& layout, const std::function<float(uint32_t, float, float)>& f);

// Copy at another R that keeps the shape (fitSamples of the old D; the mask likewise, clamped to
// [0, 1]; an empty mask stays empty). R is raised to the cage's minimum; the same R returns a copy.
Displacement resampleDisplacement(const Displacement& displacement, uint32_t resolution);

// The displacement of a file of version 1 (sample grids), fitted on a layout of the same cage.
Displacement fitSampleGrids(const DisplacementLayout& layout, const SampleGrids& grids);

// Tessellation factors at which a renderer shows every cell: a sub-face's cells, and on an edge
// split at a cage-edge midpoint the quad side's convention (twice the n-gon sub-face's factor),
// so both sides of every edge ask for the same.
uint32_t requiredTessellationFactor(const DisplacementLayout& layout, uint32_t subface);

// The displaced point s + D N and its shading normal. The normal's own derivatives are
// dropped (Blinn's approximation, as Nießner & Loop's fast variant): f_u ~ s_u + D_u N, which
// needs no second derivatives of the limit surface (the plan evaluators give none) and errs
// by the factor (1 + D kappa) on the tangents, i.e. not at all where the surface is flat.
struct DisplacedPoint {
    glm::vec3 position, normal;
};
// Inline: renderers call it for every vertex of a grid.
inline DisplacedPoint displacePoint(const glm::vec3& position, const glm::vec3& du, const glm::vec3& dv,
                                    const glm::vec3& unitNormal, const DisplacementValue& d) {
    DisplacedPoint out;
    out.position = position + d.value * unitNormal;
    const glm::vec3 fu = du + d.du * unitNormal, fv = dv + d.dv * unitNormal;
    const glm::vec3 n = glm::cross(fu, fv);
    const float length = glm::length(n);
    out.normal = length > 0.0f ? n / length : unitNormal;
    return out;
}

}  // namespace qp
