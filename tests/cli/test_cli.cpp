// Runs the real `quadplan` executable and checks what it prints and its exit status.
#include <array>
#include <optional>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <vector>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include "cli_run.h"
#include "test_support.h"

#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#include <stb/stb_image.h>

namespace qp::test {

Png loadPng(const std::string& path) {
    Png png;
    int channels = 0;
    unsigned char* pixels = stbi_load(path.c_str(), &png.width, &png.height, &channels, 4);
    if (pixels) png.rgba.assign(pixels, pixels + size_t(png.width) * size_t(png.height) * 4);
    stbi_image_free(pixels);
    return png;
}

}  // namespace qp::test

namespace {

using qp::test::CommandRun;
using qp::test::loadPng;
using qp::test::Png;
using qp::test::runQuadplan;

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
    // Macro faces of each partition (issue 21): no more faces in them than the cage has.
    for (const char* key : {"faces_in_macro_faces", "faces_in_quartets", "faces_in_blocks"}) {
        ASSERT_TRUE(first.contains(key)) << key;
        EXPECT_LE(first[key].get<uint64_t>(), first["faces"].get<uint64_t>()) << key;
    }
    EXPECT_GT(first["faces_in_blocks"].get<uint64_t>(), 0u) << "the default scene has blocks of quads";
    EXPECT_LE(2 * first["macro_faces"].get<uint64_t>(), first["faces_in_macro_faces"].get<uint64_t>())
        << "a macro face holds at least two faces";
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

// A closed unit cube cage (eight valence-3 vertices) in a temporary OBJ: every scheme draws it,
// and the approximating ones are visibly off the limit next to its extraordinary vertices.
std::string tempCubeObj() {
    const std::string path =
        (std::filesystem::temp_directory_path() / ("qp-" + std::to_string(::getpid()) + "-cube.obj")).string();
    std::ofstream obj(path);
    obj << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
           "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    return path;
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

namespace {

// Fraction of a rectangle's pixels that differ from its top-left (background) pixel.
double coverage(const Png& png, int x0, int y0, int w, int h) {
    size_t covered = 0;
    for (int y = y0; y < y0 + h; ++y)
        for (int x = x0; x < x0 + w; ++x) covered += std::memcmp(png.at(x, y), png.at(x0, y0), 3) != 0;
    return double(covered) / double(w * h);
}

// Pixels of a rectangle that are clearly green (a heat colour of 1e-5 .. 1e-3), not the pale background.
size_t greenPixels(const Png& png, int x0, int y0, int w, int h) {
    size_t count = 0;
    for (int y = y0; y < y0 + h; ++y)
        for (int x = x0; x < x0 + w; ++x) {
            const uint8_t* p = png.at(x, y);
            count += p[1] > 120 && p[1] > p[0] + 40 && p[2] < 200;
        }
    return count;
}

constexpr int kTileW = 200, kTileH = 160, kLegendHeight = 78;  // kLegendHeight: editor/cmd_compare.cpp

}  // namespace

TEST(CliCompare, JsonTableAndOneTilePairPerScheme) {
    const std::string out = tempPng("compare");
    CommandRun run = runQuadplan(std::string("compare ") + QUADPLAN_SCENES_DIR +
                                 "/default.json --schemes plans,osd-fas,uniform --json --validate --size 200x160 --tess 4 "
                                 "--samples 8 --repeats 1 --out " + out);
    ASSERT_EQ(run.status, 0) << run.out;  // 4 would mean validation messages
    auto json = nlohmann::json::parse(run.out);
    ASSERT_EQ(json["schemes"].size(), 3u);
    EXPECT_TRUE(json["skipped"].empty());
    std::map<std::string, nlohmann::json> byName;
    for (const auto& s : json["schemes"]) {
        for (const char* key : {"name", "max_rel_error", "rms_rel_error", "max_normal_deg", "p99_normal_deg",
                                "normal_samples_excluded", "normal_samples_no_tangent_plane", "patches", "primitives", "path",
                                "single_crease_patches",
                                "triangles", "frame_ms"})
            EXPECT_TRUE(s.contains(key)) << key;
        EXPECT_LE(s["p99_normal_deg"].get<double>(), s["max_normal_deg"].get<double>());
        EXPECT_GT(s["triangles"].get<double>(), 0.0);
        EXPECT_GT(s["frame_ms"].get<double>(), 0.0);
        byName[s["name"]] = s;
    }
    // Measured against Far at depth 10 in double: the plans' float round-off remains.
    EXPECT_LT(byName["plans"]["max_rel_error"].get<double>(), 1e-6);
    EXPECT_EQ(json["reference"]["method"], "far-adaptive");
    EXPECT_EQ(json["reference"]["depth"], 10);
    EXPECT_LT(json["reference"]["error_bound"].get<double>(), 1e-7);
    EXPECT_EQ(byName["plans"]["patches"].get<int>(), 180);  // one primitive per sub-face
    EXPECT_LT(byName["osd-fas"]["max_rel_error"].get<double>(), 5e-5);
    EXPECT_GT(byName["osd-fas"]["patches"].get<int>(), 180);  // feature-adaptive: many patches near creases
    EXPECT_GT(byName["osd-fas"]["single_crease_patches"].get<int>(), 0);  // scenes/default has semi-sharp creases
    EXPECT_EQ(byName["plans"]["single_crease_patches"].get<int>(), 0);
    // osd-fas tessellates on the CPU: it submits triangles; uniform too.
    EXPECT_EQ(byName["osd-fas"]["path"], "cpu");
    EXPECT_EQ(byName["osd-fas"]["primitives"], byName["osd-fas"]["triangles"]);
    EXPECT_EQ(byName["uniform"]["path"], "cpu");
    // The exact schemes' normals: every sample compared but the two at the corners of the
    // two-face sector of the infinitely sharp corner (vertex 183), where the limit surface has no
    // tangent plane (core/plans/tangent_plane.h; the end patches' normals there were 3.6 degrees apart
    // at depth 6 and converge to nothing); everywhere else they agree closely.
    for (const char* exact : {"plans", "osd-fas"}) {
        SCOPED_TRACE(exact);
        EXPECT_EQ(byName[exact]["normal_samples_no_tangent_plane"].get<int>(), 2);
        EXPECT_EQ(byName[exact]["normal_samples_excluded"].get<int>(), 2);
        EXPECT_LT(byName[exact]["max_normal_deg"].get<double>(), 0.1);
    }
    EXPECT_LT(byName["plans"]["p99_normal_deg"].get<double>(), 0.1);
    EXPECT_GT(byName["uniform"]["max_rel_error"].get<double>(), 1e-4);
    EXPECT_EQ(byName["uniform"]["patches"].get<int>(), 0);

    // Three columns, each with the scheme's rendering over its heat map, then the legend.
    const Png png = loadPng(out);
    ASSERT_EQ(png.width, 3 * kTileW);
    const int label = png.height - kLegendHeight - 2 * kTileH;
    ASSERT_GT(label, 20);
    ASSERT_LT(label, 60);
    for (int column = 0; column < 3; ++column) {
        const int x = column * kTileW + 2;  // clear of the column separator
        EXPECT_GT(coverage(png, x, label, kTileW - 4, kTileH), 0.1) << "rendering of column " << column;
        EXPECT_GT(coverage(png, x, label + kTileH, kTileW - 4, kTileH), 0.1) << "heat map of column " << column;
    }
    // Order as requested: plans (exact: all dark blue), osd-fas (exact), uniform (visible error).
    EXPECT_EQ(greenPixels(png, 0, label + kTileH, kTileW, kTileH), 0u);
    EXPECT_EQ(greenPixels(png, kTileW, label + kTileH, kTileW, kTileH), 0u);
    EXPECT_GT(greenPixels(png, 2 * kTileW, label + kTileH, kTileW, kTileH), 500u);
    // The legend's colour bar runs from dark blue to red.
    const uint8_t* low = png.at(20, png.height - kLegendHeight + 16);
    const uint8_t* high = png.at(3 * kTileW - 20, png.height - kLegendHeight + 16);
    EXPECT_GT(low[2], low[0]);
    EXPECT_GT(high[0], high[2]);
    std::filesystem::remove(out);

    CommandRun table = runQuadplan(std::string("compare ") + QUADPLAN_SCENES_DIR +
                                   "/default.json --schemes osd-fas --size 100x100 --tess 2 --samples 4 --repeats 1 --out " + out);
    EXPECT_EQ(table.status, 0);
    EXPECT_NE(table.out.find("| scheme | max rel error | rms rel error | max normal (deg) | patches | triangles | frame ms"),
              std::string::npos)
        << table.out;
    EXPECT_NE(table.out.find("| osd-fas |"), std::string::npos);
    EXPECT_NE(table.out.find("reference: OpenSubdiv Far adaptive patches, depth 10, double precision"), std::string::npos);
    std::filesystem::remove(out);
}

TEST(CliCompare, UnknownAndRefusedSchemesAreReportedAndTheOthersDrawn) {
    const std::string out = tempPng("compare-partial");
    const std::string args = std::string("compare ") + QUADPLAN_SCENES_DIR +
                             "/default.json --schemes plans,acc9,uniform --option uniform:level=12 --json --size 100x100 "
                             "--tess 2 --samples 4 --repeats 1 --out " + out;
    CommandRun run = runQuadplan(args);
    EXPECT_EQ(run.status, 2);  // partial: some drawn, some not
    auto json = nlohmann::json::parse(run.out);
    ASSERT_EQ(json["schemes"].size(), 1u);
    EXPECT_EQ(json["schemes"][0]["name"], "plans");
    ASSERT_EQ(json["skipped"].size(), 2u);
    EXPECT_EQ(json["skipped"][0]["name"], "acc9");
    EXPECT_NE(json["skipped"][0]["reason"].get<std::string>().find("unknown scheme 'acc9'; available schemes:"), std::string::npos);
    EXPECT_NE(json["skipped"][1]["reason"].get<std::string>().find("level must be 1..8"), std::string::npos);
    EXPECT_TRUE(std::filesystem::exists(out));
    CommandRun messages = runQuadplan(args, true);
    EXPECT_NE(messages.out.find("error: unknown scheme 'acc9'"), std::string::npos) << messages.out;
    std::filesystem::remove(out);

    CommandRun none = runQuadplan(std::string("compare ") + QUADPLAN_SCENES_DIR + "/default.json --schemes acc9 --out " + out, true);
    EXPECT_EQ(none.status, 1);
    std::filesystem::remove(out);
}

TEST(CliCompare, BrokenPluginsWarnAndTheRestWorks) {
    // The test modules: a good one, one that throws in build, and several that cannot load.
    const std::string out = tempPng("compare-broken");
    setenv("QUADPLAN_PLUGIN_DIR", QUADPLAN_TEST_PLUGIN_DIR, 1);
    CommandRun run = runQuadplan(std::string("compare ") + QUADPLAN_SCENES_DIR +
                                 "/default.json --schemes test-flat,test-throws --size 100x100 --tess 2 --samples 4 "
                                 "--repeats 1 --out " + out, true);
    // --plugin-dir wins over the environment.
    CommandRun flag = runQuadplan(std::string("compare ") + QUADPLAN_SCENES_DIR + "/default.json --plugin-dir " +
                                  QUADPLAN_PLUGIN_DIR + " --schemes uniform --size 100x100 --tess 2 --samples 4 "
                                  "--repeats 1 --out " + out, true);
    unsetenv("QUADPLAN_PLUGIN_DIR");
    EXPECT_EQ(run.status, 2) << run.out;
    EXPECT_NE(run.out.find("warning: scheme plugin"), std::string::npos) << run.out;
    EXPECT_NE(run.out.find("interface version"), std::string::npos);
    EXPECT_NE(run.out.find("scheme 'test-throws' threw during build: deliberate failure in build"), std::string::npos);
    EXPECT_NE(run.out.find("| test-flat |"), std::string::npos) << run.out;
    EXPECT_EQ(flag.status, 0) << flag.out;
    EXPECT_EQ(flag.out.find("warning: scheme plugin"), std::string::npos) << flag.out;
    std::filesystem::remove(out);
}

TEST(CliRender, OtherSchemesDrawThroughTheirPlugins) {
    for (const char* scheme : {"osd-fas", "uniform", "plans --path cpu"}) {
        const std::string out = tempPng("scheme");
        CommandRun run = runQuadplan(std::string("render ") + QUADPLAN_SCENES_DIR + "/default.json --validate --size 240x180 "
                                     "--tess 4 --wire --scheme " + scheme + " --out " + out, true);
        ASSERT_EQ(run.status, 0) << scheme << "\n" << run.out;
        EXPECT_NE(run.out.find(std::string("scheme ") + std::string(scheme).substr(0, std::string(scheme).find(' '))),
                  std::string::npos)
            << run.out;
        int w = 0, h = 0;
        EXPECT_GT(pngCoverage(out, w, h), 0.15) << scheme;
        std::filesystem::remove(out);
    }
    CommandRun mode = runQuadplan(std::string("render ") + QUADPLAN_SCENES_DIR +
                                  "/default.json --scheme uniform --color-by depth --out /tmp/x.png", true);
    EXPECT_NE(mode.status, 0);
    EXPECT_NE(mode.out.find("unknown --color-by 'depth' for scheme uniform; use shading"), std::string::npos) << mode.out;
}

TEST(CliRender, ApproximatingSchemesDrawAndSayWhatTheyCannot) {
    const std::string cube = tempCubeObj();
    for (const char* scheme : {"acc1", "acc2", "pn", "stam", "acc2 --option path=cpu"}) {
        const std::string out = tempPng("approximating");
        CommandRun run = runQuadplan("render " + cube + " --validate --size 200x160 --tess 6 --scheme " + scheme + " --out " + out, true);
        ASSERT_EQ(run.status, 0) << scheme << "\n" << run.out;
        int w = 0, h = 0;
        EXPECT_GT(pngCoverage(out, w, h), 0.05) << scheme;
        std::filesystem::remove(out);
    }
    // Warnings name what is approximated; a refusal is an error, not an empty picture.
    const std::string out = tempPng("refused");
    CommandRun acc1 = runQuadplan(std::string("render ") + QUADPLAN_SCENES_DIR + "/default.json --size 100x100 --scheme acc1 --out " + out, true);
    EXPECT_EQ(acc1.status, 0) << acc1.out;
    EXPECT_NE(acc1.out.find("warning: acc1: acc1 draws semi-sharp creases smooth"), std::string::npos) << acc1.out;
    CommandRun stam = runQuadplan(std::string("render ") + QUADPLAN_SCENES_DIR + "/default.json --size 100x100 --scheme stam --out " + out, true);
    EXPECT_EQ(stam.status, 1) << stam.out;
    EXPECT_NE(stam.out.find("stam evaluates closed surfaces only"), std::string::npos) << stam.out;
    std::filesystem::remove(out);
    std::filesystem::remove(cube);
}

// Issue 5, item 4, on a cage every scheme draws: the exact schemes within 5e-5 of the limit,
// the approximating ones visibly off it, ACC-2's normals no worse than ACC-1's, PN the farthest.
TEST(CliCompare, ApproximatingSchemesAgreeWithTheLiteratureInKind) {
    const std::string cube = tempCubeObj(), out = tempPng("compare-approximating");
    CommandRun run = runQuadplan("compare " + cube + " --schemes plans,osd-fas,acc1,acc2,pn,stam,uniform --json --validate "
                                 "--size 120x100 --tess 4 --samples 8 --repeats 1 --out " + out);
    ASSERT_EQ(run.status, 0) << run.out;
    auto json = nlohmann::json::parse(run.out);
    ASSERT_EQ(json["schemes"].size(), 7u);
    std::map<std::string, nlohmann::json> by;
    for (const auto& s : json["schemes"]) by[s["name"]] = s;
    auto maxError = [&](const char* name) { return by[name]["max_rel_error"].get<double>(); };
    auto rmsError = [&](const char* name) { return by[name]["rms_rel_error"].get<double>(); };
    auto normal = [&](const char* name) { return by[name]["max_normal_deg"].get<double>(); };
    for (const char* exact : {"plans", "osd-fas", "stam"}) EXPECT_LT(maxError(exact), 5e-5) << exact;
    EXPECT_LT(normal("stam"), 0.01);
    for (const char* approximate : {"acc1", "acc2", "pn"}) EXPECT_GT(maxError(approximate), 1e-3) << approximate;
    EXPECT_LE(normal("acc2"), normal("acc1"));
    for (const char* other : {"plans", "osd-fas", "acc1", "acc2", "stam", "uniform"}) {
        EXPECT_GT(maxError("pn"), maxError(other)) << other;
        EXPECT_GT(rmsError("pn"), rmsError(other)) << other;
    }
    EXPECT_EQ(by["acc1"]["patches"].get<int>(), 6);  // one patch per quad
    EXPECT_EQ(by["acc2"]["patches"].get<int>(), 6);
    EXPECT_EQ(by["pn"]["patches"].get<int>(), 12);  // two triangles per quad
    std::filesystem::remove(out);
    std::filesystem::remove(cube);
}

TEST(CliSchemes, ListsPluginsAndWhatTheyDoWithACage) {
    CommandRun run = runQuadplan("schemes --json");
    ASSERT_EQ(run.status, 0);
    auto json = nlohmann::json::parse(run.out);
    EXPECT_EQ(json["schemes"].size(), 7u);  // plans, osd-fas, uniform, acc1, acc2, pn, stam
    EXPECT_TRUE(json["problems"].empty());
    CommandRun cage = runQuadplan(std::string("schemes ") + QUADPLAN_SCENES_DIR + "/default.json --json");
    ASSERT_EQ(cage.status, 0);
    const nlohmann::json listed = nlohmann::json::parse(cage.out);  // a loop over parse(...)["schemes"] would outlive it
    for (const auto& s : listed["schemes"]) {
        EXPECT_TRUE(s.contains("approximations")) << s;
        if (s["name"] == "stam") {  // the default scene has a boundary rim
            EXPECT_NE(s["refusals"].dump().find("stam evaluates closed surfaces only"), std::string::npos) << s;
        } else {
            EXPECT_TRUE(s["refusals"].empty()) << s;
        }
        if (s["name"] == "acc1" || s["name"] == "acc2" || s["name"] == "pn") {  // its creases are not drawn sharp
            EXPECT_NE(s["approximations"].dump().find("crease"), std::string::npos) << s;
        }
    }
    CommandRun broken = runQuadplan(std::string("schemes --plugin-dir ") + QUADPLAN_TEST_PLUGIN_DIR);
    EXPECT_EQ(broken.status, 0);  // the good test module loads
    EXPECT_NE(broken.out.find("not loaded:"), std::string::npos) << broken.out;
}
