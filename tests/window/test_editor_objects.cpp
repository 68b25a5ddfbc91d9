// Issue 17 in the real editor with real X events (xdotool): Tab into object mode, a click picks
// an object, the move handle drags it (one history entry, the picture follows), undo and redo
// of object edits, Tab into edit mode on the picked object's cage, undo across the modes (a cage
// edit undone from object mode), the outliner's rows, Shift+D and X, and the scene saved with
// the objects as edited, and File > Export. One editor run (lavapipe on 2 cores is slow to start).
#include <gtest/gtest.h>

#include <cmath>

#include <glm/glm.hpp>

#include "editor_process.h"
#include "mesh/obj_io.h"
#include "render_test_support.h"
#include "scene/scene.h"
#include "test_cages.h"

using namespace qp;
using namespace qp::test;
using nlohmann::json;

namespace {

constexpr double kRunSeconds = 240.0;



const json& objectNamed(const json& state, const std::string& name) {
    for (const json& o : state["objects"])
        if (o["name"] == name) return o;
    static const json none;
    ADD_FAILURE() << "no object " << name << " in the state";
    return none;
}

glm::vec2 point(const json& j) { return {j[0].get<float>(), j[1].get<float>()}; }


class EditorObjectMode : public ::testing::Test {
protected:
    fs::path dir;

