#include "displacement/sample_grids.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>

#include "plans/face_config.h"

namespace qp {

namespace {

// 2^14: edge parameters are snapped to multiples of its inverse (see evaluateSampleGrids).
constexpr float kEdgeSnap = 16384.0f;

uint32_t midpointId(const SampleGridLayout& l, uint32_t edge) { return l.vertexCount + edge; }
uint32_t centreId(const SampleGridLayout& l, uint32_t face) { return l.vertexCount + l.edgeCount + face; }

// The segment resolution a sub-face edge asks for.
uint32_t segmentNeed(uint32_t resolution, const DisplacementEdge& edge) {
    return edge.flags & kEdgeSplit ? std::max(resolution / 2, 1u) : resolution;
}

void assignResolutionsAndOffsets(SampleGridLayout& layout) {
    for (DisplacementSegment& s : layout.segments) s.resolution = 1;
    for (const DisplacementSubface& sf : layout.subfaces)
        for (const DisplacementEdge& e : sf.edges) {
            uint32_t need = segmentNeed(sf.resolution, e);
            layout.segments[e.segment].resolution = std::max(layout.segments[e.segment].resolution, need);
            if (e.secondHalf != kNoSegment)
                layout.segments[e.secondHalf].resolution = std::max(layout.segments[e.secondHalf].resolution, need);
        }
    uint32_t offset = layout.pointCount;
    for (DisplacementSegment& s : layout.segments) {
        s.offset = offset;
        offset += s.resolution - 1;
    }
    for (DisplacementSubface& sf : layout.subfaces) {
        sf.interiorOffset = offset;
        offset += (sf.resolution - 1) * (sf.resolution - 1);
        for (DisplacementEdge& e : sf.edges) {
            e.flags &= ~kEdgeFiner;
            bool finer = e.flags & kEdgeSplit
                             ? sf.resolution == 1 || layout.segments[e.segment].resolution * 2 > sf.resolution ||
                                   layout.segments[e.secondHalf].resolution * 2 > sf.resolution
                             : layout.segments[e.segment].resolution > sf.resolution;
            if (finer) e.flags |= kEdgeFiner;
        }
    }
    layout.sampleCount = offset;
}

struct DisplacementCell {
    uint32_t i, j;   // the cell's corner (i, j); 0 <= i, j < R
    float fx, fy;    // position inside the cell, in [0, 1]
};
DisplacementCell displacementCell(uint32_t resolution, float u, float v) {
    const float Rf = float(resolution);
    const float x = u * Rf, y = v * Rf;
    const uint32_t i = std::min(uint32_t(x), resolution - 1), j = std::min(uint32_t(y), resolution - 1);
    return {i, j, x - float(i), y - float(j)};
}
float lerp(float a, float b, float f) { return (1.0f - f) * a + f * b; }
DisplacementValue bilinearDisplacement(float g00, float g10, float g01, float g11, const DisplacementCell& c, float Rf) {
    DisplacementValue out;
    out.value = lerp(lerp(g00, g10, c.fx), lerp(g01, g11, c.fx), c.fy);
    out.du = Rf * lerp(g10 - g00, g11 - g01, c.fy);
    out.dv = Rf * lerp(g01 - g00, g11 - g10, c.fx);
    return out;
}

// Value and d/dt of a segment at canonical t. On a sample (f = 0 or 1) the value is that
// sample's bits, so a corner reached through any of its segments reads the same bits.
DisplacementValue segmentValue(const SampleGridLayout& layout, const std::vector<float>& samples, uint32_t segment,
                               float t) {
    const DisplacementSegment& s = layout.segments[segment];
    float x = std::clamp(t, 0.0f, 1.0f) * float(s.resolution);
    uint32_t k = std::min(uint32_t(x), s.resolution - 1);
    float f = x - float(k);
    float a = samples[segmentSample(s, k)], b = samples[segmentSample(s, k + 1)];
    float value = f == 0.0f ? a : f == 1.0f ? b : lerp(a, b, f);
    return {value, float(s.resolution) * (b - a), 0.0f};
}

// Edge function of a sub-face edge at its own parameter t, and dE/dt. With `snap`, the
// canonical parameter is snapped so both sides of the edge compute the same bits.
DisplacementValue edgeValue(const SampleGridLayout& layout, const std::vector<float>& samples,
                            const DisplacementEdge& edge, float t, bool snap) {
    auto snapped = [snap](float tc) { return snap ? std::round(tc * kEdgeSnap) / kEdgeSnap : tc; };
    if (!(edge.flags & kEdgeSplit)) {
        bool reversed = edge.flags & kEdgeReversed;
        DisplacementValue v = segmentValue(layout, samples, edge.segment, snapped(reversed ? 1.0f - t : t));
        if (reversed) v.du = -v.du;
        return v;
    }
    // Both halves run from a cage vertex to the midpoint (vertex ids are below midpoint ids).
    if (t <= 0.5f) {
        DisplacementValue v = segmentValue(layout, samples, edge.segment, snapped(2.0f * t));
        v.du *= 2.0f;
        return v;
    }
    DisplacementValue v = segmentValue(layout, samples, edge.secondHalf, snapped(2.0f * (1.0f - t)));
    v.du *= -2.0f;
    return v;
}

}  // namespace

uint32_t SampleGridLayout::tileSampleBegin() const {
    return subfaces.empty() ? sampleCount : subfaces.front().interiorOffset;
}

bool SampleGridLayout::operator==(const SampleGridLayout& o) const {
    auto bytesEqual = [](const auto& a, const auto& b) {
        return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](const auto& x, const auto& y) {
                   return std::memcmp(&x, &y, sizeof x) == 0;
               });
    };
    return vertexCount == o.vertexCount && edgeCount == o.edgeCount && faceCount == o.faceCount &&
           pointCount == o.pointCount && sampleCount == o.sampleCount && bytesEqual(subfaces, o.subfaces) &&
           bytesEqual(segments, o.segments);
}

