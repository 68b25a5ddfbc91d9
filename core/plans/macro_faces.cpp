#include "plans/macro_faces.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <deque>
#include <unordered_map>

namespace qp {

namespace {

// Lattice step across cell side s (0: j - 1, 1: i + 1, 2: j + 1, 3: i - 1).
constexpr int kStepI[4] = {0, 1, 0, -1}, kStepJ[4] = {-1, 0, 1, 0};

// What the partitions read of the cage: which edges join two quads the ordinary way, and which
// vertices lines run straight through.
struct Grid {
    const Cage& cage;
    const Topology& topology;
    std::vector<uint8_t> inner;    // per edge: two quads on it, wound against each other
    std::vector<uint8_t> regular;  // per vertex: interior, four quads, four inner edges

    Grid(const Cage& c, const Topology& t) : cage(c), topology(t) {
        const uint32_t edges = t.edgeCount();
        inner.assign(edges, 0);
        for (uint32_t e = 0; e < edges; ++e) {
            if (t.edgeFaceCount(e) != 2) continue;
            const uint32_t f = t.edgeFaces[t.edgeFaceOffsets[e]], g = t.edgeFaces[t.edgeFaceOffsets[e] + 1];
            if (f == g || c.faceSize(f) != 4 || c.faceSize(g) != 4) continue;
            // Opposite winding: f runs the edge one way, g the other.
            inner[e] = edgeStart(f, localEdge(f, e)) != edgeStart(g, localEdge(g, e));
        }
        const uint32_t vertices = uint32_t(c.positions.size());
        regular.assign(vertices, 0);
        for (uint32_t v = 0; v < vertices; ++v) {
            if (t.vertexFaceCount(v) != 4 || t.vertexEdgeCount(v) != 4) continue;
            bool ok = true;
            for (uint32_t k = t.vertexEdgeOffsets[v]; k < t.vertexEdgeOffsets[v + 1]; ++k) ok = ok && inner[t.vertexEdges[k]];
            regular[v] = ok;
        }
    }

