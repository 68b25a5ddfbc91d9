#include "grid_layout.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <cmath>
#include <memory>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace qp {

namespace {

// GpuEdgeRef::flags and GpuSegment::ownerEdge, as gpu_plans.cpp writes them.
constexpr uint32_t kStartCorner[4] = {0, 1, 3, 0}, kEndCorner[4] = {1, 2, 2, 3};

bool isNgonSubface(const GpuPlanData& data, uint32_t drawn) { return (data.boundaries[drawn].edges[0].flags & kEdgeRefHalf) != 0; }

// Pieces along edge `e` of a drawn sub-face.
uint32_t edgePieces(const GpuPlanData& data, const GridFactors& factors, uint32_t drawn, uint32_t e) {
    const GpuEdgeRef& r = data.boundaries[drawn].edges[e];
    const uint32_t pieces = factors.segmentPieces[r.segment];
    return (r.flags & kEdgeRefSplit) ? 2 * pieces : pieces;
}

// A place on a drawn sub-face's boundary: slot (x, y) of its grid.
struct GridPlace {
    uint32_t drawn, x, y;
};

GridPlace cornerPlace(uint32_t drawn, uint32_t corner, uint32_t n) {
    return {drawn, (corner == 1 || corner == 2) ? n : 0, corner >= 2 ? n : 0};
}

GridPlace edgePlace(uint32_t drawn, uint32_t e, uint32_t index, uint32_t n) {
    switch (e) {
    case 0: return {drawn, index, 0};
    case 1: return {drawn, n, index};
    case 2: return {drawn, index, n};
    default: return {drawn, 0, index};
    }
}

// The C++ twin of shaders/plan_boundary.glsl's owner lookup, ending in the owner's grid slot
// instead of a parameter. Vertex c of k along `segment`, counted in its canonical direction.
GridPlace segmentOwnerPlace(const GpuPlanData& data, const GridFactors& factors, uint32_t segment, uint32_t c, uint32_t k) {
    const GpuSegment& s = data.segments[segment];
    const uint32_t edge = s.ownerEdge & 3, halfOfEdge = (s.ownerEdge >> 2) & 3;
    const uint32_t local = s.ownerReversed ? k - c : c;
    const uint32_t numerator = halfOfEdge == 0 ? local : (halfOfEdge - 1) * k + local;
    const uint32_t denominator = halfOfEdge == 0 ? k : 2 * k;
    const uint32_t n = factors.subfaceFactor[s.owner];
    assert(n % denominator == 0 && "an edge's pieces divide the grid factor of the sub-face owning it");
    return edgePlace(s.owner, edge, numerator * (n / denominator), n);
}

GridPlace pointOwnerPlace(const GpuPlanData& data, const GridFactors& factors, uint32_t point) {
    const GpuPoint& p = data.boundaryPoints[point];
    return cornerPlace(p.owner, p.ownerCorner, factors.subfaceFactor[p.owner]);
}

// Vertex i of P along edge e of `drawn`.
GridPlace edgeVertexOwnerPlace(const GpuPlanData& data, const GridFactors& factors, uint32_t drawn, uint32_t e,
                               uint32_t i, uint32_t pieces) {
    const GpuSubfaceBoundary& b = data.boundaries[drawn];
    const GpuEdgeRef& r = b.edges[e];
    if (i == 0) return pointOwnerPlace(data, factors, b.corners[kStartCorner[e]]);
    if (i == pieces) return pointOwnerPlace(data, factors, b.corners[kEndCorner[e]]);
    if (r.flags & kEdgeRefSplit) {
        const uint32_t k = pieces / 2;
        if (i == k) return pointOwnerPlace(data, factors, r.midpoint);
        if (i < k) return segmentOwnerPlace(data, factors, r.segment, i, k);
        return segmentOwnerPlace(data, factors, r.secondHalf, pieces - i, k);
    }
    return segmentOwnerPlace(data, factors, r.segment, (r.flags & kEdgeRefReversed) ? pieces - i : i, pieces);
}

// Segments needed for a sphere to be `pixelsPerSegment` long on screen (plan_draw.glsl). A
// sphere wholly behind the eye takes one: its w (depth along the view, 1 everywhere for an
// orthographic camera) stays below 0 however far across it, with twice its radius for the curve
// between the points. (Clamped as one that reaches the eye, it took 64: with the camera among a
// million faces, the half behind it laid out at 64 filled the memory.)
float sphereFactor(const AdaptiveView& view, const glm::vec3& centre, float radius) {
    const glm::mat4& m = view.viewProjection;
    const float w = (m * glm::vec4(centre, 1.0f)).w;
    if (w + 2.0f * radius * glm::length(glm::vec3(m[0][3], m[1][3], m[2][3])) < 0.0f) return 1.0f;
    return std::clamp(2.0f * radius * view.pixelsPerUnit / std::max(w, 1e-4f) / view.pixelsPerSegment, 1.0f, 64.0f);
}

uint32_t powerOfTwoAtLeast(float pieces) { return std::bit_ceil(uint32_t(std::ceil(pieces))); }

}  // namespace

