// Runs the real `quadplan` executable and checks what it prints and its exit status.
#include <array>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>

#include "test_support.h"

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
