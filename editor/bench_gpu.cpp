// `quadplan bench render` and `bench schemes`: every plan path and every scheme plugin against
// pre-tessellated triangles drawn in the same rounds; cmd_bench.cpp runs them and writes the
// report (bench_report.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>

#include "bench_stats.h"
#include "bspline_pass.h"
#include "camera.h"
#include "draw_path.h"
#include "mesh_pass.h"
#include "offscreen_target.h"
#include "plan_pass.h"
#include "planned_cage.h"
#include "scheme_host.h"
#include "vk_commands.h"
#include "bench_report.h"

namespace qp::cli {

namespace {

// ---- the render suite -------------------------------------------------------------------
// Frame times of PlanPass's paths (plan_pass.h, draw_path.h) against the same surface
// pre-tessellated into a triangle buffer (the fastest this device can draw it) and against
// plain B-spline patches through the tessellator (bspline_pass.h), at uniform factors, into an
// offscreen target. A frame's time is the wall time of everything the host does for it (CPU
// evaluation included) and of the submitAndWait round trip.
//
// Frames are measured in rounds: each round draws one frame of every kind back to back, and
// ratios are medians of the per-round ratios. Other work on the machine then slows a whole
// round rather than one kind of frame (measuring each kind in a block of its own made the
// baseline jump by 2-3x between factors on a busy machine). The baseline is drawn twice a
// round, first and halfway, and the round's ratios use the mean of the two.

constexpr uint32_t kRenderWarmups = 2;  // rounds: pipeline JIT, first touch of new buffers
constexpr uint32_t kRenderTargetFactor = 8;
constexpr double kRenderTargetRatio = 1.5;  // issue: default path within 1.5x of pre-tessellated

}  // namespace

// Lavapipe unless QUADPLAN_VK_DEVICE names a device (as the render tests). Validation stays
// off: it would dominate the timings.
Result<VulkanContext> createBenchContext() {
    ContextOptions options;
    if (const char* device = std::getenv("QUADPLAN_VK_DEVICE"); device && device[0]) {
        options.forceDevice = device;
    } else if (const char* icd = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json"; std::filesystem::exists(icd)) {
        setenv("VK_ICD_FILENAMES", icd, 1);  // before the loader looks for drivers
        setenv("VK_DRIVER_FILES", icd, 1);
    }
    return createContext(options);
}

Result<BenchDevice> createBenchDevice(uint32_t width, uint32_t height) {
    Result<VulkanContext> context = createBenchContext();
    if (!context) return context.error();
    BenchDevice device{std::move(context).value(), {}};
    Result<OffscreenTarget> target = createOffscreenTarget(device.ctx, width, height, VK_FORMAT_R8G8B8A8_UNORM);
    if (!target) {
        destroyContext(device.ctx);
        return target.error();
    }
    device.target = *target;
    return device;
}

void destroyBenchDevice(BenchDevice& device) {
    destroyOffscreenTarget(device.ctx, device.target);
    destroyContext(device.ctx);
}

std::string loadAverage() {
    std::string one, five, fifteen;
    std::ifstream("/proc/loadavg") >> one >> five >> fifteen;
    return one + " " + five + " " + fifteen;
}

namespace {

// One kind of frame: `host` runs first (untimed when `hostTimed` is false), then `record` is
// submitted and waited for; both count.
struct FrameKind {
    std::string name;
    std::function<Status()> host;
    std::function<void(VkCommandBuffer)> record;
    bool baseline = false;       // pre-tessellated: the round's reference
    std::vector<double> ms, ratios;
    std::vector<double> cpuRatios;  // the same with the process's CPU time instead of wall time
    uint32_t coveredPixels = 0;  // not the background in the last round: a sanity check

