#include "displacement/displacement_transfer.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <optional>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <tbb/parallel_for.h>

#include "displacement/displaced_picker.h"
#include "displacement/sculpt_samples.h"
#include "mesh/topology_edits.h"

namespace qp {

namespace {

// Whether each sub-face after the edit keeps its limit surface (and so its samples).
std::vector<bool> keptSubfaces(const PlannedCage& after, const EditReport& report) {
    std::vector<bool> kept(after.subfaceCount(), false);
    for (uint32_t s = 0; s < after.subfaceCount(); ++s) kept[s] = report.previousSubfaceOf[s] != kNewElement;
    for (uint32_t s : report.updatedSubfaceList) kept[s] = false;
    return kept;
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

// Whether any sample (or mask value) these sub-faces' tiles read is not zero.
bool readsNonZero(const Displacement& d, const std::vector<uint32_t>& subfaces) {
    for (uint32_t s : subfaces) {
        const DisplacementTile& tile = d.layout.tiles[s];
        const uint32_t count = (tile.cells + 2) * (tile.cells + 2);
        for (uint32_t k = 0; k < count; ++k) {
            const uint32_t sample = d.layout.padded[tile.offset + k];
            if (d.samples[sample] != 0.0f || (d.hasMask() && d.mask[sample] != 0.0f)) return true;
        }
    }
    return false;
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
    Displacement& next = out.displacement;
    next.layout = buildDisplacementLayout(after.cage(), after.topology(), old.layout.resolution);
    const DisplacementLayout& layout = next.layout;
    next.samples.assign(layout.sampleCount, 0.0f);
    const bool masked = old.hasMask();
    const Displacement oldMask = masked ? maskAsDisplacement(old) : Displacement{};
    if (masked) next.mask.assign(layout.sampleCount, 0.0f);

    // Kept sub-faces: their own cells take the old tile's samples, bit for bit (same cells: the
    // sub-face and R are the same). A shared corner sample is the same old sample from every
    // kept tile around it.
    std::vector<bool> assigned(layout.sampleCount, false);
    for (uint32_t s = 0; s < after.subfaceCount(); ++s) {
        if (!kept[s]) continue;
        ++out.keptSubfaces;
        const uint32_t from = report.previousSubfaceOf[s];
        const int n = int(layout.tiles[s].cells);
        if (old.layout.tiles[from].cells != uint32_t(n)) continue;  // not met: a kept sub-face keeps its kind
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const uint32_t sample = layout.sampleAt(s, i, j), previous = old.layout.sampleAt(from, i, j);
                next.samples[sample] = old.samples[previous];
                if (masked) next.mask[sample] = old.mask[previous];
                assigned[sample] = true;
            }
    }
    out.changedSubfaces = after.subfaceCount() - out.keptSubfaces;
    if (out.changedSubfaces == 0) return out;

    // Changed sub-faces: the samples living there are fitted (fitSamples' quasi-interpolant) to
    // the old D at the places where the normal lines of the new limit surface meet the old one,
    // on a grid of half cells per changed tile (each cell's centre, edge midpoints and corners).
    out.reach = changedFaceScale(after, kept);
    // Projections land on the old sub-faces around the edit only: where D and the mask are zero
    // on all of them (an edit away from the sculpt), every changed sample is zero, as made.
    const std::vector<uint32_t> neighbourhood = oldNeighbourhood(before, kept, report);
    if (!readsNonZero(old, neighbourhood)) return out;
    // A coarse sampling of the limit surface will do: Newton's refinement finds the surface
    // itself, and the ray casts' triangle tests are most of the transfer's time.
    constexpr uint32_t kPickResolution = 4;
    const DisplacedPicker picker(before, Displacement{}, neighbourhood, kPickResolution);
    std::vector<uint32_t> changed;
    for (uint32_t s = 0; s < after.subfaceCount(); ++s)
        if (!kept[s] && after.hasSurface(s)) changed.push_back(s);
    std::vector<uint32_t> reachedCounts(changed.size(), 0), unreachedCounts(changed.size(), 0);
    tbb::parallel_for(size_t(0), changed.size(), [&](size_t c) {
        const uint32_t t = changed[c];
        const uint32_t n = layout.tiles[t].cells, side = 2 * n + 1;
        std::vector<std::optional<OldPlace>> places(size_t(side) * side);
        std::optional<OldPlace> previous;
        for (uint32_t b = 0; b < side; ++b)
            for (uint32_t a = 0; a < side; ++a) {
                const float u = float(a) / float(2 * n), v = float(b) / float(2 * n);
                const LimitSample limit = after.evaluate(t, u, v);
                const glm::vec3 normal = limitNormal(after, t, u, v, limit);
                std::optional<OldPlace> place =
                    previous ? newtonOnSubface(before, *previous, limit.position, normal, out.reach) : std::nullopt;
                if (!place)
                    if (const std::optional<DisplacedPicker::Hit> hit = project(picker, before, limit.position, normal, out.reach))
                        place = OldPlace{hit->subface, hit->u, hit->v};
                if (place) previous = place;
                places[b * side + a] = place;
            }
        auto valueAt = [&](const Displacement& d, uint32_t a, uint32_t b) {
            const std::optional<OldPlace>& place = places[b * side + a];
            return place ? evaluateDisplacement(d, place->subface, place->u, place->v).value : 0.0f;
        };
        constexpr float kWeights[3] = {-0.5f, 2.0f, -0.5f};
        auto fit = [&](const Displacement& d, const SampleHome& home) {
            if (home.corner >= 0) return valueAt(d, kCornerU[home.corner] * 2 * n, kCornerV[home.corner] * 2 * n);
            const uint32_t ca = 2 * uint32_t(home.i) + 1, cb = 2 * uint32_t(home.j) + 1;
            float sum = 0.0f;
            for (int y = 0; y < 3; ++y)
                for (int x = 0; x < 3; ++x) sum += kWeights[x] * kWeights[y] * valueAt(d, ca + x - 1, cb + y - 1);
            return sum;
        };
        for (uint32_t j = 0; j < n; ++j)
            for (uint32_t i = 0; i < n; ++i) {
                const uint32_t sample = layout.sampleAt(t, int(i), int(j));
                const SampleHome& home = layout.homes[sample];
                // Each sample once: from the tile it lives in, at its own cell or shared corner.
                if (assigned[sample] || home.tile != t) continue;
                if (home.corner < 0 && (home.i != int(i) || home.j != int(j))) continue;
                const bool corner = home.corner >= 0;
                const bool reached = corner ? places[size_t(kCornerV[home.corner] * 2 * n) * side +
                                                     size_t(kCornerU[home.corner] * 2 * n)].has_value()
                                            : places[size_t(2 * j + 1) * side + 2 * i + 1].has_value();
                ++(reached ? reachedCounts[c] : unreachedCounts[c]);
                next.samples[sample] = fit(old, home) + 0.0f;
                if (masked) next.mask[sample] = std::clamp(fit(oldMask, home), 0.0f, 1.0f) + 0.0f;
            }
    });
    for (size_t c = 0; c < changed.size(); ++c) {
        out.projectedSamples += reachedCounts[c];
        out.unreachedSamples += unreachedCounts[c];
    }
    return out;
}

}  // namespace qp
