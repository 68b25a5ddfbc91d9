// Which sub-faces read a displacement sample: what a renderer re-evaluates after a brush dab
// changed samples in place (docs/displacement.md, "How a renderer integrates it").
//
// A sub-face's D reads its padded block: its own cells and the overlap around them. A sample is
// read by the tile it lives in and by every tile that shows it in its overlap (the neighbours
// across the edges next to it, and at a corner the tiles around that corner).
#pragma once

#include <bit>
#include <cstdint>
#include <span>
#include <vector>

#include "displacement/displacement.h"

namespace qp {

struct DisplacementUsers {
    std::vector<uint32_t> offsets, subfaces;  // CSR: sample -> the sub-faces reading it, ascending
};
DisplacementUsers buildDisplacementUsers(const DisplacementLayout& layout);

// The sub-faces whose D reads one of `samples` (any order, repeats allowed): sorted, each once.
std::vector<uint32_t> subfacesReadingSamples(const DisplacementLayout& layout, const DisplacementUsers& users,
                                             std::span<const uint32_t> samples);

// A set of samples as one bit each: a big dab's list (any order, repeats) marked into a few
// tens of KiB that stay in cache, then read in sample order (sorted and unique for free) and
// tested in O(1). Reused between dabs: assign() clears it.
struct SampleBits {
    std::vector<uint64_t> words;

    void assign(uint32_t sampleCount, std::span<const uint32_t> samples);
    bool contains(uint32_t sample) const { return words[sample >> 6] >> (sample & 63) & 1; }
    template <class Visit>
    void forEach(const Visit& visit) const {
        for (uint32_t word = 0; word < words.size(); ++word)
            for (uint64_t bits = words[word]; bits; bits &= bits - 1) visit(word * 64 + uint32_t(std::countr_zero(bits)));
    }
};
// subfacesReadingSamples for the samples in `samples`.
std::vector<uint32_t> subfacesReadingSamples(const DisplacementLayout& layout, const DisplacementUsers& users,
                                             const SampleBits& samples);

}  // namespace qp
