// PN-triangles: interpolation of the cage, continuity, the sub-face maps, and (for the record)
// their distance from the exact Catmull-Clark limit.
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "pn.h"
#include "scheme_test_support.h"
#include "test_cages.h"

namespace {

using qp::Cage;

qp::PnPatches build(const Cage& cage) { return qp::test::built(qp::buildPn(cage, "test cage")); }

Cage makeOctahedron() {
    Cage cage;
    cage.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    uint32_t faces[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    for (auto& f : faces) cage.addFace(f, 3);
    return cage;
}

}  // namespace

TEST(Pn, InterpolatesCageVerticesAndTheirNormals) {
    // Sub-face numbering: quads one each, n-gons n each (as PlannedCage).
    Cage mixed = qp::test::makeMixedGrid();
    qp::PnPatches patches = build(mixed);
    uint32_t subface = 0;
    for (uint32_t f = 0; f < mixed.faceCount(); ++f) {
        const uint32_t n = mixed.faceSize(f);
        const float corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        for (uint32_t k = 0; k < n; ++k) {
            uint32_t s = n == 4 ? subface : subface + k;
            glm::vec2 uv = n == 4 ? glm::vec2(corner[k][0], corner[k][1]) : glm::vec2(0, 0);
            qp::PnSample p = qp::evaluatePn(patches, s, uv.x, uv.y);
            uint32_t vertex = mixed.faceBegin(f)[k];
            ASSERT_TRUE(p.valid);
            EXPECT_LT(glm::length(p.position - mixed.positions[vertex]), 1e-6f) << "face " << f << " corner " << k;
            // The grid's folded triangle-pentagon pair cancels its centre vertex's normal.
            if (glm::length(patches.vertexNormals[vertex]) == 0.0f) continue;
            EXPECT_LT(qp::test::angleDegrees(glm::dvec3(p.normal), glm::dvec3(patches.vertexNormals[vertex])), 1e-3);
        }
        subface += n == 4 ? 1 : n;
    }
    EXPECT_EQ(patches.stats.fannedFaces, 1u);  // the pentagon
    EXPECT_EQ(patches.stats.triangles, 2u * 15u + 1u + 5u);
    EXPECT_EQ(patches.stats.controlPoints, patches.stats.triangles * 16u);
}

TEST(Pn, NeighboursMeetWithContinuousNormals) {
    for (const Cage& cage : {qp::test::makeMixedGrid(), makeOctahedron(), qp::test::makeSubdividedCube()}) {
        qp::PnPatches patches = build(cage);
        qp::Topology topology = qp::buildTopology(cage);
        // Walk each shared edge from both faces: the edge of a sub-face from (0,0) (corner k) to
        // (1,0) covers the first half of edge k of an n-gon or a triangle, and the whole edge of
        // a quad sub-face from its corner k to k+1. Compare in barycentrics of the edge instead:
        // evaluate on each side at the same fraction of the cage edge.
        double gap = 0.0, normalGap = 0.0;
        for (uint32_t e = 0; e < topology.edgeCount(); ++e) {
            if (topology.edgeFaceCount(e) != 2) continue;
            uint32_t a = topology.edgeVertices[2 * e], b = topology.edgeVertices[2 * e + 1];
            glm::dvec3 points[2][5], normals[2][5];
            for (uint32_t side = 0; side < 2; ++side) {
                uint32_t f = topology.edgeFaces[topology.edgeFaceOffsets[e] + side];
                const uint32_t n = cage.faceSize(f);
                uint32_t first = 0;
                for (uint32_t g = 0; g < f; ++g) first += cage.faceSize(g) == 4 ? 1 : cage.faceSize(g);
                uint32_t ka = 0;
                while (cage.faceBegin(f)[ka] != a) ++ka;
                bool forward = cage.faceBegin(f)[(ka + 1) % n] == b;  // edge ka runs a -> b
                for (int i = 0; i < 5; ++i) {
                    double t = 0.1 + 0.2 * i;  // fraction from a to b
                    qp::PnSample p;
                    if (n == 4) {
                        const double corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
                        uint32_t kb = forward ? (ka + 1) % 4 : (ka + 3) % 4;
                        double u = (1 - t) * corner[ka][0] + t * corner[kb][0], v = (1 - t) * corner[ka][1] + t * corner[kb][1];
                        p = qp::evaluatePn(patches, first, float(u), float(v));
                    } else {
                        // Sub-face k covers the halves of edges k (its u side) and k-1 (its v side).
                        uint32_t k = forward ? ka : (ka + n - 1) % n;  // the edge's index in the face
                        bool nearStart = (forward && t <= 0.5) || (!forward && t >= 0.5);
                        double along = forward ? t : 1 - t;  // fraction from corner k to k+1
                        if (nearStart) p = qp::evaluatePn(patches, first + k, float(2 * along), 0.0f);
                        else p = qp::evaluatePn(patches, first + (k + 1) % n, 0.0f, float(2 * (1 - along)));
                    }
                    points[side][i] = glm::dvec3(p.position);
                    normals[side][i] = glm::dvec3(p.normal);
                }
            }
            for (int i = 0; i < 5; ++i) {
                gap = std::max(gap, glm::length(points[0][i] - points[1][i]));
                normalGap = std::max(normalGap, qp::test::angleDegrees(normals[0][i], normals[1][i]));
            }
        }
        EXPECT_LT(gap, 1e-5);
        EXPECT_LT(normalGap, 1e-3);
    }
}

TEST(Pn, FlatCageStaysFlat) {
    Cage grid = qp::test::makeGrid(3);
    for (glm::vec3& p : grid.positions) p.z = 0.0f;
    qp::PnPatches patches = build(grid);
    for (uint32_t s = 0; s < grid.faceCount(); ++s)
        for (float u : {0.1f, 0.5f, 0.9f})
            for (float v : {0.2f, 0.7f}) {
                qp::PnSample p = qp::evaluatePn(patches, s, u, v);
                EXPECT_NEAR(p.position.z, 0.0f, 1e-6f);
                EXPECT_NEAR(std::abs(p.normal.z), 1.0f, 1e-6f);
            }
}

TEST(Pn, DerivativesMatchFiniteDifferences) {
    Cage mixed = qp::test::makeMixedGrid();
    qp::PnPatches patches = build(mixed);
    const float h = 1e-3f;
    for (uint32_t s = 0; s < 20; ++s)
        for (glm::vec2 uv : {glm::vec2(0.3f, 0.2f), glm::vec2(0.25f, 0.6f), glm::vec2(0.7f, 0.55f)}) {
            qp::PnSample p = qp::evaluatePn(patches, s, uv.x, uv.y);
            glm::vec3 du = (qp::evaluatePn(patches, s, uv.x + h, uv.y).position - qp::evaluatePn(patches, s, uv.x - h, uv.y).position) / (2 * h);
            glm::vec3 dv = (qp::evaluatePn(patches, s, uv.x, uv.y + h).position - qp::evaluatePn(patches, s, uv.x, uv.y - h).position) / (2 * h);
            EXPECT_LT(glm::length(du - p.du), 2e-3f) << s;
            EXPECT_LT(glm::length(dv - p.dv), 2e-3f) << s;
        }
}

TEST(Pn, TriangleCagesDirectly) {
    Cage octahedron = makeOctahedron();
    qp::PnPatches patches = build(octahedron);
    EXPECT_EQ(patches.stats.triangles, 8u);
    EXPECT_EQ(patches.stats.quadsSplit, 0u);
    // A PN octahedron with unit vertex normals rounds towards the unit sphere: its face centres
    // bulge out of the flat faces (radius 1/sqrt(3) = 0.577 there).
    qp::PnSample centre = qp::evaluatePn(patches, 0, 1.0f, 1.0f);
    EXPECT_GT(glm::length(centre.position), 0.75f);
    EXPECT_LT(glm::length(centre.position), 1.0f);
}

// The README table (plugins/pn/README.md): PN-triangles against the exact limit. PN
// interpolates the cage, so the numbers are large by design; the test only checks that they
// are finite and that a cage whose limit is far from its vertices shows it.
TEST(Pn, ErrorTableOnSharedCages) {
    QP_REQUIRE_SHARED_SHAPES();
    qp::test::printErrorTable([](const std::string& name, const Cage& cage, const qp::test::ExactSurface& exact) {
        qp::PnPatches patches = build(cage);
        qp::test::SchemeError e = qp::test::printErrorTableRow("pn", name, patches.stats.triangles, exact,
                                                               qp::test::schemeEvaluator(patches, qp::evaluatePn));
        EXPECT_TRUE(std::isfinite(e.maxRelative)) << name;
        EXPECT_LT(e.maxRelative, 0.5) << name;
        if (name == "catmark_cube") {
            EXPECT_GT(e.maxRelative, 0.05);  // interpolating the corners
        }
    });
}
