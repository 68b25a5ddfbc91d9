#include "sample_culling.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <cstring>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace qp {

namespace {

// A vertex in framebuffer pixels, or unsure (the clipper's business: behind the eye, outside
// the depth range, not finite, or so far out that float pixels lose the margin).
struct Pixel {
    float x, y;
    bool sure;
};

constexpr float kFarOut = 1e6f;  // pixels from the viewport's origin

Pixel project(const glm::vec3& p, const SampleView& view) {
    const glm::vec4 c = view.viewProjection * glm::vec4(p, 1.0f);
    // Negated so that NaN is unsure too.
    if (!(c.w > 0.0f && c.z >= 0.0f && c.z <= c.w)) return {0.0f, 0.0f, false};
    const float x = float(view.x) + (c.x / c.w + 1.0f) * 0.5f * float(view.width);
    const float y = float(view.y) + (c.y / c.w + 1.0f) * 0.5f * float(view.height);
    if (!(std::abs(x) < kFarOut && std::abs(y) < kFarOut)) return {0.0f, 0.0f, false};
    return {x, y, true};
}

// A chunk whose triangles read a run of more slots than this per triangle (coarse macro faces
// read their members' corners, far apart) does not project the run first.
constexpr uint32_t kMostSlotsPerTriangle = 4;
// Projections remembered by slot (slot modulo this) by such a chunk.
constexpr uint32_t kRecentProjections = 4096;
struct RecentProjection {
    uint32_t slot = UINT32_MAX;
    Pixel pixel;
};

// At most this many pixel centres near a triangle are tested one by one; a larger one is kept.
constexpr int kMostCentres = 16;

bool mayCover(const Pixel& a, const Pixel& b, const Pixel& c, const SampleView& view) {
    if (!a.sure || !b.sure || !c.sure) return true;
    // Pixel centres (i + 0.5, j + 0.5) within the margin of the triangle's bounds, in the viewport.
    const float m = kSampleMargin;
    const int i0 = std::max(int(std::ceil(std::min({a.x, b.x, c.x}) - m - 0.5f)), view.x);
    const int i1 = std::min(int(std::floor(std::max({a.x, b.x, c.x}) + m - 0.5f)), view.x + int(view.width) - 1);
    const int j0 = std::max(int(std::ceil(std::min({a.y, b.y, c.y}) - m - 0.5f)), view.y);
    const int j1 = std::min(int(std::floor(std::max({a.y, b.y, c.y}) + m - 0.5f)), view.y + int(view.height) - 1);
    if (i0 > i1 || j0 > j1) return false;
    if ((i1 - i0 + 1) * (j1 - j0 + 1) > kMostCentres) return true;
    const float area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (!(std::abs(area) >= kTinyArea)) return true;
    const float sign = area > 0.0f ? 1.0f : -1.0f;
    // Inside an edge p -> q, or within the margin outside it (signed distance >= -m).
    auto inside = [&](const Pixel& p, const Pixel& q, float x, float y) {
        const float ex = q.x - p.x, ey = q.y - p.y;
        return sign * (ex * (y - p.y) - ey * (x - p.x)) >= -m * std::sqrt(ex * ex + ey * ey);
    };
    for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
            const float x = float(i) + 0.5f, y = float(j) + 0.5f;
            if (inside(a, b, x, y) && inside(b, c, x, y) && inside(c, a, x, y)) return true;
        }
    return false;
}

static_assert(sizeof(glm::vec3) == 3 * sizeof(float));

