// Buffers past the device's storage buffer range (issue 21): the plan pass then reaches its
// buffers by device address (render/plan_pass.h, PlanPass::byAddress), draws exactly what the
// storage-buffer variant draws, and a grid larger than lavapipe's 128 MiB range renders on the
// compute and the CPU grid paths instead of being refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include <glm/geometric.hpp>

#include "camera.h"
#include "mesh/generated_cage.h"
#include "offscreen_target.h"
#include "plan_pass.h"
#include "plans/planned_cage.h"
#include "render_test_support.h"
#include "test_cages.h"
#include "test_support.h"
#include "vk_commands.h"

namespace qp {
namespace {

constexpr uint32_t kSize = 96;

struct LargeBuffers : ::testing::Test {
    VulkanContext ctx;
    OffscreenTarget target;

    void SetUp() override {
        Result<VulkanContext> created = test::createTestContext();
        ASSERT_TRUE(created.ok()) << created.error().message;
        ctx = std::move(created).value();
        Result<OffscreenTarget> t = createOffscreenTarget(ctx, kSize, kSize, VK_FORMAT_R8G8B8A8_UNORM);
        ASSERT_TRUE(t.ok()) << t.error().message;
        target = *t;
    }
    void TearDown() override {
        if (!ctx.device) return;
        destroyOffscreenTarget(ctx, target);
        destroyContext(ctx);
        EXPECT_EQ(validationMessageCount(ctx), 0u) << test::describeMessages(ctx);
    }

    PlanView frame(const PlannedCage& planned) const {
        return test::framedPlanView(planned.cage(), kSize);
    }

    std::vector<uint8_t> pixels() {
        Result<std::vector<uint8_t>> read = readPixels(ctx, target);
        EXPECT_TRUE(read.ok());
        return read.ok() ? std::move(read).value() : std::vector<uint8_t>{};
    }

    // The three paths' pictures of `planned` through a pass of the given variant.
    std::vector<std::vector<uint8_t>> drawEveryPath(const PlannedCage& planned, bool byAddress) {
        std::vector<std::vector<uint8_t>> out;
        Result<PlanPass> pass = createPlanPass(ctx, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_D32_SFLOAT, byAddress);
        Result<PlanBuffers> buffers = uploadPlans(ctx, planned);
        EXPECT_TRUE(pass.ok() && buffers.ok());
        if (!pass.ok() || !buffers.ok()) return out;
        EXPECT_TRUE(bindPlanBuffers(ctx, *pass, *buffers).ok());
        EXPECT_EQ(pass->byAddress, byAddress) << "small buffers keep the pass's variant";
        const PlanView view = frame(planned);
        EXPECT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) {
            recordTessellated(cmd, *pass, *buffers, renderTarget(target), view, TessellationSettings{5, 0});
        }).ok());
        out.push_back(pixels());
        EXPECT_TRUE(prepareGrid(ctx, *pass, *buffers, 7).ok());
        EXPECT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) { recordGrid(cmd, *pass, *buffers, renderTarget(target), view); }).ok());
        out.push_back(pixels());
        buffers->gridEvaluator = GridEvaluator::None;
        evaluateGridOnCpu(planned, *buffers);
        EXPECT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) { recordGrid(cmd, *pass, *buffers, renderTarget(target), view); }).ok());
        out.push_back(pixels());
        destroyPlanBuffers(ctx, *buffers);
        destroyPlanPass(ctx, *pass);
        return out;
    }
};

double coverage(const std::vector<uint8_t>& rgba) {
    size_t covered = 0;
    for (size_t i = 0; i < rgba.size(); i += 4) covered += std::memcmp(&rgba[i], rgba.data(), 3) != 0;
    return double(covered) / double(rgba.size() / 4);
}

