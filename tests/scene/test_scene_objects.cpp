// Scenes of many objects (scene format v2): round trips, version 1 compatibility, instance
// links, transforms, the errors that name the object, and plans shared through one database.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include <glm/gtc/matrix_transform.hpp>

#include "mesh/obj_io.h"
#include "scene/planned_scene.h"
#include "scene/scene.h"
#include "test_cages.h"
#include "test_support.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

class SceneObjects : public ::testing::Test {
protected:
    void SetUp() override {
        static std::atomic<int> counter{0};
        dir_ = fs::temp_directory_path() /
               ("quadplan-objects-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    std::vector<std::string> listDir() const { return qp::test::listDirectory(dir_); }
    fs::path dir_;
};

json inlineCage() {
    return json::parse(R"({"positions": [[0,0,0], [1,0,0], [1,1,0], [0,1,0]], "faces": [[0,1,2,3]],
                           "creases": [{"edge": [0,1], "sharpness": 2}]})");
}

// A box, an instance of it moved, turned and scaled, and a hidden grid.
json threeObjects() {
    json scene = {{"format", "quadplan-scene"}, {"version", 2}};
    scene["objects"] = json::array();
    scene["objects"].push_back({{"name", "box"}, {"cage", inlineCage()}});
    scene["objects"].push_back({{"name", "box.001"},
                                {"instance_of", "box"},
                                {"transform", {{"translation", {3, 0, 0}}, {"rotation_degrees", {0, 90, 0}}, {"scale", {2, 2, 2}}}}});
    scene["objects"].push_back({{"name", "grid"}, {"cage", inlineCage()}, {"visible", false}});
    return scene;
}

std::string errorOf(const json& scene) {
    qp::Result<qp::Scene> result = qp::parseScene(scene.dump(), "scene.json", ".");
    return result ? "" : result.error().message;
}

}  // namespace

TEST_F(SceneObjects, VersionTwoRoundTripKeepsObjectsInstancesAndTransforms) {
    qp::Result<qp::Scene> scene = qp::parseScene(threeObjects().dump(), "scene.json", ".");
    ASSERT_TRUE(scene) << scene.error().message;
    ASSERT_EQ(scene->objects.size(), 3u);
    EXPECT_EQ(scene->objects[1].instanceOf, "box");
    EXPECT_EQ(scene->objects[1].cage.faceCount(), 0u);
    EXPECT_EQ(scene->objects[1].transform.rotationDegrees, glm::vec3(0, 90, 0));
    EXPECT_FALSE(scene->objects[2].visible);
    EXPECT_EQ((*qp::cageOwners(scene->objects)), (std::vector<uint32_t>{0, 0, 2}));

    for (qp::CageStorage storage : {qp::CageStorage::Inline, qp::CageStorage::Referenced}) {
        ASSERT_TRUE(qp::saveScene(*scene, path("scene.json"), storage));
        qp::Result<qp::Scene> back = qp::loadScene(path("scene.json"));
        ASSERT_TRUE(back) << back.error().message;
        ASSERT_EQ(back->objects.size(), 3u);
        for (size_t i = 0; i < 3; ++i) {
            EXPECT_EQ(back->objects[i].name, scene->objects[i].name);
            EXPECT_EQ(back->objects[i].instanceOf, scene->objects[i].instanceOf);
            EXPECT_EQ(back->objects[i].transform, scene->objects[i].transform);
            EXPECT_EQ(back->objects[i].visible, scene->objects[i].visible);
            EXPECT_TRUE(qp::sameTopologyAndTags(back->objects[i].cage, scene->objects[i].cage));
        }
    }
    // Referenced: one OBJ per object with a cage of its own, none for the instance.
    EXPECT_EQ(listDir(), (std::vector<std::string>{"scene.json", "scene_box.obj", "scene_grid.obj"}));
}

TEST_F(SceneObjects, AsLoadedKeepsInlineCagesInlineAndReferencedOnesReferenced) {
    qp::Scene scene = *qp::parseScene(threeObjects().dump(), "scene.json", ".");
    scene.objects[2].cagePath = "grid.obj";
    ASSERT_TRUE(qp::saveScene(scene, path("mixed.json"), qp::CageStorage::AsLoaded));
    EXPECT_EQ(listDir(), (std::vector<std::string>{"grid.obj", "mixed.json"}));
    const json written = json::parse(std::ifstream(path("mixed.json")));
    EXPECT_TRUE(written["objects"][0]["cage"].contains("positions"));
    EXPECT_EQ(written["objects"][2]["cage"], json({{"path", "grid.obj"}}));
}

