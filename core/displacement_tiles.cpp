#include "displacement_tiles.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <optional>
#include <utility>

namespace qp {

namespace {

// Cell (i, j) of an n-cell tile next to its edge e, at index m along the edge (the edge's own
// direction: u on edges 0 and 2, v on edges 1 and 3).
std::pair<int, int> cellNextTo(uint32_t e, uint32_t n, int m) {
    switch (e) {
    case 0: return {m, 0};
    case 1: return {int(n) - 1, m};
    case 2: return {m, int(n) - 1};
    default: return {0, m};
    }
}

// The overlap coefficient across edge e at index m along it (-1 and n are the padded corners).
std::pair<int, int> overlapAcross(uint32_t e, uint32_t n, int m) {
    switch (e) {
    case 0: return {m, -1};
    case 1: return {int(n), m};
    case 2: return {m, int(n)};
    default: return {-1, m};
    }
}

// The two edges at corner k, and whether the corner is the edge's start.
struct CornerEdge {
    uint32_t edge;
    bool atStart;
};
constexpr CornerEdge kCornerEdges[4][2] = {{{0, true}, {3, true}}, {{0, false}, {1, true}},
                                           {{1, false}, {2, false}}, {{2, true}, {3, false}}};
constexpr int kPaddedCorner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};  // -1: before 0, 1: after n - 1

std::pair<int, int> paddedCorner(uint32_t k, uint32_t n) {
    return {kPaddedCorner[k][0] < 0 ? -1 : int(n), kPaddedCorner[k][1] < 0 ? -1 : int(n)};
}
std::pair<int, int> ownCornerCell(uint32_t k, uint32_t n) {
    return {kPaddedCorner[k][0] < 0 ? 0 : int(n) - 1, kPaddedCorner[k][1] < 0 ? 0 : int(n) - 1};
}

// Union-find over coefficients.
struct Sets {
    std::vector<uint32_t> parent;
    explicit Sets(uint32_t count) : parent(count) {
        for (uint32_t i = 0; i < count; ++i) parent[i] = i;
    }
    uint32_t find(uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    void unite(uint32_t a, uint32_t b) {
        a = find(a), b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
};

// The corners of every tile around one point (a cage vertex, an edge midpoint or an n-gon centre).
struct CornerGroup {
    uint32_t point;
    std::vector<std::pair<uint32_t, uint32_t>> corners;  // (tile, corner)
};

class CornerLinks {
public:
    CornerLinks(const DisplacementLayout& adjacency, const TileLayout& tiles, const TileAdjacency& crossing, Sets& sets)
        : adjacency_(adjacency), tiles_(tiles), crossing_(crossing), sets_(sets) {}

    // Links every padded corner of the group to its source, or makes the group one shared value.
    void link(const CornerGroup& group, uint32_t tilesThroughPoint) {
        if (linkRegular(group, tilesThroughPoint)) return;
        const auto [t0, k0] = group.corners.front();
        const uint32_t first = ownCorner(t0, k0);
        for (auto [t, k] : group.corners) {
            sets_.unite(first, ownCorner(t, k));
            sets_.unite(first, padded(t, k));
        }
        for (auto [t, k] : group.corners) shared_.push_back({ownCorner(t, k), uint64_t(t) << 2 | k});
    }

    // Per own corner cell of a shared group, its (tile, corner): the home's site is chosen later.
    const std::vector<std::pair<uint32_t, uint64_t>>& sharedCells() const { return shared_; }

private:
    uint32_t index(uint32_t t, std::pair<int, int> ij) const { return tiles_.index(t, ij.first, ij.second); }
    uint32_t ownCorner(uint32_t t, uint32_t k) const { return index(t, ownCornerCell(k, tiles_.tiles[t].cells)); }
    uint32_t padded(uint32_t t, uint32_t k) const { return index(t, paddedCorner(k, tiles_.tiles[t].cells)); }
    int alongAt(uint32_t t, const CornerEdge& ce) const { return ce.atStart ? 0 : int(tiles_.tiles[t].cells) - 1; }

    // The corner of `tile` at `point`, if it has one.
    std::optional<uint32_t> cornerAt(uint32_t tile, uint32_t point) const {
        for (uint32_t k = 0; k < 4; ++k)
            if (adjacency_.subfaces[tile].corners[k] == point) return k;
        return std::nullopt;
    }

    // The cell diagonally across corner k of t, reached by crossing its edge `which` first.
    std::optional<uint32_t> diagonal(uint32_t t, uint32_t k, uint32_t which, uint32_t point) const {
        const CornerEdge ce = kCornerEdges[k][which];
        const std::optional<TileEdgeCell> first = crossing_.across(t, ce.edge, alongAt(t, ce));
        if (!first) return std::nullopt;
        const uint32_t n1 = tiles_.tiles[first->tile].cells;
        if (const std::optional<uint32_t> k1 = cornerAt(first->tile, point)) {
            const CornerEdge* other = nullptr;
            for (const CornerEdge& e : kCornerEdges[*k1])
                if (e.edge != first->edge) other = &e;
            if (!other) return std::nullopt;
            const std::optional<TileEdgeCell> second = crossing_.across(first->tile, other->edge, alongAt(first->tile, *other));
            if (!second || second->tile == t) return std::nullopt;
            return index(second->tile, cellNextTo(second->edge, tiles_.tiles[second->tile].cells, second->along));
        }
        // The point lies inside the neighbour's edge (a split cage edge's midpoint): the cell
        // beyond it along that edge.
        const int half = int(n1 / 2);
        if (first->along != half - 1 && first->along != half) return std::nullopt;
        return index(first->tile, cellNextTo(first->edge, n1, first->along == half - 1 ? half : half - 1));
    }

    bool linkRegular(const CornerGroup& group, uint32_t tilesThroughPoint) {
        const size_t count = group.corners.size();
        uint32_t failures = 0;
        for (auto [t, k] : group.corners)
            for (const CornerEdge& ce : kCornerEdges[k])
                if (!crossing_.across(t, ce.edge, alongAt(t, ce))) ++failures;
        std::vector<std::pair<uint32_t, uint32_t>> links;  // (padded corner, source cell)
        if (failures == 0 && ((count == 4 && tilesThroughPoint == 0) || (count == 2 && tilesThroughPoint == 1))) {
            for (auto [t, k] : group.corners) {
                const std::optional<uint32_t> a = diagonal(t, k, 0, group.point), b = diagonal(t, k, 1, group.point);
                if (!a || !b || *a != *b) return false;
                links.push_back({padded(t, k), *a});
            }
        } else if (tilesThroughPoint == 0 && count == 1 && failures == 2) {
            auto [t, k] = group.corners.front();
            links.push_back({padded(t, k), ownCorner(t, k)});  // mirrored across both boundary edges
        } else if (tilesThroughPoint == 0 && count == 2 && failures == 2) {
            // Two tiles along one edge, each with the boundary on its other edge: mirrored across
            // the boundary, the padded corner shows the neighbour's corner cell.
            for (auto [t, k] : group.corners) {
                std::optional<TileEdgeCell> across;
                uint32_t crossed = 0;
                for (const CornerEdge& ce : kCornerEdges[k])
                    if (auto c = crossing_.across(t, ce.edge, alongAt(t, ce))) across = c, ++crossed;
                if (crossed != 1 || !cornerAt(across->tile, group.point)) return false;
                links.push_back({padded(t, k), index(across->tile, cellNextTo(across->edge, tiles_.tiles[across->tile].cells,
                                                                               across->along))});
            }
        } else {
            return false;
        }
        for (auto [from, to] : links) sets_.unite(from, to);
        return true;
    }

    const DisplacementLayout& adjacency_;
    const TileLayout& tiles_;
    const TileAdjacency& crossing_;
    Sets& sets_;
    std::vector<std::pair<uint32_t, uint64_t>> shared_;
};

// Quadratic uniform B-spline weights of the span at fraction f, and their derivatives.
struct SpanWeights {
    float w[3], d[3];
};
inline SpanWeights spanWeights(float f) {
    const float g = 1.0f - f;
    return {{0.5f * g * g, 0.5f + f * g, 0.5f * f * f}, {-g, 1.0f - 2.0f * f, f}};
}

}  // namespace

TileAdjacency::TileAdjacency(const DisplacementLayout& adjacency, const TileLayout& tiles) : adjacency_(adjacency), tiles_(tiles) {
    const size_t segments = adjacency.segments.size();
    refOffsets_.assign(segments + 1, 0);
    forEachReference([&](uint32_t segment, uint32_t) { ++refOffsets_[segment + 1]; });
    for (size_t s = 0; s < segments; ++s) refOffsets_[s + 1] += refOffsets_[s];
    refs_.resize(refOffsets_.back());
    std::vector<uint32_t> fill(refOffsets_.begin(), refOffsets_.end() - 1);
    forEachReference([&](uint32_t segment, uint32_t tileEdge) { refs_[fill[segment]++] = tileEdge; });
}

template <class F>
void TileAdjacency::forEachReference(const F& f) const {
    for (uint32_t t = 0; t < adjacency_.subfaces.size(); ++t)
        for (uint32_t e = 0; e < 4; ++e) {
            const DisplacementEdge& edge = adjacency_.subfaces[t].edges[e];
            f(edge.segment, 4 * t + e);
            if (edge.flags & kEdgeSplit) f(edge.secondHalf, 4 * t + e);
        }
}

std::optional<TileEdgeCell> TileAdjacency::across(uint32_t tile, uint32_t e, int m) const {
    const DisplacementEdge& edge = adjacency_.subfaces[tile].edges[e];
    const uint32_t n = tiles_.tiles[tile].cells;
    uint32_t segment = edge.segment, cell = uint32_t(m), cells = n;
    if (edge.flags & kEdgeSplit) {
        cells = n / 2;
        if (2 * uint32_t(m) >= n) segment = edge.secondHalf, cell = n - 1 - uint32_t(m);
    } else if (edge.flags & kEdgeReversed) {
        cell = n - 1 - uint32_t(m);
    }
    if (refOffsets_[segment + 1] - refOffsets_[segment] != 2) return std::nullopt;
    const uint32_t self = 4 * tile + e;
    const uint32_t a = refs_[refOffsets_[segment]], b = refs_[refOffsets_[segment] + 1];
    if ((a != self && b != self) || a == b) return std::nullopt;
    const uint32_t other = a == self ? b : a;
    const uint32_t tile2 = other / 4, e2 = other % 4, n2 = tiles_.tiles[tile2].cells;
    const DisplacementEdge& edge2 = adjacency_.subfaces[tile2].edges[e2];
    int along = 0;
    if (edge2.flags & kEdgeSplit) {
        if (2 * cells != n2) return std::nullopt;
        along = edge2.segment == segment ? int(cell) : int(n2 - 1 - cell);
    } else {
        if (cells != n2) return std::nullopt;
        along = edge2.flags & kEdgeReversed ? int(n2 - 1 - cell) : int(cell);
    }
    return TileEdgeCell{tile2, e2, along};
}

uint32_t minimumTileResolution(const DisplacementLayout& adjacency) {
    for (const DisplacementSubface& s : adjacency.subfaces)
        if (s.corners[2] >= adjacency.vertexCount + adjacency.edgeCount) return 2;  // an n-gon's centre
    return 1;
}

TileLayout buildTileLayout(const DisplacementLayout& adjacency, uint32_t resolution) {
    assert(isPowerOfTwo(resolution) && resolution >= minimumTileResolution(adjacency));
    TileLayout layout;
    layout.resolution = resolution;
    const uint32_t centres = adjacency.vertexCount + adjacency.edgeCount;
    uint32_t offset = 0;
    for (const DisplacementSubface& s : adjacency.subfaces) {
        // An n-gon sub-face has the n-gon's centre at its corner 2.
        const uint32_t cells = s.corners[2] >= centres ? resolution / 2 : resolution;
        layout.tiles.push_back({cells, offset, {0, 0}});
        offset += (cells + 2) * (cells + 2);
    }
    const uint32_t count = offset;
    std::vector<uint8_t> own(count, 0);
    for (uint32_t t = 0; t < layout.tiles.size(); ++t)
        for (uint32_t j = 0; j < layout.tiles[t].cells; ++j)
            for (uint32_t i = 0; i < layout.tiles[t].cells; ++i) own[layout.index(t, int(i), int(j))] = 1;

    Sets sets(count);
    const TileAdjacency crossing(adjacency, layout);
    // Edges: each overlap shows the neighbour's cell, or mirrors the tile's own.
    for (uint32_t t = 0; t < layout.tiles.size(); ++t) {
        const uint32_t n = layout.tiles[t].cells;
        for (uint32_t e = 0; e < 4; ++e)
            for (int m = 0; m < int(n); ++m) {
                const auto [i, j] = overlapAcross(e, n, m);
                const std::optional<TileEdgeCell> c = crossing.across(t, e, m);
                const auto [ci, cj] = c ? cellNextTo(c->edge, layout.tiles[c->tile].cells, c->along) : cellNextTo(e, n, m);
                sets.unite(layout.index(t, i, j), layout.index(c ? c->tile : t, ci, cj));
            }
    }
    // Corners, grouped by the point they lie at.
    std::vector<std::pair<uint32_t, uint32_t>> cornersByPoint;  // (point, 4 * tile + corner)
    for (uint32_t t = 0; t < adjacency.subfaces.size(); ++t)
        for (uint32_t k = 0; k < 4; ++k) cornersByPoint.push_back({adjacency.subfaces[t].corners[k], 4 * t + k});
    std::sort(cornersByPoint.begin(), cornersByPoint.end());
    std::vector<uint32_t> tilesThrough(adjacency.pointCount, 0);  // quads whose split edge has this midpoint
    for (const DisplacementSubface& s : adjacency.subfaces)
        for (const DisplacementEdge& e : s.edges)
            if (e.flags & kEdgeSplit) ++tilesThrough[adjacency.segments[e.segment].pointB];
    CornerLinks links(adjacency, layout, crossing, sets);
    layout.sharedCorner.assign(count, kNoTileCorner);
    for (size_t a = 0; a < cornersByPoint.size();) {
        CornerGroup group{cornersByPoint[a].first, {}};
        size_t b = a;
        for (; b < cornersByPoint.size() && cornersByPoint[b].first == group.point; ++b)
            group.corners.push_back({cornersByPoint[b].second / 4, cornersByPoint[b].second % 4});
        links.link(group, tilesThrough[group.point]);
        a = b;
    }

    // Homes: the lowest own cell of each set.
    std::vector<uint32_t> homeOfRoot(count, UINT32_MAX);
    for (uint32_t x = 0; x < count; ++x)
        if (own[x] && homeOfRoot[sets.find(x)] == UINT32_MAX) homeOfRoot[sets.find(x)] = x;
    layout.home.resize(count);
    for (uint32_t x = 0; x < count; ++x) {
        layout.home[x] = homeOfRoot[sets.find(x)];
        assert(layout.home[x] != UINT32_MAX && "every coefficient is linked to an own cell");
    }
    for (auto [cell, tileCorner] : links.sharedCells())
        if (layout.home[cell] == cell) layout.sharedCorner[cell] = tileCorner;

    layout.copyOffsets.assign(count + 1, 0);
    for (uint32_t x = 0; x < count; ++x)
        if (layout.home[x] != x) ++layout.copyOffsets[layout.home[x] + 1];
    for (uint32_t x = 0; x < count; ++x) layout.copyOffsets[x + 1] += layout.copyOffsets[x];
    layout.copies.resize(layout.copyOffsets.back());
    std::vector<uint32_t> fill(layout.copyOffsets.begin(), layout.copyOffsets.end() - 1);
    for (uint32_t x = 0; x < count; ++x)
        if (layout.home[x] != x) layout.copies[fill[layout.home[x]]++] = x;
    return layout;
}

DisplacementValue evaluateTile(const TileLayout& layout, std::span<const float> coefficients, uint32_t subface, float u,
                               float v) {
    const DisplacementTile& tile = layout.tiles[subface];
    const uint32_t n = tile.cells;
    const float x = std::clamp(u, 0.0f, 1.0f) * float(n), y = std::clamp(v, 0.0f, 1.0f) * float(n);
    const uint32_t i = std::min(uint32_t(x), n - 1), j = std::min(uint32_t(y), n - 1);
    const SpanWeights wu = spanWeights(x - float(i)), wv = spanWeights(y - float(j));
    // Span (i, j) reads cells i-1..i+1 x j-1..j+1: padded columns i..i+2, rows j..j+2.
    const float* c = coefficients.data() + tile.offset + j * (n + 2) + i;
    DisplacementValue out;
    for (uint32_t b = 0; b < 3; ++b) {
        const float* row = c + b * (n + 2);
        const float along = wu.w[0] * row[0] + wu.w[1] * row[1] + wu.w[2] * row[2];
        const float slope = wu.d[0] * row[0] + wu.d[1] * row[1] + wu.d[2] * row[2];
        out.value += wv.w[b] * along;
        out.du += wv.w[b] * slope;
        out.dv += wv.d[b] * along;
    }
    out.du *= float(n);
    out.dv *= float(n);
    return out;
}

namespace {

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

}  // namespace

float evaluateTileValue(const TileLayout& layout, const DisplacementLayout& adjacency, std::span<const float> coefficients,
                        uint32_t subface, float u, float v) {
    u = std::clamp(u, 0.0f, 1.0f);
    v = std::clamp(v, 0.0f, 1.0f);
    const bool onEdge = u == 0.0f || u == 1.0f || v == 0.0f || v == 1.0f;
    if (!onEdge) return evaluateTile(layout, coefficients, subface, u, v).value;
    const DisplacementTile& tile = layout.tiles[subface];
    const uint32_t n = tile.cells;
    auto at = [&](int i, int j) { return coefficients[layout.index(subface, i, j)]; };
    // Which edge, and the parameter along it in its own direction.
    const uint32_t e = v == 0.0f ? 0 : u == 1.0f ? 1 : v == 1.0f ? 2 : 3;
    const float t = e == 0 || e == 2 ? u : v;
    const DisplacementEdge& edge = adjacency.subfaces[subface].edges[e];
    const bool split = edge.flags & kEdgeSplit;
    // The segment the point is on: cells along it and the map from its canonical cell index to
    // the edge's own. Canonical directions run from the lower point id: a split edge's halves
    // from its corners (vertices come before midpoints), a whole edge as its flag says.
    const bool secondHalf = split && t > 0.5f;
    const uint32_t cells = split ? n / 2 : n;
    const bool reversed = split ? secondHalf : bool(edge.flags & kEdgeReversed);
    const float local = split ? (secondHalf ? 2.0f * (1.0f - t) : 2.0f * t) : t;
    const float canonical = snapped(reversed && !split ? 1.0f - local : local);
    const float x = canonical * float(cells);
    auto ownAlong = [&](int k) { return secondHalf ? int(n) - 1 - k : (reversed ? int(cells) - 1 - k : k); };
    if (x == std::floor(x)) {  // a knot crossing: the four cells meeting there, added sorted
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

void propagateCopies(const TileLayout& layout, std::span<float> coefficients, std::span<const uint32_t> homes) {
    for (uint32_t x : homes) {
        const uint32_t h = layout.home[x];
        for (uint32_t k = layout.copyOffsets[h]; k < layout.copyOffsets[h + 1]; ++k) coefficients[layout.copies[k]] = coefficients[h];
    }
}

void propagateAllCopies(const TileLayout& layout, std::span<float> coefficients) {
    for (uint32_t x = 0; x < layout.coefficientCount(); ++x)
        if (layout.home[x] != x) coefficients[x] = coefficients[layout.home[x]];
}

uint32_t tileOfCoefficient(const TileLayout& layout, uint32_t coefficient) {
    const auto after = std::upper_bound(layout.tiles.begin(), layout.tiles.end(), coefficient,
                                        [](uint32_t x, const DisplacementTile& t) { return x < t.offset; });
    return uint32_t(after - layout.tiles.begin()) - 1;
}

std::vector<uint32_t> tilesReadingHomes(const TileLayout& layout, std::span<const uint32_t> homes) {
    std::vector<uint32_t> tiles;
    for (uint32_t x : homes) {
        const uint32_t h = layout.home[x];
        tiles.push_back(tileOfCoefficient(layout, h));
        for (uint32_t k = layout.copyOffsets[h]; k < layout.copyOffsets[h + 1]; ++k)
            tiles.push_back(tileOfCoefficient(layout, layout.copies[k]));
    }
    std::sort(tiles.begin(), tiles.end());
    tiles.erase(std::unique(tiles.begin(), tiles.end()), tiles.end());
    return tiles;
}

CoefficientSite homeSite(const TileLayout& layout, uint32_t home) {
    if (layout.sharedCorner[home] != kNoTileCorner) {
        const uint32_t tile = uint32_t(layout.sharedCorner[home] >> 2), k = uint32_t(layout.sharedCorner[home] & 3);
        return {tile, kCornerU[k], kCornerV[k]};
    }
    const uint32_t tile = tileOfCoefficient(layout, home);
    const uint32_t n = layout.tiles[tile].cells, local = home - layout.tiles[tile].offset;
    const int i = int(local % (n + 2)) - 1, j = int(local / (n + 2)) - 1;
    return {tile, (float(i) + 0.5f) / float(n), (float(j) + 0.5f) / float(n)};
}

std::vector<float> fitTiles(const TileLayout& layout, const std::function<float(uint32_t, float, float)>& f) {
    std::vector<float> coefficients(layout.coefficientCount(), 0.0f);
    constexpr float kWeights[3] = {-0.5f, 2.0f, -0.5f};
    for (uint32_t x = 0; x < layout.coefficientCount(); ++x) {
        if (layout.home[x] != x) continue;
        const CoefficientSite site = homeSite(layout, x);
        if (layout.sharedCorner[x] != kNoTileCorner) {
            coefficients[x] = f(site.subface, site.u, site.v);
            continue;
        }
        const float h = 0.5f / float(layout.tiles[site.subface].cells);
        double sum = 0.0;
        for (int b = 0; b < 3; ++b)
            for (int a = 0; a < 3; ++a)
                sum += double(kWeights[a] * kWeights[b]) * f(site.subface, site.u + float(a - 1) * h, site.v + float(b - 1) * h);
        coefficients[x] = float(sum);
    }
    propagateAllCopies(layout, coefficients);
    return coefficients;
}

std::vector<float> fitSampleGrids(const TileLayout& layout, const Displacement& grids) {
    return fitTiles(layout, [&](uint32_t subface, float u, float v) { return evaluateDisplacement(grids, subface, u, v).value; });
}

}  // namespace qp
