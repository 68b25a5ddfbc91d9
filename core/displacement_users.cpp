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
    return users;
}

std::vector<uint32_t> subfacesReadingSamples(const DisplacementLayout& layout, const DisplacementUsers& users,
                                             std::span<const uint32_t> samples) {
    // A bitmap of sub-faces (sorted and unique for free). A brush's samples come in runs from
    // one tile or segment: the last run's range skips the search for the rest of it.
    std::vector<uint64_t> reading((layout.subfaces.size() + 63) / 64, 0);
    auto mark = [&](uint32_t subface) { reading[subface / 64] |= uint64_t(1) << (subface % 64); };
    auto markAll = [&](const std::vector<uint32_t>& offsets, const std::vector<uint32_t>& values, uint32_t key) {
        for (uint32_t k = offsets[key]; k < offsets[key + 1]; ++k) mark(values[k]);
    };
    const uint32_t segmentBegin = layout.segmentSampleBegin(), tileBegin = layout.tileSampleBegin();
    uint32_t runBegin = 0, runEnd = 0;  // samples of the last tile or segment found
    for (uint32_t sample : samples) {
        if (sample >= runBegin && sample < runEnd) continue;
        if (sample < segmentBegin) {
            markAll(users.pointOffsets, users.pointSubfaces, sample);
        } else if (sample < tileBegin) {
            // Segments are stored in offset order; the last one starting at or before the
            // sample holds it (segments without interior samples share their successor's offset).
            auto it = std::upper_bound(layout.segments.begin(), layout.segments.end(), sample,
                                       [](uint32_t x, const DisplacementSegment& s) { return x < s.offset; });
            const uint32_t segment = uint32_t(it - layout.segments.begin()) - 1;
            markAll(users.segmentOffsets, users.segmentSubfaces, segment);
            runBegin = layout.segments[segment].offset;
            runEnd = runBegin + layout.segments[segment].resolution - 1;
        } else if (sample < layout.sampleCount) {
            auto it = std::upper_bound(layout.subfaces.begin(), layout.subfaces.end(), sample,
                                       [](uint32_t x, const DisplacementSubface& s) { return x < s.interiorOffset; });
            const uint32_t subface = uint32_t(it - layout.subfaces.begin()) - 1;
            mark(subface);
            const uint32_t R = layout.subfaces[subface].resolution;
            runBegin = layout.subfaces[subface].interiorOffset;
            runEnd = runBegin + (R - 1) * (R - 1);
        }
    }
    std::vector<uint32_t> out;
    for (uint32_t word = 0; word < reading.size(); ++word)
        for (uint64_t bits = reading[word]; bits; bits &= bits - 1) out.push_back(word * 64 + uint32_t(std::countr_zero(bits)));
    return out;
}

}  // namespace qp
