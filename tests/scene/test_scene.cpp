#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "mesh/obj_io.h"
#include "scene/scene.h"
#include "test_support.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string scenesPath(const std::string& name) { return std::string(QUADPLAN_SCENES_DIR) + "/" + name; }

// A fresh directory per test, removed afterwards.
class SceneFiles : public ::testing::Test {
protected:
    void SetUp() override {
        static std::atomic<int> counter{0};
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() / ("quadplan-scene-" + std::to_string(::getpid()) + "-" +
                                            std::to_string(counter++) + "-" + info->name());
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    std::string path(const std::string& name) const { return (dir_ / name).string(); }

    std::string write(const std::string& name, const std::string& text) const {
        std::ofstream(path(name)) << text;
        return path(name);
    }

    std::vector<std::string> listDir() const { return qp::test::listDirectory(dir_); }

    fs::path dir_;
};

// Two quads sharing the edge 1-4, with every optional section present.
json validScene() {
    return json::parse(R"({
      "format": "quadplan-scene",
      "version": 1,
      "cage": {
        "positions": [[0,0,0], [1,0,0], [2,0,0], [0,1,0], [1,1,0], [2,1,0]],
        "faces": [[0,1,4,3], [1,2,5,4]],
        "creases": [{"edge": [1,4], "sharpness": 2.5}],
        "corners": [{"vertex": 0, "sharpness": 10}],
        "holes": [],
        "options": {"boundary": "edges-only", "crease_method": "chaikin"}
      },
      "camera": {"eye": [1,0.5,4], "target": [1,0.5,0], "up": [0,1,0], "fov_y_degrees": 40},
      "viewports": [{"scheme": "plans"}],
      "tessellation": {"mode": "uniform", "factor": 4},
      "displacement": {"version": 0, "faces": []}
    })");
}

// Parses `scene` as "scene.json" and returns its error message ("" when it parsed).
std::string errorOf(const json& scene, const std::string& baseDir = ".") {
    qp::Result<qp::Scene> result = qp::parseScene(scene.dump(), "scene.json", baseDir);
    return result ? "" : result.error().message;
}

void expectSameScene(const qp::Scene& a, const qp::Scene& b) {
    EXPECT_TRUE(qp::sameTopologyAndTags(a.objects[0].cage, b.objects[0].cage));
    EXPECT_EQ(a.objects[0].cage.positions, b.objects[0].cage.positions);
    EXPECT_EQ(a.objects[0].cage.uvs, b.objects[0].cage.uvs);
    EXPECT_EQ(a.camera, b.camera);
    EXPECT_EQ(a.viewports, b.viewports);
    EXPECT_EQ(a.tessellation, b.tessellation);
    EXPECT_EQ(a.display, b.display);
    EXPECT_EQ(a.objects[0].displacement, b.objects[0].displacement);
}

}  // namespace

// --- round trips ---

TEST_F(SceneFiles, SceneRoundTripInline) {
    json source = validScene();
    source["cage"]["uvs"] = {{0, 0}, {0.5, 0}, {1, 0}, {0, 1}, {0.5, 1}, {1, 1}};
    source["cage"]["face_uvs"] = {{0, 1, 4, 3}, {1, 2, 5, 4}};
    source["camera"]["projection"] = "orthographic";
    source["camera"]["ortho_height"] = 3.3;
    source["viewports"].push_back({{"scheme", "someone-elses-plugin"}, {"camera", "independent"}, {"color_by", "x"}});
    source["tessellation"]["pixels_per_edge"] = 0.1;
    source["display"] = {{"shading", "matcap"}, {"show_grid", false}, {"dense_cage_lines", true}};
    qp::Result<qp::Scene> original = qp::parseScene(source.dump(), "source.json", "");
    ASSERT_TRUE(original) << original.error().message;
    EXPECT_TRUE(original->display.denseCageLines);

    ASSERT_TRUE(qp::saveScene(*original, path("scene.json"), qp::CageStorage::Inline));
    qp::Result<qp::Scene> reloaded = qp::loadScene(path("scene.json"));
    ASSERT_TRUE(reloaded) << reloaded.error().message;
    expectSameScene(*original, *reloaded);
    EXPECT_TRUE(reloaded->objects[0].cagePath.empty());
    EXPECT_EQ(qp::formatScene(*reloaded, qp::CageStorage::Inline), qp::formatScene(*original, qp::CageStorage::Inline));
}