// Bit for bit, as the device receives them (float == would call +0 and -0 the same).
bool samePosition(const glm::vec3& a, const glm::vec3& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

glm::vec3 positionOf(const GridVertex& v) { return {v.position[0], v.position[1], v.position[2]}; }

// Index ranges (first index, count; empty: all) as sorted triangle ranges [first, end).
std::vector<std::pair<uint32_t, uint32_t>> drawnTriangles(std::span<const std::pair<uint32_t, uint32_t>> ranges,
                                                          uint32_t triangles) {
    std::vector<std::pair<uint32_t, uint32_t>> drawn;
    if (ranges.empty()) drawn.push_back({0, triangles});
    for (const auto& [first, count] : ranges)
        if (count) drawn.push_back({first / 3, (first + count) / 3});
    return drawn;
}

// The triangle ranges [first, end) drawn by one of `a` and `b` and not the other (each sorted,
// ranges apart).
std::vector<std::pair<uint32_t, uint32_t>> differingTriangles(const std::vector<std::pair<uint32_t, uint32_t>>& a,
                                                              const std::vector<std::pair<uint32_t, uint32_t>>& b) {
    std::vector<std::pair<uint32_t, int>> edges;  // (triangle, +1 / -1): where a range starts or ends
    for (const auto* list : {&a, &b})
        for (const auto& [first, end] : *list) {
            edges.push_back({first, 1});
            edges.push_back({end, -1});
        }
    std::sort(edges.begin(), edges.end());
    std::vector<std::pair<uint32_t, uint32_t>> differing;
    int covering = 0;  // ranges of a and b holding the triangles after the last edge
    for (size_t k = 0; k < edges.size(); ++k) {
        covering += edges[k].second;
        const uint32_t from = edges[k].first, to = k + 1 < edges.size() ? edges[k + 1].first : from;
        if (covering == 1 && from < to) {
            if (!differing.empty() && differing.back().second == from) differing.back().second = to;
            else differing.push_back({from, to});
        }
    }
    return differing;
}

// What facingAway says of a triangle.
enum class Facing : uint8_t { Shown, HiddenAway, NotDrawn };

// Per triangle of `layout`: NotDrawn outside `drawn` (triangle ranges), HiddenAway when it faces
// away from `eye` and none of its corners (by the evaluated slot each shows) is a corner of a
// drawn triangle that does not (sample_culling.h, "Facing away"), else Shown.
std::vector<Facing> facingAway(const GridLayout& layout, const GridVertex* vertices, const glm::vec4& eye,
                               const std::vector<std::pair<uint32_t, uint32_t>>& drawn) {
    const std::vector<uint32_t>& indices = layout.indices;
    std::vector<Facing> facing(indices.size() / 3, Facing::NotDrawn);
    std::vector<uint8_t> cornerOfShown(layout.slotCount(), 0);  // per evaluated slot
    auto overDrawn = [&](auto&& visit) {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, drawn.size(), 1), [&](const tbb::blocked_range<size_t>& runs) {
            for (size_t r = runs.begin(); r < runs.end(); ++r)
                for (uint32_t t = drawn[r].first; t < drawn[r].second; ++t) visit(t, indices.data() + 3 * size_t(t));
        });
    };
    overDrawn([&](uint32_t t, const uint32_t* tri) {
        const bool away = facesAwayFrom(positionOf(vertices[tri[0]]), positionOf(vertices[tri[1]]), positionOf(vertices[tri[2]]), eye);
        facing[t] = away ? Facing::HiddenAway : Facing::Shown;
        if (!away)
            for (int k = 0; k < 3; ++k) std::atomic_ref<uint8_t>(cornerOfShown[layout.source[tri[k]]]).store(1, std::memory_order_relaxed);
    });
    overDrawn([&](uint32_t t, const uint32_t* tri) {
        if (facing[t] == Facing::HiddenAway &&
            (cornerOfShown[layout.source[tri[0]]] || cornerOfShown[layout.source[tri[1]]] || cornerOfShown[layout.source[tri[2]]]))
            facing[t] = Facing::Shown;
    });
    return facing;
}

}  // namespace

bool facesAwayFrom(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec4& eye) {
    const glm::dvec3 pa(a), e = glm::dvec3(glm::dvec3(eye)) - pa * double(eye.w);
    const glm::dvec3 normal = glm::cross(glm::dvec3(b) - pa, glm::dvec3(c) - pa);
    return glm::dot(normal, e) < -kFacingMargin * glm::length(normal) * glm::length(e);
}

