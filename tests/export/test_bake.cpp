// Baking displacement to texture space (export/displacement_bake.h, `quadplan bake`): the map
// read back by OpenEXR and sampled at the limit surface's UVs gives the sculpted values within
// the texel error; the normal map turned back into the world gives the displaced normals; the
// PNG decodes to the map; refusals. Smooth UVs (export/cage_uvs.h) are OpenSubdiv's
// face-varying limit: on a flat cage with UVs = (x, y) they are the limit surface's (x, y).
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include <unistd.h>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <glm/geometric.hpp>
#include <glm/mat2x2.hpp>
#include <stb/stb_image.h>

#include "cage_uvs.h"
#include "cli_run.h"
#include "displacement_bake.h"
#include "plans/planned_cage.h"
#include "scene/scene.h"
#include "test_cages.h"

using namespace qp;
namespace fs = std::filesystem;

namespace {

fs::path scratch() {
    const fs::path dir = fs::temp_directory_path() / ("quadplan_bake_" + std::to_string(getpid()));
    fs::create_directories(dir);
    return dir;
}

// A subdivided cube whose faces are UV islands in a 6 x 4 atlas of [0, 1]^2, a margin around each.
Cage atlasCube() {
    Cage cube = test::makeSubdividedCube(2);  // 24 faces
    const glm::vec2 square[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (uint32_t f = 0; f < cube.faceCount(); ++f)
        for (uint32_t k = 0; k < 4; ++k) {
            cube.faceUVIndices.push_back(uint32_t(cube.uvs.size()));
            const glm::vec2 cell(float(f % 6), float(f / 6));
            cube.uvs.push_back((cell + 0.1f + 0.8f * square[k]) / glm::vec2(6.0f, 4.0f));
        }
    return cube;
}

// Random sample values: a rough field, so interpolation errors would show.
Displacement randomDisplacement(const PlannedCage& planned, uint32_t resolution, uint32_t seed) {
    Displacement d = makeDisplacement(planned.cage(), planned.topology(), resolution);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> value(-0.05f, 0.1f);
    for (float& s : d.samples) s = value(rng);
    return d;
}

std::vector<float> readExr(const fs::path& path, uint32_t& size) {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    size = uint32_t(window.max.x - window.min.x + 1);
    EXPECT_EQ(window.max.y - window.min.y + 1, int(size)) << "the map is not square";
    EXPECT_NE(file.header().channels().findChannel("Y"), nullptr);
    EXPECT_EQ(file.header().channels().findChannel("Y")->type, Imf::FLOAT) << "not a 32-bit float map";
    std::vector<float> pixels(size_t(size) * size);
    Imf::FrameBuffer frame;
    frame.insert("Y", Imf::Slice(Imf::FLOAT, (char*)pixels.data(), sizeof(float), sizeof(float) * size));
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    return pixels;
}

struct Footprint {
    uint32_t x0, y0;
    float fx, fy;
};
// The bilinear footprint of a UV in the map (texel centres at half-integers).
std::optional<Footprint> footprint(glm::vec2 uv, uint32_t size) {
    const float x = uv.x * float(size) - 0.5f, y = (1.0f - uv.y) * float(size) - 0.5f;
    if (x < 0.0f || y < 0.0f || x >= float(size - 1) || y >= float(size - 1)) return std::nullopt;
    return Footprint{uint32_t(x), uint32_t(y), x - std::floor(x), y - std::floor(y)};
}

template <typename T>
T bilinear(const std::vector<T>& map, uint32_t size, const Footprint& f) {
    auto at = [&](uint32_t dx, uint32_t dy) { return map[size_t(f.y0 + dy) * size + f.x0 + dx]; };
    return (1 - f.fy) * ((1 - f.fx) * at(0, 0) + f.fx * at(1, 0)) + f.fy * ((1 - f.fx) * at(0, 1) + f.fx * at(1, 1));
}

bool insideIsland(const BakedMaps& maps, const Footprint& f) {
    for (uint32_t dy = 0; dy < 2; ++dy)
        for (uint32_t dx = 0; dx < 2; ++dx)
            if (maps.coverage[size_t(f.y0 + dy) * maps.size + f.x0 + dx] != TexelCoverage::Island) return false;
    return true;
}

glm::vec3 displacedNormal(const PlannedCage& planned, const Displacement& d, uint32_t s, float u, float v) {
    const LimitSample limit = planned.evaluate(s, u, v);
    const glm::vec3 normal = glm::normalize(glm::cross(limit.du, limit.dv));
    return displacePoint(limit.position, limit.du, limit.dv, normal, evaluateDisplacement(d, s, u, v)).normal;
}

}  // namespace

TEST(DisplacementBake, TheMapSampledAtTheSurfacesUvsGivesTheSculptedValues) {
    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(atlasCube(), database, PlanOptions{}, "atlas cube");
    ASSERT_TRUE(planned) << planned.error().message;
    const Displacement displacement = randomDisplacement(*planned, 4, 7);
    BakeOptions options;
    options.size = 384;
    options.normalMap = true;
    Result<BakedMaps> maps = bakeDisplacement(*planned, displacement, options, "atlas cube");
    ASSERT_TRUE(maps) << maps.error().message;
    // Each island covers 0.8^2 of its atlas cell: about that share of the texels.
    const double islandShare = double(maps->islandTexels) / double(options.size * options.size);
    EXPECT_NEAR(islandShare, 0.64, 0.02);
    EXPECT_GT(maps->paddingTexels, 0u);

    // The file, read by OpenEXR, holds the baked values bit for bit.
    const fs::path dir = scratch();
    ASSERT_TRUE(writeDisplacementExr(*maps, (dir / "d.exr").string()));
    uint32_t size = 0;
    const std::vector<float> map = readExr(dir / "d.exr", size);
    ASSERT_EQ(size, options.size);
    EXPECT_EQ(map, maps->displacement);

    // Random surface points: the map, bilinear at the point's UV, against the sculpted D. The
    // texel error: how far D moves within a texel of the point (along the sub-face's u and v).
    Result<CageUvs> uvs = CageUvs::create(*planned, UvMode::Linear);
    ASSERT_TRUE(uvs);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    uint32_t checked = 0;
    float worstAngle = 0.0f;
    for (int i = 0; i < 3000; ++i) {
        const uint32_t s = uint32_t(unit(rng) * float(planned->subfaceCount())) % planned->subfaceCount();
        const float u = unit(rng), v = unit(rng);
        const std::optional<Footprint> f = footprint(uvs->at(s, u, v), size);
        if (!f || !insideIsland(*maps, *f)) continue;
        ++checked;
        const float extent = glm::length(uvs->at(s, 1, 0) - uvs->at(s, 0, 0)) * float(size);  // texels per unit u
        const float step = 1.0f / extent;
        const float exact = evaluateDisplacement(displacement, s, u, v).value;
        float texelError = 0.0f;
        for (const glm::vec2 d : {glm::vec2(step, 0), glm::vec2(-step, 0), glm::vec2(0, step), glm::vec2(0, -step)})
            texelError = std::max(texelError, std::abs(evaluateDisplacement(displacement, s, u + d.x, v + d.y).value - exact));
        const float sampled = bilinear(map, size, *f);
        EXPECT_LE(std::abs(sampled - exact), texelError + 1e-6f) << "sub-face " << s << " at (" << u << ", " << v << ")";

        // The normal map back in the world: the frame of the derivatives along U and V.
        const LimitSample limit = planned->evaluate(s, u, v);
        const glm::vec3 normal = glm::normalize(glm::cross(limit.du, limit.dv));
        const glm::vec2 dU = (uvs->at(s, std::min(u + 1e-3f, 1.0f), v) - uvs->at(s, std::max(u - 1e-3f, 0.0f), v)),
                        dV = (uvs->at(s, u, std::min(v + 1e-3f, 1.0f)) - uvs->at(s, u, std::max(v - 1e-3f, 0.0f)));
        const glm::mat2 inverse = glm::inverse(glm::mat2(dU, dV));
        const glm::vec3 alongU = limit.du * inverse[0][0] + limit.dv * inverse[0][1];
        const glm::vec3 tangent = glm::normalize(alongU - normal * glm::dot(normal, alongU));
        const glm::vec3 bitangent = glm::cross(normal, tangent);  // the atlas keeps the faces' orientation
        const glm::vec3 t = glm::normalize(bilinear(maps->normals, size, *f));
        const glm::vec3 world = glm::normalize(t.x * tangent + t.y * bitangent + t.z * normal);
        const glm::vec3 expected = displacedNormal(*planned, displacement, s, u, v);
        float normalSpread = 0.0f;  // the displaced normal's own change within a texel
        for (const glm::vec2 d : {glm::vec2(step, 0), glm::vec2(-step, 0), glm::vec2(0, step), glm::vec2(0, -step)}) {
            const glm::vec3 n = displacedNormal(*planned, displacement, s, std::clamp(u + d.x, 0.0f, 1.0f),
                                                std::clamp(v + d.y, 0.0f, 1.0f));
            normalSpread = std::max(normalSpread, std::acos(std::clamp(glm::dot(n, expected), -1.0f, 1.0f)));
        }
        const float angle = std::acos(std::clamp(glm::dot(world, expected), -1.0f, 1.0f));
        worstAngle = std::max(worstAngle, angle - normalSpread);
        EXPECT_LE(angle, normalSpread + glm::radians(0.5f)) << "sub-face " << s << " at (" << u << ", " << v << ")";
    }
    EXPECT_GT(checked, 1500u) << "too few points fell inside the islands";

    // The PNG decodes to the normal map, 8 bits per component.
    ASSERT_TRUE(writeNormalMapPng(*maps, (dir / "n.png").string()));
    int w = 0, h = 0, channels = 0;
    stbi_uc* png = stbi_load((dir / "n.png").c_str(), &w, &h, &channels, 4);
    ASSERT_NE(png, nullptr);
    ASSERT_EQ(uint32_t(w), options.size);
    float worst = 0.0f;
    for (size_t t = 0; t < maps->normals.size(); ++t)
        for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(float(png[t * 4 + k]) / 255.0f * 2.0f - 1.0f - maps->normals[t][k]));
    stbi_image_free(png);
    EXPECT_LE(worst, 1.0f / 255.0f + 1e-6f);
    fs::remove_all(dir);
}

