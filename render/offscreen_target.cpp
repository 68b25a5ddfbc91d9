#include "offscreen_target.h"

#include <cassert>
#include <cstring>

#include "mesh/file_io.h"
#include "vk_buffer.h"
#include "vk_check.h"
#include "vk_commands.h"

// The only stb_image_write implementation in the program. Static, so it can never clash with
// the copy inside Debian's libstb (which Dear ImGui links).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
#pragma GCC diagnostic pop

namespace qp {


Status createImage(const VulkanContext& ctx, Image& image, uint32_t width, uint32_t height, VkFormat format,
                   VkImageUsageFlags usage, VkImageAspectFlags aspect) {
    image.format = format;
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {width, height, 1};
    info.mipLevels = 1;
    info.arrayLayers = 1;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    VK_CHECK(vkCreateImage(ctx.device, &info, nullptr, &image.image));

    VkMemoryRequirements requirements;
    vkGetImageMemoryRequirements(ctx.device, image.image, &requirements);
    const uint32_t type = findMemoryType(ctx.memoryProperties, requirements.memoryTypeBits, 0,
                                         VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    if (type == UINT32_MAX) return Error{"no memory type can hold a render target on " + ctx.deviceName};
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = requirements.size;
    alloc.memoryTypeIndex = type;
    VK_CHECK(vkAllocateMemory(ctx.device, &alloc, nullptr, &image.memory));
    VK_CHECK(vkBindImageMemory(ctx.device, image.image, image.memory, 0));

    VkImageViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    viewInfo.image = image.image;
    viewInfo.viewType = VK_IMAGE_VIEW_TYPE_2D;
    viewInfo.format = format;
    viewInfo.subresourceRange = {aspect, 0, 1, 0, 1};
    VK_CHECK(vkCreateImageView(ctx.device, &viewInfo, nullptr, &image.view));
    return success();
}

void destroyImage(const VulkanContext& ctx, Image& image) {
    if (image.view) vkDestroyImageView(ctx.device, image.view, nullptr);
    if (image.image) vkDestroyImage(ctx.device, image.image, nullptr);
    if (image.memory) vkFreeMemory(ctx.device, image.memory, nullptr);
    image = Image{};
}

Result<OffscreenTarget> createOffscreenTarget(const VulkanContext& ctx, uint32_t width, uint32_t height,
                                              VkFormat colorFormat) {
    assert(width > 0 && height > 0);
    assert(colorFormat == VK_FORMAT_R8G8B8A8_SRGB || colorFormat == VK_FORMAT_R8G8B8A8_UNORM);
    OffscreenTarget t;
    t.width = width;
    t.height = height;
    if (Status s = createAttachments(ctx, width, height, colorFormat, t.color, t.depth); !s) {
        destroyOffscreenTarget(ctx, t);
        return s.error();
    }
    return t;
}

Status createAttachments(const VulkanContext& ctx, uint32_t width, uint32_t height, VkFormat colorFormat, Image& color,
                         Image& depth) {
    if (Status s = createImage(ctx, color, width, height, colorFormat,
                               VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                               VK_IMAGE_ASPECT_COLOR_BIT);
        !s)
        return s;
    if (Status s = createImage(ctx, depth, width, height, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                               VK_IMAGE_ASPECT_DEPTH_BIT);
        !s)
        return s;
    return submitAndWait(ctx, [&](VkCommandBuffer cmd) {
        VkImageMemoryBarrier2 toColor = imageBarrier(color.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                                                     VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
        toColor.dstStageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
        toColor.dstAccessMask = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
        VkImageMemoryBarrier2 toDepth = imageBarrier(depth.image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                                                     VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
        toDepth.dstStageMask = VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
        toDepth.dstAccessMask = VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
        pipelineBarrier(cmd, {toColor, toDepth});
    });
}

void destroyOffscreenTarget(const VulkanContext& ctx, OffscreenTarget& t) {
    destroyImage(ctx, t.color);
    destroyImage(ctx, t.depth);
    t = OffscreenTarget{};
}

RenderTarget renderTargetOf(VkImage colorImage, VkImageView colorView, VkFormat colorFormat, const Image& depth,
                            uint32_t width, uint32_t height) {
    RenderTarget r;
    r.colorImage = colorImage;
    r.colorView = colorView;
    r.colorFormat = colorFormat;
    r.depthImage = depth.image;
    r.depthView = depth.view;
    r.depthFormat = depth.format;
    r.width = width;
    r.height = height;
    r.area = {{0, 0}, {width, height}};
    return r;
}

RenderTarget renderTarget(const OffscreenTarget& t) {
    return renderTargetOf(t.color.image, t.color.view, t.color.format, t.depth, t.width, t.height);
}

Result<std::vector<uint8_t>> readPixels(const VulkanContext& ctx, const OffscreenTarget& t) {
    const VkDeviceSize size = VkDeviceSize(t.width) * t.height * 4;
    Result<Buffer> staging = createBuffer(ctx, size, VK_BUFFER_USAGE_TRANSFER_DST_BIT);
    if (!staging) return staging.error();

    Status copied = submitAndWait(ctx, [&](VkCommandBuffer cmd) {
        VkImageMemoryBarrier2 toSource = imageBarrier(t.color.image, VK_IMAGE_ASPECT_COLOR_BIT,
                                                      VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
        toSource.srcStageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
        toSource.srcAccessMask = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
        toSource.dstStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
        toSource.dstAccessMask = VK_ACCESS_2_TRANSFER_READ_BIT;
        pipelineBarrier(cmd, {toSource});

        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {t.width, t.height, 1};
        vkCmdCopyImageToBuffer(cmd, t.color.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging->buffer, 1, &region);

        const VkBufferMemoryBarrier2 toHost = copyToHostBarrier(staging->buffer);
        // Back to the resting layout; the copy's reads must finish before the transition.
        VkImageMemoryBarrier2 back = imageBarrier(t.color.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
        back.srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
        back.dstStageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
        back.dstAccessMask = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT;
        pipelineBarrier(cmd, {back}, &toHost);
    });
    std::vector<uint8_t> pixels;
    if (copied) {
        pixels.resize(size);
        std::memcpy(pixels.data(), staging->data, size);
    }
    destroyBuffer(ctx, *staging);
    if (!copied) return copied.error();
    return pixels;
}

Status writePng(const std::string& path, uint32_t width, uint32_t height, std::span<const uint8_t> rgba) {
    assert(rgba.size() == size_t(width) * height * 4);
    std::string encoded;
    auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
    };
    if (!stbi_write_png_to_func(append, &encoded, int(width), int(height), 4, rgba.data(), int(width * 4)))
        return Error{"cannot encode '" + path + "' as PNG"};
    return writeFileAtomically(path, encoded);
}

}  // namespace qp
