// Culling (DrawView::cull, docs/culling.md): for every scheme that culls, on every path and from
// views around and inside the model, a culled frame draws exactly the pixels of the unculled one
// while drawing fewer patches; on an open cage, or one turned inside out, the back-patch tests
// stay off.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "camera.h"
#include "offscreen_target.h"
#include "plan_pass.h"
#include "planned_cage.h"
#include "render_test_support.h"
#include "scheme_host.h"
#include "scheme_test_support.h"
#include "test_cages.h"
#include "vk_commands.h"

using namespace qp;

namespace {

const PluginCatalog& catalog() {
    static const PluginCatalog plugins = loadPlugins(QUADPLAN_PLUGIN_DIR);
    return plugins;
}

struct Frame {
    std::vector<uint8_t> pixels;
    uint64_t patches = 0;
};

// A scheme with its options (e.g. plans with path=grid).
struct Variant {
    std::string scheme;
    std::vector<std::pair<std::string, std::string>> options;
    std::string name() const {
        std::string out = scheme;
        for (const auto& [key, value] : options) out += " " + key + "=" + value;
        return out;
    }
};

// One frame of `variant` through `camera`, culled by `cull`.
Frame drawFrame(const VulkanContext& ctx, const PlannedCage& planned, const Variant& variant, CullMethod cull,
                const RenderCamera& camera) {
    constexpr uint32_t kSize = 160;
    Frame frame;
    Result<OffscreenTarget> target = createOffscreenTarget(ctx, kSize, kSize, VK_FORMAT_R8G8B8A8_UNORM);
    EXPECT_TRUE(target.ok());
    if (!target) return frame;
    SchemeSettings settings;
    settings.tessFactor = 8;
    settings.options = variant.options;
    const GpuContext gpu{&ctx, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_D32_SFLOAT};
    Result<PreparedScheme> prepared = prepareScheme(catalog(), variant.scheme, planned, analyzeCage(planned.cage(), planned.topology()),
                                                    settings, gpu, "test cage");
    EXPECT_TRUE(prepared.ok()) << (prepared ? "" : prepared.error().message);
    if (prepared) {
        DrawView view;
        view.viewProjection = viewProjection(camera);
        view.eye = camera.eye;
        view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(camera), kSize);
        view.cull = cull;
        Result<DrawStats> drawn = DrawStats{};
        EXPECT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) { drawn = prepared->instance.record(cmd, renderTarget(*target), view); }).ok());
        if (drawn) frame.patches = drawn->patches;
        Result<std::vector<uint8_t>> pixels = readPixels(ctx, *target);
        if (pixels) frame.pixels = std::move(*pixels);
        EXPECT_TRUE(prepared->instance.destroyGpu().ok());
    }
    destroyOffscreenTarget(ctx, *target);
    return frame;
}

// Views: framing the model from six directions, one close up (part of the model off screen and
// the near plane through it: its back side shows through the cut), one orthographic.
std::vector<RenderCamera> views(const Cage& cage) {
    const Bounds bounds = computeBounds(cage);
    std::vector<RenderCamera> out;
    const glm::vec3 directions[] = {{1, 0.4f, 0.8f}, {-1, -0.5f, 0.6f}, {0.1f, 1, -0.2f}, {0.3f, -1, -0.9f}, {-0.7f, 0.2f, -1}, {0, 0.05f, 1}};
    for (const glm::vec3& d : directions) {
        RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
        camera.eye = camera.target + glm::length(camera.eye - camera.target) * glm::normalize(d);
        out.push_back(camera);
    }
    RenderCamera close = out[0];
    close.eye = close.target + 0.35f * (close.eye - close.target);
    close.target += 0.2f * (bounds.max - bounds.min);
    out.push_back(close);
    RenderCamera ortho = out[1];
    ortho.orthographic = true;
    ortho.orthoHeight = 0.8f * glm::length(bounds.max - bounds.min);
    out.push_back(ortho);
    return out;
}

