// SwapchainTarget in a real GLFW window (X11; ctest runs this binary under xvfb-run): frames
// are presented through the same passes as offscreen ones, into sub-areas of the image, the
// presented image reads back as drawn, a resize recreates the swapchain, and the validation
// layer (synchronization validation on) stays silent.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "camera.h"
#include "mesh_pass.h"
#include "render_test_support.h"
#include "swapchain_target.h"

using namespace qp;

namespace {

// A flat square in z = 0 covering [-1, 1]^2: simple to check pixel by pixel.
GpuMesh makeSquare(const VulkanContext& ctx) {
    const MeshVertex vertices[] = {{{-1, -1, 0}, {0, 0, 1}}, {{1, -1, 0}, {0, 0, 1}},
                                   {{1, 1, 0}, {0, 0, 1}}, {{-1, 1, 0}, {0, 0, 1}}};
    const uint32_t indices[] = {0, 1, 2, 0, 2, 3};
    Result<GpuMesh> mesh = uploadMesh(ctx, vertices, indices);
    EXPECT_TRUE(mesh.ok()) << mesh.error().message;
    return mesh ? *mesh : GpuMesh{};
}

struct Rgb {
    int r, g, b;
};
Rgb pixel(const std::vector<uint8_t>& rgba, uint32_t width, uint32_t x, uint32_t y) {
    const uint8_t* p = &rgba[(size_t(y) * width + x) * 4];
    return {p[0], p[1], p[2]};
}
bool near(Rgb a, Rgb b, int tolerance = 3) {
    return std::abs(a.r - b.r) <= tolerance && std::abs(a.g - b.g) <= tolerance && std::abs(a.b - b.b) <= tolerance;
}

// GLFW is initialised once per process: on X11, GLFW 3.3 cannot always initialise again after
// glfwTerminate in the same process.
bool initGlfwOnce() {
    static const bool initialised = [] {
        glfwSetErrorCallback([](int code, const char* text) { std::fprintf(stderr, "GLFW error %d: %s\n", code, text); });
        const bool ok = glfwInit();
        if (ok) std::atexit(glfwTerminate);
        return ok;
    }();
    return initialised;
}

class SwapchainWindow : public ::testing::Test {
protected:
    GLFWwindow* window = nullptr;
    VulkanContext ctx;
    VkSurfaceKHR surface = VK_NULL_HANDLE;

    void SetUp() override {
        const char* display = std::getenv("DISPLAY");
        if (!display || !display[0])
            GTEST_SKIP() << "SKIPPED: DISPLAY is unset; run under xvfb-run (ctest does when xvfb-run is installed)";
        ASSERT_TRUE(initGlfwOnce()) << "glfwInit failed with DISPLAY=" << display;
        ASSERT_TRUE(glfwVulkanSupported()) << "GLFW finds no Vulkan loader";
        glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
        window = glfwCreateWindow(320, 240, "swapchain test", nullptr, nullptr);
        ASSERT_NE(window, nullptr);

        ContextOptions options;
        uint32_t count = 0;
        const char** extensions = glfwGetRequiredInstanceExtensions(&count);
        for (uint32_t i = 0; i < count; ++i) options.instanceExtensions.push_back(extensions[i]);
        options.deviceExtensions = swapchainDeviceExtensions();
        Result<VulkanContext> created = test::createTestContext(options);
        ASSERT_TRUE(created.ok()) << created.error().message;
        ctx = std::move(created).value();
        ASSERT_EQ(glfwCreateWindowSurface(ctx.instance, window, nullptr, &surface), VK_SUCCESS);
    }

    void TearDown() override {
        if (surface) vkDestroySurfaceKHR(ctx.instance, surface, nullptr);
        if (ctx.device) {
            destroyContext(ctx);
            EXPECT_EQ(validationMessageCount(ctx), 0u) << test::describeMessages(ctx);
        }
        if (window) glfwDestroyWindow(window);
    }

    std::pair<uint32_t, uint32_t> framebufferSize() {
        int w = 0, h = 0;
        glfwGetFramebufferSize(window, &w, &h);
        return {uint32_t(w), uint32_t(h)};
    }

