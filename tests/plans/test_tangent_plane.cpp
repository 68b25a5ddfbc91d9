// Where the limit surface has no tangent plane (core/plans/tangent_plane.h): the claim behind the
// samples `quadplan compare` leaves out of its normal statistics, checked against the spectrum
// of OpenSubdiv's own subdivision matrix around the vertex, and the corners the function names.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <bit>
#include <numeric>

#include <Eigen/Dense>
#include <glm/geometric.hpp>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyRefiner.h>

#include "plans/limit_reference.h"
#include "plans/osd_refiner.h"
#include "plans/planned_cage.h"
#include "plans/tangent_plane.h"
#include "test_cages.h"

namespace qp {
namespace {

using namespace OpenSubdiv;

// k quads around vertex 0, spokes 1..k+1 (closed: k spokes, the last face back to spoke 1),
// face corners k+2... Open fans end in two boundary edges at vertex 0.
Cage fan(uint32_t k, bool closed) {
    Cage cage;
    cage.positions.push_back({0.0f, 0.0f, 0.2f});
    const uint32_t spokes = closed ? k : k + 1;
    const float span = closed ? 2.0f * float(M_PI) : 0.5f * float(M_PI) * float(k) / 2.0f;
    for (uint32_t i = 0; i < spokes; ++i) {
        const float a = span * float(i) / float(closed ? spokes : spokes - 1);
        cage.positions.push_back({std::cos(a), std::sin(a), 0.1f * float(i % 2)});
    }
    for (uint32_t i = 0; i < k; ++i) {
        const float a = span * (float(i) + 0.5f) / float(closed ? spokes : spokes - 1);
        cage.positions.push_back({1.6f * std::cos(a), 1.6f * std::sin(a), -0.1f});
        const uint32_t quad[4] = {0, 1 + i, 1 + spokes + i, 1 + (i + 1) % spokes};
        cage.addFace(quad, 4);
    }
    return cage;
}

// Far primvar of one value per ring point (the impulse responses of the subdivision matrix).
constexpr int kMaxRing = 16;
struct Impulse {
    double w[kMaxRing];
    void Clear(void* = nullptr) { std::fill(std::begin(w), std::end(w), 0.0); }
    void AddWithWeight(const Impulse& source, float weight) {
        for (int i = 0; i < kMaxRing; ++i) w[i] += double(weight) * source.w[i];
    }
};

// The subdivision matrix of vertex 0's 1-ring from level 0 to level 1, as Far refines it: ring
// points are vertex 0, then per face its next and opposite corner (each once); below, their
// children (the vertex's, the edges', the faces').
Eigen::MatrixXd subdivisionMatrix(const Cage& cage) {
    Result<std::unique_ptr<Far::TopologyRefiner>> created = createRefiner(cage, "fan");
    EXPECT_TRUE(created.ok());
    Far::TopologyRefiner& refiner = **created;
    refiner.RefineUniform(Far::TopologyRefiner::UniformOptions(1));
    const Far::TopologyLevel& base = refiner.GetLevel(0);
    std::vector<Far::Index> ring{0}, below{base.GetVertexChildVertex(0)};
    for (Far::Index f : base.GetVertexFaces(0)) {
        const Far::ConstIndexArray v = base.GetFaceVertices(f);
        for (int step : {1, 2, 3}) {
            const Far::Index p = v[step];  // every fan face starts at vertex 0
            if (std::find(ring.begin(), ring.end(), p) != ring.end()) continue;
            ring.push_back(p);
            below.push_back(step == 2 ? base.GetFaceChildVertex(f) : base.GetEdgeChildVertex(base.FindEdge(0, p)));
        }
    }
    const int m = int(ring.size());
    EXPECT_LE(m, kMaxRing);
    std::vector<Impulse> source(size_t(base.GetNumVertices())), destination(size_t(refiner.GetLevel(1).GetNumVertices()));
    for (Impulse& s : source) s.Clear();
    for (int j = 0; j < m; ++j) source[size_t(ring[size_t(j)])].w[j] = 1.0;
    const Impulse* from = source.data();
    Impulse* to = destination.data();
    Far::PrimvarRefiner(refiner).Interpolate(1, from, to);
    Eigen::MatrixXd map(m, m);
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) map(i, j) = destination[size_t(below[size_t(i)])].w[j];
    return map;
}

struct Spectrum {
    double lambda1 = 0, lambda2 = 0, lambda3 = 0;  // the largest moduli after the limit position's 1
    // A tangent plane (Reif's conditions, as far as a spectrum shows them): lambda2 > |lambda3|,
    // the two dominant modes real and not defective, and, where the sector ends in sharp edges,
    // those edges moving with them (else the characteristic map collapses the sector's sharp
    // edges onto the vertex).
    bool tangentPlane = false;
};

// `edgeEnds`: ring slots of the points at the far end of the sector's bounding sharp edges.
Spectrum spectrumOf(const Eigen::MatrixXd& map, std::vector<int> edgeEnds = {}) {
    Eigen::EigenSolver<Eigen::MatrixXd> solver(map);
    const Eigen::VectorXcd values = solver.eigenvalues();
    std::vector<int> order(size_t(values.size()));
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return std::abs(values[a]) > std::abs(values[b]); });
    // Far's weights are floats: exact for the corner rule's (halves, quarters, sixteenths), off
    // by round-off for a smooth vertex's 1/n.
    EXPECT_NEAR(values[order[0]].real(), 1.0, 1e-6);  // affine invariance
    Spectrum s{std::abs(values[order[1]]), std::abs(values[order[2]]), std::abs(values[order[3]])};
    auto nullity = [&](double lambda) {
        Eigen::FullPivLU<Eigen::MatrixXd> lu(map - lambda * Eigen::MatrixXd::Identity(map.rows(), map.cols()));
        lu.setThreshold(1e-6);
        return int(map.rows() - lu.rank());
    };
    const bool real = std::abs(values[order[1]].imag()) < 1e-6 && std::abs(values[order[2]].imag()) < 1e-6;
    const bool notDefective = std::abs(s.lambda1 - s.lambda2) > 1e-6 || nullity(s.lambda1) >= 2;
    bool edgesMove = true;
    if (edgeEnds.size() == 2) {
        const Eigen::MatrixXd r = solver.eigenvectors().real();
        auto chord = [&](int mode, int end) { return r(end, order[size_t(mode)]) - r(0, order[size_t(mode)]); };
        const double det = chord(1, edgeEnds[0]) * chord(2, edgeEnds[1]) - chord(2, edgeEnds[0]) * chord(1, edgeEnds[1]);
        edgesMove = std::abs(det) > 1e-6;
    }
    s.tangentPlane = real && s.lambda2 > s.lambda3 + 1e-6 && notDefective && edgesMove;
    return s;
}

}  // namespace

