#include "scene_cache.h"

#include "vk_check.h"
#include "vk_commands.h"

namespace qp::editor {

namespace {

VkImageMemoryBarrier2 layoutBarrier(VkImage image, VkImageAspectFlags aspect, VkImageLayout from, VkImageLayout to) {
    VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {aspect, 0, 1, 0, 1};
    return b;
}

void barriers(VkCommandBuffer cmd, const VkImageMemoryBarrier2* b, uint32_t count) {
    VkDependencyInfo dependency{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dependency.imageMemoryBarrierCount = count;
    dependency.pImageMemoryBarriers = b;
    vkCmdPipelineBarrier2(cmd, &dependency);
}

}  // namespace

Status ensureSceneCache(const VulkanContext& ctx, SceneCache& cache, VkExtent2D extent, VkFormat colorFormat) {
    if (cache.color.image && cache.extent.width == extent.width && cache.extent.height == extent.height &&
        cache.color.format == colorFormat)
        return success();
    VK_CHECK(vkQueueWaitIdle(ctx.queue));
    destroySceneCache(ctx, cache);
    if (Status s = createImage(ctx, cache.color, extent.width, extent.height, colorFormat,
                               VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                               VK_IMAGE_ASPECT_COLOR_BIT);
        !s)
        return s;
    if (Status s = createImage(ctx, cache.depth, extent.width, extent.height, VK_FORMAT_D32_SFLOAT,
                               VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, VK_IMAGE_ASPECT_DEPTH_BIT);
        !s)
        return s;
    cache.extent = extent;
    cache.key.clear();
    return submitAndWait(ctx, [&](VkCommandBuffer cmd) {
        VkImageMemoryBarrier2 b[2] = {
            layoutBarrier(cache.color.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                          VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL),
            layoutBarrier(cache.depth.image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                          VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL)};
        b[0].dstStageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
        b[0].dstAccessMask = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
        b[1].dstStageMask = VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
        b[1].dstAccessMask = VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
        barriers(cmd, b, 2);
    });
}

void destroySceneCache(const VulkanContext& ctx, SceneCache& cache) {
    destroyImage(ctx, cache.color);
    destroyImage(ctx, cache.depth);
    cache = SceneCache{};
}

RenderTarget sceneCacheTarget(const SceneCache& cache) {
    RenderTarget t;
    t.colorImage = cache.color.image;
    t.colorView = cache.color.view;
    t.colorFormat = cache.color.format;
    t.depthImage = cache.depth.image;
    t.depthView = cache.depth.view;
    t.depthFormat = cache.depth.format;
    t.width = cache.extent.width;
    t.height = cache.extent.height;
    t.area = {{0, 0}, cache.extent};
    return t;
}

void recordCopyToFrame(VkCommandBuffer cmd, const SceneCache& cache, const SwapchainFrame& frame) {
    VkImageMemoryBarrier2 before[2] = {
        layoutBarrier(cache.color.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                      VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL),
        layoutBarrier(frame.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                      VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL)};
    before[0].srcStageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    before[0].srcAccessMask = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
    before[0].dstStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
    before[0].dstAccessMask = VK_ACCESS_2_TRANSFER_READ_BIT;
    before[1].srcStageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    before[1].srcAccessMask = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
    before[1].dstStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
    before[1].dstAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
    barriers(cmd, before, 2);
    VkImageCopy region{};
    region.srcSubresource = region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.extent = {cache.extent.width, cache.extent.height, 1};
    vkCmdCopyImage(cmd, cache.color.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, frame.image,
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    VkImageMemoryBarrier2 after[2] = {
        layoutBarrier(cache.color.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                      VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL),
        layoutBarrier(frame.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL)};
    after[0].srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
    after[0].dstStageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    after[0].dstAccessMask = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT;
    after[1].srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
    after[1].srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
    after[1].dstStageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    after[1].dstAccessMask = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT;
    barriers(cmd, after, 2);
}

}  // namespace qp::editor