SampleGridLayout buildSampleGridLayout(const Cage& cage, const Topology& topology, uint32_t resolution) {
    assert(isPowerOfTwo(resolution) && resolution <= kMaxDisplacementResolution);
    SampleGridLayout layout;
    layout.vertexCount = cage.vertexCount();
    layout.edgeCount = topology.edgeCount();
    layout.faceCount = cage.faceCount();
    layout.pointCount = layout.vertexCount + layout.edgeCount + layout.faceCount;

    // Cage edges: one segment, or two halves (the half at edgeVertices[0] first).
    std::vector<uint32_t> edgeSegment(topology.edgeCount());
    std::vector<bool> split(topology.edgeCount(), false);
    for (uint32_t e = 0; e < topology.edgeCount(); ++e) {
        for (uint32_t k = topology.edgeFaceOffsets[e]; k < topology.edgeFaceOffsets[e + 1]; ++k)
            if (cage.faceSize(topology.edgeFaces[k]) != 4) split[e] = true;
        uint32_t a = topology.edgeVertices[2 * e], b = topology.edgeVertices[2 * e + 1];
        edgeSegment[e] = uint32_t(layout.segments.size());
        if (split[e]) {
            layout.segments.push_back({a, midpointId(layout, e), 1, 0});
            layout.segments.push_back({b, midpointId(layout, e), 1, 0});
        } else {
            layout.segments.push_back({a, b, 1, 0});
        }
    }
    // The half of split edge e that ends at cage vertex v.
    auto halfAt = [&](uint32_t e, uint32_t v) { return edgeSegment[e] + (topology.edgeVertices[2 * e] == v ? 0 : 1); };

    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        const uint32_t n = cage.faceSize(f);
        const uint32_t* fv = cage.faceBegin(f);
        const uint32_t* fe = topology.faceEdges.data() + cage.faceOffsets[f];
        if (n == 4) {
            DisplacementSubface sf{};
            sf.resolution = resolution;
            for (uint32_t c = 0; c < 4; ++c) sf.corners[c] = fv[c];
            for (uint32_t e = 0; e < 4; ++e) {
                uint32_t a = fv[kEdgeStart[e]], z = fv[kEdgeEnd[e]];
                // Cage edge e of the face runs fv[e] -> fv[e+1]: the same edge as sub-face edge
                // e (edges 2 and 3 run against the winding).
                uint32_t cageEdge = fe[e];
                DisplacementEdge& edge = sf.edges[e];
                if (split[cageEdge]) {
                    edge = {halfAt(cageEdge, a), halfAt(cageEdge, z), kEdgeSplit, 0};
                } else {
                    edge = {edgeSegment[cageEdge], kNoSegment, a > z ? kEdgeReversed : 0u, 0};
                }
            }
            layout.subfaces.push_back(sf);
            continue;
        }
        const uint32_t spokes = uint32_t(layout.segments.size());  // spoke i: midpoint of cage edge i -> centre
        for (uint32_t i = 0; i < n; ++i) layout.segments.push_back({midpointId(layout, fe[i]), centreId(layout, f), 1, 0});
        for (uint32_t k = 0; k < n; ++k) {
            const uint32_t next = fe[k], prev = fe[(k + n - 1) % n];
            DisplacementSubface sf{};
            sf.resolution = resolution;
            sf.corners[0] = fv[k];
            sf.corners[1] = midpointId(layout, next);
            sf.corners[2] = centreId(layout, f);
            sf.corners[3] = midpointId(layout, prev);
            // Every n-gon sub-face edge runs from its lower point id to its higher one.
            sf.edges[0] = {halfAt(next, fv[k]), kNoSegment, 0, 0};
            sf.edges[1] = {spokes + k, kNoSegment, 0, 0};
            sf.edges[2] = {spokes + (k + n - 1) % n, kNoSegment, 0, 0};
            sf.edges[3] = {halfAt(prev, fv[k]), kNoSegment, 0, 0};
            layout.subfaces.push_back(sf);
        }
    }
    assignResolutionsAndOffsets(layout);
    return layout;
}

