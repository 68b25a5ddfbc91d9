// quadplan cull-stats (issue 20): culling measured by drawing. From views on a sphere around a
// cage or scene, the scheme draws every frame unculled and with each method (DrawView::cull);
// per method the share of patches culled, the frame time against the unculled frame, and the
// two promises checked: no culled part (patch or sub-face, cull_stats_views.h) owns a pixel of the
// unculled ID buffer (visible_culled) and the culled picture is the unculled one
// (differing_pixels). A promise broken is an error: exit status 3.
#include <algorithm>
#include <cstdio>
#include <numeric>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "cull_stats_views.h"
#include "mesh/closed_surface.h"
#include "mesh/generated_cage.h"
#include "plan_db_option.h"
#include "render_setup.h"

namespace qp::cli {

namespace {

struct CullStatsArgs {
    std::string path;
    uint32_t generatedFaces = 0, seed = 1;
    uint32_t views = 26, tess = 8, depth = 6, repeats = 3;
    std::string size = "800x600", scheme = "plans", drawPath, pluginDir, planDb;
    std::vector<std::string> options;
    bool json = false, validate = false;
};

int fail(const std::string& message) {
    std::fprintf(stderr, "error: %s\n", message.c_str());
    return 1;
}

// The file, or the generated benchmark cage (core/mesh/generated_cage.h), planned.
Result<PlannedFile> loadInput(const CullStatsArgs& args, PlanDatabase& database) {
    const PlanOptions options{args.depth, true};
    if (args.generatedFaces == 0) return loadAndPlan(args.path, database, options);
    Scene scene = sceneOfCage(makeBenchmarkCage(args.generatedFaces, args.seed), "generated");
    Result<PlannedScene> planned = PlannedScene::create(scene, database, options, "the generated cage");
    if (!planned) return planned.error();
    return PlannedFile{std::move(scene), std::move(planned).value()};
}

std::string inputName(const CullStatsArgs& args) {
    if (args.generatedFaces == 0) return args.path;
    return "generated (" + std::to_string(args.generatedFaces) + " faces, seed " + std::to_string(args.seed) + ")";
}

double mean(const std::vector<double>& values) {
    return values.empty() ? 0.0 : std::accumulate(values.begin(), values.end(), 0.0) / double(values.size());
}

// Where a promise broke: the view (its index and eye) and what showed, so it can be reproduced
// (`render --camera EYE,TARGET`).
struct Broken {
    uint32_t view = 0;
    glm::vec3 eye{0.0f}, target{0.0f};
    VisibleCulled part;  // pixels 0: no culled part showed in this view
    uint64_t differingPixels = 0;
};

// One method over every view.
struct MethodSummary {
    std::vector<double> fractions, frameMs, gpuMs, triangles, facingAway, cullMs;
    CullCounts counts;
    uint64_t differingPixels = 0, culledParts = 0, visibleCulled = 0;
    std::vector<Broken> broken;

