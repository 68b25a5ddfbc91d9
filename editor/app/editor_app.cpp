#include "editor_app.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <malloc.h>
#include <thread>
#include <utility>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <imgui.h>

#include "automation.h"
#include "overlays.h"
#include "panels.h"
#include "recovery.h"
#include "scene_cache.h"
#include "schemes.h"
#include "viewport_input.h"
#include "vk_check.h"

namespace qp::editor {

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) { return std::chrono::duration<double, std::milli>(Clock::now() - start).count(); }

// Most triangles the adaptive grid may draw per frame over all viewports (lavapipe rasterises
// on the CPU; see docs/editor.md for the measurements behind it).
constexpr double kAdaptiveTriangleBudget = 400000.0;
const glm::vec3 kGapColor(0.08f, 0.08f, 0.09f);

std::string g_glfwError;  // the last GLFW error, for messages

Status openWindow(EditorApp& app) {
    const char* display = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    if ((!display || !display[0]) && (!wayland || !wayland[0]))
        return Error{"cannot open the editor window: there is no display (DISPLAY is not set). Run it on a desktop, "
                     "under a virtual display (xvfb-run -a quadplan edit FILE), or use the headless commands "
                     "such as `quadplan render`."};
    glfwSetErrorCallback([](int, const char* text) { g_glfwError = text; });
    if (!glfwInit()) return Error{"cannot open the editor window: GLFW failed to start (" + g_glfwError + ")"};
    if (!glfwVulkanSupported()) return Error{"cannot open the editor window: GLFW found no Vulkan loader"};
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    app.window = glfwCreateWindow(int(app.options.width), int(app.options.height), "Quadplan", nullptr, nullptr);
    if (!app.window) return Error{"cannot open the editor window: " + g_glfwError};
    return success();
}

Status startVulkan(EditorApp& app) {
    ContextOptions options;
    options.validation = app.options.validate;
    if (const char* device = std::getenv("QUADPLAN_VK_DEVICE")) options.forceDevice = device;
    uint32_t count = 0;
    const char** extensions = glfwGetRequiredInstanceExtensions(&count);
    for (uint32_t i = 0; i < count; ++i) options.instanceExtensions.push_back(extensions[i]);
    options.deviceExtensions = swapchainDeviceExtensions();
    Result<VulkanContext> context = createContext(options);
    if (!context) return Error{"cannot start Vulkan: " + context.error().message};
    app.ctx = std::move(context).value();
    VK_CHECK(glfwCreateWindowSurface(app.ctx.instance, app.window, nullptr, &app.surface));
    int w = 0, h = 0;
    glfwGetFramebufferSize(app.window, &w, &h);
    SwapchainOptions swapOptions;
    swapOptions.vsync = app.options.vsync;
    Result<SwapchainTarget> swap = createSwapchainTarget(app.ctx, app.surface, uint32_t(w), uint32_t(h), swapOptions);
    if (!swap) return swap.error();
    app.swapchain = std::move(swap).value();

    std::vector<std::string> warnings;
    Result<PipelineCache> cache = loadPipelineCache(app.ctx, defaultPipelineCachePath(), &warnings);
    for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (cache) app.pipelineCache = *cache;
    const VkPipelineCache vkCache = app.pipelineCache ? app.pipelineCache->cache : VK_NULL_HANDLE;
    Result<SceneRenderer> renderer =
        createSceneRenderer(app.ctx, vkCache, sceneCacheFormat(app.ctx, app.swapchain.surfaceFormat.format));
    if (!renderer) return Error{"cannot set up the renderer: " + renderer.error().message};
    app.renderer = std::move(renderer).value();
    // Before ImGui's backend, which chains to it.
    glfwSetWindowUserPointer(app.window, &app);
    glfwSetKeyCallback(app.window, [](GLFWwindow* window, int key, int, int action, int mods) {
        if (action != GLFW_PRESS) return;
        auto* self = static_cast<EditorApp*>(glfwGetWindowUserPointer(window));
        self->keyPresses.push_back(
            {key, (mods & GLFW_MOD_CONTROL) != 0, (mods & GLFW_MOD_SHIFT) != 0, (mods & GLFW_MOD_ALT) != 0});
    });
    glfwSetMouseButtonCallback(app.window, [](GLFWwindow* window, int button, int action, int) {
        if (button != GLFW_MOUSE_BUTTON_LEFT || action != GLFW_PRESS) return;
        auto* self = static_cast<EditorApp*>(glfwGetWindowUserPointer(window));
        glm::dvec2 at;
        glfwGetCursorPos(window, &at.x, &at.y);
        const ImGuiIO& io = ImGui::GetIO();
        self->leftDoubleClick |= pairPress(self->leftPresses, glfwGetTime(), at, io.MouseDoubleClickTime, io.MouseDoubleClickMaxDist);
    });
    Result<ImGuiLayer> imgui = createImGuiLayer(app.ctx, app.window, app.swapchain, vkCache);
    if (!imgui) return imgui.error();
    app.imgui = std::move(imgui).value();
    for (auto& timer : app.timers)
        if (Result<GpuTimer> t = createGpuTimer(app.ctx)) timer = *t;  // no timestamps: GPU time unknown
    return success();
}

