#include "displacement_transfer.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <optional>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <tbb/parallel_for.h>

#include "displaced_picker.h"
#include "sculpt_samples.h"
#include "topology_edits.h"

namespace qp {

namespace {

// Every sample a sub-face's D reads, with its (u, v) on the sub-face: the grid points, and where
// an edge is finer than the grid its segments' samples (and a split edge's midpoint).
template <class F>
void forEachSubfaceSample(const DisplacementLayout& layout, uint32_t subface, std::vector<uint32_t>& grid, const F& f) {
    const DisplacementSubface& sf = layout.subfaces[subface];
    const uint32_t R = sf.resolution, side = R + 1;
    grid.resize(side * side);
    gridSamples(layout, subface, grid.data());
    for (uint32_t j = 0; j <= R; ++j)
        for (uint32_t i = 0; i <= R; ++i) f(grid[j * side + i], float(i) / float(R), float(j) / float(R));
    for (uint32_t e = 0; e < 4; ++e) {
        const DisplacementEdge& edge = sf.edges[e];
        if (!(edge.flags & kEdgeFiner)) continue;
        const bool split = edge.flags & kEdgeSplit;
        for (uint32_t half = 0; half < (split ? 2u : 1u); ++half) {
            const DisplacementSegment& segment = layout.segments[half ? edge.secondHalf : edge.segment];
            for (uint32_t k = 1; k < segment.resolution; ++k) {
                const glm::vec2 uv = edgePoint(e, edgeParameter(edge, half, k, segment.resolution));
                f(segment.offset + k - 1, uv.x, uv.y);
            }
        }
        if (split) {
            const glm::vec2 uv = edgePoint(e, 0.5f);
            f(layout.segments[edge.segment].pointB, uv.x, uv.y);
        }
    }
}

// Whether each sub-face after the edit keeps its limit surface (and so its samples).
std::vector<bool> keptSubfaces(const PlannedCage& after, const EditReport& report) {
    std::vector<bool> kept(after.subfaceCount(), false);
    for (uint32_t s = 0; s < after.subfaceCount(); ++s) kept[s] = report.previousSubfaceOf[s] != kNewElement;
    for (uint32_t s : report.updatedSubfaceList) kept[s] = false;
    return kept;
}

// Per sub-face after the edit: kept ones their old resolution, changed ones the finest kept
// resolution at their corners, or the old displacement's finest.
std::vector<uint32_t> transferResolutions(const DisplacementLayout& corners, const Displacement& old,
                                          const std::vector<bool>& kept, const EditReport& report) {
    uint32_t finest = 1;
    for (const DisplacementSubface& sf : old.layout.subfaces) finest = std::max(finest, sf.resolution);
    const uint32_t count = uint32_t(corners.subfaces.size());
    std::vector<uint32_t> resolutions(count, 0), pointFinest(corners.pointCount, 0);
    for (uint32_t s = 0; s < count; ++s) {
        if (!kept[s]) continue;
        resolutions[s] = old.layout.subfaces[report.previousSubfaceOf[s]].resolution;
        for (uint32_t p : corners.subfaces[s].corners) pointFinest[p] = std::max(pointFinest[p], resolutions[s]);
    }
    for (uint32_t s = 0; s < count; ++s) {
        if (kept[s]) continue;
        uint32_t r = 0;
        for (uint32_t p : corners.subfaces[s].corners) r = std::max(r, pointFinest[p]);
        resolutions[s] = r ? r : finest;
    }
    return resolutions;
}

// The old sub-faces the changed ones may project onto: those whose surface the edit changed or
// removed, and every sub-face of a face sharing a vertex with theirs.
std::vector<uint32_t> oldNeighbourhood(const PlannedCage& before, const std::vector<bool>& kept, const EditReport& report) {
    std::vector<bool> keptOld(before.subfaceCount(), false);
    for (uint32_t s = 0; s < kept.size(); ++s)
        if (kept[s]) keptOld[report.previousSubfaceOf[s]] = true;
    const Cage& cage = before.cage();
    const Topology& topology = before.topology();
    std::vector<bool> nearFace(cage.faceCount(), false), atVertex(cage.vertexCount(), false);
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        bool changed = false;
        for (uint32_t s = before.firstSubface(f); s < before.firstSubface(f + 1); ++s) changed |= !keptOld[s];
        if (!changed) continue;
        for (uint32_t i = 0; i < cage.faceSize(f); ++i) atVertex[cage.faceBegin(f)[i]] = true;
    }
    for (uint32_t v = 0; v < cage.vertexCount(); ++v) {
        if (!atVertex[v]) continue;
        for (uint32_t k = topology.vertexFaceOffsets[v]; k < topology.vertexFaceOffsets[v + 1]; ++k)
            nearFace[topology.vertexFaces[k]] = true;
    }
    std::vector<uint32_t> subfaces;
    for (uint32_t f = 0; f < cage.faceCount(); ++f)
        if (nearFace[f])
            for (uint32_t s = before.firstSubface(f); s < before.firstSubface(f + 1); ++s) subfaces.push_back(s);
    return subfaces;
}

// Half the mean cage edge length of the changed faces: how far an edit of this kind moves the
// limit surface at most, roughly (an edge loop or a deleted neighbour changes it by a fraction of
// the local edge length).
float changedFaceScale(const PlannedCage& after, const std::vector<bool>& kept) {
    const Cage& cage = after.cage();
    double total = 0.0;
    uint32_t edges = 0;
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        bool changed = false;
        for (uint32_t s = after.firstSubface(f); s < after.firstSubface(f + 1); ++s) changed |= !kept[s];
        if (!changed) continue;
        const uint32_t* vs = cage.faceBegin(f);
        for (uint32_t i = 0, n = cage.faceSize(f); i < n; ++i, ++edges)
            total += glm::length(cage.positions[vs[(i + 1) % n]] - cage.positions[vs[i]]);
    }
    return edges ? float(0.5 * total / edges) : 0.0f;
}

