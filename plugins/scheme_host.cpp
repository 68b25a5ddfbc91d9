#include "scheme_host.h"

#include <chrono>

namespace qp {

namespace {

double msSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

std::string unknownSchemeMessage(const PluginCatalog& catalog, const std::string& name) {
    std::string message = "unknown scheme '" + name + "'; available schemes: " + catalog.names() + " (from " +
                          catalog.directory + ")";
    if (!catalog.problems.empty())
        message += "; " + std::to_string(catalog.problems.size()) + " plugin(s) failed to load (see the warnings above)";
    return message;
}

Result<PreparedScheme> prepareScheme(const PluginCatalog& catalog, const std::string& name, const PlannedCage& planned,
                                     const CageFeatures& features, const SchemeSettings& settings,
                                     const GpuContext& gpu, const std::string& source,
                                     const Displacement* displacement) {
    std::shared_ptr<SchemePlugin> plugin = catalog.find(name);
    if (!plugin) return Error{unknownSchemeMessage(catalog, name)};
    Result<SchemeInstance> instance = SchemeInstance::create(plugin);
    if (!instance) return instance.error();
    Result<SupportReport> support = instance->support(features, settings);
    if (!support) return support.error();
    if (!support->usable()) {
        std::string message = "scheme '" + name + "' cannot draw " + source + ":";
        for (const std::string& reason : support->refusals) message += " " + reason + ";";
        message.back() = '.';
        return Error{message};
    }
    PreparedScheme prepared{std::move(*instance), std::move(*support)};
    auto start = std::chrono::steady_clock::now();
    if (Status s = prepared.instance.build(planned, settings); !s) return s.error();
    if (displacement && !displacement->empty()) {
        if (Status s = prepared.instance.setDisplacement(displacement); !s)
            prepared.support.approximations.push_back("drawn without the sculpted displacement: " + s.error().message);
    }
    prepared.buildMs = msSince(start);
    start = std::chrono::steady_clock::now();
    Status gpuStatus = prepared.instance.createGpu(gpu);
    prepared.gpuMs = msSince(start);
    start = std::chrono::steady_clock::now();
    Status updated = gpuStatus ? prepared.instance.update() : gpuStatus;
    prepared.updateMs = msSince(start);
    if (!updated) {
        (void)prepared.instance.destroyGpu();
        return updated.error();
    }
    return prepared;
}

}  // namespace qp
