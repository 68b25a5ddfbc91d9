// Culling across edits (plans keeps its culling bounds between frames, core/culling/subface_cull_bounds.h
// updateSubfaceCullBounds): after vertex moves, a hole and topology edits, a culled frame of the
// same instance still draws exactly the pixels of its unculled frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <optional>
#include <tuple>

#include "camera.h"
#include "edit/edit_history.h"
#include "mesh/topology_edits.h"
#include "offscreen_target.h"
#include "plan_pass.h"
#include "plans/planned_cage.h"
#include "render_test_support.h"
#include "scheme_host.h"
#include "scheme_test_support.h"
#include "vk_commands.h"

using namespace qp;

namespace {

constexpr uint32_t kSize = 160;

struct CulledInstance {
    const VulkanContext& ctx;
    PreparedScheme prepared;
    OffscreenTarget target;
    uint64_t facingAway = 0;  // the last frame's DrawStats::facingAwayTriangles

    // The frame's pixels and the sub-faces it drew.
    std::pair<std::vector<uint8_t>, uint64_t> draw(const RenderCamera& camera, CullMethod cull) {
        DrawView view;
        view.viewProjection = viewProjection(camera);
        view.eye = camera.eye;
        view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(camera), kSize);
        view.cull = cull;
        Result<DrawStats> drawn = DrawStats{};
        EXPECT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) { drawn = prepared.instance.record(cmd, renderTarget(target), view); }).ok());
        Result<std::vector<uint8_t>> pixels = readPixels(ctx, target);
        EXPECT_TRUE(pixels.ok() && drawn.ok());
        facingAway = drawn ? drawn->facingAwayTriangles : 0;
        return {pixels ? *pixels : std::vector<uint8_t>{}, drawn ? drawn->patches : 0};
    }
};

// Pixels (RGBA) that differ between two frames.
size_t differing(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    if (a.size() != b.size()) return std::max(a.size(), b.size()) / 4;
    size_t count = 0;
    for (size_t i = 0; i < a.size(); i += 4) count += !std::equal(a.begin() + i, a.begin() + i + 4, b.begin() + i);
    return count;
}

// The cage framed from above and aside (the torus's far side faces away from it).
RenderCamera obliqueCamera(const Cage& cage) {
    const Bounds bounds = computeBounds(cage);
    RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
    camera.eye = camera.target + glm::length(camera.eye - camera.target) * glm::normalize(glm::vec3(0.3f, 1.0f, 0.6f));
    return camera;
}

// A closed 24 x 12 torus, planned, a device and a target to draw it into, and a camera from which
// its far side faces away.
class PlanCullingEdits : public ::testing::Test {
protected:
    void SetUp() override {
        Result<VulkanContext> created = test::createTestContext();
        ASSERT_TRUE(created.ok()) << created.error().message;
        context.emplace(std::move(created).value());
        Result<PlannedCage> torus = PlannedCage::create(test::makeTorus(24, 12), database, PlanOptions{}, "torus");
        ASSERT_TRUE(torus.ok());
        planned.emplace(std::move(torus).value());
        camera = obliqueCamera(planned->cage());
        Result<OffscreenTarget> createdTarget = createOffscreenTarget(*context, kSize, kSize, VK_FORMAT_R8G8B8A8_UNORM);
        ASSERT_TRUE(createdTarget.ok());
        target = *createdTarget;
    }
    void TearDown() override {
        if (!context) return;
        if (target) destroyOffscreenTarget(*context, *target);
        EXPECT_EQ(test::describeMessages(*context), "");
        destroyContext(*context);
    }
    // plans on draw path `path`, for the torus as it is now.
    Result<PreparedScheme> prepare(const char* path) {
        SchemeSettings settings;
        settings.options = {{"path", path}};
        const GpuContext gpu{&*context, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_D32_SFLOAT};
        return prepareScheme(catalog, "plans", *planned, analyzeCage(planned->cage(), planned->topology()), settings, gpu, "torus");
    }

