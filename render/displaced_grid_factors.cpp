#include "displaced_grid_factors.h"

#include <algorithm>
#include <bit>

namespace qp {

namespace {

// D is identically zero on a tile whose padded block (its cells and the overlap around them)
// holds only zeros, and only then can its factors stay as asked.
bool tileIsZero(const Displacement& d, uint32_t tile) {
    const DisplacementTile& t = d.layout.tiles[tile];
    const uint32_t count = (t.cells + 2) * (t.cells + 2);
    for (uint32_t k = 0; k < count; ++k)
        if (d.samples[d.layout.padded[t.offset + k]] != 0.0f) return false;
    return true;
}

// D on tile edge e reads the strip along it alone: the tile's own row next to the edge and the
// overlap across it, from one padded corner to the other (evaluateDisplacement on an edge; the
// span weights of points near the edge reach no further either). The tile on the other side
// has the same samples in its strip, so both sides find the same answer.
bool edgeIsZero(const Displacement& d, uint32_t tile, uint32_t e) {
    const int n = int(d.layout.tiles[tile].cells);
    for (int along = -1; along <= n; ++along)
        for (int row = 0; row < 2; ++row) {
            const int inner = row == 0 ? 0 : -1, outer = row == 0 ? n - 1 : n;
            const int i = e == 0 || e == 2 ? along : e == 1 ? outer : inner;
            const int j = e == 1 || e == 3 ? along : e == 0 ? inner : outer;
            if (d.samples[d.layout.sampleAt(tile, i, j)] != 0.0f) return false;
        }
    return true;
}

}  // namespace

GridFactors displacedGridFactors(const GpuPlanData& data, const Displacement& displacement, GridFactors base,
                                 const GridFactors* screen) {
    GridFactors f = std::move(base);
    for (uint32_t& pieces : f.segmentPieces) pieces = std::bit_ceil(std::max(pieces, 1u));
    for (uint32_t& n : f.subfaceFactor) n = std::bit_ceil(std::max(n, 1u));
    const DisplacementLayout& layout = displacement.layout;

    // Per drawn sub-face: whether its D is zero, and the factor that shows its cells.
    std::vector<uint8_t> zero(data.subfaces.size());
    std::vector<uint32_t> required(data.subfaces.size());
    for (uint32_t d = 0; d < data.subfaces.size(); ++d) {
        const uint32_t s = data.subfaces[d].subface;
        zero[d] = tileIsZero(displacement, s);
        required[d] = zero[d] ? 1 : requiredTessellationFactor(layout, s);
    }
    // Segments first: their pieces bound the factors of every sub-face on them. An edge whose
    // strip is not zero asks for its tile's cells along it (half of them on each half of a
    // split edge); segmentPieces is one number per segment, so both sides read the same, and
    // the other side asks for the same (its cells have the same size).
    for (uint32_t d = 0; d < data.subfaces.size(); ++d) {
        if (zero[d]) continue;
        const uint32_t s = data.subfaces[d].subface;
        for (uint32_t e = 0; e < 4; ++e) {
            if (edgeIsZero(displacement, s, e)) continue;
            const GpuEdgeRef& ref = data.boundaries[d].edges[e];
            if (ref.flags & kEdgeRefSplit) {  // both halves alike, as the grid layout expects
                uint32_t need = std::max(required[d] / 2, 1u);
                if (screen) need = std::min(need, std::max({screen->segmentPieces[ref.segment], screen->segmentPieces[ref.secondHalf], 1u}));
                const uint32_t pieces = std::max({need, f.segmentPieces[ref.segment], f.segmentPieces[ref.secondHalf]});
                f.segmentPieces[ref.segment] = f.segmentPieces[ref.secondHalf] = pieces;
            } else {
                uint32_t need = required[d];
                if (screen) need = std::min(need, std::max(screen->segmentPieces[ref.segment], 1u));
                f.segmentPieces[ref.segment] = std::max(f.segmentPieces[ref.segment], need);
            }
        }
    }
    // A quad's split edge shares its halves with the n-gon next to it: equalise once more,
    // as a half may have been raised from the n-gon's side after the quad was seen.
    for (uint32_t d = 0; d < data.subfaces.size(); ++d)
        for (const GpuEdgeRef& ref : data.boundaries[d].edges)
            if (ref.flags & kEdgeRefSplit) {
                const uint32_t pieces = std::max(f.segmentPieces[ref.segment], f.segmentPieces[ref.secondHalf]);
                f.segmentPieces[ref.segment] = f.segmentPieces[ref.secondHalf] = pieces;
            }
    for (uint32_t d = 0; d < data.subfaces.size(); ++d) {
        uint32_t& n = f.subfaceFactor[d];
        if (!zero[d]) n = std::max(n, screen ? std::min(required[d], std::max(screen->subfaceFactor[d], 1u)) : required[d]);
        for (const GpuEdgeRef& ref : data.boundaries[d].edges)
            n = std::max(n, (ref.flags & kEdgeRefSplit) ? 2 * f.segmentPieces[ref.segment] : f.segmentPieces[ref.segment]);
    }
    return f;
}

}  // namespace qp
