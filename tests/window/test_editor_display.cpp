// The editor's display and keyboard behaviour (issue 15), driven as a person would: real X
// key presses and clicks from xdotool, and the automation hook for the rest, with Vulkan
// validation on. Each test is one editor launch that checks several things in turn:
//   EditorDisplay.KeyboardPopupsDialogsAndLayouts: a Z-up cage is recognised (up axis, camera,
//     Numpad 7 looks down z), Esc closes a drop-down and shortcuts work again, Save As proposes
//     NAME.json beside the cage, has the keyboard, Esc cancels and Enter saves, Ctrl+2 frames.
//   EditorDisplay.ShadingGridCreasesAndPanels: at 1280x800 every side-panel tab fits on screen,
//     matcap differs from studio, the heat map keeps the form shaded, the grid draws, creases
//     are wide, and shading survives save and reopen.
//   EditorDisplay.CullingKeepsThePictureAndCounts (issue 20): a viewport's culling combo culls
//     patches facing away on a closed torus without changing a pixel, and Stats counts them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

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

constexpr double kRunSeconds = 240.0;  // lavapipe on 2 busy cores can be slow


struct Image {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb;
    const uint8_t* at(int x, int y) const { return &rgb[(size_t(y) * width + x) * 3]; }
};

Image loadImage(const fs::path& path) {
    Image p;
    int channels = 0;
    if (uint8_t* data = stbi_load(path.c_str(), &p.width, &p.height, &channels, 3)) {
        p.rgb.assign(data, data + size_t(p.width) * p.height * 3);
        stbi_image_free(data);
    }
    return p;
}

// Pixels of a rectangle that differ clearly between two pictures.
size_t differing(const Image& a, const Image& b, int x0, int y0, int x1, int y1) {
    if (a.width != b.width || a.height != b.height) return SIZE_MAX;
    size_t n = 0;
    for (int y = std::max(y0, 0); y < std::min(y1, a.height); ++y)
        for (int x = std::max(x0, 0); x < std::min(x1, a.width); ++x) {
            const uint8_t *p = a.at(x, y), *q = b.at(x, y);
            n += std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]) > 24;
        }
    return n;
}

// Distinct brightness levels (8 per channel step) among the strongly coloured pixels of a
// rectangle: a flat heat map has a handful per hue, a shaded one many.
size_t shadedColorLevels(const Image& p, int x0, int y0, int x1, int y1) {
    std::set<uint32_t> levels;
    for (int y = std::max(y0, 0); y < std::min(y1, p.height); ++y)
        for (int x = std::max(x0, 0); x < std::min(x1, p.width); ++x) {
            const uint8_t* c = p.at(x, y);
            const int hi = std::max({c[0], c[1], c[2]}), lo = std::min({c[0], c[1], c[2]});
            if (hi - lo > 60) levels.insert(uint32_t(c[0] >> 3) << 10 | uint32_t(c[1] >> 3) << 5 | uint32_t(c[2] >> 3));
        }
    return levels.size();
}

std::array<float, 4> rectOf(const json& j) { return {j[0].get<float>(), j[1].get<float>(), j[2].get<float>(), j[3].get<float>()}; }

glm::vec3 vec3Of(const json& j) { return {j[0].get<float>(), j[1].get<float>(), j[2].get<float>()}; }

// Whether every cage vertex of viewport `v` projects inside its rectangle.
bool modelInside(const json& v) {
    const std::array<float, 4> r = rectOf(v["rect"]);
    for (const json& p : v["projected_vertices"]) {
        if (p.is_null()) return false;
        const float x = p[0], y = p[1];
        if (x < r[0] || y < r[1] || x > r[0] + r[2] || y > r[1] + r[3]) return false;
    }
    return !v["projected_vertices"].empty();
}

// A 2 x 1.2 x 3 box standing on the z = 0 plane (modelled Z up), one edge infinitely sharp.
constexpr const char* kTowerObj =
    "v -1 -0.6 0\nv 1 -0.6 0\nv 1 0.6 0\nv -1 0.6 0\nv -1 -0.6 3\nv 1 -0.6 3\nv 1 0.6 3\nv -1 0.6 3\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n"
    "t crease 2/1/0 4 5 10\n";

class EditorDisplay : public ::testing::Test {
protected:
    fs::path dir;

