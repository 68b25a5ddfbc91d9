// `quadplan animate`: an OBJ sequence or a scene's keys played into a PNG per frame; the frames
// re-plan nothing; bad input is refused naming the problem, with no PNG written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>
#include <unistd.h>

#include "cli_run.h"
#include "mesh/obj_io.h"
#include "test_cages.h"

namespace fs = std::filesystem;

namespace {

using qp::test::CommandRun;
using qp::test::runQuadplan;

// Small and coarse: every run is a fraction of a second on lavapipe.
const std::string kFast = " --size 96x72 --tess 3";

class CliAnimate : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("quadplan-animate-" + std::to_string(::getpid()) + "-" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_ / "seq");
        cage_ = qp::test::makeCube();
        ASSERT_TRUE(qp::saveObj(cage_, path("cube.obj")));
    }
    void TearDown() override { fs::remove_all(dir_); }

    std::string path(const std::string& name) const { return (dir_ / name).string(); }

    // Frame k of a twist that also stretches the top: every frame looks different.
    qp::Cage frame(int k) const {
        qp::Cage c = cage_;
        const float angle = 0.4f * float(k - 1);
        for (glm::vec3& p : c.positions) {
            const float a = angle * (p.y + 1.0f) * 0.5f;
            p = {std::cos(a) * p.x + std::sin(a) * p.z, p.y > 0 ? p.y * (1.0f + 0.3f * float(k - 1)) : p.y,
                 -std::sin(a) * p.x + std::cos(a) * p.z};
        }
        return c;
    }
    void writeFrame(int k, const qp::Cage& c) {
        char name[32];
        std::snprintf(name, sizeof name, "seq/frame_%04d.obj", k);
        ASSERT_TRUE(qp::saveObj(c, path(name)));
    }
    void writeSequence(int frames) {
        for (int k = 1; k <= frames; ++k) writeFrame(k, frame(k));
    }
    std::string sequence() const { return " --sequence '" + path("seq/frame_*.obj") + "'"; }
    std::vector<std::string> pngs(const std::string& out) const {
        std::vector<std::string> names;
        if (!fs::exists(out)) return names;
        for (const auto& entry : fs::directory_iterator(out))
            if (entry.path().extension() == ".png") names.push_back(entry.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }
    // Fails with a message containing `expected`; no PNG lies in `out` afterwards.
    void expectRefused(const std::string& args, const std::string& out, const std::string& expected) {
        CommandRun run = runQuadplan("animate " + args + " --out " + out + kFast, true);
        EXPECT_NE(run.status, 0) << run.out;
        EXPECT_NE(run.out.find("error: "), std::string::npos) << run.out;
        EXPECT_NE(run.out.find(expected), std::string::npos) << "expected \"" << expected << "\" in: " << run.out;
        EXPECT_TRUE(pngs(out).empty()) << args;
    }

    fs::path dir_;
    qp::Cage cage_;
};

TEST_F(CliAnimate, SequenceWritesAFramePerFileAndReplansNothing) {
    writeSequence(3);
    const std::string out = path("out");
    CommandRun run = runQuadplan("animate " + path("cube.obj") + sequence() + " --out " + out + kFast + " --json");
    ASSERT_EQ(run.status, 0) << run.out;
    const nlohmann::json json = nlohmann::json::parse(run.out);
    EXPECT_EQ(json["frames"], 3);
    EXPECT_EQ(json["replanned_faces"], 0);
    EXPECT_EQ(json["rebuilds"], 0);
    EXPECT_EQ(json["scheme"], "plans");
    EXPECT_EQ(json["tess"], 3);
    EXPECT_EQ(json["triangles"].size(), 3u);
    EXPECT_GE(json["update_ms_median"].get<double>(), 0.0);
    EXPECT_GT(json["frame_ms_median"].get<double>(), 0.0);
    EXPECT_EQ(pngs(out), (std::vector<std::string>{"frame_0001.png", "frame_0002.png", "frame_0003.png"}));

    const qp::test::Png first = qp::test::loadPng(out + "/frame_0001.png");
    const qp::test::Png last = qp::test::loadPng(out + "/frame_0003.png");
    ASSERT_EQ(first.width, 96);
    ASSERT_EQ(first.height, 72);
    ASSERT_EQ(last.rgba.size(), first.rgba.size());
    EXPECT_NE(first.rgba, last.rgba);  // the cage moved between them
}

