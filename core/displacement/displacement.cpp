#include "displacement/displacement.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>

namespace qp {

namespace {

// Quadratic uniform B-spline weights of the span at fraction f, and their derivatives.
struct SpanWeights {
    float w[3], d[3];
};
inline SpanWeights spanWeights(float f) {
    const float g = 1.0f - f;
    return {{0.5f * g * g, 0.5f + f * g, 0.5f * f * f}, {-g, 1.0f - 2.0f * f, f}};
}

// The tile's B-spline at (u, v) in [0, 1]^2 from its padded block, read through at(i, j) with
// -1 <= i, j <= n.
template <class At>
DisplacementValue splineAt(uint32_t n, float u, float v, const At& at) {
    const float x = u * float(n), y = v * float(n);
    const int i = int(std::min(uint32_t(x), n - 1)), j = int(std::min(uint32_t(y), n - 1));
    const SpanWeights wu = spanWeights(x - float(i)), wv = spanWeights(y - float(j));
    // Span (i, j) reads cells i-1..i+1 x j-1..j+1.
    DisplacementValue out;
    for (int b = 0; b < 3; ++b) {
        const float c0 = at(i - 1, j - 1 + b), c1 = at(i, j - 1 + b), c2 = at(i + 1, j - 1 + b);
        const float along = wu.w[0] * c0 + wu.w[1] * c1 + wu.w[2] * c2;
        const float slope = wu.d[0] * c0 + wu.d[1] * c1 + wu.d[2] * c2;
        out.value += wv.w[b] * along;
        out.du += wv.w[b] * slope;
        out.dv += wv.d[b] * along;
    }
    out.du *= float(n);
    out.dv *= float(n);
    return out;
}

// Padded (i, j) of the strip along tile edge e: row 0 is the tile's own cell next to the edge,
// row 1 the overlap across it; `along` in the edge's own direction, -1 .. n.
std::pair<int, int> stripCell(uint32_t e, uint32_t n, int along, int row) {
    const int inner = row == 0 ? 0 : -1, outer = row == 0 ? int(n) - 1 : int(n);
    switch (e) {
    case 0: return {along, inner};
    case 1: return {outer, along};
    case 2: return {along, outer};
    default: return {inner, along};
    }
}

float snapped(float t) {
    constexpr float kGrid = 16384.0f;  // 2^14: every parameter i / n, n <= 64, lies on it
    return std::round(std::clamp(t, 0.0f, 1.0f) * kGrid) / kGrid;
}

// D's value on edge e of a tile at its own parameter t, the same bits from both sides (see the
// header): pair sums in the segment's canonical direction, sorted four-sample means at knots.
template <class At>
float edgeValue(const DisplacementTile& tile, uint32_t e, float t, const At& at) {
    const uint32_t n = tile.cells, flags = tile.edgeFlags >> (4 * e) & 0xF;
    const bool split = flags & kEdgeSplit;
    // Canonical directions run from the lower point id: a split edge's halves from its corners
    // (vertices come before midpoints), a whole edge as its flag says.
    const bool secondHalf = split && t > 0.5f;
    const uint32_t cells = split ? n / 2 : n;
    const bool reversed = split ? secondHalf : bool(flags & kEdgeReversed);
    const float local = split ? (secondHalf ? 2.0f * (1.0f - t) : 2.0f * t) : t;
    const float canonical = snapped(reversed && !split ? 1.0f - local : local);
    const float x = canonical * float(cells);
    auto ownAlong = [&](int k) { return secondHalf ? int(n) - 1 - k : (reversed ? int(cells) - 1 - k : k); };
    if (x == std::floor(x)) {  // a knot crossing: the four samples meeting there, added sorted
        const int k = int(x);
        float four[4];
        for (int r = 0; r < 2; ++r)
            for (int side = 0; side < 2; ++side) {
                const auto [i, j] = stripCell(e, n, ownAlong(k - 1 + side), r);
                four[2 * r + side] = at(i, j);
            }
        std::sort(four, four + 4);
        return 0.25f * ((four[0] + four[1]) + (four[2] + four[3]));
    }
    const int k = int(x);
    const SpanWeights w = spanWeights(x - float(k));
    float value = 0.0f;
    for (int b = 0; b < 3; ++b) {
        const int along = ownAlong(k - 1 + b);
        const auto [i0, j0] = stripCell(e, n, along, 0);
        const auto [i1, j1] = stripCell(e, n, along, 1);
        value += w.w[b] * (0.5f * (at(i0, j0) + at(i1, j1)));
    }
    return value;
}

template <class At>
DisplacementValue evaluateTile(const DisplacementTile& tile, float u, float v, const At& at) {
    u = std::clamp(u, 0.0f, 1.0f);
    v = std::clamp(v, 0.0f, 1.0f);
    DisplacementValue out = splineAt(tile.cells, u, v, at);
    if (v == 0.0f) out.value = edgeValue(tile, 0, u, at);
    else if (u == 1.0f) out.value = edgeValue(tile, 1, v, at);
    else if (v == 1.0f) out.value = edgeValue(tile, 2, u, at);
    else if (u == 0.0f) out.value = edgeValue(tile, 3, v, at);
    return out;
}

}  // namespace

bool DisplacementLayout::operator==(const DisplacementLayout& o) const {
    auto bytesEqual = [](const auto& a, const auto& b) {
        return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](const auto& x, const auto& y) {
                   return std::memcmp(&x, &y, sizeof x) == 0;
               });
    };
    return resolution == o.resolution && sampleCount == o.sampleCount && adjacency == o.adjacency &&
           bytesEqual(tiles, o.tiles) && padded == o.padded && bytesEqual(homes, o.homes);
}