uint32_t uniformGridFactor(const GpuPlanData& data, uint32_t factor) {
    assert(factor >= 1 && factor <= 64);
    for (uint32_t d = 0; d < data.subfaces.size(); ++d)
        if (isNgonSubface(data, d)) return factor % 2 ? factor + 1 : factor;
    return factor;
}

GridFactors uniformGridFactors(const GpuPlanData& data, uint32_t factor) {
    factor = uniformGridFactor(data, factor);
    GridFactors f;
    f.segmentPieces.assign(data.segments.size(), factor);
    f.subfaceFactor.resize(data.subfaces.size());
    for (uint32_t d = 0; d < data.subfaces.size(); ++d) {
        const bool ngon = isNgonSubface(data, d);
        f.subfaceFactor[d] = ngon ? std::max(1u, factor / 2) : factor;
        // n-gon sub-faces are half-size: their spokes and half edges take half the pieces.
        for (const GpuEdgeRef& r : data.boundaries[d].edges) {
            if (ngon || (r.flags & kEdgeRefSplit)) f.segmentPieces[r.segment] = std::max(1u, factor / 2);
            if (r.flags & kEdgeRefSplit) f.segmentPieces[r.secondHalf] = std::max(1u, factor / 2);
        }
    }
    return f;
}

namespace {

// Pieces for the segments of drawn sub-face d that have none yet (0 in `pieces`): by the screen
// size of a sphere around each (a half edge by its whole edge's), kept at `kept(segment)` (a
// power of two, or 0: none) while enough and not 2.5 times too many.
template <class Kept>
void chooseSegmentPieces(const GpuPlanData& data, std::span<const glm::vec4> points, const AdaptiveView& view, uint32_t d,
                         const Kept& kept, std::vector<uint32_t>& pieces) {
    auto choose = [&](uint32_t segment, float wanted) {
        if (pieces[segment]) return;  // seen from its other side
        uint32_t chosen = powerOfTwoAtLeast(wanted);
        // Only powers of two: a uniform layout's 5 pieces next to 4 would not divide the
        // sub-face's factor.
        const uint32_t previous = kept(segment);
        if (std::has_single_bit(previous) && wanted <= float(previous) && wanted * 2.5f > float(previous)) chosen = previous;
        pieces[segment] = chosen;
    };
    const GpuSubfaceBoundary& b = data.boundaries[d];
    const bool ngon = isNgonSubface(data, d);
    for (uint32_t e = 0; e < 4; ++e) {
        const GpuEdgeRef& r = b.edges[e];
        if (r.flags & (kEdgeRefSplit | kEdgeRefHalf)) {  // half of a cage edge: sized by the whole edge
            const glm::vec4& m = points[r.midpoint];
            const float wanted = 0.5f * sphereFactor(view, glm::vec3(m), m.w);
            choose(r.segment, wanted);
            if (r.flags & kEdgeRefSplit) choose(r.secondHalf, wanted);
            continue;
        }
        const uint32_t a = b.corners[kStartCorner[e]], z = b.corners[kEndCorner[e]];
        const glm::vec3 pa(points[std::min(a, z)]), pz(points[std::max(a, z)]);
        const float wanted = sphereFactor(view, 0.5f * (pa + pz), 0.5f * glm::length(pz - pa));
        choose(r.segment, ngon ? 0.5f * wanted : wanted);
    }
}

}  // namespace

