// Shared by the tests of the approximate patching schemes (plugins/*/test_*.cpp) and of the
// core pieces they stand on: the exact limit surface of a cage (subdivision plans), and the
// error of a scheme against it at the same (sub-face, u, v).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "mesh/obj_io.h"
#include "mesh/topology.h"
#include "plans/planned_cage.h"
#include "plans/quad_patch_source.h"
#include "test_cages.h"
#include "test_support.h"

namespace qp::test {

// A cage with its exact limit surface. Heap-allocated so the plan database stays put.
struct ExactSurface {
    Cage cage;
    PlanDatabase database;
    std::unique_ptr<PlannedCage> planned;
    double diagonal = 1.0;
};

inline std::unique_ptr<ExactSurface> makeExactSurface(const Cage& cage, const std::string& name = "test cage") {
    auto surface = std::make_unique<ExactSurface>();
    surface->cage = cage;
    auto planned = PlannedCage::create(cage, surface->database, PlanOptions{}, name);
    EXPECT_TRUE(planned.ok()) << (planned.ok() ? "" : planned.error().message);
    if (!planned.ok()) return nullptr;
    surface->planned = std::make_unique<PlannedCage>(std::move(planned).value());
    surface->diagonal = std::max(double(computeBounds(cage).diagonal()), 1e-30);
    return surface;
}

// Loads ../shared/shapes/<name>.obj (callers skip when the shapes are missing).
inline Cage loadSharedShape(const std::string& name) {
    std::vector<std::string> warnings;
    auto cage = loadObj((sharedShapesDir() / (name + ".obj")).string(), &warnings);
    EXPECT_TRUE(cage.ok()) << name << ": " << (cage.ok() ? "" : cage.error().message);
    return cage.ok() ? std::move(cage).value() : Cage{};
}

// Sub-faces of faces with an interior extraordinary corner whose whole 1-ring (every face
// sharing a vertex with it) is free of boundaries, creases, corners and holes: where the
// schemes' handling of extraordinary vertices alone decides the error.
inline std::function<bool(uint32_t)> smoothExtraordinaryFilter(const Cage& cage) {
    Topology topology = buildTopology(cage);
    std::vector<bool> bad(cage.vertexCount(), false);
    for (const EdgeCrease& c : cage.creases) bad[c.v0] = bad[c.v1] = true;
    for (const VertexCorner& c : cage.corners) bad[c.vertex] = true;
    for (uint32_t e = 0; e < topology.edgeCount(); ++e)
        if (topology.edgeFaceCount(e) != 2) bad[topology.edgeVertices[2 * e]] = bad[topology.edgeVertices[2 * e + 1]] = true;
    for (uint32_t h : cage.holes)
        for (uint32_t k = 0; k < cage.faceSize(h); ++k) bad[cage.faceBegin(h)[k]] = true;
    std::vector<bool> faceOk(cage.faceCount(), false);
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        bool extraordinary = false, clean = true;
        for (uint32_t k = 0; k < cage.faceSize(f); ++k) {
            uint32_t v = cage.faceBegin(f)[k];
            extraordinary |= topology.vertexEdgeCount(v) != 4;
            for (uint32_t i = topology.vertexFaceOffsets[v]; i < topology.vertexFaceOffsets[v + 1]; ++i) {
                uint32_t g = topology.vertexFaces[i];
                for (uint32_t m = 0; m < cage.faceSize(g); ++m) clean &= !bad[cage.faceBegin(g)[m]];
            }
        }
        faceOk[f] = extraordinary && clean;
    }
    std::vector<bool> subfaceOk;
    for (uint32_t f = 0; f < cage.faceCount(); ++f)
        for (uint32_t k = 0; k < (cage.faceSize(f) == 4 ? 1u : cage.faceSize(f)); ++k) subfaceOk.push_back(faceOk[f]);
    return [subfaceOk](uint32_t s) { return s < subfaceOk.size() && subfaceOk[s]; };
}

// What a scheme returns at one (sub-face, u, v), in double.
struct SchemeSample {
    glm::dvec3 position{0.0}, normal{0.0};
};
using SchemeEvaluator = std::function<SchemeSample(uint32_t subface, double u, double v)>;
// Which sub-faces to measure (all with a surface when empty).
using SubfaceFilter = std::function<bool(uint32_t subface)>;