Displacement maskAsDisplacement(const Displacement& d) {
    Displacement mask;
    mask.layout = d.layout;
    mask.samples = d.mask;
    return mask;
}

// Where the line p + t N, |t| <= reach, meets the old limit surface nearest to p.
std::optional<DisplacedPicker::Hit> project(const DisplacedPicker& picker, const PlannedCage& before, const glm::vec3& p,
                                            const glm::vec3& n, float reach) {
    // Both rays start a hair behind p, so a surface through p itself is met by one of them.
    const float hair = 1e-4f * reach;
    const Displacement none;
    std::optional<DisplacedPicker::Hit> best;
    float bestT = reach;
    for (float sign : {1.0f, -1.0f}) {
        // The second ray need not look further than the first one's hit.
        const DisplacedPicker::Hit hit = picker.intersect(before, none, Ray{p - sign * hair * n, sign * n}, bestT + hair);
        if (hit.subface == kNoHit) continue;
        const float t = std::abs(glm::dot(hit.position - p, n));
        if (!std::isfinite(t) || t > bestT) continue;
        best = hit, bestT = t;
    }
    return best;
}

struct OldPlace {
    uint32_t subface;
    float u, v;
};

// Newton's method on one old sub-face for s(u, v) = p + t n, from `start`: the place, when it
// converges inside the sub-face with |t| <= reach. Neighbouring samples meet the old surface at
// neighbouring places, so a sample starts where the one before it landed and needs no ray cast.
std::optional<OldPlace> newtonOnSubface(const PlannedCage& before, const OldPlace& start, const glm::vec3& p,
                                        const glm::vec3& n, float reach) {
    constexpr int kIterations = 8;
    constexpr float kInside = 1e-4f;
    glm::vec3 x(start.u, start.v, 0.0f);
    for (int k = 0; k < kIterations; ++k) {
        const LimitSample s = before.evaluate(start.subface, x.x, x.y);
        const glm::vec3 f = s.position - p - x.z * n;
        const float scale = glm::length(s.du) + glm::length(s.dv);
        if (glm::length(f) <= 1e-6f * scale) {
            if (std::abs(x.z) > reach) return std::nullopt;
            return OldPlace{start.subface, std::clamp(x.x, 0.0f, 1.0f), std::clamp(x.y, 0.0f, 1.0f)};
        }
        const glm::mat3 jacobian(s.du, s.dv, -n);
        if (std::abs(glm::determinant(jacobian)) <= 1e-12f * scale * scale) return std::nullopt;
        x -= glm::inverse(jacobian) * f;
        if (!(x.x >= -kInside && x.x <= 1.0f + kInside && x.y >= -kInside && x.y <= 1.0f + kInside)) return std::nullopt;
    }
    return std::nullopt;
}

}  // namespace

