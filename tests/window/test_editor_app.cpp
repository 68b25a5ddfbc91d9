// The real editor (`quadplan edit`) in a window on the test's X display (ctest runs this
// binary under xvfb-run), driven as a person would: the automation hook replays commands, and
// xdotool sends real mouse and keyboard events. Each test asserts on the state the editor dumps
// (vertices, creases, selection, frame counter, dirty flag, dialogs) and on its screenshots,
// with Vulkan validation on: any validation message makes the editor exit with status 4.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include <glm/geometric.hpp>

#include "editor_process.h"
#include "mesh/generated_cage.h"
#include "mesh/obj_io.h"
#include "render_test_support.h"
#include "scene/scene.h"

#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>

using namespace qp;
using namespace qp::test;
using nlohmann::json;

namespace {

constexpr double kRunSeconds = 240.0;  // lavapipe on 2 busy cores can be slow; CI has the same


#define REQUIRE_DISPLAY()                                                                                       \
    if (!haveDisplay())                                                                                         \
    GTEST_SKIP() << "SKIPPED: DISPLAY is unset; run under xvfb-run (ctest does when xvfb-run is installed)"

struct Picture {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb;
};

Picture loadPng(const fs::path& path) {
    Picture p;
    int channels = 0;
    if (uint8_t* data = stbi_load(path.c_str(), &p.width, &p.height, &channels, 3)) {
        p.rgb.assign(data, data + size_t(p.width) * p.height * 3);
        stbi_image_free(data);
    }
    return p;
}

// Distinct colours (quantised to 4 bits per channel) in a rectangle of the picture.
size_t distinctColors(const Picture& p, int x0, int y0, int x1, int y1) {
    std::set<uint32_t> colors;
    for (int y = std::max(y0, 0); y < std::min(y1, p.height); ++y)
        for (int x = std::max(x0, 0); x < std::min(x1, p.width); ++x) {
            const uint8_t* c = &p.rgb[(size_t(y) * p.width + x) * 3];
            colors.insert(uint32_t(c[0] >> 4) << 8 | uint32_t(c[1] >> 4) << 4 | uint32_t(c[2] >> 4));
        }
    return colors.size();
}

size_t differingPixels(const Picture& a, const Picture& b) {
    if (a.width != b.width || a.height != b.height) return SIZE_MAX;
    size_t n = 0;
    for (size_t i = 0; i < a.rgb.size(); i += 3)
        n += std::abs(a.rgb[i] - b.rgb[i]) + std::abs(a.rgb[i + 1] - b.rgb[i + 1]) + std::abs(a.rgb[i + 2] - b.rgb[i + 2]) > 24;
    return n;
}

glm::vec3 vertexOf(const json& state, uint32_t v) {
    const json& p = state["vertices"][v];
    return {p[0].get<float>(), p[1].get<float>(), p[2].get<float>()};
}

std::array<float, 4> widgetRect(const json& state, const std::string& label) {
    const json& r = state["widgets"][label];
    return {r[0].get<float>(), r[1].get<float>(), r[2].get<float>(), r[3].get<float>()};
}

class EditorWindow : public ::testing::Test {
protected:
    fs::path dir;