TEST(DisplacementBake, RefusesWhatItCannotBakeAndWritesNothing) {
    PlanDatabase database;
    Result<PlannedCage> bare = PlannedCage::create(test::makeSubdividedCube(2), database, PlanOptions{}, "cube");
    ASSERT_TRUE(bare);
    Result<BakedMaps> noUvs = bakeDisplacement(*bare, randomDisplacement(*bare, 2, 1), BakeOptions{}, "cube");
    ASSERT_FALSE(noUvs);
    EXPECT_NE(noUvs.error().message.find("no texture coordinates"), std::string::npos) << noUvs.error().message;
    Result<PlannedCage> atlas = PlannedCage::create(atlasCube(), database, PlanOptions{}, "atlas");
    ASSERT_TRUE(atlas);
    Result<BakedMaps> nothing = bakeDisplacement(*atlas, Displacement{}, BakeOptions{}, "atlas");
    ASSERT_FALSE(nothing);
    EXPECT_NE(nothing.error().message.find("no sculpted displacement"), std::string::npos);
    BakeOptions tiny;
    tiny.size = 8;
    EXPECT_FALSE(bakeDisplacement(*atlas, randomDisplacement(*atlas, 2, 1), tiny, "atlas"));
    Result<BakedMaps> foreign = bakeDisplacement(*atlas, randomDisplacement(*bare, 2, 1), BakeOptions{}, "atlas");
    EXPECT_TRUE(foreign) << "the same topology with other UVs is the same cage";

    // The command: a cage without displacement is refused, and no file appears.
    const fs::path dir = scratch();
    test::CommandRun run = test::runQuadplan("bake " + std::string(QUADPLAN_SCENES_DIR) + "/default.obj --out " + (dir / "x.exr").string(), true);
    EXPECT_EQ(run.status, 1);
    EXPECT_FALSE(fs::exists(dir / "x.exr"));
    EXPECT_NE(run.out.find("error:"), std::string::npos) << run.out;
    run = test::runQuadplan("bake " + std::string(QUADPLAN_SCENES_DIR) + "/default.json --out " + (dir / "x.png").string(), true);
    EXPECT_EQ(run.status, 1);
    EXPECT_NE(run.out.find(".exr"), std::string::npos) << run.out;
    fs::remove_all(dir);
}

