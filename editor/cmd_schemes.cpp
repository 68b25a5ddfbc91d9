// `quadplan schemes`: the scheme plugins this quadplan finds, and those it could not load.
// With a cage, also what each scheme approximates or refuses on it.
#include <cstdio>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "plans/planned_cage.h"
#include "render_setup.h"
#include "scheme_loader.h"

namespace qp::cli {

namespace {

struct SchemesArgs {
    std::string pluginDir, cage;
    bool json = false;
};

int runSchemes(const SchemesArgs& args) {
    const PluginCatalog catalog = loadPlugins(pluginDirectory(args.pluginDir));
    std::optional<Scene> scene;
    std::optional<CageFeatures> features;
    if (!args.cage.empty()) {
        Result<Scene> loaded = loadSceneOrCage(args.cage);
        if (!loaded) {
            std::fprintf(stderr, "error: %s\n", loaded.error().message.c_str());
            return 1;
        }
        // A scene's features are every object's cage's together: what a scheme must draw for it.
        features.emplace();
        for (const SceneObject& o : loaded->objects) {
            if (o.isInstance()) continue;
            if (Status valid = validateCage(o.cage, args.cage); !valid) {
                std::fprintf(stderr, "error: %s\n", valid.error().message.c_str());
                return 1;
            }
            const CageFeatures f = analyzeCage(o.cage, buildTopology(o.cage));
            for (uint32_t k = 0; k < kCageFeatureCount; ++k) features->count[k] += f.count[k];
            features->maxValence = std::max(features->maxValence, f.maxValence);
        }
    }
    nlohmann::json json = {{"directory", catalog.directory}, {"schemes", nlohmann::json::array()},
                           {"problems", nlohmann::json::array()}};
    if (!args.json) std::printf("scheme plugins in %s:\n", catalog.directory.c_str());
    for (const auto& plugin : catalog.plugins) {
        nlohmann::json entry = {{"name", plugin->name}, {"summary", plugin->summary}, {"path", plugin->path}};
        // How a tag or topology edit reaches it: in place (Scheme::updatePlans) or a new instance.
        Result<SchemeInstance> probe = SchemeInstance::create(plugin);
        const bool inPlace = probe && probe->updatesPlansInPlace();
        const bool topologyInPlace = inPlace && probe->updatesTopologyInPlace();
        entry["after_edits"] = topologyInPlace ? "updates in place" : inPlace ? "updates tag edits in place" : "rebuilds";
        if (!args.json)
            std::printf("  %-10s %s\n             after a tag or topology edit: %s\n", plugin->name.c_str(),
                        plugin->summary.c_str(),
                        topologyInPlace ? "updates the re-planned sub-faces in place (tag and topology edits)"
                        : inPlace       ? "updates the re-planned sub-faces in place (tag edits; topology edits rebuild)"
                                        : "rebuilds the whole instance");
        if (features) {
            Result<SchemeInstance> instance = SchemeInstance::create(plugin);
            Result<SupportReport> report = instance ? instance->support(*features, SchemeSettings{})
                                                    : Result<SupportReport>(instance.error());
            if (!report) {
                entry["error"] = report.error().message;
                if (!args.json) std::printf("             error: %s\n", report.error().message.c_str());
            } else {
                entry["approximations"] = report->approximations;
                entry["refusals"] = report->refusals;
                if (!args.json) {
                    for (const std::string& a : report->approximations) std::printf("             approximates: %s\n", a.c_str());
                    for (const std::string& r : report->refusals) std::printf("             cannot draw: %s\n", r.c_str());
                    if (report->approximations.empty() && report->refusals.empty()) std::printf("             nothing to approximate or refuse on this cage\n");
                }
            }
        }
        json["schemes"].push_back(entry);
    }
    for (const PluginProblem& p : catalog.problems) {
        json["problems"].push_back({{"path", p.path}, {"message", p.message}});
        if (!args.json) std::printf("  not loaded: %s\n", p.message.c_str());
    }
    if (args.json) std::printf("%s\n", json.dump(2).c_str());
    return catalog.plugins.empty() ? 1 : 0;
}

}  // namespace

void registerSchemes(CLI::App& app, int& exitCode) {
    auto* cmd = app.add_subcommand("schemes", "List the patching-scheme plugins (and what each does with a cage)");
    auto args = std::make_shared<SchemesArgs>();
    cmd->add_option("cage", args->cage, "Cage (.obj, .om, .ply, .off, .stl) or scene (.json): say what each scheme approximates or refuses");
    cmd->add_option("--plugin-dir", args->pluginDir, "Where the scheme plugins are (default: $QUADPLAN_PLUGIN_DIR, else <bin>/../plugins)");
    cmd->add_flag("--json", args->json, "Print JSON");
    cmd->callback([args, &exitCode] { exitCode = runSchemes(*args); });
}

}  // namespace qp::cli