TEST(TangentPlane, CornerSectorsOfTwoOrMoreFacesHaveNoneByOpenSubdivsOwnSubdivisionMatrix) {
    for (uint32_t k = 1; k <= 6; ++k) {
        SCOPED_TRACE("corner sector of " + std::to_string(k) + " faces");
        Cage cage = fan(k, false);
        cage.setVertexSharpness(0, kInfiniteSharpness);
        // Ring slots: vertex 0, then per face its spoke, face corner and next spoke (each once):
        // the first spoke is slot 1, the last 2k + 1.
        const Spectrum s = spectrumOf(subdivisionMatrix(cage), {1, int(2 * k + 1)});
        std::printf("corner, %u faces: lambda %.6f %.6f %.6f, tangent plane %s\n", k, s.lambda1, s.lambda2, s.lambda3,
                    s.tangentPlane ? "yes" : "no");
        EXPECT_EQ(s.tangentPlane, k == 1);
        Result<std::vector<SubfaceCorner>> corners = cornersWithoutTangentPlane(cage, "fan");
        ASSERT_TRUE(corners.ok());
        EXPECT_EQ(corners->size(), k == 1 ? 0u : k);
        for (const SubfaceCorner& c : *corners) EXPECT_EQ(c.corner, 0u);  // every fan face starts at the vertex
    }
    // The cases the criterion leaves alone, for contrast: smooth and dart vertices of valence
    // 3 to 7 have a tangent plane, and none of their corners is named.
    for (uint32_t n = 3; n <= 7; ++n) {
        SCOPED_TRACE("valence " + std::to_string(n));
        Cage smooth = fan(n, true);
        const Spectrum s = spectrumOf(subdivisionMatrix(smooth));
        Cage dart = smooth;
        dart.setEdgeSharpness(0, 1, kInfiniteSharpness);
        const Spectrum d = spectrumOf(subdivisionMatrix(dart));
        std::printf("valence %u: smooth lambda %.6f %.6f %.6f, dart %.6f %.6f %.6f\n", n, s.lambda1, s.lambda2, s.lambda3,
                    d.lambda1, d.lambda2, d.lambda3);
        EXPECT_TRUE(s.tangentPlane);
        EXPECT_TRUE(d.tangentPlane);
        for (const Cage* cage : {&smooth, &dart}) {
            Result<std::vector<SubfaceCorner>> corners = cornersWithoutTangentPlane(*cage, "fan");
            ASSERT_TRUE(corners.ok());
            EXPECT_TRUE(corners->empty());
        }
        // A cone point: the same vertex made a corner, one sector all around it.
        Cage cone = smooth;
        cone.setVertexSharpness(0, kInfiniteSharpness);
        EXPECT_FALSE(spectrumOf(subdivisionMatrix(cone)).tangentPlane);
        Result<std::vector<SubfaceCorner>> corners = cornersWithoutTangentPlane(cone, "fan");
        ASSERT_TRUE(corners.ok());
        EXPECT_EQ(corners->size(), n);
    }
}