SampleGridLayout withResolutions(const SampleGridLayout& layout, std::span<const uint32_t> resolutions) {
    assert(resolutions.size() == layout.subfaces.size());
    SampleGridLayout out = layout;
    for (size_t s = 0; s < resolutions.size(); ++s) {
        assert(isPowerOfTwo(resolutions[s]) && resolutions[s] <= kMaxDisplacementResolution);
        out.subfaces[s].resolution = resolutions[s];
    }
    assignResolutionsAndOffsets(out);
    return out;
}

SampleGrids makeSampleGrids(const Cage& cage, const Topology& topology, uint32_t resolution) {
    SampleGrids d;
    d.layout = buildSampleGridLayout(cage, topology, resolution);
    d.samples.assign(d.layout.sampleCount, 0.0f);
    return d;
}

EdgeSite edgeSite(const DisplacementSubface& subface, uint32_t edge, uint32_t i, uint32_t n) {
    const DisplacementEdge& e = subface.edges[edge];
    if (!(e.flags & kEdgeSplit)) return {e.segment, e.flags & kEdgeReversed ? n - i : i, n};
    assert(n % 2 == 0);
    if (2 * i <= n) return {e.segment, i, n / 2};
    return {e.secondHalf, n - i, n / 2};
}

float edgeParameter(const DisplacementEdge& edge, uint32_t half, uint32_t k, uint32_t m) {
    if (edge.flags & kEdgeSplit) return half ? float(2 * m - k) / float(2 * m) : float(k) / float(2 * m);
    return float(edge.flags & kEdgeReversed ? m - k : k) / float(m);
}

glm::vec2 edgePoint(uint32_t edge, float t) {
    switch (edge) {
    case 0: return {t, 0.0f};
    case 1: return {1.0f, t};
    case 2: return {t, 1.0f};
    default: return {0.0f, t};
    }
}

namespace {

// gridSample of point `along` (0 < along < R) of sub-face edge `edge`: R intervals on the
// sub-face edge; its segment has as many or more (a power of two times).
uint32_t edgeGridSample(const SampleGridLayout& layout, const DisplacementSubface& sf, uint32_t edge, uint32_t along) {
    const DisplacementEdge& e = sf.edges[edge];
    const uint32_t R = sf.resolution;
    uint32_t segment = e.segment, k = along, intervals = R;  // edgeSite, inline
    if (!(e.flags & kEdgeSplit)) {
        if (e.flags & kEdgeReversed) k = R - along;
    } else {
        intervals = R / 2;
        if (2 * along > R) segment = e.secondHalf, k = R - along;
    }
    const DisplacementSegment& seg = layout.segments[segment];
    return segmentSample(seg, k * (seg.resolution / intervals));
}

}  // namespace

uint32_t gridSample(const SampleGridLayout& layout, uint32_t subface, uint32_t i, uint32_t j) {
    const DisplacementSubface& sf = layout.subfaces[subface];
    const uint32_t R = sf.resolution;
    if (i > 0 && i < R && j > 0 && j < R) return sf.interiorOffset + (j - 1) * (R - 1) + (i - 1);
    // On an edge: the edge's own index and direction (edges 0, 2 along u; 1, 3 along v).
    uint32_t edge = j == 0 ? 0 : i == R ? 1 : j == R ? 2 : 3;
    uint32_t along = edge == 0 || edge == 2 ? i : j;
    if (along == 0) return sf.corners[kEdgeStart[edge]];
    if (along == R) return sf.corners[kEdgeEnd[edge]];
    return edgeGridSample(layout, sf, edge, along);
}

