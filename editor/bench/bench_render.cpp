// `quadplan bench render`: frame times of PlanPass's paths (plan_pass.h, draw_path.h) against the
// same surface pre-tessellated into a triangle buffer (the fastest this device can draw it) and
// against plain B-spline patches through the tessellator (bspline_pass.h), at uniform factors,
// into an offscreen target, in rounds (bench_frames.h). A frame's time is the wall time of
// everything the host does for it (CPU evaluation included) and of the submitAndWait round trip.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>

#include "bench_frames.h"
#include "bench_report.h"
#include "bench_stats.h"
#include "bspline_pass.h"
#include "camera.h"
#include "draw_path.h"
#include "mesh_pass.h"
#include "offscreen_target.h"
#include "plan_pass.h"
#include "plans/planned_cage.h"
#include "scheme_host.h"
#include "vk_commands.h"


namespace qp::cli {

void benchRender(const BenchCage& bench, const BenchArgs& args, Report& report) {
    const std::string& name = bench.name;
    std::fprintf(stderr, "bench render: %s (%u faces)\n", name.c_str(), bench.cage.faceCount());
    auto skip = [&](const std::string& why) { report.notes.push_back(name + ": skipped, " + why); };
    Result<FrameBench> made = createFrameBench(bench.cage, name, report.notes);
    if (!made) return skip(made.error().message);
    // Everything below is destroyed at the end, whatever failed on the way.
    FrameBench& frames = *made;
    PlannedCage& planned = *frames.planned;
    VulkanContext& ctx = frames.ctx;
    OffscreenTarget& target = frames.target;
    PlanPass& pass = frames.pass;
    PlanBuffers& buffers = frames.buffers;
    GpuMesh& preMesh = frames.preMesh;
    std::string& error = frames.error;
    BSplinePass bspline;
    if (error.empty()) {
        if (Result<BSplinePass> spline = createBSplinePass(ctx, VK_NULL_HANDLE, pass)) bspline = std::move(spline).value();
        else error = spline.error().message;
    }

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
                        Result<uint32_t> covered = coveredPixels(ctx, target);
                        if (!covered) {
                            error = covered.error().message;
                            break;
                        }
                        kind.coveredPixels = *covered;
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
    destroyBSplinePass(ctx, bspline);
    destroyFrameBench(frames);
}

}  // namespace qp::cli
