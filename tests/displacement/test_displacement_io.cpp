// The scene file's displacement: bit-identical round trips, the version 0 migration and
// errors that name the field at fault.
#include <gtest/gtest.h>

#include <bit>
#include <cfloat>
#include <cmath>
#include <filesystem>
#include <random>

#include <unistd.h>

#include "displacement/displacement_io.h"
#include "displacement/sample_grids.h"
#include "mesh/topology.h"
#include "scene/scene.h"
#include "test_cages.h"

using namespace qp;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// The mixed grid (quads, a triangle, a pentagon) with values that a decimal round trip could get
// wrong: -0, subnormals, the extremes, non-terminating decimals.
Scene sculptedScene(uint32_t seed) {
    Scene scene = sceneOfCage(test::makeMixedGrid(), "cage");
    Displacement d = makeDisplacement(scene.objects[0].cage, buildTopology(scene.objects[0].cage), 4);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> value(-0.3f, 0.3f);
    for (float& s : d.samples) s = value(rng);
    const float special[] = {-0.0f, 1e-40f, -FLT_TRUE_MIN, FLT_MAX, -FLT_MAX, FLT_MIN, 0.1f, 1.0f / 3.0f};
    for (size_t i = 0; i < std::size(special); ++i) d.samples[(i * 7919) % d.samples.size()] = special[i];
    scene.objects[0].displacement = std::move(d);
    return scene;
}

// Random sample grids of version 1 (random resolutions per sub-face) for the mixed grid.
SampleGrids version1Grids(uint32_t seed) {
    const Cage cage = test::makeMixedGrid();
    SampleGrids d = makeSampleGrids(cage, buildTopology(cage), 1);
    std::mt19937 rng(seed);
    std::vector<uint32_t> resolutions(d.layout.subfaces.size());
    for (uint32_t& r : resolutions) r = 1u << (rng() % 5);
    d.layout = withResolutions(d.layout, resolutions);
    std::uniform_real_distribution<float> value(-0.3f, 0.3f);
    d.samples.resize(d.layout.sampleCount);
    for (float& s : d.samples) s = value(rng);
    return d;
}

// A scene written by a version 1 writer (the format as it was).
json version1Scene(const SampleGrids& d) {
    json scene = json::parse(formatScene(sceneOfCage(test::makeMixedGrid(), "cage"), CageStorage::Inline));
    json out = {{"version", 1}, {"encoding", "base64-float32-le"}, {"subfaces", json::array()}};
    const SampleGridLayout& layout = d.layout;
    for (const DisplacementSubface& sf : layout.subfaces)
        out["subfaces"].push_back({{"resolution", sf.resolution},
                                   {"interior", encodeFloats(d.samples.data() + sf.interiorOffset,
                                                             size_t(sf.resolution - 1) * (sf.resolution - 1))}});
    out["points"] = encodeFloats(d.samples.data(), layout.pointCount);
    out["segments"] = encodeFloats(d.samples.data() + layout.segmentSampleBegin(), layout.tileSampleBegin() - layout.segmentSampleBegin());
    if (!d.mask.empty()) out["mask"] = encodeFloats(d.mask.data(), d.mask.size());
    scene["objects"][0]["displacement"] = out;
    return scene;
}

json sceneJson(const Scene& scene) { return json::parse(formatScene(scene, CageStorage::Inline)); }

std::string errorOf(const json& scene) {
    Result<Scene> result = parseScene(scene.dump(), "scene.json", ".");
    return result ? "" : result.error().message;
}

std::string tempPath(const std::string& name) {
    return (fs::temp_directory_path() / ("quadplan-displacement-" + std::to_string(::getpid()) + "-" + name)).string();
}

std::string base64Of(std::vector<float> values) { return encodeFloats(values.data(), values.size()); }

}  // namespace

TEST(DisplacementFile, Base64RoundTripsEveryBitPattern) {
    std::mt19937 rng(5);
    for (size_t count : {0u, 1u, 2u, 3u, 17u}) {
        std::vector<float> values(count);
        for (float& v : values) v = std::bit_cast<float>(uint32_t(rng()));  // NaNs included
        Result<std::vector<float>> back = decodeFloats(encodeFloats(values.data(), values.size()));
        ASSERT_TRUE(back) << back.error().message;
        ASSERT_EQ(back->size(), count);
        for (size_t i = 0; i < count; ++i) EXPECT_EQ(std::bit_cast<uint32_t>((*back)[i]), std::bit_cast<uint32_t>(values[i]));
    }
    EXPECT_EQ(encodeFloats(std::vector<float>{1.0f}.data(), 1), "AACAPw==");  // 3f800000, little-endian
    EXPECT_FALSE(decodeFloats("AACAPw="));
    EXPECT_FALSE(decodeFloats("AAC*Pw=="));
    EXPECT_FALSE(decodeFloats("AACA"));  // 3 bytes: not a whole float
}

