// ACC-1 (bicubic geometry + tangent patches) against the exact Catmull-Clark limit surface.
#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include "acc1.h"
#include "scheme_test_support.h"
#include "test_cages.h"

namespace {

using qp::Cage;

qp::Acc1Patches build(const Cage& cage, qp::Acc1Settings settings = {}) {
    return qp::test::built(qp::buildAcc1(cage, settings, "test cage"));
}

qp::test::SchemeEvaluator evaluator(const qp::Acc1Patches& patches) { return qp::test::schemeEvaluator(patches, qp::evaluateAcc1); }

}  // namespace

TEST(Acc1, RegularClosedCageIsTheBSplineLimit) {
    Cage torus = qp::test::makeTorus();
    qp::Acc1Patches patches = build(torus);
    qp::test::expectRegularCageIsTheBSplineLimit(torus, patches, evaluator(patches), 40);
    auto exact = qp::test::makeExactSurface(torus);
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
    qp::Acc1Patches patches = build(grid);
    EXPECT_GT(patches.stats.boundaryPatches, 0u);
    qp::test::expectBSplineLimit(*qp::test::makeExactSurface(grid), evaluator(patches));
}

TEST(Acc1, CornersInterpolateTheLimitPositionAndNormal) {
    for (const Cage& cage : {qp::test::makeCube(), qp::test::makeSubdividedCube(), qp::test::makeMixedGrid()}) {
        auto exact = qp::test::makeExactSurface(cage);
        qp::Acc1Patches patches = build(cage);
        qp::test::expectCornersOnTheLimit(*exact, evaluator(patches));
        qp::test::expectContinuousNormals(qp::test::measurePatchSeams(patches, qp::evaluateAcc1Patch, exact->diagonal));
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
    qp::test::printErrorTable([](const std::string& name, const Cage& cage, const qp::test::ExactSurface& exact) {
        auto patches = qp::buildAcc1(cage, {}, name);
        ASSERT_TRUE(patches.ok()) << patches.error().message;
        qp::test::SchemeError e = qp::test::printErrorTableRow("acc1", name, patches->stats.patches, exact, evaluator(*patches));
        EXPECT_LT(e.maxRelative, 0.1) << name;  // gregory_test1's boundary EVs: 4e-2 (ACC-1), 8e-2 (ACC-2)
        if (name == "catmark_torus") {
            EXPECT_LT(e.maxRelative, 1e-6);
        }
    });
}

// Away from extraordinary vertices the scheme is the B-spline limit, also on irregular cages:
// faces whose four corners are interior valence-4 vertices.
TEST(Acc1, RegularFacesOfIrregularCagesAreExact) {
    for (const Cage& cage : {qp::test::makeSubdividedCube(4), qp::test::makeMixedGrid()}) {
        qp::Acc1Patches patches = build(cage);
        qp::test::expectBSplineLimit(*qp::test::makeExactSurface(cage), evaluator(patches),
                                     qp::test::regularPatchSubfaces(patches.source));
    }
}

// The tangent patches are those of the production ACC-1 implementations (Valve's Source engine,
// r_studiosubd_patches.cpp; Microsoft's DirectX SDK sample SubD11, written with Loop's help):
// rebuilt here from their formulas, independently of acc1.cpp and limit_frame.cpp, for every
// patch whose corners are interior vertices:
//   corner vectors  sum_i (1/n + cos(pi/n) beta) cos(2 pi (i-j)/n) e_i + beta cos((2 pi (i-j) + pi)/n) d_i,
//                   beta = 1 / (n sqrt(4 + cos^2(pi/n))), towards ring edge j;
//   edge rows       the geometry patch's own derivative coefficients;
//   cross rows      the geometry's cross derivative + lambda(t) T(t) (degree-raised), T the
//                   along-edge quadratic (corner vectors and the geometry's middle coefficient),
//                   lambda linear from cos(2 pi / n0) to -cos(2 pi / n1) (SubD11's fCWts).
TEST(Acc1, TangentPatchesAreTheProductionConstruction) {
    Cage cube = qp::test::makeSubdividedCube(2);
    for (size_t i = 0; i < cube.positions.size(); ++i)  // break the symmetry
        cube.positions[i] += 0.15f * glm::vec3(std::sin(1.3f * float(i)), std::cos(2.1f * float(i)), std::sin(0.7f * float(i)));
    std::vector<std::pair<std::string, Cage>> cages = {{"perturbed cube", cube}};
    if (qp::test::haveSharedShapes())
        for (const char* name : {"catmark_toroidal_tet", "catmark_pawn"}) cages.push_back({name, qp::test::loadSharedShape(name)});
    for (const auto& [name, cage] : cages) {
        SCOPED_TRACE(name);
        qp::Acc1Patches patches = build(cage);
        const qp::QuadPatchSource& src = patches.source;
        const double scale = qp::computeBounds(cage).diagonal();
        auto P = [&](uint32_t v) { return glm::dvec3(src.quads.positions[v]); };
        // Production corner vector of vertex `v` towards ring edge j, and cos(2 pi / n).
        auto cornerVector = [&](uint32_t v, uint32_t j) {
            const qp::QuadRing& ring = src.rings[v];
            const double n = double(ring.faceCount()), pi = std::numbers::pi, cp = std::cos(pi / n);
            const double beta = 1.0 / (n * std::sqrt(4.0 + cp * cp)), alpha = 1.0 / n + cp * beta;
            glm::dvec3 t(0.0);
            for (uint32_t i = 0; i < ring.faceCount(); ++i) {
                const double a = 2.0 * pi * (double(i) - double(j)) / n;
                t += alpha * std::cos(a) * (P(ring.edges[i]) - P(v)) + beta * std::cos(a + pi / n) * (P(ring.diagonals[i]) - P(v));
            }
            return t;
        };
        auto cosine = [&](uint32_t v) { return std::cos(2.0 * std::numbers::pi / double(src.rings[v].faceCount())); };
        uint32_t checked = 0;
        double worst = 0.0;
        for (uint32_t patch = 0; patch < src.patchFace.size(); ++patch) {
            const uint32_t face = src.patchFace[patch];
            const uint32_t* corner = src.quads.faceBegin(face);
            bool interior = true;
            for (uint32_t k = 0; k < 4; ++k) interior &= !src.rings[corner[k]].boundary;
            if (!interior) continue;
            ++checked;
            const glm::vec3* cp = &patches.controlPoints[size_t(patch) * qp::Acc1Patches::kControlPointsPerPatch];
            auto b = [&](int i, int j) { return glm::dvec3(cp[4 * j + i]); };
            // Corner k's vectors towards its next (k+1) and previous (k-1) corner.
            glm::dvec3 toNext[4], toPrev[4];
            double c[4];
            for (uint32_t k = 0; k < 4; ++k) {
                const uint32_t i = src.ringFace(face, k), n = src.rings[corner[k]].faceCount();
                toNext[k] = cornerVector(corner[k], i);
                toPrev[k] = cornerVector(corner[k], (i + 1) % n);
                c[k] = cosine(corner[k]);
            }
            // lambda T on an edge from corner a (t = 0) to corner b, T = {T0, T1, T2}: cubic coefficients 1 and 2.
            auto lambdaT = [](double ca, double cb, glm::dvec3 T0, glm::dvec3 T1, glm::dvec3 T2, int index) {
                return index == 1 ? (2.0 * ca * T1 - cb * T0) / 3.0 : (ca * T2 - 2.0 * cb * T1) / 3.0;
            };
            glm::dvec3 U[3][4], V[4][3];
            // d/du: rows v = 0 and v = 1 along edges 0 (corner 0 -> 1) and 2 (corner 3 -> 2).
            U[0][0] = toNext[0], U[1][0] = 3.0 * (b(2, 0) - b(1, 0)), U[2][0] = -toPrev[1];
            U[0][3] = toPrev[3], U[1][3] = 3.0 * (b(2, 3) - b(1, 3)), U[2][3] = -toNext[2];
            // Edge u = 0, corner 0 -> 3 (along +v): T = {toPrev[0], 3 (b02 - b01), -toNext[3]}.
            // Edge u = 1, corner 1 -> 2: T = {toNext[1], 3 (b32 - b31), -toPrev[2]}; there +u points out.
            for (int j = 1; j <= 2; ++j) {
                U[1][j] = 3.0 * (b(2, j) - b(1, j));
                U[0][j] = 3.0 * (b(1, j) - b(0, j)) + lambdaT(c[0], c[3], toPrev[0], 3.0 * (b(0, 2) - b(0, 1)), -toNext[3], j);
                U[2][j] = 3.0 * (b(3, j) - b(2, j)) - lambdaT(c[1], c[2], toNext[1], 3.0 * (b(3, 2) - b(3, 1)), -toPrev[2], j);
            }
            V[0][0] = toPrev[0], V[0][1] = 3.0 * (b(0, 2) - b(0, 1)), V[0][2] = -toNext[3];
            V[3][0] = toNext[1], V[3][1] = 3.0 * (b(3, 2) - b(3, 1)), V[3][2] = -toPrev[2];
            for (int i = 1; i <= 2; ++i) {
                V[i][1] = 3.0 * (b(i, 2) - b(i, 1));
                V[i][0] = 3.0 * (b(i, 1) - b(i, 0)) + lambdaT(c[0], c[1], toNext[0], 3.0 * (b(2, 0) - b(1, 0)), -toPrev[1], i);
                V[i][2] = 3.0 * (b(i, 3) - b(i, 2)) - lambdaT(c[3], c[2], toPrev[3], 3.0 * (b(2, 3) - b(1, 3)), -toNext[2], i);
            }
            for (int j = 0; j < 4; ++j)
                for (int i = 0; i < 3; ++i)
                    worst = std::max(worst, glm::length(glm::dvec3(cp[16 + 3 * j + i]) - U[i][j]) / scale);
            for (int j = 0; j < 3; ++j)
                for (int i = 0; i < 4; ++i)
                    worst = std::max(worst, glm::length(glm::dvec3(cp[28 + 4 * j + i]) - V[i][j]) / scale);
        }
        EXPECT_GT(checked, 0u);
        EXPECT_LT(worst, 1e-6);
    }
}
