// HeadlessRenderer: one Vulkan context and the scheme plugins, for the Python module's
// rendering, error heat maps and scheme comparisons. Offscreen only (no window, no GLFW).
//
// Each call prepares the scheme for the document's current cage (as `quadplan render` does),
// draws into an offscreen target of the requested size, reads the pixels back and releases
// everything it created, so a renderer serves any number of scenes. With validation on, any
// validation message during a call makes that call fail with the messages.
// Cameras follow `quadplan render`: the given one, else the scene's, else framed on the cage
// (editor/render_setup.h: chooseCamera), with near and far planes holding the whole cage.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "camera.h"
#include "line_pass.h"
#include "mesh_pass.h"
#include "pipeline_cache.h"
#include "render_setup.h"
#include "scene_document.h"
#include "scheme_loader.h"
#include "surface_error.h"

namespace qp::py {

using cli::SchemeComparison;  // one scheme's numbers, as `quadplan compare` computes them

struct RendererOptions {
    bool validation = false;
    std::string device;     // part of a device name; empty: $QUADPLAN_VK_DEVICE, else any (GPU first)
    bool lavapipe = false;  // use Mesa's lavapipe (CPU) only: deterministic pictures for tests
    std::string pluginDir;  // empty: $QUADPLAN_PLUGIN_DIR, else the module's default
};

using SchemeOptions = std::vector<std::pair<std::string, std::string>>;

struct RenderRequest {
    std::string scheme = "plans";
    uint32_t width = 800, height = 600;
    std::optional<Camera> camera;  // absent: the scene's camera, else framed on the cage
    uint32_t tess = 0;             // uniform factor; 0 with adaptive 0: the scene's tessellation settings
    float adaptive = 0.0f;         // target pixels per segment
    bool wireframe = false;
    std::optional<bool> showCage;  // absent: the scene's setting
    std::string colorBy = "shading";
    SchemeOptions options;
    CullMethod cull = CullMethod::None;  // DrawView::cull (render only)
};

struct RenderedImage {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> rgba;  // rows top to bottom
    DrawStats draw;
    std::vector<std::string> approximations;  // what the scheme approximates on this cage
};

struct CompareRequest {
    std::vector<std::string> schemes;  // empty: every loaded scheme
    uint32_t tileWidth = 360, tileHeight = 300;
    uint32_t tess = 8, samples = 16, depth = 6, repeats = 5;
    std::optional<Camera> camera;
    std::vector<std::pair<std::string, std::pair<std::string, std::string>>> options;  // scheme, key, value
};

class HeadlessRenderer {
public:
    static Result<std::unique_ptr<HeadlessRenderer>> create(const RendererOptions& options);
    ~HeadlessRenderer();
    HeadlessRenderer(const HeadlessRenderer&) = delete;
    HeadlessRenderer& operator=(const HeadlessRenderer&) = delete;

    const std::string& deviceName() const { return context_.deviceName; }
    bool isSoftware() const { return context_.isSoftware; }
    bool validation() const { return validation_; }
    const PluginCatalog& catalog() const { return catalog_; }

    // The surface through a scheme, with the cage drawn over it when asked.
    Result<RenderedImage> render(const SceneDocument& document, const RenderRequest& request);
    // The displaced surface (CPU mesh at the factor that shows every sample, as
    // `quadplan sculpt --png`), lit, with the cage over it when asked.
    Result<RenderedImage> renderDisplaced(const SceneDocument& document, const RenderRequest& request);
    // A scheme's error against the exact limit surface on a grid of `samples` segments per
    // sub-face edge, coloured on compare's logarithmic heat scale (surface_error.h).
    Result<RenderedImage> renderError(const SceneDocument& document, const RenderRequest& request, uint32_t samples,
                                      ErrorStats* stats);
    // Every requested scheme's error, timings and statistics (`quadplan compare`'s numbers).
    Result<std::vector<SchemeComparison>> compare(const SceneDocument& document, const CompareRequest& request);

private:
    HeadlessRenderer() = default;
    Status checkValidation(uint32_t before) const;
    Result<RenderCamera> cameraFor(const SceneDocument& document, const std::optional<Camera>& camera, uint32_t width,
                                   uint32_t height) const;
    GpuContext gpu() const;

    VulkanContext context_;
    bool validation_ = false;
    PluginCatalog catalog_;
    std::optional<PipelineCache> cache_;
    std::optional<LinePass> lines_;
    std::optional<MeshPass> meshes_;
};

// The default directory the module looks for plugins in, set by the package at import
// (python/quadplan/__init__.py); $QUADPLAN_PLUGIN_DIR wins over it.
void setDefaultPluginDirectory(const std::string& directory);
std::string defaultPluginDirectory();

}  // namespace qp::py