    std::optional<VulkanContext> context;
    const PluginCatalog catalog = loadPlugins(QUADPLAN_PLUGIN_DIR);
    PlanDatabase database;
    std::optional<PlannedCage> planned;
    RenderCamera camera;
    std::optional<OffscreenTarget> target;
};

}  // namespace

TEST_F(PlanCullingEdits, MovesAndAHoleKeepCulledFramesExact) {
    for (const char* path : {"cpu", "grid", "tess"}) {
        Result<PreparedScheme> prepared = prepare(path);
        ASSERT_TRUE(prepared.ok()) << prepared.error().message;
        CulledInstance instance{*context, std::move(*prepared), *target};
        const auto before = instance.draw(camera, CullMethod::PPlane);
        EXPECT_LT(before.second, instance.draw(camera, CullMethod::None).second) << path << ": pplane culls the far side";

        // Move the far side of the torus sideways, out past the silhouette: patches that faced
        // away when the bounds were built now face the eye. Whole cross-sections of the tube move
        // (the torus has 24 of 12 vertices: vertex j * 24 + i is in cross-section i): moving only
        // their far vertices turns the tube inside out where the near ones stay, and pulling the
        // far side through the near side does too, which back-facing culling cannot handle
        // (docs/culling.md; the facing-away triangles there showed).
        std::vector<uint32_t> moved;
        std::vector<glm::vec3> positions;
        const glm::vec3 toEye = glm::normalize(camera.eye - camera.target);
        const glm::vec3 sideways = 3.0f * glm::normalize(glm::cross(toEye, glm::vec3(0, 1, 0)));
        constexpr uint32_t kColumns = 24, kRows = 12;
        ASSERT_EQ(planned->cage().vertexCount(), kColumns * kRows);
        for (uint32_t i = 0; i < kColumns; ++i) {
            glm::vec3 centre(0.0f);
            for (uint32_t j = 0; j < kRows; ++j) centre += planned->cage().positions[j * kColumns + i] / float(kRows);
            if (glm::dot(centre - camera.target, toEye) < -0.3f)
                for (uint32_t j = 0; j < kRows; ++j) {
                    moved.push_back(j * kColumns + i);
                    positions.push_back(planned->cage().positions[j * kColumns + i] + sideways);
                }
        }
        ASSERT_FALSE(moved.empty());
        ASSERT_TRUE(planned->moveVertices(moved, positions).ok());
        ASSERT_TRUE(instance.prepared.instance.updateMoved(moved).ok());
        const auto movedCulled = instance.draw(camera, CullMethod::PPlane);
        if (std::string(path) == "cpu") {
            EXPECT_GT(instance.facingAway, 0u) << "the CPU grid tests its moved triangles' facing again";
        }
        EXPECT_EQ(differing(movedCulled.first, instance.draw(camera, CullMethod::None).first), 0u) << path << ": after the move";

        // A hole opens the surface: back sides show through it, so only the frustum may cull.
        Result<EditReport> hole = planned->setHole(0, true);
        ASSERT_TRUE(hole.ok());
        Result<PlanUpdate> updated = instance.prepared.instance.updatePlans(PlanChange{hole->updatedSubfaceList, false, {}});
        ASSERT_TRUE(updated.ok());
        ASSERT_EQ(*updated, PlanUpdate::Updated);
        const auto holed = instance.draw(camera, CullMethod::PPlane);
        const auto holedPlain = instance.draw(camera, CullMethod::None);
        EXPECT_EQ(differing(holed.first, holedPlain.first), 0u) << path << ": with a hole";
        EXPECT_EQ(holed.second, instance.draw(camera, CullMethod::Frustum).second)
            << path << ": with a hole only the frustum culls";

        // Back as it was, for the next path.
        ASSERT_TRUE(planned->setHole(0, false).ok());
        std::vector<glm::vec3> back;
        for (const glm::vec3& p : positions) back.push_back(p - sideways);
        ASSERT_TRUE(planned->moveVertices(moved, back).ok());
        EXPECT_TRUE(instance.prepared.instance.destroyGpu().ok());
    }
}

