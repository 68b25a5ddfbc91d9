#include <cstdio>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "plan_db_option.h"
#include "plans/limit_check.h"
#include "render_setup.h"
#include "scene/planned_scene.h"
#include "scene/scene.h"

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
    Result<Scene> scene = loadSceneWarning(args.path);
    if (!scene) {
        std::fprintf(stderr, "error: %s\n", scene.error().message.c_str());
        return 1;
    }
    PlanDatabase database;
    loadPlanDatabase(database, args.planDatabase);
    PlanOptions options;
    options.maxDepth = args.depth;
    options.useCreaseNodes = !args.noCreaseNodes;
    Result<PlannedScene> planned = PlannedScene::create(*scene, database, options, args.path);
    if (!planned) {
        std::fprintf(stderr, "error: %s\n", planned.error().message.c_str());
        return 1;
    }
    savePlanDatabase(database, args.planDatabase);
    // Each distinct cage in its own coordinates (an instance's transform moves the surface, not
    // its exactness), errors relative to that cage's diagonal.
    struct CageResult {
        std::string name;
        uint32_t faces = 0;
        LimitCheck check;
        uint32_t worstFace = 0, worstDerivativeFace = 0;
    };
    std::vector<CageResult> results;
    for (uint32_t c = 0; c < planned->cages.size(); ++c) {
        const PlannedCage& cage = planned->cages[c];
        const std::string& name = scene->objects[planned->objectOfCage[c]].name;
        const std::string source = planned->cages.size() == 1 ? args.path : args.path + ": object \"" + name + "\"";
        Result<LimitReference> reference = LimitReference::create(cage.cage(), args.depth, source);
        if (!reference) {
            std::fprintf(stderr, "error: %s\n", reference.error().message.c_str());
            return 1;
        }
        CageResult r{name, cage.cage().faceCount(), compareWithReference(cage, *reference, args.samples)};
        r.worstFace = faceOfSubface(cage, r.check.worstPositionSubface);
        r.worstDerivativeFace = faceOfSubface(cage, r.check.worstDerivativeSubface);
        results.push_back(std::move(r));
    }
    // The scene's figures are its worst cage's.
    size_t worstPosition = 0, worstDerivative = 0;
    bool pass = true;
    uint32_t faces = 0, subfaces = 0;
    uint64_t samples = 0;
    for (size_t i = 0; i < results.size(); ++i) {
        const LimitCheck& c = results[i].check;
        if (c.maxPositionError > results[worstPosition].check.maxPositionError) worstPosition = i;
        if (c.maxDerivativeError > results[worstDerivative].check.maxDerivativeError) worstDerivative = i;
        pass = pass && c.pass();
        faces += results[i].faces;
        subfaces += c.subfaces;
        samples += c.samples;
    }
    const CageResult& wp = results[worstPosition];
    const CageResult& wd = results[worstDerivative];

    if (args.json) {
        nlohmann::json out = {
            {"file", args.path},
            {"faces", faces},
            {"subfaces", subfaces},
            {"samples", samples},
            {"depth", args.depth},
            {"max_rel_error_position", wp.check.maxPositionError},
            {"max_rel_error_derivative", wd.check.maxDerivativeError},
            {"worst_face_position", wp.worstFace + 1},
            {"worst_face_derivative", wd.worstDerivativeFace + 1},
            {"worst_object_position", wp.name},
            {"worst_object_derivative", wd.name},
            {"tolerance_position", kPositionTolerance},
            {"tolerance_derivative", derivativeTolerance(args.depth)},
            {"unique_plans", database.size()},
            {"plan_ms", planned->planMs},
            {"pass", pass},
        };
        out["cages"] = nlohmann::json::array();
        for (const CageResult& r : results)
            out["cages"].push_back({{"object", r.name},
                                    {"faces", r.faces},
                                    {"max_rel_error_position", r.check.maxPositionError},
                                    {"max_rel_error_derivative", r.check.maxDerivativeError},
                                    {"pass", r.check.pass()}});
        std::printf("%s\n", out.dump(2).c_str());
    } else {
        std::printf("%s: %u faces (%u sub-faces), %llu samples at depth %u\n", args.path.c_str(), faces, subfaces,
                    (unsigned long long)samples, args.depth);
        if (results.size() > 1)
            for (const CageResult& r : results)
                std::printf("  object %-20s position %.3g, derivative %.3g of its diagonal\n", r.name.c_str(),
                            r.check.maxPositionError, r.check.maxDerivativeError);
        const std::string inPosition = results.size() > 1 ? " of object " + wp.name : "";
        const std::string inDerivative = results.size() > 1 ? " of object " + wd.name : "";
        std::printf("  max position error   %.3g of the diagonal (face %u%s; tolerance %.1g)\n", wp.check.maxPositionError,
                    wp.worstFace + 1, inPosition.c_str(), kPositionTolerance);
        std::printf("  max derivative error %.3g of the diagonal (face %u%s; tolerance %.1g)\n",
                    wd.check.maxDerivativeError, wd.worstDerivativeFace + 1, inDerivative.c_str(),
                    derivativeTolerance(args.depth));
        std::printf("  %s\n", pass ? "PASS" : "FAIL");
    }
    return pass ? 0 : 3;
}

}  // namespace

void registerCheckLimit(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand("check-limit",
                                   "Compare the planned limit surface with OpenSubdiv's at the same depth");
    auto args = std::make_shared<CheckLimitArgs>();
    cmd->add_option("file", args->path, "Cage (.obj, .om, .ply, .off, .stl) or scene (.json)")->required();
    cmd->add_option("--samples", args->samples, "Samples per side of each face's grid")->check(CLI::Range(2, 1000));
    cmd->add_option("--depth", args->depth, "Plan and reference depth")->check(CLI::Range(1u, kMaxPlanDepth));
    cmd->add_flag("--no-crease-nodes", args->noCreaseNodes, "Isolate semi-sharp creases instead of crease nodes");
    cmd->add_flag("--json", args->json, "Print one JSON object");
    addPlanDatabaseOption(cmd, args->planDatabase);
    cmd->callback([args, &exitCode] { exitCode = runCheckLimit(*args); });
}

}  // namespace qp::cli