void gridSamples(const SampleGridLayout& layout, uint32_t subface, uint32_t* out) {
    const DisplacementSubface& sf = layout.subfaces[subface];
    const uint32_t R = sf.resolution, side = R + 1;
    for (uint32_t j = 1; j < R; ++j)
        for (uint32_t i = 1; i < R; ++i) out[j * side + i] = sf.interiorOffset + (j - 1) * (R - 1) + (i - 1);
    // Corners 0..3 at (0,0) (R,0) (R,R) (0,R); edges 0 and 2 along rows 0 and R, 1 and 3 along
    // columns R and 0.
    out[0] = sf.corners[0], out[R] = sf.corners[1], out[R * side + R] = sf.corners[2], out[R * side] = sf.corners[3];
    for (uint32_t k = 1; k < R; ++k) {
        out[k] = edgeGridSample(layout, sf, 0, k);
        out[k * side + R] = edgeGridSample(layout, sf, 1, k);
        out[R * side + k] = edgeGridSample(layout, sf, 2, k);
        out[k * side] = edgeGridSample(layout, sf, 3, k);
    }
}

namespace {

// evaluateSampleGrids's formula; `G(i, j)` gives grid point (i, j)'s value. Both callers
// run these same operations, so they get the same bits.
template <class Grid>
DisplacementValue evaluateOnGrid(const SampleGridLayout& layout, const std::vector<float>& samples,
                                 const DisplacementSubface& sf, float u, float v, const Grid& G) {
    u = std::clamp(u, 0.0f, 1.0f);
    v = std::clamp(v, 0.0f, 1.0f);
    const uint32_t R = sf.resolution;
    const float Rf = float(R);
    const DisplacementCell cell = displacementCell(R, u, v);
    const uint32_t i = cell.i, j = cell.j;
    const float fx = cell.fx, fy = cell.fy;
    const float g00 = G(i, j), g10 = G(i + 1, j), g01 = G(i, j + 1), g11 = G(i + 1, j + 1);

    DisplacementValue out = bilinearDisplacement(g00, g10, g01, g11, cell, Rf);

    // Boundary strips of edges finer than the grid: (E - L) fading over one cell.
    auto finer = [&](uint32_t e) { return (sf.edges[e].flags & kEdgeFiner) != 0; };
    if (j == 0 && finer(0)) {
        DisplacementValue E = edgeValue(layout, samples, sf.edges[0], u, false);
        float delta = E.value - lerp(g00, g10, fx), w = 1.0f - fy;
        out.value += w * delta;
        out.du += w * (E.du - Rf * (g10 - g00));
        out.dv -= Rf * delta;
    }
    if (j == R - 1 && finer(2)) {
        DisplacementValue E = edgeValue(layout, samples, sf.edges[2], u, false);
        float delta = E.value - lerp(g01, g11, fx), w = fy;
        out.value += w * delta;
        out.du += w * (E.du - Rf * (g11 - g01));
        out.dv += Rf * delta;
    }
    if (i == 0 && finer(3)) {
        DisplacementValue E = edgeValue(layout, samples, sf.edges[3], v, false);
        float delta = E.value - lerp(g00, g01, fy), w = 1.0f - fx;
        out.value += w * delta;
        out.dv += w * (E.du - Rf * (g01 - g00));
        out.du -= Rf * delta;
    }
    if (i == R - 1 && finer(1)) {
        DisplacementValue E = edgeValue(layout, samples, sf.edges[1], v, false);
        float delta = E.value - lerp(g10, g11, fy), w = fx;
        out.value += w * delta;
        out.dv += w * (E.du - Rf * (g11 - g10));
        out.du += Rf * delta;
    }

    // On an edge the value comes from the shared edge samples alone.
    if (v == 0.0f) out.value = edgeValue(layout, samples, sf.edges[0], u, true).value;
    else if (u == 1.0f) out.value = edgeValue(layout, samples, sf.edges[1], v, true).value;
    else if (v == 1.0f) out.value = edgeValue(layout, samples, sf.edges[2], u, true).value;
    else if (u == 0.0f) out.value = edgeValue(layout, samples, sf.edges[3], v, true).value;
    return out;
}

}  // namespace

DisplacementValue evaluateSampleGrids(const SampleGrids& d, uint32_t subface, float u, float v) {
    return evaluateOnGrid(d.layout, d.samples, d.layout.subfaces[subface], u, v,
                          [&](uint32_t i, uint32_t j) { return d.samples[gridSample(d.layout, subface, i, j)]; });
}

bool SampleGrids::operator==(const SampleGrids& o) const {
    if (!(layout == o.layout) || samples != o.samples) return false;
    if (mask.size() == o.mask.size()) return mask == o.mask;
    const std::vector<float>& other = mask.empty() ? o.mask : mask;
    if (!mask.empty() && !o.mask.empty()) return false;
    return std::all_of(other.begin(), other.end(), [](float m) { return m == 0.0f; });
}

}  // namespace qp
