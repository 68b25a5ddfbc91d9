#include <chrono>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "plan_db_option.h"
#include "limit_check.h"
#include "scene.h"

namespace qp::cli {

namespace {

struct CheckLimitArgs {
    std::string path;
    uint32_t samples = 9;
    uint32_t depth = 6;
    bool noCreaseNodes = false;
    bool json = false;
    std::string planDatabase;
};

// Base face that owns a sub-face (for messages users can map back to their cage).
uint32_t faceOfSubface(const PlannedCage& planned, uint32_t subface) {
    uint32_t face = 0;
    while (face + 1 < planned.cage().faceCount() && planned.firstSubface(face + 1) <= subface) ++face;
    return face;
}

int runCheckLimit(const CheckLimitArgs& args) {
    std::vector<std::string> warnings;
    Result<Scene> scene = loadSceneOrCage(args.path, &warnings);
    for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (!scene) {
        std::fprintf(stderr, "error: %s\n", scene.error().message.c_str());
        return 1;
    }
    PlanDatabase database;
    loadPlanDatabase(database, args.planDatabase);
    PlanOptions options;
    options.maxDepth = args.depth;
    options.useCreaseNodes = !args.noCreaseNodes;
    auto start = std::chrono::steady_clock::now();
    Result<PlannedCage> planned = PlannedCage::create(scene->cage, database, options, args.path);
    if (!planned) {
        std::fprintf(stderr, "error: %s\n", planned.error().message.c_str());
        return 1;
    }
    savePlanDatabase(database, args.planDatabase);
    double planMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    Result<LimitReference> reference = LimitReference::create(scene->cage, args.depth, args.path);
    if (!reference) {
        std::fprintf(stderr, "error: %s\n", reference.error().message.c_str());
        return 1;
    }
    LimitCheck check = compareWithReference(*planned, *reference, args.samples);
    uint32_t worstFace = faceOfSubface(*planned, check.worstPositionSubface);
    uint32_t worstDerivativeFace = faceOfSubface(*planned, check.worstDerivativeSubface);

    if (args.json) {
        nlohmann::json out = {
            {"file", args.path},
            {"faces", planned->cage().faceCount()},
            {"subfaces", check.subfaces},
            {"samples", check.samples},
            {"depth", args.depth},
            {"max_rel_error_position", check.maxPositionError},
            {"max_rel_error_derivative", check.maxDerivativeError},
            {"worst_face_position", worstFace + 1},
            {"worst_face_derivative", worstDerivativeFace + 1},
            {"tolerance_position", kPositionTolerance},
            {"tolerance_derivative", derivativeTolerance(args.depth)},
            {"unique_plans", database.size()},
            {"plan_ms", planMs},
            {"pass", check.pass()},
        };
        std::printf("%s\n", out.dump(2).c_str());
    } else {
        std::printf("%s: %u faces (%u sub-faces), %llu samples at depth %u\n", args.path.c_str(),
                    planned->cage().faceCount(), check.subfaces, (unsigned long long)check.samples, args.depth);
        std::printf("  max position error   %.3g of the diagonal (face %u; tolerance %.1g)\n", check.maxPositionError,
                    worstFace + 1, kPositionTolerance);
        std::printf("  max derivative error %.3g of the diagonal (face %u; tolerance %.1g)\n",
                    check.maxDerivativeError, worstDerivativeFace + 1, derivativeTolerance(args.depth));
        std::printf("  %s\n", check.pass() ? "PASS" : "FAIL");
    }
    return check.pass() ? 0 : 3;
}

}  // namespace

void registerCheckLimit(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand("check-limit",
                                   "Compare the planned limit surface with OpenSubdiv's at the same depth");
    auto args = std::make_shared<CheckLimitArgs>();
    cmd->add_option("file", args->path, "Cage (.obj) or scene (.json)")->required();
    cmd->add_option("--samples", args->samples, "Samples per side of each face's grid")->check(CLI::Range(2, 1000));
    cmd->add_option("--depth", args->depth, "Plan and reference depth")->check(CLI::Range(1u, kMaxPlanDepth));
    cmd->add_flag("--no-crease-nodes", args->noCreaseNodes, "Isolate semi-sharp creases instead of crease nodes");
    cmd->add_flag("--json", args->json, "Print one JSON object");
    addPlanDatabaseOption(cmd, args->planDatabase);
    cmd->callback([args, &exitCode] { exitCode = runCheckLimit(*args); });
}

}  // namespace qp::cli
