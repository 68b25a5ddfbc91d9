// `quadplan render`: draws a cage or scene with the plans renderer into a PNG, headless.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "camera.h"
#include "commands.h"
#include "draw_path.h"
#include "line_pass.h"
#include "offscreen_target.h"
#include "pipeline_cache.h"
#include "plan_pass.h"
#include "planned_cage.h"
#include "scene.h"
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
    std::string drawPath = "auto";
    uint32_t depth = 6;
};

int fail(const std::string& message) {
    std::fprintf(stderr, "error: %s\n", message.c_str());
    return 1;
}

std::optional<ColorBy> parseColorBy(const std::string& name) {
    if (name == "shading") return ColorBy::Shading;
    if (name == "node-kind") return ColorBy::NodeKind;
    if (name == "depth") return ColorBy::PlanDepth;
    if (name == "sharpness") return ColorBy::Sharpness;
    return std::nullopt;
}

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

bool parseSize(const std::string& text, uint32_t& width, uint32_t& height) {
    unsigned w = 0, h = 0;
    char x = 0;
    if (std::sscanf(text.c_str(), "%u%c%u", &w, &x, &h) != 3 || (x != 'x' && x != 'X')) return false;
    if (w < 16 || h < 16 || w > 8192 || h > 8192) return false;
    width = w;
    height = h;
    return true;
}

int runRender(const RenderArgs& args) {
    uint32_t width = 0, height = 0;
    if (!parseSize(args.size, width, height))
        return fail("--size must be WIDTHxHEIGHT with each side between 16 and 8192, got '" + args.size + "'");
    if (args.scheme != "plans")
        return fail("unknown scheme '" + args.scheme + "'; available schemes: plans");
    std::optional<ColorBy> colorBy = parseColorBy(args.colorBy);
    if (!colorBy) return fail("unknown --color-by '" + args.colorBy + "'; use shading, node-kind, depth or sharpness");
    std::optional<DrawPath> requestedPath = parseDrawPath(args.drawPath);
    if (!requestedPath) return fail("unknown --path '" + args.drawPath + "'; use auto, tess, grid or cpu");
    if (args.tess > 0 && args.adaptive > 0.0f) return fail("give either --tess or --adaptive, not both");

    std::vector<std::string> warnings;
    Result<Scene> scene = loadSceneOrCage(args.path, &warnings);
    for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (!scene) return fail(scene.error().message);

    TessellationSettings tessellation;
    if (args.tess > 0) {
        tessellation.uniformFactor = args.tess;
    } else if (args.adaptive > 0.0f) {
        tessellation = TessellationSettings{0, args.adaptive};
    } else {
        const Tessellation& t = scene->tessellation;
        tessellation = t.mode == TessellationMode::Uniform ? TessellationSettings{uint32_t(t.factor), 8.0f}
                                                          : TessellationSettings{0, t.pixelsPerEdge};
    }
    const bool showCage = !args.noCage && scene->tessellation.showCage;
    const bool showWire = args.wire || scene->tessellation.showWireframe;

    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(scene->cage, database, PlanOptions{args.depth, true}, args.path);
    if (!planned) return fail(planned.error().message);

    const float aspect = float(width) / float(height);
    const Bounds bounds = computeBounds(planned->cage());
    RenderCamera camera = frameBounds(bounds.min, bounds.max, aspect);
    if (!args.camera.empty()) {
        std::optional<RenderCamera> parsed = parseCamera(args.camera, aspect);
        if (!parsed) return fail("--camera must be EX,EY,EZ,TX,TY,TZ[,FOV_DEGREES], got '" + args.camera + "'");
        camera = *parsed;
        fitDepthRange(camera, bounds);
    } else if (scene->camera) {
        camera = fromScene(*scene->camera, aspect);
        fitDepthRange(camera, bounds);
    }

    // Headless: lavapipe unless a GPU is present or QUADPLAN_VK_DEVICE names a device.
    ContextOptions contextOptions;
    contextOptions.validation = args.validate;
    if (const char* device = std::getenv("QUADPLAN_VK_DEVICE")) contextOptions.forceDevice = device;
    Result<VulkanContext> context = createContext(contextOptions);
    if (!context) return fail("cannot start Vulkan: " + context.error().message);
    VulkanContext& ctx = *context;

    int status = 0;
    std::vector<std::string> cacheWarnings;
    Result<PipelineCache> cache = loadPipelineCache(ctx, defaultPipelineCachePath(), &cacheWarnings);
    for (const std::string& w : cacheWarnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    const VkPipelineCache vkCache = cache ? cache->cache : VK_NULL_HANDLE;
    const VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
    Result<OffscreenTarget> target = createOffscreenTarget(ctx, width, height, format);
    Result<PlanPass> pass = target ? createPlanPass(ctx, vkCache, format) : Result<PlanPass>(target.error());
    Result<LinePass> lines = pass ? createLinePass(ctx, vkCache, format) : Result<LinePass>(pass.error());
    Result<PlanBuffers> buffers = lines ? uploadPlans(ctx, *planned) : Result<PlanBuffers>(lines.error());
    std::vector<LineVertex> cageVertices = cageLines(planned->cage());
    Result<Buffer> lineBuffer = buffers ? createBuffer(ctx, std::max<size_t>(cageVertices.size(), 2) * sizeof(LineVertex),
                                                       VK_BUFFER_USAGE_VERTEX_BUFFER_BIT)
                                        : Result<Buffer>(buffers.error());
    if (!lineBuffer) {
        status = fail("cannot set up the renderer: " + lineBuffer.error().message);
    } else {
        uploadBuffer(*lineBuffer, cageVertices.data(), cageVertices.size() * sizeof(LineVertex));
        bindPlanBuffers(ctx, *pass, *buffers);
        PlanView view;
        view.viewProjection = viewProjection(camera);
        view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(camera), height);
        view.colorBy = *colorBy;
        view.wireframe = showWire;
        const DrawPath path = resolveDrawPath(*requestedPath, ctx);
        Status prepared = preparePlanFrame(ctx, *pass, *buffers, *planned, path, view, tessellation);
        Status drawn = prepared ? submitAndWait(ctx, [&](VkCommandBuffer cmd) {
            recordPlanFrame(cmd, *pass, *buffers, path, renderTarget(*target), view, tessellation);
            if (showCage && !cageVertices.empty())
                recordLines(cmd, *lines, renderTarget(*target), view.viewProjection, *lineBuffer, uint32_t(cageVertices.size()));
        }) : prepared;
        Result<std::vector<uint8_t>> pixels = drawn ? readPixels(ctx, *target) : Result<std::vector<uint8_t>>(drawn.error());
        Status written = pixels ? writePng(args.out, width, height, *pixels) : Status(pixels.error());
        if (!written) status = fail("rendering " + args.path + " failed: " + written.error().message);
        else
            std::fprintf(stderr, "wrote %s (%ux%u, %s path on %s, %u sub-faces)\n", args.out.c_str(), width, height,
                         drawPathName(path), ctx.deviceName.c_str(), uint32_t(buffers->data.subfaces.size()));
    }
    if (cache) {
        if (Status saved = savePipelineCache(ctx, *cache); !saved)
            std::fprintf(stderr, "warning: pipeline cache not saved: %s\n", saved.error().message.c_str());
        destroyPipelineCache(ctx, *cache);
    }
    if (lineBuffer) destroyBuffer(ctx, *lineBuffer);
    if (buffers) destroyPlanBuffers(ctx, *buffers);
    if (lines) destroyLinePass(ctx, *lines);
    if (pass) destroyPlanPass(ctx, *pass);
    if (target) destroyOffscreenTarget(ctx, *target);
    destroyContext(ctx);
    if (args.validate && validationMessageCount(ctx) > 0) {
        for (const std::string& m : validationMessages(ctx)) std::fprintf(stderr, "validation: %s\n", m.c_str());
        return status ? status : 4;
    }
    return status;
}

}  // namespace