// `closed`: the cage is closed and outward (back-patch tests apply), else only the frustum culls.
void expectSamePixelsFewerPatches(const Cage& cage, const std::string& name, bool closed, const std::vector<Variant>& variants) {
    Result<VulkanContext> context = test::createTestContext();
    ASSERT_TRUE(context.ok()) << context.error().message;
    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(cage, database, PlanOptions{}, name);
    ASSERT_TRUE(planned.ok());
    uint64_t drawn[5] = {}, views_ = 0;
    const std::vector<RenderCamera> cameras = views(cage);
    for (const Variant& variant : variants)
        for (size_t v = 0; v < cameras.size(); ++v) {
            const RenderCamera& camera = cameras[v];
            const Frame plain = drawFrame(*context, *planned, variant, CullMethod::None, camera);
            ++views_;
            drawn[0] += plain.patches;
            int k = 1;
            for (CullMethod method : {CullMethod::Frustum, CullMethod::TCone, CullMethod::NCone, CullMethod::PPlane}) {
                const Frame culled = drawFrame(*context, *planned, variant, method, camera);
                size_t differing = 0;
                for (size_t i = 0; i < plain.pixels.size() && i < culled.pixels.size(); i += 4)
                    differing += plain.pixels[i] != culled.pixels[i] || plain.pixels[i + 1] != culled.pixels[i + 1] ||
                                 plain.pixels[i + 2] != culled.pixels[i + 2];
                ASSERT_EQ(culled.pixels, plain.pixels) << name << ", " << variant.name() << ", view " << v << ", "
                                                       << cullMethodName(method)
                                                       << ": a culled frame differs in " << differing << " pixels";
                EXPECT_LE(culled.patches, plain.patches);
                drawn[k++] += culled.patches;
            }
        }
    EXPECT_LE(drawn[2], drawn[1]);
    EXPECT_LE(drawn[3], drawn[2]);
    EXPECT_LE(drawn[4], drawn[3]);
    if (closed) EXPECT_LT(drawn[4], drawn[0] * 9 / 10) << name << ": pplane culls";
    else EXPECT_EQ(drawn[4], drawn[1]) << name << ": back sides show on an open or inside-out cage; only the frustum culls";
    ::testing::Test::RecordProperty(name, std::to_string(drawn[0]) + " " + std::to_string(drawn[1]) + " " + std::to_string(drawn[2]) + " " +
                             std::to_string(drawn[3]) + " " + std::to_string(drawn[4]) + " patches drawn over " +
                             std::to_string(views_) + " frames (none, frustum, tcone, ncone, pplane)");
    EXPECT_EQ(test::describeMessages(*context), "");
    destroyContext(*context);
}

const std::vector<Variant> kPlanPaths = {{"plans", {{"path", "cpu"}}}, {"plans", {{"path", "grid"}}}, {"plans", {{"path", "tess"}}}};

// The torus with every face's winding reversed: closed, but its normals point inward.
Cage insideOutTorus() {
    Cage cage = test::makeTorus();
    for (uint32_t f = 0; f < cage.faceCount(); ++f)
        std::reverse(cage.faceVertices.begin() + cage.faceOffsets[f], cage.faceVertices.begin() + cage.faceOffsets[f + 1]);
    return cage;
}

}  // namespace

TEST(PlanCulling, ClosedTorusDrawsTheSamePixelsWithFewerSubfaces) {
    expectSamePixelsFewerPatches(test::makeTorus(), "torus", true, kPlanPaths);
}

TEST(PlanCulling, ClosedCubeWithExtraordinaryVerticesDrawsTheSamePixels) {
    expectSamePixelsFewerPatches(test::makeSubdividedCube(3), "subdivided cube", true, kPlanPaths);
}

TEST(PlanCulling, OpenGridCullsOnlyByTheFrustum) {
    expectSamePixelsFewerPatches(test::makeGrid(4), "grid", false, kPlanPaths);
}

TEST(PlanCulling, InsideOutTorusCullsOnlyByTheFrustum) {
    expectSamePixelsFewerPatches(insideOutTorus(), "inside-out torus", false, kPlanPaths);
}
