#include "displacement_users.h"

#include <algorithm>

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
    std::vector<uint32_t> out;
    const uint32_t segmentBegin = layout.segmentSampleBegin(), tileBegin = layout.tileSampleBegin();
    auto append = [&](const std::vector<uint32_t>& offsets, const std::vector<uint32_t>& values, uint32_t key) {
        out.insert(out.end(), values.begin() + offsets[key], values.begin() + offsets[key + 1]);
    };
    for (uint32_t sample : samples) {
        if (sample < segmentBegin) {
            append(users.pointOffsets, users.pointSubfaces, sample);
        } else if (sample < tileBegin) {
            // Segments are stored in offset order; the last one starting at or before the
            // sample holds it (segments without interior samples share their successor's offset).
            auto it = std::upper_bound(layout.segments.begin(), layout.segments.end(), sample,
                                       [](uint32_t x, const DisplacementSegment& s) { return x < s.offset; });
            append(users.segmentOffsets, users.segmentSubfaces, uint32_t(it - layout.segments.begin()) - 1);
        } else if (sample < layout.sampleCount) {
            auto it = std::upper_bound(layout.subfaces.begin(), layout.subfaces.end(), sample,
                                       [](uint32_t x, const DisplacementSubface& s) { return x < s.interiorOffset; });
            out.push_back(uint32_t(it - layout.subfaces.begin()) - 1);
        }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

}  // namespace qp