void shutDown(EditorApp& app) {
    if (app.ctx.device) {
        app.loader.waitAndDiscard();
        vkDeviceWaitIdle(app.ctx.device);
        destroyImGuiLayer(app.ctx, app.imgui);
        destroySceneRenderer(app.ctx, app.renderer);
        destroySceneCache(app.ctx, app.sceneCache);
        for (auto& timer : app.timers)
            if (timer) destroyGpuTimer(app.ctx, *timer);
        if (app.pipelineCache) {
            if (Status saved = savePipelineCache(app.ctx, *app.pipelineCache); !saved)
                std::fprintf(stderr, "warning: pipeline cache not saved: %s\n", saved.error().message.c_str());
            destroyPipelineCache(app.ctx, *app.pipelineCache);
        }
        destroySwapchainTarget(app.ctx, app.swapchain);
    }
    if (app.surface) vkDestroySurfaceKHR(app.ctx.instance, app.surface, nullptr);
    if (app.ctx.instance) destroyContext(app.ctx);
    if (app.window) glfwDestroyWindow(app.window);
    glfwTerminate();
}

// Pixels per world unit at clip w = 1 (the projection's y scale; Vulkan flips y).
float pixelsPerUnit(const glm::mat4& projection, uint32_t viewportHeight) {
    return 0.5f * float(viewportHeight) * std::abs(projection[1][1]);
}

// The scene's view settings become the editor's (after a load).
void applySceneView(EditorApp& app) {
    const Scene& scene = app.doc->scene;
    app.tessellation = scene.tessellation;
    app.display = scene.display;
    const UpAxis up = scene.display.upAxis.value_or(guessUpAxis(computeBounds(app.doc->planned->cage())));
    app.display.upAxis = up;
    app.viewports.clear();
    for (const Viewport& v : scene.viewports) {
        ViewportState state;
        state.scheme = v.scheme;
        state.colorBy = canonicalColorMode(v.colorBy);
        state.linked = v.camera == CameraLink::Linked;
        app.viewports.push_back(state);
    }
    if (app.viewports.empty()) app.viewports.push_back(ViewportState{});
    setViewportCount(app, uint32_t(std::min<size_t>(app.viewports.size(), 4)));
    app.activeViewport = 0;
    if (scene.camera) {
        app.sharedCamera = fromSceneCamera(*scene.camera, up);
    } else {  // a 3/4 view from the front right, above, like `quadplan render`
        app.sharedCamera = ViewCamera{};
        app.sharedCamera.up = up;
        app.sharedCamera.yaw = glm::radians(35.0f);
        app.sharedCamera.pitch = glm::radians(25.0f);
        frameSelection(app, 0, true);
    }
    for (ViewportState& v : app.viewports) v.camera = app.sharedCamera;
}

