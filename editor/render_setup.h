// What the commands share: loading and planning a file; and for the headless drawing ones
// (render, compare, export's adaptive density) image size and camera options, the Vulkan
// context, and the scheme plugins' settings.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "camera.h"
#include "mesh/cage.h"
#include "mesh/result.h"
#include "scene/planned_scene.h"
#include "scene/scene.h"
#include "scheme_api.h"
#include "surface_error.h"
#include "vk_context.h"

namespace qp::cli {

// A scene or cage file (loadSceneOrCage); the reader's warnings go to stderr as "warning: ...".
Result<Scene> loadSceneWarning(const std::string& path);

// A scene or cage file, planned with `options` through `database` (every command's first step);
// the reader's warnings go to stderr as "warning: ...".
struct PlannedFile {
    Scene scene;
    PlannedScene planned;
};
Result<PlannedFile> loadAndPlan(const std::string& path, PlanDatabase& database, const PlanOptions& options);

// "WIDTHxHEIGHT", each side 16..8192.
bool parseSize(const std::string& text, uint32_t& width, uint32_t& height);

// The camera for a view of `aspect`: `cameraText` ("EX,EY,EZ,TX,TY,TZ[,FOV_DEGREES]") when
// given, else the scene's, else framed on the bounds; near and far planes hold the whole cage.
Result<RenderCamera> chooseCamera(const Scene& scene, const Bounds& bounds, float aspect, const std::string& cameraText);

// A headless context: lavapipe unless a GPU is present or QUADPLAN_VK_DEVICE names a device.
Result<VulkanContext> createHeadlessContext(bool validation);

// Prints validation messages; true when there were any.
bool reportValidation(const VulkanContext& context);

// One scheme's numbers, as `quadplan compare` and the Python module's compare compute them.
struct SchemeComparison {
    std::string name;
    bool drawn = false;
    std::string reason;  // why not, when not drawn
    std::vector<std::string> approximations;
    ErrorStats error;
    DrawStats draw;
    SchemeStats stats;
    double frameMs = 0.0, drawMs = 0.0, setupMs = 0.0;
};

// "key=value" scheme options, as given to --option; fails with a message naming the text.
Result<std::pair<std::string, std::string>> parseOption(const std::string& text);

}  // namespace qp::cli