void registerRender(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand("render", "Render a cage or scene to a PNG (headless, Vulkan)");
    auto args = std::make_shared<RenderArgs>();
    cmd->add_option("file", args->path, "Cage (.obj) or scene (.json)")->required();
    cmd->add_option("--out", args->out, "PNG file to write")->required();
    cmd->add_option("--scheme", args->scheme, "Patching scheme (plans)");
    cmd->add_option("--size", args->size, "Image size, WIDTHxHEIGHT (default 800x600)");
    cmd->add_option("--tess", args->tess, "Uniform tessellation factor")->check(CLI::Range(1u, 64u));
    cmd->add_option("--adaptive", args->adaptive, "Adaptive tessellation: target pixels per segment")
        ->check(CLI::PositiveNumber);
    cmd->add_flag("--wire", args->wire, "Draw the tessellation wireframe");
    cmd->add_flag("--no-cage", args->noCage, "Do not draw the cage");
    cmd->add_option("--color-by", args->colorBy, "shading, node-kind, depth or sharpness");
    cmd->add_option("--camera", args->camera, "EX,EY,EZ,TX,TY,TZ[,FOV_DEGREES] (default: the scene's, or framed)");
    cmd->add_option("--path", args->drawPath,
                    "auto (default: cpu on a CPU device, tess on a GPU), tess (tessellator), grid (compute-shader "
                    "grid) or cpu (grid from the multithreaded CPU evaluator)");
    cmd->add_option("--depth", args->depth, "Plan depth")->check(CLI::Range(1u, kMaxPlanDepth));
    cmd->add_flag("--validate", args->validate, "Enable Vulkan validation; any message makes the command fail");
    cmd->callback([args, &exitCode] { exitCode = runRender(*args); });
}

}  // namespace qp::cli