    uint32_t faceEdge(uint32_t f, uint32_t local) const { return topology.faceEdges[cage.faceOffsets[f] + local]; }
    uint32_t edgeStart(uint32_t f, uint32_t local) const { return cage.faceBegin(f)[local]; }
    uint32_t localEdge(uint32_t f, uint32_t e) const {
        for (uint32_t i = 0; i < cage.faceSize(f); ++i)
            if (faceEdge(f, i) == e) return i;
        assert(false && "the face has the edge");
        return 0;
    }
    uint32_t otherFace(uint32_t e, uint32_t f) const {
        const uint32_t a = topology.edgeFaces[topology.edgeFaceOffsets[e]];
        return a == f ? topology.edgeFaces[topology.edgeFaceOffsets[e] + 1] : a;
    }
    uint32_t otherEnd(uint32_t e, uint32_t v) const {
        const uint32_t a = topology.edgeVertices[2 * e];
        return a == v ? topology.edgeVertices[2 * e + 1] : a;
    }
    bool shareFace(uint32_t e, uint32_t c) const {
        for (uint32_t i = topology.edgeFaceOffsets[e]; i < topology.edgeFaceOffsets[e + 1]; ++i)
            for (uint32_t k = topology.edgeFaceOffsets[c]; k < topology.edgeFaceOffsets[c + 1]; ++k)
                if (topology.edgeFaces[i] == topology.edgeFaces[k]) return true;
        return false;
    }
    // The edge that continues `e` straight through regular vertex w: the one sharing no face with it.
    uint32_t straightOn(uint32_t e, uint32_t w) const {
        assert(regular[w]);
        for (uint32_t k = topology.vertexEdgeOffsets[w]; k < topology.vertexEdgeOffsets[w + 1]; ++k) {
            const uint32_t c = topology.vertexEdges[k];
            if (c != e && !shareFace(e, c)) return c;
        }
        assert(false && "a regular vertex has an opposite edge");
        return e;
    }
    bool faceIsRegular(uint32_t f) const {
        if (cage.faceSize(f) != 4) return false;
        for (uint32_t i = 0; i < 4; ++i)
            if (!regular[cage.faceBegin(f)[i]]) return false;
        return true;
    }
};

// A connected set of quads laid on the integer lattice.
struct Placed {
    std::vector<uint32_t> faces;
    bool consistent = true;
    int minI = 0, minJ = 0, maxI = 0, maxJ = 0;
};

// Lays faces on the lattice from `seed` (cell (0, 0), corner `rotation` at its origin), crossing
// only edges `crossable` allows to faces `allowed` allows. Writes each reached face's cell and
// rotation; `mark[f]` = `stamp` for reached faces (so a caller's later floods skip them).
template <class Crossable, class Allowed>
Placed placeFaces(const Grid& grid, uint32_t seed, uint32_t rotation, const Crossable& crossable, const Allowed& allowed,
                  std::vector<uint32_t>& mark, uint32_t stamp, std::vector<int>& cellI, std::vector<int>& cellJ,
                  std::vector<uint8_t>& rot) {
    Placed placed;
    std::deque<uint32_t> queue{seed};
    mark[seed] = stamp;
    cellI[seed] = 0, cellJ[seed] = 0, rot[seed] = uint8_t(rotation);
    while (!queue.empty()) {
        const uint32_t f = queue.front();
        queue.pop_front();
        placed.faces.push_back(f);
        placed.minI = std::min(placed.minI, cellI[f]), placed.maxI = std::max(placed.maxI, cellI[f]);
        placed.minJ = std::min(placed.minJ, cellJ[f]), placed.maxJ = std::max(placed.maxJ, cellJ[f]);
        for (uint32_t s = 0; s < 4; ++s) {
            const uint32_t e = grid.faceEdge(f, (rot[f] + s) & 3);
            if (!grid.inner[e] || !crossable(e)) continue;
            const uint32_t g = grid.otherFace(e, f);
            if (!allowed(g)) continue;
            const int gi = cellI[f] + kStepI[s], gj = cellJ[f] + kStepJ[s];
            const uint8_t gr = uint8_t((grid.localEdge(g, e) + 2 - s) & 3);  // g has e as its side s + 2
            if (mark[g] == stamp) {
                if (cellI[g] != gi || cellJ[g] != gj || rot[g] != gr) placed.consistent = false;
                continue;
            }
            mark[g] = stamp;
            cellI[g] = gi, cellJ[g] = gj, rot[g] = gr;
            queue.push_back(g);
        }
    }
    return placed;
}

// The placed faces as one macro face when they fill their bounding rectangle once and cells
// next to each other on the lattice share the edge between them; appended to `out`.
bool appendRectangle(const Grid& grid, const Placed& placed, const std::vector<int>& cellI, const std::vector<int>& cellJ,
                     const std::vector<uint8_t>& rot, MacroFaces& out) {
    if (!placed.consistent) return false;
    const uint32_t width = uint32_t(placed.maxI - placed.minI + 1), height = uint32_t(placed.maxJ - placed.minJ + 1);
    if (uint64_t(width) * height != placed.faces.size()) return false;
    const uint32_t first = uint32_t(out.cells.size());
    out.cells.resize(first + placed.faces.size(), MacroCell{UINT32_MAX, 0});
    for (uint32_t f : placed.faces) {
        MacroCell& cell = out.cells[first + uint32_t(cellJ[f] - placed.minJ) * width + uint32_t(cellI[f] - placed.minI)];
        if (cell.face != UINT32_MAX) {  // two faces on one cell
            out.cells.resize(first);
            return false;
        }
        cell = {f, rot[f]};
    }
    auto side = [&](const MacroCell& c, uint32_t s) { return grid.faceEdge(c.face, (c.rotation + s) & 3); };
    for (uint32_t j = 0; j < height; ++j)
        for (uint32_t i = 0; i < width; ++i) {
            const MacroCell& c = out.cells[first + j * width + i];
            const bool rightOk = i + 1 == width || side(c, 1) == side(out.cells[first + j * width + i + 1], 3);
            const bool upOk = j + 1 == height || side(c, 2) == side(out.cells[first + (j + 1) * width + i], 0);
            if (!rightOk || !upOk) {
                out.cells.resize(first);
                return false;
            }
        }
    out.faces.push_back(MacroFace{width, height, first, {}});
    return true;
}

// Spans: each side cut where the macro face across it changes (or stops being one). A span is
// named by its first and last edges and its length, the same from both macro faces that have it.
void numberSpans(const Grid& grid, MacroFaces& out) {
    // The cage edge at step t of side s of macro face m.
    auto sideEdge = [&](const MacroFace& m, uint32_t s, uint32_t t) {
        const uint32_t i = s == 0 || s == 2 ? t : (s == 1 ? m.width - 1 : 0);
        const uint32_t j = s == 1 || s == 3 ? t : (s == 2 ? m.height - 1 : 0);
        const MacroCell& c = out.cells[m.firstCell + j * m.width + i];
        return grid.faceEdge(c.face, (c.rotation + s) & 3);
    };
    // Per edge, the (up to two) macro face sides it lies on, as 4 m + s.
    const uint32_t edgeCount = grid.topology.edgeCount();
    std::vector<uint32_t> users(2 * size_t(edgeCount), UINT32_MAX);
    for (uint32_t m = 0; m < out.faces.size(); ++m)
        for (uint32_t s = 0; s < 4; ++s)
            for (uint32_t t = 0; t < (s % 2 ? out.faces[m].height : out.faces[m].width); ++t) {
                const uint32_t e = sideEdge(out.faces[m], s, t);
                users[2 * size_t(e) + (users[2 * size_t(e)] == UINT32_MAX ? 0 : 1)] = 4 * m + s;
            }
    struct Key {
        uint32_t a, b, length;
        bool operator==(const Key&) const = default;
    };
    struct Hash {
        size_t operator()(const Key& k) const { return (size_t(k.a) * 0x9E3779B97F4A7C15ull) ^ (size_t(k.b) << 20) ^ k.length; }
    };
    std::unordered_map<Key, uint32_t, Hash> ids;
    std::vector<uint8_t> spanUsers;
    out.spans.clear();
    for (uint32_t m = 0; m < out.faces.size(); ++m) {
        MacroFace& face = out.faces[m];
        for (uint32_t s = 0; s < 4; ++s) {
            face.spanBegin[s] = uint32_t(out.spans.size());
            const uint32_t length = s % 2 ? face.height : face.width, self = 4 * m + s;
            auto across = [&](uint32_t t) {
                const uint32_t e = sideEdge(face, s, t);
                const uint32_t a = users[2 * size_t(e)], b = users[2 * size_t(e) + 1];
                return a == self ? b : a;
            };
            for (uint32_t t = 0; t < length;) {
                const uint32_t neighbour = across(t);
                uint32_t end = t + 1;
                while (end < length && across(end) == neighbour) ++end;
                const uint32_t first = sideEdge(face, s, t), last = sideEdge(face, s, end - 1);
                const Key key{std::min(first, last), std::max(first, last), end - t};
                auto [it, added] = ids.try_emplace(key, uint32_t(spanUsers.size()));
                if (added) spanUsers.push_back(0);
                ++spanUsers[it->second];
                out.spans.push_back({it->second, t, end - t});
                t = end;
            }
        }
        face.spanBegin[4] = uint32_t(out.spans.size());
    }
    out.spanShared.resize(spanUsers.size());
    for (size_t k = 0; k < spanUsers.size(); ++k) out.spanShared[k] = spanUsers[k] == 2;
}

}  // namespace

MacroFaces rectangularMacroFaces(const Cage& cage, const Topology& topology, uint32_t maxSpan) {
    assert(maxSpan >= 1);
    const Grid grid(cage, topology);
    const uint32_t faceCount = cage.faceCount(), vertexCount = uint32_t(cage.positions.size());
    std::vector<uint8_t> cut(topology.edgeCount());
    for (uint32_t e = 0; e < topology.edgeCount(); ++e) cut[e] = !grid.inner[e];

    // A line from v along e, straight on through regular vertices, until a singular vertex, the
    // boundary, or the line it would continue is there already.
    auto traceFrom = [&](uint32_t v, uint32_t e) {
        for (;;) {
            cut[e] = 1;
            const uint32_t w = grid.otherEnd(e, v);
            if (!grid.regular[w]) return;
            const uint32_t next = grid.straightOn(e, w);
            if (cut[next]) return;
            v = w, e = next;
        }
    };
    // The whole line through edge e, both ways.
    auto traceThrough = [&](uint32_t e) {
        const uint32_t a = topology.edgeVertices[2 * e];
        const bool backwards = grid.regular[a] && !cut[grid.straightOn(e, a)];
        traceFrom(a, e);
        if (backwards) traceFrom(a, grid.straightOn(e, a));
    };

    // Separatrices from every singular vertex. A boundary vertex with two quads (three edges) is
    // regular on its boundary; isolated vertices have no edges.
    for (uint32_t v = 0; v < vertexCount; ++v) {
        if (grid.regular[v]) continue;
        const uint32_t faces = topology.vertexFaceCount(v), edges = topology.vertexEdgeCount(v);
        bool regularBoundary = faces == 2 && edges == 3;
        for (uint32_t k = topology.vertexFaceOffsets[v]; k < topology.vertexFaceOffsets[v + 1] && regularBoundary; ++k)
            regularBoundary = cage.faceSize(topology.vertexFaces[k]) == 4;
        if (regularBoundary) continue;
        for (uint32_t k = topology.vertexEdgeOffsets[v]; k < topology.vertexEdgeOffsets[v + 1]; ++k)
            if (!cut[topology.vertexEdges[k]]) traceFrom(v, topology.vertexEdges[k]);
    }

    // Regions between the lines; those too long, or closed on themselves, get further lines.
    std::vector<uint32_t> mark(faceCount, 0);
    std::vector<int> cellI(faceCount), cellJ(faceCount);
    std::vector<uint8_t> rot(faceCount);
    MacroFaces out;
    auto crossable = [&](uint32_t e) { return !cut[e]; };
    auto isQuad = [&](uint32_t f) { return cage.faceSize(f) == 4; };
    constexpr uint32_t kMaxPasses = 64;
    for (uint32_t pass = 1;; ++pass) {
        out = MacroFaces{};
        bool traced = false;
        for (uint32_t f = 0; f < faceCount; ++f) {
            if (mark[f] == pass || cage.faceSize(f) != 4) continue;
            const Placed placed = placeFaces(grid, f, 0, crossable, isQuad, mark, pass, cellI, cellJ, rot);
            if (placed.faces.size() < 2) continue;
            const uint32_t width = uint32_t(placed.maxI - placed.minI + 1), height = uint32_t(placed.maxJ - placed.minJ + 1);
            if (pass < kMaxPasses && placed.consistent && (width > maxSpan || height > maxSpan)) {
                // Into nearly equal parts of at most maxSpan, all in this pass: lines along the
                // left sides of the cells of dividing columns and the bottoms of dividing rows.
                std::vector<uint32_t> columnFace(width, UINT32_MAX), rowFace(height, UINT32_MAX);
                for (uint32_t g : placed.faces) {
                    columnFace[uint32_t(cellI[g] - placed.minI)] = g;
                    rowFace[uint32_t(cellJ[g] - placed.minJ)] = g;
                }
                auto divide = [&](const std::vector<uint32_t>& lineFace, uint32_t length, uint32_t side) {
                    const uint32_t parts = (length + maxSpan - 1) / maxSpan;
                    for (uint32_t t = 1; t < parts; ++t) {
                        const uint32_t g = lineFace[t * length / parts];
                        const uint32_t e = grid.faceEdge(g, (rot[g] + side) & 3);
                        if (!cut[e]) traceThrough(e), traced = true;
                    }
                };
                divide(columnFace, width, 3);
                divide(rowFace, height, 0);
                continue;
            }
            if (pass < kMaxPasses && !placed.consistent) {
                // Closed on itself: two lines across it through a regular corner of its seed face.
                for (uint32_t c = 0; c < 4 && !traced; ++c) {
                    if (!grid.regular[cage.faceBegin(f)[c]]) continue;
                    for (uint32_t local : {c, (c + 3) & 3}) {
                        const uint32_t e = grid.faceEdge(f, local);
                        if (!cut[e]) traceThrough(e), traced = true;
                    }
                }
                continue;
            }
            appendRectangle(grid, placed, cellI, cellJ, rot, out);
        }
        if (!traced) break;
    }
    numberSpans(grid, out);
    return out;
}

namespace {

// Lays a connected set of allowed quads on the lattice row by row: from each row's first face
// along u both ways as far as it goes, then the faces above and below it start rows of their
// own. Where the set closes on itself (a torus, a cylinder) the coordinates jump along straight
// seams (a breadth-first flood would leave diagonal ones, which cut more blocks).
template <class Allowed>
std::vector<uint32_t> placeRows(const Grid& grid, uint32_t seed, const Allowed& allowed, std::vector<uint32_t>& mark,
                                uint32_t stamp, std::vector<int>& cellI, std::vector<int>& cellJ, std::vector<uint8_t>& rot) {
    std::vector<uint32_t> placed{seed}, rowStarts{seed};
    mark[seed] = stamp;
    cellI[seed] = 0, cellJ[seed] = 0, rot[seed] = 0;
    // The face across side s of f, placed, or UINT32_MAX.
    auto step = [&](uint32_t f, uint32_t s) {
        const uint32_t e = grid.faceEdge(f, (rot[f] + s) & 3);
        if (!grid.inner[e]) return UINT32_MAX;
        const uint32_t g = grid.otherFace(e, f);
        if (!allowed(g) || mark[g] == stamp) return UINT32_MAX;
        mark[g] = stamp;
        cellI[g] = cellI[f] + kStepI[s], cellJ[g] = cellJ[f] + kStepJ[s];
        rot[g] = uint8_t((grid.localEdge(g, e) + 2 - s) & 3);
        placed.push_back(g);
        return g;
    };
    for (size_t next = 0; next < rowStarts.size(); ++next) {
        const size_t rowBegin = placed.size();
        const uint32_t start = rowStarts[next];
        for (uint32_t s : {1u, 3u})
            for (uint32_t f = step(start, s); f != UINT32_MAX; f = step(f, s)) {}
        // The row: its start and what was just placed; the faces above and below start rows.
        auto spread = [&](uint32_t f) {
            for (uint32_t s : {0u, 2u})
                if (const uint32_t g = step(f, s); g != UINT32_MAX) rowStarts.push_back(g);
        };
        spread(start);
        for (size_t k = rowBegin; k < placed.size(); ++k)
            if (cellJ[placed[k]] == cellJ[start]) spread(placed[k]);
    }
    return placed;
}

// Aligned blocks: each connected set of member candidates (`regularOnly`: regular faces, else
// any quads) laid on the lattice (placeRows; where it closes on itself or winds around an
// extraordinary vertex the coordinates jump, and blocks across the jump fail appendRectangle's
// check, which also keeps every extraordinary vertex off a block's inside), then B x B blocks at
// multiples of B for B = maxBlock, maxBlock / 2, ... 2, each taking faces no bigger block took.
// Neighbouring blocks of one size share whole sides; a block beside smaller ones meets each along
// a span of its side.
void appendAlignedBlocks(const Grid& grid, uint32_t maxBlock, bool regularOnly, std::vector<uint8_t>& taken,
                         MacroFaces& out) {
    const Cage& cage = grid.cage;
    const uint32_t faceCount = cage.faceCount();
    std::vector<uint32_t> mark(faceCount, 0);
    std::vector<int> cellI(faceCount), cellJ(faceCount);
    std::vector<uint8_t> rot(faceCount);
    std::vector<uint8_t> candidate(faceCount);
    for (uint32_t f = 0; f < faceCount; ++f) candidate[f] = regularOnly ? grid.faceIsRegular(f) : cage.faceSize(f) == 4;
    auto isCandidate = [&](uint32_t f) { return candidate[f] != 0; };
    auto key = [](int i, int j) { return (uint64_t(uint32_t(i)) << 32) | uint32_t(j); };
    auto floorMod = [](int x, int b) { return ((x % b) + b) % b; };
    std::unordered_map<uint64_t, uint32_t> at;
    uint32_t stamp = 0;
    for (uint32_t seed = 0; seed < faceCount; ++seed) {
        if (!candidate[seed] || mark[seed] || taken[seed]) continue;
        const std::vector<uint32_t> component = placeRows(grid, seed, isCandidate, mark, ++stamp, cellI, cellJ, rot);
        at.clear();
        for (uint32_t f : component) at.try_emplace(key(cellI[f], cellJ[f]), f);
        for (uint32_t block = maxBlock; block >= 2; block /= 2) {
            for (uint32_t f : component) {
                if (taken[f] || floorMod(cellI[f], int(block)) || floorMod(cellJ[f], int(block))) continue;
                Placed candidate;
                candidate.minI = cellI[f], candidate.maxI = cellI[f] + int(block) - 1;
                candidate.minJ = cellJ[f], candidate.maxJ = cellJ[f] + int(block) - 1;
                bool whole = true;
                for (int j = candidate.minJ; j <= candidate.maxJ && whole; ++j)
                    for (int i = candidate.minI; i <= candidate.maxI && whole; ++i) {
                        const auto it = at.find(key(i, j));
                        whole = it != at.end() && !taken[it->second] && cellI[it->second] == i && cellJ[it->second] == j;
                        if (whole) candidate.faces.push_back(it->second);
                    }
                if (!whole || !appendRectangle(grid, candidate, cellI, cellJ, rot, out)) continue;
                for (uint32_t g : candidate.faces) taken[g] = 1;
            }
        }
    }
}

}  // namespace

namespace {

// Any 2 x 2 block of free regular faces left around a regular vertex, greedily in vertex order.
void appendGreedyQuartets(const Grid& grid, std::vector<uint8_t>& taken, MacroFaces& out) {
    const Cage& cage = grid.cage;
    const Topology& topology = grid.topology;
    const uint32_t faceCount = cage.faceCount();
    std::vector<uint32_t> mark(faceCount, 0);
    std::vector<int> cellI(faceCount), cellJ(faceCount);
    std::vector<uint8_t> rot(faceCount);
    uint32_t stamp = 0;
    for (uint32_t v = 0; v < uint32_t(cage.positions.size()); ++v) {
        if (!grid.regular[v]) continue;
        const uint32_t* around = topology.vertexFaces.data() + topology.vertexFaceOffsets[v];
        bool free = true;
        for (uint32_t k = 0; k < 4 && free; ++k) free = !taken[around[k]] && grid.faceIsRegular(around[k]);
        if (!free) continue;
        // The first face with v at its lattice point (1, 1): its corner there is rotation + 2.
        const uint32_t seed = around[0];
        uint32_t corner = 0;
        while (cage.faceBegin(seed)[corner] != v) ++corner;
        auto inQuartet = [&](uint32_t g) { return std::find(around, around + 4, g) != around + 4; };
        const Placed placed =
            placeFaces(grid, seed, (corner + 2) & 3, [](uint32_t) { return true; }, inQuartet, mark, ++stamp, cellI, cellJ, rot);
        if (placed.faces.size() != 4 || !appendRectangle(grid, placed, cellI, cellJ, rot, out)) continue;
        for (uint32_t k = 0; k < 4; ++k) taken[around[k]] = 1;
    }
}

MacroFaces alignedBlocks(const Cage& cage, const Topology& topology, uint32_t maxBlock, bool regularOnly) {
    const Grid grid(cage, topology);
    std::vector<uint8_t> taken(cage.faceCount(), 0);
    MacroFaces out;
    appendAlignedBlocks(grid, maxBlock, regularOnly, taken, out);
    appendGreedyQuartets(grid, taken, out);  // near seams and irregular faces
    numberSpans(grid, out);
    return out;
}

}  // namespace

MacroFaces quartetMacroFaces(const Cage& cage, const Topology& topology) { return alignedBlocks(cage, topology, 2, true); }

MacroFaces blockMacroFaces(const Cage& cage, const Topology& topology, uint32_t maxSpan) {
    assert(maxSpan >= 2);
    return alignedBlocks(cage, topology, std::bit_floor(maxSpan), false);
}

uint32_t macroLatticeVertex(const Cage& cage, const MacroFaces& macros, uint32_t m, uint32_t a, uint32_t b) {
    const MacroFace& face = macros.faces[m];
    assert(a <= face.width && b <= face.height);
    const uint32_t i = std::min(a, face.width - 1), j = std::min(b, face.height - 1);
    const MacroCell& cell = macros.cells[face.firstCell + j * face.width + i];
    // Corner of the cell at (a, b): (0, 0) -> 0, (1, 0) -> 1, (1, 1) -> 2, (0, 1) -> 3.
    const uint32_t du = a - i, dv = b - j;
    const uint32_t k = dv ? (du ? 2 : 3) : du;
    return cage.faceBegin(cell.face)[(cell.rotation + k) & 3];
}

}  // namespace qp
