// The command line on scenes of many objects: render draws every visible object under its
// transform (the same picture as the transformed cages written out), plan-stats reports per
// object and for the scene, check-limit and compare measure every cage, sculpt --object.
#include <cmath>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include "cli_run.h"
#include "scene/scene.h"
#include "test_cages.h"

namespace fs = std::filesystem;
using nlohmann::json;
using qp::test::runQuadplan;

namespace {

std::string temp(const std::string& name) {
    return (fs::temp_directory_path() / ("quadplan-cli-objects-" + std::to_string(::getpid()) + "-" + name)).string();
}

const std::string kObjects = std::string(QUADPLAN_SCENES_DIR) + "/objects.json";
constexpr const char* kCamera = "--camera 0,3,10,0,0,0,40 --size 240x160 --tess 4";

// A cube, an instance of it turned and scaled (uniformly or not) and moved, and a second cube of
// its own.
qp::Scene cubes(bool uniformScale = false) {
    qp::Scene scene = qp::sceneOfCage(qp::test::makeSubdividedCube(2), "cube");
    qp::SceneObject instance;
    instance.name = "turned";
    instance.instanceOf = "cube";
    instance.transform = {{2.5f, 0.5f, 0.0f}, {10.0f, 35.0f, 0.0f}, uniformScale ? glm::vec3(0.8f) : glm::vec3(0.7f, 0.7f, 1.2f)};
    scene.objects.push_back(instance);
    qp::SceneObject other;
    other.name = "other";
    other.cage = qp::test::makeSubdividedCube(2);
    other.transform.translation = {-2.5f, 0.0f, 0.0f};
    scene.objects.push_back(other);
    return scene;
}

// The same surfaces with every transform applied to the positions: what the objects must look like.
qp::Scene flattened(const qp::Scene& scene) {
    qp::Scene out = scene;
    for (qp::SceneObject& o : out.objects) {
        if (o.isInstance()) {
            o.cage = scene.objects[qp::findObject(scene.objects, o.instanceOf)].cage;
            o.instanceOf.clear();
        }
        const glm::mat4 m = o.transform.matrix();
        for (glm::vec3& p : o.cage.positions) p = glm::vec3(m * glm::vec4(p, 1.0f));
        o.transform = {};
    }
    return out;
}

}  // namespace

TEST(CliObjects, RenderDrawsEveryObjectUnderItsTransform) {
    const std::string placed = temp("placed.json"), baked = temp("baked.json");
    for (bool uniformScale : {true, false})
    for (const std::string scheme : {"plans", "osd-fas"}) {
        const qp::Scene scene = cubes(uniformScale);
        ASSERT_TRUE(qp::saveScene(scene, placed, qp::CageStorage::Inline));
        ASSERT_TRUE(qp::saveScene(flattened(scene), baked, qp::CageStorage::Inline));
        const std::string a = temp("placed-" + scheme + ".png"), b = temp("baked-" + scheme + ".png");
        qp::test::CommandRun run =
            runQuadplan("render " + placed + " --validate --no-cage --scheme " + scheme + " " + kCamera + " --out " + a, true);
        ASSERT_EQ(run.status, 0) << run.out;
        EXPECT_NE(run.out.find("3 objects, 2 cages"), std::string::npos) << run.out;
        ASSERT_EQ(runQuadplan("render " + baked + " --no-cage --scheme " + scheme + " " + kCamera + " --out " + b).status, 0);
        const qp::test::Png pa = qp::test::loadPng(a), pb = qp::test::loadPng(b);
        ASSERT_EQ(pa.width, 240);
        ASSERT_EQ(pb.width, 240);
        // The same surfaces through another matrix: the silhouettes agree up to rounding along
        // their edges, and so does the shading of plans, whose lights stay fixed in the world,
        // under rotations and uniform scales (osd-fas's meshes keep their fill light in the
        // object's frame, and a non-uniform scale bends normals the lights do not follow:
        // docs/renderer.md).
        size_t covered = 0, differing = 0, shadedDifferently = 0;
        for (int y = 0; y < pa.height; ++y)
            for (int x = 0; x < pa.width; ++x) {
                const bool inA = std::memcmp(pa.at(x, y), pa.at(0, 0), 3) != 0;
                const bool inB = std::memcmp(pb.at(x, y), pb.at(0, 0), 3) != 0;
                covered += inA;
                differing += inA != inB;
                int diff = 0;
                for (int c = 0; c < 3; ++c) diff = std::max(diff, std::abs(int(pa.at(x, y)[c]) - int(pb.at(x, y)[c])));
                shadedDifferently += inA && inB && diff > 12;
            }
        EXPECT_GT(covered, size_t(240 * 160 / 10)) << scheme << ": three cubes should cover a tenth of the image";
        EXPECT_LT(differing, covered / 100) << scheme << ": " << differing << " of " << covered << " pixels differ";
        if (scheme == "plans" && uniformScale) {
            EXPECT_LT(shadedDifferently, covered / 100) << shadedDifferently << " of " << covered << " pixels shaded differently";
        }
        fs::remove(a);
        fs::remove(b);
    }

    // Hiding every object leaves the background only.
    qp::Scene hidden = cubes();
    for (qp::SceneObject& o : hidden.objects) o.visible = false;
    ASSERT_TRUE(qp::saveScene(hidden, placed, qp::CageStorage::Inline));
    const std::string empty = temp("empty.png");
    ASSERT_EQ(runQuadplan("render " + placed + " " + kCamera + " --out " + empty).status, 0);
    const qp::test::Png pe = qp::test::loadPng(empty);
    for (int y = 0; y < pe.height; ++y)
        for (int x = 0; x < pe.width; ++x) ASSERT_EQ(std::memcmp(pe.at(x, y), pe.at(0, 0), 3), 0) << x << "," << y;
    for (const std::string& f : {placed, baked, empty}) fs::remove(f);
}