    void SetUp() override {
        REQUIRE_DISPLAY();
        dir = testOutputDir() / ("editor_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir);
        fs::create_directories(dir / "recovery");
        for (const char* name : {"default.json", "default.obj"})
            fs::copy_file(fs::path(QUADPLAN_SCENES_DIR) / name, dir / name);
    }

    std::map<std::string, std::string> environment() const {
        std::map<std::string, std::string> env = editorEnvironment(dir / "recovery");
        return env;
    }

    // Starts the editor on `file` (none: the bundled default scene, untitled) with `script`.
    void start(EditorProcess& editor, const std::string& script, const std::string& file,
               std::vector<std::string> extra = {}) {
        writeText(dir / "script.txt", script);
        std::vector<std::string> args{"edit"};
        if (!file.empty()) args.push_back(file);
        args.insert(args.end(), {"--automation", (dir / "script.txt").string(), "--validate", "--size", "1100x700"});
        args.insert(args.end(), extra.begin(), extra.end());
        editor.start(args, dir, environment(), dir / "editor.log");
    }

    // A 40k-face cage opened and vertex 10 moved, an autosave started (the automation's
    // `autosave`) and the state dumped in the next frame (a0.json), then `then`. Returns the cage.
    Cage startAutosaveOfALargeCage(EditorProcess& editor, const std::string& then) {
        const Cage big = makeBenchmarkCage(40000, 7);
        EXPECT_TRUE(saveObj(big, (dir / "big.obj").string()).ok());
        start(editor,
              "wait-idle\nselect-vertex 10\nmove-selection 0 0.02 0\nwait-frames 2\nautosave\ndump-state a0.json\n" + then,
              (dir / "big.obj").string(), {"--autosave-seconds", "3600"});
        return big;
    }

    json waitForState(EditorProcess& editor, const std::string& name) {
        EXPECT_TRUE(waitForFile(dir / name, editor, kRunSeconds)) << name << " never came; editor output:\n"
                                                                  << editor.output();
        return readJson(dir / name);
    }

    void expectCleanExit(EditorProcess& editor) {
        EXPECT_EQ(editor.status >= 0 ? editor.status : editor.wait(kRunSeconds), 0) << editor.output();
    }
};

// Automation edits a vertex and a crease; the frame is redrawn, the title marks the change,
// the picture changes, Save writes both files atomically and clears the marker.
TEST_F(EditorWindow, AutomationEditsSavesAndRedraws) {
    Result<Scene> scene = loadSceneOrCage((dir / "default.json").string());
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    const Cage& cage = scene->objects[0].cage;
    // A vertex on the top rim and an uncreased edge of the first face.
    uint32_t vertex = 0;
    for (uint32_t v = 0; v < cage.vertexCount(); ++v)
        if (cage.positions[v].y > cage.positions[vertex].y) vertex = v;
    uint32_t a = 0, b = 0;
    for (uint32_t f = 0; f < cage.faceCount() && a == b; ++f)
        if (cage.edgeSharpness(cage.faceBegin(f)[0], cage.faceBegin(f)[1]) == 0.0f)
            a = cage.faceBegin(f)[0], b = cage.faceBegin(f)[1];
    ASSERT_NE(a, b) << "no uncreased edge";

    EditorProcess editor;
    start(editor,
          "wait-idle\nwait-frames 3\ndump-state s0.json\nscreenshot before.png\n"
          "select-vertex " + std::to_string(vertex) + "\nmove-selection 0 0.4 0\n"
          "set-edge-sharpness " + std::to_string(a) + " " + std::to_string(b) + " 2.5\n"
          "wait-frames 2\nscreenshot after.png\ndump-state s1.json\n"
          "action file.save\nwait-frames 2\ndump-state s2.json\n"
          "resize 900 620\nset-viewports 2\nwait-frames 2\nscreenshot resized.png\nquit\n",
          (dir / "default.json").string());
    json s0 = waitForState(editor, "s0.json"), s1 = waitForState(editor, "s1.json"), s2 = waitForState(editor, "s2.json");
    expectCleanExit(editor);
    ASSERT_TRUE(s0.is_object() && s1.is_object() && s2.is_object());

    EXPECT_FALSE(s0["dirty"].get<bool>());
    EXPECT_EQ(s0["title"], "Quadplan - default.json");
    const glm::vec3 before = vertexOf(s0, vertex), after = vertexOf(s1, vertex);
    EXPECT_NEAR(after.y - before.y, 0.4f, 1e-5f);
    EXPECT_NEAR(after.x, before.x, 1e-6f);
    EXPECT_EQ(vertexOf(s1, (vertex + 1) % cage.vertexCount()), vertexOf(s0, (vertex + 1) % cage.vertexCount()));
    EXPECT_TRUE(s1["creases"].dump().find(json{std::min(a, b), std::max(a, b), 2.5}.dump()) != std::string::npos)
        << s1["creases"].dump();
    EXPECT_TRUE(s1["dirty"].get<bool>());
    EXPECT_EQ(s1["title"], "Quadplan - default.json*");
    EXPECT_NE(s1["last_edit"]["description"].get<std::string>().find("sharpness"), std::string::npos);
    EXPECT_GT(s1["last_edit"]["replanned_faces"].get<int>(), 0);
    EXPECT_GT(s1["frame"].get<int>(), s0["frame"].get<int>()) << "the edit was not redrawn";
    EXPECT_GT(s1["frame"].get<int>(), s1["last_edit"]["frame"].get<int>()) << "no frame after the edit";
    EXPECT_GT(s1["viewports"][0]["triangles"].get<int>(), 0);

    // Saved: not dirty, and the files hold the edits.
    EXPECT_FALSE(s2["dirty"].get<bool>());
    EXPECT_EQ(s2["title"], "Quadplan - default.json");
    Result<Scene> saved = loadSceneOrCage((dir / "default.json").string());
    ASSERT_TRUE(saved.ok()) << saved.error().message;
    EXPECT_NEAR(saved->objects[0].cage.positions[vertex].y, after.y, 1e-5f);
    EXPECT_FLOAT_EQ(saved->objects[0].cage.edgeSharpness(a, b), 2.5f);

    // Pictures: a real frame, not blank, and the edits visibly changed it.
    Picture p0 = loadPng(dir / "before.png"), p1 = loadPng(dir / "after.png");
    ASSERT_EQ(p0.width, 1100);
    ASSERT_EQ(p0.height, 700);
    const json rect = s0["viewports"][0]["rect"];
    const int x0 = rect[0].get<int>(), y0 = rect[1].get<int>();
    const int x1 = x0 + rect[2].get<int>(), y1 = y0 + rect[3].get<int>();
    EXPECT_GT(distinctColors(p0, x0, y0, x1, y1), 20u) << "the viewport looks blank";
    EXPECT_GT(distinctColors(p0, x1, 0, p0.width, p0.height), 5u) << "the side panel looks blank";
    EXPECT_GT(differingPixels(p0, p1), 500u) << "moving a vertex and creasing an edge changed nothing on screen";

    // After a resize (swapchain, ImGui framebuffers and the 3D cache recreated), two viewports.
    Picture resized = loadPng(dir / "resized.png");
    ASSERT_EQ(resized.width, 900);
    ASSERT_EQ(resized.height, 620);
    EXPECT_GT(distinctColors(resized, 0, 30, 270, 620), 20u);
    EXPECT_GT(distinctColors(resized, 290, 30, 560, 620), 20u);
}

// The sculpt tool: a drag over the surface is one stroke (one undo entry, which also made the
// displacement the scene did not have), drawn at once with only the changed samples uploaded; undo and redo
// redraw; Save writes the displacement; a right click during a stroke cancels it.
TEST_F(EditorWindow, SculptsStrokesUndoesCancelsAndSaves) {
    const int cx = 360, cy = 380;  // the front wall of the default scene in a 1100x700 window
    std::string stroke = "mouse-move " + std::to_string(cx - 70) + " " + std::to_string(cy) + "\nmouse-down left\nwait-frames 1\n";
    for (int x = cx - 60; x <= cx + 70; x += 10)
        stroke += "mouse-move " + std::to_string(x) + " " + std::to_string(cy) + "\nwait-frames 1\n";
    EditorProcess editor;
    start(editor,
          "wait-idle\nwait-frames 3\ndump-state k0.json\nscreenshot before.png\n"
          "set-tool sculpt\nbrush raise 0.06 0.12 smooth\n" + stroke +
          "mouse-up left\nwait-frames 3\nscreenshot sculpted.png\ndump-state k1.json\n"
          "undo\nwait-frames 3\nscreenshot undone.png\ndump-state k2.json\n"
          "redo\naction file.save\nwait-frames 2\n"
          "brush lower 0.06 0.12\n" + stroke +
          "mouse-down right\nwait-frames 1\nmouse-up right\nmouse-up left\nwait-frames 3\ndump-state k3.json\nquit\n",
          (dir / "default.json").string());
    json k0 = waitForState(editor, "k0.json"), k1 = waitForState(editor, "k1.json"), k2 = waitForState(editor, "k2.json"),
         k3 = waitForState(editor, "k3.json");
    expectCleanExit(editor);
    ASSERT_TRUE(k0.is_object() && k1.is_object() && k2.is_object() && k3.is_object());

    EXPECT_TRUE(k0["displacement"].is_null());
    EXPECT_EQ(k1["tool"]["tool"], "sculpt");
    ASSERT_TRUE(k1["displacement"].is_object()) << "the stroke made no displacement";
    const int samples = k1["displacement"]["samples"].get<int>(), nonzero = k1["displacement"]["nonzero"].get<int>();
    EXPECT_GT(nonzero, 50);
    EXPECT_LT(nonzero, samples / 4) << "a local stroke changed most of the surface";
    EXPECT_GT(k1["displacement"]["max_abs"].get<double>(), 0.0);
    ASSERT_EQ(k1["history"]["size"], 1);
    EXPECT_EQ(k1["history"]["entries"][0]["name"].get<std::string>().rfind("Raise stroke (", 0), 0u)
        << k1["history"]["entries"][0]["name"];
    EXPECT_EQ(k1["history"]["entries"][0]["replanned_faces"], 0);
    EXPECT_TRUE(k1["dirty"].get<bool>());
    const json& view = k1["viewports"][0];
    EXPECT_EQ(view["problem"], "");
    EXPECT_GT(view["updated_samples"].get<int>(), 0);
    EXPECT_LT(view["updated_samples"].get<int>(), samples) << "the renderer was sent every sample, not the stroke's";

    EXPECT_TRUE(k2["displacement"].is_null()) << "undoing the first stroke left a displacement";
    EXPECT_EQ(k3["history"]["size"], 1) << "a cancelled stroke made a history entry";
    EXPECT_EQ(k3["displacement"]["nonzero"], nonzero) << "a cancelled stroke left samples changed";
    EXPECT_EQ(k3["displacement"]["max_abs"], k1["displacement"]["max_abs"]);

    // Saved after the redo: the stroke's samples are in the file.
    Result<Scene> saved = loadSceneOrCage((dir / "default.json").string());
    ASSERT_TRUE(saved.ok()) << saved.error().message;
    ASSERT_FALSE(saved->objects[0].displacement.empty());
    EXPECT_EQ(int(saved->objects[0].displacement.samples.size()), samples);
    EXPECT_EQ(int(std::count_if(saved->objects[0].displacement.samples.begin(), saved->objects[0].displacement.samples.end(),
                                [](float x) { return x != 0.0f; })),
              nonzero);

    // Pictures: the stroke shows, and undo takes it away again.
    const Picture before = loadPng(dir / "before.png"), sculpted = loadPng(dir / "sculpted.png"), undone = loadPng(dir / "undone.png");
    EXPECT_GT(differingPixels(before, sculpted), 400u) << "the stroke did not show";
    EXPECT_GT(differingPixels(undone, sculpted), 400u) << "undo did not show";
}

// Real X events: with the move tool (W) a mouse drag on a cage vertex moves it, a numpad key changes the view, a click
// on an ImGui radio button switches to face selection, Ctrl+4 to four viewports.
TEST_F(EditorWindow, RealMouseAndKeyboardThroughX) {
    if (!haveProgram("xdotool")) GTEST_SKIP() << "SKIPPED: xdotool is not installed (scripts/install-deps.sh)";
    EditorProcess editor;
    start(editor,
          "wait-idle\nwait-frames 3\ndump-state r0.json\n"
          "wait-file go1\nwait-frames 4\ndump-state r1.json\n"
          "wait-file go2\nwait-frames 4\ndump-state r2.json\n"
          "wait-file go3\nwait-frames 4\nscreenshot r3.png\ndump-state r3.json\n"
          "quit\nclick-button Discard changes\n",
          (dir / "default.json").string());
    json r0 = waitForState(editor, "r0.json");
    ASSERT_TRUE(r0.is_object());
    const int wx = r0["window"]["x"].get<int>(), wy = r0["window"]["y"].get<int>();
    auto screen = [&](float x, float y) { return std::to_string(wx + int(x)) + " " + std::to_string(wy + int(y)); };

    // 1. Drag a vertex whose projection is well inside the viewport and away from the others.
    const json& view = r0["viewports"][0];
    const float vx = view["rect"][0], vy = view["rect"][1], vw = view["rect"][2], vh = view["rect"][3];
    const json& projected = view["projected_vertices"];
    const json& pickable = view["pickable_vertices"];  // not hidden by the limit surface
    ASSERT_EQ(pickable.size(), projected.size());
    int chosen = -1;
    for (size_t i = 0; i < projected.size() && chosen < 0; ++i) {
        if (projected[i].is_null() || !pickable[i].get<bool>()) continue;
        const float x = projected[i][0], y = projected[i][1];
        if (x < vx + 60 || x > vx + vw - 60 || y < vy + 80 || y > vy + vh - 60) continue;
        bool isolated = true;
        for (size_t j = 0; j < projected.size() && isolated; ++j)
            if (j != i && !projected[j].is_null())
                isolated = std::hypot(projected[j][0].get<float>() - x, projected[j][1].get<float>() - y) > 30.0f;
        if (isolated) chosen = int(i);
    }
    ASSERT_GE(chosen, 0) << "no isolated vertex to grab";
    const float gx = projected[chosen][0], gy = projected[chosen][1];
    // The select tool only boxes: moving needs the move tool (W).
    EXPECT_EQ(xdotool("mousemove " + screen(gx, gy) + " sleep 0.5 key w sleep 0.5 mousedown 1 sleep 0.8 mousemove " +
                      screen(gx + 25, gy + 40) + " sleep 0.8 mousemove " + screen(gx + 40, gy + 60) +
                      " sleep 0.8 mouseup 1 sleep 0.5"),
              0);
    writeText(dir / "go1", "");
    json r1 = waitForState(editor, "r1.json");
    ASSERT_TRUE(r1.is_object());
    EXPECT_EQ(r1["selection"]["vertices"], json::array({chosen})) << "the click did not select the vertex under it";
    const glm::vec3 moved = vertexOf(r1, chosen) - vertexOf(r0, chosen);
    EXPECT_GT(glm::length(moved), 1e-3f) << "the drag did not move the vertex";
    EXPECT_TRUE(r1["dirty"].get<bool>());
    EXPECT_EQ(r1["last_edit"]["description"], "move vertex " + std::to_string(chosen));
    // Dragged down on screen: the vertex went down in the world.
    EXPECT_LT(moved.y, 0.0f);

    // 2. Numpad 7 over the viewport: top view (the eye straight above the target).
    EXPECT_EQ(xdotool("mousemove " + screen(vx + vw / 2, vy + vh / 2) + " sleep 0.3 key KP_7 sleep 0.5"), 0);
    writeText(dir / "go2", "");
    json r2 = waitForState(editor, "r2.json");
    ASSERT_TRUE(r2.is_object());
    const json& camera = r2["viewports"][0]["camera"];
    const glm::vec3 eye(camera["eye"][0], camera["eye"][1], camera["eye"][2]);
    const glm::vec3 target(camera["target"][0], camera["target"][1], camera["target"][2]);
    EXPECT_GT(glm::normalize(eye - target).y, 0.999f) << "Numpad 7 did not give the top view";

    // 3. Click the "Face" radio button in the side panel, then Ctrl+4 over the viewport.
    const std::array<float, 4> face = widgetRect(r2, "Face");
    EXPECT_EQ(xdotool("mousemove " + screen(face[0] + face[2] / 2, face[1] + face[3] / 2) + " sleep 0.3 click 1 sleep 0.5"),
              0);
    EXPECT_EQ(xdotool("mousemove " + screen(vx + vw / 2, vy + vh / 2) + " sleep 0.3 key ctrl+4 sleep 0.5"), 0);
    writeText(dir / "go3", "");
    json r3 = waitForState(editor, "r3.json");
    expectCleanExit(editor);
    ASSERT_TRUE(r3.is_object());
    EXPECT_EQ(r3["selection"]["mode"], "face") << "the click on the radio button did not reach ImGui";
    EXPECT_EQ(r3["viewports"].size(), 4u) << "Ctrl+4 did not give four viewports";
    Picture p = loadPng(dir / "r3.png");
    for (const json& v : r3["viewports"]) {
        const int x = v["rect"][0], y = v["rect"][1], w = v["rect"][2], h = v["rect"][3];
        EXPECT_GT(distinctColors(p, x, y, x + w, y + h), 20u) << "a viewport is blank";
    }
}

// Issue 6 items 3-7 as a person uses them: box select in face mode, extrude, crease and corner
// tools, undo/redo and a jump in the history, the move handle dragged with real X events, and two
// viewports with different schemes beside each other, one with its error heat map.
TEST_F(EditorWindow, SelectsEditsCreasesUndoesAndComparesSchemes) {
    Result<Scene> scene = loadSceneOrCage((dir / "default.json").string());
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    const Cage& cage = scene->objects[0].cage;
    const uint32_t faces = cage.faceCount();
    ASSERT_EQ(cage.faceSize(0), 4u);
    const uint32_t a = cage.faceBegin(0)[0], b = cage.faceBegin(0)[1];
    const bool gestures = haveProgram("xdotool");
    EditorProcess editor;
    start(editor,
          "wait-idle\nwait-frames 2\ndump-state t0.json\n"
          // Box select over the whole viewport in face mode: the faces the surface shows.
          "select-mode face\nbox-select 0 5 45 715 695\ndump-state t1.json\n"
          // Extrude one face, undo, redo.
          "select face 0\nextrude 0.2\nwait-frames 1\ndump-state t2.json\nundo\ndump-state t3.json\nredo\n"
          "wait-frames 1\nscreenshot extruded.png\ndump-state t4.json\n"
          // Crease an edge and corner a vertex through the selection tools.
          "select edge " + std::to_string(a) + "-" + std::to_string(b) + "\ncrease 3.5\n"
          "select vertex " + std::to_string(a) + "\ncorner 2\nwait-frames 1\ndump-state t5.json\n"
          // Back to the document as opened, in one jump.
          "jump-history 0\nwait-frames 1\ndump-state t6.json\n"
          // The move handle on one vertex, dragged along x by the test (xdotool).
          "select vertex " + std::to_string(a) + "\nset-tool move\nwait-frames 2\ndump-state g0.json\n" +
              (gestures ? "wait-file go\nwait-frames 4\ndump-state g1.json\n" : "") +
              "set-tool select\n"
              // Two viewports, plans beside uniform with its error heat map.
              "set-viewports 2\nset-scheme 1 uniform\nheatmap 1 on\nwait-frames 30\nscreenshot compare.png\n"
              "dump-state h.json\nquit\nclick-button Discard changes\n",
          (dir / "default.json").string());
    json t0 = waitForState(editor, "t0.json"), t1 = waitForState(editor, "t1.json");
    json t2 = waitForState(editor, "t2.json"), t3 = waitForState(editor, "t3.json"), t4 = waitForState(editor, "t4.json");
    json t5 = waitForState(editor, "t5.json"), t6 = waitForState(editor, "t6.json"), g0 = waitForState(editor, "g0.json");
    ASSERT_TRUE(t0.is_object() && t6.is_object() && g0.is_object());

    // Box select: some faces but not the hidden ones behind the surface.
    const size_t boxed = t1["selection"]["faces"].size();
    EXPECT_GT(boxed, 10u);
    EXPECT_LT(boxed, faces) << "box select took faces the surface hides";

    // Extrude adds the face's four sides; undo removes them; redo brings them back.
    EXPECT_EQ(t2["faces"].get<uint32_t>(), faces + 4);
    EXPECT_TRUE(t2["last_edit"]["topology_changed"].get<bool>());
    EXPECT_GT(t2["last_edit"]["replanned_faces"].get<uint32_t>(), 0u);
    EXPECT_LT(t2["last_edit"]["replanned_faces"].get<uint32_t>(), faces) << "an extrude re-planned everything";
    EXPECT_EQ(t3["faces"].get<uint32_t>(), faces);
    EXPECT_EQ(t3["vertices"], t0["vertices"]) << "undo did not restore the cage";
    EXPECT_EQ(t4["faces"].get<uint32_t>(), faces + 4);
    EXPECT_EQ(t4["vertices"], t2["vertices"]);

    // Crease and corner, as the history says.
    EXPECT_NE(t5["creases"].dump().find(json{std::min(a, b), std::max(a, b), 3.5}.dump()), std::string::npos)
        << t5["creases"].dump();
    EXPECT_NE(t5["corners"].dump().find(json{a, 2.0}.dump()), std::string::npos) << t5["corners"].dump();
    EXPECT_EQ(t5["history"]["size"].get<int>(), 3);
    EXPECT_EQ(t5["history"]["position"].get<int>(), 3);

    // The jump undid all three: the cage and tags as opened, the entries still there to redo.
    EXPECT_EQ(t6["faces"].get<uint32_t>(), faces);
    EXPECT_EQ(t6["vertices"], t0["vertices"]);
    EXPECT_EQ(t6["creases"], t0["creases"]);
    EXPECT_EQ(t6["corners"], t0["corners"]);
    EXPECT_EQ(t6["history"]["position"].get<int>(), 0);
    EXPECT_EQ(t6["history"]["size"].get<int>(), 3);
    EXPECT_FALSE(t6["dirty"].get<bool>()) << "back at the saved state, the document is clean";

    // The move handle: grab the x arrow half way and drag 60 px along it on screen.
    ASSERT_TRUE(g0["viewports"][0].contains("gizmo")) << "no move handle for a selected vertex";
    if (gestures) {
        const int wx = g0["window"]["x"].get<int>(), wy = g0["window"]["y"].get<int>();
        auto screen = [&](glm::vec2 p) { return std::to_string(wx + int(p.x)) + " " + std::to_string(wy + int(p.y)); };
        const json& gizmo = g0["viewports"][0]["gizmo"];
        const glm::vec2 centre(gizmo["centre"][0].get<float>(), gizmo["centre"][1].get<float>());
        const glm::vec2 xEnd(gizmo["x"][0].get<float>(), gizmo["x"][1].get<float>());
        const glm::vec2 grab = 0.5f * (centre + xEnd), along = glm::normalize(xEnd - centre);
        EXPECT_EQ(xdotool("mousemove " + screen(grab) + " sleep 0.8 mousedown 1 sleep 0.8 mousemove " +
                          screen(grab + 30.0f * along) + " sleep 0.8 mousemove " + screen(grab + 60.0f * along) +
                          " sleep 0.8 mouseup 1 sleep 0.5"),
                  0);
        writeText(dir / "go", "");
        json g1 = waitForState(editor, "g1.json");
        ASSERT_TRUE(g1.is_object());
        const glm::vec3 moved = vertexOf(g1, a) - vertexOf(g0, a);
        EXPECT_GT(moved.x, 1e-3f) << "dragging the x arrow did not move the vertex along +x";
        EXPECT_NEAR(moved.y, 0.0f, 1e-5f);
        EXPECT_NEAR(moved.z, 0.0f, 1e-5f);
        EXPECT_EQ(g1["last_edit"]["replanned_faces"], 0) << "a move re-planned faces";
    }

    // Side by side: plans (exact, no heat map) and uniform with its error coloured.
    json h = waitForState(editor, "h.json");
    expectCleanExit(editor);
    ASSERT_EQ(h["viewports"].size(), 2u);
    EXPECT_EQ(h["viewports"][0]["scheme"], "plans");
    EXPECT_EQ(h["viewports"][1]["scheme"], "uniform");
    EXPECT_TRUE(h["viewports"][1]["drawn"].get<bool>()) << h["viewports"][1]["problem"];
    const json& heat = h["viewports"][1]["heatmap"];
    EXPECT_TRUE(heat["on"].get<bool>());
    EXPECT_TRUE(heat["valid"].get<bool>());
    EXPECT_GT(heat["max"].get<double>(), 0.0) << "uniform subdivision is not the limit surface";
    Picture p = loadPng(dir / "compare.png");
    for (const json& v : h["viewports"]) {
        const int x = v["rect"][0], y = v["rect"][1], w = v["rect"][2], hh = v["rect"][3];
        EXPECT_GT(distinctColors(p, x, y, x + w, y + hh), 20u) << "a viewport is blank";
    }
}

// Quitting with unsaved changes asks first; Cancel keeps editing; Save on an untitled document
// asks for a name (Save As) and then quits.
TEST_F(EditorWindow, ConfirmsBeforeLosingChanges) {
    EditorProcess editor;
    start(editor,
          "wait-idle\nselect-vertex 0\nmove-selection 0.1 0 0\nwait-frames 1\naction file.quit\nwait-frames 2\n"
          "dump-state q0.json\nclick-button Cancel\nwait-frames 2\ndump-state q1.json\n"
          "action file.quit\nwait-frames 2\nclick-button Save\nwait-frames 2\ndump-state q2.json\n"
          "click-button Save\n",
          "");
    json q0 = waitForState(editor, "q0.json"), q1 = waitForState(editor, "q1.json"), q2 = waitForState(editor, "q2.json");
    expectCleanExit(editor);
    EXPECT_EQ(q0["open_popups"], json::array({"Unsaved changes"}));
    EXPECT_EQ(q0["title"], "Quadplan - untitled*");
    EXPECT_EQ(q1["open_popups"], json::array());
    EXPECT_TRUE(q1["dirty"].get<bool>());
    EXPECT_EQ(q2["open_popups"], json::array({"Save As"}));
    // Saved where the Save As dialog proposed (the working directory), then quit.
    Result<Scene> saved = loadSceneOrCage((dir / "untitled.json").string());
    ASSERT_TRUE(saved.ok()) << saved.error().message;
    EXPECT_NEAR(saved->objects[0].cage.positions[0].x, vertexOf(q1, 0).x, 1e-5f);
    EXPECT_FALSE(fs::exists(dir / "recovery" / "autosave.json"));
}

// Unsaved work is autosaved; after the editor is killed, the next start offers it back and
// Restore brings back the edit, still marked unsaved.
TEST_F(EditorWindow, OffersAutosavedWorkAfterACrash) {
    EditorProcess crashed;
    start(crashed, "wait-idle\nselect-vertex 3\nmove-selection 0 0 0.5\nwait-frames 2\ndump-state c0.json\nwait-file never 600\n",
          (dir / "default.json").string(), {"--autosave-seconds", "1"});
    json c0 = waitForState(crashed, "c0.json");
    ASSERT_TRUE(waitForFile(dir / "recovery" / "autosave-info.json", crashed, 60.0)) << crashed.output();
    crashed.kill();  // no chance to clean up: like a crash

    EditorProcess restarted;
    start(restarted,
          "wait-frames 5\ndump-state b0.json\nclick-button Restore\nwait-idle\nwait-frames 2\ndump-state b1.json\n"
          "quit\nclick-button Discard changes\n",
          (dir / "default.json").string());
    json b0 = waitForState(restarted, "b0.json"), b1 = waitForState(restarted, "b1.json");
    expectCleanExit(restarted);
    EXPECT_TRUE(b0["recovery"]["offered"].get<bool>());
    EXPECT_EQ(b0["open_popups"], json::array({"Restore unsaved work?"}));
    EXPECT_NEAR(vertexOf(b1, 3).z, vertexOf(c0, 3).z, 1e-5f);
    EXPECT_TRUE(b1["dirty"].get<bool>());
    EXPECT_EQ(b1["path"], (dir / "default.json").string());
    // Discarding on quit removes the recovery files.
    EXPECT_FALSE(fs::exists(dir / "recovery" / "autosave.json"));
}

// The autosave is written off the UI thread: the frame after the one that starts it runs while
// the large cage is still being written, and the files come out whole.
TEST_F(EditorWindow, AutosavesALargeCageWithoutFreezing) {
    EditorProcess editor;
    const Cage big = startAutosaveOfALargeCage(editor, "wait-file never 600\n");
    const json a0 = waitForState(editor, "a0.json");
    EXPECT_TRUE(a0["dirty"].get<bool>());
    EXPECT_TRUE(a0["recovery"]["writing"].get<bool>()) << "the frame after the autosave started waited for its write";
    ASSERT_TRUE(waitForFile(dir / "recovery" / "autosave-info.json", editor, 60.0)) << editor.output();
    editor.kill();
    Result<Scene> written = loadScene((dir / "recovery" / "autosave.json").string());
    ASSERT_TRUE(written.ok()) << written.error().message;
    ASSERT_EQ(written->objects.size(), 1u);
    EXPECT_EQ(written->objects[0].cage.faceCount(), big.faceCount());
    EXPECT_NEAR(written->objects[0].cage.positions[10].y, vertexOf(a0, 10).y, 1e-5f) << "the edit is in the autosave";
}

// Discarding the changes (quit, Discard changes) while an autosave is still being written waits
// for it before removing the recovery files: none are left to be offered at the next start.
TEST_F(EditorWindow, DiscardingDuringAnAutosaveLeavesNoRecovery) {
    EditorProcess editor;
    startAutosaveOfALargeCage(editor, "quit\nclick-button Discard changes\n");
    const json a0 = waitForState(editor, "a0.json");
    expectCleanExit(editor);
    EXPECT_TRUE(a0["recovery"]["writing"].get<bool>()) << "the autosave was no longer being written";
    EXPECT_FALSE(fs::exists(dir / "recovery" / "autosave.json"));
    EXPECT_FALSE(fs::exists(dir / "recovery" / "autosave-info.json"));
}

// Opening a large cage plans it off the UI thread: frames keep coming (with a progress bar)
// until the new document takes over.
TEST_F(EditorWindow, LoadsALargeCageWithoutFreezing) {
    const Cage big = makeBenchmarkCage(40000, 3);
    ASSERT_TRUE(saveObj(big, (dir / "big.obj").string()).ok());
    EditorProcess editor;
    start(editor,
          "wait-idle\nwait-frames 2\ndump-state l0.json\nopen big.obj\nwait-frames 3\nscreenshot loading.png\n"
          "dump-state l1.json\nwait-idle\nwait-frames 2\ndump-state l2.json\nquit\n",
          (dir / "default.json").string());
    json l0 = waitForState(editor, "l0.json"), l1 = waitForState(editor, "l1.json"), l2 = waitForState(editor, "l2.json");
    expectCleanExit(editor);
    EXPECT_EQ(l0["faces"], 180);
    EXPECT_TRUE(l1["loading"].get<bool>()) << "the load finished within 3 frames; use a bigger cage";
    const std::string stage = l1["loading_stage"].get<std::string>();  // how far it got depends on the machine
    EXPECT_TRUE(stage.find("Reading") != std::string::npos || stage.find("Planning") != std::string::npos) << stage;
    EXPECT_EQ(l1["faces"], 180) << "the old document stays until the new one is ready";
    EXPECT_EQ(l1["title"], "Quadplan - default.json (loading)");
    EXPECT_FALSE(l2["loading"].get<bool>());
    EXPECT_EQ(l2["faces"].get<uint32_t>(), big.faceCount());
    EXPECT_EQ(l2["path"], "big.obj");
    EXPECT_GT(l2["frame"].get<int>(), l1["frame"].get<int>() + 2) << "no frames were drawn while planning";
}

// Issue 21 part 4 on a large generated cage: frames keep coming while it loads, while the camera
// orbits (coarse frames, `--coarse-above 0` making every orbit coarse whatever this machine's
// speed, then one full frame when it stops and nothing drawn after it) and across an edit.
// Counts frames and what they drew; asserts no timing.
TEST_F(EditorWindow, ALargeCageLoadsOrbitsAndEditsWithFramesComing) {
    const Cage big = makeBenchmarkCage(40000, 5);
    ASSERT_TRUE(saveObj(big, (dir / "big.obj").string()).ok());
    EditorProcess editor;
    start(editor,
          "wait-frames 2\ndump-state s0.json\nwait-idle\nwait-frames 3\nmeasure-frames 12 orbit.json orbit\n"
          "dump-state s1.json\nwait-seconds 0.6\nwait-frames 3\nscreenshot full.png\ndump-state s2.json\n"
          "measure-frames 6 idle.json\nselect-vertex 100\nmove-selection 0 0.02 0\nwait-frames 2\ndump-state s3.json\n"
          "quit\nclick-button Discard changes\n",
          (dir / "big.obj").string(), {"--no-vsync", "--coarse-above", "0"});
    json s0 = waitForState(editor, "s0.json"), s1 = waitForState(editor, "s1.json"), s2 = waitForState(editor, "s2.json"),
         s3 = waitForState(editor, "s3.json");
    expectCleanExit(editor);
    EXPECT_TRUE(s0["loading"].get<bool>()) << "the load finished within 2 frames; use a bigger cage";
    EXPECT_EQ(s2["faces"].get<uint32_t>(), big.faceCount());

    const json orbit = readJson(dir / "orbit.json"), idle = readJson(dir / "idle.json");
    ASSERT_TRUE(orbit.is_object() && idle.is_object());
    const int coarse = orbit["scene_drawn_coarse"]["cpu_ms"]["count"].get<int>();
    const int full = orbit["scene_drawn_full"]["cpu_ms"]["count"].get<int>();
    std::printf("[ measure  ] orbit over %u faces: %d coarse and %d full frames of %d; median interval %.1f ms\n",
                big.faceCount(), coarse, full, orbit["frames"].get<int>(), orbit["all_frames"]["interval_ms"]["median"].get<double>());
    EXPECT_GE(coarse + full, 12) << "an orbit frame was not drawn";
    EXPECT_GE(coarse, 10) << "the camera moved but frames were full";
    EXPECT_TRUE(s1["coarse_frame"].get<bool>());
    EXPECT_FALSE(s2["coarse_frame"].get<bool>()) << "no full-quality frame after the camera stopped";
    EXPECT_EQ(idle["scene_drawn"]["cpu_ms"]["count"], 0) << "the 3D was drawn again with nothing changed";
    EXPECT_GT(distinctColors(loadPng(dir / "full.png"), 0, 40, 700, 650), 20u);

    EXPECT_EQ(s3["last_edit"]["description"], "move vertex 100");
    EXPECT_GT(s3["frame"].get<int>(), s2["frame"].get<int>() + 6) << "frames stopped across the edit";
}

// Issue 6 item 11 on a ~2,000-face cage at the default tessellation: every frame of a drag
// (an edit per frame) draws the edited surface, frames without changes only copy the cached 3D.
// Prints the frame times (medians; docs/editor.md has the measurement); asserts no timing.
TEST_F(EditorWindow, EditsShowInTheNextFrameOnA2000FaceCage) {
    const Cage cage = makeBenchmarkCage(2000, 1);
    ASSERT_TRUE(saveObj(cage, (testOutputDir() / "generated_2000.obj").string()).ok());
    EditorProcess editor;
    start(editor,
          "wait-idle\nwait-frames 3\nmeasure-frames 20 idle.json\nmeasure-frames 20 orbit.json orbit\n"
          "select-vertex 10\nmeasure-frames 20 drag.json drag\nscreenshot drag.png\ndump-state d.json\n"
          "quit\nclick-button Discard changes\n",
          (testOutputDir() / "generated_2000.obj").string(), {"--no-vsync"});
    json d = waitForState(editor, "d.json");
    expectCleanExit(editor);
    for (const char* mode : {"idle", "orbit", "drag"}) {
        json m = readJson(dir / (std::string(mode) + ".json"));
        ASSERT_TRUE(m.is_object()) << mode;
        const json& drawn = m["scene_drawn"];
        std::printf("[ measure  ] %-5s %u faces, plans path %s, factor %s: 3D drawn in %d of %d frames; median CPU %.1f ms, "
                    "GPU %.1f ms, interval %.1f ms\n",
                    mode, m["faces"].get<unsigned>(), m["plans_path"].get<std::string>().c_str(), m["factors"].dump().c_str(),
                    drawn["cpu_ms"]["count"].get<int>(), m["frames"].get<int>(),
                    m["all_frames"]["cpu_ms"]["median"].get<double>(), m["all_frames"]["gpu_ms"]["median"].get<double>(),
                    m["all_frames"]["interval_ms"]["median"].get<double>());
        if (std::string(mode) == "idle") EXPECT_EQ(drawn["cpu_ms"]["count"], 0) << "an unchanged scene was drawn again";
        else EXPECT_GE(drawn["cpu_ms"]["count"].get<int>(), 20) << mode << ": a changed frame was not drawn";
    }
    EXPECT_EQ(d["last_edit"]["description"], "move vertex 10");
    EXPECT_EQ(d["last_edit"]["replanned_faces"], 0);
    EXPECT_GT(distinctColors(loadPng(dir / "drag.png"), 0, 40, 700, 650), 20u);
}

// A file that cannot be read gives an error dialog and an empty editor, not a crash; saving
// then has nothing to save.
TEST_F(EditorWindow, ReportsABrokenFile) {
    EditorProcess editor;
    start(editor,
          "wait-idle\nwait-frames 2\ndump-state e0.json\naction file.save\nclick-button OK\nwait-frames 2\n"
          "dump-state e1.json\nquit\n",
          std::string(QUADPLAN_TEST_DATA) + "/broken/garbage.obj");
    json e0 = waitForState(editor, "e0.json"), e1 = waitForState(editor, "e1.json");
    expectCleanExit(editor);
    EXPECT_EQ(e0["open_popups"], json::array({"Error"}));
    EXPECT_NE(e0["status"].get<std::string>().find("this is not an OBJ file"), std::string::npos) << e0["status"];
    EXPECT_FALSE(e0.contains("faces"));
    EXPECT_EQ(e1["open_popups"], json::array());
    EXPECT_NE(e1["status"].get<std::string>().find("Nothing to save"), std::string::npos) << e1["status"];
}

// Bad automation is refused up front with the line at fault.
TEST_F(EditorWindow, RejectsABadAutomationScript) {
    EditorProcess editor;
    start(editor, "wait-frames 2\nselect-vertex banana\n", (dir / "default.json").string());
    EXPECT_EQ(editor.wait(60.0), 2);
    EXPECT_NE(editor.output().find("script.txt:2"), std::string::npos) << editor.output();
    // Colour modes belong to each scheme: an unknown one stops the run when it is reached.
    EditorProcess running;
    start(running, "wait-idle\nwait-frames 2\nset-color-by 0 rainbow\nquit\n", (dir / "default.json").string());
    EXPECT_EQ(running.wait(kRunSeconds), 3);
    EXPECT_NE(running.output().find("no colour mode 'rainbow'"), std::string::npos) << running.output();
}

// Without a display the editor says so and exits non-zero, without touching GLFW.
TEST(EditorNoDisplay, ExitsWithAClearMessage) {
    const fs::path dir = testOutputDir();
    EditorProcess editor;
    editor.start({"edit", (fs::path(QUADPLAN_SCENES_DIR) / "default.json").string()}, dir,
                 {{"DISPLAY", ""}, {"WAYLAND_DISPLAY", ""}}, dir / "editor_no_display.log");
    EXPECT_EQ(editor.wait(60.0), 1);
    EXPECT_NE(editor.output().find("there is no display"), std::string::npos) << editor.output();
}

}  // namespace