    void SetUp() override {
        if (!haveDisplay()) GTEST_SKIP() << "SKIPPED: DISPLAY is unset; run under xvfb-run";
        if (!haveProgram("xdotool")) GTEST_SKIP() << "SKIPPED: DISPLAY: xdotool is not installed";
        dir = testOutputDir() / ("objects_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir);
        fs::create_directories(dir / "recovery");
        ASSERT_TRUE(saveObj(makeSubdividedCube(2), (dir / "tower.obj").string()).ok());
        json objects = json::array();
        objects.push_back({{"name", "tower"}, {"cage", {{"path", "tower.obj"}}}});
        objects.push_back({{"name", "tower.001"}, {"instance_of", "tower"}, {"transform", {{"translation", {4, 0, 0}}}}});
        Cage block = makeCube();
        json positions = json::array(), faces = json::array();
        for (const glm::vec3& p : block.positions) positions.push_back({p.x, p.y, p.z});
        for (uint32_t f = 0; f < block.faceCount(); ++f)
            faces.push_back(std::vector<uint32_t>(block.faceBegin(f), block.faceBegin(f) + block.faceSize(f)));
        objects.push_back({{"name", "block"},
                           {"cage", {{"positions", positions}, {"faces", faces}}},
                           {"transform", {{"translation", {-4, 0, 0}}}}});
        const json scene = {{"format", "quadplan-scene"}, {"version", 2}, {"objects", objects},
                            {"camera", {{"eye", {0, -14, 6}}, {"target", {0, 0, 0}}, {"up", {0, 0, 1}}}},
                            {"display", {{"up_axis", "z"}}}};
        writeText(dir / "scene.json", scene.dump());
    }

    void start(EditorProcess& editor, const std::string& script) {
        writeText(dir / "script.txt", script);
        std::map<std::string, std::string> env = editorEnvironment(dir / "recovery");
        env["QUADPLAN_PLAN_CACHE"] = "off";
        editor.start({"edit", (dir / "scene.json").string(), "--automation", (dir / "script.txt").string(), "--validate",
                      "--size", "1100x700"},
                     dir, env, dir / "editor.log");
    }

    json state(EditorProcess& editor, const std::string& name) {
        EXPECT_TRUE(waitForFile(dir / name, editor, kRunSeconds)) << name << " never came:\n" << editor.output();
        return readJson(dir / name);
    }

    void act(const std::string& events, const std::string& go) {
        EXPECT_EQ(xdotool(events), 0) << events;
        writeText(dir / go, "");
    }
};

}  // namespace

TEST_F(EditorObjectMode, PicksPlacesEditsAndUndoesObjectsAcrossModes) {
    EditorProcess editor;
    std::string script = "wait-idle\nwait-frames 3\ndump-state s0.json\n";
    auto step = [&](int i, const std::string& extra = "") {
        script += "wait-file go" + std::to_string(i) + "\nwait-frames 4\n" + extra + "dump-state s" + std::to_string(i) + ".json\n";
    };
    step(1);
    step(2);
    step(3, "screenshot before.png\n");
    step(4, "screenshot after.png\n");
    step(5);
    step(6, "save-as " + (dir / "saved.json").string() + "\nwait-frames 2\n");
    step(7, "select-vertex 0\nmove-selection 0 0 1\nwait-frames 2\n");
    step(8);
    step(9);
    step(10);
    step(11);
    step(12);
    step(13, "action file.export\nwait-frames 3\nclick-button Export\nwait-frames 3\nwait-idle\nwait-frames 2\n");
    script += "quit\nclick-button Discard changes\n";
    start(editor, script);

    const json s0 = state(editor, "s0.json");
    ASSERT_TRUE(s0.is_object());
    EXPECT_EQ(s0["mode"], "edit");
    EXPECT_TRUE(objectNamed(s0, "tower")["edited"].get<bool>());
    const Screen screen{s0["window"]["x"].get<int>(), s0["window"]["y"].get<int>()};
    const glm::vec2 inViewport = point(objectNamed(s0, "tower")["screen"]) + glm::vec2(0, 150);  // the floor below the tower

    // Tab: object mode, the edited object selected.
    act("mousemove " + screen(inViewport) + " sleep 0.3 key Tab sleep 0.5", "go1");
    const json s1 = state(editor, "s1.json");
    EXPECT_EQ(s1["mode"], "object") << "Tab did not enter object mode";
    EXPECT_TRUE(objectNamed(s1, "tower")["selected"].get<bool>());

    // A click on the block picks it.
    const glm::vec2 blockAt = point(objectNamed(s1, "block")["screen"]);
    act("mousemove " + screen(blockAt) + " sleep 0.3 click 1 sleep 0.5", "go2");
    const json s2 = state(editor, "s2.json");
    EXPECT_TRUE(objectNamed(s2, "block")["selected"].get<bool>()) << "the click did not pick the block: " << s2["status"];
    EXPECT_FALSE(objectNamed(s2, "tower")["selected"].get<bool>());

    // W shows the move handle at the block's origin.
    act("key w sleep 0.5", "go3");
    const json s3 = state(editor, "s3.json");
    const json& gizmo = s3["viewports"][0]["gizmo"];
    ASSERT_TRUE(gizmo.is_object()) << "no move handle on the selected object";
    EXPECT_NEAR(gizmo["pivot"][0].get<float>(), -4.0f, 1e-4f);

    // Dragging its x arrow moves the block along x: shown live, one history entry.
    const glm::vec2 arrow = point(gizmo["x"]), along = glm::normalize(arrow - point(gizmo["centre"]));
    act("mousemove " + screen(arrow) + " sleep 0.3 mousedown 1 sleep 0.3 mousemove " + screen(arrow + 40.0f * along) +
            " sleep 0.3 mousemove " + screen(arrow + 90.0f * along) + " sleep 0.4 mouseup 1 sleep 0.5",
        "go4");
    const json s4 = state(editor, "s4.json");
    const float movedX = objectNamed(s4, "block")["translation"][0].get<float>();
    EXPECT_GT(movedX, -3.7f) << "the drag did not move the block";
    EXPECT_NEAR(objectNamed(s4, "block")["translation"][1].get<float>(), 0.0f, 1e-4f) << "an x drag moved it off its axis";
    ASSERT_EQ(s4["history"]["size"], 1) << "the drag is not one history entry";
    EXPECT_EQ(s4["history"]["entries"][0]["name"], "Transform block");
    EXPECT_TRUE(s4["dirty"].get<bool>());
    EXPECT_GT(differingPixels(dir / "before.png", dir / "after.png"), 800u) << "the picture did not follow the block";

    // Undo puts it back, redo moves it again; the saved scene has it where it was left.
    act("key ctrl+z sleep 0.5", "go5");
    const json s5 = state(editor, "s5.json");
    EXPECT_NEAR(objectNamed(s5, "block")["translation"][0].get<float>(), -4.0f, 1e-5f) << "Ctrl+Z did not undo the move";
    act("key ctrl+shift+z sleep 0.5", "go6");
    const json s6 = state(editor, "s6.json");
    EXPECT_NEAR(objectNamed(s6, "block")["translation"][0].get<float>(), movedX, 1e-5f) << "redo";
    Result<Scene> saved = loadScene((dir / "saved.json").string());
    ASSERT_TRUE(saved) << saved.error().message;
    ASSERT_EQ(saved->objects.size(), 3u);
    EXPECT_NEAR(saved->objects[2].transform.translation.x, movedX, 1e-5f);
    EXPECT_EQ(saved->objects[1].instanceOf, "tower");

    // Tab: edit mode on the block's cage; the script moves one of its vertices.
    act("mousemove " + screen(inViewport) + " sleep 0.3 key Tab sleep 0.5", "go7");
    const json s7 = state(editor, "s7.json");
    EXPECT_EQ(s7["mode"], "edit");
    EXPECT_TRUE(objectNamed(s7, "block")["edited"].get<bool>()) << "Tab did not edit the picked object's cage";
    EXPECT_EQ(s7["faces"], 6) << "not the block's cage";
    ASSERT_EQ(s7["history"]["size"], 2);

    // Back to object mode, then Ctrl+Z undoes the vertex move (a cage edit, from object mode),
    // and Ctrl+Z again the object move.
    act("key Tab sleep 0.4 key ctrl+z sleep 0.5", "go8");
    const json s8 = state(editor, "s8.json");
    EXPECT_EQ(s8["mode"], "object");
    EXPECT_EQ(s8["history"]["position"], 1);
    EXPECT_NEAR(s8["vertices"][0][2].get<float>(), s7["vertices"][0][2].get<float>() - 1.0f, 1e-5f)
        << "the vertex move was not undone";
    act("key ctrl+z sleep 0.5", "go9");
    const json s9 = state(editor, "s9.json");
    EXPECT_EQ(s9["history"]["position"], 0);
    EXPECT_NEAR(objectNamed(s9, "block")["translation"][0].get<float>(), -4.0f, 1e-5f);

    // The outliner: a click on the instance's row selects it; Shift+D copies it with a cage of
    // its own; X deletes the copy.
    const json& row = s9["widgets"]["tower.001  -> tower"];
    ASSERT_TRUE(row.is_array()) << "no outliner row for the instance";
    const glm::vec2 rowAt(row[0].get<float>() + 20.0f, row[1].get<float>() + row[3].get<float>() / 2);
    act("mousemove " + screen(rowAt) + " sleep 0.3 click 1 sleep 0.5", "go10");
    const json s10 = state(editor, "s10.json");
    EXPECT_TRUE(objectNamed(s10, "tower.001")["selected"].get<bool>()) << "the outliner row did not select";
    act("mousemove " + screen(inViewport) + " sleep 0.3 key shift+d sleep 0.6", "go11");
    const json s11 = state(editor, "s11.json");
    ASSERT_EQ(s11["objects"].size(), 4u) << "Shift+D did not duplicate";
    EXPECT_EQ(objectNamed(s11, "tower.002")["instance_of"], "");
    EXPECT_TRUE(objectNamed(s11, "tower.002")["selected"].get<bool>());
    act("key x sleep 0.5", "go12");
    const json s12 = state(editor, "s12.json");
    EXPECT_EQ(s12["objects"].size(), 3u) << "X did not delete the selected object";
    EXPECT_EQ(s12["validation_messages"], 0);

    // File > Export writes the scene's limit surface beside its file (saved.json since the Save As: saved.glb).
    writeText(dir / "go13", "");
    const json s13 = state(editor, "s13.json");
    EXPECT_EQ(s13["status"].get<std::string>().rfind("Exported 1 file(s): ", 0), 0u) << s13["status"];
    EXPECT_TRUE(fs::exists(dir / "saved.glb"));
    EXPECT_EQ(editor.wait(kRunSeconds), 0) << editor.output();
}
