// `quadplan render`: draws a cage or scene through a scheme plugin (plans by default) into a
// PNG, headless.
#include <algorithm>
#include <cstdio>

#include "commands.h"
#include "line_pass.h"
#include "offscreen_target.h"
#include "pipeline_cache.h"
#include "plan_pass.h"
#include "planned_scene.h"
#include "render_setup.h"
#include "scene_schemes.h"
#include "vk_commands.h"

namespace qp::cli {

namespace {

struct RenderArgs {
    std::string path, out;
    std::string scheme = "plans";
    std::string size = "800x600";
    uint32_t tess = 0;
    float adaptive = 0.0f;
    bool wire = false, noCage = false, validate = false;
    std::string colorBy = "shading";
    std::string camera;
    std::string drawPath;
    std::vector<std::string> options;
    std::string pluginDir;
    uint32_t depth = 6;
};

int fail(const std::string& message) {
    std::fprintf(stderr, "error: %s\n", message.c_str());
    return 1;
}

int runRender(const RenderArgs& args) {
    uint32_t width = 0, height = 0;
    if (!parseSize(args.size, width, height))
        return fail("--size must be WIDTHxHEIGHT with each side between 16 and 8192, got '" + args.size + "'");
    if (args.tess > 0 && args.adaptive > 0.0f) return fail("give either --tess or --adaptive, not both");

    SchemeSettings settings;
    settings.planDepth = args.depth;
    if (!args.drawPath.empty()) settings.options.push_back({"path", args.drawPath});
    for (const std::string& text : args.options) {
        auto option = parseOption(text);
        if (!option) return fail(option.error().message);
        settings.options.push_back(*option);
    }

    const PluginCatalog catalog = loadPlugins(pluginDirectory(args.pluginDir));
    for (const PluginProblem& p : catalog.problems) std::fprintf(stderr, "warning: %s\n", p.message.c_str());
    if (!catalog.find(args.scheme)) return fail(unknownSchemeMessage(catalog, args.scheme));

    PlanDatabase database;
    Result<PlannedFile> file = loadAndPlan(args.path, database, PlanOptions{args.depth, true});
    if (!file) return fail(file.error().message);
    Scene& scene = file->scene;
    PlannedScene& planned = file->planned;

    if (args.tess > 0) {
        settings.tessFactor = args.tess;
    } else if (args.adaptive > 0.0f) {
        settings.adaptivePixels = args.adaptive;
    } else {
        const Tessellation& t = scene.tessellation;
        if (t.mode == TessellationMode::Uniform) settings.tessFactor = uint32_t(t.factor);
        else settings.adaptivePixels = t.pixelsPerEdge;
    }
    const bool showCage = !args.noCage && scene.tessellation.showCage;


    const float aspect = float(width) / float(height);
    Result<RenderCamera> camera = chooseCamera(scene, sceneBounds(scene), aspect, args.camera);
    if (!camera) return fail(camera.error().message);

    Result<VulkanContext> context = createHeadlessContext(args.validate);
    if (!context) return fail(context.error().message);
    VulkanContext& ctx = *context;

    int status = 0;
    std::vector<std::string> cacheWarnings;
    Result<PipelineCache> cache = loadPipelineCache(ctx, defaultPipelineCachePath(), &cacheWarnings);
    for (const std::string& w : cacheWarnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    const VkPipelineCache vkCache = cache ? cache->cache : VK_NULL_HANDLE;
    const VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
    const GpuContext gpu{&ctx, vkCache, format, VK_FORMAT_D32_SFLOAT};

    Result<SceneSchemes> prepared = prepareSceneSchemes(catalog, args.scheme, scene, planned, settings, gpu, args.path);
    Result<std::vector<std::string>> modes = prepared ? prepared->cages.front().instance.colorModes()
                                                      : Result<std::vector<std::string>>(prepared.error());
    Result<OffscreenTarget> target = modes ? createOffscreenTarget(ctx, width, height, format) : Result<OffscreenTarget>(modes.error());
    Result<LinePass> lines = target ? createLinePass(ctx, vkCache, format) : Result<LinePass>(target.error());
    Result<SceneCageLines> cageLineBuffers = lines ? createSceneCageLines(ctx, planned) : Result<SceneCageLines>(lines.error());
    if (!cageLineBuffers) {
        status = fail(prepared ? "cannot set up the renderer: " + cageLineBuffers.error().message
                               : cageLineBuffers.error().message);
    } else if (std::find(modes->begin(), modes->end(), args.colorBy) == modes->end()) {
        std::string known;
        for (const std::string& m : *modes) known += (known.empty() ? "" : ", ") + m;
        status = fail("unknown --color-by '" + args.colorBy + "' for scheme " + args.scheme + "; use " + known);
    } else {
        for (const PreparedScheme& p : prepared->cages)
            for (const std::string& w : p.support.approximations)
                std::fprintf(stderr, "warning: %s: %s\n", args.scheme.c_str(), w.c_str());
        DrawView view;
        view.viewProjection = viewProjection(*camera);
        view.eye = camera->eye;
        view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(*camera), height);
        view.colorBy = args.colorBy;
        view.wireframe = args.wire || scene.tessellation.showWireframe;
        Result<DrawStats> drawStats = DrawStats{};
        Status drawn = submitAndWait(ctx, [&](VkCommandBuffer cmd) {
            drawStats = recordScene(cmd, *prepared, scene, planned, renderTarget(*target), view);
            if (showCage) recordSceneCageLines(cmd, *lines, renderTarget(*target), *cageLineBuffers, scene, planned, view);
        });
        if (drawn && !drawStats) drawn = drawStats.error();
        Result<std::vector<uint8_t>> pixels = drawn ? readPixels(ctx, *target) : Result<std::vector<uint8_t>>(drawn.error());
        Status written = pixels ? writePng(args.out, width, height, *pixels) : Status(pixels.error());
        if (!written)
            status = fail("rendering " + args.path + " failed: " + written.error().message);
        else {
            const std::string triangles = drawStats->triangles > 0
                                              ? std::to_string(drawStats->triangles) + " triangles"
                                              : "triangle count set by the tessellator at draw time";
            const std::string objects = scene.objects.size() == 1 ? ""
                                        : std::to_string(scene.objects.size()) + " objects, " +
                                              std::to_string(planned.cages.size()) + " cages, ";
            std::fprintf(stderr, "wrote %s (%ux%u, scheme %s on %s, %s%llu patches, %s)\n", args.out.c_str(), width,
                         height, args.scheme.c_str(), ctx.deviceName.c_str(), objects.c_str(),
                         (unsigned long long)drawStats->patches, triangles.c_str());
        }
    }
    if (prepared) {
        if (Status s = destroySceneSchemes(*prepared); !s) status = fail(s.error().message);
    }
    if (cache) {
        if (Status saved = savePipelineCache(ctx, *cache); !saved)
            std::fprintf(stderr, "warning: pipeline cache not saved: %s\n", saved.error().message.c_str());
        destroyPipelineCache(ctx, *cache);
    }
    if (cageLineBuffers) destroySceneCageLines(ctx, *cageLineBuffers);
    if (lines) destroyLinePass(ctx, *lines);
    if (target) destroyOffscreenTarget(ctx, *target);
    destroyContext(ctx);
    if (args.validate && reportValidation(ctx)) return status ? status : 4;
    return status;
}

}  // namespace

void registerRender(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand("render", "Render a cage or scene to a PNG (headless, Vulkan) through a scheme plugin");
    auto args = std::make_shared<RenderArgs>();
    cmd->add_option("file", args->path, "Cage (.obj, .om, .ply, .off, .stl) or scene (.json)")->required();
    cmd->add_option("--out", args->out, "PNG file to write")->required();
    cmd->add_option("--scheme", args->scheme, "Patching scheme (default plans; `quadplan schemes` lists them)");
    cmd->add_option("--size", args->size, "Image size, WIDTHxHEIGHT (default 800x600)");
    cmd->add_option("--tess", args->tess, "Uniform tessellation factor")->check(CLI::Range(1u, 64u));
    cmd->add_option("--adaptive", args->adaptive, "Adaptive tessellation: target pixels per segment")
        ->check(CLI::PositiveNumber);
    cmd->add_flag("--wire", args->wire, "Draw the tessellation wireframe");
    cmd->add_flag("--no-cage", args->noCage, "Do not draw the cage");
    cmd->add_option("--color-by", args->colorBy, "shading, or a scheme's own mode (plans: node-kind, depth, sharpness)");
    cmd->add_option("--camera", args->camera, "EX,EY,EZ,TX,TY,TZ[,FOV_DEGREES] (default: the scene's, or framed)");
    cmd->add_option("--path", args->drawPath, "plans: auto (default: cpu on a CPU device, tess on a GPU), tess (tessellator), grid (compute-shader "
                    "grid) or cpu (grid from the multithreaded CPU evaluator); osd-fas: auto, tess or cpu; acc1, acc2, pn: "
                    "tess (default) or cpu; the option path=...");
    cmd->add_option("--option", args->options, "Scheme option KEY=VALUE (repeatable), e.g. level=4 for uniform");
    cmd->add_option("--plugin-dir", args->pluginDir, "Where the scheme plugins are (default: $QUADPLAN_PLUGIN_DIR, else <bin>/../plugins)");
    cmd->add_option("--depth", args->depth, "Plan depth")->check(CLI::Range(1u, kMaxPlanDepth));
    cmd->add_flag("--validate", args->validate, "Enable Vulkan validation; any message makes the command fail");
    cmd->callback([args, &exitCode] { exitCode = runRender(*args); });
}

}  // namespace qp::cli
