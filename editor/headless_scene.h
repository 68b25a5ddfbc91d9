// The Vulkan side a headless command draws a scene with (render, animate): the context, the
// pipeline cache, one scheme instance per cage, an offscreen target and the cages' lines. Set up
// in one call and torn down in one, so each command writes only what it draws.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "camera.h"
#include "line_pass.h"
#include "mesh/result.h"
#include "offscreen_target.h"
#include "pipeline_cache.h"
#include "render_setup.h"
#include "scene/planned_scene.h"
#include "scene/scene.h"
#include "scene_schemes.h"
#include "scheme_loader.h"

namespace qp::cli {

// What a drawing command's scheme options give: the settings (the plan depth, `--path` as the
// option path=..., `--option KEY=VALUE` pairs, refused naming a malformed one) and the plugins of
// `pluginDir` (problems printed as warnings), refused, naming the schemes there, when `scheme`
// is not one of them.
struct SchemeChoice {
    SchemeSettings settings;
    PluginCatalog catalog;
};
Result<SchemeChoice> chooseScheme(uint32_t depth, const std::string& drawPath, const std::vector<std::string>& options,
                                  const std::string& pluginDir, const std::string& scheme);
// The tessellation: `tess` when set, else `adaptive` pixels when set, else the scene's.
void setTessellation(SchemeSettings& settings, uint32_t tess, float adaptive, const Tessellation& scene);

// The drawing options `render` and `animate` share, registered by addDrawOptions with the help
// texts both give (the camera's and the path's help differ per command).
struct DrawOptions {
    std::string scheme = "plans";
    std::string size = "800x600";
    uint32_t tess = 0;
    float adaptive = 0.0f;
    bool wire = false, noCage = false, validate = false;
    std::string colorBy = "shading";
    std::string camera, drawPath;
    std::vector<std::string> options;
    std::string pluginDir;
    uint32_t depth = 6;
};
void addDrawOptions(CLI::App& cmd, DrawOptions& draw, const std::string& cameraHelp, const std::string& pathHelp);

// What `render` and `animate` draw: the scheme `draw` chooses and the file planned at its depth
// (warnings printed), the plans in a database of their own.
struct DrawInput {
    SchemeChoice scheme;
    std::unique_ptr<PlanDatabase> database;  // on the heap: the planned scene points into it
    PlannedFile file;
};
Result<DrawInput> loadDrawInput(const std::string& path, const DrawOptions& draw);

struct HeadlessSceneRequest {
    const PluginCatalog* catalog = nullptr;
    std::string scheme;
    SchemeSettings settings;
    std::string source;  // the file, in messages
    uint32_t width = 0, height = 0;
    std::string colorBy;  // must be one of the scheme's colour modes
    bool validate = false;
};

struct HeadlessScene {
    VulkanContext ctx;  // heap-held with the rest: `gpu` points at it
    std::optional<PipelineCache> cache;
    GpuContext gpu;
    std::optional<SceneSchemes> schemes;
    std::optional<OffscreenTarget> target;
    std::optional<LinePass> lines;
    std::optional<SceneCageLines> cageLines;
    // Set when a step after the context failed, or the colour mode is unknown to the scheme: the
    // command reports it and draws nothing.
    std::string problem;
};

// Fails only when no Vulkan context can be made (then there is nothing to tear down). The
// pipeline cache's warnings and the scheme's approximations are printed as "warning: ...".
Result<std::unique_ptr<HeadlessScene>> createHeadlessScene(const HeadlessSceneRequest& request, const Scene& scene,
                                                           const PlannedScene& planned);

// The view of `camera` on an image `height` pixels high.
DrawView headlessView(const RenderCamera& camera, uint32_t height, const std::string& colorBy, bool wireframe);

// Tears everything down (saving the pipeline cache) and reports validation messages; returns the
// command's exit status given its own `status` so far (4 for validation messages, as documented).
int destroyHeadlessScene(HeadlessScene& headless, bool validate, int status);

}  // namespace qp::cli
