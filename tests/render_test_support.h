// Vulkan set-up shared by the rendering tests: lavapipe with validation on.
//
// Vulkan is a declared dependency (mesa-vulkan-drivers provides lavapipe): when it cannot be
// initialised the tests fail, they never skip. QUADPLAN_VK_DEVICE=<name part> runs them on
// another device instead of lavapipe.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "camera.h"
#include "plan_pass.h"
#include "plans/planned_cage.h"
#include "vk_context.h"

namespace qp::test {

constexpr const char* kLavapipeIcd = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";

// Plans a test cage (the test fails when it cannot).
inline PlannedCage planCage(const Cage& cage, PlanDatabase& database) {
    Result<PlannedCage> planned = PlannedCage::create(cage, database, {}, "test cage");
    EXPECT_TRUE(planned.ok()) << planned.error().message;
    return std::move(planned).value();
}

// Points `options` (and the loader) at the tests' device: lavapipe, or QUADPLAN_VK_DEVICE.
inline Status selectTestDevice(ContextOptions& options) {
    if (const char* device = std::getenv("QUADPLAN_VK_DEVICE"); device && device[0]) {
        options.forceDevice = device;
        return success();
    }
    if (!std::filesystem::exists(kLavapipeIcd))
        return Error{std::string(kLavapipeIcd) + " is missing: install mesa-vulkan-drivers (lavapipe)"};
    // Must happen before the loader looks for drivers, i.e. before the instance exists.
    setenv("VK_ICD_FILENAMES", kLavapipeIcd, 1);
    setenv("VK_DRIVER_FILES", kLavapipeIcd, 1);  // newer loaders prefer this name
    return success();
}

// `options` adds what a test needs beyond the defaults (e.g. window-system extensions).
inline Result<VulkanContext> createTestContext(ContextOptions options = {}) {
    options.validation = true;
    if (Status s = selectTestDevice(options); !s) return s.error();
    return createContext(options);
}

inline std::string describeMessages(const VulkanContext& ctx) {
    std::string text;
    for (const std::string& m : validationMessages(ctx)) text += "\n  " + m;
    return text;
}

// Where tests leave pictures for a person to look at: <build>/test-output (the binary is in
// <build>/bin).
inline std::filesystem::path testOutputDir() {
    std::filesystem::path dir =
        std::filesystem::read_symlink("/proc/self/exe").parent_path().parent_path() / "test-output";
    std::filesystem::create_directories(dir);
    return dir;
}

// A plan view framing `cage` (frameBounds' three-quarter view) on a square image `size` pixels high.
inline PlanView framedPlanView(const Cage& cage, uint32_t size) {
    const Bounds bounds = computeBounds(cage);
    const RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
    PlanView view;
    view.viewProjection = viewProjection(camera);
    view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(camera), size);
    return view;
}

// A test with the tests' device and a plan pass (R8G8B8A8, D32), that fails when validation
// said anything by its end; upload() gives a planned cage's buffers bound to the pass.
struct PlanPassTest : ::testing::Test {
    VulkanContext ctx;
    PlanPass pass;

    void SetUp() override {
        Result<VulkanContext> created = createTestContext();
        ASSERT_TRUE(created.ok()) << created.error().message;
        ctx = std::move(created).value();
        Result<PlanPass> p = createPlanPass(ctx, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM);
        ASSERT_TRUE(p.ok()) << p.error().message;
        pass = *p;
    }
    void TearDown() override {
        if (!ctx.device) return;
        destroyPlanPass(ctx, pass);
        destroyContext(ctx);
        EXPECT_EQ(validationMessageCount(ctx), 0u) << describeMessages(ctx);
    }
    PlanBuffers upload(const PlannedCage& planned) {
        Result<PlanBuffers> buffers = uploadPlans(ctx, planned);
        EXPECT_TRUE(buffers.ok()) << buffers.error().message;
        EXPECT_TRUE(bindPlanBuffers(ctx, pass, *buffers).ok());
        return std::move(buffers).value();
    }
};

}  // namespace qp::test