TEST_F(SceneObjects, VersionOneLoadsAsOneObjectAndSavesAsVersionTwo) {
    const std::string v1 = std::string(QUADPLAN_SCENES_DIR) + "/default.json";  // version 1, cage by path
    qp::Result<qp::Scene> scene = qp::loadScene(v1);
    ASSERT_TRUE(scene) << scene.error().message;
    ASSERT_EQ(scene->objects.size(), 1u);
    EXPECT_EQ(scene->objects[0].name, "default");  // after the OBJ it references
    EXPECT_EQ(scene->objects[0].cagePath, "default.obj");
    EXPECT_TRUE(scene->objects[0].transform.isIdentity());

    const json written = json::parse(qp::formatScene(*scene, qp::CageStorage::Inline));
    EXPECT_EQ(written["version"], 2);
    EXPECT_FALSE(written.contains("cage"));
    ASSERT_EQ(written["objects"].size(), 1u);
    qp::Result<qp::Scene> back = qp::parseScene(written.dump(), "again.json", ".");
    ASSERT_TRUE(back) << back.error().message;
    EXPECT_TRUE(qp::sameTopologyAndTags(back->objects[0].cage, scene->objects[0].cage));
    EXPECT_EQ(back->objects[0].cage.positions, scene->objects[0].cage.positions);

    // An inline version 1 cage is called "cage"; a bare OBJ after its file.
    json inlineV1 = {{"format", "quadplan-scene"}, {"version", 1}, {"cage", inlineCage()}};
    EXPECT_EQ(qp::parseScene(inlineV1.dump(), "s.json", ".")->objects[0].name, "cage");
    EXPECT_EQ(qp::loadSceneOrCage(std::string(QUADPLAN_SCENES_DIR) + "/default.obj")->objects[0].name, "default");
}

TEST_F(SceneObjects, BadObjectsAreRefusedNamingTheObject) {
    json scene = threeObjects();
    scene["objects"][2]["name"] = "box";
    EXPECT_EQ(errorOf(scene), "scene.json: objects[2].name: \"box\" is also the name of objects[0]; object names must be unique");

    scene = threeObjects();
    scene["objects"][1]["instance_of"] = "crate";
    EXPECT_EQ(errorOf(scene), "scene.json: objects: object \"box.001\" is an instance of \"crate\", which is not in the scene");

    scene = threeObjects();
    scene["objects"][0] = {{"name", "box"}, {"instance_of", "box.001"}};
    EXPECT_EQ(errorOf(scene), "scene.json: objects: object \"box\": its instance links go round in a cycle "
                              "(\"box\" -> \"box.001\" -> \"box\")");

    scene = threeObjects();
    scene["objects"][1]["transform"]["scale"] = {1, 0, 1};
    EXPECT_EQ(errorOf(scene), "scene.json: objects[1].transform.scale[1]: scale must not be zero");

    scene = threeObjects();
    scene["objects"][1]["cage"] = inlineCage();
    EXPECT_EQ(errorOf(scene), "scene.json: objects[1].cage: not allowed with \"instance_of\": an instance draws its "
                              "source's cage");

    scene = threeObjects();
    scene["objects"][0]["cage"] = {{"path", "missing.obj"}};
    EXPECT_NE(errorOf(scene).find("scene.json: objects[0].cage.path: cannot load the referenced cage \"missing.obj\""),
              std::string::npos)
        << errorOf(scene);

    scene = threeObjects();
    scene["objects"] = json::array();
    EXPECT_EQ(errorOf(scene), "scene.json: objects: must list at least one object");

    scene = threeObjects();
    scene["objects"][0]["cage"]["faces"][0][2] = 9;
    EXPECT_EQ(errorOf(scene), "scene.json: objects[0].cage.faces[0][2]: vertex index 9 out of range (cage has 4 vertices)");
}