TEST(DisplacementFile, SceneRoundTripIsBitIdentical) {
    Scene scene = sculptedScene(3);
    const std::string path = tempPath("round-trip.json");
    ASSERT_TRUE(saveScene(scene, path, CageStorage::Inline));
    Result<Scene> loaded = loadScene(path);
    ASSERT_TRUE(loaded) << loaded.error().message;
    ASSERT_EQ(loaded->objects[0].displacement.layout, scene.objects[0].displacement.layout);
    ASSERT_EQ(loaded->objects[0].displacement.samples.size(), scene.objects[0].displacement.samples.size());
    for (size_t i = 0; i < scene.objects[0].displacement.samples.size(); ++i)
        ASSERT_EQ(std::bit_cast<uint32_t>(loaded->objects[0].displacement.samples[i]), std::bit_cast<uint32_t>(scene.objects[0].displacement.samples[i]))
            << "sample " << i;
    EXPECT_EQ(formatScene(*loaded, qp::CageStorage::Inline), formatScene(scene, CageStorage::Inline));
    fs::remove(path);
}

TEST(DisplacementFile, EmptyDisplacementWritesVersion2WithoutData) {
    Scene scene = sceneOfCage(test::makeCube(), "cage");
    json written = sceneJson(scene)["objects"][0]["displacement"];
    EXPECT_EQ(written, json::parse(R"({"version": 2, "encoding": "base64-float32-le", "resolution": 0})"));
    Result<Scene> back = parseScene(formatScene(scene, CageStorage::Inline), "scene.json", ".");
    ASSERT_TRUE(back) << back.error().message;
    EXPECT_TRUE(back->objects[0].displacement.empty());
}

TEST(DisplacementFile, Version0PlaceholderMigratesToNoDisplacement) {
    // The bundled default scene was written with the version 0 placeholder.
    Result<Scene> scene = loadScene(std::string(QUADPLAN_SCENES_DIR) + "/default.json");
    ASSERT_TRUE(scene) << scene.error().message;
    EXPECT_TRUE(scene->objects[0].displacement.empty());
    EXPECT_EQ(sceneJson(*scene)["objects"][0]["displacement"]["version"], 2);

    json placeholder = sceneJson(sculptedScene(1));
    placeholder["objects"][0]["displacement"] = {{"version", 0}, {"faces", json::array()}};
    EXPECT_EQ(errorOf(placeholder), "");
    placeholder["objects"][0]["displacement"]["faces"] = {{{"face", 1}}};
    EXPECT_EQ(errorOf(placeholder), "scene.json: objects[0].displacement.faces: a version 0 displacement is an empty "
                                    "placeholder; expected [], got [{\"face\":1}]");
}

