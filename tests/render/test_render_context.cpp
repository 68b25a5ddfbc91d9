// The Vulkan foundation end to end, on lavapipe with validation on: context, offscreen target,
// mesh pass, read-back, PNG, pipeline cache. Every test also asserts that the validation layer
// (with synchronization validation) reported nothing, teardown included.
//
// Vulkan is a declared dependency (mesa-vulkan-drivers provides lavapipe): when it cannot be
// initialised these tests fail, they never skip. QUADPLAN_VK_DEVICE=<name part> runs them on
// another device instead of lavapipe.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "camera.h"
#include "mesh/file_io.h"
#include "mesh_pass.h"
#include "offscreen_target.h"
#include "pipeline_cache.h"
#include "render_test_support.h"
#include "vk_check.h"
#include "vk_commands.h"
#include "vk_context.h"

namespace fs = std::filesystem;
using namespace qp;
using qp::test::createTestContext;
using qp::test::describeMessages;
using qp::test::testOutputDir;

namespace {

constexpr uint32_t kSize = 256;

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A UV sphere: smooth normals, 32 segments around, 16 rings.
void makeSphere(float radius, std::vector<MeshVertex>& vertices, std::vector<uint32_t>& indices) {
    const uint32_t segments = 32, rings = 16;
    for (uint32_t r = 0; r <= rings; ++r) {
        const float theta = float(M_PI) * float(r) / float(rings);
        for (uint32_t s = 0; s <= segments; ++s) {
            const float phi = 2.0f * float(M_PI) * float(s) / float(segments);
            glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
            vertices.push_back({radius * n, n});
        }
    }
    for (uint32_t r = 0; r < rings; ++r)
        for (uint32_t s = 0; s < segments; ++s) {
            const uint32_t a = r * (segments + 1) + s, b = a + segments + 1;
            indices.insert(indices.end(), {a, b, a + 1, a + 1, b, b + 1});
        }
}

// An axis-aligned square in the plane z = `z`, facing +Z.
void makeQuad(float halfSize, float z, std::vector<MeshVertex>& vertices, std::vector<uint32_t>& indices) {
    const glm::vec3 n(0, 0, 1);
    vertices = {{{-halfSize, -halfSize, z}, n}, {{halfSize, -halfSize, z}, n},
                {{halfSize, halfSize, z}, n},   {{-halfSize, halfSize, z}, n}};
    indices = {0, 1, 2, 0, 2, 3};
}

struct Rgba {
    uint8_t r, g, b, a;
};

Rgba pixelAt(const std::vector<uint8_t>& pixels, uint32_t x, uint32_t y) {
    const uint8_t* p = &pixels[(size_t(y) * kSize + x) * 4];
    return {p[0], p[1], p[2], p[3]};
}

uint8_t srgbByte(float linear) {
    const float c = linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
    return uint8_t(std::lround(c * 255.0f));
}

bool near(uint8_t a, uint8_t b, int tolerance = 1) { return std::abs(int(a) - int(b)) <= tolerance; }


// One validated context per test; TearDown destroys it and asserts that the validation layer
// stayed silent throughout, teardown included.
class RenderTest : public ::testing::Test {
protected:
    void SetUp() override {
        const auto start = std::chrono::steady_clock::now();
        Result<VulkanContext> created = createTestContext();
        contextSeconds_ = secondsSince(start);
        ASSERT_TRUE(created.ok()) << "Vulkan must work here (lavapipe is a declared dependency): "
                                  << created.error().message;
        ctx_ = std::move(*created);
    }
    void TearDown() override {
        if (!ctx_.validation) return;
        destroyContext(ctx_);
        EXPECT_EQ(validationMessageCount(ctx_), 0u) << describeMessages(ctx_);
    }

    // Renders `draws` into `target` and reads it back.
    std::vector<uint8_t> render(const MeshPass& pass, const OffscreenTarget& target, const MeshView& view,
                                std::span<const MeshDraw> draws) {
        Status drawn = submitAndWait(ctx_, [&](VkCommandBuffer cmd) { recordMeshPass(cmd, pass, renderTarget(target), view, draws); });
        EXPECT_TRUE(drawn.ok()) << (drawn ? "" : drawn.error().message);
        Result<std::vector<uint8_t>> pixels = readPixels(ctx_, target);
        EXPECT_TRUE(pixels.ok()) << (pixels ? "" : pixels.error().message);
        return pixels ? *pixels : std::vector<uint8_t>(size_t(target.width) * target.height * 4);
    }

