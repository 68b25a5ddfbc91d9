// What the render and schemes suites share (bench_render.cpp, bench_schemes.cpp): frames of
// several kinds measured in rounds against the same surface pre-tessellated into triangles.
//
// Frames are measured in rounds: each round draws one frame of every kind back to back, and
// ratios are medians of the per-round ratios. Other work on the machine then slows a whole
// round rather than one kind of frame (measuring each kind in a block of its own made the
// baseline jump by 2-3x between factors on a busy machine). The baseline is drawn twice a
// round, first and halfway, and the round's ratios use the mean of the two.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "bench_stats.h"
#include "mesh/result.h"
#include "mesh_pass.h"
#include "offscreen_target.h"
#include "plan_pass.h"
#include "plans/planned_cage.h"

namespace qp::cli {

inline constexpr uint32_t kRenderWarmups = 2;  // rounds: pipeline JIT, first touch of new buffers
inline constexpr uint32_t kRenderTargetFactor = 8;
inline constexpr double kRenderTargetRatio = 1.5;  // issue: default path within 1.5x of pre-tessellated

// One kind of frame: `host` runs first, then `record` is submitted and waited for; both count.
struct FrameKind {
    std::string name;
    std::function<Status()> host;
    std::function<void(VkCommandBuffer)> record;
    bool baseline = false;       // pre-tessellated: the round's reference
    std::vector<double> ms, ratios;
    std::vector<double> cpuRatios;  // the same with the process's CPU time instead of wall time
    uint32_t coveredPixels = 0;  // not the background in the last round: a sanity check

    double medianMs() const { return ms.empty() ? NAN : median(ms); }
    double medianRatio() const { return ratios.empty() ? NAN : median(ratios); }
    double medianCpuRatio() const { return cpuRatios.empty() ? NAN : median(cpuRatios); }
};

// CPU time of this process, every thread (lavapipe's and TBB's included), in ms.
double processCpuMs();
// "median ms (ratio x)"; the default path's cells also give the CPU-time ratio, which other work
// on the machine hardly moves.
std::string cell(const FrameKind& k, bool withRatio = true);
std::string cellWithCpu(const FrameKind& k);
// The baseline at uniform `factor`: the plans grid evaluated once on the CPU and copied into a
// mesh of its own (replacing `mesh`), drawn with recordShadedTriangles, i.e. the limit of this
// device for those triangles.
Status preparePreTessellated(const VulkanContext& ctx, PlanPass& pass, PlanBuffers& buffers, const PlannedCage& planned,
                             uint32_t factor, GpuMesh& mesh);
// What both suites draw with: the cage planned, the benchmark device, a kRenderSize square RGBA8
// target, the plans' pass and buffers for the cage, and the pre-tessellated baseline's mesh
// (filled per factor by preparePreTessellated).
struct FrameBench {
    std::unique_ptr<PlanDatabase> database;  // on the heap: the planned cage points into it
    std::unique_ptr<PlannedCage> planned;
    VulkanContext ctx;
    OffscreenTarget target;
    PlanPass pass;
    PlanBuffers buffers;
    GpuMesh preMesh;
    std::string error;  // the first failure after the context was made; the rest is then skipped
};
// Fails only when the cage cannot be planned or no Vulkan context can be made (nothing to destroy
// then); the load average goes into the notes, prefixed with `name`.
Result<FrameBench> createFrameBench(const Cage& cage, const std::string& name, std::vector<std::string>& notes);
// Waits for the device and destroys whatever was made.
void destroyFrameBench(FrameBench& bench);

// Pixels of the last frame that are not the background (the top-left pixel's colour).
Result<uint32_t> coveredPixels(const VulkanContext& ctx, const OffscreenTarget& target);

}  // namespace qp::cli
