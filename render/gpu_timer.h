// GpuTimer: how long the device spent on a span of recorded commands, from two timestamps in a
// VkQueryPool (begin at the top of the pipe, end at the bottom).
//
// On lavapipe a timestamp is the CPU clock when its rasterizer threads reach the query, and a
// bottom-of-pipe timestamp flushes the draws before it, so the span is the real execution time
// of the commands (period 1 ns). It excludes submission and the fence wait, which a wall clock
// around submitAndWait includes; on a CPU device both matter, so benchmarks report both.
#pragma once

#include <vulkan/vulkan.h>

#include "mesh/result.h"
#include "vk_context.h"

namespace qp {

struct GpuTimer {
    VkQueryPool pool = VK_NULL_HANDLE;
    double periodNs = 1.0;        // VkPhysicalDeviceLimits::timestampPeriod
    uint64_t validMask = ~0ull;   // the queue family's timestampValidBits as a mask
};

// Fails when the context's queue family writes no timestamps (timestampValidBits == 0).
Result<GpuTimer> createGpuTimer(const VulkanContext& context);
void destroyGpuTimer(const VulkanContext& context, GpuTimer& timer);

// Record around the span to time, in one command buffer, outside a rendering instance.
void beginGpuTimer(VkCommandBuffer cmd, const GpuTimer& timer);
void endGpuTimer(VkCommandBuffer cmd, const GpuTimer& timer);

// Milliseconds between the two timestamps; waits for both to be available, so call it after
// the command buffer was submitted.
Result<double> readGpuTimerMs(const VulkanContext& context, const GpuTimer& timer);

}  // namespace qp
