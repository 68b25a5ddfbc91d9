#include "headless_scene.h"

#include <algorithm>
#include <cstdio>

#include "plan_pass.h"
#include "render_setup.h"

namespace qp::cli {

namespace {

// Each step after the context; the first failure is kept as the problem.
std::string setUp(HeadlessScene& h, const HeadlessSceneRequest& request, const Scene& scene, const PlannedScene& planned) {
    Result<SceneSchemes> schemes =
        prepareSceneSchemes(*request.catalog, request.scheme, scene, planned, request.settings, h.gpu, request.source);
    if (!schemes) return schemes.error().message;
    h.schemes = std::move(schemes).value();
    Result<std::vector<std::string>> modes = h.schemes->cages.front().instance.colorModes();
    if (!modes) return modes.error().message;
    const VkFormat format = h.gpu.colorFormat;
    Result<OffscreenTarget> target = createOffscreenTarget(h.ctx, request.width, request.height, format);
    if (!target) return "cannot set up the renderer: " + target.error().message;
    h.target = *target;
    Result<LinePass> lines = createLinePass(h.ctx, h.gpu.cache, format);
    if (!lines) return "cannot set up the renderer: " + lines.error().message;
    h.lines = *lines;
    Result<SceneCageLines> cageLines = createSceneCageLines(h.ctx, planned);
    if (!cageLines) return "cannot set up the renderer: " + cageLines.error().message;
    h.cageLines = std::move(cageLines).value();
    if (std::find(modes->begin(), modes->end(), request.colorBy) == modes->end()) {
        std::string known;
        for (const std::string& m : *modes) known += (known.empty() ? "" : ", ") + m;
        return "unknown --color-by '" + request.colorBy + "' for scheme " + request.scheme + "; use " + known;
    }
    for (const PreparedScheme& p : h.schemes->cages)
        for (const std::string& w : p.support.approximations)
            std::fprintf(stderr, "warning: %s: %s\n", request.scheme.c_str(), w.c_str());
    return "";
}

Result<SchemeSettings> schemeSettingsOf(uint32_t depth, const std::string& drawPath, const std::vector<std::string>& options) {
    SchemeSettings settings;
    settings.planDepth = depth;
    if (!drawPath.empty()) settings.options.push_back({"path", drawPath});
    for (const std::string& text : options) {
        Result<std::pair<std::string, std::string>> option = parseOption(text);
        if (!option) return option.error();
        settings.options.push_back(*option);
    }
    return settings;
}

Result<PluginCatalog> loadCatalogWith(const std::string& pluginDir, const std::string& scheme) {
    PluginCatalog catalog = loadPlugins(pluginDirectory(pluginDir));
    for (const PluginProblem& p : catalog.problems) std::fprintf(stderr, "warning: %s\n", p.message.c_str());
    if (!catalog.find(scheme)) return Error{unknownSchemeMessage(catalog, scheme)};
    return catalog;
}

}  // namespace

Result<SchemeChoice> chooseScheme(uint32_t depth, const std::string& drawPath, const std::vector<std::string>& options,
                                  const std::string& pluginDir, const std::string& scheme) {
    Result<SchemeSettings> settings = schemeSettingsOf(depth, drawPath, options);
    if (!settings) return settings.error();
    Result<PluginCatalog> catalog = loadCatalogWith(pluginDir, scheme);
    if (!catalog) return catalog.error();
    return SchemeChoice{std::move(settings).value(), std::move(catalog).value()};
}

void addDrawOptions(CLI::App& cmd, DrawOptions& draw, const std::string& cameraHelp, const std::string& pathHelp) {
    cmd.add_option("--scheme", draw.scheme, "Patching scheme (default plans; `quadplan schemes` lists them)");
    cmd.add_option("--size", draw.size, "Image size, WIDTHxHEIGHT (default 800x600)");
    cmd.add_option("--tess", draw.tess, "Uniform tessellation factor")->check(CLI::Range(1u, 64u));
    cmd.add_option("--adaptive", draw.adaptive, "Adaptive tessellation: target pixels per segment")->check(CLI::PositiveNumber);
    cmd.add_flag("--wire", draw.wire, "Draw the tessellation wireframe");
    cmd.add_flag("--no-cage", draw.noCage, "Do not draw the cage");
    cmd.add_option("--color-by", draw.colorBy, "shading, or a scheme's own mode (plans: node-kind, depth, sharpness)");
    cmd.add_option("--camera", draw.camera, cameraHelp);
    cmd.add_option("--path", draw.drawPath, pathHelp);
    cmd.add_option("--option", draw.options, "Scheme option KEY=VALUE (repeatable), e.g. level=4 for uniform");
    cmd.add_option("--plugin-dir", draw.pluginDir, "Where the scheme plugins are (default: $QUADPLAN_PLUGIN_DIR, else <bin>/../plugins)");
    cmd.add_option("--depth", draw.depth, "Plan depth")->check(CLI::Range(1u, kMaxPlanDepth));
    cmd.add_flag("--validate", draw.validate, "Enable Vulkan validation; any message makes the command fail");
}

Result<DrawInput> loadDrawInput(const std::string& path, const DrawOptions& draw) {
    Result<SchemeChoice> chosen = chooseScheme(draw.depth, draw.drawPath, draw.options, draw.pluginDir, draw.scheme);
    if (!chosen) return chosen.error();
    auto database = std::make_unique<PlanDatabase>();
    Result<PlannedFile> file = loadAndPlan(path, *database, PlanOptions{draw.depth, true});
    if (!file) return file.error();
    return DrawInput{std::move(chosen).value(), std::move(database), std::move(file).value()};
}

void setTessellation(SchemeSettings& settings, uint32_t tess, float adaptive, const Tessellation& scene) {
    if (tess > 0) settings.tessFactor = tess;
    else if (adaptive > 0.0f) settings.adaptivePixels = adaptive;
    else if (scene.mode == TessellationMode::Uniform) settings.tessFactor = uint32_t(scene.factor);
    else settings.adaptivePixels = scene.pixelsPerEdge;
}

Result<std::unique_ptr<HeadlessScene>> createHeadlessScene(const HeadlessSceneRequest& request, const Scene& scene,
                                                           const PlannedScene& planned) {
    Result<VulkanContext> context = createHeadlessContext(request.validate);
    if (!context) return context.error();
    auto h = std::make_unique<HeadlessScene>();
    h->ctx = std::move(context).value();
    std::vector<std::string> cacheWarnings;
    Result<PipelineCache> cache = loadPipelineCache(h->ctx, defaultPipelineCachePath(), &cacheWarnings);
    for (const std::string& w : cacheWarnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (cache) h->cache = *cache;
    h->gpu = GpuContext{&h->ctx, h->cache ? h->cache->cache : VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_D32_SFLOAT};
    h->problem = setUp(*h, request, scene, planned);
    return h;
}

DrawView headlessView(const RenderCamera& camera, uint32_t height, const std::string& colorBy, bool wireframe) {
    DrawView view;
    view.viewProjection = viewProjection(camera);
    view.eye = camera.eye;
    view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(camera), height);
    view.colorBy = colorBy;
    view.wireframe = wireframe;
    return view;
}

int destroyHeadlessScene(HeadlessScene& h, bool validate, int status) {
    if (h.schemes) {
        if (Status s = destroySceneSchemes(*h.schemes); !s) {
            std::fprintf(stderr, "error: %s\n", s.error().message.c_str());
            if (status == 0) status = 1;
        }
    }
    if (h.cache) {
        if (Status saved = savePipelineCache(h.ctx, *h.cache); !saved)
            std::fprintf(stderr, "warning: pipeline cache not saved: %s\n", saved.error().message.c_str());
        destroyPipelineCache(h.ctx, *h.cache);
    }
    if (h.cageLines) destroySceneCageLines(h.ctx, *h.cageLines);
    if (h.lines) destroyLinePass(h.ctx, *h.lines);
    if (h.target) destroyOffscreenTarget(h.ctx, *h.target);
    destroyContext(h.ctx);
    if (validate && reportValidation(h.ctx)) return status ? status : 4;
    return status;
}

}  // namespace qp::cli
