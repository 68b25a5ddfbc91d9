#include "headless_renderer.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <mutex>

#include "displacement/displaced_mesh.h"
#include "gpu_timer.h"
#include "offscreen_target.h"
#include "plan_pass.h"
#include "render_setup.h"
#include "scene_schemes.h"
#include "scheme_host.h"
#include "scheme_support.h"
#include "vk_buffer.h"
#include "vk_commands.h"

namespace qp::py {

namespace {

constexpr const char* kLavapipeIcd = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";
constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_UNORM;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;
constexpr glm::vec3 kBackground{0.9f, 0.92f, 0.95f};  // DrawView's default, as the schemes clear to
constexpr glm::vec3 kDisplacedColor{0.75f, 0.72f, 0.68f};

std::mutex pluginDirMutex;
std::string pluginDirDefault;

// Runs its function when the scope ends, whatever path leaves it.
struct Defer {
    std::function<void()> run;
    ~Defer() { run(); }
};

Status checkSize(uint32_t width, uint32_t height) {
    if (width < 16 || height < 16 || width > 8192 || height > 8192)
        return Error{"image size must be between 16 and 8192 pixels on each side, got " + std::to_string(width) + "x" +
                     std::to_string(height)};
    return success();
}

// A PlannedCage at `depth`: the document's when it has that depth, else planned afresh.
struct PlannedAtDepth {
    std::unique_ptr<PlanDatabase> database;
    std::optional<PlannedCage> own;
    const PlannedCage* planned = nullptr;
};
Result<PlannedAtDepth> plannedAtDepth(const SceneDocument& document, uint32_t depth) {
    PlannedAtDepth out;
    if (document.planned().options().maxDepth == depth) {
        out.planned = &document.planned();
        return out;
    }
    out.database = std::make_unique<PlanDatabase>();
    Result<PlannedCage> planned = PlannedCage::create(document.cage(), *out.database, PlanOptions{depth, true}, document.source());
    if (!planned) return planned.error();
    out.own.emplace(std::move(planned).value());
    out.planned = &*out.own;
    return out;
}

// The scene's sculpted displacement, for the schemes to draw (none when it has none).
const Displacement* displacementOf(const SceneDocument& document) {
    return document.displacement().empty() ? nullptr : &document.displacement();
}

}  // namespace

void setDefaultPluginDirectory(const std::string& directory) {
    std::lock_guard lock(pluginDirMutex);
    pluginDirDefault = directory;
}

std::string defaultPluginDirectory() {
    std::lock_guard lock(pluginDirMutex);
    return pluginDirDefault;
}

Result<std::unique_ptr<HeadlessRenderer>> HeadlessRenderer::create(const RendererOptions& options) {
    ContextOptions contextOptions;
    contextOptions.validation = options.validation;
    contextOptions.forceDevice = options.device;
    if (contextOptions.forceDevice.empty())
        if (const char* device = std::getenv("QUADPLAN_VK_DEVICE"); device && device[0]) contextOptions.forceDevice = device;
    if (options.lavapipe) {
        if (!std::filesystem::exists(kLavapipeIcd))
            return Error{std::string(kLavapipeIcd) + " is missing: install mesa-vulkan-drivers (lavapipe)"};
        // Before the loader looks for drivers, i.e. before the instance exists.
        setenv("VK_ICD_FILENAMES", kLavapipeIcd, 1);
        setenv("VK_DRIVER_FILES", kLavapipeIcd, 1);
        contextOptions.preferSoftware = true;
    }
    Result<VulkanContext> context = createContext(contextOptions);
    if (!context) return Error{"cannot start Vulkan: " + context.error().message};

    std::unique_ptr<HeadlessRenderer> renderer(new HeadlessRenderer());
    renderer->context_ = std::move(context).value();
    renderer->validation_ = options.validation;
    std::string directory = options.pluginDir;
    if (directory.empty())
        if (const char* env = std::getenv(kPluginDirEnv); env && env[0]) directory = env;
    if (directory.empty()) directory = defaultPluginDirectory();
    renderer->catalog_ = loadPlugins(pluginDirectory(directory));

    std::vector<std::string> warnings;  // a bad cache file only costs time
    if (Result<PipelineCache> cache = loadPipelineCache(renderer->context_, defaultPipelineCachePath(), &warnings); cache)
        renderer->cache_ = std::move(cache).value();
    const VkPipelineCache vkCache = renderer->cache_ ? renderer->cache_->cache : VK_NULL_HANDLE;
    Result<LinePass> lines = createLinePass(renderer->context_, vkCache, kColorFormat, kDepthFormat);
    if (!lines) return Error{"cannot set up the renderer: " + lines.error().message};
    renderer->lines_ = *lines;
    Result<MeshPass> meshes = createMeshPass(renderer->context_, vkCache, kColorFormat, kDepthFormat);
    if (!meshes) return Error{"cannot set up the renderer: " + meshes.error().message};
    renderer->meshes_ = *meshes;
    return renderer;
}

HeadlessRenderer::~HeadlessRenderer() {
    if (!context_.device) return;
    vkDeviceWaitIdle(context_.device);
    if (lines_) destroyLinePass(context_, *lines_);
    if (meshes_) destroyMeshPass(context_, *meshes_);
    if (cache_) {
        (void)savePipelineCache(context_, *cache_);
        destroyPipelineCache(context_, *cache_);
    }
    destroyContext(context_);
}

GpuContext HeadlessRenderer::gpu() const {
    return GpuContext{&context_, cache_ ? cache_->cache : VK_NULL_HANDLE, kColorFormat, kDepthFormat};
}

Status HeadlessRenderer::checkValidation(uint32_t before) const {
    if (!validation_ || validationMessageCount(context_) == before) return success();
    const std::vector<std::string> messages = validationMessages(context_);
    std::string text = "Vulkan validation reported " + std::to_string(messages.size() - std::min<size_t>(before, messages.size())) +
                       " message(s):";
    for (size_t i = before; i < messages.size(); ++i) text += "\n  " + messages[i];
    return Error{text};
}

Result<RenderCamera> HeadlessRenderer::cameraFor(const SceneDocument& document, const std::optional<Camera>& camera,
                                                 uint32_t width, uint32_t height) const {
    Scene view;  // chooseCamera reads only the camera
    view.camera = camera ? camera : document.scene().camera;
    return cli::chooseCamera(view, sceneBounds(document.scene(), document.plannedScene()), float(width) / float(height), "");
}

Result<RenderedImage> HeadlessRenderer::render(const SceneDocument& document, const RenderRequest& request) {
    const uint32_t before = validationMessageCount(context_);
    if (Status ok = checkSize(request.width, request.height); !ok) return ok.error();
    if (request.tess > 0 && request.adaptive > 0.0f) return Error{"give either tess or adaptive, not both"};
    if (request.tess > 64) return Error{"tess must be between 1 and 64, got " + std::to_string(request.tess)};
    if (!catalog_.find(request.scheme)) return Error{unknownSchemeMessage(catalog_, request.scheme)};
    const Scene& scene = document.scene();

    SchemeSettings settings;
    settings.planDepth = document.planned().options().maxDepth;
    settings.options = request.options;
    if (request.tess > 0) {
        settings.tessFactor = request.tess;
    } else if (request.adaptive > 0.0f) {
        settings.adaptivePixels = request.adaptive;
    } else if (scene.tessellation.mode == TessellationMode::Uniform) {
        settings.tessFactor = uint32_t(scene.tessellation.factor);
    } else {
        settings.adaptivePixels = scene.tessellation.pixelsPerEdge;
    }
    const bool showCage = request.showCage.value_or(scene.tessellation.showCage);
    Result<RenderCamera> camera = cameraFor(document, request.camera, request.width, request.height);
    if (!camera) return camera.error();

    // Every object: one scheme instance per cage, drawn per object under its transform.
    const PlannedScene& cages = document.plannedScene();
    Result<SceneSchemes> prepared = prepareSceneSchemes(catalog_, request.scheme, scene, cages, settings, gpu(), document.source());
    if (!prepared) return prepared.error();
    Defer releaseSchemes{[&] { (void)destroySceneSchemes(*prepared); }};
    Result<std::vector<std::string>> modes = prepared->cages.front().instance.colorModes();
    if (!modes) return modes.error();
    if (std::find(modes->begin(), modes->end(), request.colorBy) == modes->end()) {
        std::string known;
        for (const std::string& m : *modes) known += (known.empty() ? "" : ", ") + m;
        return Error{"unknown color_by '" + request.colorBy + "' for scheme " + request.scheme + "; use " + known};
    }

    Result<OffscreenTarget> target = createOffscreenTarget(context_, request.width, request.height, kColorFormat);
    if (!target) return Error{"cannot set up the renderer: " + target.error().message};
    Defer releaseTarget{[&] { destroyOffscreenTarget(context_, *target); }};
    Result<SceneCageLines> cageLineBuffers = createSceneCageLines(context_, cages);
    if (!cageLineBuffers) return Error{"cannot set up the renderer: " + cageLineBuffers.error().message};
    Defer releaseLines{[&] { destroySceneCageLines(context_, *cageLineBuffers); }};

    DrawView view;
    view.viewProjection = viewProjection(*camera);
    view.eye = camera->eye;
    view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(*camera), request.height);
    view.colorBy = request.colorBy;
    view.wireframe = request.wireframe;
    view.cull = request.cull;
    Result<DrawStats> drawStats = DrawStats{};
    Status drawn = submitAndWait(context_, [&](VkCommandBuffer cmd) {
        drawStats = recordScene(cmd, *prepared, scene, cages, renderTarget(*target), view);
        if (showCage) recordSceneCageLines(cmd, *lines_, renderTarget(*target), *cageLineBuffers, scene, cages, view);
    });
    if (drawn && !drawStats) drawn = drawStats.error();
    if (!drawn) return Error{"rendering " + document.source() + " failed: " + drawn.error().message};
    Result<std::vector<uint8_t>> pixels = readPixels(context_, *target);
    if (!pixels) return Error{"rendering " + document.source() + " failed: " + pixels.error().message};

