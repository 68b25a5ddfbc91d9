// `quadplan bench scene`: a scene of many objects (issue 17). The suite's cage (catmark_car, or
// the generated one) as 100 instances on a 10 x 10 grid, beside 20 distinct cages (the first
// catmark_* cages of ../shared, else generated ones of different sizes), all planned through one
// database and drawn through the plans scheme at the scene's default tessellation (adaptive,
// 8 pixels per segment) on an 800 x 600 target.
//
// Rows: (a) the plans the scene needs against its distinct cages planned together (instances and
// shared configurations add none; the ratio to planning each cage on its own is the second
// baseline); (b) the frame; (c) an object move: the plans it builds (none) and the frame after
// it against a frame with nothing changed (the move sets a transform, so no scheme is updated
// and nothing is evaluated again).
#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "bench_report.h"
#include "bench_stats.h"
#include "camera.h"
#include "mesh/generated_cage.h"
#include "mesh/obj_io.h"
#include "offscreen_target.h"
#include "plan_pass.h"  // pixelsPerUnit
#include "render_setup.h"
#include "scene/planned_scene.h"
#include "scene_schemes.h"
#include "vk_commands.h"

namespace qp::cli {

namespace {

constexpr uint32_t kInstanceRows = 10, kDistinctCages = 20;
constexpr uint32_t kWidth = 800, kHeight = 600;

// Up to kDistinctCages cages unlike `bench`: shared regression cages, else generated ones.
std::vector<BenchCage> distinctCages(const BenchCage& bench, const BenchArgs& args) {
    std::vector<BenchCage> out;
    const std::filesystem::path shapes = std::filesystem::path(benchSharedDir()) / "shapes";
    std::vector<std::filesystem::path> paths;
    if (!args.noShared && std::filesystem::is_directory(shapes))
        for (const auto& entry : std::filesystem::directory_iterator(shapes))
            if (entry.path().filename().string().rfind("catmark_", 0) == 0 && entry.path().extension() == ".obj")
                paths.push_back(entry.path());
    std::sort(paths.begin(), paths.end());
    for (const auto& path : paths) {
        if (out.size() == kDistinctCages) break;
        if (path.stem().string() == bench.name) continue;
        if (Result<Cage> cage = loadObj(path.string()); cage) out.push_back({path.stem().string(), std::move(cage).value()});
    }
    for (uint32_t i = 0; out.size() < kDistinctCages; ++i)
        out.push_back({"generated " + std::to_string(i), makeBenchmarkCage(300 + 150 * i, args.seed + i)});
    return out;
}

// The bench cage on a grid of instances, the distinct cages in a row in front, each scaled to
// the bench cage's size.
Scene buildScene(const BenchCage& bench, const std::vector<BenchCage>& others) {
    Scene scene = sceneOfCage(bench.cage, "cage");
    const Bounds b = computeBounds(bench.cage);
    const float size = std::max(b.diagonal(), 1e-6f), spacing = 1.2f * size;
    const glm::vec3 centre = 0.5f * (b.min + b.max);
    scene.objects[0].transform.translation = -centre;
    for (uint32_t i = 1; i < kInstanceRows * kInstanceRows; ++i) {
        SceneObject o;
        o.name = "cage." + std::to_string(i);
        o.instanceOf = "cage";
        o.transform.translation = glm::vec3(float(i % kInstanceRows) * spacing, 0.0f, float(i / kInstanceRows) * spacing) - centre;
        o.transform.rotationDegrees = {0.0f, float(i * 37 % 360), 0.0f};
        scene.objects.push_back(o);
    }
    for (uint32_t i = 0; i < others.size(); ++i) {
        SceneObject o;
        o.name = others[i].name;
        o.cage = others[i].cage;
        const Bounds ob = computeBounds(o.cage);
        const float scale = size / std::max(ob.diagonal(), 1e-6f);
        o.transform.scale = glm::vec3(scale);
        o.transform.translation = glm::vec3(float(i % kInstanceRows) * spacing, 0.0f, -float(1 + i / kInstanceRows) * spacing) -
                                  scale * 0.5f * (ob.min + ob.max);
        scene.objects.push_back(std::move(o));
    }
    return scene;
}

}  // namespace

void benchScene(const BenchCage& bench, const BenchArgs& args, Report& report) {
    const std::string& name = bench.name;
    auto note = [&](const std::string& text) { report.notes.push_back(name + ": " + text); };
    const std::vector<BenchCage> others = distinctCages(bench, args);
    Scene scene = buildScene(bench, others);
    std::fprintf(stderr, "bench scene: %s x %u instances + %zu cages\n", name.c_str(), kInstanceRows * kInstanceRows,
                 others.size());

    // (a) Plans: the scene, its distinct cages in one database, each cage in a database of its own.
    PlanDatabase database;
    Result<PlannedScene> planned = PlannedScene::create(scene, database, PlanOptions{}, name);
    if (!planned) return note("skipped, " + planned.error().message);
    PlanDatabase together;
    uint64_t separately = 0;
    for (const BenchCage* cage : [&] {
             std::vector<const BenchCage*> all{&bench};
             for (const BenchCage& o : others) all.push_back(&o);
             return all;
         }()) {
        PlanDatabase own;
        if (!PlannedCage::create(cage->cage, together, PlanOptions{}, cage->name) ||
            !PlannedCage::create(cage->cage, own, PlanOptions{}, cage->name))
            return note("skipped, " + cage->name + " could not be planned");
        separately += own.stats().plans;
    }
    const ScenePlanStats stats = scenePlanStats(scene, *planned);
    const std::string sceneText = std::to_string(scene.objects.size()) + " objects (" +
                                  std::to_string(kInstanceRows * kInstanceRows) + " instances of the cage, " +
                                  std::to_string(others.size()) + " other cages)";
    Row plans{name, bench.cage.faceCount(), "(a) plans of a scene of " + sceneText + " vs its " +
                                                std::to_string(others.size() + 1) +
                                                " distinct cages planned together; baseline2: each cage in a database of its own",
              1, "plans", double(stats.uniquePlans), double(together.stats().plans)};
    plans.baseline2 = double(separately);
    plans.target = Target::RatioAtMost;
    plans.targetValue = 1.0;
    report.rows.push_back(plans);
    note("planning the scene took " + number(planned->planMs) + " ms; " + std::to_string(stats.sharedPlans) +
         " of its plans are used by more than one cage; " + std::to_string(stats.instanceFaces) + " faces drawn a frame");

    // (b), (c) Frames through the plans scheme.
    const PluginCatalog catalog = loadPlugins(pluginDirectory());
    for (const PluginProblem& p : catalog.problems) note(p.message);
    Result<VulkanContext> context = createBenchContext();
    if (!context) return note("frames skipped, " + context.error().message);
    VulkanContext ctx = std::move(context).value();
    note("load average at the start (1, 5, 15 min): " + loadAverage() + "; device " + ctx.deviceName);
    const VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
    Result<OffscreenTarget> offscreen = createOffscreenTarget(ctx, kWidth, kHeight, format);
    SchemeSettings settings;
    settings.adaptivePixels = Tessellation{}.pixelsPerEdge;  // the scene's default tessellation
    Result<SceneSchemes> schemes = offscreen ? prepareSceneSchemes(catalog, "plans", scene, *planned, settings,
                                                                   GpuContext{&ctx, VK_NULL_HANDLE, format, VK_FORMAT_D32_SFLOAT}, name)
                                             : Result<SceneSchemes>(offscreen.error());
    if (!schemes) {
        note("frames skipped, " + schemes.error().message);
    } else {
        Result<RenderCamera> camera = chooseCamera(scene, sceneBounds(scene, *planned), float(kWidth) / float(kHeight), "");
        DrawView view;
        view.viewProjection = viewProjection(*camera);
        view.eye = camera->eye;
        view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(*camera), kHeight);
        const RenderTarget target = renderTarget(*offscreen);
        DrawStats drawn;
        auto frame = [&]() -> Result<double> {
            const auto start = Clock::now();
            Result<DrawStats> stats = DrawStats{};
            if (Status ok = submitAndWait(ctx, [&](VkCommandBuffer cmd) { stats = recordScene(cmd, *schemes, scene, *planned, target, view); });
                !ok)
                return ok.error();
            if (!stats) return stats.error();
            drawn = *stats;
            return msSince(start);
        };
        std::vector<double> still, moved;
        const uint64_t missesBefore = database.misses();
        bool failed = false;
        for (uint32_t round = 0; round <= args.repeats && !failed; ++round) {
            Result<double> a = frame();
            // An object move: its transform changes, nothing else (no scheme update, no plans).
            scene.objects[1].transform.translation.y += 0.01f * computeBounds(bench.cage).diagonal();
            Result<double> b = frame();
            if (!a || !b) {
                note("frames failed: " + (a ? b.error().message : a.error().message));
                failed = true;
            } else if (round > 0) {  // round 0 warms up
                still.push_back(*a);
                moved.push_back(*b);
            }
        }
        if (!failed) {
            const std::string triangles = drawn.triangles ? std::to_string(drawn.triangles) + " triangles" : "tessellator-chosen triangles";
            Row frameRow{name, bench.cage.faceCount(), "(b) frame of the scene, plans " +
                                                           std::string(drawnByName(drawn.drawnBy)) + " path, adaptive 8 px, " +
                                                           std::to_string(kWidth) + "x" + std::to_string(kHeight) + ", " +
                                                           triangles + ", " + std::to_string(drawn.patches) + " patches",
                         args.repeats, "ms", median(still)};
            frameRow.target = Target::Informative;
            report.rows.push_back(frameRow);
            Row replans{name, bench.cage.faceCount(), "(c1) plans built by " + std::to_string(args.repeats + 1) + " object moves",
                        args.repeats, "plans", double(database.misses() - missesBefore)};
            replans.target = Target::OursAtMost;
            replans.targetValue = 0.0;
            report.rows.push_back(replans);
            Row move{name, bench.cage.faceCount(), "(c2) the frame after an object move vs a frame with nothing changed",
                     args.repeats, "ms", median(moved), median(still)};
            std::vector<double> ratios;
            for (size_t i = 0; i < moved.size(); ++i) ratios.push_back(moved[i] / still[i]);
            move.pairedRatio = median(ratios);
            move.target = Target::RatioAtMost;
            move.targetValue = 1.25;
            report.rows.push_back(move);
        }
        (void)destroySceneSchemes(*schemes);
    }
    if (offscreen) destroyOffscreenTarget(ctx, *offscreen);
    destroyContext(ctx);
}

}  // namespace qp::cli
