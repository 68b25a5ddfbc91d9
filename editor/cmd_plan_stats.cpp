#include <cstdio>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "plan_db_option.h"
#include "plans/macro_faces.h"
#include "render_setup.h"
#include "scene/planned_scene.h"
#include "scene/scene.h"

namespace qp::cli {

namespace {

struct PlanStatsArgs {
    std::string path;
    uint32_t depth = 6;
    bool noCreaseNodes = false;
    bool json = false;
    std::string planDatabase;
};

int runPlanStats(const PlanStatsArgs& args) {
    Result<Scene> scene = loadSceneWarning(args.path);
    if (!scene) {
        std::fprintf(stderr, "error: %s\n", scene.error().message.c_str());
        return 1;
    }
    PlanDatabase database;
    loadPlanDatabase(database, args.planDatabase);
    PlanOptions options{args.depth, !args.noCreaseNodes};
    Result<PlannedScene> planned = PlannedScene::create(*scene, database, options, args.path);
    if (!planned) {
        std::fprintf(stderr, "error: %s\n", planned.error().message.c_str());
        return 1;
    }
    const double buildMs = planned->planMs;
    savePlanDatabase(database, args.planDatabase);
    const PlanDatabaseStats stats = database.stats();
    const ScenePlanStats sceneStats = scenePlanStats(*scene, *planned);
    uint64_t controlPoints = 0, faces = 0, subfaces = 0;
    for (const PlannedCage& cage : planned->cages) {
        faces += cage.cage().faceCount();
        subfaces += cage.subfaceCount();
        for (uint32_t s = 0; s < cage.subfaceCount(); ++s) controlPoints += cage.storedControlPoints(s).size();
    }
    // Macro faces (macro_faces.h) of each distinct cage, both partitions.
    struct MacroCounts {
        uint64_t faces = 0, members = 0, sharedSpans = 0, spans = 0;
    } rectangles, quartets, blocks;
    for (const PlannedCage& cage : planned->cages) {
        auto add = [](MacroCounts& counts, const MacroFaces& macros) {
            counts.faces += macros.faces.size();
            counts.members += macros.facesInMacroFaces();
            counts.spans += macros.spanCount();
            for (uint8_t shared : macros.spanShared) counts.sharedSpans += shared;
        };
        add(rectangles, rectangularMacroFaces(cage.cage(), cage.topology()));
        add(quartets, quartetMacroFaces(cage.cage(), cage.topology()));
        add(blocks, blockMacroFaces(cage.cage(), cage.topology()));
    }

    nlohmann::json nodes = nlohmann::json::object();
    uint64_t totalNodes = 0;
    for (uint32_t k = 0; k < kNodeKindCount; ++k) {
        nodes[nodeKindName(NodeKind(k))] = stats.nodesByKind[k];
        totalNodes += stats.nodesByKind[k];
    }
    if (args.json) {
        nlohmann::json objects = nlohmann::json::array();
        for (const ObjectPlanStats& o : sceneStats.objects)
            objects.push_back({{"name", o.name},
                               {"instance_of", o.instanceOf.empty() ? nlohmann::json(nullptr) : nlohmann::json(o.instanceOf)},
                               {"cage", o.cage},
                               {"faces", o.faces},
                               {"subfaces", o.subfaces},
                               {"plans", o.plans},
                               {"shared_plans", o.sharedPlans},
                               {"new_plans", o.newPlans},
                               {"plan_bytes", o.planBytes}});
        nlohmann::json out = {
            {"file", args.path},
            {"depth", args.depth},
            {"crease_nodes", !args.noCreaseNodes},
            {"objects", objects},
            {"cages", sceneStats.cages},
            {"faces", faces},
            {"instance_faces", sceneStats.instanceFaces},
            {"subfaces", subfaces},
            {"unique_plans", stats.plans},
            {"plans_in_use", sceneStats.uniquePlans},
            {"shared_plans", sceneStats.sharedPlans},
            {"nodes", totalNodes},
            {"nodes_by_kind", nodes},
            {"stencils", stats.stencils},
            {"bytes", stats.bytes},
            {"plan_bytes_in_use", sceneStats.planBytes},
            {"control_points", controlPoints},
            {"control_point_bytes", controlPoints * sizeof(glm::vec3)},
            {"build_ms", buildMs},
            {"database_hits", stats.hits},
            {"database_misses", stats.misses},
            {"macro_faces", rectangles.faces},
            {"faces_in_macro_faces", rectangles.members},
            {"macro_spans", rectangles.spans},
            {"macro_spans_shared", rectangles.sharedSpans},
            {"quartet_macro_faces", quartets.faces},
            {"faces_in_quartets", quartets.members},
            {"block_macro_faces", blocks.faces},
            {"faces_in_blocks", blocks.members},
        };
        std::printf("%s\n", out.dump(2).c_str());
        return 0;
    }
    std::printf("%s (depth %u, crease nodes %s)\n", args.path.c_str(), args.depth, args.noCreaseNodes ? "off" : "on");
    if (scene->objects.size() > 1) {
        std::printf("  objects        %zu (%u distinct cages, %llu faces drawn counting instances)\n", scene->objects.size(),
                    sceneStats.cages, (unsigned long long)sceneStats.instanceFaces);
        for (const ObjectPlanStats& o : sceneStats.objects) {
            if (!o.instanceOf.empty()) {
                std::printf("    %-20s instance of %s\n", o.name.c_str(), o.instanceOf.c_str());
                continue;
            }
            std::printf("    %-20s %u faces, %u plans (%u shared with other cages, %u new)\n", o.name.c_str(), o.faces,
                        o.plans, o.sharedPlans, o.newPlans);
        }
    }
    std::printf("  faces          %llu (%llu sub-faces)\n", (unsigned long long)faces, (unsigned long long)subfaces);
    std::printf("  unique plans   %u (%u used by more than one cage)\n", stats.plans, sceneStats.sharedPlans);
    std::printf("  nodes          %llu:", (unsigned long long)totalNodes);
    for (uint32_t k = 0; k < kNodeKindCount; ++k)
        std::printf(" %s %llu", nodeKindName(NodeKind(k)), (unsigned long long)stats.nodesByKind[k]);
    std::printf("\n  stencils       %llu\n", (unsigned long long)stats.stencils);
    std::printf("  plan bytes     %llu\n", (unsigned long long)stats.bytes);
    std::printf("  control points %llu stored, those factors <= %u read (%llu bytes)\n", (unsigned long long)controlPoints,
                1u << PlannedCage::kStoredControlPointLevel,
                (unsigned long long)(controlPoints * sizeof(glm::vec3)));
    std::printf("  macro faces    %llu rectangles holding %llu faces (%llu of %llu side spans shared); or %llu quartets "
                "holding %llu; or %llu aligned blocks holding %llu\n",
                (unsigned long long)rectangles.faces, (unsigned long long)rectangles.members,
                (unsigned long long)rectangles.sharedSpans, (unsigned long long)rectangles.spans,
                (unsigned long long)quartets.faces, (unsigned long long)quartets.members, (unsigned long long)blocks.faces,
                (unsigned long long)blocks.members);
    std::printf("  build          %.1f ms (database: %llu hits, %llu misses)\n", buildMs,
                (unsigned long long)stats.hits, (unsigned long long)stats.misses);
    return 0;
}

}  // namespace

void registerPlanStats(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand("plan-stats", "Build the subdivision plans of a cage and print their statistics");
    auto args = std::make_shared<PlanStatsArgs>();
    cmd->add_option("file", args->path, "Cage (.obj, .om, .ply, .off, .stl) or scene (.json)")->required();
    cmd->add_option("--depth", args->depth, "Maximum quadtree depth")->check(CLI::Range(1u, kMaxPlanDepth));
    cmd->add_flag("--no-crease-nodes", args->noCreaseNodes, "Isolate semi-sharp creases instead of crease nodes");
    cmd->add_flag("--json", args->json, "Print one JSON object");
    addPlanDatabaseOption(cmd, args->planDatabase);
    cmd->callback([args, &exitCode] { exitCode = runPlanStats(*args); });
}

}  // namespace qp::cli