    void add(const MethodInView& m, uint32_t view, const RenderCamera& camera) {
        const CullCounts& c = m.draw.cull;
        fractions.push_back(c.tested ? double(c.frustum + c.backFacing) / double(c.tested) : 0.0);
        frameMs.push_back(m.frameMs);
        gpuMs.push_back(m.gpuMs);
        triangles.push_back(double(m.draw.triangles));
        facingAway.push_back(double(m.draw.facingAwayTriangles));
        cullMs.push_back(m.draw.cullMilliseconds);
        counts.tested += c.tested, counts.frustum += c.frustum, counts.backFacing += c.backFacing;
        counts.frustumOnly += c.frustumOnly;
        differingPixels += m.differingPixels;
        culledParts += m.culledParts;
        visibleCulled += m.visibleCulledParts.size();
        for (const VisibleCulled& v : m.visibleCulledParts) broken.push_back({view, camera.eye, camera.target, v, 0});
        if (m.differingPixels > 0) broken.push_back({view, camera.eye, camera.target, {}, m.differingPixels});
    }
};

// Every view's measurements, and what the report says about the setting.
struct Measured {
    std::vector<MethodSummary> summaries = std::vector<MethodSummary>(1 + kMeasuredCullMethods.size());  // [0]: unculled
    std::vector<double> visibleParts;  // per view
    std::string idParts = "sub-faces";  // what the ID buffers number: "patches", "sub-faces" or both
    std::string device, drawnBy = "?";
    bool closed = true;  // every cage a closed outward surface (closed_surface.h)
    std::vector<std::string> objectNames;
};

std::string cameraText(const Broken& b) {
    char text[160];
    std::snprintf(text, sizeof text, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g", b.eye.x, b.eye.y, b.eye.z, b.target.x, b.target.y, b.target.z);
    return text;
}

nlohmann::ordered_json brokenJson(const std::vector<Broken>& broken, const Measured& measured) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const Broken& b : broken) {
        nlohmann::ordered_json entry = {{"view", b.view}, {"camera", cameraText(b)}};
        if (b.part.pixels > 0) {
            entry["object"] = measured.objectNames[b.part.object];
            entry[b.part.patch ? "patch" : "subface"] = b.part.part;
            entry["pixels"] = b.part.pixels;
        } else {
            entry["differing_pixels"] = b.differingPixels;
        }
        out.push_back(entry);
    }
    return out;
}

// Each broken promise on stderr, with the camera that shows it.
void printBroken(CullMethod method, const std::vector<Broken>& broken, const Measured& measured) {
    for (const Broken& b : broken) {
        if (b.part.pixels > 0)
            std::fprintf(stderr, "error: %s culled %s %u of object \"%s\" in view %u (--camera %s), which owns %u pixels "
                                 "of the unculled ID buffer\n",
                         cullMethodName(method), b.part.patch ? "patch" : "sub-face", b.part.part,
                         measured.objectNames[b.part.object].c_str(), b.view, cameraText(b).c_str(), b.part.pixels);
        else
            std::fprintf(stderr, "error: %s: view %u (--camera %s) differs from the unculled frame in %llu pixels\n",
                         cullMethodName(method), b.view, cameraText(b).c_str(), (unsigned long long)b.differingPixels);
    }
}

int report(const CullStatsArgs& args, const Measured& measured) {
    const std::vector<MethodSummary>& summaries = measured.summaries;
    const MethodSummary& none = summaries[0];
    uint64_t patches = 0, differing = 0, visible = 0, checked = 0;
    for (size_t m = 1; m < summaries.size(); ++m) {
        patches = std::max<uint64_t>(patches, summaries[m].counts.tested / std::max<uint64_t>(1, args.views));
        differing += summaries[m].differingPixels;
        visible += summaries[m].visibleCulled;
        checked += summaries[m].culledParts;
    }
    nlohmann::ordered_json methods;
    for (size_t m = 1; m < summaries.size(); ++m) {
        const MethodSummary& s = summaries[m];
        const auto [lo, hi] = std::minmax_element(s.fractions.begin(), s.fractions.end());
        methods[cullMethodName(kMeasuredCullMethods[m - 1])] = {
            {"culled_fraction", {{"mean", mean(s.fractions)}, {"min", *lo}, {"max", *hi}}},
            {"frame_ratio", mean(none.frameMs) > 0 ? mean(s.frameMs) / mean(none.frameMs) : 0.0},
            {"gpu_ratio", mean(none.gpuMs) > 0 ? mean(s.gpuMs) / mean(none.gpuMs) : 0.0},
            {"frame_ms", mean(s.frameMs)},
            {"gpu_ms", mean(s.gpuMs)},
            {"triangles", mean(s.triangles)},
            {"facing_away_triangles", mean(s.facingAway)},
            {"cull_ms", mean(s.cullMs)},
            {"tested", s.counts.tested},
            {"frustum", s.counts.frustum},
            {"back_facing", s.counts.backFacing},
            {"frustum_only", s.counts.frustumOnly},
            {"culled_parts", s.culledParts},
            {"visible_culled", s.visibleCulled},
            {"differing_pixels", s.differingPixels},
            {"broken", brokenJson(s.broken, measured)}};
        printBroken(kMeasuredCullMethods[m - 1], s.broken, measured);
    }
    const char* timing = "frame_ms: wall time of record + submit + wait, median of the timed frames of a view (every other "
                         "one with the scene moved by a hair, so view-dependent work runs in each), mean over views; gpu_ms: "
                         "timestamps around the recorded commands, likewise; ratios: culled / unculled";
    if (args.json) {
        nlohmann::ordered_json out = {
            {"file", inputName(args)}, {"scheme", args.scheme}, {"path", measured.drawnBy}, {"tess", args.tess},
            {"size", args.size}, {"device", measured.device}, {"views", args.views}, {"repeats", args.repeats},
            {"objects", measured.objectNames.size()}, {"closed", measured.closed}, {"patches", patches},
            {"id_parts", measured.idParts}, {"visible_parts", mean(measured.visibleParts)},
            {"visible_culled", visible}, {"culled_parts", checked},
            {"differing_pixels", differing}, {"timing", timing},
            {"unculled", {{"frame_ms", mean(none.frameMs)}, {"gpu_ms", mean(none.gpuMs)}, {"triangles", mean(none.triangles)}}},
            {"methods", methods}};
        std::printf("%s\n", out.dump(1).c_str());
    } else {
        std::printf("%s: scheme %s (%s path), tess %u, %s, %u views, %llu patches, on %s%s\n", inputName(args).c_str(),
                    args.scheme.c_str(), measured.drawnBy.c_str(), args.tess, args.size.c_str(), args.views,
                    (unsigned long long)patches, measured.device.c_str(),
                    measured.closed ? "" : " (not every cage is a closed outward surface: back-patch tests off there, back sides show)");
        std::printf("| method | culled mean | min | max | triangles | facing away | frame ms | ratio | gpu ms | ratio | cull ms |\n");
        std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
        std::printf("| none | | | | %.0f | | %.2f | 1 | %.2f | 1 | |\n", mean(none.triangles), mean(none.frameMs), mean(none.gpuMs));
        for (size_t m = 1; m < summaries.size(); ++m) {
            const nlohmann::ordered_json& j = methods[cullMethodName(kMeasuredCullMethods[m - 1])];
            const auto& f = j["culled_fraction"];
            std::printf("| %s | %.1f%% | %.1f%% | %.1f%% | %.0f | %.0f | %.2f | %.2f | %.2f | %.2f | %.2f |\n",
                        cullMethodName(kMeasuredCullMethods[m - 1]), 100.0 * f["mean"].get<double>(),
                        100.0 * f["min"].get<double>(), 100.0 * f["max"].get<double>(), j["triangles"].get<double>(),
                        j["facing_away_triangles"].get<double>(),
                        j["frame_ms"].get<double>(), j["frame_ratio"].get<double>(), j["gpu_ms"].get<double>(),
                        j["gpu_ratio"].get<double>(), j["cull_ms"].get<double>());
        }
        std::printf("(%s)\n", timing);
        // Numbering sub-faces, the ID buffer checks the sub-faces culled whole: a scheme that culls
        // patches inside a sub-face without saying what it draws per patch (acc1, acc2 and pn on
        // the tess path of a refined cage) has the rest covered by the pictures' comparison.
        const char* culledParts = measured.idParts == "sub-faces" ? "sub-faces culled whole" : measured.idParts.c_str();
        std::printf("visible_culled: %llu of %llu %s (over every view and method) own a pixel of their object's unculled "
                    "ID buffer, in which %.1f %s a view own pixels\n",
                    (unsigned long long)visible, (unsigned long long)checked, culledParts, mean(measured.visibleParts),
                    measured.idParts.c_str());
        std::printf("differing_pixels: %llu (culled frames against unculled ones)\n", (unsigned long long)differing);
    }
    if (visible > 0 || differing > 0) {
        std::fprintf(stderr, "error: culling showed in the picture: %llu visible %s culled, %llu pixels differ\n",
                     (unsigned long long)visible, measured.idParts.c_str(), (unsigned long long)differing);
        return 3;
    }
    return 0;
}

int runCullStats(const CullStatsArgs& args) {
    if (args.path.empty() == (args.generatedFaces == 0)) return fail("give either a cage or scene file, or --generated-faces N");
    uint32_t width = 0, height = 0;
    if (!parseSize(args.size, width, height))
        return fail("--size must be WIDTHxHEIGHT with each side between 16 and 8192, got '" + args.size + "'");
    Result<SchemeChoice> chosen = chooseScheme(args.depth, args.drawPath, args.options, args.pluginDir, args.scheme);
    if (!chosen) return fail(chosen.error().message);
    SchemeSettings settings = chosen->settings;
    settings.tessFactor = args.tess;
    const PluginCatalog& catalog = chosen->catalog;

    PlanDatabase database;
    loadPlanDatabase(database, args.planDb);
    Result<PlannedFile> file = loadInput(args, database);
    if (!file) return fail(file.error().message);
    savePlanDatabase(database, args.planDb);
    const Scene& scene = file->scene;
    const PlannedScene& planned = file->planned;
    Measured measured;
    for (const SceneObject& object : scene.objects) measured.objectNames.push_back(object.name);
    for (const PlannedCage& cage : planned.cages)
        measured.closed = measured.closed && closedOutwardSurface(cage.cage(), cage.topology());

    HeadlessSceneRequest request{&catalog, args.scheme, settings, inputName(args), width, height, "shading", args.validate};
    Result<std::unique_ptr<HeadlessScene>> created = createHeadlessScene(request, scene, planned);
    if (!created) return fail(created.error().message);
    HeadlessScene& h = **created;
    if (!h.problem.empty()) return destroyHeadlessScene(h, args.validate, fail(h.problem));
    Result<CullStatsRig> rig = createCullStatsRig(h, scene, planned, args.tess);
    if (!rig) return destroyHeadlessScene(h, args.validate, fail(rig.error().message));
    const auto numbersPatches = [](const PartIdMesh& parts) { return parts.patches; };
    if (!rig->meshes.empty() && std::all_of(rig->meshes.begin(), rig->meshes.end(), numbersPatches)) measured.idParts = "patches";
    else if (std::any_of(rig->meshes.begin(), rig->meshes.end(), numbersPatches)) measured.idParts = "patches and sub-faces";

    measured.device = h.ctx.deviceName;
    int status = 0;
    const std::vector<RenderCamera> cameras = sphereCameras(sceneBounds(scene, planned), args.views, float(width) / float(height));
    for (uint32_t v = 0; v < cameras.size(); ++v) {
        Result<ViewMeasurement> view = measureView(h, *rig, scene, planned, headlessView(cameras[v], height, "shading", false),
                                                   args.repeats);
        if (!view) {
            status = fail("drawing " + inputName(args) + " failed: " + view.error().message);
            break;
        }
        for (size_t m = 0; m < measured.summaries.size(); ++m) measured.summaries[m].add(view->methods[m], v, cameras[v]);
        measured.visibleParts.push_back(double(view->visibleParts));
        measured.drawnBy = drawnByName(view->methods[0].draw.drawnBy);
    }
    if (status == 0) status = report(args, measured);
    destroyCullStatsRig(h.ctx, *rig);
    return destroyHeadlessScene(h, args.validate, status);
}

}  // namespace

