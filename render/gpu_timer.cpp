#include "gpu_timer.h"

#include <vector>

#include "vk_check.h"

namespace qp {

Result<GpuTimer> createGpuTimer(const VulkanContext& ctx) {
    uint32_t familyCount = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(ctx.physicalDevice, &familyCount, nullptr);
    std::vector<VkQueueFamilyProperties> families(familyCount);
    vkGetPhysicalDeviceQueueFamilyProperties(ctx.physicalDevice, &familyCount, families.data());
    const uint32_t validBits = ctx.queueFamily < familyCount ? families[ctx.queueFamily].timestampValidBits : 0;
    if (validBits == 0) return Error{"the Vulkan device '" + ctx.deviceName + "' writes no timestamps on its queue"};

    GpuTimer timer;
    timer.periodNs = ctx.properties.limits.timestampPeriod;
    timer.validMask = validBits >= 64 ? ~0ull : (1ull << validBits) - 1;
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = 2;
    VK_CHECK(vkCreateQueryPool(ctx.device, &info, nullptr, &timer.pool));
    return timer;
}

void destroyGpuTimer(const VulkanContext& ctx, GpuTimer& timer) {
    if (timer.pool) vkDestroyQueryPool(ctx.device, timer.pool, nullptr);
    timer = GpuTimer{};
}

void beginGpuTimer(VkCommandBuffer cmd, const GpuTimer& timer) {
    // Reset in the same command buffer, so the timer can be reused every frame.
    vkCmdResetQueryPool(cmd, timer.pool, 0, 2);
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, timer.pool, 0);
}

void endGpuTimer(VkCommandBuffer cmd, const GpuTimer& timer) {
    // Bottom of the pipe: after every earlier command has finished, rasterisation included.
    vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, timer.pool, 1);
}

Result<double> readGpuTimerMs(const VulkanContext& ctx, const GpuTimer& timer) {
    uint64_t stamps[2] = {0, 0};
    VK_CHECK(vkGetQueryPoolResults(ctx.device, timer.pool, 0, 2, sizeof stamps, stamps, sizeof(uint64_t),
                                   VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    const uint64_t ticks = ((stamps[1] & timer.validMask) - (stamps[0] & timer.validMask)) & timer.validMask;
    return double(ticks) * timer.periodNs * 1e-6;
}

}  // namespace qp
