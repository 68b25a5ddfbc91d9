#include "displacement_users.h"

#include <algorithm>
#include <bit>

namespace qp {

namespace {

// CSR from (key, value) pairs, values per key sorted and unique.
void buildCsr(uint32_t keys, std::vector<std::pair<uint32_t, uint32_t>>& pairs, std::vector<uint32_t>& offsets,
              std::vector<uint32_t>& values) {
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    offsets.assign(keys + 1, 0);
    for (const auto& [key, value] : pairs) ++offsets[key + 1];
    for (uint32_t k = 0; k < keys; ++k) offsets[k + 1] += offsets[k];
    values.resize(pairs.size());
    for (size_t i = 0; i < pairs.size(); ++i) values[i] = pairs[i].second;
}

}  // namespace

DisplacementUsers buildDisplacementUsers(const DisplacementLayout& layout) {
    std::vector<std::pair<uint32_t, uint32_t>> points, segments;
    for (uint32_t s = 0; s < layout.subfaces.size(); ++s) {
        const DisplacementSubface& sf = layout.subfaces[s];
        for (uint32_t c = 0; c < 4; ++c) points.push_back({sf.corners[c], s});
        for (const DisplacementEdge& e : sf.edges)
            for (uint32_t segment : {e.segment, e.secondHalf}) {
                if (segment == kNoSegment) continue;
                segments.push_back({segment, s});
                points.push_back({layout.segments[segment].pointA, s});
                points.push_back({layout.segments[segment].pointB, s});
            }
    }
    DisplacementUsers users;
    buildCsr(layout.pointCount, points, users.pointOffsets, users.pointSubfaces);
    buildCsr(uint32_t(layout.segments.size()), segments, users.segmentOffsets, users.segmentSubfaces);
    users.holder.resize(layout.sampleCount - layout.pointCount);
    for (uint32_t g = 0; g < layout.segments.size(); ++g) {
        const DisplacementSegment& s = layout.segments[g];
        std::fill_n(users.holder.begin() + (s.offset - layout.pointCount), s.resolution - 1, g);
    }
    for (uint32_t f = 0; f < layout.subfaces.size(); ++f) {
        const DisplacementSubface& sf = layout.subfaces[f];
        std::fill_n(users.holder.begin() + (sf.interiorOffset - layout.pointCount), (sf.resolution - 1) * (sf.resolution - 1), f);
    }
    return users;
}

namespace {

// Sub-faces reading the samples `forEachSample` visits.
template <class ForEachSample>
std::vector<uint32_t> subfacesReading(const DisplacementLayout& layout, const DisplacementUsers& users,
                                      const ForEachSample& forEachSample) {
    // A bitmap of sub-faces: sorted and unique for free.
    std::vector<uint64_t> reading((layout.subfaces.size() + 63) / 64, 0);
    auto mark = [&](uint32_t subface) { reading[subface / 64] |= uint64_t(1) << (subface % 64); };
    auto markAll = [&](const std::vector<uint32_t>& offsets, const std::vector<uint32_t>& values, uint32_t key) {
        for (uint32_t k = offsets[key]; k < offsets[key + 1]; ++k) mark(values[k]);
    };
    const uint32_t segmentBegin = layout.segmentSampleBegin(), tileBegin = layout.tileSampleBegin();
    forEachSample([&](uint32_t sample) {
        if (sample < segmentBegin) markAll(users.pointOffsets, users.pointSubfaces, sample);
        else if (sample < tileBegin) markAll(users.segmentOffsets, users.segmentSubfaces, users.holder[sample - segmentBegin]);
        else if (sample < layout.sampleCount) mark(users.holder[sample - segmentBegin]);
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
    // In sample order: the holder table is read in sequence.
    return subfacesReading(layout, users, [&](const auto& visit) { samples.forEach(visit); });
}

void SampleBits::assign(uint32_t sampleCount, std::span<const uint32_t> samples) {
    words.assign((size_t(sampleCount) + 63) / 64, 0);
    for (uint32_t s : samples) words[s >> 6] |= uint64_t(1) << (s & 63);
}

}  // namespace qp
