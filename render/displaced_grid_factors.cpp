#include "displaced_grid_factors.h"

#include <algorithm>
#include <bit>

namespace qp {

namespace {

bool segmentIsZero(const Displacement& d, const DisplacementSegment& s) {
    for (uint32_t k = 0; k <= s.resolution; ++k)
        if (d.samples[segmentSample(s, k)] != 0.0f) return false;
    return true;
}

bool tileIsZero(const Displacement& d, uint32_t subface) {
    const uint32_t r = d.layout.subfaces[subface].resolution;
    for (uint32_t j = 0; j <= r; ++j)
        for (uint32_t i = 0; i <= r; ++i)
            if (d.samples[gridSample(d.layout, subface, i, j)] != 0.0f) return false;
    return true;
}

}  // namespace

GridFactors displacedGridFactors(const GpuPlanData& data, const Displacement& displacement, GridFactors base,
                                 const GridFactors* screen) {
    GridFactors f = std::move(base);
    for (uint32_t& pieces : f.segmentPieces) pieces = std::bit_ceil(std::max(pieces, 1u));
    for (uint32_t& n : f.subfaceFactor) n = std::bit_ceil(std::max(n, 1u));
    const DisplacementLayout& layout = displacement.layout;

    // Segments first: their pieces bound the factors of every sub-face on them.
    std::vector<int8_t> zeroSegment(layout.segments.size(), -1);  // -1: not looked at yet
    // `drawnSegment`: the same segment in the renderer's numbering (for the screen's cap).
    auto needed = [&](uint32_t segment, uint32_t drawnSegment) -> uint32_t {
        if (segment == kNoSegment) return 1;
        if (zeroSegment[segment] < 0) zeroSegment[segment] = segmentIsZero(displacement, layout.segments[segment]);
        if (zeroSegment[segment]) return 1;
        const uint32_t resolution = layout.segments[segment].resolution;
        return screen ? std::min(resolution, std::max(screen->segmentPieces[drawnSegment], 1u)) : resolution;
    };
    for (uint32_t d = 0; d < data.subfaces.size(); ++d) {
        const DisplacementSubface& tile = layout.subfaces[data.subfaces[d].subface];
        for (uint32_t e = 0; e < 4; ++e) {
            const GpuEdgeRef& ref = data.boundaries[d].edges[e];
            const DisplacementEdge& edge = tile.edges[e];
            if (ref.flags & kEdgeRefSplit) {  // both halves alike, as the grid layout expects
                const uint32_t pieces = std::max({needed(edge.segment, ref.segment), needed(edge.secondHalf, ref.secondHalf),
                                                  f.segmentPieces[ref.segment], f.segmentPieces[ref.secondHalf]});
                f.segmentPieces[ref.segment] = f.segmentPieces[ref.secondHalf] = pieces;
            } else {
                f.segmentPieces[ref.segment] = std::max(f.segmentPieces[ref.segment], needed(edge.segment, ref.segment));
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
        const uint32_t s = data.subfaces[d].subface;
        uint32_t& n = f.subfaceFactor[d];
        if (!tileIsZero(displacement, s)) {
            const uint32_t resolution = layout.subfaces[s].resolution;
            n = std::max(n, screen ? std::min(resolution, std::max(screen->subfaceFactor[d], 1u)) : resolution);
        }
        for (const GpuEdgeRef& ref : data.boundaries[d].edges)
            n = std::max(n, (ref.flags & kEdgeRefSplit) ? 2 * f.segmentPieces[ref.segment] : f.segmentPieces[ref.segment]);
    }
    return f;
}

}  // namespace qp