    VulkanContext ctx_;
    double contextSeconds_ = 0;
};

using RenderContext = RenderTest;
using RenderMesh = RenderTest;
using RenderPipelineCache = RenderTest;

TEST_F(RenderContext, CreatesValidatedVulkan13Device) {
    std::printf("[ timing ] context creation (validation on): %.3f s on %s\n", contextSeconds_, ctx_.deviceName.c_str());
    RecordProperty("context_seconds", std::to_string(contextSeconds_));
    EXPECT_NE(ctx_.device, VK_NULL_HANDLE);
    EXPECT_NE(ctx_.queue, VK_NULL_HANDLE);
    EXPECT_NE(ctx_.commandPool, VK_NULL_HANDLE);
    EXPECT_NE(ctx_.debugMessenger, VK_NULL_HANDLE);
    EXPECT_GE(ctx_.properties.apiVersion, VK_API_VERSION_1_3);
    EXPECT_FALSE(ctx_.deviceName.empty());
    if (!std::getenv("QUADPLAN_VK_DEVICE")) {
        EXPECT_TRUE(ctx_.isSoftware) << ctx_.deviceName;
        EXPECT_NE(ctx_.deviceName.find("llvmpipe"), std::string::npos) << ctx_.deviceName;
        // Lavapipe has all of these (platform notes); the renderer relies on them there.
        EXPECT_TRUE(ctx_.features.tessellationShader);
        EXPECT_TRUE(ctx_.features.geometryShader);
        EXPECT_TRUE(ctx_.features.fillModeNonSolid);
        EXPECT_TRUE(ctx_.features.wideLines);
        EXPECT_TRUE(ctx_.features.pipelineStatisticsQuery);
        EXPECT_TRUE(ctx_.features.shaderFloat64);
    }
}

TEST_F(RenderContext, ImpossibleDeviceIsAnErrorValue) {
    ContextOptions options;
    options.forceDevice = "no such device, surely";
    Result<VulkanContext> none = createContext(options);
    ASSERT_FALSE(none.ok());
    EXPECT_NE(none.error().message.find("no usable Vulkan device"), std::string::npos) << none.error().message;
}

// The zero-message assertions mean something only if messages are caught: provoke one (an
// unknown flag bit, harmless to the driver) in a context of its own.
TEST_F(RenderContext, ValidationMessagesAreCounted) {
    Result<VulkanContext> other = createTestContext();
    ASSERT_TRUE(other.ok()) << other.error().message;
    VkFenceCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
    info.flags = 0x80;  // no such VkFenceCreateFlagBits
    VkFence fence = VK_NULL_HANDLE;
    std::fprintf(stderr, "(the next validation error is expected)\n");
    if (vkCreateFence(other->device, &info, nullptr, &fence) == VK_SUCCESS) vkDestroyFence(other->device, fence, nullptr);
    EXPECT_EQ(validationMessageCount(*other), 1u);
    ASSERT_FALSE(validationMessages(*other).empty());
    EXPECT_NE(validationMessages(*other)[0].find("VUID-VkFenceCreateInfo-flags-parameter"), std::string::npos)
        << validationMessages(*other)[0];
    destroyContext(*other);
}

// QUADPLAN_VALIDATE (the test command sets it) validates contexts that did not ask for it, such
// as the commands' and the editor's, and a message in one ends the process with status 4.
TEST(RenderValidationFromEnvironment, AMessageEndsTheProcessWithStatus4) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    auto provokeOneMessage = [] {
        setenv("QUADPLAN_VALIDATE", "1", 1);
        ContextOptions options;  // validation not asked for
        if (!test::selectTestDevice(options)) std::_Exit(1);
        Result<VulkanContext> ctx = createContext(options);
        if (!ctx) std::_Exit(2);
        VkFenceCreateInfo info{};
        info.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
        info.flags = 0x80;  // no such VkFenceCreateFlagBits
        VkFence fence = VK_NULL_HANDLE;
        if (vkCreateFence(ctx->device, &info, nullptr, &fence) == VK_SUCCESS) vkDestroyFence(ctx->device, fence, nullptr);
        destroyContext(*ctx);
        std::_Exit(0);
    };
    EXPECT_EXIT(provokeOneMessage(), testing::ExitedWithCode(4), "1 Vulkan validation message\\(s\\) with QUADPLAN_VALIDATE");
}