void registerCullStats(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand(
        "cull-stats", "Culling measured by drawing: per method the share of patches culled over views around the model, the "
                      "frame time against the unculled frame, and the check that nothing visible was culled (exit 3 if it was)");
    auto args = std::make_shared<CullStatsArgs>();
    cmd->add_option("file", args->path, "Cage (.obj, .om, .ply, .off, .stl) or scene (.json: its visible objects)");
    cmd->add_option("--generated-faces", args->generatedFaces,
                    "Instead of a file: the generated closed benchmark cage (core/mesh/generated_cage.h) of about this many faces")
        ->check(CLI::Range(1u, 10000000u));
    cmd->add_option("--seed", args->seed, "Seed of the generated cage (default 1)");
    cmd->add_option("--views", args->views, "Views on a sphere around the model, each framing it (default 26)")
        ->check(CLI::Range(1u, 10000u));
    cmd->add_option("--size", args->size, "Image size, WIDTHxHEIGHT (default 800x600)");
    cmd->add_option("--scheme", args->scheme, "Patching scheme (default plans; `quadplan schemes` lists them)");
    cmd->add_option("--tess", args->tess, "Uniform tessellation factor (default 8)")->check(CLI::Range(1u, 64u));
    cmd->add_option("--repeats", args->repeats, "Timed frames per view and method, after one warm-up (default 3)")
        ->check(CLI::Range(1u, 1000u));
    cmd->add_option("--path", args->drawPath, "The scheme's draw path, as for render (the option path=...)");
    cmd->add_option("--option", args->options, "Scheme option KEY=VALUE (repeatable)");
    cmd->add_option("--depth", args->depth, "Plan depth")->check(CLI::Range(1u, kMaxPlanDepth));
    cmd->add_option("--plugin-dir", args->pluginDir, "Where the scheme plugins are (default: $QUADPLAN_PLUGIN_DIR, else <bin>/../plugins)");
    addPlanDatabaseOption(cmd, args->planDb);
    cmd->add_flag("--json", args->json, "Print one JSON object");
    cmd->add_flag("--validate", args->validate, "Enable Vulkan validation; any message makes the command fail");
    cmd->callback([args, &exitCode] { exitCode = runCullStats(*args); });
}

}  // namespace qp::cli