GridFactors adaptiveGridFactors(const GpuPlanData& data, std::span<const glm::vec4> points, const AdaptiveView& view,
                                const GridFactors* previous) {
    auto choose = [&](const AdaptiveView& v, const GridFactors* before) {
        GridFactors f;
        f.segmentPieces.assign(data.segments.size(), 0);
        f.subfaceFactor.assign(data.subfaces.size(), 1);
        auto kept = [&](uint32_t segment) { return before ? before->segmentPieces[segment] : 0u; };
        for (uint32_t d = 0; d < data.subfaces.size(); ++d) chooseSegmentPieces(data, points, v, d, kept, f.segmentPieces);
        for (uint32_t d = 0; d < data.subfaces.size(); ++d)
            for (uint32_t e = 0; e < 4; ++e) f.subfaceFactor[d] = std::max(f.subfaceFactor[d], edgePieces(data, f, d, e));
        return f;
    };
    GridFactors f = choose(view, previous);
    // Slots go about as the square of the pieces: one pass with the segments coarser by the
    // power of two that should fit, more only where the factors' rounding kept it over. The
    // factors in use keep their hysteresis at the coarser size too.
    AdaptiveView coarser = view;
    for (uint64_t slots = gridSlots(f); slots > kMaxAdaptiveGridSlots && coarser.pixelsPerSegment < 1e6f;
         slots = gridSlots(f)) {
        const double over = std::sqrt(double(slots) / double(kMaxAdaptiveGridSlots));
        coarser.pixelsPerSegment *= float(std::max(2.0, std::exp2(std::ceil(std::log2(over)))));
        f = choose(coarser, previous);
    }
    return f;
}

uint64_t gridSlots(const GridFactors& factors) {
    uint64_t slots = 0;
    for (uint32_t n : factors.subfaceFactor) slots += uint64_t(n + 1) * (n + 1);
    return slots;
}

void updateAdaptiveGridFactors(const GpuPlanData& data, std::span<const glm::vec4> points, const AdaptiveView& view,
                               GridFactors& factors, std::span<const uint32_t> touched) {
    // The touched sub-faces' segments chosen again, each kept at what it had.
    std::vector<std::pair<uint32_t, uint32_t>> before;  // (segment, pieces), sorted by segment
    for (uint32_t d : touched)
        for (const GpuEdgeRef& r : data.boundaries[d].edges) {
            before.push_back({r.segment, factors.segmentPieces[r.segment]});
            if (r.flags & kEdgeRefSplit) before.push_back({r.secondHalf, factors.segmentPieces[r.secondHalf]});
        }
    std::sort(before.begin(), before.end());
    before.erase(std::unique(before.begin(), before.end()), before.end());
    for (const auto& [segment, pieces] : before) factors.segmentPieces[segment] = 0;
    auto kept = [&](uint32_t segment) {
        return std::lower_bound(before.begin(), before.end(), std::pair<uint32_t, uint32_t>{segment, 0})->second;
    };
    for (uint32_t d : touched) chooseSegmentPieces(data, points, view, d, kept, factors.segmentPieces);
    for (uint32_t d : touched) {
        factors.subfaceFactor[d] = 1;
        for (uint32_t e = 0; e < 4; ++e) factors.subfaceFactor[d] = std::max(factors.subfaceFactor[d], edgePieces(data, factors, d, e));
    }
}

