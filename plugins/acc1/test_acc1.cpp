// ACC-1 (bicubic geometry + tangent patches) against the exact Catmull-Clark limit surface.
#include <cstdio>

#include <gtest/gtest.h>

#include "acc1.h"
#include "scheme_test_support.h"
#include "test_cages.h"

namespace {

using qp::Cage;
using qp::test::SchemeSample;

qp::Acc1Patches build(const Cage& cage, qp::Acc1Settings settings = {}) {
    auto patches = qp::buildAcc1(cage, settings, "test cage");
    EXPECT_TRUE(patches.ok()) << (patches.ok() ? "" : patches.error().message);
    return std::move(patches).value();
}

qp::test::SchemeEvaluator evaluator(const qp::Acc1Patches& patches) {
    return [&patches](uint32_t s, double u, double v) {
        qp::Acc1Sample a = qp::evaluateAcc1(patches, s, float(u), float(v));
        return SchemeSample{glm::dvec3(a.position), glm::dvec3(a.normal)};
    };
}

qp::test::SeamGap seams(const qp::Acc1Patches& patches, double diagonal) {
    const qp::QuadPatchSource& src = patches.source;
    return qp::test::measureSeams(
        src.quads, src.topology,
        [&](uint32_t face, double s, double t) {
            qp::Acc1Sample a = qp::evaluateAcc1Patch(patches, src.facePatch[face], float(s), float(t));
            return SchemeSample{glm::dvec3(a.position), glm::dvec3(a.normal)};
        },
        [&](uint32_t face) { return src.facePatch[face] != qp::kNoPatch; }, diagonal);
}

}  // namespace

TEST(Acc1, RegularClosedCageIsTheBSplineLimit) {
    Cage torus = qp::test::makeTorus();
    auto exact = qp::test::makeExactSurface(torus);
    qp::Acc1Patches patches = build(torus);
    EXPECT_EQ(patches.stats.patches, torus.faceCount());
    EXPECT_EQ(patches.stats.regularPatches, torus.faceCount());
    EXPECT_EQ(patches.stats.controlPoints, 40 * torus.faceCount());
    qp::test::SchemeError e = qp::test::measureScheme(*exact, evaluator(patches));
    EXPECT_LT(e.maxRelative, 1e-6);
    EXPECT_LT(e.maxNormalDegrees, 1e-3);
    // The tangent patches are the geometry's derivatives there: compare with the plans' du, dv.
    double worst = 0.0;
    for (uint32_t s = 0; s < torus.faceCount(); ++s)
        for (float u : {0.0f, 0.3f, 0.7f})
            for (float v : {0.2f, 0.5f, 1.0f}) {
                qp::LimitSample ref = exact->planned->evaluate(s, u, v);
                qp::Acc1Sample ours = qp::evaluateAcc1(patches, s, u, v);
                worst = std::max({worst, double(glm::length(ours.du - ref.du)), double(glm::length(ours.dv - ref.dv))});
            }
    EXPECT_LT(worst / exact->diagonal, 1e-5);
}

TEST(Acc1, RegularBoundaryAndCornerPatchesAreExact) {
    Cage grid = qp::test::makeGrid(5);
    auto exact = qp::test::makeExactSurface(grid);
    qp::Acc1Patches patches = build(grid);
    EXPECT_GT(patches.stats.boundaryPatches, 0u);
    qp::test::SchemeError e = qp::test::measureScheme(*exact, evaluator(patches));
    EXPECT_LT(e.maxRelative, 1e-6);
    EXPECT_LT(e.maxNormalDegrees, 1e-3);
}

