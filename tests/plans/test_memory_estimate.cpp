// A cage too large for the machine's memory is refused before planning allocates, with the
// estimate in the message (issue 21, bad input and limits).
#include <gtest/gtest.h>

#include "mesh/generated_cage.h"
#include "plans/memory_estimate.h"

TEST(MemoryEstimate, CountsSubfacesAtTheMeasuredCostOfOne) {
    const qp::Cage cage = qp::makeBenchmarkCage(3000, 1);
    const qp::BenchmarkCageCounts counts = qp::benchmarkCageCounts(3000);
    // Quads are one sub-face, the poked quads' triangles three each.
    const uint64_t subfaces = uint64_t(counts.gridQuads() - counts.pokedQuads) + 4ull * 3 * counts.pokedQuads;
    EXPECT_EQ(qp::planningBytesEstimate(cage), subfaces * qp::kPlanningBytesPerSubface);
}

TEST(MemoryEstimate, RefusesWhatTheMachineCannotHoldAndSaysHowMuch) {
    const qp::Status refused = qp::checkMemory(3ull << 30, 1ull << 30, "planning big.obj (1600000 faces)");
    ASSERT_FALSE(refused);
    const std::string& message = refused.error().message;
    EXPECT_NE(message.find("planning big.obj (1600000 faces)"), std::string::npos) << message;
    EXPECT_NE(message.find("3.0 GiB"), std::string::npos) << message;
    EXPECT_NE(message.find("1.0 GiB is available"), std::string::npos) << message;
    EXPECT_TRUE(qp::checkMemory(1ull << 30, 3ull << 30, "planning"));
    EXPECT_TRUE(qp::checkMemory(1ull << 40, 0, "planning")) << "unknown memory refuses nothing";
    EXPECT_GT(qp::availableMemoryBytes(), 0u) << "Linux reports MemAvailable";
}
