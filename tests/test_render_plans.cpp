// Plans on the GPU (lavapipe, validation on): positions from both drawing paths match the CPU
// evaluator, shared edges are bit-identical, draws are split under lavapipe's vertex limit,
// and the pictures look like surfaces.
#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <numeric>
#include <tuple>

#include <glm/geometric.hpp>

#include "camera.h"
#include "line_pass.h"
#include "obj_io.h"
#include "offscreen_target.h"
#include "plan_pass.h"
#include "planned_cage.h"
#include "render_test_support.h"
#include "test_cages.h"
#include "test_support.h"
#include "vk_commands.h"

using namespace qp;

namespace {

constexpr uint32_t kImageSize = 320;

// Where a boundary vertex lies, independent of which sub-face produced it: a boundary point,
// or a position along a segment as a reduced fraction.
using BoundaryKey = std::tuple<int, uint32_t, uint32_t, uint32_t>;

BoundaryKey boundaryKey(const GpuPlanData& data, uint32_t drawn, uint32_t edge, uint32_t i, uint32_t n) {
    static const uint32_t startCorner[4] = {0, 1, 3, 0}, endCorner[4] = {1, 2, 2, 3};
    const GpuSubfaceBoundary& b = data.boundaries[drawn];
    const GpuEdgeRef& r = b.edges[edge];
    if (i == 0) return {0, b.corners[startCorner[edge]], 0, 0};
    if (i == n) return {0, b.corners[endCorner[edge]], 0, 0};
    uint32_t segment = r.segment, c = (r.flags & 1) ? n - i : i, k = n;
    if (r.flags & 2) {
        k = n / 2;
        if (i == k) return {0, r.midpoint, 0, 0};
        if (i > k) {
            segment = r.secondHalf;
            c = n - i;
        }
    }
    uint32_t g = std::gcd(c, k);
    return {1, segment, c / g, k / g};
}

struct Fixture : ::testing::Test {
    VulkanContext ctx;
    PlanPass pass;
    OffscreenTarget target;

    void SetUp() override {
        Result<VulkanContext> created = test::createTestContext();
        ASSERT_TRUE(created.ok()) << created.error().message;
        ctx = std::move(created).value();
        Result<PlanPass> p = createPlanPass(ctx, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM);
        ASSERT_TRUE(p.ok()) << p.error().message;
        pass = *p;
        Result<OffscreenTarget> t = createOffscreenTarget(ctx, kImageSize, kImageSize, VK_FORMAT_R8G8B8A8_UNORM);
        ASSERT_TRUE(t.ok()) << t.error().message;
        target = *t;
    }
    void TearDown() override {
        if (!ctx.device) return;
        destroyOffscreenTarget(ctx, target);
        destroyPlanPass(ctx, pass);
        destroyContext(ctx);
        EXPECT_EQ(validationMessageCount(ctx), 0u) << test::describeMessages(ctx);
    }

    PlanBuffers upload(const PlannedCage& planned) {
        Result<PlanBuffers> buffers = uploadPlans(ctx, planned);
        EXPECT_TRUE(buffers.ok()) << buffers.error().message;
        bindPlanBuffers(ctx, pass, *buffers);
        return std::move(buffers).value();
    }

    PlanView frame(const PlannedCage& planned) {
        Bounds bounds = computeBounds(planned.cage());
        RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
        PlanView view;
        view.viewProjection = viewProjection(camera);
        view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(camera), kImageSize);
        return view;
    }

    std::vector<uint8_t> pixels() {
        Result<std::vector<uint8_t>> read = readPixels(ctx, target);
        EXPECT_TRUE(read.ok());
        return std::move(read).value();
    }
};

PlannedCage planCage(const Cage& cage, PlanDatabase& db) {
    Result<PlannedCage> planned = PlannedCage::create(cage, db, {}, "test cage");
    EXPECT_TRUE(planned.ok()) << planned.error().message;
    return std::move(planned).value();
}

// EVs, an n-gon next to quads, semi-sharp and infinite creases, a corner, a hole, a boundary.
Cage featureCage() {
    Cage cage = test::makeMixedGrid();
    for (uint32_t x = 15; x < 19; ++x) cage.setEdgeSharpness(x, x + 1, 2.5f);  // an interior grid line
    cage.setEdgeSharpness(12, 13, kInfiniteSharpness);
    cage.setVertexSharpness(24, 3.0f);
    cage.setHole(0, true);
    return cage;
}

