// `quadplan bench fas`: the experiment of Brainerd et al. 2016 §9.1 redone, subdivision plans
// against OpenSubdiv's feature-adaptive patches (the `osd-fas` plugin: Far's patch table with
// single-crease patches, inf-sharp patches and Gregory-basis end caps, as OpenSubdiv's GPU path
// builds it), each through the paths it has: plans tess / grid / cpu, osd-fas tess / cpu.
//
// Two frames of each kind per round, back to back: a moving frame (update(): the cage's
// positions changed, then record, submit and wait) and a still frame (record, submit, wait:
// what was computed from the positions is reused). Their difference is the position-dependent
// work, on the tessellator paths the stencils (B16's "stencil time"); on the grid and cpu paths
// it is the whole surface evaluation, since the still frame only draws the cached triangles.
// Ratios are medians of per-round ratios plans / osd-fas on the same path (grid against
// osd-fas tess: osd-fas has no grid). Every row states both triangle counts.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "bench_report.h"
#include "bench_stats.h"
#include "camera.h"
#include "offscreen_target.h"
#include "plan_pass.h"  // pixelsPerUnit
#include "scheme_host.h"
#include "scheme_support.h"
#include "vk_commands.h"

namespace qp::cli {

namespace {

// B16's target for factors of 4 and more: plans at most 0.8x FAS's frame time (issue 16).
constexpr double kPlansOverFasTarget = 0.8;
constexpr uint32_t kTargetFromFactor = 4;
constexpr uint32_t kWarmups = 1;

struct Kind {
    Kind(std::string schemeName, std::string pathName, PreparedScheme scheme)
        : scheme(std::move(schemeName)), path(std::move(pathName)), prepared(std::move(scheme)) {}
    std::string scheme, path;
    PreparedScheme prepared;
    DrawStats draw;
    SchemeStats stats;
    std::vector<double> moving, still;
    bool failed = false;
    std::string label() const { return scheme + " " + path; }
};

Result<double> frame(const VulkanContext& ctx, Kind& k, const RenderTarget& target, const DrawView& view, bool moving) {
    const auto start = Clock::now();
    if (moving)
        if (Status updated = k.prepared.instance.update(); !updated) return updated.error();
    Result<DrawStats> drawn = DrawStats{};
    if (Status ok = submitAndWait(ctx, [&](VkCommandBuffer cmd) { drawn = k.prepared.instance.record(cmd, target, view); }); !ok)
        return ok.error();
    if (!drawn) return drawn.error();
    const double ms = msSince(start);
    if (drawn->primitives() == 0) return Error{"it drew nothing (its message is above)"};
    k.draw = *drawn;
    return ms;
}

// Triangles of the plans at uniform factor F: 2 F^2 a drawn sub-face (the budget check, made
// before anything is drawn).
uint64_t plansTriangles(const PlannedCage& planned, uint32_t factor) {
    uint64_t subfaces = 0;
    for (uint32_t s = 0; s < planned.subfaceCount(); ++s) subfaces += planned.hasSurface(s);
    return 2ull * factor * factor * subfaces;
}

}  // namespace

void benchFas(const BenchCage& bench, const BenchArgs& args, Report& report) {
    const std::string& name = bench.name;
    std::fprintf(stderr, "bench fas: %s (%u faces)\n", name.c_str(), bench.cage.faceCount());
    auto note = [&](const std::string& text) { report.notes.push_back(name + ": " + text); };
    PlanDatabase database;
    Result<PlannedCage> created = PlannedCage::create(bench.cage, database, PlanOptions{}, name);
    if (!created) return note("skipped, " + created.error().message);
    const PlannedCage& planned = *created;
    const PluginCatalog catalog = loadPlugins(pluginDirectory());
    for (const PluginProblem& p : catalog.problems) note(p.message);
    Result<VulkanContext> context = createBenchContext();
    if (!context) return note("skipped, " + context.error().message);
    VulkanContext ctx = std::move(context).value();
    note("load average at the start (1, 5, 15 min): " + loadAverage() + "; device " + ctx.deviceName);
    const VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
    Result<OffscreenTarget> offscreen = createOffscreenTarget(ctx, kRenderSize, kRenderSize, format);
    if (!offscreen) {
        destroyContext(ctx);
        return note("skipped, " + offscreen.error().message);
    }
    const RenderTarget target = renderTarget(*offscreen);
    const Bounds bounds = computeBounds(bench.cage);
    const RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
    DrawView view;
    view.viewProjection = viewProjection(camera);
    view.eye = camera.eye;
    view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(camera), kRenderSize);
    view.sampleCulling = false;  // like with like: osd-fas draws every triangle too
    const CageFeatures features = analyzeCage(planned.cage(), planned.topology());
    const GpuContext gpu{&ctx, VK_NULL_HANDLE, format, VK_FORMAT_D32_SFLOAT};