TEST(TangentPlane, SectorsSplitAtSharpEdgesAndSubfacesOfNgons) {
    // A 4x4 grid: three infinitely sharp edges meet at the centre vertex 12 (the corner rule),
    // splitting its four faces into sectors of one, one and two faces.
    Cage cage = test::makeGrid(4);
    cage.setEdgeSharpness(12, 13, kInfiniteSharpness);
    cage.setEdgeSharpness(12, 11, kInfiniteSharpness);
    cage.setEdgeSharpness(12, 17, kInfiniteSharpness);
    Result<std::vector<SubfaceCorner>> corners = cornersWithoutTangentPlane(cage, "grid");
    ASSERT_TRUE(corners.ok());
    // The two faces below the T (faces 5 and 6, the vertex their corners 2 and 3) share the
    // sector without a sharp edge between them; the faces above it are one-face sectors.
    const std::vector<SubfaceCorner> expected{{5, 2}, {6, 3}};
    EXPECT_EQ(*corners, expected);

    // A pentagon at a cone point: its sub-face at the vertex, corner 0.
    Cage mixed = test::makeMixedGrid();
    const uint32_t centre = uint32_t(mixed.positions.size() - 1);
    mixed.setVertexSharpness(centre, kInfiniteSharpness);
    Result<std::vector<SubfaceCorner>> ngon = cornersWithoutTangentPlane(mixed, "mixed");
    ASSERT_TRUE(ngon.ok());
    ASSERT_EQ(ngon->size(), 2u);  // the triangle's and the pentagon's sub-faces at the centre
    for (const SubfaceCorner& c : *ngon) EXPECT_EQ(c.corner, 0u);

    EXPECT_EQ(domainCorner(0.0, 0.0), 0);
    EXPECT_EQ(domainCorner(1.0, 1.0), 2);
    EXPECT_EQ(domainCorner(0.0, 1.0), 3);
    EXPECT_EQ(domainCorner(0.5, 0.0), -1);
    EXPECT_EQ(patchCornerOfDomain(3, 0, 4, 1), 1);  // the last patch of the bottom row, its corner (1, 0)
    EXPECT_EQ(patchCornerOfDomain(3, 0, 4, 0), -1);
}

