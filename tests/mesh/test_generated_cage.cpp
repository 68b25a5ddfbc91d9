#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "mesh/cage.h"
#include "mesh/generated_cage.h"
#include "mesh/topology.h"
#include "plans/osd_refiner.h"

namespace {

using qp::BenchmarkCageCounts;
using qp::Cage;

TEST(GeneratedCage, CountsAreAsDocumented) {
    for (uint32_t target : {10u, 2000u, 100000u}) {
        BenchmarkCageCounts counts = qp::benchmarkCageCounts(target);
        EXPECT_EQ(counts.columns, 2 * counts.rows);
        EXPECT_EQ(counts.pokedQuads, std::max(1u, counts.gridQuads() / 100));
        EXPECT_EQ(counts.creases, std::max(1u, 2 * counts.gridQuads() / 100));
        if (target >= 2000) {
            EXPECT_NEAR(double(counts.faces()), double(target), 0.02 * target);
        }

        Cage cage = qp::makeBenchmarkCage(target, 7);
        EXPECT_EQ(cage.faceCount(), counts.faces());
        EXPECT_EQ(cage.vertexCount(), counts.vertices());
        EXPECT_EQ(cage.creases.size(), counts.creases);
        EXPECT_EQ(cage.corners.size(), counts.corners);

        qp::CageStats stats = qp::computeStats(cage, qp::buildTopology(cage));
        EXPECT_EQ(stats.edges, counts.edges());
        EXPECT_EQ(stats.faceSizeHistogram[3], 4 * counts.pokedQuads);
        EXPECT_EQ(stats.faceSizeHistogram[4], counts.gridQuads() - counts.pokedQuads);
        EXPECT_EQ(stats.boundaryEdges, 0u);
        EXPECT_EQ(stats.nonManifoldEdges, 0u);
        EXPECT_EQ(stats.nonManifoldVertices, 0u);
        EXPECT_EQ(stats.isolatedVertices, 0u);
    }
}

TEST(GeneratedCage, IsValidAndAcceptedByOpenSubdiv) {
    Cage cage = qp::makeBenchmarkCage(2000, 1);
    EXPECT_TRUE(qp::validateCage(cage, "generated").ok());
    auto refiner = qp::createRefiner(cage, "generated");
    ASSERT_TRUE(refiner.ok()) << refiner.error().message;
    EXPECT_EQ(uint32_t((*refiner)->GetLevel(0).GetNumFaces()), cage.faceCount());
}

TEST(GeneratedCage, IsDeterministicForASeed) {
    Cage a = qp::makeBenchmarkCage(2000, 42), b = qp::makeBenchmarkCage(2000, 42), c = qp::makeBenchmarkCage(2000, 43);
    EXPECT_TRUE(qp::sameTopologyAndTags(a, b));
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_FALSE(qp::sameTopologyAndTags(a, c));
}

TEST(GeneratedCage, HasTheFeaturesThatMakePlanningExpensive) {
    Cage cage = qp::makeBenchmarkCage(20000, 3);
    qp::Topology topology = qp::buildTopology(cage);
    qp::CageStats stats = qp::computeStats(cage, topology);
    EXPECT_GE(stats.valenceHistogram[5], 4u);  // the corners of a poked quad
    EXPECT_GT(stats.extraordinaryVertices, 0u);
    EXPECT_GT(stats.faceSizeHistogram[3], 0u);
    EXPECT_GT(stats.infinitelySharpEdges, 0u);
    EXPECT_GT(stats.creasedEdges, stats.infinitelySharpEdges);  // semi-sharp ones too
    EXPECT_EQ(stats.cornerVertices, 4u);
    for (const qp::EdgeCrease& c : cage.creases)
        EXPECT_TRUE(c.sharpness == qp::kInfiniteSharpness || (c.sharpness >= 0.5f && c.sharpness <= 4.0f));

    // The centre of a poked quad sits off the torus: its distance from the tube's core
    // circle differs from the minor radius.
    const glm::vec3 centre = cage.positions.back();
    float core = std::sqrt(centre.x * centre.x + centre.y * centre.y) - 2.0f;
    EXPECT_GT(std::abs(std::sqrt(core * core + centre.z * centre.z) - 1.0f), 1e-3f);
}

}  // namespace
