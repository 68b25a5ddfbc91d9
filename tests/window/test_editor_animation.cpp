// Issue 22 in the real editor: an animated scene (a cage with vertex keys at two frames, a second
// object whose cage and transform are keyed too) opens on its first frame; set-frame shows keyed
// and interpolated frames re-planning nothing, the other object's cage and transform follow, and
// the picture changes; playback advances by the clock and reports the rate it achieved; a move at
// a frame without keys keys it there (saved in the scene, the rest positions untouched) and undo
// takes the key away; with a third key, Catmull-Rom interpolation (set-interpolation, one history
// entry, the timeline's combo) moves a vertex between keys off the linear path and undo brings
// linear back; a topology edit carries the keys. One editor run, automation only.
#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include "animation/cage_animation.h"
#include "editor_process.h"
#include "render_test_support.h"
#include "scene/scene.h"
#include "test_cages.h"

using namespace qp;
using namespace qp::test;
using nlohmann::json;

namespace {

constexpr double kRunSeconds = 240.0;
const glm::vec3 kLift(0.5f, 0.8f, 0.0f);  // what frame 24 does to the top of the tower
constexpr uint32_t kMovedVertex = 0;      // a bottom corner: no keys of its own
const glm::vec3 kThirdKey(0.0f, 0.0f, 1.0f);  // top[0] at frame 36: frame 24's lift and this

json positionsJson(const std::vector<glm::vec3>& positions) {
    json out = json::array();
    for (const glm::vec3& p : positions) out.push_back({p.x, p.y, p.z});
    return out;
}

json inlineCage(const Cage& cage) {
    json faces = json::array();
    for (uint32_t f = 0; f < cage.faceCount(); ++f)
        faces.push_back(std::vector<uint32_t>(cage.faceBegin(f), cage.faceBegin(f) + cage.faceSize(f)));
    return {{"positions", positionsJson(cage.positions)}, {"faces", faces}};
}

// Keys of `vertices` at frame 1 (where they are) and 24 (moved by `offset`).
json twoKeys(const Cage& cage, const std::vector<uint32_t>& vertices, glm::vec3 offset) {
    std::vector<glm::vec3> at1, at24;
    for (uint32_t v : vertices) at1.push_back(cage.positions[v]), at24.push_back(cage.positions[v] + offset);
    return json::array({{{"frame", 1}, {"vertices", vertices}, {"positions", positionsJson(at1)}},
                        {{"frame", 24}, {"vertices", vertices}, {"positions", positionsJson(at24)}}});
}

glm::vec3 vec(const json& j) { return {j[0].get<float>(), j[1].get<float>(), j[2].get<float>()}; }

const json& objectNamed(const json& state, const std::string& name) {
    for (const json& o : state["objects"])
        if (o["name"] == name) return o;
    static const json none;
    ADD_FAILURE() << "no object " << name;
    return none;
}

// The keys the scene file holds for `vertex` at `frame`, or null.
json savedKey(const json& scene, uint32_t vertex, int frame) {
    for (const json& key : scene["objects"][0]["animation"]["keys"]) {
        if (key["frame"] != frame) continue;
        for (size_t k = 0; k < key["vertices"].size(); ++k)
            if (key["vertices"][k] == vertex) return key["positions"][k];
    }
    return nullptr;
}

class EditorAnimation : public ::testing::Test {
protected:
    fs::path dir;
    Cage tower = makeSubdividedCube(2);
    std::vector<uint32_t> top;  // the tower's vertices on y = 1

