// QuadPatchSource: the all-quad cage a per-quad patching scheme (ACC-1, ACC-2, Stam) builds its
// patches on, the map from the original cage's (sub-face, u, v) onto it, and the per-vertex
// data those schemes share (1-rings, limit positions and tangents).
//
// The original cage is refined `steps` times with refineOnce (0: used as it is). Patches are
// made for the faces of the refined cage that have a surface: not holes, and not touching the
// boundary when the boundary rule is "none".
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include <glm/geometric.hpp>

#include "mesh/cage.h"
#include "mesh/topology.h"
#include "plans/limit_frame.h"
#include "plans/quad_ring.h"
#include "plans/refine_once.h"

namespace qp {

inline constexpr uint32_t kNoPatch = UINT32_MAX;

struct QuadPatchSource {
    Cage quads;                       // the cage patches are built on: all quads, manifold
    Topology topology;                // of `quads`
    std::vector<RefinedCage> steps;   // the refinements applied, first to last (their cages moved out)
    uint32_t originalSubfaces = 0;    // sub-faces of the original cage
    std::vector<uint32_t> facePatch;  // per face of `quads`: its patch, or kNoPatch
    std::vector<uint32_t> patchFace;  // per patch: its face of `quads`

    // Per vertex of `quads` (empty rings for unused vertices): the ring gathered from its first
    // face, and the limit position and tangents in that ring's order.
    std::vector<QuadRing> rings;
    std::vector<VertexLimit> limits;

    // Tags of `quads` that the smooth patch rules cannot honour (boundary edges excluded).
    uint32_t ignoredCreases = 0, ignoredCorners = 0;

    // Index in rings[vertex] of the face that has `vertex` at its corner `corner`.
    uint32_t ringFace(uint32_t face, uint32_t corner) const;
};

// steps = 0, 1 or 2. Fails with a message when OpenSubdiv rejects the cage or the result is not
// an all-quad manifold cage (e.g. a quad cage with a non-manifold vertex and steps = 0).
Result<QuadPatchSource> prepareQuadPatchSource(const Cage& cage, uint32_t steps, TangentRule rule,
                                               const std::string& source);

// Fewest steps that give an all-quad cage: 0 if it is one already, else 1.
uint32_t stepsToAllQuads(const Cage& cage);

// Where (sub-face, u, v) of the original cage lies on `quads`. `face` may have no patch (holes).
RefinedLocation locateOnQuads(const QuadPatchSource& source, uint32_t subface, double u, double v);

// A quad of `quads` whose four corners are interior vertices of valence 4 (where a per-quad
// scheme's patch is the bicubic B-spline), and one with a corner on the boundary.
bool regularQuad(const QuadPatchSource& source, uint32_t face);
bool boundaryQuad(const QuadPatchSource& source, uint32_t face);

// A patch sample's normal: normalize(du x dv), zero where du and dv are parallel (float or
// double vectors).
template <class Vec>
Vec patchNormal(const Vec& du, const Vec& dv) {
    const Vec n = glm::cross(du, dv);
    const auto length = glm::length(n);
    return length > 0 ? n / length : Vec(0);
}

// A scheme's sample at (sub-face, u, v) of the original cage: evaluatePatch(patch, s, t) of the
// patch it lands on, whose du and dv (float or double vectors) are in the frame of that quad,
// taken back to the sub-face's frame (the normal stays: the map keeps orientation). A default
// sample where the quad has no patch.
template <class EvaluatePatch>
auto evaluateOnQuads(const QuadPatchSource& source, uint32_t subface, double u, double v, EvaluatePatch evaluatePatch) {
    using Sample = std::invoke_result_t<EvaluatePatch, uint32_t, double, double>;
    const RefinedLocation loc = locateOnQuads(source, subface, u, v);
    const uint32_t patch = source.facePatch[loc.face];
    if (patch == kNoPatch) return Sample{};
    Sample sample = evaluatePatch(patch, loc.s, loc.t);
    using Real = typename decltype(sample.du)::value_type;
    const auto ds = sample.du, dt = sample.dv;
    sample.du = Real(loc.dsdu) * ds + Real(loc.dtdu) * dt;
    sample.dv = Real(loc.dsdv) * ds + Real(loc.dtdv) * dt;
    return sample;
}

// The set-up counts a per-quad scheme's stats share (patches, controlPoints, refinementSteps,
// ignoredCreases, ignoredCorners, setupMilliseconds): one patch per entry of source.patchFace,
// and the time since `start`.
template <class Stats>
void countQuadPatches(Stats& stats, const QuadPatchSource& source, size_t controlPoints,
                      std::chrono::steady_clock::time_point start) {
    stats.patches = uint32_t(source.patchFace.size());
    stats.controlPoints = uint32_t(controlPoints);
    stats.refinementSteps = uint32_t(source.steps.size());
    stats.ignoredCreases = source.ignoredCreases;
    stats.ignoredCorners = source.ignoredCorners;
    stats.setupMilliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// The patches of a scheme with Patches::kControlPointsPerPatch points per quad of the fewest
// steps to an all-quad cage (ACC-1, ACC-2; tangents by `rule`): buildPatch(source, face, points)
// writes the points of each patch's quad, and the stats get countQuadPatches' counts and the
// regular and boundary patches.
template <class Patches, class BuildPatch>
Result<Patches> buildQuadPatches(const Cage& cage, TangentRule rule, const std::string& source, BuildPatch buildPatch) {
    const auto start = std::chrono::steady_clock::now();
    Result<QuadPatchSource> prepared = prepareQuadPatchSource(cage, stepsToAllQuads(cage), rule, source);
    if (!prepared) return prepared.error();
    Patches out;
    out.source = std::move(prepared).value();
    const QuadPatchSource& src = out.source;
    out.controlPoints.resize(src.patchFace.size() * Patches::kControlPointsPerPatch);
    for (uint32_t patch = 0; patch < src.patchFace.size(); ++patch) {
        const uint32_t face = src.patchFace[patch];
        out.stats.regularPatches += regularQuad(src, face);
        out.stats.boundaryPatches += boundaryQuad(src, face);
        buildPatch(src, face, &out.controlPoints[size_t(patch) * Patches::kControlPointsPerPatch]);
    }
    countQuadPatches(out.stats, src, out.controlPoints.size(), start);
    return out;
}

}  // namespace qp