void adoptFinishedLoad(EditorApp& app) {
    std::optional<Result<LoadedDocument>> loaded = app.loader.take();
    if (!loaded) return;
    const LoadRequest& request = app.loader.request();
    if (!*loaded) {
        showError(app, "Opening " + (request.fromRecovery ? std::string("the recovered work") : request.path) +
                           " failed: " + loaded->error().message);
        return;
    }
    LoadedDocument& result = loaded->value();
    for (const std::string& w : result.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (app.doc)
        if (std::optional<std::string> why = storeNewPlans(*app.doc)) std::fprintf(stderr, "warning: %s\n", why->c_str());
    // The scheme instances point into the old document: they go first.
    releaseSchemes(app.ctx, app.renderer);
    app.doc = std::move(result.document);
    ++app.documentGeneration;
    app.picking = std::move(result.picking);  // built by the loader for this document
    app.picking.generation = app.documentGeneration;
    app.drag = Drag{};
    app.playback = PlaybackClock{};  // the new document opens paused
    app.tools.loopTool = false;
    app.mode = EditorMode::Edit;  // on the first object's cage, as before object mode existed
    app.objectPicking = ObjectPickCache{};
    app.autosavedOnce = false;
    applySceneView(app);
    const Cage& cage = app.doc->planned->cage();
    app.tools.extrudeDistance = 0.5f * cageExtent(*app.doc).meanEdgeLength();
    app.tools.sculpt.resolution = defaultDisplacementResolution(app.doc->planned->subfaceCount());
    app.ui.status = (request.fromRecovery ? "Restored unsaved work" : "Opened " + request.path) + " (" +
                    std::to_string(cage.faceCount()) + " faces, " + std::to_string(app.doc->database->size()) +
                    " plans, " + std::to_string(int(std::lround(app.loader.secondsRunning() * 1000))) + " ms)";
    if (app.doc->scene.objects.size() > 1)
        app.ui.status += "; " + std::to_string(app.doc->scene.objects.size()) + " objects, edit mode on \"" +
                         activeObject(*app.doc).name + "\" (Tab: object mode)";
    if (app.ui.recovery && app.ui.recovery->restoreWhenIdle) restoreRecovery(app);
}

// Every autosaveSeconds while there are unsaved changes, the scene is copied here and written on
// the autosaver's thread; its outcome shows in the status line when it is done.
void autosave(EditorApp& app) {
    if (std::optional<Result<std::string>> done = app.autosaver.take()) {
        if (*done) {
            app.ui.status = done->value();
        } else {
            app.ui.status = "Autosave failed: " + done->error().message;
            app.autosavedOnce = false;  // tried again at the next interval
        }
    }
    const Document& doc = *app.doc;
    if (!doc.dirty || !doc.planned || app.recoveryDir.empty() || app.autosaver.busy()) return;
    // The displacement and scene revisions only grow, so their sum changes whenever one does.
    const uint64_t displacement = doc.displacementRevision + doc.sampleRevision + doc.sceneRevision;
    const bool changed = !app.autosavedOnce || app.autosavedPositionRevision != doc.positionRevision ||
                         app.autosavedPlanRevision != doc.planRevision || app.autosavedDisplacementRevision != displacement;
    const double since = std::chrono::duration<double>(Clock::now() - app.lastAutosave).count();
    if (!changed || since < app.options.autosaveSeconds) return;
    app.autosaver.start([scene = sceneToSave(doc), directory = app.recoveryDir,
                         info = RecoveryInfo{doc.path, localTimeNow()}](const auto&) -> Result<std::string> {
        if (Status written = writeRecovery(directory, scene, info); !written) return written.error();
        return "Autosaved to " + directory;
    });
    app.lastAutosave = Clock::now();
    app.autosavedOnce = true;
    app.autosavedPositionRevision = doc.positionRevision;
    app.autosavedPlanRevision = doc.planRevision;
    app.autosavedDisplacementRevision = displacement;
}

void updateTitle(EditorApp& app) {
    std::string title = "Quadplan - " + documentTitle(*app.doc);
    if (app.loader.busy()) title += " (loading)";
    if (title != app.ui.title) {
        glfwSetWindowTitle(app.window, title.c_str());
        app.ui.title = title;
    }
}

// Viewport rectangles (framebuffer pixels) below the menu bar, above the timeline strip and left
// of the side panel.
void layoutViewports(EditorApp& app) {
    int w = 0, h = 0;
    glfwGetFramebufferSize(app.window, &w, &h);
    const float scale = ImGui::GetIO().DisplayFramebufferScale.x > 0 ? ImGui::GetIO().DisplayFramebufferScale.x : 1.0f;
    const int top = int(std::ceil(menuBarHeight() * scale));
    const int right = std::max(w - int(sidePanelWidth() * scale), w / 2);
    const int bottom = int(std::ceil(timelineHeight() * scale));  // the timeline strip
    const int width = std::max(right, 1), height = std::max(h - top - bottom, 1);
    const int gap = 2;  // px of background between viewports
    const int n = int(app.viewports.size()), columns = n >= 2 ? 2 : 1, rows = n == 4 ? 2 : 1;
    for (int i = 0; i < n; ++i) {
        const int column = i % columns, row = i / columns;
        const int x0 = column * width / columns + (column > 0 ? gap / 2 : 0);
        const int x1 = (column + 1) * width / columns - (column + 1 < columns ? gap / 2 : 0);
        const int y0 = top + row * height / rows + (row > 0 ? gap / 2 : 0);
        const int y1 = top + (row + 1) * height / rows - (row + 1 < rows ? gap / 2 : 0);
        app.viewports[i].rect = {{x0, y0}, {uint32_t(std::max(x1 - x0, 1)), uint32_t(std::max(y1 - y0, 1))}};
    }
}

void updateViewMatrices(EditorApp& app) {
    const Bounds bounds = app.doc->planned ? documentBounds(*app.doc) : Bounds{glm::vec3(-1), glm::vec3(1)};
    const glm::mat4 model = app.doc->planned ? activeObject(*app.doc).transform.matrix() : glm::mat4(1.0f);
    for (uint32_t i = 0; i < app.viewports.size(); ++i) {
        ViewportState& v = app.viewports[i];
        const float aspect = float(v.rect.extent.width) / float(v.rect.extent.height);
        v.renderCamera = renderCamera(cameraOf(app, i), aspect, bounds);
        v.worldViewProjection = viewProjection(v.renderCamera);
        v.viewProjection = v.worldViewProjection * model;
    }
}

// Progressive refinement: within kSettleMs of a camera step, and when full frames are slow
// (the median device time of the full frames among the kept samples over
// LaunchOptions::coarseAboveMs, 100 ms by default: a million faces on lavapipe, not a small cage
// anywhere), viewports draw coarse: adaptive factors for a view with kCoarsening times fewer
// pixels per unit, chosen once and kept while the camera moves (DrawView::navigating), and no
// cage lines. The first frame after it draws at full quality again.
constexpr double kSettleMs = 250.0;
constexpr float kCoarsening = 4.0f;

bool navigating(const EditorApp& app) {
    if (msSince(app.cameraMovedAt) > kSettleMs) return false;
    if (app.options.coarseAboveMs <= 0.0) return true;
    const Summary full = summarize(app.stats, FrameField::Gpu, 0, FrameFilter::SceneDrawnFull);
    return full.count > 0 && full.median > app.options.coarseAboveMs;
}

// The tessellation factor asked of viewport `i`'s scheme: the uniform factor, or (adaptive)
// the one that makes an average cage edge span about `pixelsPerEdge` pixels per segment in
// that viewport, within a per-frame triangle budget shared by the viewports.
uint32_t chooseFactor(EditorApp& app, uint32_t i) {
    if (app.tessellation.mode == TessellationMode::Uniform) return uint32_t(std::clamp(app.tessellation.factor, 1, 64));
    if (!app.doc->planned) return 1;
    const CageExtent& extent = cageExtent(*app.doc);
    const Bounds& bounds = extent.bounds;
    const glm::vec3 centre = 0.5f * (bounds.min + bounds.max);
    const ViewportState& v = app.viewports[i];
    const float ppu = pixelsPerUnit(projectionMatrix(v.renderCamera), v.rect.extent.height);
    const float depth = v.renderCamera.orthographic ? 1.0f : std::max(glm::length(centre - v.renderCamera.eye), 1e-4f);
    const float wanted = extent.meanEdgeLength() * ppu / depth / std::max(app.tessellation.pixelsPerEdge, 1.0f);
    const double subfaces = std::max<double>(app.doc->planned->subfaceCount(), 1.0);
    const double budget = std::sqrt(kAdaptiveTriangleBudget / (2.0 * subfaces * double(app.viewports.size())));
    return uint32_t(std::clamp<double>(std::ceil(wanted), 1.0, std::clamp(std::floor(budget), 1.0, 64.0)));
}

std::string resolvedPlansPath(const EditorApp& app) {
    if (app.plansPath != "auto") return app.plansPath;
    return app.ctx.isSoftware ? "cpu" : "tess";
}

// What each viewport asks of its scheme this frame.
std::vector<SchemeRequest> schemeRequests(EditorApp& app) {
    std::vector<SchemeRequest> requests;
    const bool adaptive = app.tessellation.mode == TessellationMode::Adaptive;
    // The grid paths go screen-adaptive (factors per frame, macro faces below one triangle a face)
    // only where the triangle budget cannot hold every sub-face at factor 1: below that, a
    // uniform factor within the budget draws faster on lavapipe (catmark_car's orbit frame
    // 20.8 ms against 31.6 ms screen-adaptive at 8 px).
    const double subfaces = app.doc->planned ? double(app.doc->planned->subfaceCount()) : 0.0;
    const bool pastBudget = 2.0 * subfaces * double(app.viewports.size()) > kAdaptiveTriangleBudget;
    for (uint32_t i = 0; i < app.viewports.size(); ++i) {
        ViewportState& v = app.viewports[i];
        v.factor = chooseFactor(app, i);
        SchemeRequest r;
        r.name = v.scheme;
        r.settings.planDepth = app.options.planDepth;
        r.settings.tessFactor = v.factor;
        if (v.scheme == "plans") {
            const std::string path = resolvedPlansPath(app);
            // Sculpted detail finer than this on screen costs no triangles (displaced_grid_factors.h);
            // zooming in brings it back.
            r.settings.options = {{"path", path}, {"displacement-pixels", "2"}};
            if (adaptive && (path == "tess" || pastBudget)) {  // per edge on the GPU, per frame on the grids: no rebuild on zoom
                r.settings.tessFactor = 8;
                r.settings.adaptivePixels = std::max(app.tessellation.pixelsPerEdge, 1.0f);
            }
        }
        r.heatMap = v.heatMap;
        r.heatFactor = std::clamp(v.factor, 4u, 16u);
        requests.push_back(std::move(r));
    }
    return requests;
}

// Everything the 3D viewports depend on, as bytes: equal keys draw equal pictures.
std::string sceneKey(const EditorApp& app, const std::vector<ViewportDraw>& draws, const DisplayOptions& options) {
    std::string key;
    const Document& doc = *app.doc;
    appendKey(key, app.documentGeneration);
    appendKey(key, doc.positionRevision);
    appendKey(key, doc.planRevision);
    appendKey(key, doc.hiddenRevision);
    appendKey(key, doc.sceneRevision);
    key += app.renderer.overlayKey;
    for (size_t i = 0; i < draws.size(); ++i) {
        const ViewportDraw& d = draws[i];
        appendKey(key, d.rect);
        appendKey(key, d.viewProjection);
        appendKey(key, d.pixelsPerUnit);
        appendKey(key, d.navigating);
        key += d.colorBy;
        appendKey(key, d.cull);  // the same picture, but the culling statistics change
        if (i < app.renderer.views.size()) {
            appendKey(key, app.renderer.views[i].drawRevision);
            appendKey(key, app.renderer.views[i].instance.has_value());
        }
        if (i < app.renderer.others.size()) appendKey(key, app.renderer.others[i].drawRevision);
    }
    appendKey(key, options.wireframe);
    appendKey(key, options.cage);
    appendKey(key, options.denseCage);
    appendKey(key, options.selection);
    appendKey(key, options.grid);
    appendKey(key, options.shading);
    appendKey(key, options.up);
    appendKey(key, app.swapchain.extent);
    return key;
}

Status drawFrame(EditorApp& app, Clock::time_point frameStart) {
    DisplayOptions options;
    options.wireframe = app.tessellation.showWireframe;
    options.cage = app.tessellation.showCage;
    options.grid = app.display.showGrid;
    options.denseCage = app.display.denseCageLines;
    options.shading = app.display.shading;
    options.up = upAxisOf(app);
    // Object mode shows the objects, not the edited cage's lines and selection; a coarse frame
    // while the camera moves (decided once for the whole frame) leaves the lines for the full
    // frame after it.
    const bool coarse = navigating(app);
    options.cage = options.cage && app.mode == EditorMode::Edit && !coarse;
    options.selection = app.mode == EditorMode::Edit;
    if (app.doc->editedCageRevision != app.syncedEditedCageRevision) {
        // Edit mode moved to another cage: every scheme instance and picker points into cages
        // that moved, and starts afresh.
        releaseSchemes(app.ctx, app.renderer);
        app.picking = PickCache{};
        ++app.documentGeneration;
    } else if (app.doc->objectsRevision != app.syncedObjectsRevision) {
        // Objects were added or removed: only the other cages' instances point into cages that
        // moved; the edited cage's views stay as they are.
        releaseOtherObjects(app.ctx, app.renderer);
    }
    app.syncedEditedCageRevision = app.doc->editedCageRevision;
    app.syncedObjectsRevision = app.doc->objectsRevision;
    const std::vector<SchemeRequest> requests = schemeRequests(app);
    const std::vector<uint32_t> changedSamples = takeUnsyncedSamples(*app.doc);
    const EditReport planChange = takeUnsyncedPlanChange(*app.doc);
    noteTopologyChange(app.picking, *app.doc, planChange);
    if (Status s = syncScene(app.ctx, app.renderer, app.catalog, *app.doc, app.documentGeneration, requests, changedSamples,
                             planChange, options);
        !s)
        return s;

    int w = 0, h = 0;
    glfwGetFramebufferSize(app.window, &w, &h);
    const uint32_t slot = app.swapchain.slot;
    // The CPU time leaves out the wait for a free frame slot and image (the GPU's or the display's
    // pace), and the sync's wait for earlier frames on the device.
    const double deviceWaitMs = app.renderer.lastDeviceWaitMs;
    double cpuMs = msSince(frameStart) - deviceWaitMs;
    Result<std::optional<SwapchainFrame>> begun = beginFrame(app.ctx, app.swapchain, uint32_t(w), uint32_t(h));
    const Clock::time_point recordStart = Clock::now();
    if (!begun) return begun.error();
    if (!*begun) return success();  // minimised
    const SwapchainFrame& frame = **begun;

    // The slot's previous frame has finished: its timings and counts are ready.
    if (app.timerUsed[slot]) {
        if (Result<double> gpu = readGpuTimerMs(app.ctx, *app.timers[slot]))
            app.stats.setGpuMs(size_t(app.frame - 1 - app.timerFrame[slot]), *gpu);
    }
    if (app.sceneRecorded[slot]) app.stats.viewportCounts = readViewportCounts(app.ctx, app.renderer, slot);
    if (app.timers[slot]) {
        beginGpuTimer(frame.cmd, *app.timers[slot]);
        app.timerUsed[slot] = true;
        app.timerFrame[slot] = app.frame;
    }

    std::vector<ViewportDraw> draws;
    for (const ViewportState& v : app.viewports) {
        ViewportDraw d;
        d.rect = v.rect;
        d.worldViewProjection = v.worldViewProjection;
        d.worldEye = v.renderCamera.eye;
        d.worldPixelsPerUnit = pixelsPerUnit(projectionMatrix(v.renderCamera), v.rect.extent.height);
        // In the active object's coordinates (scene_renderer.h ViewportDraw).
        const ObjectTransform transform = app.doc->planned ? activeObject(*app.doc).transform : ObjectTransform{};
        d.viewProjection = v.viewProjection;
        d.eye = glm::vec3(glm::inverse(transform.matrix()) * glm::vec4(d.worldEye, 1.0f));
        d.pixelsPerUnit = d.worldPixelsPerUnit * maxScale(transform);
        d.colorBy = v.colorBy;
        d.cull = v.cull;
        d.navigating = coarse;
        if (coarse) {
            d.pixelsPerUnit /= kCoarsening;
            d.worldPixelsPerUnit /= kCoarsening;
        }
        draws.push_back(d);
    }
    // Draw the viewports only when something they show changed; otherwise copy the last ones.
    // In the format the renderer's pipelines were made for (sceneCacheFormat, at start-up).
    if (Status s = ensureSceneCache(app.ctx, app.sceneCache, app.swapchain.extent, app.renderer.gpu.colorFormat); !s)
        return s;
    const std::string key = sceneKey(app, draws, options);
    const bool drawScene = key != app.sceneCache.key;
    if (drawScene) {
        const RenderTarget target = sceneCacheTarget(app.sceneCache);
        beginRendering(frame.cmd, target, true, kGapColor);
        vkCmdEndRendering(frame.cmd);
        recordScene(frame.cmd, app.renderer, slot, target, draws, options);
        app.sceneCache.key = key;
    }
    app.sceneRecorded[slot] = drawScene;
    recordCopyToFrame(frame.cmd, app.sceneCache, frame);
    if (Status s = recordImGui(app.ctx, app.imgui, app.swapchain, frame, ImGui::GetDrawData()); !s) return s;
    if (app.timers[slot]) endGpuTimer(frame.cmd, *app.timers[slot]);

    FrameSample sample;
    sample.sceneDrawn = drawScene;
    sample.culled = std::any_of(draws.begin(), draws.end(), [](const ViewportDraw& d) { return d.cull != CullMethod::None; });
    sample.coarse = std::any_of(draws.begin(), draws.end(), [](const ViewportDraw& d) { return d.navigating; });
    sample.cpuMs = cpuMs + msSince(recordStart);
    sample.deviceWaitMs = deviceWaitMs;
    sample.intervalMs = app.frame == 0 ? 0.0 : std::chrono::duration<double, std::milli>(frameStart - app.lastFrameStart).count();
    app.lastFrameStart = frameStart;
    if (app.lastEditFrame.frame + 1 == app.frame) app.lastEditFrame.intervalMs = sample.intervalMs;
    if (app.doc->lastEdit && app.doc->lastEdit->frame == app.frame && app.lastEditFrame.frame != app.frame)
        app.lastEditFrame = {app.frame, sample.cpuMs, -1.0, app.renderer.lastSyncMs};
    std::vector<uint8_t> pixels;
    const bool screenshot = !app.pendingScreenshot.empty();
    if (Status s = endFrame(app.ctx, app.swapchain, frame, screenshot ? &pixels : nullptr); !s) return s;
    app.stats.add(sample);
    ++app.frame;
    if (screenshot) {
        const std::string path = std::exchange(app.pendingScreenshot, std::string());
        Status written = writePng(path, app.swapchain.extent.width, app.swapchain.extent.height, pixels);
        if (app.automation) app.automation->screenshotWritten(path, written);
    }
    return success();
}

// Whether the next frame can wait for input: nothing animates, loads, replays or waits for its
// full-quality frame after the camera moved.
bool canIdle(const EditorApp& app) {
    const ImGuiIO& io = ImGui::GetIO();
    return (!app.automation || app.automation->finished()) && !app.loader.busy() && !app.job.busy() &&
           app.drag.kind == DragKind::None && !navigating(app) && !io.MouseDown[0] &&
           !io.MouseDown[1] && !io.MouseDown[2] && app.pendingScreenshot.empty();
}

void runLoop(EditorApp& app) {
    int settleFrames = 3;  // ImGui needs a frame or two after an event to settle hover and popups
    while (app.running) {
        if (settleFrames <= 0 && canIdle(app)) {
            // While an animation plays, until its next frame is due.
            const double untilFrame = secondsToNextFrame(app);
            const double timeout = untilFrame >= 0.0 ? std::min(untilFrame, 0.5) : 0.5;
            const Clock::time_point waitStart = Clock::now();
            glfwWaitEventsTimeout(timeout);
            if (msSince(waitStart) < 1000.0 * timeout - 10.0) settleFrames = 3;
        } else {
            glfwPollEvents();
            --settleFrames;
        }
        const Clock::time_point frameStart = Clock::now();
        if (glfwWindowShouldClose(app.window)) {
            glfwSetWindowShouldClose(app.window, GLFW_FALSE);
            requestQuit(app);
        }
        adoptFinishedLoad(app);
        adoptFinishedJob(app);
        if (app.automation) app.automation->beforeFrame(app);
        advancePlayback(app);

        beginImGuiBackends();
        if (app.automation) app.automation->applySyntheticInput();
        ImGui::NewFrame();
        layoutViewports(app);
        updateViewMatrices(app);
        handleViewportInput(app);
        app.leftDoubleClick = false;
        handleShortcuts(app);
        layoutViewports(app);  // a layout shortcut above: the new viewports, framed once
        if (std::exchange(app.frameAfterLayout, false))
            for (uint32_t i = 0; i < app.viewports.size(); ++i) frameSelection(app, i, true);
        updateViewMatrices(app);
        drawPanels(app);
        drawViewportOverlays(app);
        ImGui::Render();

        autosave(app);
        updateTitle(app);
        if (Status s = drawFrame(app, frameStart); !s) stopOnFatalError(app, "drawing failed: " + s.error().message);
        if (app.automation && app.automation->failed()) {
            app.exitCode = 3;
            app.running = false;
        }
    }
}

}  // namespace

