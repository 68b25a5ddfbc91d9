#include "scheme_host.h"

#include <algorithm>
#include <chrono>
#include <functional>
#include <vector>

#include "vk_commands.h"

namespace qp {

namespace {

double msSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

double median(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace

Result<SchemeFrameTimes> timeFrames(const VulkanContext& ctx, const std::function<Status()>& update,
                                    const std::function<Result<DrawStats>(VkCommandBuffer)>& record, const GpuTimer& timer,
                                    uint32_t repeats) {
    SchemeFrameTimes times;
    std::vector<double> frames, draws;
    for (uint32_t k = 0; k <= repeats; ++k) {
        const auto start = std::chrono::steady_clock::now();
        if (Status updated = update(); !updated) return updated.error();
        Result<DrawStats> drawn = DrawStats{};
        if (Status submitted = submitAndWait(ctx, [&](VkCommandBuffer cmd) {
                beginGpuTimer(cmd, timer);
                drawn = record(cmd);
                endGpuTimer(cmd, timer);
            });
            !submitted)
            return submitted.error();
        if (!drawn) return drawn.error();
        times.draw = *drawn;
        const double wall = msSince(start);
        Result<double> gpuMs = readGpuTimerMs(ctx, timer);
        if (k == 0) continue;  // warm-up
        frames.push_back(wall);
        draws.push_back(gpuMs ? *gpuMs : 0.0);
    }
    times.frameMs = median(frames);
    times.drawMs = median(draws);
    return times;
}

Result<SchemeFrameTimes> timeSchemeFrames(const VulkanContext& ctx, SchemeInstance& scheme, const RenderTarget& target,
                                          const DrawView& view, const GpuTimer& timer, uint32_t repeats) {
    return timeFrames(
        ctx, [&] { return scheme.update(); }, [&](VkCommandBuffer cmd) { return scheme.record(cmd, target, view); }, timer,
        repeats);
}

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

std::vector<uint32_t> changedSubfaces(const PlannedCage& planned, const EditReport& report) {
    std::vector<uint32_t> out = report.updatedSubfaceList;
    for (uint32_t f : report.replannedFaceList)
        for (uint32_t s = planned.firstSubface(f); s < planned.firstSubface(f + 1); ++s) out.push_back(s);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

}  // namespace qp