bool mayCoverPixelCentre(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const SampleView& view) {
    if (samePosition(a, b) || samePosition(b, c) || samePosition(c, a)) return false;
    return mayCover(project(a, view), project(b, view), project(c, view), view);
}

void markSlotsChanged(SampleCulling& culling, const GridLayout& layout, std::span<const uint32_t> drawn) {
    if (!culling.valid) return;
    // Many moves while nothing is culled (a long drag at a density below the gate): testing
    // everything again later is cheaper than keeping the list.
    if (culling.changedSlots.size() + drawn.size() > kMostChangedRanges) return invalidateSampleCulling(culling);
    for (uint32_t d : drawn) {
        const uint32_t first = layout.subfaceOffset[d], end = layout.subfaceOffset[d + 1];
        if (!culling.changedSlots.empty() && culling.changedSlots.back().second == first) culling.changedSlots.back().second = end;
        else culling.changedSlots.push_back({first, end});
    }
}

void carrySampleCulling(SampleCulling& culling, const GridLayout& before, const GridLayout& after,
                        std::span<const uint32_t> oldOf) {
    auto coarseMacros = [](const GridLayout& layout) {
        const std::vector<uint32_t>& resolution = layout.factors.macroResolution;
        return std::any_of(resolution.begin(), resolution.end(), [](uint32_t r) { return r != 0; });
    };
    const uint32_t oldTriangles = before.indexOffset.empty() ? 0 : before.indexOffset.back() / 3;
    if (!culling.valid || before.subfaceOffset.empty() || culling.triangleResult.size() != oldTriangles ||
        coarseMacros(before) || coarseMacros(after))
        return invalidateSampleCulling(culling);
    // Slots written since the last test (a move before the relayout), in the old numbering: their
    // sub-faces are tested again in the new one.
    const std::vector<uint32_t>& oldOffset = before.subfaceOffset;
    std::vector<char> written(oldOffset.size() - 1, 0);
    for (const auto& [first, end] : culling.changedSlots)
        for (size_t o = size_t(std::upper_bound(oldOffset.begin(), oldOffset.end(), first) - oldOffset.begin()) - 1;
             o < written.size() && oldOffset[o] < end; ++o)
            written[o] = 1;
    culling.changedSlots.clear();
    const std::vector<uint8_t> carried = std::move(culling.triangleResult);
    const uint32_t triangles = uint32_t(after.indices.size() / 3);
    culling.triangleResult.assign(triangles, 0);
    std::vector<uint32_t> renewed;  // drawn sub-faces laid out anew or written: tested at the next update
    for (uint32_t d = 0; d < uint32_t(oldOf.size()); ++d) {
        const uint32_t old = oldOf[d];
        const uint32_t count = (after.indexOffset[d + 1] - after.indexOffset[d]) / 3;
        // Single faces of one factor have the same triangles over their own slots.
        if (old != UINT32_MAX && !written[old] && before.factors.subfaceFactor[old] == after.factors.subfaceFactor[d] &&
            (before.indexOffset[old + 1] - before.indexOffset[old]) / 3 == count)
            std::memcpy(culling.triangleResult.data() + after.indexOffset[d] / 3, carried.data() + before.indexOffset[old] / 3, count);
        else
            renewed.push_back(d);
    }
    markSlotsChanged(culling, after, renewed);
    if (!culling.valid) return;  // too many to list
    // Each chunk's slot bounds over its new triangles; its kept triangles are written again.
    const uint32_t chunks = (triangles + culling.chunkTriangles - 1) / culling.chunkTriangles;
    culling.chunkKept.assign(chunks, 0);
    culling.chunkFacingAway.assign(chunks, 0);
    culling.chunkSlotMin.assign(chunks, 0);
    culling.chunkSlotMax.assign(chunks, 0);
    tbb::parallel_for(uint32_t(0), chunks, [&](uint32_t c) {
        const uint32_t begin = c * culling.chunkTriangles, end = std::min(begin + culling.chunkTriangles, triangles);
        const auto [low, high] = std::minmax_element(after.indices.begin() + 3 * size_t(begin), after.indices.begin() + 3 * size_t(end));
        culling.chunkSlotMin[c] = *low;
        culling.chunkSlotMax[c] = *high;
    });
    culling.rewriteAll = true;
}