    double medianMs() const { return ms.empty() ? NAN : median(ms); }
    double medianRatio() const { return ratios.empty() ? NAN : median(ratios); }
    double medianCpuRatio() const { return cpuRatios.empty() ? NAN : median(cpuRatios); }
};

// CPU time of this process, every thread (lavapipe's and TBB's included), in ms.
double processCpuMs() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

std::string cell(const FrameKind& k, bool withRatio = true) {
    if (k.ms.empty()) return "";
    return number(k.medianMs()) + (withRatio ? " (" + number(k.medianRatio()) + "x)" : "");
}

// The default path's cells also give the CPU-time ratio, which other work on the machine
// hardly moves.
std::string cellWithCpu(const FrameKind& k) {
    if (k.ms.empty()) return "";
    return number(k.medianMs()) + " (" + number(k.medianRatio()) + "x; CPU " + number(k.medianCpuRatio()) + "x)";
}

// The render and schemes suites' baseline at uniform `factor`: the plans grid evaluated once
// on the CPU and copied into a mesh of its own (replacing `mesh`), drawn with
// recordShadedTriangles, i.e. the limit of this device for those triangles.
Status preparePreTessellated(const VulkanContext& ctx, PlanPass& pass, PlanBuffers& buffers, const PlannedCage& planned,
                             uint32_t factor, GpuMesh& mesh) {
    if (Status s = prepareGrid(ctx, pass, buffers, factor); !s) return s;
    evaluateGridOnCpu(planned, buffers);
    const GridLayout& layout = buffers.gridLayout;
    destroyMesh(ctx, mesh);
    Result<GpuMesh> uploaded =
        uploadMesh(ctx, {static_cast<const MeshVertex*>(buffers.grid.data), layout.slotCount()}, layout.indices);
    if (!uploaded) return uploaded.error();
    mesh = std::move(uploaded).value();
    return success();
}

}  // namespace

void benchRender(const BenchCage& bench, const BenchArgs& args, Report& report) {
    const std::string& name = bench.name;
    std::fprintf(stderr, "bench render: %s (%u faces)\n", name.c_str(), bench.cage.faceCount());
    auto skip = [&](const std::string& why) { report.notes.push_back(name + ": skipped, " + why); };
    PlanDatabase database;
    Result<PlannedCage> created = PlannedCage::create(bench.cage, database, PlanOptions{}, name);
    if (!created) return skip(created.error().message);
    PlannedCage& planned = *created;
    Result<VulkanContext> context = createBenchContext();
    if (!context) return skip(context.error().message);
    VulkanContext ctx = std::move(context).value();
    report.notes.push_back(name + ": load average at the start (1, 5, 15 min): " + loadAverage());

    // Everything below is destroyed at the end, whatever failed on the way.
    const VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
    OffscreenTarget target;
    PlanPass pass;
    BSplinePass bspline;
    PlanBuffers buffers;
    GpuMesh preMesh;
    std::string error;
    auto take = [&](auto result, auto& out) {
        if (result) out = std::move(result).value();
        else if (error.empty()) error = result.error().message;
        return bool(result);
    };
    take(createOffscreenTarget(ctx, kRenderSize, kRenderSize, format), target) &&
        take(createPlanPass(ctx, VK_NULL_HANDLE, format), pass) &&
        take(createBSplinePass(ctx, VK_NULL_HANDLE, pass), bspline) && take(uploadPlans(ctx, planned), buffers);

    const DrawPath picked = resolveDrawPath(DrawPath::Auto, ctx);
    const uint32_t subfaces = uint32_t(buffers.data.subfaces.size());
    std::string defaultTable =
        "### render: " + name + " (" + std::to_string(bench.cage.faceCount()) + " faces, " + std::to_string(subfaces) +
        " drawn sub-faces), the default path (" + drawPathName(picked) + ")\n\n"
        "| factor | grid factor | triangles | pre-tessellated ms | view frame ms | drag frame ms | edit frame ms |\n"
        "|---:|---:|---:|---:|---:|---:|---:|\n";
    std::string pathTable = "### render: " + name + ", every path (ms, and the ratio to pre-tessellated)\n\n"
                            "| factor | tess view | tess edit | grid (compute) edit | cpu edit | grid / cpu view | "
                            "grid drag | cpu drag | B-spline |\n"
                            "|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    bool coverageDiffers = false;
    if (error.empty())
        if (Status s = bindPlanBuffers(ctx, pass, buffers); !s) error = s.error().message;
    if (error.empty()) {
        const Bounds bounds = computeBounds(bench.cage);
        const RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
        PlanView view;
        view.viewProjection = viewProjection(camera);
        view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(camera), kRenderSize);
        const RenderTarget rt = renderTarget(target);

        // The drag: an interior vertex moving there and back, as under the editor's mouse.
        const uint32_t dragged = [&] {
            const Topology& topology = planned.topology();
            for (uint32_t k = 0; k < planned.cage().vertexCount(); ++k) {
                uint32_t v = (planned.cage().vertexCount() / 2 + k) % planned.cage().vertexCount();
                if (topology.vertexFaceCount(v) >= 3) return v;
            }
            return 0u;
        }();
        const glm::vec3 home = planned.cage().positions[dragged];
        const glm::vec3 away = home + 2e-3f * bounds.diagonal() * glm::vec3(0.3f, 0.5f, 0.8f);
        bool dragAway = true;
        auto drag = [&]() -> Status {
            const glm::vec3 to = dragAway ? away : home;
            dragAway = !dragAway;
            Result<EditReport> moved = planned.moveVertices({&dragged, 1}, {&to, 1});
            return moved ? success() : Status(moved.error());
        };

        for (uint32_t factor : args.factorsOr({1, 2, 4, 8, 16})) {
            const TessellationSettings settings{factor, 8.0f};
            // The grid and, from it, the pre-tessellated triangles.
            if (Status s = preparePreTessellated(ctx, pass, buffers, planned, factor, preMesh); !s) {
                report.notes.push_back(name + ", factor " + std::to_string(factor) + ": not measured, " + s.error().message);
                continue;
            }
            const GridLayout& layout = buffers.gridLayout;
            const uint32_t gridFactor = layout.maxFactor, triangles = uint32_t(layout.indices.size() / 3);

            auto dropAll = [&] {
                buffers.gridEvaluator = GridEvaluator::None;
                buffers.controlPointLevel = kNoControlPoints;
                return success();
            };
            auto drawGrid = [&](VkCommandBuffer cmd) { recordGridDraw(cmd, pass, buffers, rt, view); };
            // Order matters where kinds share state: each kind leaves what the next one needs.
            std::vector<FrameKind> kinds;
            auto add = [&](const char* kindName, std::function<Status()> host, std::function<void(VkCommandBuffer)> record) {
                FrameKind k;
                k.name = kindName;
                k.baseline = k.name == "pre-tessellated";
                k.host = std::move(host);
                k.record = std::move(record);
                kinds.push_back(std::move(k));
            };
            auto drawPre = [&](VkCommandBuffer cmd) {
                recordShadedTriangles(cmd, pass, preMesh.vertices.buffer, preMesh.indices.buffer, preMesh.indexCount, rt, view);
            };
            add("pre-tessellated", {}, drawPre);
            add("tess edit", dropAll, [&](VkCommandBuffer cmd) { recordTessellated(cmd, pass, buffers, rt, view, settings); });
            add("tess view", {}, [&](VkCommandBuffer cmd) { recordTessellated(cmd, pass, buffers, rt, view, settings); });
            add("B-spline", {}, [&](VkCommandBuffer cmd) { recordBSplinePatches(cmd, bspline, pass, buffers, rt, view, settings); });
            add("grid edit", dropAll, [&](VkCommandBuffer cmd) { recordGrid(cmd, pass, buffers, rt, view); });
            // A drag updates on the device what the device filled.
            add("grid drag", drag, [&](VkCommandBuffer cmd) {
                recordMovedVertices(cmd, pass, buffers, planned, {&dragged, 1});
                drawGrid(cmd);
            });
            // The cpu path as the editor runs it: no control points on the device.
            add("pre-tessellated", {}, drawPre);  // halfway through the round
            add("cpu edit", [&] {
                (void)dropAll();
                evaluateGridOnCpu(planned, buffers);
                return success();
            }, drawGrid);
            add("view", {}, drawGrid);
            // The CPU grid's update runs in recordMovedVertices, on the host, before the submit.
            add("cpu drag", drag, [&](VkCommandBuffer cmd) {
                recordMovedVertices(cmd, pass, buffers, planned, {&dragged, 1});
                drawGrid(cmd);
            });

            const uint32_t rounds = kRenderWarmups + args.repeats;
            for (uint32_t round = 0; round < rounds && error.empty(); ++round) {
                std::vector<double> roundMs, roundCpuMs;
                for (FrameKind& kind : kinds) {
                    const double cpuStart = processCpuMs();
                    auto start = Clock::now();
                    Status status = kind.host ? kind.host() : success();
                    if (status) status = submitAndWait(ctx, kind.record);
                    const double ms = msSince(start);
                    roundCpuMs.push_back(processCpuMs() - cpuStart);
                    if (!status) {
                        error = kind.name + ": " + status.error().message;
                        break;
                    }
                    roundMs.push_back(ms);
                    if (round + 1 == rounds) {  // untimed: what the last frame covered
                        Result<std::vector<uint8_t>> pixels = readPixels(ctx, target);
                        if (!pixels) {
                            error = pixels.error().message;
                            break;
                        }
                        const uint32_t* rgba = reinterpret_cast<const uint32_t*>(pixels->data());
                        kind.coveredPixels = 0;
                        for (size_t p = 0; p < pixels->size() / 4; ++p) kind.coveredPixels += rgba[p] != rgba[0];
                    }
                }
                if (round < kRenderWarmups || !error.empty()) continue;
                double baseSum = 0.0, baseCpuSum = 0.0, baseCount = 0.0;
                for (size_t k = 0; k < kinds.size(); ++k)
                    if (kinds[k].baseline) baseSum += roundMs[k], baseCpuSum += roundCpuMs[k], baseCount += 1.0;
                // The baseline's entries: its two frames (the same kind, twice) fold into one.
                for (size_t k = 0; k < kinds.size(); ++k) {
                    const double ms = kinds[k].baseline ? baseSum / baseCount : roundMs[k];
                    const double cpuMs = kinds[k].baseline ? baseCpuSum / baseCount : roundCpuMs[k];
                    kinds[k].ms.push_back(ms);
                    kinds[k].ratios.push_back(ms / (baseSum / baseCount));
                    kinds[k].cpuRatios.push_back(cpuMs / (baseCpuSum / baseCount));
                }
            }
            if (!error.empty()) break;
            if (Result<EditReport> back = planned.moveVertices({&dragged, 1}, {&home, 1}); back) {
                dragAway = true;
                updatePositions(buffers, planned);
            }

            auto kind = [&](const char* n) -> const FrameKind& {
                for (const FrameKind& k : kinds)
                    if (k.name == n) return k;
                std::abort();
            };
            const FrameKind& pre = kind("pre-tessellated");
            const FrameKind& defaultEdit = kind(picked == DrawPath::Tessellated ? "tess edit" : picked == DrawPath::Grid ? "grid edit" : "cpu edit");
            const FrameKind& defaultView = kind(picked == DrawPath::Tessellated ? "tess view" : "view");
            const FrameKind& defaultDrag = kind(picked == DrawPath::Grid ? "grid drag" : "cpu drag");
            // Grid factors other than the request (odd factors on cages with non-quads) draw a
            // finer surface than the pre-tessellated one at the request: compare like with like.
            for (const FrameKind& k : kinds)
                if (k.name != "B-spline" && std::abs(double(k.coveredPixels) - pre.coveredPixels) > 0.02 * pre.coveredPixels)
                    coverageDiffers = true;
            defaultTable += "| " + std::to_string(factor) + " | " + std::to_string(gridFactor) + " | " + std::to_string(triangles) +
                            " | " + cell(pre, false) + " | " + cellWithCpu(defaultView) + " | " +
                            (picked == DrawPath::Tessellated ? std::string("") : cellWithCpu(defaultDrag)) + " | " +
                            cellWithCpu(defaultEdit) + " |\n";
            pathTable += "| " + std::to_string(factor) + " | " + cell(kind("tess view")) + " | " + cell(kind("tess edit")) + " | " +
                         cell(kind("grid edit")) + " | " + cell(kind("cpu edit")) + " | " + cell(kind("view")) + " | " +
                         cell(kind("grid drag")) + " | " + cell(kind("cpu drag")) + " | " + cell(kind("B-spline")) + " |\n";
            for (const FrameKind& k : kinds)
                report.series.push_back({"frame time, " + name, std::to_string(factor), k.name, k.medianMs(), "ms"});
            std::fprintf(stderr, "  factor %u: pre %s, view %s, cpu drag %s, cpu edit %s, grid edit %s, tess view %s, tess edit %s ms\n",
                         factor, cell(pre, false).c_str(), cell(kind("view")).c_str(), cell(kind("cpu drag")).c_str(),
                         cell(kind("cpu edit")).c_str(), cell(kind("grid edit")).c_str(), cell(kind("tess view")).c_str(),
                         cell(kind("tess edit")).c_str());

            if (factor != kRenderTargetFactor) continue;
            // The target: the default path within 1.5x of pre-tessellated triangles.
            struct Target {
                const char* frame;
                const FrameKind* kind;
            };
            for (Target t : {Target{"view frame (camera moved)", &defaultView}, Target{"drag frame (one vertex moved)", &defaultDrag},
                             Target{"edit frame (everything re-evaluated)", &defaultEdit}}) {
                if (picked == DrawPath::Tessellated && t.kind == &defaultDrag) continue;
                Row r;
                r.cage = name;
                r.faces = bench.cage.faceCount();
                r.benchmark = std::string("factor 8, ") + t.frame + ": default path (" + drawPathName(picked) +
                              ") vs pre-tessellated triangles; 2nd: plain B-spline patches";
                r.repeats = args.repeats;
                r.unit = "ms";
                r.ours = t.kind->medianMs();
                r.baseline = pre.medianMs();
                r.pairedRatio = t.kind->medianRatio();
                r.baseline2 = kind("B-spline").medianMs();
                r.targetValue = kRenderTargetRatio;
                report.rows.push_back(r);
            }
            // Which path is fastest for a full re-evaluation on this device, as measured.
            const FrameKind* fastest = &kind("tess edit");
            for (const char* n : {"grid edit", "cpu edit"})
                if (kind(n).medianMs() < fastest->medianMs()) fastest = &kind(n);
            report.notes.push_back(name + ": auto picks " + drawPathName(picked) + " on '" + ctx.deviceName +
                                   "'; the fastest edit frame at factor 8 is " + fastest->name + " (" +
                                   number(fastest->medianMs()) + " ms; tess " + number(kind("tess edit").medianMs()) +
                                   ", grid " + number(kind("grid edit").medianMs()) + ", cpu " +
                                   number(kind("cpu edit").medianMs()) + ")");
        }
    }
    if (!error.empty()) report.notes.push_back(name + ": stopped, " + error);
    report.notes.push_back(name + ": load average at the end: " + loadAverage());
    if (coverageDiffers)
        report.notes.push_back(name + ": WARNING: a plans path covers more than 2% more or fewer pixels than the "
                                      "pre-tessellated triangles: the paths may not draw the same surface");
    if (report.appendix.empty())
        report.appendix =
            "Render suite: " + std::to_string(kRenderSize) + "x" + std::to_string(kRenderSize) +
            " offscreen target, camera framing the cage, uniform factors. Each round draws one frame of every kind "
            "back to back, the pre-tessellated one twice (first and halfway); medians of R rounds after " +
            std::to_string(kRenderWarmups) +
            " warm-up rounds. A frame's time is wall time: host work for the frame (CPU evaluation, updates) plus the "
            "submitAndWait round trip. Ratios (in brackets) are medians of the per-round ratios to the mean of the "
            "round's two pre-tessellated frames; CPU: the same with this process's CPU time (all threads), which other "
            "work on the machine hardly moves but which counts work on two cores twice. Pre-tessellated = the grid's "
            "vertices evaluated once, copied into a vertex and an index buffer of their own, drawn with the grid's "
            "plain-shading pipeline (the same shaders as a grid view frame). View frame: the camera moved, the cached grid is drawn (tess: "
            "the cached control points are tessellated). Drag frame: one vertex moved (PlannedCage::moveVertices, then "
            "recordMovedVertices re-evaluates the sub-faces around it), then the draw. Edit frame: everything "
            "re-evaluated (positions or factor changed), then the draw. B-spline = one bicubic patch per sub-face "
            "through the tessellator (a cost baseline, not the exact surface). Grid factor: the grid rounds odd "
            "factors up on cages with non-quads.\n\n";
    report.appendix += defaultTable + "\n" + pathTable + "\n";

