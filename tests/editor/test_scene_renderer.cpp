// The editor's SceneRenderer after tag and topology edits (editor/app/scene_renderer.h): `plans`
// takes both in place; a scheme whose update in place fails is rebuilt for the edited cage and
// the viewport says why (issue 15's bad input: nothing lost, no stale pixels).
#include <gtest/gtest.h>

#include "document.h"
#include "render_test_support.h"
#include "scene_renderer.h"
#include "test_cages.h"

using namespace qp;
using namespace qp::editor;

namespace {

struct SceneRendererTest : ::testing::Test {
    VulkanContext ctx;
    SceneRenderer renderer;
    std::unique_ptr<Document> doc;

    void SetUp() override {
        Result<VulkanContext> created = test::createTestContext();
        ASSERT_TRUE(created.ok()) << created.error().message;
        ctx = std::move(created).value();
        Result<SceneRenderer> made = createSceneRenderer(ctx, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM);
        ASSERT_TRUE(made.ok()) << made.error().message;
        renderer = std::move(made).value();
        Scene scene = sceneOfCage(test::makeSubdividedCube(3), "cage");
        Result<std::unique_ptr<Document>> opened = createDocument(scene, "", PlanOptions{});
        ASSERT_TRUE(opened.ok()) << opened.error().message;
        doc = std::move(opened).value();
    }
    void TearDown() override {
        if (!ctx.device) return;
        destroySceneRenderer(ctx, renderer);
        destroyContext(ctx);
        EXPECT_EQ(validationMessageCount(ctx), 0u) << test::describeMessages(ctx);
    }

    void sync(const PluginCatalog& catalog, const std::string& scheme) {
        SchemeRequest request;
        request.name = scheme;
        const EditReport change = takeUnsyncedPlanChange(*doc);
        ASSERT_TRUE(syncScene(ctx, renderer, catalog, *doc, 1, {&request, 1}, {}, change, DisplayOptions{}).ok());
        ASSERT_EQ(renderer.views.size(), 1u);
        ASSERT_TRUE(renderer.views[0].instance) << renderer.views[0].problem;
    }
};

// The cage's last face (a quad of the extrude) at its corner 0, through the instance.
glm::vec3 lastCorner(const SchemeView& view, const PlannedCage& planned) {
    const SampleRequest request{planned.subfaceCount() - 1, 0.0f, 0.0f};
    SurfacePoint point;
    EXPECT_TRUE(view.instance->evaluate({&request, 1}, {&point, 1}).ok());
    return point.position;
}

}  // namespace

TEST_F(SceneRendererTest, PlansTakesTagAndTopologyEditsInPlace) {
    const PluginCatalog catalog = loadPlugins(QUADPLAN_PLUGIN_DIR);
    sync(catalog, "plans");
    const Scheme* instance = &renderer.views[0].instance->scheme();
    const uint32_t* quad = doc->planned->cage().faceBegin(4);
    ASSERT_TRUE(applyEdit(*doc, SetEdgeSharpness{{{std::min(quad[0], quad[1]), std::max(quad[0], quad[1]), 3.0f}}}, 1).ok());
    sync(catalog, "plans");
    EXPECT_TRUE(renderer.views[0].planUpdateInPlace) << renderer.views[0].planUpdateNote;
    ASSERT_TRUE(applyEdit(*doc, ExtrudeFaces{{4}, 0.2f}, 2).ok());
    sync(catalog, "plans");
    EXPECT_TRUE(renderer.views[0].planUpdateInPlace) << renderer.views[0].planUpdateNote;
    EXPECT_NE(renderer.views[0].planUpdateNote.find("in place"), std::string::npos) << renderer.views[0].planUpdateNote;
    ASSERT_TRUE(undoEdit(*doc, 3).ok());
    sync(catalog, "plans");
    EXPECT_TRUE(renderer.views[0].planUpdateInPlace) << renderer.views[0].planUpdateNote;
    EXPECT_EQ(&renderer.views[0].instance->scheme(), instance) << "an edit made a new instance";
}

TEST_F(SceneRendererTest, AFailedUpdateInPlaceRebuildsForTheEditedCageAndSaysSo) {
    const PluginCatalog catalog = loadPlugins(QUADPLAN_TEST_PLUGIN_DIR);
    ASSERT_TRUE(catalog.find("test-update-fails")) << catalog.names();
    sync(catalog, "test-update-fails");
    const uint32_t facesBefore = doc->planned->cage().faceCount();
    ASSERT_TRUE(applyEdit(*doc, ExtrudeFaces{{4}, 0.2f}, 1).ok());
    ASSERT_GT(doc->planned->cage().faceCount(), facesBefore);
    sync(catalog, "test-update-fails");
    const SchemeView& view = renderer.views[0];
    EXPECT_FALSE(view.planUpdateInPlace);
    EXPECT_NE(view.planUpdateNote.find("failed"), std::string::npos) << view.planUpdateNote;
    EXPECT_NE(view.planUpdateNote.find("deliberate failure in updatePlans"), std::string::npos) << view.planUpdateNote;
    EXPECT_EQ(view.planRevision, doc->planRevision);
    // The rebuilt instance shows the edited cage (the flat test scheme is the cage itself).
    const PlannedCage& planned = *doc->planned;
    const uint32_t lastFace = planned.cage().faceCount() - 1;
    const glm::vec3 corner = planned.cage().positions[planned.cage().faceBegin(lastFace)[0]];
    EXPECT_LT(glm::length(lastCorner(view, planned) - corner), 1e-5f);
}

// A drag: one step behind, the renderer takes the step's vertices (Document::lastMove) instead
// of comparing every position; two steps behind it compares. Either way the instance shows the
// moved cage and the renderer's copy of the positions is the cage's.
TEST_F(SceneRendererTest, DragStepsReachTheInstanceWithTheirVerticesAlone) {
    const PluginCatalog catalog = loadPlugins(QUADPLAN_PLUGIN_DIR);
    sync(catalog, "plans");
    const glm::vec3 start = doc->planned->cage().positions[7], other = doc->planned->cage().positions[20];
    auto expectShowsTheCage = [&](const std::string& what) {
        EXPECT_EQ(renderer.positions, doc->planned->cage().positions) << what;
        for (uint32_t s = 0; s < doc->planned->subfaceCount(); ++s) {
            const SampleRequest request{s, 0.25f, 0.5f};
            SurfacePoint point;
            ASSERT_TRUE(renderer.views[0].instance->evaluate({&request, 1}, {&point, 1}).ok());
            const LimitSample exact = doc->planned->evaluate(s, 0.25f, 0.5f);
            ASSERT_LT(glm::length(point.position - exact.position), 1e-5f) << what << ", sub-face " << s;
        }
    };
    for (int step = 0; step < 3; ++step) {
        ASSERT_TRUE(applyEdit(*doc, MoveVertices{{7}, {start + glm::vec3(0.0f, 0.1f * float(step + 1), 0.0f)}, step > 0}, 1).ok());
        sync(catalog, "plans");
        EXPECT_EQ(renderer.views[0].updatedVertices, 1u);
        expectShowsTheCage("drag step " + std::to_string(step));
    }
    ASSERT_TRUE(applyEdit(*doc, MoveVertices{{7}, {start}, true}, 2).ok());
    ASSERT_TRUE(applyEdit(*doc, MoveVertices{{20}, {other + glm::vec3(0.2f, 0.0f, 0.0f)}, false}, 3).ok());
    sync(catalog, "plans");
    EXPECT_EQ(renderer.views[0].updatedVertices, 2u) << "two steps behind: both moved vertices, found by comparing";
    expectShowsTheCage("two steps at once");
}