TEST(DisplacementFile, MalformedVersion1DataNamesTheField) {
    const json good = version1Scene(version1Grids(2));
    ASSERT_EQ(errorOf(good), "");
    auto edited = [&](auto change) {
        json scene = good;
        change(scene["objects"][0]["displacement"]);
        return errorOf(scene);
    };
    // Sub-face 0 of the mixed grid: find one with resolution >= 4 to damage.
    size_t s = 0;
    while (good["objects"][0]["displacement"]["subfaces"][s]["resolution"].get<int>() < 4) ++s;
    const std::string sub = "objects[0].displacement.subfaces[" + std::to_string(s) + "]";
    const int R = good["objects"][0]["displacement"]["subfaces"][s]["resolution"];
    const size_t interior = size_t(R - 1) * (R - 1);

    EXPECT_EQ(edited([&](json& d) { d["subfaces"][s]["resolution"] = 3; }),
              "scene.json: " + sub + ".resolution: resolution 3 is not a power of two between 1 and 64");
    EXPECT_EQ(edited([&](json& d) { d["subfaces"][s]["resolution"] = 128; }),
              "scene.json: " + sub + ".resolution: resolution 128 is not a power of two between 1 and 64");
    EXPECT_EQ(edited([&](json& d) { d["subfaces"][s]["resolution"] = 4.0; }),
              "scene.json: " + sub + ".resolution: expected an integer, got a number");
    EXPECT_EQ(edited([&](json& d) { d["subfaces"][s]["interior"] = base64Of(std::vector<float>(interior - 1, 0.0f)); }),
              "scene.json: " + sub + ".interior: has " + std::to_string(interior - 1) + " values but " +
                  std::to_string(interior) + " are needed");
    EXPECT_EQ(edited([&](json& d) {
                  std::vector<float> values(interior, 0.5f);
                  values[R] = NAN;  // grid point (2, 2): one row of R - 1 plus one
                  d["subfaces"][s]["interior"] = base64Of(values);
              }),
              "scene.json: " + sub + ".interior: value " + std::to_string(R) + " (grid point (2, 2) of resolution " +
                  std::to_string(R) + ") is NaN; displacements must be finite numbers");
    EXPECT_EQ(edited([&](json& d) {
                  std::vector<float> values(interior, 0.5f);
                  values[0] = -INFINITY;
                  d["subfaces"][s]["interior"] = base64Of(values);
              }),
              "scene.json: " + sub + ".interior: value 0 (grid point (1, 1) of resolution " + std::to_string(R) +
                  ") is infinite; displacements must be finite numbers");
    EXPECT_EQ(edited([&](json& d) { d["subfaces"][s]["interior"] = "not base64!"; }),
              "scene.json: " + sub + ".interior: is not base64: its length 11 is not a multiple of 4");
    EXPECT_EQ(edited([&](json& d) { d["subfaces"][s]["interior"] = std::vector<float>(interior, 0.0f); }),
              "scene.json: " + sub + ".interior: expected a base64 string of float32 values, got an array");
    EXPECT_EQ(edited([&](json& d) { d["subfaces"][s].erase("interior"); }),
              "scene.json: " + sub + ".interior: required field is missing");
    EXPECT_EQ(edited([&](json& d) { d["subfaces"].erase(d["subfaces"].size() - 1); }),
              "scene.json: objects[0].displacement.subfaces: has 22 entries but the cage has 23 sub-faces (17 faces; a quad is one "
              "sub-face, an n-gon n): the displacement belongs to another cage");
    EXPECT_EQ(edited([&](json& d) { d["points"] = base64Of(std::vector<float>(3, 0.0f)); }),
              "scene.json: objects[0].displacement.points: has 3 values but " + std::to_string(26 + 42 + 17) + " are needed");
    EXPECT_EQ(edited([&](json& d) {
                  Result<std::vector<float>> points = decodeFloats(d["points"]);
                  (*points)[26 + 3] = NAN;  // cage edge 3's midpoint
                  d["points"] = base64Of(*points);
              }),
              "scene.json: objects[0].displacement.points: value 29 (midpoint of cage edge 3) is NaN; displacements must be finite "
              "numbers");
    EXPECT_NE(edited([&](json& d) { d["segments"] = ""; }).find("scene.json: objects[0].displacement.segments: has 0 values but"),
              std::string::npos);
    EXPECT_EQ(edited([&](json& d) { d.erase("points"); }), "scene.json: objects[0].displacement.points: required field is missing");
    EXPECT_EQ(edited([&](json& d) { d["encoding"] = "decimal"; }),
              "scene.json: objects[0].displacement.encoding: expected \"base64-float32-le\", got \"decimal\"");
    EXPECT_EQ(edited([&](json& d) { d["subfaces"] = json::array(); }),
              "scene.json: objects[0].displacement.points: not allowed when \"subfaces\" is empty (no displacement)");
    EXPECT_EQ(edited([&](json& d) { d["version"] = -1; }), "scene.json: objects[0].displacement.version: displacement version -1 is not valid");
}

TEST(DisplacementFile, UnknownFieldsAreWarnings) {
    json scene = sceneJson(sculptedScene(4));
    scene["objects"][0]["displacement"]["brush"] = "raise";
    std::vector<std::string> warnings;
    Result<Scene> loaded = parseScene(scene.dump(), "scene.json", ".", &warnings);
    ASSERT_TRUE(loaded) << loaded.error().message;
    EXPECT_EQ(warnings, (std::vector<std::string>{"scene.json: objects[0].displacement.brush: unknown field, ignored"}));
    json old = version1Scene(version1Grids(4));
    old["objects"][0]["displacement"]["subfaces"][1]["mips"] = 3;
    warnings.clear();
    ASSERT_TRUE(parseScene(old.dump(), "scene.json", ".", &warnings));
    ASSERT_EQ(warnings.size(), 2u);
    EXPECT_EQ(warnings[0], "scene.json: objects[0].displacement.subfaces[1].mips: unknown field, ignored");
    EXPECT_NE(warnings[1].find("version 1 (bilinear sample grids) converted"), std::string::npos) << warnings[1];
}

