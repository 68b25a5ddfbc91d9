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
                                             std::span<const SampleRange> ranges) {
    std::vector<uint32_t> out;
    const uint32_t segmentBegin = layout.segmentSampleBegin(), tileBegin = layout.tileSampleBegin();
    for (const SampleRange& range : ranges) {
        uint32_t first = range.first;
        const uint32_t end = std::min(range.first + range.count, layout.sampleCount);
        // Points.
        for (; first < std::min(end, segmentBegin); ++first)
            out.insert(out.end(), users.pointSubfaces.begin() + users.pointOffsets[first],
                       users.pointSubfaces.begin() + users.pointOffsets[first + 1]);
        // Segment interiors: segments are stored in offset order.
        if (first < std::min(end, tileBegin)) {
            auto it = std::upper_bound(layout.segments.begin(), layout.segments.end(), first,
                                       [](uint32_t sample, const DisplacementSegment& s) { return sample < s.offset; });
            for (uint32_t seg = uint32_t(it - layout.segments.begin()) - 1;
                 seg < layout.segments.size() && layout.segments[seg].offset < std::min(end, tileBegin); ++seg)
                if (layout.segments[seg].resolution > 1 && layout.segments[seg].offset + layout.segments[seg].resolution - 1 > first)
                    out.insert(out.end(), users.segmentSubfaces.begin() + users.segmentOffsets[seg],
                               users.segmentSubfaces.begin() + users.segmentOffsets[seg + 1]);
            first = std::min(end, tileBegin);
        }
        // Tiles: sub-faces are stored in offset order.
        if (first < end) {
            auto it = std::upper_bound(layout.subfaces.begin(), layout.subfaces.end(), first,
                                       [](uint32_t sample, const DisplacementSubface& s) { return sample < s.interiorOffset; });
            for (uint32_t s = uint32_t(it - layout.subfaces.begin()) - 1;
                 s < layout.subfaces.size() && layout.subfaces[s].interiorOffset < end; ++s) {
                const uint32_t R = layout.subfaces[s].resolution;
                if (R > 1 && layout.subfaces[s].interiorOffset + (R - 1) * (R - 1) > first) out.push_back(s);
            }
        }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

}  // namespace qp