TEST_F(SceneFiles, SceneRoundTripByPath) {
    qp::Result<qp::Scene> original = qp::loadScene(scenesPath("default.json"));
    ASSERT_TRUE(original) << original.error().message;
    EXPECT_EQ(original->objects[0].cagePath, "default.obj");

    ASSERT_TRUE(qp::saveScene(*original, path("copy.json"), qp::CageStorage::Referenced));
    EXPECT_EQ(listDir(), (std::vector<std::string>{"copy.json", "default.obj"}));
    qp::Result<qp::Scene> reloaded = qp::loadScene(path("copy.json"));
    ASSERT_TRUE(reloaded) << reloaded.error().message;
    expectSameScene(*original, *reloaded);
    EXPECT_EQ(reloaded->objects[0].cagePath, "default.obj");
}

TEST_F(SceneFiles, SceneSaveByPathWithoutCagePathNamesTheObjAfterTheScene) {
    qp::Result<qp::Scene> scene = qp::parseScene(validScene().dump(), "scene.json", "");
    ASSERT_TRUE(scene) << scene.error().message;
    ASSERT_TRUE(qp::saveScene(*scene, path("tub.json"), qp::CageStorage::Referenced));
    EXPECT_EQ(listDir(), (std::vector<std::string>{"tub.json", "tub.obj"}));
    qp::Result<qp::Scene> reloaded = qp::loadScene(path("tub.json"));
    ASSERT_TRUE(reloaded) << reloaded.error().message;
    EXPECT_EQ(reloaded->objects[0].cagePath, "tub.obj");
    expectSameScene(*scene, *reloaded);
}

// --- bundled scenes ---

TEST(SceneBundled, DefaultSceneShowsOffTheProduct) {
    std::vector<std::string> warnings;
    qp::Result<qp::Scene> scene = qp::loadScene(scenesPath("default.json"), &warnings);
    ASSERT_TRUE(scene) << scene.error().message;
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    const qp::Cage& cage = scene->objects[0].cage;
    EXPECT_GE(cage.faceCount(), 100u);
    EXPECT_LE(cage.faceCount(), 300u);
    EXPECT_TRUE(std::any_of(cage.creases.begin(), cage.creases.end(),
                            [](const qp::EdgeCrease& c) { return c.sharpness != std::floor(c.sharpness); }));
    EXPECT_FALSE(cage.corners.empty());
    EXPECT_EQ(cage.options.boundary, qp::BoundaryInterpolation::EdgesAndCorners);
    EXPECT_TRUE(scene->camera.has_value());
}

TEST(SceneBundled, CreasedBoxLoads) {
    std::vector<std::string> warnings;
    qp::Result<qp::Scene> scene = qp::loadSceneOrCage(scenesPath("creased_box.json"), &warnings);
    ASSERT_TRUE(scene) << scene.error().message;
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    EXPECT_TRUE(scene->objects[0].cagePath.empty());
    EXPECT_EQ(scene->objects[0].cage.faceCount(), 6u);
    EXPECT_EQ(scene->objects[0].cage.options.creaseMethod, qp::CreaseMethod::Chaikin);
    EXPECT_FLOAT_EQ(scene->objects[0].cage.edgeSharpness(5, 1), 3.25f);
    EXPECT_FALSE(scene->camera.has_value());  // framed automatically
    EXPECT_EQ(scene->viewports.size(), 2u);
    EXPECT_TRUE(scene->objects[0].displacement.empty());
}

// --- defaults and warnings ---

