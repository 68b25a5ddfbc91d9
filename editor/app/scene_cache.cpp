#include "scene_cache.h"

#include "vk_check.h"
#include "vk_commands.h"

namespace qp::editor {

VkFormat sceneCacheFormat(const VulkanContext& ctx, VkFormat swapchainFormat) {
    const VkFormat srgb = swapchainFormat == VK_FORMAT_B8G8R8A8_UNORM   ? VK_FORMAT_B8G8R8A8_SRGB
                          : swapchainFormat == VK_FORMAT_R8G8B8A8_UNORM ? VK_FORMAT_R8G8B8A8_SRGB
                                                                        : VK_FORMAT_UNDEFINED;
    if (srgb == VK_FORMAT_UNDEFINED) return swapchainFormat;
    VkFormatProperties properties{};
    vkGetPhysicalDeviceFormatProperties(ctx.physicalDevice, srgb, &properties);
    constexpr VkFormatFeatureFlags needed = VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT | VK_FORMAT_FEATURE_TRANSFER_SRC_BIT;
    return (properties.optimalTilingFeatures & needed) == needed ? srgb : swapchainFormat;
}

Status ensureSceneCache(const VulkanContext& ctx, SceneCache& cache, VkExtent2D extent, VkFormat colorFormat) {
    if (cache.color.image && cache.extent.width == extent.width && cache.extent.height == extent.height &&
        cache.color.format == colorFormat)
        return success();
    VK_CHECK(vkQueueWaitIdle(ctx.queue));
    destroySceneCache(ctx, cache);
    if (Status s = createAttachments(ctx, extent.width, extent.height, colorFormat, cache.color, cache.depth); !s) return s;
    cache.extent = extent;
    cache.key.clear();
    return success();
}

void destroySceneCache(const VulkanContext& ctx, SceneCache& cache) {
    destroyImage(ctx, cache.color);
    destroyImage(ctx, cache.depth);
    cache = SceneCache{};
}

RenderTarget sceneCacheTarget(const SceneCache& cache) {
    return renderTargetOf(cache.color.image, cache.color.view, cache.color.format, cache.depth, cache.extent.width,
                          cache.extent.height);
}

void recordCopyToFrame(VkCommandBuffer cmd, const SceneCache& cache, const SwapchainFrame& frame) {
    VkImageMemoryBarrier2 before[2] = {
        imageBarrier(cache.color.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                      VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL),
        imageBarrier(frame.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                      VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL)};
    before[0].srcStageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    before[0].srcAccessMask = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
    before[0].dstStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
    before[0].dstAccessMask = VK_ACCESS_2_TRANSFER_READ_BIT;
    before[1].srcStageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    before[1].srcAccessMask = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
    before[1].dstStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
    before[1].dstAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
    pipelineBarrier(cmd, {before[0], before[1]});
    VkImageCopy region{};
    region.srcSubresource = region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.extent = {cache.extent.width, cache.extent.height, 1};
    vkCmdCopyImage(cmd, cache.color.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, frame.image,
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    VkImageMemoryBarrier2 after[2] = {
        imageBarrier(cache.color.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                      VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL),
        imageBarrier(frame.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL)};
    after[0].srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
    after[0].dstStageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    after[0].dstAccessMask = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT;
    after[1].srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
    after[1].srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
    after[1].dstStageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    after[1].dstAccessMask = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT;
    pipelineBarrier(cmd, {after[0], after[1]});
}

}  // namespace qp::editor
