#include "frame_stats.h"

#include <algorithm>

namespace qp::editor {

void FrameStats::add(const FrameSample& sample) {
    samples.push_back(sample);
    while (samples.size() > kKept) samples.pop_front();
}

void FrameStats::setGpuMs(size_t age, double ms) {
    if (age < samples.size()) samples[samples.size() - 1 - age].gpuMs = ms;
}

Summary summarize(const FrameStats& stats, FrameField field, size_t last, FrameFilter filter) {
    std::vector<double> values;
    const size_t count = last == 0 ? stats.samples.size() : std::min(last, stats.samples.size());
    for (size_t i = stats.samples.size() - count; i < stats.samples.size(); ++i) {
        const FrameSample& s = stats.samples[i];
        const bool passes = filter == FrameFilter::All                  ? true
                            : filter == FrameFilter::SceneDrawn         ? s.sceneDrawn
                            : filter == FrameFilter::SceneCopied        ? !s.sceneDrawn
                            : filter == FrameFilter::SceneDrawnCulled   ? s.sceneDrawn && s.culled
                            : filter == FrameFilter::SceneDrawnUnculled ? s.sceneDrawn && !s.culled
                            : filter == FrameFilter::SceneDrawnFull     ? s.sceneDrawn && !s.coarse
                                                                        : s.sceneDrawn && s.coarse;
        if (!passes) continue;
        const double v = field == FrameField::Cpu ? s.cpuMs : field == FrameField::Gpu ? s.gpuMs : s.intervalMs;
        if (v >= 0.0) values.push_back(v);
    }
    Summary summary;
    summary.count = values.size();
    if (values.empty()) return summary;
    std::sort(values.begin(), values.end());
    summary.median = values[values.size() / 2];
    summary.p90 = values[std::min(values.size() - 1, values.size() * 9 / 10)];
    summary.max = values.back();
    return summary;
}

}  // namespace qp::editor
