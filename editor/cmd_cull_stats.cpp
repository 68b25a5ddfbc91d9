// quadplan cull-stats (issue 20, first part): per culling method the share of a planned cage's
// sub-faces culled over views on a sphere around it. Frame times with and without culling and
// the ID-buffer check of the promise (no culled patch draws a pixel) come with the renderer's
// culling (docs/culling-plan.md).
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "camera.h"
#include "closed_surface.h"
#include "commands.h"
#include "planned_cage.h"
#include "scene.h"
#include "subface_cull_bounds.h"

namespace qp::cli {

namespace {

struct CullStatsArgs {
    std::string path;
    uint32_t views = 26;
    bool json = false;
};

// Evenly spread directions (a Fibonacci sphere).
std::vector<glm::vec3> viewDirections(uint32_t count) {
    std::vector<glm::vec3> out;
    const float golden = 3.14159265f * (3.0f - std::sqrt(5.0f));
    for (uint32_t k = 0; k < count; ++k) {
        const float y = 1.0f - 2.0f * (float(k) + 0.5f) / float(count), r = std::sqrt(std::max(0.0f, 1.0f - y * y));
        out.push_back({r * std::cos(golden * float(k)), y, r * std::sin(golden * float(k))});
    }
    return out;
}

int runCullStats(const CullStatsArgs& args) {
    std::vector<std::string> warnings;
    Result<Scene> scene = loadSceneOrCage(args.path, &warnings);
    for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (!scene) {
        std::fprintf(stderr, "error: %s\n", scene.error().message.c_str());
        return 1;
    }
    if (scene->objects.empty()) {
        std::fprintf(stderr, "error: %s has no object\n", args.path.c_str());
        return 1;
    }
    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(scene->objects[0].cage, database, PlanOptions{}, args.path);
    if (!planned) {
        std::fprintf(stderr, "error: %s\n", planned.error().message.c_str());
        return 1;
    }
    const PatchCullSet bounds = buildSubfaceCullBounds(*planned);
    const bool closed = closedOutwardSurface(planned->cage(), planned->topology());
    CullBox all{glm::vec3(INFINITY), glm::vec3(-INFINITY)};  // what each view frames
    uint32_t patches = 0;
    for (uint32_t s = 0; s < planned->subfaceCount(); ++s)
        if (planned->hasSurface(s)) {
            ++patches;
            all.lo = glm::min(all.lo, bounds.boxes[s].lo), all.hi = glm::max(all.hi, bounds.boxes[s].hi);
        }
    const char* names[4] = {"frustum", "tcone", "ncone", "pplane"};
    std::vector<double> fractions[4];
    for (const glm::vec3& direction : viewDirections(args.views)) {
        // Framing the whole model from this direction (render/camera.h's rule, turned).
        RenderCamera camera = frameBounds(all.lo, all.hi, 1.0f);
        const float distance = glm::length(camera.eye - camera.target);
        camera.eye = camera.target + distance * direction;
        camera.up = std::abs(direction.y) > 0.99f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
        const glm::vec4 eye = homogeneousEye(viewProjection(camera), camera.eye);
        uint32_t culled[4] = {};
        const CullMethod methods[4] = {CullMethod::Frustum, CullMethod::TCone, CullMethod::NCone, CullMethod::PPlane};
        for (int m = 0; m < 4; ++m)
            culled[m] = uint32_t(cullPatches(bounds, methods[m], viewProjection(camera), eye, closed).size());
        for (int m = 0; m < 4; ++m) fractions[m].push_back(patches ? double(culled[m]) / patches : 0.0);
    }
    nlohmann::ordered_json methods;
    for (int m = 0; m < 4; ++m) {
        double sum = 0.0, lo = 1.0, hi = 0.0;
        for (double f : fractions[m]) sum += f, lo = std::min(lo, f), hi = std::max(hi, f);
        methods[names[m]] = {{"culled_fraction", {{"mean", sum / double(fractions[m].size())}, {"min", lo}, {"max", hi}}}};
    }
    if (args.json) {
        nlohmann::ordered_json out = {{"cage", args.path}, {"views", args.views}, {"patches", patches},
                                      {"closed", closed}, {"methods", methods}};
        std::printf("%s\n", out.dump(1).c_str());
        return 0;
    }
    std::printf("%s: %u sub-faces, %u views%s\n", args.path.c_str(), patches, args.views,
                closed ? "" : " (open cage: back-patch tests off, back sides are drawn)");
    for (int m = 0; m < 4; ++m)
        std::printf("  %-8s culled %5.1f%% (min %5.1f%%, max %5.1f%%)\n", names[m],
                    100.0 * methods[names[m]]["culled_fraction"]["mean"].get<double>(),
                    100.0 * methods[names[m]]["culled_fraction"]["min"].get<double>(),
                    100.0 * methods[names[m]]["culled_fraction"]["max"].get<double>());
    return 0;
}

}  // namespace

void registerCullStats(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand("cull-stats", "Share of a cage's sub-faces each culling method culls, over views around it "
                                                 "(frame times and the ID-buffer check are not in yet)");
    auto args = std::make_shared<CullStatsArgs>();
    cmd->add_option("file", args->path, "Cage (.obj, .om, .ply, .off, .stl) or scene (.json; its first object)")->required();
    cmd->add_option("--views", args->views, "Views on a sphere around the model, each framing it")->check(CLI::Range(1u, 10000u));
    cmd->add_flag("--json", args->json, "Print one JSON object");
    cmd->callback([args, &exitCode] { exitCode = runCullStats(*args); });
}

}  // namespace qp::cli