TEST(SceneParse, OptionalSectionsTakeDefaults) {
    json minimal = validScene();
    for (const char* key : {"camera", "viewports", "tessellation", "displacement"}) minimal.erase(key);
    qp::Result<qp::Scene> scene = qp::parseScene(minimal.dump(), "scene.json", "");
    ASSERT_TRUE(scene) << scene.error().message;
    EXPECT_FALSE(scene->camera.has_value());
    ASSERT_EQ(scene->viewports.size(), 1u);
    EXPECT_EQ(scene->viewports[0].scheme, "plans");
    EXPECT_EQ(scene->tessellation, qp::Tessellation{});
    EXPECT_TRUE(scene->objects[0].displacement.empty());
}

TEST(SceneParse, UnknownFieldsAreWarningsNotErrors) {
    json scene = validScene();
    scene["lighting"] = "studio";
    scene["tessellation"]["facter"] = 3;
    std::vector<std::string> warnings;
    qp::Result<qp::Scene> result = qp::parseScene(scene.dump(), "scene.json", "", &warnings);
    ASSERT_TRUE(result) << result.error().message;
    EXPECT_EQ(warnings, (std::vector<std::string>{"scene.json: tessellation.facter: unknown field, ignored",
                                                  "scene.json: lighting: unknown field, ignored"}));
}

TEST(SceneParse, UnknownSchemeNamesAreAcceptedButNotEmptyOnes) {
    json scene = validScene();
    scene["viewports"][0]["scheme"] = "future-plugin";
    EXPECT_EQ(errorOf(scene), "");
    scene["viewports"][0]["scheme"] = "";
    EXPECT_EQ(errorOf(scene), "scene.json: viewports[0].scheme: must not be empty");
    scene["viewports"][0]["scheme"] = 7;
    EXPECT_EQ(errorOf(scene), "scene.json: viewports[0].scheme: expected a string, got a number");
}

// --- bad input ---

TEST(SceneErrors, MalformedJsonGivesLineColumnAndByte) {
    std::string text = "{\n  \"format\": \"quadplan-scene\"\n  \"version\": 1\n}\n";
    qp::Result<qp::Scene> result = qp::parseScene(text, "scene.json", "");
    ASSERT_FALSE(result);
    EXPECT_EQ(result.error().message.rfind("scene.json:3:11: invalid JSON (byte 42): syntax error", 0), 0u)
        << result.error().message;
}

TEST(SceneErrors, EmptyFileIsMalformed) {
    qp::Result<qp::Scene> result = qp::parseScene("", "scene.json", "");
    ASSERT_FALSE(result);
    EXPECT_EQ(result.error().message.rfind("scene.json:1:1: invalid JSON", 0), 0u) << result.error().message;
}

TEST(SceneErrors, NotAScene) {
    EXPECT_EQ(errorOf(json::array()), "scene.json: expected a JSON object at the top level, got an array");
    json scene = validScene();
    scene["format"] = "blender";
    EXPECT_EQ(errorOf(scene), "scene.json: format: expected \"quadplan-scene\", got \"blender\" (this is not a "
                              "Quadplan scene)");
}

TEST(SceneErrors, FutureVersion) {
    json scene = validScene();
    scene["version"] = 3;
    scene["cage"] = "laid out differently";
    EXPECT_EQ(errorOf(scene), "scene.json: version: scene version 3 was written by a newer Quadplan; this build "
                              "reads versions up to 2");
    scene["version"] = 0;
    EXPECT_EQ(errorOf(scene), "scene.json: version: scene version 0 is not valid (versions start at 1)");
    scene["version"] = "1";
    EXPECT_EQ(errorOf(scene), "scene.json: version: expected an integer, got a string");
}

TEST(SceneErrors, FutureDisplacementVersion) {
    json scene = validScene();
    scene["displacement"]["version"] = 3;
    EXPECT_EQ(errorOf(scene), "scene.json: displacement.version: displacement version 3 is not supported (this "
                              "build reads versions up to 2); the scene was written by a newer Quadplan");
}