std::vector<std::pair<uint32_t, uint32_t>> updateSampleCulling(SampleCulling& culling, const GridLayout& layout,
                                                               const GridVertex* vertices, const SampleView& view,
                                                               std::span<const std::pair<uint32_t, uint32_t>> drawnRanges,
                                                               uint32_t* culledIndices) {
    const std::vector<uint32_t>& indices = layout.indices;
    const uint32_t triangles = uint32_t(indices.size() / 3);
    const uint32_t chunkTriangles = culling.chunkTriangles;
    assert(chunkTriangles > 0);
    const uint32_t chunks = (triangles + chunkTriangles - 1) / chunkTriangles;
    // With back faces hidden a triangle's result depends on its neighbours': any change tests everything.
    const bool everything = !culling.valid || !(culling.view == view) || culling.chunkKept.size() != chunks ||
                            culling.triangleResult.size() != triangles ||
                            (view.backFacesHidden && (culling.rewriteAll || !culling.changedSlots.empty() ||
                                                      !std::equal(drawnRanges.begin(), drawnRanges.end(),
                                                                  culling.drawnRanges.begin(), culling.drawnRanges.end())));
    // Triangle ranges drawn: [first, end) in triangles, sorted.
    const std::vector<std::pair<uint32_t, uint32_t>> drawn = drawnTriangles(drawnRanges, triangles);
    // Per chunk: 2 tested and written, 1 written from the kept results, 0 as it is.
    std::vector<char> work(chunks, everything ? 2 : 0);
    if (everything) {
        culling.chunkKept.assign(chunks, 0);
        culling.chunkFacingAway.assign(chunks, 0);
        culling.chunkSlotMin.assign(chunks, 0);
        culling.chunkSlotMax.assign(chunks, 0);
        culling.triangleResult.assign(triangles, 0);
        culling.view = view;
    } else {
        // Carried through a relayout: every chunk's triangles moved (the drawn ranges kept are
        // the old layout's). Else faces hidden or shown (a hole made or filled): the chunks where
        // what is drawn changed.
        if (culling.rewriteAll) std::fill(work.begin(), work.end(), 1);
        else
            for (const auto& [first, end] : differingTriangles(drawnTriangles(culling.drawnRanges, triangles), drawn))
                std::fill(work.begin() + first / chunkTriangles, work.begin() + (end - 1) / chunkTriangles + 1, 1);
        for (uint32_t c = 0; c < chunks; ++c)
            for (const auto& [first, end] : culling.changedSlots)
                if (first <= culling.chunkSlotMax[c] && culling.chunkSlotMin[c] < end) {
                    work[c] = 2;
                    break;
                }
    }
    std::vector<uint32_t> dirty;
    for (uint32_t c = 0; c < chunks; ++c)
        if (work[c]) dirty.push_back(c);
    culling.drawnRanges.assign(drawnRanges.begin(), drawnRanges.end());
    culling.changedSlots.clear();
    culling.rewriteAll = false;
    culling.valid = true;

    // With back faces hidden (and so everything tested) the facing goes first: triangles it leaves
    // out, and those not drawn, need no pixel centres.
    const std::vector<Facing> facing = view.backFacesHidden ? facingAway(layout, vertices, view.eye, drawn) : std::vector<Facing>{};
    std::atomic<uint64_t> tested{0};
    tbb::parallel_for(tbb::blocked_range<size_t>(0, dirty.size(), 1), [&](const tbb::blocked_range<size_t>& range) {
        std::vector<Pixel> projected;
        std::vector<RecentProjection> recent;
        for (size_t k = range.begin(); k < range.end(); ++k) {
            const uint32_t c = dirty[k];
            const uint32_t begin = c * chunkTriangles, end = std::min(begin + chunkTriangles, triangles);
            if (everything) {
                const auto [low, high] = std::minmax_element(indices.begin() + 3 * size_t(begin), indices.begin() + 3 * size_t(end));
                culling.chunkSlotMin[c] = *low;
                culling.chunkSlotMax[c] = *high;
            }
            if (work[c] == 2) {
                // Each slot is read by about six triangles: projected once. A chunk of single faces
                // reads a narrow run of slots, projected first; one with coarse macro faces (whose
                // triangles read their members' corners, far apart) remembers recent projections.
                const uint32_t slotMin = culling.chunkSlotMin[c], slots = culling.chunkSlotMax[c] - slotMin + 1;
                const bool narrow = slots <= kMostSlotsPerTriangle * (end - begin);
                if (view.testPixelCentres && narrow) {
                    projected.resize(slots);
                    for (uint32_t i = 0; i < slots; ++i) projected[i] = project(positionOf(vertices[slotMin + i]), view);
                } else if (view.testPixelCentres) {
                    recent.assign(kRecentProjections, RecentProjection{});
                }
                auto pixelOf = [&](uint32_t slot) {
                    if (narrow) return projected[slot - slotMin];
                    RecentProjection& r = recent[slot % kRecentProjections];
                    if (r.slot != slot) r = {slot, project(positionOf(vertices[slot]), view)};
                    return r.pixel;
                };
                for (uint32_t t = begin; t < end; ++t) {
                    if (!facing.empty() && facing[t] != Facing::Shown) {
                        culling.triangleResult[t] = facing[t] == Facing::HiddenAway ? SampleCulling::kHiddenFacingAway
                                                                                    : SampleCulling::kCoversNothing;
                        continue;
                    }
                    const uint32_t* tri = indices.data() + 3 * size_t(t);
                    const glm::vec3 p0 = positionOf(vertices[tri[0]]), p1 = positionOf(vertices[tri[1]]),
                                    p2 = positionOf(vertices[tri[2]]);
                    const bool covers = !(samePosition(p0, p1) || samePosition(p1, p2) || samePosition(p2, p0)) &&
                                        (!view.testPixelCentres || mayCover(pixelOf(tri[0]), pixelOf(tri[1]), pixelOf(tri[2]), view));
                    culling.triangleResult[t] = covers ? SampleCulling::kCovers : SampleCulling::kCoversNothing;
                }
                tested += end - begin;
            }
            // The drawn triangles that may cover a centre, at the chunk's own place.
            uint32_t* out = culledIndices + 3 * size_t(begin);
            uint32_t kept = 0, away = 0;
            auto run = std::lower_bound(drawn.begin(), drawn.end(), begin,
                                        [](const std::pair<uint32_t, uint32_t>& r, uint32_t t) { return r.second <= t; });
            for (; run != drawn.end() && run->first < end; ++run)
                for (uint32_t t = std::max(run->first, begin), to = std::min(run->second, end); t < to; ++t)
                    if (culling.triangleResult[t] == SampleCulling::kCovers)
                        std::memcpy(out + 3 * size_t(kept++), indices.data() + 3 * size_t(t), 3 * sizeof(uint32_t));
                    else
                        away += culling.triangleResult[t] == SampleCulling::kHiddenFacingAway;
            culling.chunkKept[c] = kept;
            culling.chunkFacingAway[c] = away;
        }
    });
    culling.testedTriangles = tested;

    std::vector<std::pair<uint32_t, uint32_t>> draws;
    culling.keptTriangles = 0;
    culling.facingAwayTriangles = 0;
    for (uint32_t c = 0; c < chunks; ++c) {
        const uint32_t kept = culling.chunkKept[c];
        culling.keptTriangles += kept;
        culling.facingAwayTriangles += culling.chunkFacingAway[c];
        if (!kept) continue;
        const uint32_t first = 3 * c * chunkTriangles;
        if (!draws.empty() && draws.back().first + draws.back().second == first) draws.back().second += 3 * kept;
        else draws.push_back({first, 3 * kept});
    }
    return draws;
}

}  // namespace qp