void writeGridIndices(const GpuPlanData& data, GridLayout& layout) {
    const GridFactors& factors = layout.factors;
    const uint32_t count = uint32_t(data.subfaces.size());
    std::vector<uint32_t>& indexOffset = layout.indexOffset;
    indexOffset.assign(count + 1, 0);
    // A member of a coarse macro face draws nothing of its own; its head draws the macro face.
    const MacroGrid& macros = data.macros;
    const bool coarseMacros = !factors.macroResolution.empty();
    assert(!coarseMacros || factors.macroResolution.size() == 2 * macros.faces.size());
    auto coarseMacroOf = [&](uint32_t d) {
        const uint32_t m = coarseMacros ? macros.macroOfDrawn[d] : UINT32_MAX;
        return m != UINT32_MAX && macroColumns(factors, m) ? m : UINT32_MAX;
    };
    for (uint32_t d = 0; d < count; ++d) {
        const uint32_t n = factors.subfaceFactor[d];
        uint32_t indexCount = 6 * n * n;
        if (const uint32_t m = coarseMacroOf(d); m != UINT32_MAX)
            indexCount = macros.faces[m].head == d ? 6 * macroColumns(factors, m) * macroRows(factors, m) : 0;
        indexOffset[d + 1] = indexOffset[d] + indexCount;
    }
    layout.indices.resize(indexOffset[count]);
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, count, 256), [&](const tbb::blocked_range<uint32_t>& range) {
        for (uint32_t d = range.begin(); d != range.end(); ++d) {
            const uint32_t m = coarseMacroOf(d);
            uint32_t* index = layout.indices.data() + indexOffset[d];
            if (m != UINT32_MAX) {
                if (macros.faces[m].head == d) writeMacroIndices(macros, m, factors, layout.subfaceOffset, layout.source, index);
                continue;
            }
            const uint32_t n = factors.subfaceFactor[d], side = n + 1, base = layout.subfaceOffset[d];
            for (uint32_t y = 0; y < n; ++y)
                for (uint32_t x = 0; x < n; ++x) {
                    const uint32_t a = base + y * side + x, b = a + 1, c = a + side + 1, e = a + side;
                    *index++ = a, *index++ = b, *index++ = c, *index++ = a, *index++ = c, *index++ = e;
                }
        }
    });
}