TEST(DisplacementFile, MalformedVersion2DataNamesTheField) {
    const json good = sceneJson(sculptedScene(2));
    ASSERT_EQ(errorOf(good), "");
    auto edited = [&](auto change) {
        json scene = good;
        change(scene["objects"][0]["displacement"]);
        return errorOf(scene);
    };
    const std::string at = "scene.json: objects[0].displacement.";
    EXPECT_EQ(edited([&](json& d) { d["resolution"] = 3; }),
              at + "resolution: resolution 3 is not a power of two between 1 and 64 (or 0 for none)");
    EXPECT_EQ(edited([&](json& d) { d["resolution"] = 128; }),
              at + "resolution: resolution 128 is not a power of two between 1 and 64 (or 0 for none)");
    EXPECT_EQ(edited([&](json& d) { d["resolution"] = 2; }),
              at + "resolution: resolution 2 is below 4, the least a cage with non-quad faces allows (their sub-faces get half, "
                   "and tiles need 2 cells per side)");
    EXPECT_EQ(edited([&](json& d) { d["resolution"] = "4"; }), at + "resolution: expected an integer, got a string");
    EXPECT_EQ(edited([&](json& d) { d.erase("resolution"); }), at + "resolution: required field is missing");
    EXPECT_EQ(edited([&](json& d) { d.erase("samples"); }), at + "samples: required field is missing");
    EXPECT_EQ(edited([&](json& d) { d["resolution"] = 0; }), at + "samples: not allowed when \"resolution\" is 0 (no displacement)");
    EXPECT_NE(edited([&](json& d) { d["resolution"] = 8; }).find(at + "samples: has "), std::string::npos);
    EXPECT_EQ(edited([&](json& d) {
                  Result<std::vector<float>> samples = decodeFloats(d["samples"]);
                  (*samples)[5] = NAN;
                  d["samples"] = base64Of(*samples);
              }).find(at + "samples: value 5 (sample 5, cell ("), 0u);
    EXPECT_NE(edited([&](json& d) { d["samples"] = "not base64!"; }).find(at + "samples: is not base64"), std::string::npos);
    EXPECT_EQ(edited([&](json& d) { d["mask"] = base64Of({0.5f}); }).find(at + "mask: has 1 values"), 0u);
}

// A version 1 scene loads converted: tiles fitted to its grids, close to their D, and saves as
// version 2.
TEST(DisplacementFile, Version1ScenesAreConvertedByFitting) {
    SampleGrids grids = version1Grids(9);
    // A constant relief: it is in every spline space, so the conversion must keep it exactly.
    grids.samples.assign(grids.samples.size(), 0.1f);
    grids.mask.assign(grids.samples.size(), 1.0f);
    uint32_t finest = 0;  // in quad cells: an n-gon sub-face spans half a quad side
    for (uint32_t s = 0; s < grids.layout.subfaces.size(); ++s)
        finest = std::max(finest, grids.layout.subfaces[s].resolution * (s >= 15 ? 2u : 1u));
    std::vector<std::string> warnings;
    Result<Scene> loaded = parseScene(version1Scene(grids).dump(), "scene.json", ".", &warnings);
    ASSERT_TRUE(loaded) << loaded.error().message;
    const Displacement& d = loaded->objects[0].displacement;
    ASSERT_FALSE(d.empty());
    EXPECT_EQ(d.resolution(), std::min(finest, kMaxDisplacementResolution));
    for (uint32_t s = 0; s < d.layout.tiles.size(); ++s)
        for (float u : {0.0f, 0.3f, 1.0f}) EXPECT_NEAR(evaluateDisplacement(d, s, u, 0.5f).value, 0.1f, 1e-6f);
    for (float m : d.mask) EXPECT_FLOAT_EQ(m, 1.0f);
    EXPECT_EQ(sceneJson(*loaded)["objects"][0]["displacement"]["version"], 2);
    ASSERT_EQ(warnings.size(), 1u);
}

TEST(DisplacementFile, SaveRefusesADisplacementOfAnotherTopology) {
    Scene scene = sculptedScene(6);
    scene.objects[0].cage = test::makeGrid(4);  // 16 quads, the displacement was for the mixed grid
    const std::string path = tempPath("refused.json");
    Status saved = saveScene(scene, path, CageStorage::Inline);
    ASSERT_FALSE(saved);
    EXPECT_NE(saved.error().message.find("does not fit the cage"), std::string::npos) << saved.error().message;
    EXPECT_FALSE(fs::exists(path));
    EXPECT_TRUE(displacementFitsCage(Displacement{}, scene.objects[0].cage));
}