    // One frame: the left half cleared to `left` with the square drawn in white over it, the
    // right half cleared to `right` (two viewports of one image). Returns the read-back image
    // when asked.
    std::vector<uint8_t> drawFrame(SwapchainTarget& swap, const MeshPass& pass, const GpuMesh& square, glm::vec3 left,
                                   glm::vec3 right, bool readBack) {
        glfwPollEvents();
        auto [w, h] = framebufferSize();
        Result<std::optional<SwapchainFrame>> frame = beginFrame(ctx, swap, w, h);
        EXPECT_TRUE(frame.ok()) << frame.error().message;
        if (!frame || !*frame) return {};
        const RenderTarget whole = (*frame)->target;
        const uint32_t half = whole.width / 2;
        RenderCamera camera;
        camera.eye = {0, 0, 4};
        camera.aspect = float(half) / float(whole.height);
        MeshView view;
        view.viewProjection = viewProjection(camera);
        view.eye = camera.eye;
        view.background = left;
        MeshDraw draw{&square, glm::vec3(1.0f), false};
        recordMeshPass((*frame)->cmd, pass, subArea(whole, {{0, 0}, {half, whole.height}}), view, {&draw, 1});
        view.background = right;
        recordMeshPass((*frame)->cmd, pass, subArea(whole, {{int32_t(half), 0}, {whole.width - half, whole.height}}),
                       view, {});
        std::vector<uint8_t> pixels;
        Status ended = endFrame(ctx, swap, **frame, readBack ? &pixels : nullptr);
        EXPECT_TRUE(ended.ok()) << ended.error().message;
        return pixels;
    }
};

TEST_F(SwapchainWindow, PresentsViewportsReadsBackAndSurvivesResize) {
    auto [w, h] = framebufferSize();
    Result<SwapchainTarget> created = createSwapchainTarget(ctx, surface, w, h);
    ASSERT_TRUE(created.ok()) << created.error().message;
    SwapchainTarget swap = std::move(created).value();
    EXPECT_TRUE(swap.surfaceFormat.format == VK_FORMAT_B8G8R8A8_UNORM ||
                swap.surfaceFormat.format == VK_FORMAT_R8G8B8A8_UNORM);
    EXPECT_GE(swap.images.size(), 2u);

    Result<MeshPass> pass = createMeshPass(ctx, VK_NULL_HANDLE, swap.surfaceFormat.format);
    ASSERT_TRUE(pass.ok()) << pass.error().message;
    GpuMesh square = makeSquare(ctx);

    // Several frames, more than the frames in flight and the images, so every slot and image
    // is reused; the last one is read back. Pure primaries survive sRGB encoding exactly.
    const glm::vec3 red(1, 0, 0), blue(0, 0, 1), green(0, 1, 0);
    std::vector<uint8_t> pixels;
    for (int i = 0; i < 8; ++i) pixels = drawFrame(swap, *pass, square, red, blue, i == 7);
    ASSERT_EQ(pixels.size(), size_t(swap.extent.width) * swap.extent.height * 4);
    const uint32_t W = swap.extent.width, H = swap.extent.height;
    EXPECT_TRUE(near(pixel(pixels, W, 3, 3), {255, 0, 0}));           // left viewport background
    EXPECT_TRUE(near(pixel(pixels, W, W / 4, H / 2), {255, 255, 255}));  // the square, centred on the left
    EXPECT_TRUE(near(pixel(pixels, W, W - 4, H - 4), {0, 0, 255}));   // right viewport
    EXPECT_TRUE(near(pixel(pixels, W, 3 * W / 4, H / 2), {0, 0, 255}));
    ASSERT_TRUE(writePng((test::testOutputDir() / "swapchain_320x240.png").string(), W, H, pixels).ok());

    // Resize: the next frames recreate the swapchain at the new size.
    const uint32_t generation = swap.generation;
    glfwSetWindowSize(window, 400, 300);
    for (int i = 0; i < 100 && framebufferSize() != std::pair<uint32_t, uint32_t>{400, 300}; ++i) glfwWaitEventsTimeout(0.02);
    ASSERT_EQ(framebufferSize(), (std::pair<uint32_t, uint32_t>{400, 300})) << "the window manager refused the resize";
    for (int i = 0; i < 4; ++i) pixels = drawFrame(swap, *pass, square, green, red, i == 3);
    EXPECT_GT(swap.generation, generation);
    EXPECT_EQ(swap.extent.width, 400u);
    EXPECT_EQ(swap.extent.height, 300u);
    ASSERT_EQ(pixels.size(), size_t(400) * 300 * 4);
    EXPECT_TRUE(near(pixel(pixels, 400, 3, 3), {0, 255, 0}));
    EXPECT_TRUE(near(pixel(pixels, 400, 100, 150), {255, 255, 255}));
    EXPECT_TRUE(near(pixel(pixels, 400, 396, 296), {255, 0, 0}));
    ASSERT_TRUE(writePng((test::testOutputDir() / "swapchain_400x300.png").string(), 400, 300, pixels).ok());

    destroyMesh(ctx, square);
    destroyMeshPass(ctx, *pass);
    destroySwapchainTarget(ctx, swap);
}

// A window with no area (minimised) gives no frame and no error.
TEST_F(SwapchainWindow, ZeroSizedWindowSkipsTheFrame) {
    auto [w, h] = framebufferSize();
    Result<SwapchainTarget> created = createSwapchainTarget(ctx, surface, w, h);
    ASSERT_TRUE(created.ok()) << created.error().message;
    SwapchainTarget swap = std::move(created).value();
    Result<std::optional<SwapchainFrame>> frame = beginFrame(ctx, swap, 0, 0);
    ASSERT_TRUE(frame.ok());
    EXPECT_FALSE(frame->has_value());
    destroySwapchainTarget(ctx, swap);
}

}  // namespace