std::vector<std::pair<std::string, Cage>> testCages() {
    std::vector<std::pair<std::string, Cage>> cages = {{"features", featureCage()},
                                                       {"subdivided cube", test::makeSubdividedCube()}};
    if (test::haveSharedShapes())
        for (const char* name : {"catmark_nonquads", "catmark_cube_creases1", "catmark_pole8"}) {
            Result<Cage> cage = loadObj((test::sharedShapesDir() / (std::string(name) + ".obj")).string());
            if (cage) cages.push_back({name, std::move(cage).value()});
        }
    return cages;
}

double coverage(const std::vector<uint8_t>& rgba, const std::vector<uint8_t>& background) {
    size_t covered = 0;
    for (size_t i = 0; i < rgba.size(); i += 4) covered += std::memcmp(&rgba[i], &background[0], 3) != 0;
    return double(covered) / double(rgba.size() / 4);
}

}  // namespace

TEST_F(Fixture, GridPathMatchesCpuAndIsWatertight) {
    for (auto& [name, cage] : testCages()) {
        SCOPED_TRACE(name);
        PlanDatabase db;
        PlannedCage planned = planCage(cage, db);
        PlanBuffers buffers = upload(planned);
        const float diagonal = computeBounds(planned.cage()).diagonal();
        for (uint32_t factor : {2u, 7u, 16u}) {
            ASSERT_TRUE(prepareGrid(ctx, pass, buffers, factor).ok());
            ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) { recordGridEvaluation(cmd, pass, buffers); }).ok());
            const GridVertex* grid = static_cast<const GridVertex*>(buffers.grid.data);
            const uint32_t stride = gridVerticesPerSubface(buffers.gridFactor);
            double worst = 0.0;
            std::map<BoundaryKey, const GridVertex*> seen;
            uint32_t shared = 0;
            for (uint32_t d = 0; d < buffers.data.subfaces.size(); ++d) {
                const uint32_t n = gridFactorOf(buffers.data, d, buffers.gridFactor), side = n + 1;
                for (uint32_t k = 0; k < side * side; ++k) {
                    const uint32_t x = k % side, y = k / side;
                    const GridVertex& g = grid[d * stride + k];
                    LimitSample cpu = planned.evaluate(buffers.data.subfaces[d].subface, float(x) / float(n), float(y) / float(n));
                    worst = std::max(worst, double(glm::length(glm::vec3(g.position[0], g.position[1], g.position[2]) -
                                                               cpu.position)) / diagonal);
                    int edge = y == 0 ? 0 : x == n ? 1 : y == n ? 2 : x == 0 ? 3 : -1;
                    if (edge < 0) continue;
                    uint32_t i = (edge == 1 || edge == 3) ? y : x;
                    auto [it, inserted] = seen.emplace(boundaryKey(buffers.data, d, uint32_t(edge), i, n), &g);
                    if (!inserted) {
                        ++shared;
                        ASSERT_EQ(std::memcmp(it->second, &g, sizeof(GridVertex)), 0)
                            << "factor " << factor << ": drawn sub-face " << d << " edge " << edge << " vertex " << i
                            << " differs from its neighbour's copy";
                    }
                }
            }
            EXPECT_LE(worst, 1e-5) << "factor " << factor;
            EXPECT_GT(shared, 0u);
        }
        destroyPlanBuffers(ctx, buffers);
    }
}