bool Displacement::operator==(const Displacement& o) const {
    if (!(layout == o.layout) || samples != o.samples) return false;
    if (mask.size() == o.mask.size()) return mask == o.mask;
    const std::vector<float>& other = mask.empty() ? o.mask : mask;
    if (!mask.empty() && !o.mask.empty()) return false;
    return std::all_of(other.begin(), other.end(), [](float m) { return m == 0.0f; });
}

Displacement makeDisplacement(const Cage& cage, const Topology& topology, uint32_t resolution) {
    Displacement d;
    d.layout = buildDisplacementLayout(cage, topology, resolution);
    d.samples.assign(d.layout.sampleCount, 0.0f);
    return d;
}

DisplacementValue evaluateDisplacement(const Displacement& d, uint32_t subface, float u, float v) {
    const DisplacementLayout& layout = d.layout;
    return evaluateTile(layout.tiles[subface], u, v,
                        [&](int i, int j) { return d.samples[layout.sampleAt(subface, i, j)]; });
}

SubfaceDisplacement::SubfaceDisplacement(const Displacement& d, uint32_t subface)
    : displacement_(d), subface_(subface), cells_(d.layout.tiles[subface].cells) {
    const uint32_t count = (cells_ + 2) * (cells_ + 2);
    const uint32_t* padded = d.layout.padded.data() + d.layout.tiles[subface].offset;
    for (uint32_t k = 0; k < count; ++k) block_[k] = d.samples[padded[k]];
}

DisplacementValue SubfaceDisplacement::evaluate(float u, float v) const {
    const uint32_t side = cells_ + 2;
    return evaluateTile(displacement_.layout.tiles[subface_], u, v,
                        [&](int i, int j) { return block_[uint32_t(j + 1) * side + uint32_t(i + 1)]; });
}

DisplacementValue SubfaceDisplacement::inside(float u, float v) const {
    const uint32_t side = cells_ + 2;
    return splineAt(cells_, u, v, [&](int i, int j) { return block_[uint32_t(j + 1) * side + uint32_t(i + 1)]; });
}

SampleSite sampleSite(const DisplacementLayout& layout, uint32_t sample) {
    const SampleHome& home = layout.homes[sample];
    if (home.corner >= 0) return {home.tile, kCornerU[home.corner], kCornerV[home.corner]};
    const float n = float(layout.tiles[home.tile].cells);
    return {home.tile, (float(home.i) + 0.5f) / n, (float(home.j) + 0.5f) / n};
}

std::vector<float> fitSamples(const DisplacementLayout& layout, const std::function<float(uint32_t, float, float)>& f) {
    std::vector<float> samples(layout.sampleCount, 0.0f);
    constexpr float kWeights[3] = {-0.5f, 2.0f, -0.5f};
    for (uint32_t s = 0; s < layout.sampleCount; ++s) {
        const SampleSite site = sampleSite(layout, s);
        if (layout.homes[s].corner >= 0) {
            samples[s] = f(site.subface, site.u, site.v);
            continue;
        }
        const float h = 0.5f / float(layout.tiles[site.subface].cells);
        double sum = 0.0;
        for (int b = 0; b < 3; ++b)
            for (int a = 0; a < 3; ++a)
                sum += double(kWeights[a] * kWeights[b]) * f(site.subface, site.u + float(a - 1) * h, site.v + float(b - 1) * h);
        samples[s] = float(sum);
    }
    return samples;
}

Displacement resampleDisplacement(const Displacement& old, uint32_t resolution) {
    Displacement out;
    out.layout = withResolution(old.layout, resolution);
    if (out.layout.resolution == old.layout.resolution) return old;
    out.samples = fitSamples(out.layout, [&](uint32_t s, float u, float v) { return evaluateDisplacement(old, s, u, v).value; });
    if (old.hasMask()) {
        Displacement mask = old;
        mask.samples = old.mask;
        out.mask = fitSamples(out.layout, [&](uint32_t s, float u, float v) { return evaluateDisplacement(mask, s, u, v).value; });
        for (float& m : out.mask) m = std::clamp(m, 0.0f, 1.0f) + 0.0f;
    }
    return out;
}

Displacement fitSampleGrids(const DisplacementLayout& layout, const SampleGrids& grids) {
    Displacement out;
    out.layout = layout;
    out.samples = fitSamples(layout, [&](uint32_t s, float u, float v) { return evaluateSampleGrids(grids, s, u, v).value; });
    if (grids.hasMask()) {
        SampleGrids mask = grids;
        mask.samples = grids.mask;
        out.mask = fitSamples(layout, [&](uint32_t s, float u, float v) { return evaluateSampleGrids(mask, s, u, v).value; });
        for (float& m : out.mask) m = std::clamp(m, 0.0f, 1.0f) + 0.0f;
    }
    return out;
}

uint32_t requiredTessellationFactor(const DisplacementLayout& layout, uint32_t subface) {
    return layout.tiles[subface].cells;
}

}  // namespace qp