TEST(Acc1, CornersInterpolateTheLimitPositionAndNormal) {
    for (const Cage& cage : {qp::test::makeCube(), qp::test::makeSubdividedCube(), qp::test::makeMixedGrid()}) {
        auto exact = qp::test::makeExactSurface(cage);
        qp::Acc1Patches patches = build(cage);
        double worstCorner = 0.0, worstCornerNormal = 0.0;
        for (uint32_t s = 0; s < exact->planned->subfaceCount(); ++s)
            for (glm::vec2 uv : {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(1, 1), glm::vec2(0, 1)}) {
                qp::LimitSample ref = exact->planned->evaluate(s, uv.x, uv.y);
                qp::Acc1Sample ours = qp::evaluateAcc1(patches, s, uv.x, uv.y);
                worstCorner = std::max(worstCorner, double(glm::length(ours.position - ref.position)) / exact->diagonal);
                glm::dvec3 refNormal = glm::cross(glm::dvec3(ref.du), glm::dvec3(ref.dv));
                if (glm::length(refNormal) == 0.0) continue;  // valence-2 vertex: no tangent plane
                worstCornerNormal = std::max(worstCornerNormal, qp::test::angleDegrees(glm::dvec3(ours.normal), refNormal));
            }
        EXPECT_LT(worstCorner, 1e-6);
        EXPECT_LT(worstCornerNormal, 0.5);  // the plans' own scatter at extraordinary vertices
        qp::test::SeamGap gap = seams(patches, exact->diagonal);
        EXPECT_GT(gap.edges, 0u);
        EXPECT_LT(gap.position, 1e-6);       // C0 geometry
        EXPECT_LT(gap.normalDegrees, 1e-2);  // continuous normal field
        qp::test::SchemeError e = qp::test::measureScheme(*exact, evaluator(patches));
        EXPECT_LT(e.maxRelative, 2e-2);
    }
}

TEST(Acc1, NonQuadCagesAreRefinedOnce) {
    Cage mixed = qp::test::makeMixedGrid();
    qp::Acc1Patches patches = build(mixed);
    EXPECT_EQ(patches.stats.refinementSteps, 1u);
    uint32_t corners = 0;
    for (uint32_t f = 0; f < mixed.faceCount(); ++f) corners += mixed.faceSize(f);
    EXPECT_EQ(patches.stats.patches, corners);
    EXPECT_NE(std::string(qp::acc1Restrictions()).find("creases"), std::string::npos);
}

// The README table (plugins/acc1/README.md): ACC-1 against the exact limit on the shared cages.
TEST(Acc1, ErrorTableOnSharedCages) {
    QP_REQUIRE_SHARED_SHAPES();
    qp::test::printErrorTableHeader();
    for (const std::string& name : qp::test::errorTableCages()) {
        Cage cage = qp::test::loadSharedShape(name);
        auto exact = qp::test::makeExactSurface(cage, name);
        ASSERT_TRUE(exact);
        auto patches = qp::buildAcc1(cage, {}, name);
        ASSERT_TRUE(patches.ok()) << patches.error().message;
        qp::test::SchemeError e = qp::test::printErrorTableRow("acc1", name, patches->stats.patches, *exact, evaluator(*patches));
        EXPECT_LT(e.maxRelative, 0.1) << name;  // gregory_test1's boundary EVs: 4e-2 (ACC-1), 8e-2 (ACC-2)
        if (name == "catmark_torus") {
            EXPECT_LT(e.maxRelative, 1e-6);
        }
    }
}

// Away from extraordinary vertices the scheme is the B-spline limit, also on irregular cages:
// faces whose four corners are interior valence-4 vertices.
TEST(Acc1, RegularFacesOfIrregularCagesAreExact) {
    for (const Cage& cage : {qp::test::makeSubdividedCube(4), qp::test::makeMixedGrid()}) {
        auto exact = qp::test::makeExactSurface(cage);
        auto patches = build(cage);
        const qp::QuadPatchSource& src = patches.source;
        qp::test::SchemeEvaluator eval = evaluator(patches);
        // Sub-faces all of whose points land on patches with four regular corners.
        auto regular = [&](uint32_t s) {
            for (double u : {0.0, 1.0})
                for (double v : {0.0, 1.0}) {
                    uint32_t face = qp::locateOnQuads(src, s, u, v).face;
                    for (uint32_t k = 0; k < 4; ++k) {
                        const qp::QuadRing& ring = src.rings[src.quads.faceBegin(face)[k]];
                        if (ring.boundary || ring.faceCount() != 4) return false;
                    }
                }
            return true;
        };
        qp::test::SchemeError e = qp::test::measureScheme(*exact, eval, 9, regular);
        EXPECT_GT(e.samples, 0u);
        EXPECT_LT(e.maxRelative, 1e-6);
        EXPECT_LT(e.maxNormalDegrees, 1e-3);
    }
}
