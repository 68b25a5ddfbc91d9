// Taking a scheme from its plugin to a drawable instance for one planned cage: the steps every
// host (render, compare, the editor) runs, with one message per way it can fail.
#pragma once

#include <functional>
#include <string>

#include "gpu_timer.h"
#include "scheme_loader.h"

namespace qp {

struct PreparedScheme {
    SchemeInstance instance;
    SupportReport support;             // approximations: warnings the host shows
    double buildMs = 0.0, gpuMs = 0.0, updateMs = 0.0;  // setup, measured by the host
    double setupMs() const { return buildMs + gpuMs + updateMs; }
};

// Finds `name` in the catalog, asks it whether it can draw the cage, builds it, creates its GPU
// part and runs the first update. With a non-empty `displacement` (matching `planned`; it must
// outlive the instance) the scheme draws it; a scheme that cannot is drawn without it, with a
// warning in `support.approximations`. Errors name the scheme and the cage (`source`): an unknown
// scheme lists the available ones, a refusal lists the scheme's reasons. On failure nothing is
// left on the GPU.
Result<PreparedScheme> prepareScheme(const PluginCatalog& catalog, const std::string& name, const PlannedCage& planned,
                                     const CageFeatures& features, const SchemeSettings& settings,
                                     const GpuContext& gpu, const std::string& source,
                                     const Displacement* displacement = nullptr);

// Frame times of a prepared scheme as if the cage moved every frame: update(), then record()
// into `target` in one submission, `repeats` times after one untimed warm-up (first use of
// pipelines and caches). Medians of the wall time (update + record + submit) and of the GPU
// time of the draw; `draw` is the last frame's. What compare and the Python module report.
struct SchemeFrameTimes {
    DrawStats draw;
    double frameMs = 0.0, drawMs = 0.0;
};
// The loop under it, for any set of updates and draws (a scene's): `update` then `record` in
// one submission per frame.
Result<SchemeFrameTimes> timeFrames(const VulkanContext& context, const std::function<Status()>& update,
                                    const std::function<Result<DrawStats>(VkCommandBuffer)>& record,
                                    const GpuTimer& timer, uint32_t repeats);
Result<SchemeFrameTimes> timeSchemeFrames(const VulkanContext& context, SchemeInstance& scheme, const RenderTarget& target,
                                          const DrawView& view, const GpuTimer& timer, uint32_t repeats);

// PlanChange::subfaces for an edit of `planned` (sorted): every sub-face of the faces it
// re-planned, and those whose control points moved.
std::vector<uint32_t> changedSubfaces(const PlannedCage& planned, const EditReport& report);

// "unknown scheme 'x'; available schemes: a, b (and what failed to load, if anything)".
std::string unknownSchemeMessage(const PluginCatalog& catalog, const std::string& name);

}  // namespace qp