TEST(SceneObjectChecks, ValidateCatchesWhatOnlyCodeCanMake) {
    qp::Scene scene = qp::sceneOfCage(qp::test::makeCube(), "cube");
    qp::SceneObject copy = scene.objects[0];
    scene.objects.push_back(copy);
    EXPECT_EQ(qp::validateObjects(scene.objects, "s").error().message,
              "s: two objects are called \"cube\"; names must be unique");
    scene.objects[1].name = qp::uniqueObjectName(scene.objects, "cube");
    EXPECT_EQ(scene.objects[1].name, "cube.001");
    EXPECT_EQ(qp::uniqueObjectName(scene.objects, "cube.001"), "cube.002");  // the number is replaced, not extended
    EXPECT_TRUE(qp::validateObjects(scene.objects, "s"));
    scene.objects[1].transform.translation.x = NAN;
    EXPECT_EQ(qp::validateObjects(scene.objects, "s").error().message,
              "s: object \"cube.001\": its transform has a non-finite value");
    scene.objects[1].transform = {};
    scene.objects[1].instanceOf = "cube";
    EXPECT_EQ(qp::validateObjects(scene.objects, "s").error().message,
              "s: object \"cube.001\": an instance draws its source's cage and cannot have one of its own");
    // saveScene checks the same and writes nothing.
    const std::string out = (fs::temp_directory_path() / ("quadplan-objects-refused-" + std::to_string(::getpid()) + ".json")).string();
    EXPECT_FALSE(qp::saveScene(scene, out, qp::CageStorage::Inline));
    EXPECT_FALSE(fs::exists(out));
}

TEST(SceneObjectChecks, TransformsComposeScaleRotationTranslationAndBoundsFollowThem) {
    qp::ObjectTransform t;
    t.translation = {10, 0, 0};
    t.rotationDegrees = {0, 0, 90};
    t.scale = {2, 1, 1};
    // (1, 0, 0) scaled to (2, 0, 0), turned about z to (0, 2, 0), moved to (10, 2, 0).
    const glm::vec4 p = t.matrix() * glm::vec4(1, 0, 0, 1);
    EXPECT_NEAR(p.x, 10.0f, 1e-5f);
    EXPECT_NEAR(p.y, 2.0f, 1e-5f);
    EXPECT_NEAR(p.z, 0.0f, 1e-5f);
    EXPECT_FLOAT_EQ(qp::maxScale(t), 2.0f);

    qp::Scene scene = qp::sceneOfCage(qp::test::makeCube(), "cube");  // the cube spans [-1, 1]^3
    qp::SceneObject moved;
    moved.name = "moved";
    moved.instanceOf = "cube";
    moved.transform.translation = {5, 0, 0};
    scene.objects.push_back(moved);
    const qp::Bounds cube = qp::computeBounds(scene.objects[0].cage);
    const qp::Bounds both = qp::sceneBounds(scene);
    EXPECT_FLOAT_EQ(both.min.x, cube.min.x);
    EXPECT_FLOAT_EQ(both.max.x, cube.max.x + 5.0f);
    scene.objects[0].visible = false;  // hidden objects are not framed
    EXPECT_FLOAT_EQ(qp::sceneBounds(scene).min.x, cube.min.x + 5.0f);
}

TEST(PlannedScenes, ObjectsWithTheSameConfigurationsShareOneDatabase) {
    qp::Scene scene = qp::sceneOfCage(qp::test::makeSubdividedCube(2), "a");
    qp::SceneObject b;
    b.name = "b";
    b.cage = qp::test::makeSubdividedCube(2);  // the same configurations, another cage
    b.transform.translation = {4, 0, 0};
    scene.objects.push_back(b);
    qp::SceneObject c;
    c.name = "c";
    c.instanceOf = "a";
    scene.objects.push_back(c);

    qp::PlanDatabase database;
    qp::Result<qp::PlannedScene> planned = qp::PlannedScene::create(scene, database, qp::PlanOptions{}, "scene");
    ASSERT_TRUE(planned) << planned.error().message;
    ASSERT_EQ(planned->cages.size(), 2u);  // the instance draws a's
    EXPECT_EQ(planned->cageOfObject, (std::vector<uint32_t>{0, 1, 0}));
    EXPECT_GT(planned->newPlansOfCage[0], 0u);
    EXPECT_EQ(planned->newPlansOfCage[1], 0u);  // b added no plans

    const qp::ScenePlanStats stats = qp::scenePlanStats(scene, *planned);
    EXPECT_EQ(stats.cages, 2u);
    EXPECT_EQ(stats.uniquePlans, database.stats().plans);
    EXPECT_EQ(stats.sharedPlans, stats.uniquePlans);  // every plan used by both cages
    EXPECT_EQ(stats.objects[1].newPlans, 0u);
    EXPECT_EQ(stats.objects[2].instanceOf, "a");
    EXPECT_EQ(stats.objects[2].plans, stats.objects[0].plans);
    EXPECT_EQ(stats.instanceFaces, 3u * scene.objects[0].cage.faceCount());
}