// Topology edits (an extrude, its undo, a delete) renumber the sub-faces: plans carries the
// kept ones' bounds through the renumbering and builds only the new and re-planned ones. Each
// culled frame after an edit draws the pixels of its unculled one and culls exactly the
// sub-faces a fresh instance of the edited cage culls.
TEST_F(PlanCullingEdits, TopologyEditsCarryTheBoundsOfKeptSubfaces) {
    // The sub-faces a culled frame of `instance` culls.
    auto culledBy = [&](SchemeInstance& instance) {
        DrawView view;
        view.viewProjection = viewProjection(camera);
        view.eye = camera.eye;
        view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(camera), kSize);
        view.cull = CullMethod::PPlane;
        std::vector<uint32_t> culled;
        view.culledSubfacesOut = &culled;
        EXPECT_TRUE(submitAndWait(*context, [&](VkCommandBuffer cmd) { EXPECT_TRUE(instance.record(cmd, renderTarget(*target), view).ok()); }).ok());
        return culled;
    };
    for (const char* path : {"cpu", "tess"}) {
        Result<PreparedScheme> prepared = prepare(path);
        ASSERT_TRUE(prepared.ok()) << prepared.error().message;
        CulledInstance instance{*context, std::move(*prepared), *target};
        EXPECT_LT(instance.draw(camera, CullMethod::PPlane).second, instance.draw(camera, CullMethod::None).second) << path;
        EditHistory history;
        const uint32_t farFace = 5 * 24 + 3;  // on the tube's far side from this camera: its bounds change
        // Each edit, and whether the surface is closed after it (a deleted face opens it: only the
        // frustum may cull then, and from a framing view it culls nothing).
        std::vector<std::tuple<std::string, std::function<Result<EditReport>()>, bool>> edits = {
            {"extrude", [&] {
                 Result<TopologyEdit> edit = extrudeFaces(planned->cage(), planned->topology(), std::vector<uint32_t>{farFace}, 0.3f);
                 if (!edit) return Result<EditReport>(edit.error());
                 return history.applyTopologyEdit(*planned, "extrude", std::move(edit).value());
             }, true},
            {"undo", [&] { return history.undo(*planned); }, true},
            {"delete", [&] {
                 Result<TopologyEdit> edit = deleteFaces(planned->cage(), planned->topology(), std::vector<uint32_t>{2}, false);
                 if (!edit) return Result<EditReport>(edit.error());
                 return history.applyTopologyEdit(*planned, "delete", std::move(edit).value());
             }, false},
            {"undo the delete", [&] { return history.undo(*planned); }, true},
        };
        for (auto& [label, edit, closed] : edits) {
            Result<EditReport> report = edit();
            ASSERT_TRUE(report.ok() && report->topologyChanged) << label;
            std::vector<uint32_t> subfaces = report->updatedSubfaceList;
            for (uint32_t f : report->replannedFaceList)
                for (uint32_t s = planned->firstSubface(f); s < planned->firstSubface(f + 1); ++s) subfaces.push_back(s);
            std::sort(subfaces.begin(), subfaces.end());
            subfaces.erase(std::unique(subfaces.begin(), subfaces.end()), subfaces.end());
            Result<PlanUpdate> updated = instance.prepared.instance.updatePlans(PlanChange{subfaces, true, report->previousSubfaceOf});
            ASSERT_TRUE(updated.ok() && *updated == PlanUpdate::Updated) << path << ", " << label;
            const std::vector<uint32_t> carried = culledBy(instance.prepared.instance);
            const auto culledFrame = instance.draw(camera, CullMethod::PPlane);
            EXPECT_EQ(differing(culledFrame.first, instance.draw(camera, CullMethod::None).first), 0u) << path << ", " << label;
            Result<PreparedScheme> fresh = prepare(path);
            ASSERT_TRUE(fresh.ok());
            EXPECT_EQ(carried, culledBy(fresh->instance)) << path << ", " << label << ": the carried bounds cull as fresh ones";
            EXPECT_EQ(carried.empty(), !closed) << path << ", " << label;
            EXPECT_TRUE(fresh->instance.destroyGpu().ok());
        }
        EXPECT_TRUE(instance.prepared.instance.destroyGpu().ok());
    }
}