struct SchemeError {
    double maxRelative = 0.0, rmsRelative = 0.0;  // position distance / bounding-box diagonal
    double maxNormalDegrees = 0.0, rmsNormalDegrees = 0.0;
    uint64_t samples = 0;
    uint32_t worstSubface = 0, worstNormalSubface = 0;
};

inline double angleDegrees(glm::dvec3 a, glm::dvec3 b) {
    double la = glm::length(a), lb = glm::length(b);
    if (la == 0.0 || lb == 0.0) return 180.0;
    double c = std::clamp(glm::dot(a, b) / (la * lb), -1.0, 1.0);
    // acos loses precision near 0; atan2 of |a x b| and a.b does not.
    return std::atan2(glm::length(glm::cross(a, b)) / (la * lb), c) * 180.0 / std::numbers::pi;
}

// Samples an n x n grid (u, v = i / (n-1)) on every measured sub-face. The exact normal is the
// normalised cross product of the plans' derivatives.
inline SchemeError measureScheme(const ExactSurface& exact, const SchemeEvaluator& scheme, uint32_t n = 9,
                                 const SubfaceFilter& filter = {}) {
    SchemeError error;
    double sumSquares = 0.0, sumNormalSquares = 0.0;
    uint64_t normalSamples = 0;
    for (uint32_t s = 0; s < exact.planned->subfaceCount(); ++s) {
        if (!exact.planned->hasSurface(s) || (filter && !filter(s))) continue;
        for (uint32_t j = 0; j < n; ++j)
            for (uint32_t i = 0; i < n; ++i) {
                double u = double(i) / double(n - 1), v = double(j) / double(n - 1);
                LimitSample ref = exact.planned->evaluate(s, float(u), float(v));
                SchemeSample ours = scheme(s, u, v);
                double d = glm::length(ours.position - glm::dvec3(ref.position)) / exact.diagonal;
                sumSquares += d * d;
                ++error.samples;
                if (d > error.maxRelative) {
                    error.maxRelative = d;
                    error.worstSubface = s;
                }
                glm::dvec3 refNormal = glm::cross(glm::dvec3(ref.du), glm::dvec3(ref.dv));
                if (glm::length(refNormal) == 0.0) continue;  // degenerate reference (collapsed corner)
                double a = angleDegrees(ours.normal, refNormal);
                sumNormalSquares += a * a;
                ++normalSamples;
                if (a > error.maxNormalDegrees) {
                    error.maxNormalDegrees = a;
                    error.worstNormalSubface = s;
                }
            }
    }
    if (error.samples) error.rmsRelative = std::sqrt(sumSquares / double(error.samples));
    if (normalSamples) error.rmsNormalDegrees = std::sqrt(sumNormalSquares / double(normalSamples));
    return error;
}

// Where neighbouring patches meet: evaluates both patches of every interior edge of an
// all-quad cage at the same points of the edge (patch frames: corner k of a face at the k-th of
// (0,0), (1,0), (1,1), (0,1)). Returns the largest position gap (relative to `diagonal`) and
// normal gap (degrees). Faces for which hasPatch is false are skipped.
struct SeamGap {
    double position = 0.0, normalDegrees = 0.0;
    uint32_t edges = 0;
};
using PatchEvaluator = std::function<SchemeSample(uint32_t face, double s, double t)>;

