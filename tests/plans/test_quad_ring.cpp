// The core pieces the approximate patching schemes stand on: one Catmull-Clark step with its
// sub-face correspondence (refine_once.h), ordered quad 1-rings (quad_ring.h) and the limit
// position and tangents at a vertex (limit_frame.h), all against the exact limit surface.
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "plans/limit_frame.h"
#include "plans/quad_ring.h"
#include "plans/refine_once.h"
#include "scheme_test_support.h"
#include "test_cages.h"

namespace {

using qp::Cage;

// The exact surface of a cage and of its once-refined cage agree at corresponding points.
void expectRefinementKeepsSubfaceFrames(const Cage& cage) {
    auto refined = qp::refineOnce(cage, "test cage");
    ASSERT_TRUE(refined.ok()) << refined.error().message;
    for (uint32_t f = 0; f < refined->cage.faceCount(); ++f) ASSERT_EQ(refined->cage.faceSize(f), 4u);
    auto coarse = qp::test::makeExactSurface(cage);
    auto fine = qp::test::makeExactSurface(refined->cage);
    ASSERT_TRUE(coarse && fine);
    ASSERT_EQ(fine->planned->subfaceCount(), refined->cage.faceCount());
    double worst = 0.0, worstDerivative = 0.0;
    const double samples[] = {0.0, 0.1, 0.3, 0.5, 0.62, 0.9, 1.0};
    for (uint32_t s = 0; s < coarse->planned->subfaceCount(); ++s) {
        if (!coarse->planned->hasSurface(s)) continue;
        for (double u : samples)
            for (double v : samples) {
                qp::LimitSample a = coarse->planned->evaluate(s, float(u), float(v));
                qp::RefinedLocation at = qp::locateInRefined(*refined, s, u, v);
                ASSERT_TRUE(fine->planned->hasSurface(at.face));
                qp::LimitSample b = fine->planned->evaluate(at.face, float(at.s), float(at.t));
                worst = std::max(worst, double(glm::length(a.position - b.position)) / coarse->diagonal);
                // At a corner the derivatives' scale is arbitrary if it is an extraordinary vertex.
                if ((u == 0.0 || u == 1.0) && (v == 0.0 || v == 1.0)) continue;
                glm::vec3 du = float(at.dsdu) * b.du + float(at.dtdu) * b.dv;
                glm::vec3 dv = float(at.dsdv) * b.du + float(at.dtdv) * b.dv;
                worstDerivative = std::max({worstDerivative, double(glm::length(a.du - du)) / coarse->diagonal,
                                            double(glm::length(a.dv - dv)) / coarse->diagonal});
            }
    }
    EXPECT_LT(worst, 1e-6);
    EXPECT_LT(worstDerivative, 1e-3);
}

}  // namespace

TEST(RefineOnce, QuadsAndNgonsKeepTheirSubfaceFrames) {
    expectRefinementKeepsSubfaceFrames(qp::test::makeMixedGrid());
    expectRefinementKeepsSubfaceFrames(qp::test::makeCube());
}

TEST(RefineOnce, ChainsTwoSteps) {
    Cage cage = qp::test::makeMixedGrid();
    auto once = qp::refineOnce(cage);
    ASSERT_TRUE(once.ok());
    auto twice = qp::refineOnce(once->cage);
    ASSERT_TRUE(twice.ok());
    auto coarse = qp::test::makeExactSurface(cage);
    auto fine = qp::test::makeExactSurface(twice->cage);
    double worst = 0.0;
    for (uint32_t s = 0; s < coarse->planned->subfaceCount(); ++s)
        for (double u : {0.05, 0.3, 0.55, 0.8})
            for (double v : {0.1, 0.45, 0.7, 0.95}) {
                qp::RefinedLocation at = qp::locateInRefined(*twice, qp::locateInRefined(*once, s, u, v));
                qp::LimitSample a = coarse->planned->evaluate(s, float(u), float(v));
                qp::LimitSample b = fine->planned->evaluate(at.face, float(at.s), float(at.t));
                worst = std::max(worst, double(glm::length(a.position - b.position)));
                glm::vec3 du = float(at.dsdu) * b.du + float(at.dtdu) * b.dv;
                EXPECT_LT(glm::length(a.du - du), 1e-3f * glm::length(a.du) + 1e-4f);
            }
    EXPECT_LT(worst / coarse->diagonal, 1e-6);
}