void noteCameraMoved(EditorApp& app) {
    app.cameraMovedAt = Clock::now();
}

int runEditorApp(const LaunchOptions& options) {
    // An edit builds tables of a few to tens of MiB and frees the ones they replace. glibc would
    // hand each freed block back to the kernel (mmap above 128 KiB, heap trimming), so the next
    // edit faulted every page in again: a quarter of a 20k-face hole frame. Freed memory stays in
    // the heap for the next edit instead.
    mallopt(M_MMAP_THRESHOLD, 64 << 20);
    mallopt(M_TRIM_THRESHOLD, 256 << 20);
    EditorApp app;
    app.options = options;
    app.recoveryDir = recoveryDirectory();
    app.doc = std::make_unique<Document>();
    if (!options.automationScript.empty()) {
        Result<std::unique_ptr<Automation>> automation = loadAutomation(options.automationScript);
        if (!automation) {
            std::fprintf(stderr, "error: %s\n", automation.error().message.c_str());
            return 2;
        }
        app.automation = std::move(automation).value();
    }
    Status started = openWindow(app);
    if (started) started = startVulkan(app);
    if (!started) {
        std::fprintf(stderr, "error: %s\n", started.error().message.c_str());
        shutDown(app);
        return 1;
    }
    app.catalog = loadPlugins(pluginDirectory(options.pluginDir));
    for (const PluginProblem& problem : app.catalog.problems) std::fprintf(stderr, "warning: %s\n", problem.message.c_str());
    if (app.catalog.plugins.empty())
        app.ui.status = "No scheme plugins were found in " + app.catalog.directory + ": the viewports stay empty.";
    app.lastAutosave = app.lastFrameStart = Clock::now();
    if (std::optional<RecoveryInfo> found = findRecovery(app.recoveryDir)) {
        app.ui.recovery = RecoveryOffer{found->source, found->savedAt};
        app.ui.requestPopup = "Restore unsaved work?";
    }
    LoadRequest first{options.path};
    first.untitled = options.untitled;
    first.options = PlanOptions{options.planDepth, true};
    app.loader.start(first);

    runLoop(app);
    if (app.doc)
        if (std::optional<std::string> why = storeNewPlans(*app.doc)) std::fprintf(stderr, "warning: %s\n", why->c_str());

    const bool validate = options.validate;
    shutDown(app);
    if (validate && validationMessageCount(app.ctx) > 0) {
        for (const std::string& m : validationMessages(app.ctx)) std::fprintf(stderr, "validation: %s\n", m.c_str());
        return app.exitCode ? app.exitCode : 4;
    }
    return app.exitCode;
}

}  // namespace qp::editor
