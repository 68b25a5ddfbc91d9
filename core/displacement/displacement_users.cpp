#include "displacement/displacement_users.h"

#include <algorithm>
#include <bit>

namespace qp {

DisplacementUsers buildDisplacementUsers(const DisplacementLayout& layout) {
    // (sample, tile) for every padded coefficient, made unique.
    std::vector<uint64_t> pairs;
    pairs.reserve(layout.padded.size());
    for (uint32_t t = 0; t < layout.tiles.size(); ++t) {
        const DisplacementTile& tile = layout.tiles[t];
        const uint32_t count = (tile.cells + 2) * (tile.cells + 2);
        for (uint32_t k = 0; k < count; ++k) pairs.push_back(uint64_t(layout.padded[tile.offset + k]) << 32 | t);
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    DisplacementUsers users;
    users.offsets.assign(size_t(layout.sampleCount) + 1, 0);
    users.subfaces.reserve(pairs.size());
    for (uint64_t p : pairs) {
        ++users.offsets[(p >> 32) + 1];
        users.subfaces.push_back(uint32_t(p));
    }
    for (size_t s = 0; s < layout.sampleCount; ++s) users.offsets[s + 1] += users.offsets[s];
    return users;
}

namespace {

// Sub-faces reading the samples `forEachSample` visits.
template <class ForEachSample>
std::vector<uint32_t> subfacesReading(const DisplacementLayout& layout, const DisplacementUsers& users,
                                      const ForEachSample& forEachSample) {
    // A bitmap of sub-faces: sorted and unique for free.
    std::vector<uint64_t> reading((layout.tiles.size() + 63) / 64, 0);
    forEachSample([&](uint32_t sample) {
        if (sample >= layout.sampleCount) return;
        for (uint32_t k = users.offsets[sample]; k < users.offsets[sample + 1]; ++k)
            reading[users.subfaces[k] / 64] |= uint64_t(1) << (users.subfaces[k] % 64);
    });
    std::vector<uint32_t> out;
    for (uint32_t word = 0; word < reading.size(); ++word)
        for (uint64_t bits = reading[word]; bits; bits &= bits - 1) out.push_back(word * 64 + uint32_t(std::countr_zero(bits)));
    return out;
}

}  // namespace

std::vector<uint32_t> subfacesReadingSamples(const DisplacementLayout& layout, const DisplacementUsers& users,
                                             std::span<const uint32_t> samples) {
    return subfacesReading(layout, users, [&](const auto& visit) {
        for (uint32_t sample : samples) visit(sample);
    });
}

std::vector<uint32_t> subfacesReadingSamples(const DisplacementLayout& layout, const DisplacementUsers& users,
                                             const SampleBits& samples) {
    // In sample order: the CSR is read in sequence.
    return subfacesReading(layout, users, [&](const auto& visit) { samples.forEach(visit); });
}

void SampleBits::assign(uint32_t sampleCount, std::span<const uint32_t> samples) {
    words.assign((size_t(sampleCount) + 63) / 64, 0);
    for (uint32_t s : samples) words[s >> 6] |= uint64_t(1) << (s & 63);
}

}  // namespace qp