TEST(SceneErrors, MissingRequiredFields) {
    json scene = validScene();
    scene.erase("cage");
    EXPECT_EQ(errorOf(scene), "scene.json: cage: required field is missing");
    scene = validScene();
    scene["cage"].erase("faces");
    EXPECT_EQ(errorOf(scene), "scene.json: cage.faces: required field is missing");
    scene = validScene();
    scene["camera"].erase("eye");
    EXPECT_EQ(errorOf(scene), "scene.json: camera.eye: required field is missing");
    scene = validScene();
    scene["cage"]["creases"][0].erase("sharpness");
    EXPECT_EQ(errorOf(scene), "scene.json: cage.creases[0].sharpness: required field is missing");
}

TEST(SceneErrors, WrongTypes) {
    json scene = validScene();
    scene["cage"]["faces"] = {{"a", "b", "c"}};
    EXPECT_EQ(errorOf(scene), "scene.json: cage.faces[0][0]: expected an integer, got a string");
    scene = validScene();
    scene["tessellation"]["factor"] = 2.5;
    EXPECT_EQ(errorOf(scene), "scene.json: tessellation.factor: expected an integer, got a number");
    scene = validScene();
    scene["tessellation"]["show_cage"] = "yes";
    EXPECT_EQ(errorOf(scene), "scene.json: tessellation.show_cage: expected true or false, got a string");
    scene = validScene();
    scene["display"] = {{"dense_cage_lines", 1}};
    EXPECT_EQ(errorOf(scene), "scene.json: display.dense_cage_lines: expected true or false, got a number");
    scene = validScene();
    scene["camera"] = json::array();
    EXPECT_EQ(errorOf(scene), "scene.json: camera: expected an object, got an array");
    scene = validScene();
    scene["cage"]["options"]["boundary"] = "all";
    EXPECT_EQ(errorOf(scene), "scene.json: cage.options.boundary: unknown value \"all\"; expected one of "
                              "\"edges-and-corners\", \"edges-only\", \"none\"");
}

TEST(SceneErrors, WrongVectorLengthsAndHugeNumbers) {
    json scene = validScene();
    scene["cage"]["positions"][4] = {1, 1};
    EXPECT_EQ(errorOf(scene), "scene.json: cage.positions[4]: expected 3 numbers, got 2");
    scene = validScene();
    scene["camera"]["up"] = {0, 1, 0, 0};
    EXPECT_EQ(errorOf(scene), "scene.json: camera.up: expected 3 numbers, got 4");
    scene = validScene();
    scene["cage"]["positions"][2][1] = 1e300;
    EXPECT_EQ(errorOf(scene), "scene.json: cage.positions[2][1]: number 1e+300 is too large");
    // 1e400 overflows even a double; it must not slip through as infinity.
    std::string text = validScene().dump();
    text.replace(text.find("\"fov_y_degrees\":40"), 18, "\"fov_y_degrees\":1e400");
    qp::Result<qp::Scene> result = qp::parseScene(text, "scene.json", "");
    ASSERT_FALSE(result);
    EXPECT_EQ(result.error().message, "scene.json: invalid JSON: number overflow parsing '1e400'");
}

TEST(SceneErrors, OutOfRangeValues) {
    json scene = validScene();
    scene["tessellation"]["factor"] = 65;
    EXPECT_EQ(errorOf(scene), "scene.json: tessellation.factor: must be between 1 and 64, got 65");
    scene = validScene();
    scene["tessellation"]["pixels_per_edge"] = 0;
    EXPECT_EQ(errorOf(scene), "scene.json: tessellation.pixels_per_edge: must be greater than 0, got 0");
    scene = validScene();
    scene["camera"]["fov_y_degrees"] = 180;
    EXPECT_EQ(errorOf(scene), "scene.json: camera.fov_y_degrees: must be between 0 and 180 degrees (exclusive), "
                              "got 180");
    scene = validScene();
    scene["camera"]["target"] = scene["camera"]["eye"];
    EXPECT_EQ(errorOf(scene), "scene.json: camera.target: must differ from \"eye\"");
    scene = validScene();
    scene["viewports"] = json::array();
    EXPECT_EQ(errorOf(scene), "scene.json: viewports: must list at least one viewport");
}

