// Runs the real `quadplan` executable and checks what it prints and its exit status.
#include <array>
#include <optional>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include "test_support.h"

#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>

namespace {

struct CommandRun {
    int status = -1;
    std::string out;  // stdout and stderr together
};

CommandRun runQuadplan(const std::string& args, bool mergeStderr = false) {
    std::string command = std::string(QUADPLAN_BINARY) + " " + args + (mergeStderr ? " 2>&1" : " 2>/dev/null");
    CommandRun run;
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return run;
    std::array<char, 4096> buffer;
    size_t n;
    while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) run.out.append(buffer.data(), n);
    int raw = pclose(pipe);
    run.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    return run;
}

std::string shape(const std::string& name) { return (qp::test::sharedShapesDir() / name).string(); }

}  // namespace

TEST(CliInfo, HelpListsSubcommands) {
    CommandRun run = runQuadplan("--help");
    EXPECT_EQ(run.status, 0);
    EXPECT_NE(run.out.find("info"), std::string::npos);
    EXPECT_NE(run.out.find("edit"), std::string::npos);
}

TEST(CliInfo, JsonOnCubeWithCreases) {
    QP_REQUIRE_SHARED_SHAPES();
    CommandRun run = runQuadplan("info --json " + shape("catmark_cube_creases1.obj"));
    ASSERT_EQ(run.status, 0);
    auto json = nlohmann::json::parse(run.out);
    EXPECT_EQ(json["vertices"], 8);
    EXPECT_EQ(json["faces"], 6);
    EXPECT_EQ(json["edges"], 12);
    EXPECT_EQ(json["boundary_edges"], 0);
    EXPECT_EQ(json["nonmanifold_edges"], 0);
    EXPECT_GT(json["creased_edges"].get<int>(), 0);
    EXPECT_EQ(json["holes"], 0);
    EXPECT_EQ(json["valences"]["3"], 8);
    EXPECT_EQ(json["face_sizes"]["4"], 6);
}

TEST(CliInfo, JsonCountsHolesCornersAndNonManifold) {
    QP_REQUIRE_SHARED_SHAPES();
    auto holes = nlohmann::json::parse(runQuadplan("info --json " + shape("catmark_hole_test1.obj")).out);
    EXPECT_GT(holes["holes"].get<int>(), 0);
    auto corners = nlohmann::json::parse(runQuadplan("info --json " + shape("catmark_cube_corner0.obj")).out);
    EXPECT_GT(corners["corner_vertices"].get<int>(), 0);
    auto nonmanifold = nlohmann::json::parse(runQuadplan("info --json " + shape("catmark_nonman_edges.obj")).out);
    EXPECT_GT(nonmanifold["nonmanifold_edges"].get<int>(), 0);
    auto bareVerts = nlohmann::json::parse(runQuadplan("info --json " + shape("catmark_nonman_verts.obj")).out);
    EXPECT_GT(bareVerts["nonmanifold_vertices"].get<int>(), 0);
}

TEST(CliInfo, TextOutputOnDefaultScene) {
    CommandRun run = runQuadplan(std::string("info ") + QUADPLAN_SCENES_DIR + "/default.json");
    EXPECT_EQ(run.status, 0);
    EXPECT_NE(run.out.find("faces"), std::string::npos);
    EXPECT_NE(run.out.find("creased edges"), std::string::npos);
}

TEST(CliInfo, BadInputExitsNonZeroWithMessageOnStderr) {
    CommandRun missing = runQuadplan("info /nonexistent/cage.obj", true);
    EXPECT_NE(missing.status, 0);
    EXPECT_NE(missing.out.find("/nonexistent/cage.obj"), std::string::npos);

    CommandRun quiet = runQuadplan("info /nonexistent/cage.obj");  // stderr dropped: nothing on stdout
    EXPECT_TRUE(quiet.out.empty());

    CommandRun wrongKind = runQuadplan("info " + qp::test::dataPath("README.md"), true);
    EXPECT_NE(wrongKind.status, 0);
}

TEST(CliPlans, CheckLimitJsonOnDefaultScene) {
    CommandRun run = runQuadplan(std::string("check-limit --json ") + QUADPLAN_SCENES_DIR + "/default.json");
    ASSERT_EQ(run.status, 0) << run.out;
    auto json = nlohmann::json::parse(run.out);
    for (const char* key : {"faces", "samples", "max_rel_error_position", "max_rel_error_derivative", "pass"})
        EXPECT_TRUE(json.contains(key)) << key;
    EXPECT_TRUE(json["pass"].get<bool>());
    EXPECT_LE(json["max_rel_error_position"].get<double>(), 5e-5);
    EXPECT_EQ(json["samples"].get<int>() % 81, 0);
}

TEST(CliPlans, CheckLimitFailsOnBadInput) {
    CommandRun run = runQuadplan("check-limit /nonexistent.obj", true);
    EXPECT_NE(run.status, 0);
    EXPECT_NE(run.out.find("/nonexistent.obj"), std::string::npos);
    EXPECT_NE(runQuadplan(std::string("check-limit --depth 0 ") + QUADPLAN_SCENES_DIR + "/default.json").status, 0);
}

