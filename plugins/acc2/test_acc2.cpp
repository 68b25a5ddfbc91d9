// ACC-2 (Gregory patches) against the exact Catmull-Clark limit surface (subdivision plans).
#include <cstdio>

#include <gtest/gtest.h>

#include "acc1.h"
#include "acc2.h"
#include "plans/limit_reference.h"
#include "scheme_test_support.h"
#include "test_cages.h"

namespace {

using qp::Cage;

qp::Acc2Patches build(const Cage& cage, qp::Acc2Settings settings = {}) {
    return qp::test::built(qp::buildAcc2(cage, settings, "test cage"));
}

qp::test::SchemeEvaluator evaluator(const qp::Acc2Patches& patches) { return qp::test::schemeEvaluator(patches, qp::evaluateAcc2); }

}  // namespace

TEST(Acc2, RegularClosedCageIsTheBSplineLimit) {
    Cage torus = qp::test::makeTorus();
    qp::Acc2Patches patches = build(torus);
    qp::test::expectRegularCageIsTheBSplineLimit(torus, patches, evaluator(patches), 20);
}

TEST(Acc2, RegularBoundaryAndCornerPatchesAreExact) {
    Cage grid = qp::test::makeGrid(5);
    qp::Acc2Patches patches = build(grid);
    EXPECT_GT(patches.stats.boundaryPatches, 0u);
    qp::test::expectBSplineLimit(*qp::test::makeExactSurface(grid), evaluator(patches));
}