TEST(SceneErrors, OutOfRangeIndices) {
    json scene = validScene();
    scene["cage"]["faces"][1][3] = 99;
    EXPECT_EQ(errorOf(scene), "scene.json: cage.faces[1][3]: vertex index 99 out of range (cage has 6 vertices)");
    scene["cage"]["faces"][1][3] = -1;
    EXPECT_EQ(errorOf(scene), "scene.json: cage.faces[1][3]: vertex index -1 out of range (cage has 6 vertices)");
    scene = validScene();
    scene["cage"]["faces"][0] = {0, 1, 0};
    EXPECT_EQ(errorOf(scene), "scene.json: cage.faces[0][2]: vertex 0 closes the face onto itself (zero-length edge)");
    scene["cage"]["faces"][0] = {0, 1, 1, 2};
    EXPECT_EQ(errorOf(scene), "scene.json: cage.faces[0][2]: vertex 1 follows itself (zero-length edge)");
    scene = validScene();
    scene["cage"]["faces"][0] = {0, 1};
    EXPECT_EQ(errorOf(scene), "scene.json: cage.faces[0]: a face needs at least 3 vertices, got 2");
    scene = validScene();
    scene["cage"]["holes"] = {2};
    EXPECT_EQ(errorOf(scene), "scene.json: cage.holes[0]: face index 2 out of range (cage has 2 faces)");
    scene = validScene();
    scene["cage"]["corners"][0]["vertex"] = 6;
    EXPECT_EQ(errorOf(scene), "scene.json: cage.corners[0].vertex: vertex index 6 out of range (cage has 6 "
                              "vertices)");
    scene = validScene();
    scene["cage"]["creases"][0]["edge"] = {0, 5};
    EXPECT_EQ(errorOf(scene), "scene.json: cage.creases[0].edge: no face has an edge between vertices 0 and 5");
}

TEST(SceneErrors, BadSharpness) {
    json scene = validScene();
    scene["cage"]["creases"][0]["sharpness"] = -1;
    EXPECT_EQ(errorOf(scene), "scene.json: cage.creases[0].sharpness: sharpness -1 is outside [0, 10] (10 is "
                              "infinitely sharp)");
    scene = validScene();
    scene["cage"]["corners"][0]["sharpness"] = 10.5;
    EXPECT_EQ(errorOf(scene), "scene.json: cage.corners[0].sharpness: sharpness 10.5 is outside [0, 10] (10 is "
                              "infinitely sharp)");
}

TEST(SceneErrors, BadTextureCoordinates) {
    json scene = validScene();
    scene["cage"]["uvs"] = {{0, 0}, {1, 0}, {1, 1}};
    EXPECT_EQ(errorOf(scene), "scene.json: cage.face_uvs: required when \"uvs\" is given");
    scene["cage"]["face_uvs"] = {{0, 1, 2, 0}};
    EXPECT_EQ(errorOf(scene), "scene.json: cage.face_uvs: has 1 entries but the cage has 2 faces");
    scene["cage"]["face_uvs"] = {{0, 1, 2, 0}, {0, 1, 2}};
    EXPECT_EQ(errorOf(scene), "scene.json: cage.face_uvs[1]: has 3 indices but face 1 has 4 vertices");
    scene["cage"]["face_uvs"] = {{0, 1, 2, 0}, {0, 1, 2, 3}};
    EXPECT_EQ(errorOf(scene), "scene.json: cage.face_uvs[1][3]: texture coordinate index 3 out of range (cage "
                              "has 3 uvs)");
}

TEST_F(SceneFiles, SceneErrorsMissingReferencedObj) {
    std::string scenePath = write("scene.json", R"({"format": "quadplan-scene", "version": 1,
                                                    "cage": {"path": "missing.obj"}})");
    qp::Result<qp::Scene> result = qp::loadScene(scenePath);
    ASSERT_FALSE(result);
    const std::string& message = result.error().message;
    EXPECT_EQ(message.rfind(scenePath + ": cage.path: cannot load the referenced cage \"missing.obj\": ", 0), 0u)
        << message;
    EXPECT_NE(message.find(path("missing.obj")), std::string::npos) << message;
}