TEST(TangentPlane, PlansAndTheReferenceCarryTheDartsExactPlaneAtEveryDepth) {
    // A valence-6 dart: Far's own end caps carry Sdc's smooth-rule tangents there, degrees off at
    // depth 6 (catmark_inf_crease1: 4.7 / 2.2 / 0.8 degrees at depths 4 / 6 / 8).
    Cage cage = fan(6, true);
    cage.positions[3].z += 0.4f;  // no symmetry that would put the smooth masks' plane right
    cage.setEdgeSharpness(0, 1, kInfiniteSharpness);
    Result<std::unique_ptr<Far::TopologyRefiner>> refiner = createRefiner(cage, "dart");
    ASSERT_TRUE(refiner.ok());
    (*refiner)->RefineAdaptive(Far::TopologyRefiner::AdaptiveOptions(2));
    std::optional<ExactTangents> tangents = exactTangents(**refiner, 0);
    ASSERT_TRUE(tangents.has_value());
    glm::dvec3 t[2]{glm::dvec3(0.0), glm::dvec3(0.0)};
    for (size_t k = 0; k < 2; ++k)
        for (size_t j = 0; j < tangents->ring.size(); ++j) t[k] += tangents->left[k][j] * glm::dvec3(cage.positions[size_t(tangents->ring[j])]);
    const glm::dvec3 exact = glm::normalize(glm::cross(t[0], t[1]));
    auto offPlane = [&](glm::dvec3 du, glm::dvec3 dv) {  // degrees between the normal and the exact one, either sign
        const glm::dvec3 n = glm::normalize(glm::cross(du, dv));
        return std::asin(std::min(1.0, glm::length(glm::cross(n, exact)))) * 180.0 / M_PI;
    };
    for (uint32_t depth : {3u, 4u, 6u, 8u}) {
        SCOPED_TRACE("depth " + std::to_string(depth));
        PlanDatabase db;
        Result<PlannedCage> planned = PlannedCage::create(cage, db, PlanOptions{depth, true}, "dart");
        ASSERT_TRUE(planned.ok());
        Result<LimitReference> far = LimitReference::create(cage, depth, "dart");
        ASSERT_TRUE(far.ok());
        for (uint32_t face = 0; face < 6; ++face) {  // every fan face has the dart at corner 0
            const LimitSample ours = planned->evaluate(face, 0.0f, 0.0f);
            EXPECT_LT(offPlane(glm::dvec3(ours.du), glm::dvec3(ours.dv)), 0.01) << "face " << face;
            const ReferenceSample reference = far->evaluate(face, 0.0, 0.0);
            EXPECT_LT(offPlane(reference.du, reference.dv), 1e-6) << "face " << face;
            // A little inside the face both are on the patches OpenSubdiv builds, unchanged.
            const LimitSample inside = planned->evaluate(face, 0.5f, 0.5f);
            const ReferenceSample insideFar = far->evaluate(face, 0.5, 0.5);
            EXPECT_LT(glm::length(glm::dvec3(inside.position) - insideFar.position), 1e-5);
        }
    }
}

TEST(TangentPlane, ExtraordinaryCornersKeepTheirPlaneAtEveryDepth) {
    // A cube's valence-3 corners: the end caps' own corner tangents are differences of stencil
    // rows that shrink like 0.41^depth, and in float the plans' corner normals drifted from the
    // double reference as the depth grew (0.001, 0.007, 0.043 degrees at depths 4, 6, 8) until
    // the plans carried the corner's tangents as rows of their own (Plan::cornerTangents).
    const Cage cage = test::makeSubdividedCube(2);
    for (uint32_t depth : {4u, 6u, 8u}) {
        SCOPED_TRACE("depth " + std::to_string(depth));
        PlanDatabase db;
        Result<PlannedCage> planned = PlannedCage::create(cage, db, PlanOptions{depth, true}, "cube");
        ASSERT_TRUE(planned.ok());
        Result<LimitReference> far = LimitReference::create(cage, depth, "cube");
        ASSERT_TRUE(far.ok());
        double worst = 0.0;
        uint32_t corners = 0;
        for (uint32_t s = 0; s < planned->subfaceCount(); ++s) {
            corners += uint32_t(std::popcount(db.plan(planned->subfacePlan(s)).cornerTangents));
            for (auto [u, v] : {std::pair{0.0, 0.0}, std::pair{1.0, 0.0}, std::pair{1.0, 1.0}, std::pair{0.0, 1.0}}) {
                const LimitSample ours = planned->evaluate(s, float(u), float(v));
                const ReferenceSample exact = far->evaluate(s, u, v);
                const glm::dvec3 a = glm::normalize(glm::cross(glm::dvec3(ours.du), glm::dvec3(ours.dv)));
                const glm::dvec3 b = glm::normalize(glm::cross(exact.du, exact.dv));
                worst = std::max(worst, std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)) * 180.0 / M_PI);
            }
        }
        std::printf("depth %u: %u extraordinary corners, plans against the reference %.5f degrees\n", depth, corners, worst);
        EXPECT_EQ(corners, 24u);  // 8 valence-3 vertices, 3 faces each
        EXPECT_LT(worst, 0.002);
    }
}

}  // namespace qp