    std::string table = "### fas: " + name + " (" + std::to_string(bench.cage.faceCount()) +
                        " faces), medians of " + std::to_string(args.repeats) +
                        " rounds\n\n| factor | scheme path | primitives | triangles | control points a frame | moving "
                        "frame ms | still frame ms | position-dependent share | plans / osd-fas |\n"
                        "|---:|---|---:|---:|---:|---:|---:|---:|---:|\n";
    const std::vector<uint32_t> factors = args.factors.empty() ? std::vector<uint32_t>{1, 2, 4, 8, 16, 32, 64} : args.factors;
    for (uint32_t factor : factors) {
        const std::string at = ", factor " + std::to_string(factor);
        if (const uint64_t triangles = plansTriangles(planned, factor); triangles > args.maxTriangles) {
            note("factor " + std::to_string(factor) + " not measured: the plans draw " + std::to_string(triangles) +
                 " triangles a frame, over this run's budget of " + std::to_string(args.maxTriangles) + " (--max-triangles)");
            continue;
        }
        std::vector<Kind> kinds;
        for (const auto& [scheme, path] : {std::pair{"plans", "tess"}, std::pair{"plans", "grid"}, std::pair{"plans", "cpu"},
                                           std::pair{"osd-fas", "tess"}, std::pair{"osd-fas", "cpu"}}) {
            SchemeSettings settings;
            settings.tessFactor = factor;
            settings.options = {{"path", path}};
            Result<PreparedScheme> prepared = prepareScheme(catalog, scheme, planned, features, settings, gpu, name);
            if (!prepared) {
                note(std::string(scheme) + " " + path + at + " not measured: " + prepared.error().message);
                continue;
            }
            kinds.emplace_back(scheme, path, std::move(prepared).value());
        }
        for (uint32_t round = 0; round < kWarmups + args.repeats; ++round)
            for (Kind& k : kinds) {
                if (k.failed) continue;
                Result<double> moving = frame(ctx, k, target, view, true);
                Result<double> still = moving ? frame(ctx, k, target, view, false) : moving;
                if (!still) {
                    k.failed = true;
                    note(k.label() + at + ": stopped, " + still.error().message);
                    continue;
                }
                if (round < kWarmups) continue;
                k.moving.push_back(*moving);
                k.still.push_back(*still);
            }
        auto find = [&](const char* scheme, const char* path) -> const Kind* {
            for (const Kind& k : kinds)
                if (k.scheme == scheme && k.path == path && !k.failed && !k.moving.empty()) return &k;
            return nullptr;
        };
        for (Kind& k : kinds) {
            if (Result<SchemeStats> stats = k.prepared.instance.stats(); stats) k.stats = *stats;
            if (Status destroyed = k.prepared.instance.destroyGpu(); !destroyed) note(k.label() + at + ": " + destroyed.error().message);
        }
        for (const Kind& k : kinds) {
            if (k.failed || k.moving.empty()) continue;
            const double moving = median(k.moving), still = median(k.still);
            const Kind* fas = k.scheme == "plans" ? find("osd-fas", k.path == "cpu" ? "cpu" : "tess") : nullptr;
            std::string ratio;
            if (fas) {
                std::vector<double> ratios;
                for (size_t i = 0; i < std::min(k.moving.size(), fas->moving.size()); ++i)
                    ratios.push_back(k.moving[i] / fas->moving[i]);
                Row r;
                r.cage = name;
                r.faces = bench.cage.faceCount();
                r.benchmark = "plans " + k.path + " vs osd-fas " + fas->path + at + ": moving frame (" +
                              std::to_string(k.draw.primitives()) + " vs " + std::to_string(fas->draw.primitives()) +
                              " primitives, " + std::to_string(k.draw.triangles) + " vs " +
                              std::to_string(fas->draw.triangles) + " triangles)";
                r.repeats = uint32_t(ratios.size());
                r.unit = "ms";
                r.ours = moving;
                r.baseline = median(fas->moving);
                r.pairedRatio = median(ratios);
                r.target = factor >= kTargetFromFactor && k.path == "tess" ? Target::RatioAtMost : Target::Informative;
                r.targetValue = kPlansOverFasTarget;
                report.rows.push_back(r);
                ratio = number(r.pairedRatio) + "x";
                report.series.push_back({"plans / osd-fas frame time, " + name, std::to_string(factor),
                                         "plans " + k.path + " / osd-fas " + fas->path, r.pairedRatio, "x"});
            }
            table += "| " + std::to_string(factor) + " | " + k.label() + " | " + std::to_string(k.draw.primitives()) + " | " +
                     (k.draw.triangles ? std::to_string(k.draw.triangles) : std::string("?")) + " | " +
                     std::to_string(k.stats.controlPoints) + " | " + number(moving) + " | " + number(still) + " | " +
                     number(100.0 * std::max(0.0, moving - still) / moving) + "% | " + ratio + " |\n";
            std::fprintf(stderr, "  %s%s: moving %s ms, still %s ms %s\n", k.label().c_str(), at.c_str(), number(moving).c_str(),
                         number(still).c_str(), ratio.c_str());
        }
    }
    note("load average at the end: " + loadAverage());
    if (report.appendix.empty())
        report.appendix =
            "FAS suite: plans (paths tess, grid, cpu) against osd-fas (OpenSubdiv's feature-adaptive patches: Far "
            "adaptive refinement and patch table at the plan depth, single-crease patches, inf-sharp patches, "
            "Gregory-basis end caps; paths tess and cpu) at uniform factors, " +
            std::to_string(kRenderSize) + "x" + std::to_string(kRenderSize) +
            " offscreen target, camera framing the cage. Moving frame: update() (positions changed), record, submit, "
            "wait; still frame: record, submit, wait. Position-dependent share: (moving - still) / moving: the stencils "
            "on the tess paths (plans: each sub-face's stencil prefix in a compute pass; osd-fas: Far's stencil table in "
            "a compute pass), the whole evaluation on the grid and cpu paths. Primitives: patch primitives through the "
            "tessellator, else triangles submitted. Control points a frame: plans, the stencils applied for the factor; "
            "osd-fas, Far's refined vertices and end-cap points. osd-fas's uniform rule gives a patch at depth d "
            "ceil(F / 2^d) segments an edge (at least 1), so at low factors its deep patches cost more triangles than the "
            "plans' grid. Target (issue 16, B16 §9): plans tess at most " +
            number(kPlansOverFasTarget) + "x osd-fas tess at factors >= " + std::to_string(kTargetFromFactor) +
            "; the other rows are informative.\n\n";
    report.appendix += table + "\n";
    vkDeviceWaitIdle(ctx.device);
    destroyOffscreenTarget(ctx, *offscreen);
    destroyContext(ctx);
}

}  // namespace qp::cli
