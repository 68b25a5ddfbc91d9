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

#include "brush.h"  // SampleRange
#include "displacement.h"

namespace qp {

struct DisplacementUsers {
    std::vector<uint32_t> pointOffsets, pointSubfaces;      // CSR: point -> sub-faces
    std::vector<uint32_t> segmentOffsets, segmentSubfaces;  // CSR: segment -> sub-faces
};
DisplacementUsers buildDisplacementUsers(const DisplacementLayout& layout);

// The sub-faces whose D reads a sample in one of `ranges`: sorted, each once.
std::vector<uint32_t> subfacesReadingSamples(const DisplacementLayout& layout, const DisplacementUsers& users,
                                             std::span<const SampleRange> ranges);

}  // namespace qp