TEST(PlannedScenes, ABadCageNamesItsObject) {
    qp::Scene scene = qp::sceneOfCage(qp::test::makeCube(), "good");
    qp::SceneObject bad;
    bad.name = "broken";
    bad.instanceOf = "nowhere";
    scene.objects.push_back(bad);
    qp::PlanDatabase database;
    qp::Result<qp::PlannedScene> planned = qp::PlannedScene::create(scene, database, qp::PlanOptions{}, "scene.json");
    ASSERT_FALSE(planned);
    EXPECT_EQ(planned.error().message, "scene.json: object \"broken\" is an instance of \"nowhere\", which is not in the scene");
}

// Two objects that reference one OBJ (the same file opened twice): while their cages agree the
// file is written once; once one is edited it gets a file of its own, never the other's.
TEST_F(SceneObjects, ObjectsSharingAnObjFileNeverOverwriteEachOther) {
    ASSERT_TRUE(qp::saveObj(qp::test::makeCube(), path("box.obj")));
    const json source = {{"format", "quadplan-scene"}, {"version", 2},
                         {"objects", {{{"name", "a"}, {"cage", {{"path", "box.obj"}}}},
                                      {{"name", "b"}, {"cage", {{"path", "box.obj"}}}, {"transform", {{"translation", {3, 0, 0}}}}}}}};
    qp::Result<qp::Scene> scene = qp::parseScene(source.dump(), "s.json", dir_.string());
    ASSERT_TRUE(scene) << scene.error().message;
    ASSERT_TRUE(qp::saveScene(*scene, path("same.json"), qp::CageStorage::AsLoaded));
    EXPECT_EQ(listDir(), (std::vector<std::string>{"box.obj", "same.json"}));

    scene->objects[0].cage.positions[6].z += 1.0f;  // a is edited, b is not
    ASSERT_TRUE(qp::saveScene(*scene, path("edited.json"), qp::CageStorage::AsLoaded));
    qp::Result<qp::Scene> back = qp::loadScene(path("edited.json"));
    ASSERT_TRUE(back) << back.error().message;
    EXPECT_EQ(back->objects[0].cage.positions, scene->objects[0].cage.positions);
    EXPECT_EQ(back->objects[1].cage.positions, qp::test::makeCube().positions);
    EXPECT_EQ(back->objects[0].cagePath, "box.obj");
    EXPECT_EQ(back->objects[1].cagePath, "edited_b.obj");
}

TEST(DecomposeTransform, RoundTripsTranslationRotationAndScale) {
    using qp::ObjectTransform;
    const std::vector<ObjectTransform> cases = {
        {{1, 2, 3}, {10, 20, 30}, {1, 2, 3}},
        {{-4, 0, 1}, {-170, 45, 95}, {0.5f, 0.5f, 0.5f}},
        {{0, 0, 0}, {0, 90, 0}, {1, 1, 1}},    // gimbal lock
        {{0, 0, 0}, {30, -90, 10}, {2, 1, 1}},  // gimbal lock with x and z
        {{5, 5, 5}, {0, 0, 0}, {-1, 2, 3}},     // a mirror
    };
    for (const ObjectTransform& t : cases) {
        qp::Result<ObjectTransform> back = qp::decomposeTransform(t.matrix());
        ASSERT_TRUE(back) << back.error().message;
        const glm::mat4 a = t.matrix(), b = back->matrix();
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) EXPECT_NEAR(a[c][r], b[c][r], 1e-4f) << "column " << c << " row " << r;
    }
}

TEST(DecomposeTransform, RefusesShearFlatAndNonFinite) {
    using qp::decomposeTransform;
    using qp::ObjectTransform;
    ObjectTransform turned;
    turned.rotationDegrees = {0, 0, 45};
    // A non-uniform scale along world axes of a turned object shears it.
    const glm::mat4 sheared = glm::scale(glm::mat4(1.0f), glm::vec3(2, 1, 1)) * turned.matrix();
    EXPECT_FALSE(decomposeTransform(sheared));
    EXPECT_FALSE(decomposeTransform(glm::scale(glm::mat4(1.0f), glm::vec3(1, 0, 1))));
    glm::mat4 nan(1.0f);
    nan[3][0] = NAN;
    EXPECT_FALSE(decomposeTransform(nan));
}