    void SetUp() override {
        if (!haveDisplay()) GTEST_SKIP() << "SKIPPED: DISPLAY is unset; run under xvfb-run";
        dir = testOutputDir() / "animation";
        fs::remove_all(dir);
        fs::create_directories(dir / "recovery");
        for (uint32_t v = 0; v < tower.vertexCount(); ++v)
            if (tower.positions[v].y > 0.5f) top.push_back(v);
        const Cage block = makeCube();
        std::vector<uint32_t> all(block.vertexCount());
        for (uint32_t v = 0; v < all.size(); ++v) all[v] = v;
        json objects = json::array();
        objects.push_back({{"name", "tower"},
                           {"cage", inlineCage(tower)},
                           {"animation", {{"interpolation", "linear"}, {"keys", twoKeys(tower, top, kLift)}}}});
        json blockKeys = {{"interpolation", "linear"},
                          {"keys", twoKeys(block, all, glm::vec3(0, 1, 0))},
                          {"transform_keys", json::array({{{"frame", 1}, {"transform", {{"translation", {3, 0, 0}}}}},
                                                          {{"frame", 24}, {"transform", {{"translation", {3, 0, 2}}}}}})}};
        objects.push_back({{"name", "block"}, {"cage", inlineCage(block)}, {"animation", blockKeys},
                           {"transform", {{"translation", {3, 0, 0}}}}});
        const json scene = {{"format", "quadplan-scene"}, {"version", 2}, {"objects", objects},
                            {"camera", {{"eye", {1, 3, 12}}, {"target", {1.5, 0.5, 0}}, {"up", {0, 1, 0}}}},
                            {"timeline", {{"fps", 24}, {"first_frame", 1}, {"last_frame", 48}}}};
        writeText(dir / "scene.json", scene.dump());
    }

    json state(EditorProcess& editor, const std::string& name) {
        EXPECT_TRUE(waitForFile(dir / name, editor, kRunSeconds)) << name << " never came:\n" << editor.output();
        return readJson(dir / name);
    }
};

}  // namespace

