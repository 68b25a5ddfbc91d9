#include "render_setup.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace qp::cli {

namespace {

// "EX,EY,EZ,TX,TY,TZ[,FOV_DEGREES]"
std::optional<RenderCamera> parseCamera(const std::string& text, float aspect) {
    std::vector<float> values;
    size_t start = 0;
    while (start <= text.size()) {
        size_t comma = text.find(',', start);
        std::string part = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        char* end = nullptr;
        float value = std::strtof(part.c_str(), &end);
        if (part.empty() || *end != '\0' || !std::isfinite(value)) return std::nullopt;
        values.push_back(value);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    if (values.size() != 6 && values.size() != 7) return std::nullopt;
    RenderCamera c;
    c.eye = {values[0], values[1], values[2]};
    c.target = {values[3], values[4], values[5]};
    if (values.size() == 7) c.fovY = glm::radians(values[6]);
    c.aspect = aspect;
    return c;
}

RenderCamera fromScene(const Camera& sceneCamera, float aspect) {
    RenderCamera c;
    c.eye = sceneCamera.eye;
    c.target = sceneCamera.target;
    c.up = sceneCamera.up;
    c.fovY = glm::radians(sceneCamera.fovYDegrees);
    c.aspect = aspect;
    c.orthographic = sceneCamera.projection == Projection::Orthographic;
    c.orthoHeight = sceneCamera.orthoHeight;
    return c;
}

// Near and far planes that hold the whole cage, whichever way the camera looks.
void fitDepthRange(RenderCamera& camera, const Bounds& bounds) {
    const float radius = std::max(0.5f * bounds.diagonal(), 1e-4f);
    const float distance = glm::length(0.5f * (bounds.min + bounds.max) - camera.eye);
    camera.farZ = distance + 2.0f * radius;
    camera.nearZ = std::max(distance - 2.0f * radius, camera.farZ * 1e-4f);
}

}  // namespace

bool parseSize(const std::string& text, uint32_t& width, uint32_t& height) {
    unsigned w = 0, h = 0;
    char x = 0;
    if (std::sscanf(text.c_str(), "%u%c%u", &w, &x, &h) != 3 || (x != 'x' && x != 'X')) return false;
    if (w < 16 || h < 16 || w > 8192 || h > 8192) return false;
    width = w;
    height = h;
    return true;
}

Result<Scene> loadSceneWarning(const std::string& path) {
    std::vector<std::string> warnings;
    Result<Scene> scene = loadSceneOrCage(path, &warnings);
    for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    return scene;
}

Result<PlannedFile> loadAndPlan(const std::string& path, PlanDatabase& database, const PlanOptions& options) {
    Result<Scene> scene = loadSceneWarning(path);
    if (!scene) return scene.error();
    Result<PlannedScene> planned = PlannedScene::create(*scene, database, options, path);
    if (!planned) return planned.error();
    return PlannedFile{std::move(scene).value(), std::move(planned).value()};
}

Result<RenderCamera> chooseCamera(const Scene& scene, const Bounds& bounds, float aspect, const std::string& cameraText) {
    RenderCamera camera = frameBounds(bounds.min, bounds.max, aspect);
    if (!cameraText.empty()) {
        std::optional<RenderCamera> parsed = parseCamera(cameraText, aspect);
        if (!parsed) return Error{"--camera must be EX,EY,EZ,TX,TY,TZ[,FOV_DEGREES], got '" + cameraText + "'"};
        camera = *parsed;
        fitDepthRange(camera, bounds);
    } else if (scene.camera) {
        camera = fromScene(*scene.camera, aspect);
        fitDepthRange(camera, bounds);
    }
    return camera;
}

Result<VulkanContext> createHeadlessContext(bool validation) {
    ContextOptions options;
    options.validation = validation;
    if (const char* device = std::getenv("QUADPLAN_VK_DEVICE")) options.forceDevice = device;
    Result<VulkanContext> context = createContext(options);
    if (!context) return Error{"cannot start Vulkan: " + context.error().message};
    return context;
}

bool reportValidation(const VulkanContext& context) {
    if (validationMessageCount(context) == 0) return false;
    for (const std::string& m : validationMessages(context)) std::fprintf(stderr, "validation: %s\n", m.c_str());
    return true;
}

Result<std::pair<std::string, std::string>> parseOption(const std::string& text) {
    const size_t equals = text.find('=');
    if (equals == std::string::npos || equals == 0)
        return Error{"--option must be KEY=VALUE (or SCHEME:KEY=VALUE for compare), got '" + text + "'"};
    return std::make_pair(text.substr(0, equals), text.substr(equals + 1));
}

}  // namespace qp::cli
