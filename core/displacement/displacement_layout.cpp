#include "displacement/displacement.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <optional>
#include <utility>

namespace qp {

namespace {

// Across tile edges: the cell of the neighbour next to a tile edge's cell (0 <= along < n), through
// the segments the sub-faces share; nothing on a boundary, a non-manifold edge or where the cells
// differ in size. `along` counts in the edge's own direction (u on edges 0 and 2, v on 1 and 3).
struct TileEdgeCell {
    uint32_t tile, edge;
    int along;
};
class TileAdjacency {
public:
    TileAdjacency(const SampleGridLayout& adjacency, const DisplacementLayout& tiles);
    std::optional<TileEdgeCell> across(uint32_t tile, uint32_t edge, int along) const;

private:
    template <class F>
    void forEachReference(const F& f) const;

    const SampleGridLayout& adjacency_;
    const DisplacementLayout& tiles_;
    std::vector<uint32_t> refOffsets_, refs_;  // CSR: segment -> 4 * tile + edge
};

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
    CornerLinks(const SampleGridLayout& adjacency, const DisplacementLayout& tiles, const TileAdjacency& crossing, Sets& sets)
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
    uint32_t index(uint32_t t, std::pair<int, int> ij) const { return tiles_.paddedIndex(t, ij.first, ij.second); }
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

    const SampleGridLayout& adjacency_;
    const DisplacementLayout& tiles_;
    const TileAdjacency& crossing_;
    Sets& sets_;
    std::vector<std::pair<uint32_t, uint64_t>> shared_;
};

TileAdjacency::TileAdjacency(const SampleGridLayout& adjacency, const DisplacementLayout& tiles) : adjacency_(adjacency), tiles_(tiles) {
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

uint32_t minimumTileResolution(const SampleGridLayout& adjacency) {
    for (const DisplacementSubface& s : adjacency.subfaces)
        if (s.corners[2] >= adjacency.vertexCount + adjacency.edgeCount) return 4;  // an n-gon's centre
    return 2;
}

DisplacementLayout buildTiles(const SampleGridLayout& adjacency, uint32_t resolution) {
    assert(isPowerOfTwo(resolution) && resolution >= minimumTileResolution(adjacency));
    DisplacementLayout layout;
    layout.adjacency = adjacency;
    layout.resolution = resolution;
    const uint32_t centres = adjacency.vertexCount + adjacency.edgeCount;
    uint32_t offset = 0;
    for (const DisplacementSubface& s : adjacency.subfaces) {
        // An n-gon sub-face has the n-gon's centre at its corner 2.
        const uint32_t cells = s.corners[2] >= centres ? resolution / 2 : resolution;
        uint32_t edgeFlags = 0;
        for (uint32_t e = 0; e < 4; ++e) edgeFlags |= (s.edges[e].flags & (kEdgeReversed | kEdgeSplit)) << (4 * e);
        layout.tiles.push_back({cells, offset, edgeFlags, 0});
        offset += (cells + 2) * (cells + 2);
    }
    const uint32_t count = offset;

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
                sets.unite(layout.paddedIndex(t, i, j), layout.paddedIndex(c ? c->tile : t, ci, cj));
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
    for (size_t a = 0; a < cornersByPoint.size();) {
        CornerGroup group{cornersByPoint[a].first, {}};
        size_t b = a;
        for (; b < cornersByPoint.size() && cornersByPoint[b].first == group.point; ++b)
            group.corners.push_back({cornersByPoint[b].second / 4, cornersByPoint[b].second % 4});
        links.link(group, tilesThrough[group.point]);
        a = b;
    }

    // Samples: one per set, numbered in the order of their lowest own cell.
    layout.padded.assign(count, UINT32_MAX);
    std::vector<uint32_t> sampleOfRoot(count, UINT32_MAX);
    for (uint32_t t = 0; t < layout.tiles.size(); ++t) {
        const uint32_t n = layout.tiles[t].cells;
        for (uint32_t j = 0; j < n; ++j)
            for (uint32_t i = 0; i < n; ++i) {
                const uint32_t root = sets.find(layout.paddedIndex(t, int(i), int(j)));
                if (sampleOfRoot[root] != UINT32_MAX) continue;
                sampleOfRoot[root] = uint32_t(layout.homes.size());
                layout.homes.push_back({t, int16_t(i), int16_t(j), -1});
            }
    }
    for (uint32_t x = 0; x < count; ++x) {
        layout.padded[x] = sampleOfRoot[sets.find(x)];
        assert(layout.padded[x] != UINT32_MAX && "every coefficient is linked to an own cell");
    }
    for (auto [cell, tileCorner] : links.sharedCells()) {
        SampleHome& home = layout.homes[layout.padded[cell]];
        if (home.corner >= 0) continue;
        const uint32_t tile = uint32_t(tileCorner >> 2), k = uint32_t(tileCorner & 3);
        const auto [i, j] = ownCornerCell(k, layout.tiles[tile].cells);
        home = {tile, int16_t(i), int16_t(j), int32_t(k)};
    }
    layout.sampleCount = uint32_t(layout.homes.size());
    return layout;
}

}  // namespace

uint32_t minimumDisplacementResolution(const Cage& cage) {
    for (uint32_t f = 0; f < cage.faceCount(); ++f)
        if (cage.faceSize(f) != 4) return 4;
    return 2;
}

DisplacementLayout buildDisplacementLayout(const Cage& cage, const Topology& topology, uint32_t resolution) {
    resolution = std::max(resolution, minimumDisplacementResolution(cage));
    assert(isPowerOfTwo(resolution) && resolution <= kMaxDisplacementResolution);
    return buildTiles(buildSampleGridLayout(cage, topology, 1), resolution);
}

DisplacementLayout withResolution(const DisplacementLayout& layout, uint32_t resolution) {
    return buildTiles(layout.adjacency, std::max(resolution, minimumTileResolution(layout.adjacency)));
}

}  // namespace qp