// The shaders of both variants do the same arithmetic on the same values; only where the loads
// come from differs. Creases, a corner, a hole, an n-gon and valence-3 vertices.
TEST_F(LargeBuffers, ByAddressDrawsWhatStorageBuffersDraw) {
    Cage mixed = test::makeMixedGrid();
    mixed.setEdgeSharpness(12, 13, kInfiniteSharpness);
    mixed.setEdgeSharpness(15, 16, 2.5f);
    mixed.setVertexSharpness(24, 3.0f);
    mixed.setHole(0, true);
    for (const Cage& cage : {mixed, test::makeSubdividedCube()}) {
        PlanDatabase database;
        const PlannedCage planned = test::planCage(cage, database);
        const auto bound = drawEveryPath(planned, false), addressed = drawEveryPath(planned, true);
        ASSERT_EQ(bound.size(), 3u);
        ASSERT_EQ(addressed.size(), 3u);
        const char* paths[] = {"tessellated", "compute grid", "CPU grid"};
        for (size_t p = 0; p < 3; ++p) {
            EXPECT_GT(coverage(bound[p]), 0.05) << paths[p];
            EXPECT_TRUE(bound[p] == addressed[p]) << paths[p] << ": the by-address picture differs";
        }
    }
}

// 1,500 faces at factor 64: about 6 million grid slots, 140 MiB of grid. Before, prepareGrid
// refused it ("larger than the Vulkan device's storage buffer range"); now the pass switches to
// the by-address variant, and the compute shader's grid agrees with the CPU evaluator's.
TEST_F(LargeBuffers, AGridLargerThanTheStorageBufferRangeRenders) {
    PlanDatabase database;
    const PlannedCage planned = test::planCage(makeBenchmarkCage(1500, 1), database);
    Result<PlanPass> pass = createPlanPass(ctx, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM);
    Result<PlanBuffers> uploaded = uploadPlans(ctx, planned);
    ASSERT_TRUE(pass.ok() && uploaded.ok());
    PlanBuffers& buffers = *uploaded;
    ASSERT_TRUE(bindPlanBuffers(ctx, *pass, buffers).ok());
    EXPECT_FALSE(pass->byAddress);
    const Status prepared = prepareGrid(ctx, *pass, buffers, 64);
    ASSERT_TRUE(prepared.ok()) << prepared.error().message;
    ASSERT_GT(buffers.grid.size, VkDeviceSize(ctx.properties.limits.maxStorageBufferRange));
    EXPECT_TRUE(pass->byAddress);

    const PlanView view = frame(planned);
    ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) { recordGrid(cmd, *pass, buffers, renderTarget(target), view); }).ok());
    const std::vector<uint8_t> computed = pixels();
    EXPECT_GT(coverage(computed), 0.1);
    const size_t slots = buffers.gridLayout.slotCount();
    const GridVertex* grid = static_cast<const GridVertex*>(buffers.grid.data);
    std::vector<GridVertex> gpu(grid, grid + slots);

    buffers.gridEvaluator = GridEvaluator::None;
    buffers.controlPointLevel = kNoControlPoints;
    evaluateGridOnCpu(planned, buffers);
    const float diagonal = computeBounds(planned.cage()).diagonal();
    float worst = 0.0f;
    size_t compared = 0;
    for (size_t slot = 0; slot < slots; slot += 31, ++compared) {  // the last slots lie past 128 MiB too
        const glm::vec3 a(gpu[slot].position[0], gpu[slot].position[1], gpu[slot].position[2]);
        const glm::vec3 b(grid[slot].position[0], grid[slot].position[1], grid[slot].position[2]);
        worst = std::max(worst, glm::length(a - b) / diagonal);
    }
    EXPECT_GT(compared, size_t(150'000));
    EXPECT_LT(worst, 1e-5f) << "compute-shader grid against the CPU evaluator, relative to the diagonal";
    ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) { recordGrid(cmd, *pass, buffers, renderTarget(target), view); }).ok());
    EXPECT_GT(coverage(pixels()), 0.1);
    EXPECT_TRUE(writePng((test::testOutputDir() / "plans_grid_past_storage_range.png").string(), kSize, kSize, computed).ok());
    destroyPlanBuffers(ctx, buffers);
    destroyPlanPass(ctx, *pass);
}

}  // namespace
}  // namespace qp