TEST_F(EditorAnimation, ShowsFramesPlaysAndKeysEditsAtTheFrame) {
    const std::string saved = (dir / "keyed.json").string(), unkeyed = (dir / "unkeyed.json").string();
    const std::string script =
        "wait-idle\nwait-frames 3\ndump-state open.json\nscreenshot frame1.png\n"
        "set-frame 24\nwait-frames 2\ndump-state f24.json\nscreenshot frame24.png\n"
        "set-frame 12.5\nwait-frames 2\ndump-state f12.json\n"
        "set-frame 1\nplay\nwait-seconds 1\npause\ndump-state played.json\n"
        "set-frame 30\nselect-vertex " + std::to_string(kMovedVertex) + "\nmove-selection 0 -0.5 0\n"
        "wait-frames 2\ndump-state moved.json\nsave-as " + saved + "\n"
        "undo\nwait-frames 2\ndump-state undone.json\nsave-as " + unkeyed + "\n"
        "resize 1280 800\nset-frame 36\nselect-vertex " + std::to_string(top[0]) + "\nmove-selection 0 0 1\n"
        "set-frame 12.5\nwait-frames 3\ndump-state linear.json\n"
        "set-interpolation catmull-rom\nwait-frames 3\ndump-state catmull.json\nscreenshot catmull.png\n"
        "undo\nwait-frames 2\ndump-state relinear.json\n"
        "set-frame 24\nselect face 0\nextrude 0.3\nset-frame 1\nwait-frames 2\ndump-state extruded.json\n"
        "quit\nclick-button Discard changes\n";
    writeText(dir / "script.txt", script);
    std::map<std::string, std::string> env = editorEnvironment(dir / "recovery");
    env["QUADPLAN_PLAN_CACHE"] = "off";
    EditorProcess editor;
    editor.start({"edit", (dir / "scene.json").string(), "--automation", (dir / "script.txt").string(), "--validate",
                  "--size", "1100x700"},
                 dir, env, dir / "editor.log");

    // Opened on the first frame: the cage as keyed there (its rest), the timeline from the file.
    const json open = state(editor, "open.json");
    ASSERT_TRUE(open.is_object());
    EXPECT_EQ(open["animation"]["frame"], 1.0);
    EXPECT_TRUE(open["animation"]["animated"].get<bool>());
    EXPECT_FALSE(open["animation"]["playing"].get<bool>());
    EXPECT_EQ(open["animation"]["last_frame"], 48);
    EXPECT_EQ(open["animation"]["key_frames"], json::array({1, 24}));
    EXPECT_EQ(vec(open["vertices"][top[0]]), tower.positions[top[0]]);
    EXPECT_EQ(vec(objectNamed(open, "block")["translation"]), glm::vec3(3, 0, 0));

    // Frame 24: the keyed top moved, nothing re-planned, the block's cage and transform followed.
    const json f24 = state(editor, "f24.json");
    for (uint32_t v : top) EXPECT_LT(glm::distance(vec(f24["vertices"][v]), tower.positions[v] + kLift), 1e-5f) << v;
    EXPECT_EQ(vec(f24["vertices"][kMovedVertex]), tower.positions[kMovedVertex]);
    EXPECT_EQ(f24["animation"]["last_frame_change"]["replanned_faces"], 0);
    EXPECT_GT(f24["animation"]["last_frame_change"]["updated_subfaces"].get<int>(), 0);
    EXPECT_EQ(f24["unique_plans"], open["unique_plans"]) << "a frame built plans";
    EXPECT_FALSE(f24["dirty"].get<bool>()) << "showing a frame is not an edit";
    const json& block24 = objectNamed(f24, "block");
    EXPECT_EQ(vec(block24["translation"]), glm::vec3(3, 0, 2));
    EXPECT_NEAR(vec(block24["bounds"][0]).y, 0.0f, 1e-5f) << "the other object's cage did not animate";

    // Between the keys: linear, halfway at 12.5.
    const json f12 = state(editor, "f12.json");
    EXPECT_GT(differingPixels(dir / "frame1.png", dir / "frame24.png"), 2000u) << "frame 24 looks like frame 1";
    EXPECT_LT(glm::distance(vec(f12["vertices"][top[0]]), tower.positions[top[0]] + 0.5f * kLift), 1e-5f);
    EXPECT_EQ(f12["animation"]["last_frame_change"]["replanned_faces"], 0);

    // A second of playback from frame 1 at 24 fps: the clock moved the frame, whatever the rate drawn.
    const json played = state(editor, "played.json");
    EXPECT_FALSE(played["animation"]["playing"].get<bool>());
    EXPECT_GE(played["animation"]["frame"].get<double>(), 12.0) << "playback fell behind the clock";
    EXPECT_GT(played["animation"]["fps_achieved"].get<double>(), 0.0);
    EXPECT_LE(played["animation"]["fps_achieved"].get<double>(), 30.0) << "faster than the timeline's 24 fps";

    // A move at frame 30 (no keys there) keys the vertex there: one entry, the status says so.
    const json moved = state(editor, "moved.json");
    EXPECT_EQ(moved["animation"]["frame"], 30.0);
    EXPECT_EQ(moved["history"]["size"], 1);
    EXPECT_NE(moved["status"].get<std::string>().find("keyed 1 vertex at frame 30"), std::string::npos) << moved["status"];
    EXPECT_EQ(moved["animation"]["key_frames"], json::array({1, 24, 30}));
    const glm::vec3 target = tower.positions[kMovedVertex] + glm::vec3(0, -0.5f, 0);
    EXPECT_LT(glm::distance(vec(moved["vertices"][kMovedVertex]), target), 1e-5f);
    const json keyed = state(editor, "keyed.json");  // saved after moved.json: waited for, not assumed
    ASSERT_TRUE(keyed.is_object());
    ASSERT_FALSE(savedKey(keyed, kMovedVertex, 30).is_null()) << keyed["objects"][0]["animation"].dump();
    EXPECT_LT(glm::distance(vec(savedKey(keyed, kMovedVertex, 30)), target), 1e-5f);
    // The scene keeps the rest positions, not the frame shown.
    EXPECT_EQ(vec(keyed["objects"][0]["cage"]["positions"][top[0]]), tower.positions[top[0]]);
    EXPECT_EQ(vec(keyed["objects"][1]["cage"]["positions"][0]), makeCube().positions[0]);

    // Undo takes the key away; the vertex is back where frame 30 leaves it (its rest).
    const json back = state(editor, "undone.json");
    EXPECT_EQ(back["animation"]["key_frames"], json::array({1, 24}));
    EXPECT_EQ(vec(back["vertices"][kMovedVertex]), tower.positions[kMovedVertex]);
    EXPECT_TRUE(savedKey(state(editor, "unkeyed.json"), kMovedVertex, 30).is_null());

    // A third key (top[0] at frame 36): between frames 1 and 24 linear stays on the line,
    // Catmull-Rom (its tangent at 24 now sees frame 36) leaves it; one entry, undone to linear.
    const glm::vec3 p0 = tower.positions[top[0]];
    VertexKeys keys{{0, 3}, {1, 24, 36}, {p0, p0 + kLift, p0 + kLift + kThirdKey}};
    glm::vec3 smooth;
    evaluatePositions(keys, Interpolation::CatmullRom, std::span(&p0, 1), 12.5, std::span(&smooth, 1));
    ASSERT_GT(glm::distance(smooth, p0 + 0.5f * kLift), 1e-3f) << "the keys do not tell the interpolations apart";
    const json lin = state(editor, "linear.json");
    EXPECT_EQ(lin["animation"]["interpolation"], "linear");
    EXPECT_EQ(lin["animation"]["key_frames"], json::array({1, 24, 36}));
    EXPECT_LT(glm::distance(vec(lin["vertices"][top[0]]), p0 + 0.5f * kLift), 1e-5f);
    const json smoothed = state(editor, "catmull.json");
    EXPECT_EQ(smoothed["animation"]["interpolation"], "catmull-rom");
    EXPECT_EQ(smoothed["animation"]["frame"], 12.5);
    EXPECT_LT(glm::distance(vec(smoothed["vertices"][top[0]]), smooth), 1e-5f);
    EXPECT_GT(glm::distance(vec(smoothed["vertices"][top[0]]), vec(lin["vertices"][top[0]])), 1e-3f);
    EXPECT_EQ(smoothed["animation"]["last_frame_change"]["replanned_faces"], 0);
    EXPECT_EQ(smoothed["history"]["size"], lin["history"]["size"].get<int>() + 1);
    EXPECT_EQ(smoothed["history"]["entries"].back()["name"], "Catmull-Rom interpolation of tower");
    EXPECT_TRUE(smoothed["dirty"].get<bool>());
    // The combo sits in the timeline strip, left of the side panel, at 1280x800.
    ASSERT_TRUE(smoothed["widgets"].contains("Interpolation"));
    const json& combo = smoothed["widgets"]["Interpolation"];
    EXPECT_LE(combo[0].get<float>() + combo[2].get<float>(), 1280.0f - 380.0f) << combo.dump();
    EXPECT_LE(combo[1].get<float>() + combo[3].get<float>(), 800.0f) << combo.dump();
    const json relin = state(editor, "relinear.json");
    EXPECT_EQ(relin["animation"]["interpolation"], "linear");
    EXPECT_EQ(relin["history"]["position"], lin["history"]["position"]);
    EXPECT_LT(glm::distance(vec(relin["vertices"][top[0]]), p0 + 0.5f * kLift), 1e-5f);

    // An extrude at frame 24 carries the keys: at frame 1 the cage has the new faces and vertices
    // and shows the first frame again without re-planning.
    const json extruded = state(editor, "extruded.json");
    EXPECT_EQ(extruded["faces"].get<int>(), open["faces"].get<int>() + 4);
    EXPECT_EQ(extruded["vertices"].size(), open["vertices"].size() + 4);
    EXPECT_EQ(extruded["animation"]["frame"], 1.0);
    EXPECT_GT(extruded["animation"]["last_frame_change"]["updated_subfaces"].get<int>(), 0);
    EXPECT_EQ(extruded["animation"]["last_frame_change"]["replanned_faces"], 0);
    EXPECT_EQ(editor.wait(kRunSeconds), 0) << editor.output();
}