// Instances of one cage at different distances under screen-adaptive factors: on the grid paths
// they share the layout their nearest needs (DrawView::sameFrame); every pixel drawn must lie
// within a few pixels of the same surfaces written out as separate cages (a draw that read
// another instance's grid would put triangles far from any of them).
TEST(CliObjects, AdaptiveInstancesShareOneLayoutAndDrawTheirOwnSurface) {
    qp::Scene scene = qp::sceneOfCage(qp::test::makeCube(), "near");
    qp::SceneObject far;
    far.name = "far";
    far.instanceOf = "near";
    far.transform.translation = {3.0f, 0.0f, -12.0f};
    scene.objects.push_back(far);
    const std::string placed = temp("adaptive-placed.json"), baked = temp("adaptive-baked.json");
    ASSERT_TRUE(qp::saveScene(scene, placed, qp::CageStorage::Inline));
    ASSERT_TRUE(qp::saveScene(flattened(scene), baked, qp::CageStorage::Inline));
    const std::string view = "--camera 0,1,5,1,0,-4,50 --size 200x150 --no-cage --adaptive 30";
    auto covered = [](const qp::test::Png& png, int x, int y) { return std::memcmp(png.at(x, y), png.at(0, 0), 3) != 0; };
    auto near = [&](const qp::test::Png& png, int x, int y) {
        for (int dy = -3; dy <= 3; ++dy)
            for (int dx = -3; dx <= 3; ++dx) {
                const int u = x + dx, v = y + dy;
                if (u >= 0 && v >= 0 && u < png.width && v < png.height && covered(png, u, v)) return true;
            }
        return false;
    };
    for (const std::string path : {"cpu", "grid", "tess"}) {
        const std::string a = temp("adaptive-placed-" + path + ".png"), b = temp("adaptive-baked-" + path + ".png");
        ASSERT_EQ(runQuadplan("render " + placed + " --validate --path " + path + " " + view + " --out " + a).status, 0);
        ASSERT_EQ(runQuadplan("render " + baked + " --path " + path + " " + view + " --out " + b).status, 0);
        const qp::test::Png pa = qp::test::loadPng(a), pb = qp::test::loadPng(b);
        ASSERT_EQ(pa.width, 200);
        size_t stray = 0, missing = 0, drawn = 0;
        for (int y = 0; y < pa.height; ++y)
            for (int x = 0; x < pa.width; ++x) {
                drawn += covered(pa, x, y);
                stray += covered(pa, x, y) && !near(pb, x, y);
                missing += covered(pb, x, y) && !near(pa, x, y);
            }
        EXPECT_GT(drawn, 2000u) << path;
        EXPECT_EQ(stray, 0u) << path << ": pixels drawn away from every surface";
        EXPECT_EQ(missing, 0u) << path << ": surface pixels left undrawn";
        fs::remove(a);
        fs::remove(b);
    }
    fs::remove(placed);
    fs::remove(baked);
}