    vkDeviceWaitIdle(ctx.device);
    destroyMesh(ctx, preMesh);
    destroyPlanBuffers(ctx, buffers);
    destroyBSplinePass(ctx, bspline);
    destroyPlanPass(ctx, pass);
    destroyOffscreenTarget(ctx, target);
    destroyContext(ctx);
}

namespace {

// ---- the schemes suite -----------------------------------------------------------------

// Pixels of the last frame that are not the background (the top-left pixel's colour).
Result<uint32_t> coveredPixels(const VulkanContext& ctx, const OffscreenTarget& target) {
    Result<std::vector<uint8_t>> pixels = readPixels(ctx, target);
    if (!pixels) return pixels.error();
    const uint32_t* rgba = reinterpret_cast<const uint32_t*>(pixels->data());
    uint32_t covered = 0;
    for (size_t p = 0; p < pixels->size() / 4; ++p) covered += rgba[p] != rgba[0];
    return covered;
}

}  // namespace

// Every scheme plugin at every uniform factor, frame time against the render suite's
// pre-tessellated triangles at the same factor, measured in the same rounds.
void benchSchemes(const BenchCage& bench, const BenchArgs& args, Report& report) {
    const std::string& name = bench.name;
    std::fprintf(stderr, "bench schemes: %s (%u faces)\n", name.c_str(), bench.cage.faceCount());
    auto skip = [&](const std::string& why) { report.notes.push_back(name + ": skipped, " + why); };
    PlanDatabase database;
    Result<PlannedCage> created = PlannedCage::create(bench.cage, database, PlanOptions{}, name);
    if (!created) return skip(created.error().message);
    PlannedCage& planned = *created;
    const PluginCatalog catalog = loadPlugins(pluginDirectory());
    for (const PluginProblem& p : catalog.problems) report.notes.push_back(name + ": " + p.message);
    if (catalog.plugins.empty()) return skip("no scheme plugin loaded from " + catalog.directory);
    Result<VulkanContext> context = createBenchContext();
    if (!context) return skip(context.error().message);
    VulkanContext ctx = std::move(context).value();
    report.notes.push_back(name + ": load average at the start (1, 5, 15 min): " + loadAverage());

    const VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
    OffscreenTarget target;
    PlanPass pass;
    PlanBuffers buffers;
    GpuMesh preMesh;
    std::string error;
    auto take = [&](auto result, auto& out) {
        if (result) out = std::move(result).value();
        else if (error.empty()) error = result.error().message;
        return bool(result);
    };
    take(createOffscreenTarget(ctx, kRenderSize, kRenderSize, format), target) &&
        take(createPlanPass(ctx, VK_NULL_HANDLE, format), pass) && take(uploadPlans(ctx, planned), buffers);

    const CageFeatures features = analyzeCage(planned.cage(), planned.topology());
    const GpuContext gpu{&ctx, VK_NULL_HANDLE, format, VK_FORMAT_D32_SFLOAT};
    std::string table = "### schemes: " + name + " (" + std::to_string(bench.cage.faceCount()) +
                        " faces), frame ms and the ratio to pre-tessellated triangles at the same factor\n\n"
                        "| scheme | factor | triangles | frame ms | pre-tessellated ms (triangles) | ratio | covered pixels vs "
                        "pre-tessellated |\n|---|---:|---:|---:|---:|---:|---:|\n";
    std::vector<std::string> noted;  // refusals and failures, each noted once
    auto noteOnce = [&](const std::string& text) {
        if (std::find(noted.begin(), noted.end(), text) == noted.end()) {
            noted.push_back(text);
            report.notes.push_back(name + ": " + text);
        }
    };
    std::vector<std::pair<std::string, std::vector<uint64_t>>> trianglesPerScheme;  // over the factors
    if (error.empty())
        if (Status s = bindPlanBuffers(ctx, pass, buffers); !s) error = s.error().message;
    if (error.empty()) {
        const Bounds bounds = computeBounds(bench.cage);
        const RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
        PlanView view;
        view.viewProjection = viewProjection(camera);
        view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(camera), kRenderSize);
        DrawView drawView;
        drawView.viewProjection = view.viewProjection;
        drawView.eye = camera.eye;
        drawView.pixelsPerUnit = view.pixelsPerUnit;
        const RenderTarget rt = renderTarget(target);

        for (uint32_t factor : args.factorsOr({1, 2, 4, 8, 16})) {
            const std::string at = ", factor " + std::to_string(factor);
            // The baseline, as in the render suite.
            if (Status s = preparePreTessellated(ctx, pass, buffers, planned, factor, preMesh); !s) {
                report.notes.push_back(name + at + ": not measured, " + s.error().message);
                continue;
            }
            const uint32_t preTriangles = uint32_t(buffers.gridLayout.indices.size() / 3);
            auto drawPre = [&](VkCommandBuffer cmd) {
                recordShadedTriangles(cmd, pass, preMesh.vertices.buffer, preMesh.indices.buffer, preMesh.indexCount, rt, view);
            };

            struct Measured {
                Measured(std::string schemeName, PreparedScheme scheme)
                    : name(std::move(schemeName)), prepared(std::move(scheme)) {}
                std::string name;
                PreparedScheme prepared;
                DrawStats draw;
                std::vector<double> ms, ratios;
                bool failed = false;
                uint32_t covered = 0;
            };
            std::vector<Measured> schemes;
            for (const auto& plugin : catalog.plugins) {
                SchemeSettings settings;
                settings.tessFactor = factor;
                Result<PreparedScheme> prepared = prepareScheme(catalog, plugin->name, planned, features, settings, gpu, name);
                if (!prepared) {
                    noteOnce("scheme " + plugin->name + " not measured: " + prepared.error().message);
                    continue;
                }
                schemes.emplace_back(plugin->name, std::move(prepared).value());
            }
            // A frame as if the cage moved every frame: the scheme's update, its record, the
            // submit and the wait.
            auto schemeFrame = [&](Measured& s) -> Result<double> {
                const auto start = Clock::now();
                Status ok = s.prepared.instance.update();
                Result<DrawStats> drawn = DrawStats{};
                if (ok) ok = submitAndWait(ctx, [&](VkCommandBuffer cmd) { drawn = s.prepared.instance.record(cmd, rt, drawView); });
                if (ok && !drawn) ok = drawn.error();
                if (!ok) return ok.error();
                s.draw = *drawn;
                return msSince(start);
            };
            auto preFrame = [&]() -> Result<double> {
                const auto start = Clock::now();
                if (Status ok = submitAndWait(ctx, drawPre); !ok) return ok.error();
                return msSince(start);
            };
            // Each round: pre-tessellated, every scheme, pre-tessellated again; ratios against
            // the mean of the round's two baseline frames.
            std::vector<double> preMs;
            const uint32_t rounds = kRenderWarmups + args.repeats;
            for (uint32_t round = 0; round < rounds && error.empty(); ++round) {
                Result<double> before = preFrame();
                std::vector<double> roundMs(schemes.size(), NAN);
                for (size_t k = 0; k < schemes.size() && before; ++k) {
                    if (schemes[k].failed) continue;
                    Result<double> ms = schemeFrame(schemes[k]);
                    if (!ms) {
                        schemes[k].failed = true;
                        noteOnce("scheme " + schemes[k].name + at + ": stopped, " + ms.error().message);
                        continue;
                    }
                    roundMs[k] = *ms;
                }
                Result<double> after = before ? preFrame() : before;
                if (!after) {
                    error = "pre-tessellated" + at + ": " + after.error().message;
                    break;
                }
                if (round < kRenderWarmups) continue;
                const double base = 0.5 * (*before + *after);
                preMs.push_back(base);
                for (size_t k = 0; k < schemes.size(); ++k)
                    if (!schemes[k].failed && !std::isnan(roundMs[k])) {
                        schemes[k].ms.push_back(roundMs[k]);
                        schemes[k].ratios.push_back(roundMs[k] / base);
                    }
            }
            // Untimed: what each drew, as a sanity check that it drew the same surface.
            uint32_t preCovered = 0;
            if (error.empty()) {
                Status drawn = submitAndWait(ctx, drawPre);
                Result<uint32_t> covered = drawn ? coveredPixels(ctx, target) : Result<uint32_t>(drawn.error());
                if (covered) preCovered = *covered;
                else error = covered.error().message;
                for (Measured& s : schemes) {
                    if (s.failed || !error.empty()) continue;
                    Result<double> frame = schemeFrame(s);
                    Result<uint32_t> c = frame ? coveredPixels(ctx, target) : Result<uint32_t>(frame.error());
                    if (c) {
                        s.covered = *c;
                    } else {
                        s.failed = true;
                        noteOnce("scheme " + s.name + at + ": stopped, " + c.error().message);
                    }
                }
            }
            for (Measured& s : schemes)
                if (Status destroyed = s.prepared.instance.destroyGpu(); !destroyed)
                    noteOnce("scheme " + s.name + at + ": " + destroyed.error().message);
            if (!error.empty()) break;

            const double pre = median(preMs);
            report.series.push_back({"scheme frame time, " + name, std::to_string(factor), "pre-tessellated", pre, "ms"});
            for (const Measured& s : schemes) {
                if (s.failed || s.ms.empty()) continue;
                Row r;
                r.cage = name;
                r.faces = bench.cage.faceCount();
                // Both triangle counts in the row: a scheme that draws more is not compared like with like.
                r.benchmark = "scheme " + s.name + at + " (" + (s.draw.triangles ? std::to_string(s.draw.triangles) : std::string("?")) +
                              " triangles, " + drawnByName(s.draw.drawnBy) + "): frame (update + record + submit) vs " +
                              "pre-tessellated triangles (" + std::to_string(preTriangles) + ")";
                r.repeats = args.repeats;
                r.unit = "ms";
                r.ours = median(s.ms);
                r.baseline = pre;
                r.pairedRatio = median(s.ratios);
                r.targetValue = kRenderTargetRatio;
                report.rows.push_back(r);
                report.series.push_back({"scheme frame time, " + name, std::to_string(factor), s.name, r.ours, "ms"});
                const std::string coverage =
                    preCovered ? number(100.0 * double(s.covered) / double(preCovered)) + "%" : std::string("");
                table += "| " + s.name + " | " + std::to_string(factor) + " | " +
                         (s.draw.triangles ? std::to_string(s.draw.triangles) : std::string("?")) + " | " + number(r.ours) +
                         " | " + number(pre) + " (" + std::to_string(preTriangles) + ") | " + number(r.ratio()) + " | " +
                         coverage + " |\n";
                auto seen = std::find_if(trianglesPerScheme.begin(), trianglesPerScheme.end(),
                                         [&](const auto& entry) { return entry.first == s.name; });
                if (seen == trianglesPerScheme.end()) seen = trianglesPerScheme.insert(seen, {s.name, {}});
                seen->second.push_back(s.draw.triangles);
                std::fprintf(stderr, "  %s%s: %s ms (%sx pre-tessellated, %s ms)\n", s.name.c_str(), at.c_str(),
                             number(r.ours).c_str(), number(r.ratio()).c_str(), number(pre).c_str());
            }
        }
    }
    for (const auto& [scheme, triangles] : trianglesPerScheme)
        if (triangles.size() > 1 && triangles.front() != 0 &&
            std::all_of(triangles.begin(), triangles.end(), [&](uint64_t t) { return t == triangles.front(); }))
            report.notes.push_back(name + ": scheme " + scheme + " draws the same " + std::to_string(triangles.front()) +
                                   " triangles at every factor (it has no uniform factor)");
    if (!error.empty()) report.notes.push_back(name + ": stopped, " + error);
    report.notes.push_back(name + ": load average at the end: " + loadAverage());
    if (report.appendix.empty())
        report.appendix =
            "Schemes suite: every scheme plugin at each uniform factor (SchemeSettings::tessFactor), " +
            std::to_string(kRenderSize) + "x" + std::to_string(kRenderSize) +
            " offscreen target, camera framing the cage. A scheme frame is wall time of update() (as if the cage moved "
            "every frame), record() and the submitAndWait round trip. Pre-tessellated is the render suite's baseline: "
            "the plans grid at the same factor evaluated once into vertex and index buffers of their own and drawn "
            "with the plain-shading pipeline. Each round draws the baseline, every scheme, the baseline again; ratios "
            "are medians of the per-round ratios to the mean of the round's two baseline frames, after " +
            std::to_string(kRenderWarmups) +
            " warm-up rounds. Target: the render suite's 1.5x (issue 8 names no target per scheme; informative). "
            "Covered pixels: the scheme's last frame against the baseline's (a sanity check that both drew the "
            "cage). Triangles '?': the scheme does not report them.\n\n";
    report.appendix += table + "\n";

    vkDeviceWaitIdle(ctx.device);
    destroyMesh(ctx, preMesh);
    destroyPlanBuffers(ctx, buffers);
    destroyPlanPass(ctx, pass);
    destroyOffscreenTarget(ctx, target);
    destroyContext(ctx);
}

}  // namespace qp::cli
