// `quadplan bench macro` (issue 21; Brainerd et al. 2016 §9.4): macro faces against single faces
// on the plans scheme's default path, per-face factors 1/4, 1/2, 1, 2 and 4, on catmark_car, the
// generated cage and a regular torus of the generated cage's size (every face regular: the
// paper's synthetic case). Per factor and partition (rectangles, quartets, blocks) one row: the frame with
// macro faces against single faces at the same factor (below 1, against single faces at factor
// 1, the least they can draw). Below 1 the macro faces draw fewer triangles; at 1 and above they
// draw the same triangles over vertices their faces share (`--option macro-whole=on`) instead of
// each face's own copies. A frame: the camera turned by 1 degree, record + submit + wait
// (uniform factors: the grid is cached, so it is the draw), median of the rounds.
#include <algorithm>
#include <cstdio>

#include <glm/gtc/matrix_transform.hpp>

#include "bench_report.h"
#include "bench_stats.h"
#include "camera.h"
#include "headless_scene.h"
#include "mesh/generated_cage.h"
#include "offscreen_target.h"
#include "scheme_host.h"
#include "vk_commands.h"

namespace qp::cli {

namespace {

constexpr uint32_t kWidth = 800, kHeight = 600;

// A per-face factor: `factor` segments a face edge, or 1 / minify.
struct FaceFactor {
    uint32_t factor, minify;
    std::string text() const { return minify > 1 ? "1/" + std::to_string(minify) : std::to_string(factor); }
};

struct FrameResult {
    double ms = NAN;
    uint64_t triangles = 0;
    std::string error;
};

void benchMacroCage(const std::string& name, const Cage& cage, const BenchArgs& args, Report& report) {
    std::fprintf(stderr, "bench macro: %s (%u faces)\n", name.c_str(), cage.faceCount());
    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(cage, database, PlanOptions{}, name);
    if (!planned) return report.notes.push_back(name + ": skipped, " + planned.error().message);
    const PluginCatalog catalog = loadPlugins(pluginDirectory());
    Result<BenchDevice> device = createBenchDevice(kWidth, kHeight);
    if (!device) return report.notes.push_back(name + ": skipped, " + device.error().message);
    const VulkanContext& ctx = device->ctx;
    const RenderTarget rt = renderTarget(device->target);
    const Bounds bounds = computeBounds(cage);
    const RenderCamera framed = frameBounds(bounds.min, bounds.max, float(kWidth) / float(kHeight));
    const GpuContext gpu = gpuContextOf(*device);
    const uint32_t rounds = std::max(5u, args.repeats);
    const CageFeatures features = analyzeCage(planned->cage(), planned->topology());

    // Frames of the plans scheme with these settings: one untimed (layout and evaluation), then
    // the rounds, each with the camera turned a little.
    auto measure = [&](const FaceFactor& f, const std::string& macro) {
        FrameResult result;
        SchemeSettings settings;
        settings.tessFactor = f.factor;
        settings.options = {{"macro", macro}, {"minify", std::to_string(f.minify)}};
        if (macro != "off") settings.options.push_back({"macro-whole", "on"});
        Result<PreparedScheme> prepared = prepareScheme(catalog, "plans", *planned, features, settings, gpu, name);
        if (!prepared) {
            result.error = prepared.error().message;
            return result;
        }
        std::vector<double> ms;
        RenderCamera camera = framed;
        for (uint32_t r = 0; r <= rounds && result.error.empty(); ++r) {
            const glm::vec3 offset = camera.eye - camera.target;
            camera.eye = camera.target + glm::vec3(glm::rotate(glm::mat4(1.0f), glm::radians(1.0f), camera.up) *
                                                   glm::vec4(offset, 0.0f));
            const DrawView view = headlessView(camera, kHeight, "shading", false);
            Result<DrawStats> drawn = DrawStats{};
            const auto start = Clock::now();
            Status ok = submitAndWait(ctx, [&](VkCommandBuffer cmd) { drawn = prepared->instance.record(cmd, rt, view); });
            if (ok && !drawn) ok = drawn.error();
            if (!ok) result.error = ok.error().message;
            else if (r > 0) ms.push_back(msSince(start));
            if (ok) result.triangles = drawn->triangles;
        }
        (void)prepared->instance.destroyGpu();
        if (!ms.empty()) result.ms = median(ms);
        return result;
    };

    const FaceFactor factors[] = {{1, 4}, {1, 2}, {1, 1}, {2, 1}, {4, 1}};
    for (const FaceFactor& f : factors) {
        const FrameResult single = measure(FaceFactor{f.factor, 1}, "off");
        if (!single.error.empty()) {
            report.notes.push_back(name + ": per-face factor " + f.text() + " not measured, " + single.error);
            continue;
        }
        for (const char* partition : {"rectangles", "quartets", "blocks"}) {
            const FrameResult macro = measure(f, partition);
            if (!macro.error.empty()) {
                report.notes.push_back(name + ": " + partition + " at " + f.text() + " not measured, " + macro.error);
                continue;
            }
            Row row;
            row.cage = name, row.faces = cage.faceCount(), row.repeats = rounds, row.unit = "ms";
            row.benchmark = "per-face factor " + f.text() + ": " + partition + " macro faces (" +
                            std::to_string(macro.triangles) + " triangles) vs single faces at factor " +
                            std::to_string(f.factor) + " (" + std::to_string(single.triangles) + " triangles); " +
                            std::to_string(kWidth) + " x " + std::to_string(kHeight) + ", default path";
            row.ours = macro.ms, row.baseline = single.ms;
            row.target = Target::Informative;
            report.rows.push_back(row);
            report.series.push_back({"macro faces: " + name, f.text(), partition, macro.ms / single.ms, "ratio"});
        }
    }
    report.notes.push_back(name + ": load average at the end: " + loadAverage());
    destroyBenchDevice(*device);
}

}  // namespace

void benchMacro(const BenchCage& bench, const BenchArgs& args, Report& report) {
    benchMacroCage(bench.name, bench.cage, args, report);
    // Beside the generated cage, the all-regular torus of its size.
    if (bench.name.rfind("generated", 0) == 0) {
        const Cage torus = makeRegularTorusCage(bench.cage.faceCount());
        benchMacroCage("regular torus (" + std::to_string(torus.faceCount()) + " faces)", torus, args, report);
    }
}

}  // namespace qp::cli