TEST(RenderVkCheck, ReturnsAnErrorNamingTheExpressionAndResult) {
    auto fails = []() -> Status {
        VK_CHECK(VK_ERROR_DEVICE_LOST);
        return success();
    };
    Status status = fails();
    ASSERT_FALSE(status.ok());
    EXPECT_EQ(status.error().message, "VK_ERROR_DEVICE_LOST failed: VK_ERROR_DEVICE_LOST");
    EXPECT_EQ(vkError("vkQueueSubmit2(queue, 1, &submit, fence)", VK_ERROR_OUT_OF_DEVICE_MEMORY).message,
              "vkQueueSubmit2(queue, 1, &submit, fence) failed: VK_ERROR_OUT_OF_DEVICE_MEMORY");
}

TEST_F(RenderMesh, LitSphereWithWireframe) {
    std::vector<MeshVertex> vertices;
    std::vector<uint32_t> indices;
    makeSphere(1.0f, vertices, indices);
    Result<GpuMesh> mesh = uploadMesh(ctx_, vertices, indices);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    Result<OffscreenTarget> target = createOffscreenTarget(ctx_, kSize, kSize);
    ASSERT_TRUE(target.ok()) << target.error().message;
    Result<MeshPass> pass = createMeshPass(ctx_, VK_NULL_HANDLE, target->color.format);
    ASSERT_TRUE(pass.ok()) << pass.error().message;

    const RenderCamera camera = frameBounds(glm::vec3(-1.0f), glm::vec3(1.0f), 1.0f);
    MeshView view{viewProjection(camera), camera.eye, glm::vec3(0.60f, 0.65f, 0.70f)};
    MeshDraw draw;
    draw.mesh = &*mesh;
    draw.color = glm::vec3(0.80f, 0.45f, 0.20f);
    draw.wireframe = true;
    std::vector<uint8_t> pixels = render(*pass, *target, view, {&draw, 1});

    // Background: the clear colour, sRGB-encoded by the target.
    const Rgba corner = pixelAt(pixels, 0, 0);
    EXPECT_TRUE(near(corner.r, srgbByte(0.60f)) && near(corner.g, srgbByte(0.65f)) && near(corner.b, srgbByte(0.70f)))
        << int(corner.r) << "," << int(corner.g) << "," << int(corner.b);
    EXPECT_EQ(corner.a, 255);
    // The centre faces the headlight: bright and orange (red > green > blue), not background.
    // Sample just beside the exact centre, where a wire may pass.
    int lit = 0;
    for (uint32_t y = 120; y < 136; ++y)
        for (uint32_t x = 120; x < 136; ++x) {
            const Rgba p = pixelAt(pixels, x, y);
            lit += p.r > 180 && p.r > p.g && p.g > p.b;
        }
    EXPECT_GT(lit, 16 * 16 / 2) << "the centre of the sphere is not lit";
    // Coverage, and the wireframe: dark lines over the sphere.
    int covered = 0, wire = 0;
    for (uint32_t y = 0; y < kSize; ++y)
        for (uint32_t x = 0; x < kSize; ++x) {
            const Rgba p = pixelAt(pixels, x, y);
            covered += !(near(p.r, corner.r, 2) && near(p.g, corner.g, 2) && near(p.b, corner.b, 2));
            wire += std::max({p.r, p.g, p.b}) < 50;
        }
    const double coverage = double(covered) / (kSize * kSize);
    // frameBounds fits the box's bounding sphere (radius sqrt 3): the unit sphere covers about
    // pi / 4 / 3 = 26% of the image.
    EXPECT_GT(coverage, 0.18);
    EXPECT_LT(coverage, 0.35);
    EXPECT_GT(wire, int(0.01 * kSize * kSize)) << "no wireframe overlay";

    // For a person to look at.
    const fs::path tempPng = fs::path(::testing::TempDir()) / ("quadplan-render-sphere-" + std::to_string(getpid()) + ".png");
    for (const fs::path& path : {tempPng, testOutputDir() / "render_sphere.png"}) {
        Status written = writePng(path.string(), kSize, kSize, pixels);
        ASSERT_TRUE(written.ok()) << written.error().message;
        Result<std::string> file = readFile(path.string());
        ASSERT_TRUE(file.ok());
        EXPECT_EQ(file->substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << path;
    }
    fs::remove(tempPng);

    destroyMeshPass(ctx_, *pass);
    destroyOffscreenTarget(ctx_, *target);
    destroyMesh(ctx_, *mesh);
}

TEST_F(RenderMesh, DepthTestHidesFartherQuadInEitherOrder) {
    std::vector<MeshVertex> vertices;
    std::vector<uint32_t> indices;
    makeQuad(0.5f, 0.5f, vertices, indices);  // near, small, red
    Result<GpuMesh> nearQuad = uploadMesh(ctx_, vertices, indices);
    makeQuad(1.0f, -0.5f, vertices, indices);  // far, large, green
    Result<GpuMesh> farQuad = uploadMesh(ctx_, vertices, indices);
    ASSERT_TRUE(nearQuad.ok() && farQuad.ok());
    // UNORM this time: the shader encodes sRGB itself.
    Result<OffscreenTarget> target = createOffscreenTarget(ctx_, kSize, kSize, VK_FORMAT_R8G8B8A8_UNORM);
    ASSERT_TRUE(target.ok()) << target.error().message;
    Result<MeshPass> pass = createMeshPass(ctx_, VK_NULL_HANDLE, target->color.format);
    ASSERT_TRUE(pass.ok()) << pass.error().message;

    RenderCamera camera;  // straight down -Z from z = 3
    camera.eye = glm::vec3(0, 0, 3);
    camera.nearZ = 0.5f;
    camera.farZ = 10.0f;
    const MeshView view{viewProjection(camera), camera.eye, glm::vec3(0.0f, 0.0f, 1.0f)};
    MeshDraw red{&*nearQuad, glm::vec3(1, 0, 0), false};
    MeshDraw green{&*farQuad, glm::vec3(0, 1, 0), false};

    // Drawn near-first and far-first into the same target: the result must not depend on order.
    for (bool redFirst : {true, false}) {
        SCOPED_TRACE(redFirst ? "red drawn first" : "green drawn first");
        const MeshDraw draws[2] = {redFirst ? red : green, redFirst ? green : red};
        std::vector<uint8_t> pixels = render(*pass, *target, view, draws);
        const Rgba centre = pixelAt(pixels, kSize / 2, kSize / 2);
        EXPECT_TRUE(centre.r == 255 && centre.g == 0 && centre.b == 0)
            << int(centre.r) << "," << int(centre.g) << "," << int(centre.b);
        // Beside the red quad (half-width ~70 px) but inside the green one (~100 px).
        const Rgba side = pixelAt(pixels, kSize / 2 + 85, kSize / 2);
        EXPECT_TRUE(side.r == 0 && side.g == 255 && side.b == 0) << int(side.r) << "," << int(side.g) << "," << int(side.b);
        const Rgba corner = pixelAt(pixels, 2, 2);
        EXPECT_TRUE(corner.r == 0 && corner.g == 0 && corner.b == 255);
    }

    destroyMeshPass(ctx_, *pass);
    destroyOffscreenTarget(ctx_, *target);
    destroyMesh(ctx_, *nearQuad);
    destroyMesh(ctx_, *farQuad);
}

// A colour stream replaces the draw's colour per vertex (heat maps); a plain mesh drawn in the
// same pass keeps its own colour.
TEST_F(RenderMesh, ColourStreamGivesPerVertexColours) {
    std::vector<MeshVertex> vertices;
    std::vector<uint32_t> indices;
    makeQuad(1.0f, 0.0f, vertices, indices);
    // Left edge red, right edge green: the centre is the mix, each side its own colour.
    const std::vector<glm::vec3> colors = {{1, 0, 0}, {0, 1, 0}, {0, 1, 0}, {1, 0, 0}};
    Result<GpuMesh> colored = uploadMesh(ctx_, vertices, indices, colors);
    makeQuad(0.1f, 0.5f, vertices, indices);
    Result<GpuMesh> plain = uploadMesh(ctx_, vertices, indices);
    ASSERT_TRUE(colored.ok() && plain.ok());
    Result<OffscreenTarget> target = createOffscreenTarget(ctx_, kSize, kSize, VK_FORMAT_R8G8B8A8_UNORM);
    ASSERT_TRUE(target.ok()) << target.error().message;
    Result<MeshPass> pass = createMeshPass(ctx_, VK_NULL_HANDLE, target->color.format);
    ASSERT_TRUE(pass.ok()) << pass.error().message;
    ASSERT_NE(pass->solidColored, VK_NULL_HANDLE);

    RenderCamera camera;
    camera.eye = glm::vec3(0, 0, 3);
    camera.nearZ = 0.5f;
    camera.farZ = 10.0f;
    const MeshView view{viewProjection(camera), camera.eye, glm::vec3(0.0f, 0.0f, 1.0f)};
    const MeshDraw draws[2] = {MeshDraw{&*colored, glm::vec3(1.0f), false}, MeshDraw{&*plain, glm::vec3(0, 0, 1), false}};
    std::vector<uint8_t> pixels = render(*pass, *target, view, draws);
    const Rgba left = pixelAt(pixels, kSize / 2 - 60, kSize / 2);
    const Rgba right = pixelAt(pixels, kSize / 2 + 60, kSize / 2);
    const Rgba centre = pixelAt(pixels, kSize / 2, kSize / 2);
    EXPECT_TRUE(left.r > 200 && left.g < 160 && left.b == 0) << int(left.r) << "," << int(left.g);
    EXPECT_TRUE(right.g > 200 && right.r < 160 && right.b == 0) << int(right.r) << "," << int(right.g);
    EXPECT_TRUE(centre.r == 0 && centre.g == 0 && centre.b == 255) << "the plain quad in front keeps its colour";

    destroyMeshPass(ctx_, *pass);
    destroyOffscreenTarget(ctx_, *target);
    destroyMesh(ctx_, *colored);
    destroyMesh(ctx_, *plain);
}

uint64_t fnv1a(const std::string& data, size_t from) {
    uint64_t hash = 0xcbf29ce484222325ull;
    for (size_t i = from; i < data.size(); ++i) hash = (hash ^ uint8_t(data[i])) * 0x100000001b3ull;
    return hash;
}

struct FirstDrawTiming {
    double create = 0;  // createMeshPass
    double total = 0;   // ... through the end of the first draw
};

// Times the mesh pass from its creation through `cache` to the end of its first draw: a driver
// may compile (JIT) pipelines at creation or at first use.
FirstDrawTiming timeFirstDraw(const VulkanContext& ctx, VkPipelineCache cache) {
    FirstDrawTiming timing;
    const auto start = std::chrono::steady_clock::now();
    Result<MeshPass> pass = createMeshPass(ctx, cache, VK_FORMAT_R8G8B8A8_SRGB);
    timing.create = secondsSince(start);
    EXPECT_TRUE(pass.ok()) << pass.error().message;
    if (!pass) return timing;
    std::vector<MeshVertex> vertices;
    std::vector<uint32_t> indices;
    makeQuad(0.5f, 0.0f, vertices, indices);
    Result<GpuMesh> mesh = uploadMesh(ctx, vertices, indices);
    Result<OffscreenTarget> target = createOffscreenTarget(ctx, 16, 16);
    EXPECT_TRUE(mesh.ok() && target.ok());
    if (mesh && target) {
        RenderCamera camera;
        camera.eye = glm::vec3(0, 0, 2);
        MeshDraw draw;
        draw.mesh = &*mesh;
        draw.wireframe = true;
        Status drawn = submitAndWait(ctx, [&](VkCommandBuffer cmd) {
            recordMeshPass(cmd, *pass, renderTarget(*target), MeshView{viewProjection(camera), camera.eye}, {&draw, 1});
        });
        EXPECT_TRUE(drawn.ok());
    }
    timing.total = secondsSince(start);
    if (target) destroyOffscreenTarget(ctx, *target);
    if (mesh) destroyMesh(ctx, *mesh);
    destroyMeshPass(ctx, *pass);
    return timing;
}

TEST_F(RenderPipelineCache, RoundTripsAndRejectsBadFiles) {
    const fs::path dir = fs::temp_directory_path() / ("quadplan-render-cache-" + std::to_string(getpid()));
    fs::remove_all(dir);
    const std::string path = (dir / "quadplan" / "pipelines.bin").string();  // directory made on save

    // No file yet: an empty cache, silently.
    std::vector<std::string> warnings;
    Result<PipelineCache> cold = loadPipelineCache(ctx_, path, &warnings);
    ASSERT_TRUE(cold.ok()) << cold.error().message;
    EXPECT_FALSE(cold->loadedFromFile);
    EXPECT_TRUE(warnings.empty());
    const FirstDrawTiming coldTiming = timeFirstDraw(ctx_, cold->cache);
    Status saved = savePipelineCache(ctx_, *cold);
    ASSERT_TRUE(saved.ok()) << saved.error().message;
    destroyPipelineCache(ctx_, *cold);
    ASSERT_TRUE(fs::exists(path));

    // A second context, as a second run of the program would have: the file is accepted.
    FirstDrawTiming warmTiming;
    {
        Result<VulkanContext> second = createTestContext();
        ASSERT_TRUE(second.ok()) << second.error().message;
        Result<PipelineCache> warm = loadPipelineCache(*second, path, &warnings);
        ASSERT_TRUE(warm.ok()) << warm.error().message;
        EXPECT_TRUE(warm->loadedFromFile);
        EXPECT_TRUE(warnings.empty()) << warnings.front();
        warmTiming = timeFirstDraw(*second, warm->cache);
        EXPECT_TRUE(savePipelineCache(*second, *warm).ok());
        destroyPipelineCache(*second, *warm);
        destroyContext(*second);
        EXPECT_EQ(validationMessageCount(*second), 0u) << describeMessages(*second);
    }
    std::printf("[ timing ] mesh pass (2 pipelines) creation / through first draw: %.3f / %.3f s without the cache, "
                "%.3f / %.3f s with it (%zu-byte cache file)\n",
                coldTiming.create, coldTiming.total, warmTiming.create, warmTiming.total, size_t(fs::file_size(path)));
    RecordProperty("pipeline_seconds_cold", std::to_string(coldTiming.total));
    RecordProperty("pipeline_seconds_cached", std::to_string(warmTiming.total));

    // Bad files are ignored with a warning, and the cache still works (empty).
    Result<std::string> good = readFile(path);
    ASSERT_TRUE(good.ok());
    std::string garbage(4096, '\0');
    for (size_t i = 0; i < garbage.size(); ++i) garbage[i] = char((i * 2654435761u) >> 13);
    std::string damaged = *good;
    damaged[damaged.size() / 2] ^= 0x5a;
    std::string foreign = *good;  // another device's cache, with a consistent hash
    foreign[24 + 16] ^= 0x01;     // Quadplan header (24 bytes), then pipelineCacheUUID at 16
    const uint64_t hash = fnv1a(foreign, 24);
    foreign.replace(16, 8, reinterpret_cast<const char*>(&hash), 8);
    const std::pair<std::string, std::string> cases[] = {
        {garbage, "not a Quadplan pipeline cache"},
        {damaged, "damaged"},
        {good->substr(0, good->size() - 7), "truncated"},
        {foreign, "another device"},
    };
    for (const auto& [contents, reason] : cases) {
        SCOPED_TRACE(reason);
        ASSERT_TRUE(writeFileAtomically(path, contents).ok());
        warnings.clear();
        Result<PipelineCache> rejected = loadPipelineCache(ctx_, path, &warnings);
        ASSERT_TRUE(rejected.ok()) << rejected.error().message;
        EXPECT_FALSE(rejected->loadedFromFile);
        ASSERT_EQ(warnings.size(), 1u);
        EXPECT_NE(warnings[0].find(reason), std::string::npos) << warnings[0];
        timeFirstDraw(ctx_, rejected->cache);
        destroyPipelineCache(ctx_, *rejected);
    }
    fs::remove_all(dir);
}

TEST(RenderPipelineCachePath, FollowsXdgCacheHome) {
    const char* old = std::getenv("XDG_CACHE_HOME");
    const std::string saved = old ? old : "";
    setenv("XDG_CACHE_HOME", "/somewhere/cache", 1);
    EXPECT_EQ(defaultPipelineCachePath(), "/somewhere/cache/quadplan/pipelines.bin");
    unsetenv("XDG_CACHE_HOME");
    if (const char* home = std::getenv("HOME")) {
        EXPECT_EQ(defaultPipelineCachePath(), std::string(home) + "/.cache/quadplan/pipelines.bin");
    }
    if (old) setenv("XDG_CACHE_HOME", saved.c_str(), 1);
}

}  // namespace
