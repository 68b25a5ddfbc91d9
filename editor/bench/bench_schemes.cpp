// `quadplan bench schemes`: every scheme plugin at every uniform factor against the render
// suite's pre-tessellated triangles at the same factor, in the same rounds (bench_frames.h).
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

void benchSchemes(const BenchCage& bench, const BenchArgs& args, Report& report) {
    const std::string& name = bench.name;
    std::fprintf(stderr, "bench schemes: %s (%u faces)\n", name.c_str(), bench.cage.faceCount());
    auto skip = [&](const std::string& why) { report.notes.push_back(name + ": skipped, " + why); };
    const PluginCatalog catalog = loadPlugins(pluginDirectory());
    for (const PluginProblem& p : catalog.problems) report.notes.push_back(name + ": " + p.message);
    if (catalog.plugins.empty()) return skip("no scheme plugin loaded from " + catalog.directory);
    Result<FrameBench> made = createFrameBench(bench.cage, name, report.notes);
    if (!made) return skip(made.error().message);
    FrameBench& frames = *made;
    PlannedCage& planned = *frames.planned;
    VulkanContext& ctx = frames.ctx;
    OffscreenTarget& target = frames.target;
    PlanPass& pass = frames.pass;
    PlanBuffers& buffers = frames.buffers;
    GpuMesh& preMesh = frames.preMesh;
    std::string& error = frames.error;

    const CageFeatures features = analyzeCage(planned.cage(), planned.topology());
    const GpuContext gpu{&ctx, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_D32_SFLOAT};
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
        drawView.sampleCulling = false;  // like with like: every scheme's triangles reach the rasteriser
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

    destroyFrameBench(frames);
}

}  // namespace qp::cli
