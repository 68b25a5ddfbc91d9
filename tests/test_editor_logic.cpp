// The editor's parts that need no window: automation parsing, the orbit camera, screen-space
// picking, the document's edit route and saving, recovery files, frame statistics.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include <unistd.h>

#include <glm/gtc/matrix_transform.hpp>

#include "automation.h"
#include "cage_pick.h"
#include "document.h"
#include "frame_stats.h"
#include "recovery.h"
#include "test_cages.h"
#include "view_camera.h"

using namespace qp;
using namespace qp::editor;
namespace fs = std::filesystem;

namespace {

fs::path scratchDir(const std::string& name) {
    fs::path dir = fs::temp_directory_path() / ("quadplan_editor_logic_" + std::to_string(getpid())) / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::unique_ptr<Document> cubeDocument() {
    Scene scene;
    scene.cage = test::makeSubdividedCube(2);
    Result<std::unique_ptr<Document>> doc = createDocument(scene, "", PlanOptions{});
    EXPECT_TRUE(doc.ok()) << doc.error().message;
    return doc ? std::move(doc).value() : nullptr;
}

// --- automation scripts -------------------------------------------------------------------

TEST(AutomationScript, ParsesCommandsCommentsAndQuotedText) {
    Result<std::vector<AutomationCommand>> parsed = parseAutomation(
        "# a comment\n\nwait-frames 3\nclick-button \"Discard changes\"\nset-edge-sharpness 1 2 2.5 # trailing\n"
        "select-vertex 4 add\nkey KP7\nmeasure-frames 10 out.json drag\n",
        "script");
    ASSERT_TRUE(parsed.ok()) << parsed.error().message;
    ASSERT_EQ(parsed->size(), 6u);
    EXPECT_EQ((*parsed)[0].line, 3);
    EXPECT_EQ((*parsed)[1].args, std::vector<std::string>{"Discard changes"});
    EXPECT_EQ((*parsed)[2].args, (std::vector<std::string>{"1", "2", "2.5"}));
    EXPECT_EQ((*parsed)[3].args, (std::vector<std::string>{"4", "add"}));
    EXPECT_EQ((*parsed)[5].args.size(), 3u);
}

TEST(AutomationScript, RejectsMistakesNamingTheLine) {
    struct Case {
        const char* text;
        const char* expected;
    } cases[] = {
        {"wait-frames 2\nfly-to-moon\n", "script:2: unknown command 'fly-to-moon'"},
        {"select-vertex -3\n", "not a whole number"},
        {"move-selection 1 2\n", "needs 3 argument"},
        {"move-selection 1 2 nan\n", "not a number"},
        {"wait-frames 1 2\n", "unexpected '2'"},
        {"action file.teleport\n", "unknown action"},
        {"key hyper\n", "unknown key"},
        {"mouse-down thumb\n", "left, middle or right"},
        {"set-color-by 0 rainbow\n", "colour mode"},
        {"measure-frames 5 out.json sprint\n", "'drag' or 'orbit'"},
    };
    for (const Case& c : cases) {
        Result<std::vector<AutomationCommand>> parsed = parseAutomation(c.text, "script");
        ASSERT_FALSE(parsed.ok()) << c.text;
        EXPECT_NE(parsed.error().message.find(c.expected), std::string::npos) << parsed.error().message;
    }
}

// --- the orbit camera ---------------------------------------------------------------------

TEST(ViewCamera, OrbitPanAndDollyKeepWhatTheyShould) {
    ViewCamera c;
    c.target = {1, 2, 3};
    c.distance = 4;
    orbit(c, 100, 50, 400);
    EXPECT_NEAR(glm::length(eyePosition(c) - c.target), 4.0f, 1e-5f);
    EXPECT_EQ(c.target, glm::vec3(1, 2, 3));

    const glm::vec3 before = c.target, forward = glm::normalize(c.target - eyePosition(c));
    pan(c, 30, -20, 400);
    EXPECT_GT(glm::length(c.target - before), 0.0f);
    EXPECT_NEAR(glm::dot(c.target - before, forward), 0.0f, 1e-5f);  // in the view plane

    dolly(c, 1);
    EXPECT_LT(c.distance, 4.0f);
    for (int i = 0; i < 1000; ++i) dolly(c, 10);
    EXPECT_GT(c.distance, 0.0f);  // never through the target
}

TEST(ViewCamera, StandardViewsLookAlongTheAxes) {
    ViewCamera c;
    setStandardView(c, StandardView::Front);
    EXPECT_NEAR(glm::normalize(eyePosition(c) - c.target).z, 1.0f, 1e-5f);
    setStandardView(c, StandardView::Right);
    EXPECT_NEAR(glm::normalize(eyePosition(c) - c.target).x, 1.0f, 1e-5f);
    setStandardView(c, StandardView::Top);
    EXPECT_NEAR(glm::normalize(eyePosition(c) - c.target).y, 1.0f, 1e-5f);
    EXPECT_NEAR(upVector(c).z, -1.0f, 1e-5f);  // front at the bottom of the screen, as in Blender
    setStandardView(c, StandardView::Bottom);
    EXPECT_NEAR(glm::normalize(eyePosition(c) - c.target).y, -1.0f, 1e-5f);
}

TEST(ViewCamera, FramedBoxIsInsideTheViewForAnyAspect) {
    const glm::vec3 lo(-1, 0, -2), hi(3, 1, 0.5f);
    for (float aspect : {0.5f, 1.0f, 2.5f})
        for (bool ortho : {false, true}) {
            ViewCamera c;
            c.yaw = 0.7f;
            c.pitch = 0.4f;
            c.orthographic = ortho;
            frameBox(c, lo, hi, aspect);
            const glm::mat4 vp = viewProjection(renderCamera(c, aspect, Bounds{lo, hi}));
            for (int corner = 0; corner < 8; ++corner) {
                glm::vec3 p((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y, (corner & 4) ? hi.z : lo.z);
                glm::vec4 clip = vp * glm::vec4(p, 1.0f);
                glm::vec3 ndc = glm::vec3(clip) / clip.w;
                EXPECT_LE(std::abs(ndc.x), 1.0f) << aspect << " " << ortho;
                EXPECT_LE(std::abs(ndc.y), 1.0f) << aspect << " " << ortho;
                EXPECT_GE(ndc.z, 0.0f);
                EXPECT_LE(ndc.z, 1.0f);
            }
        }
}

TEST(ViewCamera, SceneCameraRoundTrip) {
    Camera s;
    s.eye = {3.4f, 2.6f, 3.8f};
    s.target = {0.1f, 0.75f, 0.0f};
    s.fovYDegrees = 35.0f;
    const Camera back = toSceneCamera(fromSceneCamera(s));
    EXPECT_NEAR(glm::length(back.eye - s.eye), 0.0f, 1e-4f);
    EXPECT_NEAR(glm::length(back.target - s.target), 0.0f, 1e-6f);
    EXPECT_NEAR(back.fovYDegrees, 35.0f, 1e-4f);
}

// --- picking ------------------------------------------------------------------------------

TEST(CagePick, PicksTheNearestProjectedVertexAndEdge) {
    const Cage cage = test::makeGrid(3);  // vertices at integer x, y in [0, 3]
    const Topology topology = buildTopology(cage);
    // Looking straight down -z at the grid's centre; one world unit = 100 pixels.
    ScreenMapping m;
    m.rect = {{10, 20}, {600, 600}};
    m.viewProjection = glm::ortho(-1.5f, 4.5f, 4.5f, -1.5f, -10.0f, 10.0f) *
                       glm::lookAt(glm::vec3(0, 0, 5), glm::vec3(0, 0, 0), glm::vec3(0, 1, 0));
    std::optional<glm::vec2> p = projectToWindow(m, cage.positions[5]);  // (1, 1)
    ASSERT_TRUE(p);
    EXPECT_EQ(pickVertex(cage, m, *p + glm::vec2(4, -3), 12.0f), 5u);
    EXPECT_FALSE(pickVertex(cage, m, *p + glm::vec2(40, 0), 12.0f));
    // Half way between vertices 5 (1,1) and 6 (2,1): the edge, not a vertex.
    auto edge = pickEdge(cage, topology, m, *p + glm::vec2(50, 2), 6.0f);
    ASSERT_TRUE(edge);
    EXPECT_EQ(*edge, std::make_pair(5u, 6u));
    // A drag of (30, -20) pixels moves the projection by exactly that.
    const glm::vec3 offset = dragOffset(m, cage.positions[5], {30, -20});
    std::optional<glm::vec2> moved = projectToWindow(m, cage.positions[5] + offset);
    EXPECT_NEAR(moved->x - p->x, 30.0f, 1e-3f);
    EXPECT_NEAR(moved->y - p->y, -20.0f, 1e-3f);
}

// --- documents ----------------------------------------------------------------------------

TEST(Document, EditsGoThroughApplyEditAndBadOnesChangeNothing) {
    std::unique_ptr<Document> doc = cubeDocument();
    ASSERT_TRUE(doc);
    EXPECT_EQ(documentTitle(*doc), "untitled");
    const glm::vec3 start = doc->planned->cage().positions[3];

    Result<EditReport> moved = applyEdit(*doc, MoveVertices{{3}, {start + glm::vec3(0, 1, 0)}}, 7);
    ASSERT_TRUE(moved.ok()) << moved.error().message;
    EXPECT_EQ(moved->replannedFaces, 0u);  // moving vertices re-plans nothing
    EXPECT_EQ(doc->planned->cage().positions[3], start + glm::vec3(0, 1, 0));
    EXPECT_EQ(doc->positionRevision, 1u);
    EXPECT_TRUE(doc->dirty);
    EXPECT_EQ(documentTitle(*doc), "untitled*");
    EXPECT_EQ(doc->lastEdit->frame, 7u);

    EXPECT_FALSE(applyEdit(*doc, MoveVertices{{9999}, {glm::vec3(0)}}, 8).ok());
    EXPECT_FALSE(applyEdit(*doc, MoveVertices{{3}, {glm::vec3(NAN)}}, 8).ok());
    const Cage& cage = doc->planned->cage();
    const uint32_t a = cage.faceBegin(0)[0], b = cage.faceBegin(0)[1], opposite = cage.faceBegin(0)[2];
    Result<EditReport> notEdge = applyEdit(*doc, SetEdgeSharpness{a, opposite, 1.0f}, 8);
    ASSERT_FALSE(notEdge.ok());
    EXPECT_NE(notEdge.error().message.find("share no edge"), std::string::npos);
    EXPECT_FALSE(applyEdit(*doc, SetEdgeSharpness{a, b, -1.0f}, 8).ok());
    EXPECT_EQ(doc->planRevision, 0u);
    EXPECT_EQ(doc->lastEdit->frame, 7u);

    Result<EditReport> creased = applyEdit(*doc, SetEdgeSharpness{a, b, 3.0f}, 9);
    ASSERT_TRUE(creased.ok()) << creased.error().message;
    EXPECT_GT(creased->replannedFaces, 0u);
    EXPECT_EQ(doc->planRevision, 1u);
    EXPECT_FLOAT_EQ(doc->planned->cage().edgeSharpness(a, b), 3.0f);
    EXPECT_TRUE(doc->planned->differencesFromRebuild().empty());
}

TEST(Document, SelectionTogglesAndChecksIndices) {
    std::unique_ptr<Document> doc = cubeDocument();
    ASSERT_TRUE(doc);
    ASSERT_TRUE(selectVertex(*doc, 4, false).ok());
    ASSERT_TRUE(selectVertex(*doc, 2, true).ok());
    EXPECT_EQ(doc->selection.vertices, (std::vector<uint32_t>{2, 4}));
    ASSERT_TRUE(selectVertex(*doc, 4, true).ok());  // toggles off
    EXPECT_EQ(doc->selection.vertices, std::vector<uint32_t>{2});
    EXPECT_FALSE(selectVertex(*doc, 100000, false).ok());
    const Cage& cage = doc->planned->cage();
    ASSERT_TRUE(selectEdge(*doc, cage.faceBegin(0)[1], cage.faceBegin(0)[0]).ok());
    EXPECT_TRUE(doc->selection.vertices.empty());
    EXPECT_LT(doc->selection.edge->first, doc->selection.edge->second);
    clearSelection(*doc);
    EXPECT_TRUE(doc->selection.empty());
}

TEST(Document, SavesSceneOrCageAtomicallyAndClearsTheMarker) {
    const fs::path dir = scratchDir("save");
    std::unique_ptr<Document> doc = cubeDocument();
    ASSERT_TRUE(doc);
    ASSERT_TRUE(applyEdit(*doc, MoveVertices{{0}, {glm::vec3(-2, -2, -2)}}, 1).ok());
    Status bad = saveDocument(*doc, (dir / "cube.txt").string());
    ASSERT_FALSE(bad.ok());
    EXPECT_TRUE(doc->dirty);
    ASSERT_TRUE(saveDocument(*doc, (dir / "cube.json").string()).ok());
    EXPECT_FALSE(doc->dirty);
    EXPECT_EQ(doc->path, (dir / "cube.json").string());
    Result<Scene> scene = loadSceneOrCage((dir / "cube.json").string());
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    EXPECT_EQ(scene->cage.positions[0], glm::vec3(-2, -2, -2));
    ASSERT_TRUE(saveDocument(*doc, (dir / "cube.obj").string()).ok());
    Result<Scene> cage = loadSceneOrCage((dir / "cube.obj").string());
    ASSERT_TRUE(cage.ok()) << cage.error().message;
    EXPECT_EQ(cage->cage.faceCount(), doc->planned->cage().faceCount());
}

// --- recovery -----------------------------------------------------------------------------

TEST(Recovery, WritesFindsLoadsAndRemoves) {
    const fs::path dir = scratchDir("recovery");
    EXPECT_FALSE(findRecovery(dir.string()));
    Scene scene;
    scene.cage = test::makeCube();
    scene.cage.positions[0] = {-5, 0, 0};
    ASSERT_TRUE(writeRecovery((dir / "nested").string(), scene, {"/some/where.json", "2024-01-02 03:04:05"}).ok());
    std::optional<RecoveryInfo> found = findRecovery((dir / "nested").string());
    ASSERT_TRUE(found);
    EXPECT_EQ(found->source, "/some/where.json");
    EXPECT_EQ(found->savedAt, "2024-01-02 03:04:05");
    Result<Scene> loaded = loadRecovery((dir / "nested").string());
    ASSERT_TRUE(loaded.ok()) << loaded.error().message;
    EXPECT_EQ(loaded->cage.positions[0], glm::vec3(-5, 0, 0));
    removeRecovery((dir / "nested").string());
    EXPECT_FALSE(findRecovery((dir / "nested").string()));
}

TEST(Recovery, DirectoryFollowsTheEnvironment) {
    const char* saved = std::getenv("QUADPLAN_RECOVERY_DIR");
    const std::string keep = saved ? saved : "";
    setenv("QUADPLAN_RECOVERY_DIR", "/tmp/qp-recovery-test", 1);
    EXPECT_EQ(recoveryDirectory(), "/tmp/qp-recovery-test");
    unsetenv("QUADPLAN_RECOVERY_DIR");
    setenv("XDG_STATE_HOME", "/tmp/state", 1);
    EXPECT_EQ(recoveryDirectory(), "/tmp/state/quadplan");
    unsetenv("XDG_STATE_HOME");
    if (saved) setenv("QUADPLAN_RECOVERY_DIR", keep.c_str(), 1);
}

// --- frame statistics ---------------------------------------------------------------------

TEST(FrameStats, MediansByKindOfFrame) {
    FrameStats stats;
    for (int i = 1; i <= 9; ++i) stats.add({double(i), -1.0, 10.0 * i, i % 3 == 0});
    stats.setGpuMs(0, 5.0);  // the newest (9, drawn)
    const Summary cpu = summarize(stats, FrameField::Cpu);
    EXPECT_EQ(cpu.count, 9u);
    EXPECT_EQ(cpu.median, 5.0);
    EXPECT_EQ(cpu.max, 9.0);
    EXPECT_EQ(summarize(stats, FrameField::Cpu, 0, FrameFilter::SceneDrawn).count, 3u);   // 3, 6, 9
    EXPECT_EQ(summarize(stats, FrameField::Cpu, 0, FrameFilter::SceneDrawn).median, 6.0);
    EXPECT_EQ(summarize(stats, FrameField::Gpu).count, 1u);  // unknown GPU times are skipped
    EXPECT_EQ(summarize(stats, FrameField::Interval, 2).median, 90.0);
}

}  // namespace