namespace {

// Per sub-face, the other sub-faces it copies from: its corners' and edges' owners.
constexpr uint32_t kMaxOwners = 16;
using OwnerList = std::array<uint32_t, kMaxOwners>;

void addOwner(OwnerList& owners, uint32_t& ownerCount, uint32_t owner) {
    if (std::find(owners.data(), owners.data() + ownerCount, owner) != owners.data() + ownerCount) return;
    assert(ownerCount < kMaxOwners);
    owners[ownerCount++] = owner;
}

// Offsets and the per-slot tables sized for `factors`.
void layOutOffsets(const GridFactors& factors, uint32_t count, GridLayout& layout) {
    layout.maxFactor = 0;
    layout.uniformRequest = 0;
    layout.subfaceOffset.resize(count + 1);
    layout.subfaceOffset[0] = 0;
    for (uint32_t d = 0; d < count; ++d) {
        const uint32_t n = factors.subfaceFactor[d];
        layout.subfaceOffset[d + 1] = layout.subfaceOffset[d] + (n + 1) * (n + 1);
        layout.maxFactor = std::max(layout.maxFactor, n);
    }
    layout.source.resize(layout.slotCount());
    layout.slotSubface.resize(layout.slotCount());
}

// Sub-face d's slots, each boundary slot from the place its owner evaluates.
void layOutSubface(const GpuPlanData& data, const GridFactors& factors, uint32_t d, GridLayout& layout, OwnerList& owners,
                   uint32_t& ownerCount) {
    const uint32_t n = factors.subfaceFactor[d], side = n + 1, base = layout.subfaceOffset[d];
    std::fill(layout.slotSubface.begin() + base, layout.slotSubface.begin() + base + side * side, d);
    for (uint32_t slot = base; slot < base + side * side; ++slot) layout.source[slot] = slot;
    for (uint32_t e = 0; e < 4; ++e) {
        const uint32_t pieces = edgePieces(data, factors, d, e);
        assert(pieces >= 1 && n % pieces == 0 && "a sub-face's factor is a multiple of its edges' pieces");
        for (uint32_t i = 0; i <= n; ++i) {
            const GridPlace here = edgePlace(d, e, i, n);
            const uint32_t j = (2 * i * pieces + n) / (2 * n);  // nearest edge vertex (ties: the later one)
            const GridPlace owner = edgeVertexOwnerPlace(data, factors, d, e, j, pieces);
            const uint32_t ownerSide = factors.subfaceFactor[owner.drawn] + 1;
            layout.source[base + here.y * side + here.x] = layout.subfaceOffset[owner.drawn] + owner.y * ownerSide + owner.x;
            if (owner.drawn != d) addOwner(owners, ownerCount, owner.drawn);
        }
    }
}

// Where a carried sub-face's slots went (new first slot minus old), by its number in `before`;
// kNotCarried for the others.
constexpr int64_t kNotCarried = INT64_MIN;

// Sub-face d's slots as `before` had them for sub-face `old`, renumbered: d is laid out as `old`
// was and its owners are the same sub-faces, so each copy points at the same place of the same
// owner, wherever that owner's slots went (`shift`). False (nothing to use) when an owner was
// not carried, whose places may have moved.
bool carrySubface(const GridLayout& before, std::span<const int64_t> shift, std::span<const uint32_t> newOf, uint32_t d,
                  uint32_t old, GridLayout& layout, OwnerList& owners, uint32_t& ownerCount) {
    const uint32_t oldBase = before.subfaceOffset[old], size = before.subfaceOffset[old + 1] - oldBase;
    const uint32_t base = layout.subfaceOffset[d], n = before.factors.subfaceFactor[old];
    assert(layout.subfaceOffset[d + 1] - base == size && size == (n + 1) * (n + 1) && "a carried sub-face keeps its factor");
    auto carry = [&](uint32_t local) {
        const uint32_t from = before.source[oldBase + local];
        if (from - oldBase < size) {  // its own slot (itself, or where an edge snaps)
            layout.source[base + local] = base + (from - oldBase);
            return true;
        }
        const uint32_t oldOwner = before.slotSubface[from];
        if (shift[oldOwner] == kNotCarried) return false;
        layout.source[base + local] = uint32_t(int64_t(from) + shift[oldOwner]);
        addOwner(owners, ownerCount, newOf[oldOwner]);
        return true;
    };
    std::fill(layout.slotSubface.begin() + base, layout.slotSubface.begin() + base + size, d);
    // Copies lie on the boundary: rows 0 and n, columns 0 and n; the rest evaluate themselves.
    for (uint32_t y = 0; y <= n; ++y) {
        const uint32_t row = y * (n + 1);
        if (y == 0 || y == n) {
            for (uint32_t x = 0; x <= n; ++x)
                if (!carry(row + x)) return false;
            continue;
        }
        if (!carry(row) || !carry(row + n)) return false;
        for (uint32_t x = 1; x < n; ++x) layout.source[base + row + x] = base + row + x;
    }
    return true;
}

// The dependents (the inverse of "d copies from o", in ascending order) and the triangles.
void finishLayout(const GpuPlanData& data, GridFactors factors, const OwnerList* owners, const std::vector<uint32_t>& ownerCount,
                  GridLayout& layout) {
    const uint32_t count = uint32_t(data.subfaces.size());
    for ([[maybe_unused]] uint32_t s : layout.source) assert(layout.source[s] == s && "copies come from evaluated slots");
    layout.dependentOffsets.assign(count + 1, 0);
    for (uint32_t d = 0; d < count; ++d)
        for (uint32_t k = 0; k < ownerCount[d]; ++k) ++layout.dependentOffsets[owners[d][k] + 1];
    for (uint32_t d = 0; d < count; ++d) layout.dependentOffsets[d + 1] += layout.dependentOffsets[d];
    layout.dependents.resize(layout.dependentOffsets[count]);
    std::vector<uint32_t> fill(layout.dependentOffsets.begin(), layout.dependentOffsets.end() - 1);
    for (uint32_t d = 0; d < count; ++d)
        for (uint32_t k = 0; k < ownerCount[d]; ++k) layout.dependents[fill[owners[d][k]]++] = d;
    layout.factors = std::move(factors);
    // The triangles last: a coarse macro face's vertices are the slots that evaluate them.
    writeGridIndices(data, layout);
}

}  // namespace

