// Issue 15, "the modeler's hands", in the real editor with real X events (xdotool): Alt+click
// edge loops, Ctrl+Alt+click rings, double-click loops, Shift+Alt adding, face loops; a select
// drag that starts on the surface only boxes; H / Alt+H hide and show faces; the interactive
// extrude (mouse, typed distance, confirm, Esc and right-click cancel, one history entry);
// the live crease slider (one entry per drag) and Shift+E; the first sculpt stroke as one
// entry. Two editor runs, each combining several checks (lavapipe on 2 cores is slow to start).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include <glm/geometric.hpp>

#include "edit/edge_loops.h"
#include "editor_process.h"
#include "mesh/obj_io.h"
#include "mesh/topology.h"
#include "render_test_support.h"
#include "test_cages.h"

using namespace qp;
using namespace qp::test;
using nlohmann::json;

namespace {

constexpr double kRunSeconds = 240.0;


std::vector<EdgeKey> edgesOf(const json& selection) {
    std::vector<EdgeKey> out;
    for (const json& e : selection["edges"]) out.push_back(makeEdgeKey(e[0].get<uint32_t>(), e[1].get<uint32_t>()));
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<uint32_t> facesOf(const json& list) { return list.get<std::vector<uint32_t>>(); }


class EditorHands : public ::testing::Test {
protected:
    fs::path dir;
    Cage cage = makeSubdividedCube(4);  // 96 quads; a loop around it has 16 edges
    Topology topology;

    void SetUp() override {
        if (!haveDisplay()) GTEST_SKIP() << "SKIPPED: DISPLAY is unset; run under xvfb-run";
        if (!haveProgram("xdotool")) GTEST_SKIP() << "SKIPPED: DISPLAY: xdotool is not installed";
        dir = testOutputDir() / ("hands_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir);
        fs::create_directories(dir / "recovery");
        ASSERT_TRUE(saveObj(cage, (dir / "cube.obj").string()).ok());
        topology = buildTopology(cage);
    }

    void start(EditorProcess& editor, const std::string& script) {
        writeText(dir / "script.txt", script);
        std::map<std::string, std::string> env = editorEnvironment(dir / "recovery");
        editor.start({"edit", (dir / "cube.obj").string(), "--automation", (dir / "script.txt").string(), "--validate",
                      "--size", "1100x700"},
                     dir, env, dir / "editor.log");
    }

    json state(EditorProcess& editor, const std::string& name) {
        EXPECT_TRUE(waitForFile(dir / name, editor, kRunSeconds)) << name << " never came:\n" << editor.output();
        return readJson(dir / name);
    }

    // Sends X events, then lets the script go on past `wait-file NAME`.
    void act(const std::string& events, const std::string& go) {
        EXPECT_EQ(xdotool(events), 0) << events;
        writeText(dir / go, "");
    }
};


// Visible edges between regular (valence-4) vertices, long on screen, nearest the viewport's
// centre first: what a click at the midpoint picks without doubt.
std::vector<std::pair<EdgeKey, glm::vec2>> clickableEdges(const json& s, const Topology& t) {
    const json& view = s["viewports"][0];
    const glm::vec2 centre(view["rect"][0].get<float>() + view["rect"][2].get<float>() / 2,
                           view["rect"][1].get<float>() + view["rect"][3].get<float>() / 2);
    const json& projected = view["projected_vertices"];
    const json& pickable = view["pickable_vertices"];
    std::vector<std::pair<EdgeKey, glm::vec2>> out;
    for (uint32_t e = 0; e < t.edgeCount(); ++e) {
        const uint32_t a = t.edgeVertices[2 * e], b = t.edgeVertices[2 * e + 1];
        if (projected[a].is_null() || projected[b].is_null() || !pickable[a].get<bool>() || !pickable[b].get<bool>()) continue;
        if (t.vertexEdgeCount(a) != 4 || t.vertexEdgeCount(b) != 4) continue;
        const glm::vec2 pa(projected[a][0].get<float>(), projected[a][1].get<float>());
        const glm::vec2 pb(projected[b][0].get<float>(), projected[b][1].get<float>());
        if (glm::length(pa - pb) < 40.0f) continue;
        out.push_back({makeEdgeKey(a, b), 0.5f * (pa + pb)});
    }
    std::sort(out.begin(), out.end(), [&](const auto& x, const auto& y) {
        return glm::length(x.second - centre) < glm::length(y.second - centre);
    });
    return out;
}

}  // namespace

TEST_F(EditorHands, SelectsLoopsRingsBoxesAndHidesFaces) {
    EditorProcess editor;
    std::string script = "wait-idle\nwait-frames 3\nselect-mode edge\nwait-frames 2\nscreenshot shown.png\ndump-state a0.json\n";
    for (int i = 1; i <= 4; ++i)
        script += "wait-file go" + std::to_string(i) + "\nwait-frames 4\ndump-state a" + std::to_string(i) + ".json\n";
    script += "select-mode face\nclear-selection\nwait-frames 2\n";
    for (int i = 5; i <= 9; ++i)
        script += "wait-file go" + std::to_string(i) + "\nwait-frames 4\n" + (i == 7 ? "screenshot hidden.png\n" : "") +
                  "dump-state a" + std::to_string(i) + ".json\n";
    script += "quit\n";
    start(editor, script);
    const json a0 = state(editor, "a0.json");
    ASSERT_TRUE(a0.is_object());
    const Screen screen{a0["window"]["x"].get<int>(), a0["window"]["y"].get<int>()};
    const auto edges = clickableEdges(a0, topology);
    ASSERT_GE(edges.size(), 2u) << "no edge to click";
    const auto [e1, p1] = edges[0];
    const std::vector<EdgeKey> loop1 = edgeLoop(cage, topology, e1);
    // A second edge off the first one's loop.
    size_t second = 1;
    while (second < edges.size() && std::binary_search(loop1.begin(), loop1.end(), edges[second].first)) ++second;
    ASSERT_LT(second, edges.size());
    const auto [e2, p2] = edges[second];
    const std::vector<EdgeKey> loop2 = edgeLoop(cage, topology, e2);
    ASSERT_EQ(loop1.size(), 16u) << "the chosen edge's loop should go around the cube";

    act("mousemove " + screen(p1) + " sleep 0.4 keydown alt sleep 0.2 click 1 sleep 0.2 keyup alt sleep 0.4", "go1");
    const json a1 = state(editor, "a1.json");
    EXPECT_EQ(edgesOf(a1["selection"]), loop1) << "Alt+click did not select the edge loop";
    EXPECT_EQ(a1["viewports"][0]["camera"], a0["viewports"][0]["camera"]) << "the Alt+click orbited";

    act("mousemove " + screen(p1) + " sleep 0.3 keydown ctrl keydown alt sleep 0.2 click 1 sleep 0.2 keyup alt keyup ctrl sleep 0.4",
        "go2");
    const json a2 = state(editor, "a2.json");
    EXPECT_EQ(edgesOf(a2["selection"]), edgeRing(cage, topology, e1)) << "Ctrl+Alt+click did not select the edge ring";

    act("mousemove " + screen(p2) + " sleep 0.4 click --repeat 2 --delay 90 1 sleep 0.5", "go3");
    const json a3 = state(editor, "a3.json");
    EXPECT_EQ(edgesOf(a3["selection"]), loop2) << "a double click did not select the edge loop";

    act("mousemove " + screen(p1) + " sleep 0.4 keydown shift keydown alt sleep 0.2 click 1 sleep 0.2 keyup alt keyup shift sleep 0.4",
        "go4");
    const json a4 = state(editor, "a4.json");
    std::vector<EdgeKey> both;
    std::set_union(loop1.begin(), loop1.end(), loop2.begin(), loop2.end(), std::back_inserter(both));
    EXPECT_EQ(edgesOf(a4["selection"]), both) << "Shift+Alt+click did not add the loop";

    act("mousemove " + screen(p1) + " sleep 0.4 keydown alt sleep 0.2 click 1 sleep 0.2 keyup alt sleep 0.4", "go5");
    const json a5 = state(editor, "a5.json");
    EXPECT_EQ(a5["selection"]["mode"], "face");
    EXPECT_EQ(facesOf(a5["selection"]["faces"]), faceLoop(cage, topology, e1)) << "Alt+click in face mode: not the face loop";

    // A select-tool drag that starts on the surface boxes; nothing moves.
    act("mousemove " + screen(p1 - glm::vec2(90, 70)) + " sleep 0.3 mousedown 1 sleep 0.3 mousemove " +
            screen(p1) + " sleep 0.3 mousemove " + screen(p1 + glm::vec2(90, 70)) + " sleep 0.4 mouseup 1 sleep 0.4",
        "go6");
    const json a6 = state(editor, "a6.json");
    EXPECT_EQ(a6["vertices"], a0["vertices"]) << "a select drag from the surface moved the cage";
    EXPECT_EQ(a6["history"]["size"], 0);
    const std::vector<uint32_t> boxed = facesOf(a6["selection"]["faces"]);
    EXPECT_GE(boxed.size(), 1u) << "the drag did not box-select";

    // H hides them: not selected any more, their sub-faces listed for the schemes, the cage
    // lines gone from the picture.
    act("mousemove " + screen(p1) + " sleep 0.3 key h sleep 0.5", "go7");
    const json a7 = state(editor, "a7.json");
    EXPECT_EQ(facesOf(a7["hidden_faces"]), boxed);
    EXPECT_TRUE(a7["selection"]["faces"].empty()) << "the selection kept hidden faces";
    EXPECT_EQ(a7["hidden_subfaces"].size(), boxed.size()) << "one sub-face per hidden quad";
    EXPECT_FALSE(a7["dirty"].get<bool>()) << "hiding is not an edit";
    EXPECT_GT(differingPixels(dir / "shown.png", dir / "hidden.png"), 50u) << "hidden faces' cage lines still drawn";

    // The same box again and a click where they were: nothing hidden gets selected.
    act("mousemove " + screen(p1 - glm::vec2(90, 70)) + " sleep 0.3 mousedown 1 sleep 0.3 mousemove " +
            screen(p1 + glm::vec2(90, 70)) + " sleep 0.4 mouseup 1 sleep 0.3 mousemove " + screen(p1) +
            " sleep 0.3 keydown shift click 1 keyup shift sleep 0.4",
        "go8");
    const json a8 = state(editor, "a8.json");
    for (uint32_t f : facesOf(a8["selection"]["faces"]))
        EXPECT_FALSE(std::binary_search(boxed.begin(), boxed.end(), f)) << "hidden face " << f << " was selected";

    act("key alt+h sleep 0.5", "go9");
    const json a9 = state(editor, "a9.json");
    EXPECT_TRUE(a9["hidden_faces"].empty()) << "Alt+H did not unhide";
    EXPECT_EQ(editor.wait(kRunSeconds), 0) << editor.output();
}

TEST_F(EditorHands, ExtrudesInteractivelyCreasesLiveAndSculptsInOneEntry) {
    const uint32_t a = cage.faceBegin(0)[0], b = cage.faceBegin(0)[1], c = cage.faceBegin(0)[2];
    const std::string ab = std::to_string(a) + "-" + std::to_string(b), bc = std::to_string(b) + "-" + std::to_string(c);
    std::string stroke = "mouse-move 290 380\nmouse-down left\nwait-frames 1\n";
    for (int x = 300; x <= 430; x += 10) stroke += "mouse-move " + std::to_string(x) + " 380\nwait-frames 1\n";
    EditorProcess editor;
    std::string script = "wait-idle\nwait-frames 3\nselect-mode face\nwait-frames 2\ndump-state b0.json\n";
    for (int i = 1; i <= 5; ++i)
        script += "wait-file go" + std::to_string(i) + "\nwait-frames 4\ndump-state b" + std::to_string(i) + ".json\n";
    script += "select-mode edge\nselect edge " + ab + "\n";
    for (int i = 1; i <= 4; ++i)  // the test scrolls the side panel until the slider shows
        script += "wait-file p" + std::to_string(i) + "\nwait-frames 3\ndump-state p" + std::to_string(i) + ".json\n";
    script += ""
              "wait-file go7\nwait-frames 4\nselect edge " + bc + "\nwait-frames 2\ndump-state b7.json\n"
              "wait-file go8\nwait-frames 4\ndump-state b8.json\n"
              "set-tool sculpt\nbrush raise 0.06 0.12 smooth\n" + stroke + "mouse-up left\nwait-frames 3\ndump-state b9.json\n"
              "undo\nwait-frames 2\ndump-state b10.json\nquit\nclick-button Discard changes\n";
    start(editor, script);
    const json b0 = state(editor, "b0.json");
    ASSERT_TRUE(b0.is_object());
    const Screen screen{b0["window"]["x"].get<int>(), b0["window"]["y"].get<int>()};
    const json& view = b0["viewports"][0];
    const glm::vec2 centre(view["rect"][0].get<float>() + view["rect"][2].get<float>() / 2,
                           view["rect"][1].get<float>() + view["rect"][3].get<float>() / 2);
    const size_t faces = b0["faces"].get<size_t>();

    // Click a face, Ctrl+E, the mouse drags the distance.
    act("mousemove " + screen(centre) + " sleep 0.4 click 1 sleep 0.4 key ctrl+e sleep 0.5 mousemove " +
            screen(centre + glm::vec2(20, -20)) + " sleep 0.3 mousemove " + screen(centre + glm::vec2(50, -50)) +
            " sleep 0.3 mousemove " + screen(centre + glm::vec2(70, -70)) + " sleep 0.5",
        "go1");
    const json b1 = state(editor, "b1.json");
    ASSERT_TRUE(b1["extrude"].is_object()) << "Ctrl+E did not start the interactive extrude";
    const float dragged = b1["extrude"]["distance"].get<float>();
    EXPECT_GT(std::fabs(dragged), 1e-3f) << "the mouse did not change the distance";
    EXPECT_EQ(b1["faces"].get<size_t>(), faces + 4);

    act("click 1 sleep 0.5", "go2");  // confirm
    const json b2 = state(editor, "b2.json");
    EXPECT_TRUE(b2["extrude"].is_null());
    EXPECT_EQ(b2["faces"].get<size_t>(), faces + 4);
    ASSERT_EQ(b2["history"]["size"], 1) << "the extrude is not one history entry";
    const std::string first = b2["history"]["entries"][0]["name"];
    EXPECT_EQ(first.rfind("extrude 1 face by ", 0), 0u) << first;
    EXPECT_NE(first, "extrude 1 face by 0");

    // Typed: 0.25, Enter.
    act("key ctrl+e sleep 0.4 key 0 period 2 5 sleep 0.3 key Return sleep 0.5", "go3");
    const json b3 = state(editor, "b3.json");
    ASSERT_EQ(b3["history"]["size"], 2);
    EXPECT_EQ(b3["history"]["entries"][1]["name"], "extrude 1 face by 0.25");
    EXPECT_EQ(b3["faces"].get<size_t>(), faces + 8);

    // Esc, then a right click: the cage as it was, no entry, nothing to redo.
    for (const char* name : {"b4.json", "b5.json"}) {
        if (name[1] == '4')
            act("key ctrl+e sleep 0.4 mousemove " + screen(centre + glm::vec2(-40, -60)) + " sleep 0.4 key Escape sleep 0.5", "go4");
        else
            act("key ctrl+e sleep 0.4 mousemove " + screen(centre + glm::vec2(30, 60)) + " sleep 0.4 click 3 sleep 0.5", "go5");
        const json s = state(editor, name);
        EXPECT_TRUE(s["extrude"].is_null()) << name;
        EXPECT_EQ(s["vertices"], b3["vertices"]) << name << ": a cancelled extrude changed the cage";
        EXPECT_EQ(s["face_vertices"], b3["face_vertices"]) << name;
        EXPECT_EQ(s["history"]["size"], 2) << name;
        EXPECT_EQ(s["history"]["position"], 2) << name;
    }

    // The edge sharpness slider dragged over several frames: the edge follows, one entry.
    const json before = state(editor, "b5.json");
    json rect = before["widgets"]["Edge sharpness"];
    ASSERT_TRUE(rect.is_array()) << "no edge sharpness slider";
    for (int i = 1; i <= 4; ++i) {  // one wheel notch at a time until it is well inside the window
        const float y = rect[1].get<float>();
        const bool inside = y > 40.0f && y + rect[3].get<float>() < 680.0f;
        act(inside ? std::string("sleep 0.1") : "mousemove " + screen({960, 400}) + " sleep 0.3 click 5 sleep 0.5",
            "p" + std::to_string(i));
        rect = state(editor, "p" + std::to_string(i) + ".json")["widgets"]["Edge sharpness"];
    }
    const float sx = rect[0].get<float>(), sy = rect[1].get<float>() + rect[3].get<float>() / 2;
    ASSERT_TRUE(sy > 40.0f && sy < 680.0f) << "the slider is not in the window: " << sy;
    act("mousemove " + screen({sx + 10, sy}) + " sleep 0.3 mousedown 1 sleep 0.3 mousemove " + screen({sx + 40, sy}) +
            " sleep 0.3 mousemove " + screen({sx + 70, sy}) + " sleep 0.3 mousemove " + screen({sx + 100, sy}) +
            " sleep 0.4 mouseup 1 sleep 0.4",
        "go7");
    const json b7 = state(editor, "b7.json");
    EXPECT_EQ(b7["history"]["size"].get<int>(), before["history"]["size"].get<int>() + 1) << "the drag made several entries";
    float sharpness = -1.0f;
    for (const json& crease : b7["creases"])
        if (makeEdgeKey(crease[0].get<uint32_t>(), crease[1].get<uint32_t>()) == makeEdgeKey(a, b)) sharpness = crease[2].get<float>();
    EXPECT_GT(sharpness, 3.0f) << "the edge did not follow the slider";
    EXPECT_LT(sharpness, 9.5f);

    // Shift+E creases the newly selected edge with the slider's value.
    act("mousemove " + screen(centre) + " sleep 0.3 key shift+e sleep 0.5", "go8");
    const json b8 = state(editor, "b8.json");
    EXPECT_EQ(b8["history"]["size"].get<int>(), b7["history"]["size"].get<int>() + 1);
    float second = -1.0f;
    for (const json& crease : b8["creases"])
        if (makeEdgeKey(crease[0].get<uint32_t>(), crease[1].get<uint32_t>()) == makeEdgeKey(b, c)) second = crease[2].get<float>();
    EXPECT_FLOAT_EQ(second, sharpness);

    // The first stroke on a cage without displacement: one entry; undoing it removes both.
    const json b9 = state(editor, "b9.json"), b10 = state(editor, "b10.json");
    EXPECT_EQ(b9["history"]["size"].get<int>(), b8["history"]["size"].get<int>() + 1);
    ASSERT_TRUE(b9["displacement"].is_object());
    const std::string stroke9 = b9["history"]["entries"].back()["name"];
    EXPECT_EQ(stroke9.rfind("Raise stroke (", 0), 0u) << stroke9;
    EXPECT_TRUE(b10["displacement"].is_null()) << "undoing the first stroke left a displacement";
    EXPECT_EQ(editor.wait(kRunSeconds), 0) << editor.output();
}
