#include "macro_grid.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <iterator>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include "gpu_plans.h"
#include "grid_layout.h"
#include "plans/macro_faces.h"

namespace qp {

namespace {

// Positions (in pieces of 1 / n of a cage edge, ascending) of side s's vertices: its spans' pieces.
void sideVertexPositions(const MacroGrid& grid, const MacroGridFace& face, uint32_t s, uint32_t n,
                         std::span<const uint32_t> spanPieces, std::vector<uint32_t>& positions) {
    positions.assign(1, 0);
    for (uint32_t k = face.spanBegin[s]; k < face.spanBegin[s + 1]; ++k) {
        const MacroSpan& span = grid.spans[k];
        const uint32_t pieces = spanPieces[span.id], stepLength = span.length * n / pieces;
        for (uint32_t p = 1; p <= pieces; ++p) positions.push_back(span.start * n + p * stepLength);
    }
}

// The grid's columns (or rows): every vertex of the two opposite sides.
std::vector<uint32_t> gridLines(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
    std::vector<uint32_t> lines;
    std::set_union(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(lines));
    return lines;
}

uint64_t quadsSaved(const MacroFaces& macros) { return macros.facesInMacroFaces() - macros.faces.size(); }

// The cell of lattice point (a, b) and the corner of its member there.
struct LatticeCorner {
    uint32_t cell, corner;
};
LatticeCorner latticeCorner(const MacroGrid& grid, const MacroGridFace& face, uint32_t a, uint32_t b) {
    const uint32_t i = std::min(a, face.width - 1), j = std::min(b, face.height - 1);
    const uint32_t du = a - i, dv = b - j;
    const uint32_t k = dv ? (du ? 2 : 3) : du;  // (0,0) 0, (1,0) 1, (1,1) 2, (0,1) 3
    const uint32_t cell = face.firstCell + j * face.width + i;
    return {cell, (grid.cellRotation[cell] + k) & 3};
}

// Lattice point t along side s (sides run as MacroFace says: 0 and 2 along u, 1 and 3 along v,
// each from the lower coordinate).
void sidePoint(const MacroGridFace& face, uint32_t s, uint32_t t, uint32_t& a, uint32_t& b) {
    a = s == 0 || s == 2 ? t : (s == 1 ? face.width : 0);
    b = s == 1 || s == 3 ? t : (s == 2 ? face.height : 0);
}

uint32_t smallestDivisorAtLeast(uint32_t length, float wanted) {
    if (!(wanted > 1.0f)) return 1;
    if (wanted >= float(length)) return length;
    for (uint32_t p = uint32_t(std::ceil(wanted)); p < length; ++p)
        if (length % p == 0) return p;
    return length;
}

MacroGrid inDrawnSubfaces(const PlannedCage& planned, const GpuPlanData& data, const MacroFaces& macros) {
    std::vector<uint32_t> drawnOf(planned.subfaceCount(), UINT32_MAX);
    for (uint32_t d = 0; d < data.subfaces.size(); ++d) drawnOf[data.subfaces[d].subface] = d;
    MacroGrid grid;
    grid.macroOfDrawn.assign(data.subfaces.size(), UINT32_MAX);
    grid.spans = macros.spans;
    grid.spanShared = macros.spanShared;
    for (const MacroFace& face : macros.faces) {
        MacroGridFace out{face.width, face.height, uint32_t(grid.cellDrawn.size()), UINT32_MAX, {}};
        std::copy(face.spanBegin, face.spanBegin + 5, out.spanBegin);
        bool drawn = true;
        for (uint32_t c = 0; c < face.width * face.height && drawn; ++c)
            drawn = drawnOf[planned.firstSubface(macros.cells[face.firstCell + c].face)] != UINT32_MAX;
        if (!drawn) {
            // A member without a surface: the macro face is left out, and the spans it shared are
            // shared no more.
            for (uint32_t k = face.spanBegin[0]; k < face.spanBegin[4]; ++k) grid.spanShared[macros.spans[k].id] = 0;
            continue;
        }
        const uint32_t m = uint32_t(grid.faces.size());
        for (uint32_t c = 0; c < face.width * face.height; ++c) {
            const MacroCell& cell = macros.cells[face.firstCell + c];
            const uint32_t d = drawnOf[planned.firstSubface(cell.face)];
            grid.cellDrawn.push_back(d);
            grid.cellRotation.push_back(uint8_t(cell.rotation));
            grid.macroOfDrawn[d] = m;
            out.head = std::min(out.head, d);
        }
        grid.faces.push_back(out);
    }
    // Each span id's first use and the macro face across.
    grid.spanUses.assign(grid.spanCount(), MacroSpanUse{UINT32_MAX, 0, 0, UINT32_MAX});
    for (uint32_t m = 0; m < grid.faces.size(); ++m)
        for (uint32_t s = 0; s < 4; ++s)
            for (uint32_t k = grid.faces[m].spanBegin[s]; k < grid.faces[m].spanBegin[s + 1]; ++k) {
                MacroSpanUse& use = grid.spanUses[grid.spans[k].id];
                if (use.macro == UINT32_MAX) use = {m, s, k, UINT32_MAX};
                else if (grid.spanShared[grid.spans[k].id]) use.other = m;
            }
    return grid;
}

}  // namespace

namespace {

MacroFaces partitionOf(const PlannedCage& planned, MacroChoice choice) {
    switch (choice) {
    case MacroChoice::Rectangles: return rectangularMacroFaces(planned.cage(), planned.topology());
    case MacroChoice::Quartets: return quartetMacroFaces(planned.cage(), planned.topology());
    case MacroChoice::Blocks: return blockMacroFaces(planned.cage(), planned.topology());
    case MacroChoice::Auto: {
        // Rectangles or aligned blocks (quartets are blocks of two and save less), on two cores.
        MacroFaces rectangles, blocks;
        tbb::parallel_invoke([&] { rectangles = partitionOf(planned, MacroChoice::Rectangles); },
                             [&] { blocks = partitionOf(planned, MacroChoice::Blocks); });
        return quadsSaved(blocks) > quadsSaved(rectangles) ? std::move(blocks) : std::move(rectangles);
    }
    case MacroChoice::Off: break;
    }
    return {};
}

}  // namespace

void rebuildMacroGrid(const PlannedCage& planned, GpuPlanData& data) {
    const MacroChoice choice = data.macros.choice;
    data.macros = inDrawnSubfaces(planned, data, partitionOf(planned, choice));
    data.macros.choice = choice;
}

void markMacroGridStale(GpuPlanData& data) {
    MacroGrid stale;
    stale.choice = data.macros.choice;
    stale.stale = true;
    data.macros = std::move(stale);
}

const char* macroChoiceName(MacroChoice choice) {
    switch (choice) {
    case MacroChoice::Auto: return "auto";
    case MacroChoice::Rectangles: return "rectangles";
    case MacroChoice::Quartets: return "quartets";
    case MacroChoice::Blocks: return "blocks";
    case MacroChoice::Off: return "off";
    }
    return "?";
}

namespace {

// Distinct values of two ascending lists, counted without building their union.
uint32_t distinctInBoth(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
    uint32_t count = 0;
    size_t i = 0, j = 0;
    while (i < a.size() || j < b.size()) {
        const uint32_t next = j == b.size() || (i < a.size() && a[i] < b[j]) ? a[i] : b[j];
        while (i < a.size() && a[i] == next) ++i;
        while (j < b.size() && b[j] == next) ++j;
        ++count;
    }
    return count;
}

}  // namespace

void chooseMacroPieces(const GpuPlanData& data, GridFactors& factors, std::span<const glm::vec4> points,
                       const AdaptiveView* view, uint32_t minify, std::span<const uint32_t> blocked,
                       const GridFactors* previous, bool whole) {
    const MacroGrid& grid = data.macros;
    factors.macroSpanPieces.clear();
    factors.macroResolution.clear();
    const uint32_t macroCount = uint32_t(grid.faces.size()), spanCount = grid.spanCount();
    if (macroCount == 0 || (!view && minify <= 1 && !whole)) return;

    // Which macro faces may be drawn as one: every member at one factor n, each of its edges in n
    // pieces, none blocked. The users of a span have equal n (its segments are theirs).
    std::vector<uint32_t> resolution(macroCount, 0);  // n of an eligible macro face, else 0
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, macroCount, 256), [&](const tbb::blocked_range<uint32_t>& range) {
        for (uint32_t m = range.begin(); m != range.end(); ++m) {
            const MacroGridFace& face = grid.faces[m];
            const uint32_t n = factors.subfaceFactor[grid.cellDrawn[face.firstCell]];
            bool ok = true;
            for (uint32_t c = face.firstCell; c < face.firstCell + face.width * face.height && ok; ++c) {
                const uint32_t d = grid.cellDrawn[c];
                ok = factors.subfaceFactor[d] == n && !std::binary_search(blocked.begin(), blocked.end(), d);
                for (const GpuEdgeRef& r : data.boundaries[d].edges)
                    ok = ok && factors.segmentPieces[r.segment] * ((r.flags & kEdgeRefSplit) ? 2 : 1) == n;
            }
            resolution[m] = ok ? n : 0;
        }
    });

    // Pieces per span id, from its first use (so equal from both users), in pieces of 1 / n of a
    // cage edge: below its length only when both users are eligible.
    std::vector<uint32_t>& spanPieces = factors.macroSpanPieces;
    spanPieces.assign(spanCount, 0);
    const bool keepPrevious = previous && previous->macroSpanPieces.size() == spanCount;
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, spanCount, 1024), [&](const tbb::blocked_range<uint32_t>& range) {
        for (uint32_t id = range.begin(); id != range.end(); ++id) {
            const MacroSpanUse& use = grid.spanUses[id];
            const uint32_t other = use.other == UINT32_MAX ? 0 : resolution[use.other];
            const uint32_t n = resolution[use.macro] ? resolution[use.macro] : other;
            if (!n) continue;
            const MacroGridFace& face = grid.faces[use.macro];
            const MacroSpan& span = grid.spans[use.span];
            const uint32_t full = span.length * n;
            const bool shared = resolution[use.macro] && other;
            if (!shared) {
                spanPieces[id] = full;
            } else if (view) {
                // The span's polyline through its cage vertices, measured on screen at its middle.
                float polyline = 0.0f;
                glm::vec3 previousPoint(0.0f), middle(0.0f);
                for (uint32_t t = span.start; t <= span.start + span.length; ++t) {
                    uint32_t a, b;
                    sidePoint(face, use.side, t, a, b);
                    const LatticeCorner at = latticeCorner(grid, face, a, b);
                    const glm::vec3 p(points[data.boundaries[grid.cellDrawn[at.cell]].corners[at.corner]]);
                    if (t > span.start) polyline += glm::length(p - previousPoint);
                    if (t == span.start + span.length / 2) middle = p;
                    previousPoint = p;
                }
                const float w = std::max((view->viewProjection * glm::vec4(middle, 1.0f)).w, 1e-4f);
                const float wanted = polyline * view->pixelsPerUnit / w / view->pixelsPerSegment;
                uint32_t pieces = smallestDivisorAtLeast(full, wanted);
                if (keepPrevious) {
                    const uint32_t kept = previous->macroSpanPieces[id];
                    if (kept && full % kept == 0 && wanted <= float(kept) && wanted * 2.5f > float(kept)) pieces = kept;
                }
                spanPieces[id] = pieces;
            } else {
                spanPieces[id] = smallestDivisorAtLeast(full, float(full) / float(minify));  // factor n / minify
            }
        }
    });

    // Eligible macro faces with a span below its length (or all, `whole`) are drawn as one: columns
    // at every vertex of the bottom and top sides, rows at those of the left and right.
    factors.macroResolution.assign(2 * size_t(macroCount), 0);
    std::atomic<bool> anyCoarse{false};
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, macroCount, 256), [&](const tbb::blocked_range<uint32_t>& range) {
        std::vector<uint32_t> sides[4];
        for (uint32_t m = range.begin(); m != range.end(); ++m) {
            const uint32_t n = resolution[m];
            if (!n) continue;
            const MacroGridFace& face = grid.faces[m];
            bool coarse = whole;
            for (uint32_t k = face.spanBegin[0]; k < face.spanBegin[4] && !coarse; ++k)
                coarse = spanPieces[grid.spans[k].id] < grid.spans[k].length * n;
            if (!coarse) continue;
            for (uint32_t s = 0; s < 4; ++s) sideVertexPositions(grid, face, s, n, spanPieces, sides[s]);
            factors.macroResolution[2 * size_t(m)] = distinctInBoth(sides[0], sides[2]) - 1;
            factors.macroResolution[2 * size_t(m) + 1] = distinctInBoth(sides[1], sides[3]) - 1;
            anyCoarse = true;
        }
    });
    if (!anyCoarse) {
        factors.macroSpanPieces.clear();
        factors.macroResolution.clear();
    }
}

