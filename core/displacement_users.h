// Which sub-faces read a displacement sample: what a renderer re-evaluates after a brush dab
// changed samples in place (docs/displacement.md, "How a renderer integrates it").
//
// A sub-face's D (evaluateDisplacement) reads its tile, its corner points and every sample of
// the segments on its edges (all of them where an edge is finer than its grid), including the
// end points of those segments (the midpoint of a split quad edge is such a point without being
// a corner). Tile samples have one reader; segment samples the sub-faces on both sides; points
// every sub-face around them.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "displacement.h"

namespace qp {

struct DisplacementUsers {
    std::vector<uint32_t> pointOffsets, pointSubfaces;      // CSR: point -> sub-faces
    std::vector<uint32_t> segmentOffsets, segmentSubfaces;  // CSR: segment -> sub-faces
    // Per sample past the points: its segment, or for a tile sample its sub-face.
    std::vector<uint32_t> holder;
};
DisplacementUsers buildDisplacementUsers(const DisplacementLayout& layout);

// The sub-faces whose D reads one of `samples` (any order, repeats allowed): sorted, each once.
std::vector<uint32_t> subfacesReadingSamples(const DisplacementLayout& layout, const DisplacementUsers& users,
                                             std::span<const uint32_t> samples);

}  // namespace qp