TEST(CliObjects, PlanStatsReportsObjectsAndSharedPlans) {
    const std::string path = temp("stats.json");
    ASSERT_TRUE(qp::saveScene(cubes(), path, qp::CageStorage::Inline));
    qp::test::CommandRun run = runQuadplan("plan-stats --json " + path);
    ASSERT_EQ(run.status, 0) << run.out;
    const json stats = json::parse(run.out);
    ASSERT_EQ(stats["objects"].size(), 3u);
    EXPECT_EQ(stats["cages"], 2);
    EXPECT_EQ(stats["objects"][1]["instance_of"], "cube");
    EXPECT_EQ(stats["objects"][1]["new_plans"], 0);
    EXPECT_EQ(stats["objects"][2]["new_plans"], 0);  // the other cube has the same configurations
    EXPECT_GT(stats["objects"][0]["new_plans"].get<int>(), 0);
    EXPECT_EQ(stats["unique_plans"], stats["objects"][0]["new_plans"]);
    EXPECT_EQ(stats["shared_plans"], stats["unique_plans"]);
    EXPECT_EQ(stats["instance_faces"], 3 * stats["objects"][0]["faces"].get<int>());
    fs::remove(path);
}

TEST(CliObjects, CheckLimitAndCompareMeasureEveryCage) {
    qp::test::CommandRun check = runQuadplan("check-limit --json " + kObjects);
    ASSERT_EQ(check.status, 0) << check.out;
    const json limit = json::parse(check.out);
    EXPECT_EQ(limit["cages"].size(), 2u);  // default (and its instance) and the creased box
    EXPECT_TRUE(limit["pass"]);

    const std::string out = temp("compare.png");
    qp::test::CommandRun run =
        runQuadplan("compare " + kObjects + " --json --schemes plans,osd-fas --size 200x160 --samples 4 --repeats 1 --out " + out);
    ASSERT_EQ(run.status, 0) << run.out;
    const json compare = json::parse(run.out);
    for (const json& scheme : compare["schemes"]) {
        EXPECT_LT(scheme["max_rel_error"].get<double>(), 1e-5) << scheme["name"];
        // Two cages' sample grids, each once: instances share their source's.
        EXPECT_EQ(scheme["samples"], compare["schemes"][0]["samples"]);
    }
    fs::remove(out);
}

TEST(CliObjects, SculptTakesTheObjectByName) {
    const std::string out = temp("sculpted.json");
    qp::test::CommandRun run =
        runQuadplan("sculpt " + kObjects + " --object creased_box --radius 0.8 --strength 0.1 --path \"0,1,0\" --out " + out, true);
    ASSERT_EQ(run.status, 0) << run.out;
    qp::Result<qp::Scene> scene = qp::loadScene(out);
    ASSERT_TRUE(scene) << scene.error().message;
    EXPECT_TRUE(scene->objects[0].displacement.empty());
    EXPECT_FALSE(scene->objects[2].displacement.empty());

    run = runQuadplan("sculpt " + kObjects + " --object default.001 --radius 0.8 --strength 0.1 --path \"0,1,0\" --out " + out, true);
    EXPECT_NE(run.status, 0);
    EXPECT_NE(run.out.find("\"default.001\" is an instance of \"default\""), std::string::npos) << run.out;
    run = runQuadplan("sculpt " + kObjects + " --object nobody --radius 0.8 --strength 0.1 --path \"0,1,0\" --out " + out, true);
    EXPECT_NE(run.out.find("no object is called \"nobody\" (the scene has default, default.001, creased_box)"),
              std::string::npos)
        << run.out;
    fs::remove(out);
}