TEST_F(SceneFiles, SceneErrorsTagsBesideAReferencedCage) {
    write("box.obj", qp::formatObj(qp::parseScene(validScene().dump(), "s", "")->objects[0].cage));
    std::string scenePath = write("scene.json", R"({"format": "quadplan-scene", "version": 1,
        "cage": {"path": "box.obj", "creases": []}})");
    qp::Result<qp::Scene> result = qp::loadScene(scenePath);
    ASSERT_FALSE(result);
    EXPECT_EQ(result.error().message, scenePath + ": cage.creases: not allowed with \"path\": a referenced cage "
                                                  "keeps its geometry and tags in the OBJ file");
}

// --- saving ---

TEST_F(SceneFiles, SceneSaveLeavesNoTemporaryFiles) {
    qp::Result<qp::Scene> scene = qp::parseScene(validScene().dump(), "scene.json", "");
    ASSERT_TRUE(scene) << scene.error().message;
    scene->objects[0].cagePath = "cage.obj";
    for (int i = 0; i < 3; ++i)
        ASSERT_TRUE(qp::saveScene(*scene, path("scene.json"), i % 2 == 0 ? qp::CageStorage::Inline : qp::CageStorage::Referenced));
    EXPECT_EQ(listDir(), (std::vector<std::string>{"cage.obj", "scene.json"}));
}

TEST_F(SceneFiles, SceneSaveToMissingDirectoryFails) {
    qp::Result<qp::Scene> scene = qp::parseScene(validScene().dump(), "scene.json", "");
    ASSERT_TRUE(scene) << scene.error().message;
    std::string target = path("no/such/dir/scene.json");
    for (qp::CageStorage storage : {qp::CageStorage::Inline, qp::CageStorage::Referenced}) {
        qp::Status saved = qp::saveScene(*scene, target, storage);
        ASSERT_FALSE(saved);
        EXPECT_NE(saved.error().message.find(path("no/such/dir/")), std::string::npos) << saved.error().message;
    }
    EXPECT_TRUE(listDir().empty());
}

TEST_F(SceneFiles, SceneSaveBelowAFileFails) {
    qp::Result<qp::Scene> scene = qp::parseScene(validScene().dump(), "scene.json", "");
    ASSERT_TRUE(scene) << scene.error().message;
    write("file", "not a directory");
    qp::Status saved = qp::saveScene(*scene, path("file/scene.json"), qp::CageStorage::Inline);
    ASSERT_FALSE(saved);
    EXPECT_NE(saved.error().message.find("file/scene.json"), std::string::npos) << saved.error().message;
}

// --- scene or cage ---

TEST_F(SceneFiles, SceneOrCageByExtension) {
    qp::Result<qp::Scene> fromObj = qp::loadSceneOrCage(scenesPath("default.obj"));
    ASSERT_TRUE(fromObj) << fromObj.error().message;
    EXPECT_TRUE(fromObj->objects[0].cagePath.empty());
    EXPECT_EQ(fromObj->viewports, std::vector<qp::Viewport>{qp::Viewport{}});

    qp::Result<qp::Scene> fromJson = qp::loadSceneOrCage(scenesPath("default.json"));
    ASSERT_TRUE(fromJson) << fromJson.error().message;
    EXPECT_TRUE(qp::sameTopologyAndTags(fromObj->objects[0].cage, fromJson->objects[0].cage));

    std::string text = write("notes.txt", "hello");
    qp::Result<qp::Scene> result = qp::loadSceneOrCage(text);
    ASSERT_FALSE(result);
    EXPECT_EQ(result.error().message,
              text + ": cannot open a file of type \".txt\"; Quadplan opens scenes (.json) and cages (.obj, .ply, .off, .stl)");
}
