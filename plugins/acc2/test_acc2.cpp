// ACC-2 (Gregory patches) against the exact Catmull-Clark limit surface (subdivision plans).
#include <cstdio>

#include <gtest/gtest.h>

#include "acc2.h"
#include "scheme_test_support.h"
#include "test_cages.h"

namespace {

using qp::Cage;
using qp::test::SchemeSample;

qp::Acc2Patches build(const Cage& cage, qp::Acc2Settings settings = {}) {
    auto patches = qp::buildAcc2(cage, settings, "test cage");
    EXPECT_TRUE(patches.ok()) << (patches.ok() ? "" : patches.error().message);
    return std::move(patches).value();
}

qp::test::SchemeEvaluator evaluator(const qp::Acc2Patches& patches) {
    return [&patches](uint32_t s, double u, double v) {
        qp::Acc2Sample a = qp::evaluateAcc2(patches, s, float(u), float(v));
        return SchemeSample{glm::dvec3(a.position), glm::dvec3(a.normal)};
    };
}

qp::test::SeamGap seams(const qp::Acc2Patches& patches, double diagonal) {
    const qp::QuadPatchSource& src = patches.source;
    return qp::test::measureSeams(
        src.quads, src.topology,
        [&](uint32_t face, double s, double t) {
            qp::Acc2Sample a = qp::evaluateAcc2Patch(patches, src.facePatch[face], float(s), float(t));
            return SchemeSample{glm::dvec3(a.position), glm::dvec3(a.normal)};
        },
        [&](uint32_t face) { return src.facePatch[face] != qp::kNoPatch; }, diagonal);
}

}  // namespace

TEST(Acc2, RegularClosedCageIsTheBSplineLimit) {
    Cage torus = qp::test::makeTorus();
    auto exact = qp::test::makeExactSurface(torus);
    qp::Acc2Patches patches = build(torus);
    EXPECT_EQ(patches.stats.patches, torus.faceCount());
    EXPECT_EQ(patches.stats.regularPatches, torus.faceCount());
    EXPECT_EQ(patches.stats.controlPoints, 20 * torus.faceCount());
    qp::test::SchemeError e = qp::test::measureScheme(*exact, evaluator(patches));
    EXPECT_LT(e.maxRelative, 1e-6);
    EXPECT_LT(e.maxNormalDegrees, 1e-3);
}

TEST(Acc2, RegularBoundaryAndCornerPatchesAreExact) {
    Cage grid = qp::test::makeGrid(5);
    auto exact = qp::test::makeExactSurface(grid);
    qp::Acc2Patches patches = build(grid);
    EXPECT_GT(patches.stats.boundaryPatches, 0u);
    qp::test::SchemeError e = qp::test::measureScheme(*exact, evaluator(patches));
    EXPECT_LT(e.maxRelative, 1e-6);
    EXPECT_LT(e.maxNormalDegrees, 1e-3);
}

TEST(Acc2, CornersInterpolateTheLimitAndNeighboursMeetG1) {
    for (const Cage& cage : {qp::test::makeCube(), qp::test::makeSubdividedCube(), qp::test::makeMixedGrid()}) {
        auto exact = qp::test::makeExactSurface(cage);
        qp::Acc2Patches patches = build(cage);
        // Corners of every sub-face: the limit position (and the limit normal, checked loosely:
        // the plans' own normals scatter by a fraction of a degree at extraordinary vertices).
        double worstCorner = 0.0, worstCornerNormal = 0.0;
        for (uint32_t s = 0; s < exact->planned->subfaceCount(); ++s)
            for (glm::vec2 uv : {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(1, 1), glm::vec2(0, 1)}) {
                qp::LimitSample ref = exact->planned->evaluate(s, uv.x, uv.y);
                qp::Acc2Sample ours = qp::evaluateAcc2(patches, s, uv.x, uv.y);
                worstCorner = std::max(worstCorner, double(glm::length(ours.position - ref.position)) / exact->diagonal);
                glm::dvec3 refNormal = glm::cross(glm::dvec3(ref.du), glm::dvec3(ref.dv));
                if (glm::length(refNormal) == 0.0) continue;  // valence-2 vertex: no tangent plane
                worstCornerNormal = std::max(worstCornerNormal, qp::test::angleDegrees(glm::dvec3(ours.normal), refNormal));
            }
        EXPECT_LT(worstCorner, 1e-6);
        EXPECT_LT(worstCornerNormal, 0.5);
        qp::test::SeamGap gap = seams(patches, exact->diagonal);
        EXPECT_GT(gap.edges, 0u);
        EXPECT_LT(gap.position, 1e-6);
        EXPECT_LT(gap.normalDegrees, 1e-2);  // G1: one tangent plane on both sides
        qp::test::SchemeError e = qp::test::measureScheme(*exact, evaluator(patches));
        EXPECT_LT(e.maxRelative, 2e-2);
    }
}

TEST(Acc2, NonQuadCagesAreRefinedOnce) {
    Cage mixed = qp::test::makeMixedGrid();
    qp::Acc2Patches patches = build(mixed);
    EXPECT_EQ(patches.stats.refinementSteps, 1u);
    uint32_t corners = 0;
    for (uint32_t f = 0; f < mixed.faceCount(); ++f) corners += mixed.faceSize(f);
    EXPECT_EQ(patches.stats.patches, corners);  // one child per face corner
    EXPECT_STREQ(qp::acc2Restrictions(), qp::acc2Restrictions());
    EXPECT_NE(std::string(qp::acc2Restrictions()).find("creases"), std::string::npos);
}

TEST(Acc2, RejectsNonManifoldCagesWithAMessage) {
    Cage bowtie;
    bowtie.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 1, 0}, {2, 2, 0}, {1, 2, 0}};
    uint32_t a[4] = {0, 1, 2, 3}, b[4] = {2, 4, 5, 6};
    bowtie.addFace(a, 4);
    bowtie.addFace(b, 4);
    auto patches = qp::buildAcc2(bowtie, {}, "bowtie");
    ASSERT_FALSE(patches.ok());
    EXPECT_NE(patches.error().message.find("bowtie"), std::string::npos);
}