TEST(CageUvs, SmoothUvsAreOpenSubdivsFaceVaryingLimit) {
    // A flat cage with n-gons whose UVs are its (x, y): with the face-varying rule "none" (smooth
    // everywhere) the UVs' limit is the surface's own (x, y) on faces away from the boundary; with
    // "all" (linear everywhere, the default) smooth UVs are the linear ones.
    Cage flat = test::makeMixedGrid();
    for (glm::vec3& p : flat.positions) p.z = 0.0f;
    for (const glm::vec3& p : flat.positions) flat.uvs.push_back({p.x, p.y});
    flat.faceUVIndices = flat.faceVertices;
    PlanDatabase database;
    for (const FVarInterpolation rule : {FVarInterpolation::None, FVarInterpolation::All}) {
        Cage cage = flat;
        cage.options.fvarInterpolation = rule;
        Result<PlannedCage> planned = PlannedCage::create(cage, database, PlanOptions{}, "flat");
        ASSERT_TRUE(planned) << planned.error().message;
        Result<CageUvs> smooth = CageUvs::create(*planned, UvMode::Smooth), linear = CageUvs::create(*planned, UvMode::Linear);
        ASSERT_TRUE(smooth && linear) << (smooth ? linear.error().message : smooth.error().message);
        uint32_t interiorSubfaces = 0;
        for (uint32_t f = 0; f < cage.faceCount(); ++f) {
            bool interior = true;  // every corner inside the 4 x 4 grid
            for (uint32_t k = 0; k < cage.faceSize(f); ++k) {
                const glm::vec3 p = cage.positions[cage.faceBegin(f)[k]];
                interior = interior && p.x > 0.5f && p.x < 3.5f && p.y > 0.5f && p.y < 3.5f;
            }
            for (uint32_t s = planned->firstSubface(f); s < planned->firstSubface(f + 1); ++s)
                for (float u : {0.0f, 0.3f, 0.5f, 1.0f})
                    for (float v : {0.0f, 0.2f, 0.7f, 1.0f}) {
                        const glm::vec2 uv = smooth->at(s, u, v);
                        if (rule == FVarInterpolation::All) {
                            EXPECT_LT(glm::length(uv - linear->at(s, u, v)), 1e-5f) << "sub-face " << s;
                        } else if (interior) {
                            const glm::vec3 p = planned->evaluate(s, u, v).position;
                            EXPECT_LT(glm::length(uv - glm::vec2(p.x, p.y)), 1e-5f) << "sub-face " << s << " (" << u << ", " << v << ")";
                        }
                    }
            if (interior) interiorSubfaces += planned->firstSubface(f + 1) - planned->firstSubface(f);
        }
        EXPECT_EQ(interiorSubfaces, 3u + 3u + 5u) << "the interior should hold three quads, the triangle and the pentagon";
    }
    EXPECT_FALSE(parseUvMode("cubic"));
}
