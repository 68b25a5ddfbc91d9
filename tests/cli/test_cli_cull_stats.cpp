// Culling through the real executable (issue 20): `cull-stats` on a small closed torus keeps
// both promises (no culled sub-face owns a pixel of the unculled ID buffer, culled pictures equal
// unculled ones), its back-patch methods cull in order and pplane culls; osd-fas has its culled
// Far patches checked against an ID buffer of patches; on an open grid nothing
// is culled as facing away. `render --json` and `compare --json` report what a frame culled.
// Bad input gets a clear message.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include "cli_run.h"
#include "mesh/obj_io.h"
#include "scheme_test_support.h"
#include "test_cages.h"

namespace fs = std::filesystem;
using nlohmann::json;
using qp::test::runQuadplan;

namespace {

std::string temp(const std::string& name) {
    return (fs::temp_directory_path() / ("quadplan-cli-cull-" + std::to_string(::getpid()) + "-" + name)).string();
}

// A few small views: seconds on lavapipe.
constexpr const char* kSmall = "--views 4 --size 96x80 --tess 4 --repeats 1 --validate";

json cullStats(const std::string& cage, const std::string& extra = "") {
    const qp::test::CommandRun run = runQuadplan("cull-stats " + cage + " " + kSmall + " --json " + extra);
    EXPECT_EQ(run.status, 0) << run.out;
    return json::parse(run.out, nullptr, false);
}

std::string savedCage(const qp::Cage& cage, const std::string& name) {
    const std::string path = temp(name);
    EXPECT_TRUE(qp::saveObj(cage, path).ok());
    return path;
}

}  // namespace

TEST(CliCullStats, ClosedTorusKeepsThePromisesAndCullsInOrder) {
    const std::string torus = savedCage(qp::test::makeTorus(24, 12), "torus.obj");
    for (const std::string path : {"cpu", "tess"}) {
        const json out = cullStats(torus, "--path " + path);
        ASSERT_TRUE(out.is_object()) << path;
        EXPECT_EQ(out["views"], 4);
        EXPECT_EQ(out["patches"], 288) << "24 x 12 quads, one sub-face each";
        EXPECT_TRUE(out["closed"].get<bool>());
        EXPECT_EQ(out["id_parts"], "sub-faces") << "plans culls whole sub-faces";
        EXPECT_GT(out["visible_parts"].get<double>(), 0.0) << "the ID buffer shows the surface";
        EXPECT_EQ(out["visible_culled"], 0) << path;
        EXPECT_EQ(out["differing_pixels"], 0) << path;
        const json& m = out["methods"];
        for (const char* method : {"frustum", "tcone", "ncone", "pplane"}) {
            ASSERT_TRUE(m.contains(method)) << method;
            EXPECT_TRUE(m[method].contains("frame_ratio")) << method;
            EXPECT_GT(m[method]["frame_ratio"].get<double>(), 0.0) << method;
        }
        auto fraction = [&](const char* method) { return m[method]["culled_fraction"]["mean"].get<double>(); };
        EXPECT_LE(fraction("tcone"), fraction("ncone")) << path;
        EXPECT_LE(fraction("ncone"), fraction("pplane")) << path;
        EXPECT_GT(fraction("pplane"), 0.05) << path << ": a closed torus seen from outside faces away in part";
        EXPECT_GT(m["pplane"]["back_facing"].get<uint64_t>(), 0u);
        EXPECT_LT(m["pplane"]["triangles"].get<double>(), out["unculled"]["triangles"].get<double>());
    }
    fs::remove(torus);
}

