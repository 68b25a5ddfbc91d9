// FrameStats: recent frame times (CPU work, GPU work from timestamps, interval between frame
// starts) and what each viewport drew, for the stats panel, dump-state and measurements.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

#include "scene_renderer.h"

namespace qp::editor {

struct FrameSample {
    // The frame's work up to submission, without waiting for a frame slot or for the device to
    // finish earlier frames before buffers change (deviceWaitMs).
    double cpuMs = 0.0;
    double gpuMs = -1.0;      // device time of the frame's commands; < 0 while unknown
    double intervalMs = 0.0;  // since the previous frame started (includes waiting for input)
    bool sceneDrawn = false;  // the 3D viewports were drawn (not copied from the scene cache)
    bool culled = false;      // some viewport culled (DrawView::cull)
    bool coarse = false;      // drawn coarse while the camera moved (progressive refinement)
    double deviceWaitMs = 0.0;  // left out of cpuMs
};

struct FrameStats {
    std::deque<FrameSample> samples;  // newest last, at most kKept
    std::vector<ViewportCounts> viewportCounts;
    static constexpr size_t kKept = 600;

    void add(const FrameSample& sample);
    // The GPU time of a frame already added, `age` frames back (0: the newest).
    void setGpuMs(size_t age, double ms);
    void clear() { samples.clear(); }
};

struct Summary {
    double median = 0.0, p90 = 0.0, max = 0.0;
    size_t count = 0;
};
enum class FrameField { Cpu, Gpu, Interval };
// SceneDrawnCulled / SceneDrawnUnculled: drawn frames with some viewport culling, or none (what
// culling saves: the two medians side by side).
// SceneDrawnFull / SceneDrawnCoarse: drawn frames at full quality, or coarse while the camera moved.
enum class FrameFilter { All, SceneDrawn, SceneCopied, SceneDrawnCulled, SceneDrawnUnculled, SceneDrawnFull, SceneDrawnCoarse };
// Over the newest `last` samples (all when 0) that pass `filter`; GPU samples still unknown are
// skipped.
Summary summarize(const FrameStats& stats, FrameField field, size_t last = 0, FrameFilter filter = FrameFilter::All);

}  // namespace qp::editor