TEST(QuadRing, InteriorAndBoundaryFansAreCounterClockwise) {
    Cage grid = qp::test::makeGrid(3);  // 4 x 4 vertices, vertex 5 interior, vertex 1 on the boundary
    qp::Topology topology = qp::buildTopology(grid);
    ASSERT_TRUE(qp::checkQuadManifold(grid, topology, "grid").ok());
    // Face 0 = (0, 1, 5, 4); vertex 5 is its corner 2.
    qp::QuadRing interior = qp::gatherQuadRing(grid, topology, 0, 2);
    EXPECT_FALSE(interior.boundary);
    ASSERT_EQ(interior.faceCount(), 4u);
    EXPECT_EQ(interior.faces[0], 0u);
    EXPECT_EQ(interior.edges[0], 4u);      // next corner of face 0 after 5
    EXPECT_EQ(interior.diagonals[0], 0u);
    EXPECT_EQ(interior.edges[1], 1u);
    // Vertex 1: boundary, faces 0 and 1; the fan starts at boundary neighbour 2 (face 1) and
    // ends at boundary neighbour 0 (face 0).
    qp::QuadRing boundary = qp::gatherQuadRing(grid, topology, 0, 1);
    EXPECT_TRUE(boundary.boundary);
    ASSERT_EQ(boundary.faceCount(), 2u);
    ASSERT_EQ(boundary.edges.size(), 3u);
    EXPECT_EQ(boundary.edges.front(), 2u);
    EXPECT_EQ(boundary.edges.back(), 0u);
    EXPECT_EQ(boundary.faces[boundary.startFace], 0u);
    EXPECT_EQ(boundary.effectiveValence(), 4u);
}

TEST(QuadRing, RejectsNonQuadsWithAMessage) {
    Cage cage = qp::test::makeMixedGrid();
    auto status = qp::checkQuadManifold(cage, qp::buildTopology(cage), "mixed");
    ASSERT_FALSE(status.ok());
    EXPECT_NE(status.error().message.find("all-quad"), std::string::npos);
}