TEST_F(CliAnimate, SceneKeysPlayItsTimelineAndFramesPicksOne) {
    // Keys on the top four vertices at frames 1 and 9, a transform key pair, a timeline 2..4.
    const std::string scene = path("keys.json");
    std::ofstream(scene) << R"({"format": "quadplan-scene", "version": 2,
      "objects": [{"name": "box", "cage": {"positions": [[-1,-1,-1],[1,-1,-1],[1,1,-1],[-1,1,-1],[-1,-1,1],[1,-1,1],[1,1,1],[-1,1,1]],
                   "faces": [[0,3,2,1],[4,5,6,7],[0,1,5,4],[1,2,6,5],[2,3,7,6],[3,0,4,7]]},
        "animation": {"keys": [{"frame": 1, "vertices": [2,3,6,7], "positions": [[1,1,-1],[-1,1,-1],[1,1,1],[-1,1,1]]},
                               {"frame": 9, "vertices": [2,3,6,7], "positions": [[2,3,-1],[0,3,-1],[2,3,1],[0,3,1]]}],
                      "transform_keys": [{"frame": 1}, {"frame": 9, "transform": {"rotation_degrees": [0, 60, 0]}}]}}],
      "timeline": {"first_frame": 2, "last_frame": 4}})";
    const std::string out = path("out");
    CommandRun run = runQuadplan("animate " + scene + " --out " + out + kFast + " --json");
    ASSERT_EQ(run.status, 0) << run.out;
    nlohmann::json json = nlohmann::json::parse(run.out);
    EXPECT_EQ(json["frames"], 3);
    EXPECT_EQ(json["first_frame"], 2);
    EXPECT_EQ(json["last_frame"], 4);
    EXPECT_EQ(json["replanned_faces"], 0);
    EXPECT_EQ(pngs(out), (std::vector<std::string>{"frame_0002.png", "frame_0003.png", "frame_0004.png"}));
    EXPECT_NE(qp::test::loadPng(out + "/frame_0002.png").rgba, qp::test::loadPng(out + "/frame_0004.png").rgba);

    const std::string one = path("one");
    run = runQuadplan("animate " + scene + " --frames 2:2 --out " + one + kFast + " --json");
    ASSERT_EQ(run.status, 0) << run.out;
    json = nlohmann::json::parse(run.out);
    EXPECT_EQ(json["frames"], 1);
    EXPECT_EQ(pngs(one), std::vector<std::string>{"frame_0002.png"});
    EXPECT_EQ(qp::test::loadPng(one + "/frame_0002.png").width, 96);

    // Frames past the keys hold the last key.
    const std::string past = path("past");
    run = runQuadplan("animate " + scene + " --frames 12:13 --out " + past + kFast + " --json");
    ASSERT_EQ(run.status, 0) << run.out;
    EXPECT_EQ(qp::test::loadPng(past + "/frame_0012.png").rgba, qp::test::loadPng(past + "/frame_0013.png").rgba);
}

// Every scheme plugin plays the sequence through its in-place update, and its last frame is the
// picture `render` draws of that frame's OBJ from a new instance, pixel for pixel.
TEST_F(CliAnimate, EverySchemeUpdatesInPlaceToWhatRenderDraws) {
    writeSequence(3);
    CommandRun list = runQuadplan("schemes --json");
    ASSERT_EQ(list.status, 0);
    const nlohmann::json schemes = nlohmann::json::parse(list.out)["schemes"];
    ASSERT_GE(schemes.size(), 3u);
    const std::string view = kFast + " --camera 4,3,5,0,0,0,40";
    for (const nlohmann::json& s : schemes) {
        const std::string name = s["name"];
        const std::string out = path("out-" + name);
        CommandRun run = runQuadplan("animate " + path("cube.obj") + sequence() + " --scheme " + name + " --out " + out +
                                     view + " --json");
        ASSERT_EQ(run.status, 0) << name << ": " << run.out;
        const nlohmann::json json = nlohmann::json::parse(run.out);
        EXPECT_EQ(json["frames"], 3) << name;
        EXPECT_EQ(json["replanned_faces"], 0) << name;
        EXPECT_EQ(json["scheme"], name);
        EXPECT_GE(json["rebuilds"].get<int>(), 0) << name;
        const std::string rendered = path("render-" + name + ".png");
        CommandRun render = runQuadplan("render " + path("seq/frame_0003.obj") + " --scheme " + name + " --out " + rendered + view, true);
        ASSERT_EQ(render.status, 0) << name << ": " << render.out;
        const qp::test::Png animated = qp::test::loadPng(out + "/frame_0003.png"), fresh = qp::test::loadPng(rendered);
        ASSERT_EQ(animated.width, fresh.width) << name;
        EXPECT_EQ(animated.rgba, fresh.rgba) << name;
        EXPECT_NE(animated.rgba, qp::test::loadPng(out + "/frame_0001.png").rgba) << name;
    }
}

TEST_F(CliAnimate, BadInputIsRefusedNamingItAndWritesNothing) {
    const std::string cube = path("cube.obj");
    const std::string out = path("out");

    // A missing frame number.
    writeFrame(1, frame(1));
    writeFrame(2, frame(2));
    writeFrame(4, frame(4));
    expectRefused(cube + sequence(), out, "missing frame 3");
    EXPECT_FALSE(fs::exists(out));

    // A frame with another vertex count.
    writeFrame(3, frame(3));
    qp::Cage extra = frame(2);
    extra.positions.push_back({0, 5, 0});
    writeFrame(2, extra);
    expectRefused(cube + sequence(), out, "frame_0002.obj: the frame has 9 vertices");

    // NaN in a frame.
    writeFrame(2, frame(2));
    std::ofstream(path("seq/frame_0003.obj")) << "v 0 0 nan\nv 1 0 0\nv 1 1 0\n";
    expectRefused(cube + sequence(), out, "frame_0003.obj");

    // A first frame after the last.
    writeFrame(3, frame(3));
    expectRefused(cube + sequence() + " --frames 5:2", out, "--frames 5:2");
    expectRefused(cube + sequence() + " --frames x:2", out, "--frames must be A:B");

    // No animation at all.
    expectRefused(cube, out, "has no animation");

    // Not a sequence pattern.
    expectRefused(cube + " --sequence '" + path("seq/frame_0001.obj") + "'", out, "must have one '*'");
}

}  // namespace