inline SeamGap measureSeams(const Cage& quads, const Topology& topology, const PatchEvaluator& patch,
                            const std::function<bool(uint32_t face)>& hasPatch, double diagonal) {
    static const double cornerUV[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    SeamGap gap;
    for (uint32_t e = 0; e < topology.edgeCount(); ++e) {
        if (topology.edgeFaceCount(e) != 2) continue;
        uint32_t f = topology.edgeFaces[topology.edgeFaceOffsets[e]], g = topology.edgeFaces[topology.edgeFaceOffsets[e] + 1];
        if (!hasPatch(f) || !hasPatch(g)) continue;
        uint32_t a = topology.edgeVertices[2 * e], b = topology.edgeVertices[2 * e + 1];
        auto cornerOf = [&](uint32_t face, uint32_t vertex) {
            for (uint32_t k = 0; k < 4; ++k)
                if (quads.faceBegin(face)[k] == vertex) return k;
            return 0u;
        };
        uint32_t fa = cornerOf(f, a), fb = cornerOf(f, b), ga = cornerOf(g, a), gb = cornerOf(g, b);
        ++gap.edges;
        for (double t : {0.0, 0.13, 0.37, 0.5, 0.81, 1.0}) {
            auto point = [&](uint32_t face, uint32_t ka, uint32_t kb) {
                double s = (1 - t) * cornerUV[ka][0] + t * cornerUV[kb][0];
                double r = (1 - t) * cornerUV[ka][1] + t * cornerUV[kb][1];
                return patch(face, s, r);
            };
            SchemeSample p = point(f, fa, fb), q = point(g, ga, gb);
            gap.position = std::max(gap.position, glm::length(p.position - q.position) / diagonal);
            if (t > 0.0 && t < 1.0) gap.normalDegrees = std::max(gap.normalDegrees, angleDegrees(p.normal, q.normal));
        }
    }
    return gap;
}

inline void printSchemeError(const std::string& scheme, const std::string& cage, const SchemeError& e) {
    std::printf("| %-8s | %-22s | %10.3e | %10.3e | %8.3f | %8.3f |\n", scheme.c_str(), cage.c_str(), e.maxRelative,
                e.rmsRelative, e.maxNormalDegrees, e.rmsNormalDegrees);
}

// The shared cages of the README error tables: curved production cages with boundaries and
// creases, closed cages with extraordinary vertices of valence 3, 6 and 20, triangles, a
// regular torus, and boundary extraordinary vertices.
inline const std::vector<std::string>& errorTableCages() {
    static const std::vector<std::string> cages = {"catmark_pawn",     "catmark_car",      "catmark_torus",
                                                   "catmark_cube",     "catmark_toroidal_tet", "catmark_pyramid",
                                                   "catmark_smoothtris0", "catmark_gregory_test1"};
    return cages;
}

// One table row: all sub-faces with a surface, 9 x 9 samples each; and the same restricted to
// faces around untagged interior extraordinary vertices (smoothExtraordinaryFilter), if any.
inline void printErrorTableHeader() {
    std::printf("| scheme   | cage                   | patches | max rel    | rms rel    | max deg | rms deg | "
                "EV-only max rel | EV-only max deg |\n");
    std::printf("|---|---|---:|---:|---:|---:|---:|---:|---:|\n");
}

inline SchemeError printErrorTableRow(const std::string& scheme, const std::string& name, uint32_t patches,
                                      const ExactSurface& exact, const SchemeEvaluator& evaluate) {
    SchemeError all = measureScheme(exact, evaluate, 9);
    SchemeError ev = measureScheme(exact, evaluate, 9, smoothExtraordinaryFilter(exact.cage));
    char evPosition[32] = "-", evNormal[32] = "-";
    if (ev.samples) {
        std::snprintf(evPosition, sizeof evPosition, "%.2e", ev.maxRelative);
        std::snprintf(evNormal, sizeof evNormal, "%.2f", ev.maxNormalDegrees);
    }
    std::printf("| %-8s | %-22s | %7u | %10.2e | %10.2e | %7.2f | %7.2f | %15s | %15s |\n", scheme.c_str(), name.c_str(),
                patches, all.maxRelative, all.rmsRelative, all.maxNormalDegrees, all.rmsNormalDegrees, evPosition, evNormal);
    return all;
}

// The README error table: the header, then for every errorTableCages() cage `rows(name, cage,
// exact)`, which builds the scheme, prints its rows (printErrorTableRow) and checks them. Stops
// at a cage without an exact surface.
using ErrorTableRows = std::function<void(const std::string& name, const Cage& cage, const ExactSurface& exact)>;
inline void printErrorTable(const ErrorTableRows& rows) {
    printErrorTableHeader();
    for (const std::string& name : errorTableCages()) {
        Cage cage = loadSharedShape(name);
        auto exact = makeExactSurface(cage, name);
        ASSERT_TRUE(exact);
        rows(name, cage, *exact);
    }
}

// ---- A scheme's own build and evaluation ------------------------------------------------------

// The value of a scheme's build; the test fails (and goes on) when it is an error.
template <class T>
T built(Result<T> result) {
    EXPECT_TRUE(result.ok()) << (result.ok() ? "" : result.error().message);
    return std::move(result).value();
}

// A scheme's sample (position and normal, in float or double) in double.
template <class Sample>
SchemeSample schemeSample(const Sample& sample) {
    return SchemeSample{glm::dvec3(sample.position), glm::dvec3(sample.normal)};
}

// A SchemeEvaluator over the scheme's own evaluate(patches, subface, u, v), whose (u, v) are
// float or double. `patches` must outlive it.
template <class Patches, class Sample, class Real>
SchemeEvaluator schemeEvaluator(const Patches& patches, Sample (*evaluate)(const Patches&, uint32_t, Real, Real)) {
    return [&patches, evaluate](uint32_t s, double u, double v) { return schemeSample(evaluate(patches, s, Real(u), Real(v))); };
}

// ---- Per-quad schemes (acc1, acc2, stam: patches on a QuadPatchSource) ------------------------

// measureSeams over the quads of patches.source, evaluatePatch(patches, patch, s, t) in the
// frame of the patch's quad.
template <class Patches, class Sample, class Real>
SeamGap measurePatchSeams(const Patches& patches, Sample (*evaluatePatch)(const Patches&, uint32_t, Real, Real),
                          double diagonal) {
    const QuadPatchSource& src = patches.source;
    return measureSeams(
        src.quads, src.topology,
        [&](uint32_t face, double s, double t) {
            return schemeSample(evaluatePatch(patches, src.facePatch[face], Real(s), Real(t)));
        },
        [&](uint32_t face) { return src.facePatch[face] != kNoPatch; }, diagonal);
}

// Sub-faces all of whose points land on patches with four interior valence-4 corners: where a
// per-quad scheme is the bicubic B-spline. `src` must outlive the filter.
inline SubfaceFilter regularPatchSubfaces(const QuadPatchSource& src) {
    return [&src](uint32_t s) {
        for (double u : {0.0, 1.0})
            for (double v : {0.0, 1.0})
                if (!regularQuad(src, locateOnQuads(src, s, u, v).face)) return false;
        return true;
    };
}

// The bicubic B-spline limit to float precision, on the sub-faces `filter` keeps (all when empty).
inline void expectBSplineLimit(const ExactSurface& exact, const SchemeEvaluator& scheme, const SubfaceFilter& filter = {}) {
    SchemeError e = measureScheme(exact, scheme, 9, filter);
    EXPECT_GT(e.samples, 0u);
    EXPECT_LT(e.maxRelative, 1e-6);
    EXPECT_LT(e.maxNormalDegrees, 1e-3);
}

// On a regular closed cage: one regular patch per face of `pointsPerPatch` control points, and
// the B-spline limit.
template <class Patches>
void expectRegularCageIsTheBSplineLimit(const Cage& cage, const Patches& patches, const SchemeEvaluator& scheme,
                                        uint32_t pointsPerPatch) {
    EXPECT_EQ(patches.stats.patches, cage.faceCount());
    EXPECT_EQ(patches.stats.regularPatches, cage.faceCount());
    EXPECT_EQ(patches.stats.controlPoints, pointsPerPatch * cage.faceCount());
    expectBSplineLimit(*makeExactSurface(cage), scheme);
}

// The corners of every sub-face interpolate the limit position and, loosely, its normal: the
// plans' own normals scatter by a fraction of a degree at extraordinary vertices. A corner at a
// valence-2 vertex (no tangent plane) counts for its position only.
inline void expectCornersOnTheLimit(const ExactSurface& exact, const SchemeEvaluator& scheme) {
    double position = 0.0, normalDegrees = 0.0;
    for (uint32_t s = 0; s < exact.planned->subfaceCount(); ++s)
        for (glm::vec2 uv : {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(1, 1), glm::vec2(0, 1)}) {
            const LimitSample ref = exact.planned->evaluate(s, uv.x, uv.y);
            const SchemeSample ours = scheme(s, uv.x, uv.y);
            position = std::max(position, glm::length(ours.position - glm::dvec3(ref.position)) / exact.diagonal);
            const glm::dvec3 refNormal = glm::cross(glm::dvec3(ref.du), glm::dvec3(ref.dv));
            if (glm::length(refNormal) == 0.0) continue;
            normalDegrees = std::max(normalDegrees, angleDegrees(ours.normal, refNormal));
        }
    EXPECT_LT(position, 1e-6);
    EXPECT_LT(normalDegrees, 0.5);
}

// Neighbouring patches meet (C0 geometry) with one tangent plane (a continuous normal field).
inline void expectContinuousNormals(const SeamGap& gap) {
    EXPECT_GT(gap.edges, 0u);
    EXPECT_LT(gap.position, 1e-6);
    EXPECT_LT(gap.normalDegrees, 1e-2);
}

}  // namespace qp::test