TEST(CliPlans, PlanStatsJsonAndPersistentDatabase) {
    std::string db = (std::filesystem::temp_directory_path() / ("qp-cli-" + std::to_string(::getpid()) + ".db")).string();
    std::filesystem::remove(db);
    std::string cmd = std::string("plan-stats --json --plan-db ") + db + " " + QUADPLAN_SCENES_DIR + "/default.json";

    auto first = nlohmann::json::parse(runQuadplan(cmd).out);
    for (const char* key : {"faces", "subfaces", "unique_plans", "nodes", "stencils", "bytes", "build_ms"})
        EXPECT_TRUE(first.contains(key)) << key;
    EXPECT_GT(first["database_misses"].get<int>(), 0);
    EXPECT_TRUE(std::filesystem::exists(db));

    auto second = nlohmann::json::parse(runQuadplan(cmd).out);
    EXPECT_EQ(second["database_misses"].get<int>(), 0);  // every plan came from the file
    EXPECT_EQ(second["unique_plans"], first["unique_plans"]);

    std::ofstream(db, std::ios::trunc) << "damaged";
    CommandRun damaged = runQuadplan(cmd, true);
    EXPECT_EQ(damaged.status, 0);
    EXPECT_NE(damaged.out.find("plans will be rebuilt"), std::string::npos);
    std::filesystem::remove(db);
}

namespace {

// Fraction of pixels that differ from the top-left (background) pixel of a PNG.
double pngCoverage(const std::string& path, int& width, int& height) {
    int channels = 0;
    unsigned char* pixels = stbi_load(path.c_str(), &width, &height, &channels, 4);
    if (!pixels) return -1.0;
    size_t covered = 0;
    for (int i = 0; i < width * height; ++i) covered += std::memcmp(pixels + 4 * i, pixels, 3) != 0;
    stbi_image_free(pixels);
    return double(covered) / double(width * height);
}

std::string tempPng(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("qp-" + std::to_string(::getpid()) + "-" + name + ".png")).string();
}

}  // namespace

// Sets an environment variable for the commands a test runs, and restores it afterwards.
struct ScopedEnv {
    std::string name;
    std::optional<std::string> saved;
    ScopedEnv(std::string n, const char* value) : name(std::move(n)) {
        if (const char* old = std::getenv(name.c_str())) saved = old;
        if (value) setenv(name.c_str(), value, 1);
        else unsetenv(name.c_str());
    }
    ~ScopedEnv() {
        if (saved) setenv(name.c_str(), saved->c_str(), 1);
        else unsetenv(name.c_str());
    }
};

TEST(CliRender, DefaultSceneHeadlessWithSilentValidation) {
    std::string out = tempPng("default");
    ScopedEnv noDisplay("DISPLAY", nullptr);
    CommandRun run = runQuadplan(std::string("render ") + QUADPLAN_SCENES_DIR + "/default.json --validate --size 320x240 --out " + out, true);
    ASSERT_EQ(run.status, 0) << run.out;
    EXPECT_EQ(run.out.find("validation:"), std::string::npos) << run.out;
    int w = 0, h = 0;
    double coverage = pngCoverage(out, w, h);
    EXPECT_EQ(w, 320);
    EXPECT_EQ(h, 240);
    EXPECT_GT(coverage, 0.15);  // the surface fills a good part of the framed view
    EXPECT_LT(coverage, 0.95);
    std::filesystem::remove(out);
}

TEST(CliRender, BothPathsColourModesAndCamera) {
    std::string scene = std::string(QUADPLAN_SCENES_DIR) + "/creased_box.json";
    for (std::string options : {"--path tess --tess 4 --wire", "--path grid --tess 6 --color-by depth",
                                "--path tess --adaptive 5 --color-by node-kind --no-cage",
                                "--camera 4,3,5,0,0,0,35 --color-by sharpness", "--path cpu --tess 5 --wire",
                                "--path grid --adaptive 6 --wire", "--path cpu --adaptive 4 --color-by depth"}) {
        std::string out = tempPng("box");
        CommandRun run = runQuadplan("render " + scene + " --validate --size 200x200 " + options + " --out " + out, true);
        ASSERT_EQ(run.status, 0) << options << "\n" << run.out;
        int w = 0, h = 0;
        EXPECT_GT(pngCoverage(out, w, h), 0.05) << options;
        std::filesystem::remove(out);
    }
}

TEST(CliRender, BadRequestsFailWithAMessage) {
    std::string scene = std::string(QUADPLAN_SCENES_DIR) + "/default.json";
    struct Case {
        std::string options, expected;
    };
    for (const Case& c : {Case{"--scheme acc9 --out /tmp/x.png", "unknown scheme"},
                          Case{"--tess 4 --adaptive 3 --out /tmp/x.png", "either --tess or --adaptive"},
                          Case{"--camera 1,2,3 --out /tmp/x.png", "--camera"},
                          Case{"--size 12x9000 --out /tmp/x.png", "--size"},
                          Case{"--color-by rainbow --out /tmp/x.png", "--color-by"},
                          Case{"--size 800 --out /tmp/x.png", "--size"},
                          Case{"--path warp --out /tmp/x.png", "--path"},
                          Case{"--tess 0 --out /tmp/x.png", "--tess"},
                          Case{"--out /nonexistent-dir/x.png", "/nonexistent-dir/x.png"}}) {
        CommandRun run = runQuadplan("render " + scene + " " + c.options, true);
        EXPECT_NE(run.status, 0) << c.options;
        EXPECT_NE(run.out.find(c.expected), std::string::npos) << c.options << "\n" << run.out;
    }
    CommandRun missing = runQuadplan("render /nonexistent/cage.obj --out /tmp/x.png", true);
    EXPECT_NE(missing.status, 0);
    EXPECT_NE(missing.out.find("/nonexistent/cage.obj"), std::string::npos);
    // A device that is not there: the message names what was asked for, and nothing is written.
    const std::string out = tempPng("nodevice");
    ScopedEnv device("QUADPLAN_VK_DEVICE", "nonexistent");
    CommandRun noDevice = runQuadplan("render " + scene + " --out " + out, true);
    EXPECT_NE(noDevice.status, 0);
    EXPECT_NE(noDevice.out.find("nonexistent"), std::string::npos) << noDevice.out;
    EXPECT_FALSE(std::filesystem::exists(out));
}