DisplacementTransfer transferDisplacement(const PlannedCage& before, const Displacement& old, const PlannedCage& after,
                                          const EditReport& report) {
    assert(!old.empty() && report.previousSubfaceOf.size() == after.subfaceCount());
    DisplacementTransfer out;
    const std::vector<bool> kept = keptSubfaces(after, report);
    const DisplacementLayout corners = buildDisplacementLayout(after.cage(), after.topology(), 1);
    Displacement& next = out.displacement;
    next.layout = withResolutions(corners, transferResolutions(corners, old, kept, report));
    next.samples.assign(next.layout.sampleCount, 0.0f);
    const bool masked = old.hasMask();
    const Displacement oldMask = masked ? maskAsDisplacement(old) : Displacement{};
    if (masked) next.mask.assign(next.layout.sampleCount, 0.0f);

    // Kept sub-faces: every sample they read takes the old D at its place, which at a stored
    // sample's place is that sample's value exactly (evaluateDisplacement interpolates with
    // weights 0 and 1 there).
    std::vector<bool> assigned(next.layout.sampleCount, false);
    std::vector<uint32_t> grid;
    for (uint32_t s = 0; s < after.subfaceCount(); ++s) {
        if (!kept[s]) continue;
        ++out.keptSubfaces;
        const uint32_t from = report.previousSubfaceOf[s];
        forEachSubfaceSample(next.layout, s, grid, [&](uint32_t sample, float u, float v) {
            next.samples[sample] = evaluateDisplacement(old, from, u, v).value;
            if (masked) next.mask[sample] = evaluateDisplacement(oldMask, from, u, v).value;
            assigned[sample] = true;
        });
    }
    out.changedSubfaces = after.subfaceCount() - out.keptSubfaces;
    if (out.changedSubfaces == 0) return out;

    // Changed sub-faces: the rest, each at its owner's site, from the old D where the site's
    // normal line meets the old limit surface.
    out.reach = changedFaceScale(after, kept);
    // A coarse sampling of the limit surface will do: Newton's refinement finds the surface
    // itself, and the ray casts' triangle tests are most of the transfer's time.
    constexpr uint32_t kPickResolution = 4;
    const DisplacedPicker picker(before, Displacement{}, oldNeighbourhood(before, kept, report), kPickResolution);
    const std::vector<SampleSite> sites = computeSampleSites(next.layout, after);
    // The samples to project, by the new sub-face their site is on, in sample order.
    std::vector<uint32_t> open, groupOffsets(after.subfaceCount() + 1, 0);
    for (uint32_t i = 0; i < next.layout.sampleCount; ++i)
        if (!assigned[i] && sites[i].subface != kNoSite) ++groupOffsets[sites[i].subface + 1];
    for (uint32_t g = 0; g < after.subfaceCount(); ++g) groupOffsets[g + 1] += groupOffsets[g];
    open.resize(groupOffsets.back());
    std::vector<uint32_t> fill(groupOffsets.begin(), groupOffsets.end() - 1);
    for (uint32_t i = 0; i < next.layout.sampleCount; ++i)
        if (!assigned[i] && sites[i].subface != kNoSite) open[fill[sites[i].subface]++] = i;
    std::vector<uint8_t> reached(open.size(), 0);
    tbb::parallel_for(uint32_t(0), after.subfaceCount(), [&](uint32_t group) {
        std::optional<OldPlace> previous;
        for (uint32_t k = groupOffsets[group]; k < groupOffsets[group + 1]; ++k) {
            const uint32_t i = open[k];
            const SampleSite& site = sites[i];
            const LimitSample limit = after.evaluate(site.subface, site.u, site.v);
            const glm::vec3 normal = limitNormal(after, site.subface, site.u, site.v, limit);
            std::optional<OldPlace> place =
                previous ? newtonOnSubface(before, *previous, limit.position, normal, out.reach) : std::nullopt;
            if (!place)
                if (const std::optional<DisplacedPicker::Hit> hit = project(picker, before, limit.position, normal, out.reach))
                    place = OldPlace{hit->subface, hit->u, hit->v};
            if (!place) continue;
            previous = place;
            reached[k] = 1;
            next.samples[i] = evaluateDisplacement(old, place->subface, place->u, place->v).value + 0.0f;
            if (masked)
                next.mask[i] = std::clamp(evaluateDisplacement(oldMask, place->subface, place->u, place->v).value, 0.0f, 1.0f);
        }
    });
    for (uint8_t r : reached) r ? ++out.projectedSamples : ++out.unreachedSamples;
    return out;
}

}  // namespace qp