// osd-fas culls Far patches, many inside a sub-face next to an extraordinary vertex: its ID
// buffer numbers them (Scheme::drawnPatches), so every culled patch is checked, on both paths.
TEST(CliCullStats, OsdFasHasEveryCulledPatchChecked) {
    const std::string cube = savedCage(qp::test::makeSubdividedCube(3), "cube.obj");
    for (const std::string path : {"cpu", "tess"}) {
        const json out = cullStats(cube, "--scheme osd-fas --path " + path);
        ASSERT_TRUE(out.is_object()) << path;
        EXPECT_EQ(out["id_parts"], "patches") << path;
        EXPECT_GT(out["visible_parts"].get<double>(), 54.0) << path << ": more patches than the cube's 54 faces show";
        EXPECT_GT(out["methods"]["pplane"]["culled_parts"].get<uint64_t>(), 0u) << path;
        EXPECT_EQ(out["visible_culled"], 0) << path;
        EXPECT_EQ(out["differing_pixels"], 0) << path;
    }
    fs::remove(cube);
}

TEST(CliCullStats, OpenGridCullsNothingAsFacingAway) {
    const std::string grid = savedCage(qp::test::makeGrid(4), "grid.obj");
    const json out = cullStats(grid);
    ASSERT_TRUE(out.is_object());
    EXPECT_FALSE(out["closed"].get<bool>());
    EXPECT_EQ(out["visible_culled"], 0);
    EXPECT_EQ(out["differing_pixels"], 0);
    for (const char* method : {"frustum", "tcone", "ncone", "pplane"})
        EXPECT_EQ(out["methods"][method]["back_facing"], 0) << method << ": back sides show on an open cage";
    fs::remove(grid);
}

TEST(CliCullStats, RenderAndCompareReportTheirCulling) {
    const std::string torus = savedCage(qp::test::makeTorus(24, 12), "torus-render.obj");
    const std::string png = temp("render.png");
    qp::test::CommandRun run = runQuadplan("render " + torus + " --out " + png + " --size 96x80 --tess 4 --cull pplane --json");
    ASSERT_EQ(run.status, 0) << run.out;
    const json render = json::parse(run.out, nullptr, false);
    ASSERT_TRUE(render.is_object()) << run.out;
    EXPECT_EQ(render["scheme"], "plans");
    EXPECT_EQ(render["cull"]["method"], "pplane");
    EXPECT_EQ(render["cull"]["tested"], 288);
    EXPECT_GT(render["cull"]["back_facing"].get<uint64_t>(), 0u);
    EXPECT_EQ(render["patches"].get<uint64_t>() + render["cull"]["frustum"].get<uint64_t>() +
                  render["cull"]["back_facing"].get<uint64_t>(),
              288u)
        << "the patches drawn leave the culled ones out";
    EXPECT_TRUE(render["cull"].contains("cull_ms"));

    run = runQuadplan("compare " + torus + " --schemes plans --out " + png +
                      " --size 96x80 --tess 4 --samples 2 --repeats 1 --cull pplane --json");
    ASSERT_EQ(run.status, 0) << run.out;
    const json compare = json::parse(run.out, nullptr, false);
    ASSERT_TRUE(compare.is_object()) << run.out;
    ASSERT_EQ(compare["schemes"].size(), 1u);
    EXPECT_EQ(compare["schemes"][0]["cull"]["method"], "pplane");
    EXPECT_GT(compare["schemes"][0]["cull"]["back_facing"].get<uint64_t>(), 0u);
    fs::remove(torus);
    fs::remove(png);
}

TEST(CliCullStats, BadInputIsRefusedClearly) {
    const std::string torus = savedCage(qp::test::makeTorus(), "torus-bad.obj");
    struct Case {
        std::string args, message;
    };
    const Case cases[] = {
        {"cull-stats " + temp("missing.obj"), "missing.obj"},
        {"cull-stats " + torus + " --size 10x10", "--size must be WIDTHxHEIGHT"},
        {"cull-stats " + torus + " --scheme nosuch", "unknown scheme 'nosuch'"},
        {"cull-stats", "give either a cage or scene file, or --generated-faces N"},
    };
    for (const Case& c : cases) {
        const qp::test::CommandRun run = runQuadplan(c.args, true);
        EXPECT_NE(run.status, 0) << c.args;
        EXPECT_NE(run.out.find(c.message), std::string::npos) << c.args << "\n" << run.out;
    }
    fs::remove(torus);
}