namespace {

// Limit position and tangent plane at every vertex whose edges carry no tags, two ways:
//  - against the exact surface (plans) at the matching face corner: positions to float
//    precision; normals only roughly at extraordinary vertices, where the plans' float
//    derivatives are tiny (2^-6 scaled) and their normals scatter by up to ~1 degree;
//  - invariance under one Catmull-Clark step (the rigorous check, in double from float
//    points): the limit tangent plane of a vertex and of its child are the same plane, which
//    holds exactly for masks that are left eigenvectors of the subdivision matrix.
struct FrameError {
    double position = 0.0, regularAngle = 0.0, extraordinaryAngle = 0.0, boundaryAngle = 0.0;
    double invariance = 0.0, extraordinaryInvariance = 0.0, boundaryInvariance = 0.0;
    uint32_t checked = 0;
};

double cornerAngle(const qp::VertexLimit& a, const qp::QuadRing& ra, const qp::VertexLimit& b, const qp::QuadRing& rb) {
    return qp::test::angleDegrees(glm::cross(a.tangents[ra.startFace], a.tangents[ra.startFace + 1]),
                                  glm::cross(b.tangents[rb.startFace], b.tangents[rb.startFace + 1]));
}

FrameError checkVertexLimits(const Cage& cage, qp::TangentRule rule) {
    FrameError error;
    qp::Topology topology = qp::buildTopology(cage);
    EXPECT_TRUE(qp::checkQuadManifold(cage, topology, "cage").ok());
    auto exact = qp::test::makeExactSurface(cage);
    auto refined = qp::refineOnce(cage);
    EXPECT_TRUE(refined.ok());
    qp::Topology refinedTopology = qp::buildTopology(refined->cage);
    const glm::vec2 cornerUV[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    std::vector<bool> skip(cage.vertexCount(), false);
    for (const qp::EdgeCrease& c : cage.creases) skip[c.v0] = skip[c.v1] = true;
    for (const qp::VertexCorner& c : cage.corners) skip[c.vertex] = true;
    for (uint32_t f = 0; f < cage.faceCount(); ++f)
        for (uint32_t k = 0; k < 4; ++k) {
            uint32_t c = cage.faceBegin(f)[k];
            if (skip[c] || !exact->planned->hasSurface(exact->planned->firstSubface(f))) continue;
            qp::QuadRing ring = qp::gatherQuadRing(cage, topology, f, k);
            if (ring.boundary && ring.faceCount() == 1) continue;  // corners: plain B-spline corner
            qp::VertexLimit limit = qp::computeVertexLimit(cage, ring, rule);
            qp::LimitSample s = exact->planned->evaluate(exact->planned->firstSubface(f), cornerUV[k].x, cornerUV[k].y);
            error.position = std::max(error.position, glm::length(limit.position - glm::dvec3(s.position)) / exact->diagonal);
            glm::dvec3 normal = glm::cross(limit.tangents[ring.startFace], limit.tangents[ring.startFace + 1]);
            double angle = qp::test::angleDegrees(normal, glm::cross(glm::dvec3(s.du), glm::dvec3(s.dv)));
            // The child of corner k of face f is corner 0 of child face firstChild[f] + k.
            qp::QuadRing child = qp::gatherQuadRing(refined->cage, refinedTopology, refined->firstChild[f] + k, 0);
            double invariance = cornerAngle(limit, ring, qp::computeVertexLimit(refined->cage, child, rule), child);
            if (ring.boundary) {
                error.boundaryAngle = std::max(error.boundaryAngle, angle);
                error.boundaryInvariance = std::max(error.boundaryInvariance, invariance);
            } else if (ring.faceCount() != 4) {
                error.extraordinaryAngle = std::max(error.extraordinaryAngle, angle);
                error.extraordinaryInvariance = std::max(error.extraordinaryInvariance, invariance);
            } else {
                error.regularAngle = std::max(error.regularAngle, angle);
                error.invariance = std::max(error.invariance, invariance);
            }
            ++error.checked;
        }
    return error;
}

void expectExactFrames(const FrameError& e) {
    EXPECT_GT(e.checked, 0u);
    EXPECT_LT(e.position, 5e-6);           // the plans' float stencils at a valence-12 vertex: 2.2e-6
    EXPECT_LT(e.regularAngle, 1e-2);
    EXPECT_LT(e.extraordinaryAngle, 2.0);  // the reference's own scatter, see above
    EXPECT_LT(e.boundaryAngle, 0.05);
    EXPECT_LT(e.invariance, 1e-2);
    EXPECT_LT(e.extraordinaryInvariance, 5e-3);
    EXPECT_LT(e.boundaryInvariance, 5e-3);
}

}  // namespace

TEST(LimitFrame, ExactTangentsSpanTheLimitTangentPlane) {
    for (const Cage& cage : {qp::test::makeCube(), qp::test::makeSubdividedCube(), qp::test::makeGrid(4)})
        expectExactFrames(checkVertexLimits(cage, qp::TangentRule::Exact));
}

TEST(LimitFrame, SharedCagesInteriorAndBoundaryValences) {
    QP_REQUIRE_SHARED_SHAPES();
    for (const char* name : {"catmark_pawn", "catmark_car", "catmark_toroidal_tet", "catmark_gregory_test1",
                             "catmark_quadstrips", "catmark_tent"}) {
        SCOPED_TRACE(name);
        Cage cage = qp::test::loadSharedShape(name);
        FrameError exact = checkVertexLimits(cage, qp::TangentRule::Exact);
        FrameError mode = checkVertexLimits(cage, qp::TangentRule::AccEdgeMode);
        std::printf("%-22s %4u corners  position %.1e  vs plans (deg): regular %.1e EV %.2f boundary %.1e  "
                    "one-step invariance (deg): EV %.1e boundary %.1e, edge-mode EV %.3f\n",
                    name, exact.checked, exact.position, exact.regularAngle, exact.extraordinaryAngle,
                    exact.boundaryAngle, exact.extraordinaryInvariance, exact.boundaryInvariance,
                    mode.extraordinaryInvariance);
        expectExactFrames(exact);
        EXPECT_LT(mode.invariance, 1e-2);  // the two rules agree for valence 4
    }
}

TEST(LimitFrame, EdgeModeTangentsAreNotTheLimitTangentsAtValence3) {
    // The rule OpenSubdiv's Gregory end caps use moves under subdivision: not an eigenvector
    // (on symmetric rings both rules give the same plane, so break the cube's symmetry).
    Cage cage = qp::test::makeSubdividedCube();
    for (size_t i = 0; i < cage.positions.size(); ++i)
        cage.positions[i] += 0.15f * glm::vec3(std::sin(1.7f * float(i)), std::cos(2.3f * float(i)), std::sin(0.9f * float(i) + 1.0f));
    FrameError mode = checkVertexLimits(cage, qp::TangentRule::AccEdgeMode);
    FrameError exact = checkVertexLimits(cage, qp::TangentRule::Exact);
    EXPECT_GT(mode.extraordinaryInvariance, 1e-2);
    EXPECT_LT(exact.extraordinaryInvariance, 1e-3);
}