uint32_t macroColumns(const GridFactors& factors, uint32_t m) {
    return factors.macroResolution.empty() ? 0 : factors.macroResolution[2 * size_t(m)];
}
uint32_t macroRows(const GridFactors& factors, uint32_t m) {
    return factors.macroResolution.empty() ? 0 : factors.macroResolution[2 * size_t(m) + 1];
}

void writeMacroIndices(const MacroGrid& grid, uint32_t m, const GridFactors& factors,
                       std::span<const uint32_t> subfaceOffset, std::span<const uint32_t> source, uint32_t* out) {
    const MacroGridFace& face = grid.faces[m];
    const uint32_t n = factors.subfaceFactor[grid.cellDrawn[face.firstCell]];
    const uint32_t width = face.width * n, height = face.height * n;  // in pieces of its members' grids
    // The slot of lattice point (a, b) (in pieces): a member's grid slot, turned from the cell's
    // frame into the face's own (corner `rotation` at the cell's origin).
    auto slotAt = [&](uint32_t a, uint32_t b) {
        const uint32_t i = std::min(a / n, face.width - 1), j = std::min(b / n, face.height - 1);
        const uint32_t x = a - i * n, y = b - j * n, cell = face.firstCell + j * face.width + i;
        uint32_t fx = x, fy = y;
        switch (grid.cellRotation[cell]) {
        case 1: fx = n - y, fy = x; break;
        case 2: fx = n - x, fy = n - y; break;
        case 3: fx = y, fy = n - x; break;
        default: break;
        }
        const uint32_t d = grid.cellDrawn[cell];
        assert(factors.subfaceFactor[d] == n && "members of a coarse macro face share one factor");
        return source[subfaceOffset[d] + fy * (n + 1) + fx];
    };
    std::vector<uint32_t> sides[4];
    for (uint32_t s = 0; s < 4; ++s) sideVertexPositions(grid, face, s, n, factors.macroSpanPieces, sides[s]);
    const std::vector<uint32_t> columnAt = gridLines(sides[0], sides[2]), rowAt = gridLines(sides[1], sides[3]);
    const uint32_t columns = uint32_t(columnAt.size() - 1), rows = uint32_t(rowAt.size() - 1);
    assert(columns == macroColumns(factors, m) && rows == macroRows(factors, m));
    // The side vertex nearest to `position` (ties: the later one), as grid_layout.cpp snaps edges:
    // a grid line that is not one of this side's vertices folds into a neighbour.
    auto snap = [&](uint32_t s, uint32_t position) {
        const std::vector<uint32_t>& vertices = sides[s];
        const auto after = std::lower_bound(vertices.begin(), vertices.end(), position);
        if (after == vertices.end()) return vertices.back();
        if (after == vertices.begin() || *after == position) return *after;
        return position - *(after - 1) < *after - position ? *(after - 1) : *after;
    };
    auto vertex = [&](uint32_t x, uint32_t y) {
        if (y == 0) return slotAt(snap(0, columnAt[x]), 0);
        if (y == rows) return slotAt(snap(2, columnAt[x]), height);
        if (x == 0) return slotAt(0, snap(3, rowAt[y]));
        if (x == columns) return slotAt(width, snap(1, rowAt[y]));
        return slotAt(columnAt[x], rowAt[y]);
    };
    for (uint32_t y = 0; y < rows; ++y)
        for (uint32_t x = 0; x < columns; ++x) {
            const uint32_t a = vertex(x, y), b = vertex(x + 1, y), c = vertex(x + 1, y + 1), e = vertex(x, y + 1);
            *out++ = a, *out++ = b, *out++ = c, *out++ = a, *out++ = c, *out++ = e;
        }
}

std::vector<uint32_t> culledForDrawing(const MacroGrid& grid, const GridFactors& factors, std::span<const uint32_t> culled) {
    if (factors.macroResolution.empty()) return {culled.begin(), culled.end()};
    std::vector<uint32_t> out;
    out.reserve(culled.size());
    for (uint32_t d : culled) {
        const uint32_t m = d < grid.macroOfDrawn.size() ? grid.macroOfDrawn[d] : UINT32_MAX;
        if (m != UINT32_MAX && macroColumns(factors, m) && grid.faces[m].head == d) {
            const MacroGridFace& face = grid.faces[m];
            bool all = true;
            for (uint32_t c = face.firstCell; c < face.firstCell + face.width * face.height && all; ++c)
                all = std::binary_search(culled.begin(), culled.end(), grid.cellDrawn[c]);
            if (!all) continue;
        }
        out.push_back(d);
    }
    return out;
}

}  // namespace qp