    std::vector<std::string> approximations;
    for (const PreparedScheme& p : prepared->cages)
        approximations.insert(approximations.end(), p.support.approximations.begin(), p.support.approximations.end());
    RenderedImage image{request.width, request.height, std::move(pixels).value(), *drawStats, std::move(approximations)};
    if (Status s = destroySceneSchemes(*prepared); !s) return s.error();
    if (Status ok = checkValidation(before); !ok) return ok.error();
    return image;
}

Result<RenderedImage> HeadlessRenderer::renderDisplaced(const SceneDocument& document, const RenderRequest& request) {
    const uint32_t before = validationMessageCount(context_);
    if (Status ok = checkSize(request.width, request.height); !ok) return ok.error();
    const PlannedCage& planned = document.planned();
    const Displacement& displacement = document.displacement();
    const uint32_t factor = request.tess > 0 ? std::max(request.tess, requiredMeshFactor(planned, displacement.layout))
                                             : requiredMeshFactor(planned, displacement.layout);
    Result<DisplacedMesh> mesh = buildDisplacedMesh(planned, displacement, std::min(factor, 2 * kMaxDisplacementResolution));
    if (!mesh) return mesh.error();
    Result<RenderCamera> camera = cameraFor(document, request.camera, request.width, request.height);
    if (!camera) return camera.error();

    std::vector<MeshVertex> vertices(mesh->positions.size());
    for (size_t i = 0; i < vertices.size(); ++i) vertices[i] = {mesh->positions[i], mesh->normals[i]};
    Result<OffscreenTarget> target = createOffscreenTarget(context_, request.width, request.height, kColorFormat);
    if (!target) return Error{"cannot set up the renderer: " + target.error().message};
    Defer releaseTarget{[&] { destroyOffscreenTarget(context_, *target); }};
    Result<GpuMesh> gpuMesh = uploadMesh(context_, vertices, mesh->indices);
    if (!gpuMesh) return Error{"cannot upload the displaced mesh: " + gpuMesh.error().message};
    Defer releaseMesh{[&] { destroyMesh(context_, *gpuMesh); }};
    const std::vector<LineVertex> cageVertices = cageLines(planned.cage());
    Result<Buffer> lineBuffer = createBuffer(context_, std::max<size_t>(cageVertices.size(), 2) * sizeof(LineVertex),
                                             VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    if (!lineBuffer) return Error{"cannot set up the renderer: " + lineBuffer.error().message};
    Defer releaseLines{[&] { destroyBuffer(context_, *lineBuffer); }};
    uploadBuffer(*lineBuffer, cageVertices.data(), cageVertices.size() * sizeof(LineVertex));
    const bool showCage = request.showCage.value_or(document.scene().tessellation.showCage);

    const MeshView view{viewProjection(*camera), camera->eye, kBackground};
    const MeshDraw draw{&*gpuMesh, kDisplacedColor, true, request.wireframe};
    Status drawn = submitAndWait(context_, [&](VkCommandBuffer cmd) {
        recordMeshPass(cmd, *meshes_, renderTarget(*target), view, {&draw, 1});
        if (showCage && !cageVertices.empty())
            recordLines(cmd, *lines_, renderTarget(*target), view.viewProjection, *lineBuffer, uint32_t(cageVertices.size()));
    });
    if (!drawn) return drawn.error();
    Result<std::vector<uint8_t>> pixels = readPixels(context_, *target);
    if (!pixels) return pixels.error();
    RenderedImage image{request.width, request.height, std::move(pixels).value(),
                        DrawStats{0, mesh->indices.size() / 3}, {}};
    if (Status ok = checkValidation(before); !ok) return ok.error();
    return image;
}

Result<RenderedImage> HeadlessRenderer::renderError(const SceneDocument& document, const RenderRequest& request,
                                                    uint32_t samples, ErrorStats* stats) {
    const uint32_t before = validationMessageCount(context_);
    if (Status ok = checkSize(request.width, request.height); !ok) return ok.error();
    if (samples < 1 || samples > 256) return Error{"samples must be between 1 and 256, got " + std::to_string(samples)};
    const PlannedCage& planned = document.planned();
    SchemeSettings settings;
    settings.planDepth = planned.options().maxDepth;
    settings.tessFactor = request.tess > 0 ? request.tess : 8;
    settings.options = request.options;
    Result<RenderCamera> camera = cameraFor(document, request.camera, request.width, request.height);
    if (!camera) return camera.error();
    const CageFeatures features = analyzeCage(planned.cage(), planned.topology());
    Result<PreparedScheme> prepared = prepareScheme(catalog_, request.scheme, planned, features, settings, gpu(), document.source());
    if (!prepared) return prepared.error();
    Defer releaseScheme{[&] { (void)prepared->instance.destroyGpu(); }};

    const SubfaceGrid grid = buildSubfaceGrid(planned, samples);
    std::vector<SurfacePoint> points(grid.samples.size());
    if (Status ok = prepared->instance.evaluate(grid.samples, points); !ok) return ok.error();
    const double diagonal = std::max(double(computeBounds(planned.cage()).diagonal()), 1e-30);
    const SurfaceError error = measureSurfaceError(planned, grid.samples, points, diagonal);
    if (stats) *stats = error.stats;
    std::vector<glm::vec3> colors(points.size());
    for (size_t k = 0; k < points.size(); ++k) colors[k] = heatColorLinear(error.relError[k]);
    const std::vector<MeshVertex> vertices = meshVertices(points);

    Result<OffscreenTarget> target = createOffscreenTarget(context_, request.width, request.height, kColorFormat);
    if (!target) return Error{"cannot set up the renderer: " + target.error().message};
    Defer releaseTarget{[&] { destroyOffscreenTarget(context_, *target); }};
    Result<GpuMesh> heat = vertices.empty() ? Result<GpuMesh>(GpuMesh{}) : uploadMesh(context_, vertices, grid.indices, colors);
    if (!heat) return heat.error();
    Defer releaseHeat{[&] { if (heat->indexCount) destroyMesh(context_, *heat); }};
    const MeshDraw draw{&*heat};
    Status drawn = submitAndWait(context_, [&](VkCommandBuffer cmd) {
        recordMeshPass(cmd, *meshes_, renderTarget(*target), MeshView{viewProjection(*camera), camera->eye, kBackground},
                       heat->indexCount ? std::span<const MeshDraw>(&draw, 1) : std::span<const MeshDraw>());
    });
    if (!drawn) return drawn.error();
    Result<std::vector<uint8_t>> pixels = readPixels(context_, *target);
    if (!pixels) return pixels.error();
    RenderedImage image{request.width, request.height, std::move(pixels).value(), DrawStats{0, grid.indices.size() / 3},
                        prepared->support.approximations};
    if (Status ok = checkValidation(before); !ok) return ok.error();
    return image;
}

// The numbers of cmd_compare.cpp, computed the same way: frames as if the cage moved every
// frame (update + draw, one warm-up, median of `repeats`), then the error on the sample grid.
Result<std::vector<SchemeComparison>> HeadlessRenderer::compare(const SceneDocument& document, const CompareRequest& request) {
    const uint32_t before = validationMessageCount(context_);
    if (Status ok = checkSize(request.tileWidth, request.tileHeight); !ok) return ok.error();
    if (request.tess < 1 || request.tess > 64) return Error{"tess must be between 1 and 64"};
    if (request.samples < 1 || request.samples > 256) return Error{"samples must be between 1 and 256"};
    if (request.depth < 1 || request.depth > kMaxPlanDepth)
        return Error{"depth must be between 1 and " + std::to_string(kMaxPlanDepth)};
    if (request.repeats < 1) return Error{"repeats must be at least 1"};
    std::vector<std::string> names = request.schemes;
    if (names.empty())
        for (const auto& plugin : catalog_.plugins) names.push_back(plugin->name);
    if (names.empty()) return Error{"no schemes to compare: none given and no plugin loaded from " + catalog_.directory};

    Result<PlannedAtDepth> exact = plannedAtDepth(document, request.depth);
    if (!exact) return exact.error();
    const PlannedCage& planned = *exact->planned;
    const double diagonal = std::max(double(computeBounds(planned.cage()).diagonal()), 1e-30);
    Result<RenderCamera> camera = cameraFor(document, request.camera, request.tileWidth, request.tileHeight);
    if (!camera) return camera.error();
    const CageFeatures features = analyzeCage(planned.cage(), planned.topology());
    const SubfaceGrid grid = buildSubfaceGrid(planned, request.samples);

    Result<OffscreenTarget> target = createOffscreenTarget(context_, request.tileWidth, request.tileHeight, kColorFormat);
    if (!target) return Error{"cannot set up the renderer: " + target.error().message};
    Defer releaseTarget{[&] { destroyOffscreenTarget(context_, *target); }};
    Result<GpuTimer> timer = createGpuTimer(context_);
    if (!timer) return Error{"cannot set up the renderer: " + timer.error().message};
    Defer releaseTimer{[&] { destroyGpuTimer(context_, *timer); }};

    DrawView view;
    view.viewProjection = viewProjection(*camera);
    view.eye = camera->eye;
    view.background = kBackground;
    view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(*camera), request.tileHeight);
    std::vector<SchemeComparison> results;
    for (const std::string& name : names) {
        SchemeComparison r;
        r.name = name;
        SchemeSettings settings;
        settings.tessFactor = request.tess;
        settings.planDepth = request.depth;
        for (const auto& [scheme, option] : request.options)
            if (scheme == name) settings.options.push_back(option);
        // The pictures show the displacement; the error is the undisplaced surface's.
        Result<PreparedScheme> prepared =
            prepareScheme(catalog_, name, planned, features, settings, gpu(), document.source(), displacementOf(document));
        if (!prepared) {
            r.reason = prepared.error().message;
            results.push_back(std::move(r));
            continue;
        }
        SchemeInstance& scheme = prepared->instance;
        r.approximations = prepared->support.approximations;
        r.setupMs = prepared->setupMs();
        Status ok = success();
        if (Result<SchemeFrameTimes> times = timeSchemeFrames(context_, scheme, renderTarget(*target), view, *timer, request.repeats)) {
            r.draw = times->draw;
            r.frameMs = times->frameMs;
            r.drawMs = times->drawMs;
        } else {
            ok = times.error();
        }
        std::vector<SurfacePoint> points(grid.samples.size());
        if (ok) ok = scheme.evaluate(grid.samples, points);
        Result<SchemeStats> stats = ok ? scheme.stats() : Result<SchemeStats>(ok.error());
        if (stats) {
            r.stats = *stats;
            r.error = measureSurfaceError(planned, grid.samples, points, diagonal).stats;
        } else {
            ok = stats.error();
        }
        if (Status destroyed = scheme.destroyGpu(); ok && !destroyed) ok = destroyed;
        if (!ok) r.reason = ok.error().message;
        else r.drawn = true;
        results.push_back(std::move(r));
    }
    if (Status ok = checkValidation(before); !ok) return ok.error();
    return results;
}

}  // namespace qp::py