TEST_F(Fixture, TessellatedPathMatchesCpuAndIsWatertight) {
    for (auto& [name, cage] : testCages()) {
        PlanDatabase db;
        PlannedCage planned = planCage(cage, db);
        PlanBuffers buffers = upload(planned);
        ASSERT_TRUE(enableCapture(ctx, buffers, 2'000'000).ok());
        bindPlanBuffers(ctx, pass, buffers);
        const float diagonal = computeBounds(planned.cage()).diagonal();
        for (TessellationSettings settings : {TessellationSettings{3, 0}, TessellationSettings{8, 0},
                                              TessellationSettings{0, 6.0f}, TessellationSettings{0, 2.5f}}) {
            SCOPED_TRACE(name + (settings.uniformFactor ? " uniform " + std::to_string(settings.uniformFactor)
                                                        : " adaptive " + std::to_string(settings.pixelsPerSegment)));
            PlanView view = frame(planned);
            view.capture = true;
            ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) {
                recordTessellated(cmd, pass, buffers, renderTarget(target), view, settings);
            }).ok());
            uint32_t overflow = 0;
            std::vector<CaptureRecord> records = readCapture(buffers, &overflow);
            ASSERT_EQ(overflow, 0u);
            ASSERT_GT(records.size(), buffers.data.subfaces.size());

            double worst = 0.0;
            std::map<BoundaryKey, const CaptureRecord*> seen;
            std::map<uint32_t, uint32_t> segmentFactor;
            uint32_t shared = 0, factorsAbove1 = 0;
            for (const CaptureRecord& r : records) {
                const uint32_t edge = r.edgeAndFactor & 0xff, n = r.edgeAndFactor >> 8;
                // Edge vertices are evaluated at i/n exactly, not at the tessellator's
                // approximation of it.
                float u = r.u, v = r.v;
                if (edge == 0 || edge == 2) u = float(r.edgeIndex) / float(n);
                if (edge == 1 || edge == 3) v = float(r.edgeIndex) / float(n);
                LimitSample cpu = planned.evaluate(buffers.data.subfaces[r.drawn].subface, u, v);
                worst = std::max(worst, double(glm::length(glm::vec3(r.position[0], r.position[1], r.position[2]) -
                                                           cpu.position)) / diagonal);
                if (edge == 4) continue;
                factorsAbove1 += n > 1;
                const GpuEdgeRef& ref = buffers.data.boundaries[r.drawn].edges[edge];
                // Both sides of a segment must cut it into the same number of pieces.
                const uint32_t pieces = (ref.flags & 2) ? n / 2 : n;
                auto [f, fresh] = segmentFactor.emplace(ref.segment, pieces);
                ASSERT_EQ(f->second, pieces) << "segment " << ref.segment << " split differently by two faces";
                auto [it, inserted] = seen.emplace(boundaryKey(buffers.data, r.drawn, edge, r.edgeIndex, n), &r);
                if (!inserted) {
                    ++shared;
                    ASSERT_EQ(std::memcmp(it->second->position, r.position, sizeof(r.position)), 0)
                        << "drawn sub-face " << r.drawn << " edge " << edge << " vertex " << r.edgeIndex << " of " << n;
                }
            }
            EXPECT_LE(worst, 1e-5);
            EXPECT_GT(shared, 0u);
            EXPECT_GT(factorsAbove1, 0u);
        }
        destroyPlanBuffers(ctx, buffers);
    }
}

TEST_F(Fixture, SplitDrawsMatchTheGridPathOnALargeCage) {
    QP_REQUIRE_SHARED_SHAPES();
    Result<Cage> car = loadObj((test::sharedShapesDir() / "catmark_car.obj").string());
    ASSERT_TRUE(car.ok());
    PlanDatabase db;
    PlannedCage planned = planCage(*car, db);
    PlanBuffers buffers = upload(planned);
    // 1,575 patches at factor 16 are 7 draws of at most 226 (lavapipe corrupts 228 and more).
    EXPECT_EQ(patchesPerDraw(16), 226u);
    ASSERT_GT(buffers.data.subfaces.size(), patchesPerDraw(16));
    PlanView view = frame(planned);
    TessellationSettings settings{16, 0};
    ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) { recordTessellated(cmd, pass, buffers, renderTarget(target), view, settings); }).ok());
    std::vector<uint8_t> tessellated = pixels();
    ASSERT_TRUE(prepareGrid(ctx, pass, buffers, 16).ok());
    ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) { recordGrid(cmd, pass, buffers, renderTarget(target), view); }).ok());
    std::vector<uint8_t> grid = pixels();
    std::vector<uint8_t> background(tessellated.begin(), tessellated.begin() + 4);  // corner pixel
    // Same surface, same camera: the silhouettes agree; stray triangles would not.
    size_t differ = 0;
    for (size_t i = 0; i < grid.size(); i += 4) {
        bool a = std::memcmp(&tessellated[i], background.data(), 3) != 0, b = std::memcmp(&grid[i], background.data(), 3) != 0;
        differ += a != b;
    }
    EXPECT_GT(coverage(grid, background), 0.15);
    EXPECT_LT(double(differ) / double(grid.size() / 4), 0.003);
    EXPECT_TRUE(writePng((test::testOutputDir() / "plans_car_tessellated.png").string(), kImageSize, kImageSize, tessellated).ok());
    EXPECT_TRUE(writePng((test::testOutputDir() / "plans_car_grid.png").string(), kImageSize, kImageSize, grid).ok());
    destroyPlanBuffers(ctx, buffers);
}

