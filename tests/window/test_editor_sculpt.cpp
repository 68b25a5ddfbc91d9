// The real editor's sculpting, second pass: the mask (painted with the M key's brush, kept by
// a raise stroke over it, inverted and cleared as one undo entry each through their keys) and
// the pick on the displaced surface (a tall bump seen edge-on).
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include "displacement/displaced_picker.h"
#include "editor_process.h"
#include "render_test_support.h"
#include "scene/scene.h"

using namespace qp;
using namespace qp::test;
using nlohmann::json;

namespace {

constexpr double kRunSeconds = 240.0;

class EditorSculpt : public ::testing::Test {
protected:
    fs::path dir;

    void SetUp() override {
        if (!haveDisplay()) GTEST_SKIP() << "SKIPPED: DISPLAY is unset; run under xvfb-run";
        dir = testOutputDir() / ("editor_sculpt_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir);
        fs::create_directories(dir / "recovery");
        for (const char* name : {"default.json", "default.obj"}) fs::copy_file(fs::path(QUADPLAN_SCENES_DIR) / name, dir / name);
    }

    void start(EditorProcess& editor, const std::string& script) {
        writeText(dir / "script.txt", script);
        editor.start({"edit", (dir / "default.json").string(), "--automation", (dir / "script.txt").string(), "--validate",
                      "--size", "1100x700"},
                     dir, editorEnvironment(dir / "recovery"), dir / "editor.log");
    }

    json waitForState(EditorProcess& editor, const std::string& name) {
        EXPECT_TRUE(waitForFile(dir / name, editor, kRunSeconds)) << name << " never came; editor output:\n" << editor.output();
        return readJson(dir / name);
    }

    void expectCleanExit(EditorProcess& editor) {
        EXPECT_EQ(editor.status >= 0 ? editor.status : editor.wait(kRunSeconds), 0) << editor.output();
    }

    Displacement savedDisplacement(const std::string& file) {
        Result<Scene> scene = loadSceneOrCage((dir / file).string());
        EXPECT_TRUE(scene.ok()) << scene.error().message;
        return scene.ok() ? scene->objects[0].displacement : Displacement{};
    }
};

// A horizontal drag with the sculpt tool at window row y.
std::string stroke(int x0, int x1, int y, int step = 5) {
    std::string s = "mouse-move " + std::to_string(x0) + " " + std::to_string(y) + "\nmouse-down left\nwait-frames 1\n";
    for (int x = x0; x <= x1; x += step) s += "mouse-move " + std::to_string(x) + " " + std::to_string(y) + "\nwait-frames 1\n";
    return s + "mouse-up left\nwait-frames 2\n";
}

size_t historySize(const json& state) { return state["history"]["size"].get<size_t>(); }
std::string lastEntry(const json& state) { return state["history"]["entries"].back()["name"].get<std::string>(); }

}  // namespace

// M (with the sculpt tool: the mask brush, not merge) paints a mask; a raise stroke across it
// changes unmasked samples only; Ctrl+I and Alt+M are one undo entry each.
TEST_F(EditorSculpt, MaskKeepsSamplesAndItsOperationsAreOneUndoEntryEach) {
    const int cx = 360, cy = 380;  // the front wall of the default scene in a 1100x700 window
    EditorProcess editor;
    start(editor, "wait-idle\nwait-frames 3\nset-tool sculpt\nkey m\nwait-frames 2\ndump-state m0.json\n"
                  "brush mask 0.05 1.0 constant\n" + stroke(cx - 30, cx + 30, cy) +
                  "wait-frames 2\ndump-state m1.json\nsave-as " + (dir / "masked.json").string() + "\nwait-frames 2\n"
                  "brush raise 0.1 0.3 smooth\n" + stroke(cx - 90, cx + 90, cy) +
                  "wait-frames 2\ndump-state m2.json\nsave-as " + (dir / "raised.json").string() + "\nwait-frames 2\n"
                  "key-down ctrl\nkey i\nkey-up ctrl\nwait-frames 2\ndump-state m3.json\n"
                  "key-down alt\nkey m\nkey-up alt\nwait-frames 2\ndump-state m4.json\n"
                  "undo\nwait-frames 2\ndump-state m5.json\nsave-as " + (dir / "end.json").string() + "\nwait-frames 2\nquit\n");
    const json m0 = waitForState(editor, "m0.json"), m1 = waitForState(editor, "m1.json"), m2 = waitForState(editor, "m2.json"),
               m3 = waitForState(editor, "m3.json"), m4 = waitForState(editor, "m4.json"), m5 = waitForState(editor, "m5.json");
    expectCleanExit(editor);

    EXPECT_EQ(m0["brush"]["kind"], "mask") << "M with the sculpt tool should pick the mask brush";
    EXPECT_EQ(historySize(m0), 0u) << "M merged vertices instead";
    ASSERT_TRUE(m1["displacement"].is_object());
    const uint32_t masked = m1["displacement"]["masked"].get<uint32_t>();
    EXPECT_GT(masked, 20u);
    EXPECT_EQ(m1["displacement"]["nonzero"], 0) << "a mask stroke changed D";
    EXPECT_GT(m1["displacement"]["mask_dots"].get<uint32_t>(), 0u) << "the mask is not shown";
    EXPECT_EQ(lastEntry(m1).rfind("Mask stroke", 0), 0u) << lastEntry(m1);

    // Fully masked samples keep their D bit for bit; others under the stroke moved.
    const Displacement before = savedDisplacement("masked.json"), after = savedDisplacement("raised.json");
    ASSERT_EQ(before.samples.size(), after.samples.size());
    ASSERT_EQ(after.mask.size(), after.samples.size());
    uint32_t full = 0, changed = 0;
    for (size_t k = 0; k < after.samples.size(); ++k) {
        if (after.mask[k] == 1.0f) {
            ++full;
            EXPECT_EQ(after.samples[k], before.samples[k]) << "masked sample " << k << " changed";
        }
        changed += after.samples[k] != before.samples[k];
    }
    EXPECT_GT(full, 10u);
    EXPECT_GT(changed, 50u) << "the raise stroke changed nothing";
    EXPECT_EQ(historySize(m2), historySize(m1) + 1);

    EXPECT_EQ(historySize(m3), historySize(m2) + 1);
    EXPECT_EQ(lastEntry(m3), "Invert mask");
    EXPECT_EQ(m3["displacement"]["masked"].get<uint32_t>(), m3["displacement"]["samples"].get<uint32_t>() - full)
        << "inverting keeps exactly the partly masked samples masked, and masks every unmasked one";
    EXPECT_EQ(m3["displacement"]["sample_revision"], m2["displacement"]["sample_revision"]) << "inverting changed D";
    EXPECT_EQ(historySize(m4), historySize(m3) + 1);
    EXPECT_EQ(lastEntry(m4), "Clear mask");
    EXPECT_EQ(m4["displacement"]["masked"], 0);
    EXPECT_EQ(m4["displacement"]["mask_dots"], 0);
    EXPECT_EQ(m5["displacement"]["masked"], m3["displacement"]["masked"]) << "undoing the clear did not bring the mask back";
}

// A tall bump on the front wall seen edge-on (from +X): the cursor beside the wall, over the
// bump's profile, picks the displaced bump, where no undisplaced surface is; the hit is the
// displaced point of its (sub-face, u, v) in the saved scene.
TEST_F(EditorSculpt, PickLandsOnTheDisplacedSurfaceSeenEdgeOn) {
    const int cx = 360, cy = 380;
    EditorProcess editor;
    // The synthetic mouse stays where it is only while a button is down: the pick is read during
    // a mask stroke, which changes the mask and not the surface.
    start(editor, "wait-idle\nwait-frames 3\nset-tool sculpt\nbrush raise 0.06 0.6 smooth\n" + stroke(cx - 5, cx + 5, cy) +
                      stroke(cx - 5, cx + 5, cy) + "action view.right\nwait-frames 3\nbrush mask 0.02 0.5\n"
                      "mouse-move 50 230\nwait-frames 2\nmouse-down left\nwait-frames 3\ndump-state p1.json\n"
                      "screenshot edge_on.png\nmouse-up left\nwait-frames 2\nsave\nwait-frames 2\nquit\n");
    const json p1 = waitForState(editor, "p1.json");
    expectCleanExit(editor);
    ASSERT_TRUE(p1["displacement"].is_object());
    const json& brush = p1["brush"];
    ASSERT_FALSE(brush["hover"].is_null()) << "nothing picked over the bump's profile";
    const glm::vec3 hover(brush["hover"][0].get<float>(), brush["hover"][1].get<float>(), brush["hover"][2].get<float>());
    const glm::vec3 limit(brush["hover_limit"][0].get<float>(), brush["hover_limit"][1].get<float>(),
                          brush["hover_limit"][2].get<float>());
    const float tallest = p1["displacement"]["max_abs"].get<float>();
    EXPECT_GT(glm::length(hover - limit), 0.2f * tallest) << "the pick is near the undisplaced wall, not on the bump";

    Result<Scene> scene = loadSceneOrCage((dir / "default.json").string());
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(scene->objects[0].cage, database, PlanOptions{}, "saved");
    ASSERT_TRUE(planned.ok()) << planned.error().message;
    const DisplacedPoint expected = displacedSurfacePoint(*planned, scene->objects[0].displacement,
                                                          brush["hover_site"]["subface"].get<uint32_t>(),
                                                          brush["hover_site"]["u"].get<float>(), brush["hover_site"]["v"].get<float>());
    EXPECT_LT(glm::length(expected.position - hover), 1e-4f) << "the hit is not on the displaced surface";
    const glm::vec3 normal(brush["hover_normal"][0].get<float>(), brush["hover_normal"][1].get<float>(),
                           brush["hover_normal"][2].get<float>());
    EXPECT_GT(glm::dot(expected.normal, normal), 0.9999f) << "the brush circle's plane is not the displaced surface's";
}

// A topology edit after sculpting is not refused: the extrude is one entry that keeps the
// displacement (fitted to the new cage), and undo brings the sculpted file's displacement back.
TEST_F(EditorSculpt, TopologyEditsKeepTheSculptAndUndoBringsItBack) {
    const int cx = 360, cy = 380;
    // Each state saved in a folder of its own: Save As writes the cage file beside the scene.
    for (const char* folder : {"sculpted", "edited", "undone"}) fs::create_directories(dir / folder);
    EditorProcess editor;
    start(editor, "wait-idle\nwait-frames 3\nset-tool sculpt\nbrush raise 0.1 0.3 smooth\n" + stroke(cx - 60, cx + 60, cy) +
                      "save-as " + (dir / "sculpted" / "scene.json").string() + "\nwait-frames 2\ndump-state t0.json\n"
                      "set-tool select\nselect face 0\nextrude 0.2\nwait-frames 3\ndump-state t1.json\n"
                      "loop 2 4 0.5\nwait-frames 3\ndump-state t2.json\nsave-as " + (dir / "edited" / "scene.json").string() + "\nwait-frames 2\n"
                      "undo\nundo\nwait-frames 3\nsave-as " + (dir / "undone" / "scene.json").string() + "\nwait-frames 2\nquit\n");
    const json t0 = waitForState(editor, "t0.json"), t1 = waitForState(editor, "t1.json"), t2 = waitForState(editor, "t2.json");
    expectCleanExit(editor);
    ASSERT_TRUE(t0["displacement"].is_object());
    ASSERT_GT(t0["displacement"]["nonzero"].get<uint32_t>(), 0u) << "the stroke raised nothing";
    EXPECT_GT(t1["faces"].get<uint32_t>(), t0["faces"].get<uint32_t>()) << "the extrude was refused: " << t1["status"];
    EXPECT_EQ(historySize(t1), historySize(t0) + 1);
    EXPECT_GT(t1["displacement"]["revision"].get<uint32_t>(), t0["displacement"]["revision"].get<uint32_t>());
    EXPECT_GE(t1["displacement"]["nonzero"].get<uint32_t>(), t0["displacement"]["nonzero"].get<uint32_t>() / 2);
    EXPECT_GT(t2["faces"].get<uint32_t>(), t1["faces"].get<uint32_t>()) << "the edge loop was refused: " << t2["status"];

    // The saved scene's displacement fits its cage (the scene loads), and two undos give back the
    // sculpted displacement bit for bit.
    const Displacement edited = savedDisplacement("edited/scene.json");
    EXPECT_FALSE(edited.empty());
    EXPECT_EQ(savedDisplacement("undone/scene.json"), savedDisplacement("sculpted/scene.json"));
}