    void SetUp() override {
        if (!haveDisplay()) GTEST_SKIP() << "SKIPPED: DISPLAY is unset; run under xvfb-run";
        dir = testOutputDir() / ("display_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir);
        fs::create_directories(dir / "recovery");
        for (const char* name : {"default.json", "default.obj"})
            fs::copy_file(fs::path(QUADPLAN_SCENES_DIR) / name, dir / name);
        writeText(dir / "tower.obj", kTowerObj);
    }

    void start(EditorProcess& editor, const std::string& script, const std::string& file, const std::string& size) {
        writeText(dir / "script.txt", script);
        std::map<std::string, std::string> env = editorEnvironment(dir / "recovery");
        editor.start({"edit", file, "--automation", (dir / "script.txt").string(), "--validate", "--size", size}, dir, env,
                     dir / "editor.log");
    }

    json state(EditorProcess& editor, const std::string& name) {
        EXPECT_TRUE(waitForFile(dir / name, editor, kRunSeconds)) << name << " never came; editor output:\n" << editor.output();
        return readJson(dir / name);
    }

    // Real X input, then lets the script take its next dump.
    void send(const std::string& xdotoolArgs, const std::string& go) {
        EXPECT_EQ(xdotool(xdotoolArgs), 0) << xdotoolArgs;
        writeText(dir / go, "");
    }
};

TEST_F(EditorDisplay, KeyboardPopupsDialogsAndLayouts) {
    if (!haveProgram("xdotool")) GTEST_SKIP() << "SKIPPED: xdotool is not installed (scripts/install-deps.sh)";
    EditorProcess editor;
    std::string script = "wait-idle\nwait-frames 3\nclick-button View\nwait-frames 3\ndump-state s0.json\n";
    for (int i = 1; i <= 7; ++i)
        script += "wait-file go" + std::to_string(i) + "\nwait-frames 4\nscreenshot s" + std::to_string(i) + ".png\ndump-state s" +
                  std::to_string(i) + ".json\n";
    script += "quit\n";
    start(editor, script, (dir / "tower.obj").string(), "1100x700");

    json s0 = state(editor, "s0.json");
    ASSERT_TRUE(s0.is_object());
    const int wx = s0["window"]["x"], wy = s0["window"]["y"];
    auto at = [&](float x, float y) { return std::to_string(wx + int(x)) + " " + std::to_string(wy + int(y)); };
    const std::array<float, 4> view = rectOf(s0["viewports"][0]["rect"]);
    const std::string overView = "mousemove " + at(view[0] + view[2] / 2, view[1] + view[3] / 2) + " sleep 0.3 ";

    // The cage stands on z = 0 and its file says nothing: Z up, and the camera orbits about z.
    EXPECT_EQ(s0["display"]["up_axis"], "z");
    EXPECT_GT(vec3Of(s0["viewports"][0]["camera"]["up"]).z, 0.5f);
    EXPECT_LT(s0["viewports"][0]["axis_triad"]["screen"][2][1].get<float>(), -0.5f) << "the triad's z does not point up";
    EXPECT_GT(s0["display"]["grid_lines"].get<int>(), 20);
    EXPECT_EQ(s0["display"]["crease_lines"], 1);

    // 1. A real click opens the "Plans path" drop-down; 2. Esc closes it; 3. Numpad 7 works again.
    ASSERT_TRUE(s0["widgets"].contains("Plans path"));
    const std::array<float, 4> combo = rectOf(s0["widgets"]["Plans path"]);
    send("mousemove " + at(combo[0] + combo[2] * 0.3f, combo[1] + combo[3] / 2) + " sleep 0.3 click 1 sleep 0.6", "go1");
    json s1 = state(editor, "s1.json");
    EXPECT_TRUE(s1["popup_open"].get<bool>()) << "the click did not open the drop-down";
    send("key Escape sleep 0.5", "go2");
    json s2 = state(editor, "s2.json");
    EXPECT_FALSE(s2["popup_open"].get<bool>()) << "Esc did not close the drop-down";
    send(overView + "key KP_7 sleep 0.5", "go3");
    json s3 = state(editor, "s3.json");
    const json& camera = s3["viewports"][0]["camera"];
    EXPECT_GT(glm::normalize(vec3Of(camera["eye"]) - vec3Of(camera["target"])).z, 0.999f)
        << "Numpad 7 after the drop-down did not look down the z axis";

    // 4. Save As: proposes tower.json beside the cage, with the keyboard in its path field.
    send(overView + "key ctrl+shift+s sleep 0.6", "go4");
    json s4 = state(editor, "s4.json");
    EXPECT_EQ(s4["open_popups"], json::array({"Save As"}));
    EXPECT_EQ(fs::path(s4["save_as_path"].get<std::string>()), dir / "tower.json");
    EXPECT_TRUE(s4["text_input"].get<bool>()) << "the path field does not have the keyboard";
    // 5. Esc cancels (nothing written); 6. again, and Enter saves.
    send("key Escape sleep 0.5", "go5");
    json s5 = state(editor, "s5.json");
    EXPECT_TRUE(s5["open_popups"].empty());
    EXPECT_FALSE(fs::exists(dir / "tower.json"));
    send(overView + "key ctrl+shift+s sleep 0.8 key Return sleep 0.8", "go6");
    json s6 = state(editor, "s6.json");
    EXPECT_TRUE(s6["open_popups"].empty());
    ASSERT_TRUE(fs::exists(dir / "tower.json")) << "Enter did not save";
    EXPECT_EQ(readJson(dir / "tower.json")["display"]["up_axis"], "z");

    // 7. Zoomed in so far that the model leaves the view, then Ctrl+2: both new viewports frame it.
    send(overView + "click --repeat 8 --delay 80 4 sleep 0.5 key ctrl+2 sleep 0.6", "go7");
    json s7 = state(editor, "s7.json");
    ASSERT_EQ(s7["viewports"].size(), 2u);
    for (const json& v : s7["viewports"]) EXPECT_TRUE(modelInside(v)) << "Ctrl+2 did not frame the model in " << v["rect"];
    EXPECT_EQ(editor.wait(kRunSeconds), 0) << editor.output();
}

TEST_F(EditorDisplay, ShadingGridCreasesAndPanels) {
    EditorProcess editor;
    start(editor,
          "wait-idle\nwait-frames 3\nscreenshot model.png\ndump-state model.json\n"
          "click-button Sculpt\nwait-frames 3\ndump-state sculpt.json\n"
          "click-button View\nwait-frames 3\ndump-state view.json\nscreenshot studio.png\n"
          "click-button Matcap\nwait-frames 3\nscreenshot matcap.png\n"
          "heatmap 0 on\nwait-frames 4\nscreenshot heat.png\ndump-state heat.json\nheatmap 0 off\n"
          "click-button Grid\nwait-frames 3\nscreenshot nogrid.png\nclick-button Grid\n"
          "save-as " + (dir / "look.json").string() + "\nwait-frames 2\n"
          "open " + (dir / "look.json").string() + "\nwait-idle\nwait-frames 3\ndump-state reopened.json\nquit\n",
          (dir / "default.json").string(), "1280x800");

    // Every tab's widgets lie within the 1280x800 window.
    for (const char* name : {"model.json", "sculpt.json", "view.json"}) {
        json s = state(editor, name);
        ASSERT_TRUE(s.is_object()) << name;
        const float height = s["window"]["height"];
        for (const auto& [label, r] : s["widgets"].items()) {
            if (r[0].get<float>() > 1280 - 400) {  // the side panel
                EXPECT_LE(r[1].get<float>() + r[3].get<float>(), height) << label << " is below the fold in " << name;
            }
        }
    }
    for (const char* label : {"Crease edges", "Merge", "Fill holes"})
        EXPECT_TRUE(readJson(dir / "model.json")["widgets"].contains(label)) << label;
    for (const char* label : {"Matcap", "Studio", "Grid", "Z up", "Tessellation wireframe", "Plans path"})
        EXPECT_TRUE(readJson(dir / "view.json")["widgets"].contains(label)) << label;

    json heat = state(editor, "heat.json");
    json reopened = state(editor, "reopened.json");
    EXPECT_EQ(editor.wait(kRunSeconds), 0) << editor.output();
    ASSERT_TRUE(heat.is_object());
    EXPECT_EQ(heat["display"]["shading"], "matcap");
    EXPECT_TRUE(heat["viewports"][0]["heatmap"]["valid"].get<bool>());
    EXPECT_GT(heat["display"]["crease_lines"].get<int>(), 0);
    EXPECT_GE(heat["display"]["crease_line_width"].get<float>(), 4.0f) << "creases are not drawn wide (lavapipe has wideLines)";
    ASSERT_TRUE(reopened.is_object());
    EXPECT_EQ(reopened["display"]["shading"], "matcap") << "the shading was not saved in the scene";
    EXPECT_EQ(reopened["display"]["up_axis"], "y");

    const std::array<float, 4> r = rectOf(heat["viewports"][0]["rect"]);
    const int x0 = int(r[0]), y0 = int(r[1]) + 40, x1 = int(r[0] + r[2]), y1 = int(r[1] + r[3]);
    const Image studio = loadImage(dir / "studio.png"), matcap = loadImage(dir / "matcap.png");
    const Image heatMap = loadImage(dir / "heat.png"), noGrid = loadImage(dir / "nogrid.png");
    ASSERT_GT(studio.width, 0);
    EXPECT_GT(differing(studio, matcap, x0, y0, x1, y1), 5000u) << "matcap looks like studio";
    EXPECT_GT(differing(matcap, noGrid, x0, y0, x1, y1), 300u) << "the grid draws nothing";
    // The heat map's colours carry the shading: many brightness levels, not a few flat colours.
    EXPECT_GT(shadedColorLevels(heatMap, x0, y0, x1, y1), 60u) << "the heat map is flat colour";
}

TEST_F(EditorDisplay, CullingKeepsThePictureAndCounts) {
    writeText(dir / "torus.obj", formatObj(makeTorus(24, 12)));
    EditorProcess editor;
    start(editor,
          "wait-idle\nwait-frames 3\nscreenshot plain.png\ndump-state plain.json\n"
          "set-cull 0 pplane\nwait-frames 4\nscreenshot culled.png\ndump-state culled.json\n"
          "set-cull 0 frustum\nwait-frames 4\ndump-state frustum.json\nset-cull 0 sideways\nquit\n",
          (dir / "torus.obj").string(), "1100x700");
    json plain = state(editor, "plain.json"), culled = state(editor, "culled.json"), frustum = state(editor, "frustum.json");
    // The bad method is refused with a message; the script stops there.
    EXPECT_NE(editor.wait(kRunSeconds), 0);
    EXPECT_NE(editor.output().find("unknown culling method 'sideways'"), std::string::npos) << editor.output();
    ASSERT_TRUE(plain.is_object() && culled.is_object() && frustum.is_object());
    EXPECT_TRUE(culled["widgets"].contains("Culling 1")) << "no culling combo in the viewport bar";
    EXPECT_EQ(culled["viewports"][0]["cull"], "pplane");
    const json& counts = culled["viewports"][0]["culled"];
    EXPECT_EQ(counts["tested"], 288);
    EXPECT_GT(counts["back_facing"].get<int>(), 5) << counts;
    EXPECT_EQ(culled["viewports"][0]["patches"].get<int>(), 288 - counts["back_facing"].get<int>() - counts["frustum"].get<int>());
    EXPECT_EQ(plain["viewports"][0]["culled"]["tested"], 0);
    EXPECT_EQ(frustum["viewports"][0]["culled"]["back_facing"], 0) << "the frustum test culls nothing facing away";
    const Image a = loadImage(dir / "plain.png"), b = loadImage(dir / "culled.png");
    ASSERT_GT(a.width, 0);
    const std::array<float, 4> r = rectOf(culled["viewports"][0]["rect"]);
    // Exactly, below the viewport bar (whose combo shows the method).
    size_t changed = 0;
    for (int y = int(r[1]) + 40; y < std::min(int(r[1] + r[3]), a.height); ++y)
        for (int x = int(r[0]); x < std::min(int(r[0] + r[2]), a.width); ++x)
            changed += !std::equal(a.at(x, y), a.at(x, y) + 3, b.at(x, y));
    EXPECT_EQ(changed, 0u) << "culling changed the picture";
}

// A scene of three objects: the tower, an instance of it moved along x, and a second tower of its
// own on the other side. The editor draws all three (the instance follows an edit of the tower as
// it happens), and saves every object back as it was. Run twice, with the other two hidden in the
// second run, from the scene's own camera, so the pictures compare pixel for pixel.
TEST_F(EditorDisplay, SceneObjectsAreDrawnAndInstancesFollowEdits) {
    auto scene = [&](bool othersVisible, const std::string& obj) {
        json objects = json::array();
        objects.push_back({{"name", "tower"}, {"cage", {{"path", obj}}}});
        objects.push_back({{"name", "tower.001"}, {"instance_of", "tower"}, {"visible", othersVisible},
                           {"transform", {{"translation", {4, 0, 0}}, {"rotation_degrees", {0, 0, 30}}}}});
        objects.push_back({{"name", "other"}, {"cage", {{"path", obj}}}, {"visible", othersVisible},
                           {"transform", {{"translation", {-4, 0, 0}}, {"scale", {0.8, 0.8, 0.8}}}}});
        return json{{"format", "quadplan-scene"}, {"version", 2}, {"objects", objects},
                    {"camera", {{"eye", {0, -14, 6}}, {"target", {0, 0, 1.5}}, {"up", {0, 0, 1}}}},
                    {"display", {{"up_axis", "z"}}}};
    };
    std::map<bool, std::pair<Image, Image>> shots;  // others visible -> (before, after the edit)
    std::array<float, 4> viewport{};                 // x, y, width, height
    for (bool visible : {true, false}) {
        const std::string tag = visible ? "shown" : "hidden";
        // Each run its own OBJ: saving writes the edited tower back to it.
        fs::copy_file(dir / "tower.obj", dir / ("tower_" + tag + ".obj"), fs::copy_options::overwrite_existing);
        writeText(dir / (tag + ".json"), scene(visible, "tower_" + tag + ".obj").dump());
        EditorProcess editor;
        start(editor,
              "wait-idle\nwait-frames 3\nscreenshot " + tag + "_before.png\nselect-vertex 6\nmove-selection 0 0 1.5\n"
              "wait-frames 3\nscreenshot " + tag + "_after.png\nsave-as " + (dir / (tag + "_saved.json")).string() +
              "\nwait-frames 2\ndump-state " + tag + ".state.json\nquit\n",
              (dir / (tag + ".json")).string(), "900x600");
        const json dumped = state(editor, tag + ".state.json");
        EXPECT_EQ(editor.wait(kRunSeconds), 0) << editor.output();
        if (visible) viewport = rectOf(dumped["viewports"][0]["rect"]);
        shots[visible] = {loadImage(dir / (tag + "_before.png")), loadImage(dir / (tag + "_after.png"))};
        ASSERT_GT(shots[visible].first.width, 0) << tag;
    }
    const auto& [shownBefore, shownAfter] = shots[true];
    const auto& [hiddenBefore, hiddenAfter] = shots[false];
    // Inside the viewport, away from its toolbar (the panels change with the selection).
    const int x0 = int(viewport[0]), y0 = int(viewport[1]) + 50, x1 = int(viewport[0] + viewport[2]),
              y1 = int(viewport[1] + viewport[3]);
    // The other two objects are drawn.
    EXPECT_GT(differing(shownBefore, hiddenBefore, x0, y0, x1, y1), 3000u);
    // The edit changes the tower, and with the others shown the instance too: more pixels change.
    const size_t alone = differing(hiddenBefore, hiddenAfter, x0, y0, x1, y1);
    const size_t withInstance = differing(shownBefore, shownAfter, x0, y0, x1, y1);
    EXPECT_GT(alone, 300u);
    EXPECT_GT(withInstance, alone + 500) << alone << " pixels changed alone, " << withInstance << " with the instance";
    // Saved as loaded: three objects, the link, the transforms, the visibility, the moved vertex.
    Result<Scene> saved = loadScene((dir / "shown_saved.json").string());
    ASSERT_TRUE(saved) << saved.error().message;
    ASSERT_EQ(saved->objects.size(), 3u);
    EXPECT_EQ(saved->objects[1].instanceOf, "tower");
    EXPECT_EQ(saved->objects[1].transform.rotationDegrees, glm::vec3(0, 0, 30));
    EXPECT_EQ(saved->objects[2].transform.scale, glm::vec3(0.8f));
    EXPECT_FLOAT_EQ(saved->objects[0].cage.positions[6].z, 4.5f);
    EXPECT_FLOAT_EQ(saved->objects[2].cage.positions[6].z, 3.0f);  // the other tower was not edited
}

}  // namespace
