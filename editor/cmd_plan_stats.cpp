#include <chrono>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "plan_db_option.h"
#include "planned_cage.h"
#include "scene.h"

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
    std::vector<std::string> warnings;
    Result<Scene> scene = loadSceneOrCage(args.path, &warnings);
    for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (!scene) {
        std::fprintf(stderr, "error: %s\n", scene.error().message.c_str());
        return 1;
    }
    PlanDatabase database;
    loadPlanDatabase(database, args.planDatabase);
    PlanOptions options{args.depth, !args.noCreaseNodes};
    auto start = std::chrono::steady_clock::now();
    Result<PlannedCage> planned = PlannedCage::create(scene->cage, database, options, args.path);
    double buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (!planned) {
        std::fprintf(stderr, "error: %s\n", planned.error().message.c_str());
        return 1;
    }
    savePlanDatabase(database, args.planDatabase);
    PlanDatabaseStats stats = database.stats();
    uint64_t controlPoints = 0;
    for (uint32_t s = 0; s < planned->subfaceCount(); ++s) controlPoints += planned->subfaceControlPoints(s).size();

    nlohmann::json nodes = nlohmann::json::object();
    uint64_t totalNodes = 0;
    for (uint32_t k = 0; k < kNodeKindCount; ++k) {
        nodes[nodeKindName(NodeKind(k))] = stats.nodesByKind[k];
        totalNodes += stats.nodesByKind[k];
    }
    if (args.json) {
        nlohmann::json out = {
            {"file", args.path},
            {"depth", args.depth},
            {"crease_nodes", !args.noCreaseNodes},
            {"faces", planned->cage().faceCount()},
            {"subfaces", planned->subfaceCount()},
            {"unique_plans", stats.plans},
            {"nodes", totalNodes},
            {"nodes_by_kind", nodes},
            {"stencils", stats.stencils},
            {"bytes", stats.bytes},
            {"control_points", controlPoints},
            {"control_point_bytes", controlPoints * sizeof(glm::vec3)},
            {"build_ms", buildMs},
            {"database_hits", stats.hits},
            {"database_misses", stats.misses},
        };
        std::printf("%s\n", out.dump(2).c_str());
        return 0;
    }
    std::printf("%s (depth %u, crease nodes %s)\n", args.path.c_str(), args.depth, args.noCreaseNodes ? "off" : "on");
    std::printf("  faces          %u (%u sub-faces)\n", planned->cage().faceCount(), planned->subfaceCount());
    std::printf("  unique plans   %u\n", stats.plans);
    std::printf("  nodes          %llu:", (unsigned long long)totalNodes);
    for (uint32_t k = 0; k < kNodeKindCount; ++k)
        std::printf(" %s %llu", nodeKindName(NodeKind(k)), (unsigned long long)stats.nodesByKind[k]);
    std::printf("\n  stencils       %llu\n", (unsigned long long)stats.stencils);
    std::printf("  plan bytes     %llu\n", (unsigned long long)stats.bytes);
    std::printf("  control points %llu (%llu bytes)\n", (unsigned long long)controlPoints,
                (unsigned long long)(controlPoints * sizeof(glm::vec3)));
    std::printf("  build          %.1f ms (database: %llu hits, %llu misses)\n", buildMs,
                (unsigned long long)stats.hits, (unsigned long long)stats.misses);
    return 0;
}

}  // namespace

void registerPlanStats(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand("plan-stats", "Build the subdivision plans of a cage and print their statistics");
    auto args = std::make_shared<PlanStatsArgs>();
    cmd->add_option("file", args->path, "Cage (.obj) or scene (.json)")->required();
    cmd->add_option("--depth", args->depth, "Maximum quadtree depth")->check(CLI::Range(1u, kMaxPlanDepth));
    cmd->add_flag("--no-crease-nodes", args->noCreaseNodes, "Isolate semi-sharp creases instead of crease nodes");
    cmd->add_flag("--json", args->json, "Print one JSON object");
    addPlanDatabaseOption(cmd, args->planDatabase);
    cmd->callback([args, &exitCode] { exitCode = runPlanStats(*args); });
}

}  // namespace qp::cli