GridLayout buildGridLayout(const GpuPlanData& data, GridFactors factors, GridLayout recycled) {
    GridLayout layout = std::move(recycled);
    const uint32_t count = uint32_t(data.subfaces.size());
    layOutOffsets(factors, count, layout);
    // Only the first ownerCount[d] of each are read: left uninitialised (1.3 MB at 20k sub-faces).
    const auto owners = std::make_unique_for_overwrite<OwnerList[]>(count);
    std::vector<uint32_t> ownerCount(count, 0);
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, count, 64), [&](const tbb::blocked_range<uint32_t>& range) {
        for (uint32_t d = range.begin(); d != range.end(); ++d) layOutSubface(data, factors, d, layout, owners[d], ownerCount[d]);
    });
    finishLayout(data, std::move(factors), owners.get(), ownerCount, layout);
    return layout;
}

GridLayout carryGridLayout(const GpuPlanData& data, GridFactors factors, const GridLayout& before,
                           std::span<const uint32_t> oldOf, std::span<const char> ownersChanged, GridLayout recycled) {
    GridLayout layout = std::move(recycled);
    const uint32_t count = uint32_t(data.subfaces.size());
    assert(oldOf.size() == count && (ownersChanged.empty() || ownersChanged.size() == count));
    const size_t oldCount = before.subfaceOffset.empty() ? 0 : before.subfaceOffset.size() - 1;
    std::vector<uint32_t> newOf(oldCount, UINT32_MAX);
    for (uint32_t d = 0; d < count; ++d)
        if (oldOf[d] != UINT32_MAX) newOf[oldOf[d]] = d;
    layOutOffsets(factors, count, layout);
    std::vector<int64_t> shift(oldCount, kNotCarried);
    for (uint32_t d = 0; d < count; ++d)
        if (oldOf[d] != UINT32_MAX) shift[oldOf[d]] = int64_t(layout.subfaceOffset[d]) - int64_t(before.subfaceOffset[oldOf[d]]);
    const auto owners = std::make_unique_for_overwrite<OwnerList[]>(count);
    std::vector<uint32_t> ownerCount(count, 0);
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, count, 256), [&](const tbb::blocked_range<uint32_t>& range) {
        for (uint32_t d = range.begin(); d != range.end(); ++d) {
            const uint32_t old = oldOf[d];
            if (old != UINT32_MAX && (ownersChanged.empty() || !ownersChanged[d]) &&
                carrySubface(before, shift, newOf, d, old, layout, owners[d], ownerCount[d]))
                continue;
            ownerCount[d] = 0;
            layOutSubface(data, factors, d, layout, owners[d], ownerCount[d]);
        }
    });
    finishLayout(data, std::move(factors), owners.get(), ownerCount, layout);
    return layout;
}

std::vector<uint32_t> subfacesWithNewFactors(const GpuPlanData& data, const GridFactors& before, const GridFactors& after) {
    std::vector<uint32_t> changed;
    for (uint32_t d = 0; d < uint32_t(data.subfaces.size()); ++d) {
        bool differs = before.subfaceFactor[d] != after.subfaceFactor[d];
        for (uint32_t e = 0; e < 4 && !differs; ++e) differs = edgePieces(data, before, d, e) != edgePieces(data, after, d, e);
        if (differs) changed.push_back(d);
    }
    return changed;
}

std::vector<uint32_t> withDependents(const GridLayout& layout, std::span<const uint32_t> drawn) {
    std::vector<uint32_t> out(drawn.begin(), drawn.end());
    for (uint32_t d : drawn)
        out.insert(out.end(), layout.dependents.begin() + layout.dependentOffsets[d],
                   layout.dependents.begin() + layout.dependentOffsets[d + 1]);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

}  // namespace qp