TEST_F(Fixture, ColourModesAndWireframeDraw) {
    PlanDatabase db;
    PlannedCage planned = planCage(featureCage(), db);
    PlanBuffers buffers = upload(planned);
    PlanView view = frame(planned);
    std::vector<uint8_t> shaded;
    for (ColorBy mode : {ColorBy::Shading, ColorBy::NodeKind, ColorBy::PlanDepth, ColorBy::Sharpness}) {
        view.colorBy = mode;
        view.wireframe = mode == ColorBy::NodeKind;
        ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) {
            recordTessellated(cmd, pass, buffers, renderTarget(target), view, TessellationSettings{0, 6.0f});
        }).ok());
        std::vector<uint8_t> image = pixels();
        std::vector<uint8_t> background(image.begin(), image.begin() + 4);
        EXPECT_GT(coverage(image, background), 0.1) << "mode " << uint32_t(mode);
        if (mode == ColorBy::Shading) shaded = image;
        else EXPECT_NE(image, shaded) << "mode " << uint32_t(mode) << " looks like plain shading";
        EXPECT_TRUE(writePng((test::testOutputDir() / ("plans_features_mode" + std::to_string(uint32_t(mode)) + ".png")).string(),
                             kImageSize, kImageSize, image).ok());
    }
    destroyPlanBuffers(ctx, buffers);
}

// Every shader and the clear encode colour the same way: one picture (plans, tessellation
// wireframe, cage lines, background) stores the same bytes in an _SRGB target, where the
// hardware encodes, and in a UNORM target, where the shaders do.
TEST_F(Fixture, SrgbAndUnormTargetsStoreTheSamePicture) {
    PlanDatabase db;
    PlannedCage planned = planCage(featureCage(), db);
    PlanView view = frame(planned);
    view.wireframe = true;
    const std::vector<LineVertex> cage = cageLines(planned.cage());
    std::vector<std::vector<uint8_t>> images;
    for (VkFormat format : {VK_FORMAT_R8G8B8A8_SRGB, VK_FORMAT_R8G8B8A8_UNORM}) {
        Result<OffscreenTarget> t = createOffscreenTarget(ctx, kImageSize, kImageSize, format);
        Result<PlanPass> plans = createPlanPass(ctx, VK_NULL_HANDLE, format);
        Result<LinePass> lines = createLinePass(ctx, VK_NULL_HANDLE, format);
        Result<PlanBuffers> buffers = uploadPlans(ctx, planned);
        Result<Buffer> lineBuffer = createBuffer(ctx, cage.size() * sizeof(LineVertex), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
        ASSERT_TRUE(t && plans && lines && buffers && lineBuffer);
        uploadBuffer(*lineBuffer, cage.data(), cage.size() * sizeof(LineVertex));
        bindPlanBuffers(ctx, *plans, *buffers);
        ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) {
            recordTessellated(cmd, *plans, *buffers, renderTarget(*t), view, TessellationSettings{6, 0});
            recordLines(cmd, *lines, renderTarget(*t), view.viewProjection, *lineBuffer, uint32_t(cage.size()));
        }).ok());
        Result<std::vector<uint8_t>> read = readPixels(ctx, *t);
        ASSERT_TRUE(read.ok());
        images.push_back(std::move(read).value());
        destroyBuffer(ctx, *lineBuffer);
        destroyPlanBuffers(ctx, *buffers);
        destroyLinePass(ctx, *lines);
        destroyPlanPass(ctx, *plans);
        destroyOffscreenTarget(ctx, *t);
    }
    int worst = 0;
    size_t differing = 0;
    for (size_t i = 0; i < images[0].size(); ++i) {
        const int d = std::abs(int(images[0][i]) - int(images[1][i]));
        worst = std::max(worst, d);
        differing += d > 1;
    }
    // Rounding differs by one level at most between the hardware's and the shader's encoding.
    EXPECT_LE(worst, 1) << differing << " bytes differ by more than one level";
    std::vector<uint8_t> background(images[1].begin(), images[1].begin() + 4);
    EXPECT_GT(coverage(images[1], background), 0.1);
}