TEST(Acc2, CornersInterpolateTheLimitAndNeighboursMeetG1) {
    for (const Cage& cage : {qp::test::makeCube(), qp::test::makeSubdividedCube(), qp::test::makeMixedGrid()}) {
        auto exact = qp::test::makeExactSurface(cage);
        qp::Acc2Settings exactTangents;
        exactTangents.tangents = qp::TangentRule::Exact;
        qp::Acc2Patches patches = build(cage, exactTangents);
        // Corners of every sub-face: the limit position (and, with exact tangents, the limit normal).
        qp::test::expectCornersOnTheLimit(*exact, evaluator(patches));
        patches = build(cage);  // the default construction must meet G1 just as well
        qp::test::expectContinuousNormals(qp::test::measurePatchSeams(patches, qp::evaluateAcc2Patch, exact->diagonal));
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

// The literature's claim (issue 5: "ACC-2 no worse than ACC-1 in normals"): measured where only
// the extraordinary vertices decide, on faces with an interior extraordinary corner and no
// tags, holes or boundaries in their 1-ring. Asserted for the RMS deviation on the two curved
// production cages; the other rows (and the maxima) are printed for plugins/acc2/README.md,
// which reports where the claim does not hold (the coarse toroidal_tet, the pawn's maximum).
TEST(Acc2, NormalsAtExtraordinaryVerticesNoWorseThanAcc1) {
    QP_REQUIRE_SHARED_SHAPES();
    std::printf("| scheme | cage (EV patches) | max rel | rms rel | max deg | rms deg |\n");
    for (const char* name : {"catmark_pawn", "catmark_car", "catmark_cube", "catmark_toroidal_tet"}) {
        SCOPED_TRACE(name);
        Cage cage = qp::test::loadSharedShape(name);
        auto exact = qp::test::makeExactSurface(cage, name);
        auto filter = qp::test::smoothExtraordinaryFilter(cage);
        auto acc1 = qp::buildAcc1(cage, {}, name);
        ASSERT_TRUE(acc1.ok());
        qp::test::SchemeError e1 = qp::test::measureScheme(*exact, qp::test::schemeEvaluator(*acc1, qp::evaluateAcc1), 9, filter);
        qp::Acc2Patches acc2 = build(cage);
        qp::test::SchemeError e2 = qp::test::measureScheme(*exact, evaluator(acc2), 9, filter);
        qp::Acc2Settings exactTangents;
        exactTangents.tangents = qp::TangentRule::Exact;
        qp::Acc2Patches acc2x = build(cage, exactTangents);
        qp::Acc2Settings surface;
        surface.surfaceDerivatives = true;
        qp::Acc2Patches acc2s = build(cage, surface);
        qp::test::printSchemeError("acc1", name, e1);
        qp::test::printSchemeError("acc2", name, e2);
        qp::test::printSchemeError("acc2 x", name, qp::test::measureScheme(*exact, evaluator(acc2x), 9, filter));
        qp::test::printSchemeError("acc2 s", name, qp::test::measureScheme(*exact, evaluator(acc2s), 9, filter));
        ASSERT_GT(e2.samples, 0u);
        if (std::string(name) == "catmark_pawn" || std::string(name) == "catmark_car") {
            EXPECT_LE(e2.rmsNormalDegrees, e1.rmsNormalDegrees);
        }
    }
}

// The default construction is the one OpenSubdiv builds for its Gregory-basis end caps: with
// adaptive isolation depth 0, Far's patches are ours (B-splines on regular faces, Gregory
// patches elsewhere), to float precision, derivatives included. Closed cages: at boundaries
// OpenSubdiv uses other tangent rules (limit_frame.h).
TEST(Acc2, EqualsOpenSubdivGregoryEndCapsWithoutIsolation) {
    Cage cube = qp::test::makeSubdividedCube(2);
    for (size_t i = 0; i < cube.positions.size(); ++i)  // break the symmetry
        cube.positions[i] += 0.2f * glm::vec3(std::sin(1.7f * float(i)), std::cos(2.3f * float(i)), std::sin(0.9f * float(i)));
    std::vector<Cage> cages = {cube, qp::test::makeCube()};
    if (qp::test::haveSharedShapes()) cages.push_back(qp::test::loadSharedShape("catmark_toroidal_tet"));
    for (const Cage& cage : cages) {
        auto reference = qp::LimitReference::create(cage, 0, "cage");
        ASSERT_TRUE(reference.ok());
        qp::Acc2Patches patches = build(cage);
        const double diagonal = qp::computeBounds(cage).diagonal();
        double position = 0.0, derivative = 0.0;
        for (uint32_t s = 0; s < reference->subfaceCount(); ++s)
            for (double u : {0.0, 0.15, 0.5, 0.85, 1.0})
                for (double v : {0.0, 0.3, 0.6, 1.0}) {
                    qp::ReferenceSample r = reference->evaluate(s, u, v);
                    qp::Acc2Sample a = qp::evaluateAcc2(patches, s, float(u), float(v));
                    position = std::max(position, glm::length(glm::dvec3(a.position) - r.position) / diagonal);
                    derivative = std::max({derivative, glm::length(glm::dvec3(a.du) - r.du) / diagonal,
                                           glm::length(glm::dvec3(a.dv) - r.dv) / diagonal});
                }
        EXPECT_LT(position, 1e-6);
        EXPECT_LT(derivative, 1e-5);
    }
}

// The README table (plugins/acc2/README.md): ACC-2 against the exact limit on the shared cages.
TEST(Acc2, ErrorTableOnSharedCages) {
    QP_REQUIRE_SHARED_SHAPES();
    qp::test::printErrorTable([](const std::string& name, const Cage& cage, const qp::test::ExactSurface& exact) {
        qp::Acc2Patches patches = build(cage);
        qp::test::SchemeError e = qp::test::printErrorTableRow("acc2", name, patches.stats.patches, exact, evaluator(patches));
        EXPECT_LT(e.maxRelative, 0.1) << name;  // gregory_test1's boundary EVs: 4e-2 (ACC-1), 8e-2 (ACC-2)
        if (name == "catmark_torus") {
            EXPECT_LT(e.maxRelative, 1e-6);
        }
        qp::Acc2Settings exactTangents;
        exactTangents.tangents = qp::TangentRule::Exact;
        qp::Acc2Patches x = build(cage, exactTangents);
        qp::test::printErrorTableRow("acc2 x", name, x.stats.patches, exact, evaluator(x));
    });
}

// Away from extraordinary vertices the scheme is the B-spline limit, also on irregular cages:
// faces whose four corners are interior valence-4 vertices.
TEST(Acc2, RegularFacesOfIrregularCagesAreExact) {
    for (const Cage& cage : {qp::test::makeSubdividedCube(4), qp::test::makeMixedGrid()}) {
        qp::Acc2Patches patches = build(cage);
        qp::test::expectBSplineLimit(*qp::test::makeExactSurface(cage), evaluator(patches),
                                     qp::test::regularPatchSubfaces(patches.source));
    }
}
