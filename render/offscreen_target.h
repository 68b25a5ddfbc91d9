// OffscreenTarget: a colour + depth image pair to render into with dynamic rendering, without a
// window; its pixels can be read back and written as PNG.
//
// Passes draw into it through renderTarget(); it keeps RenderTarget's layout contract
// (render_target.h) from creation on, and readPixels restores it after its copy.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "mesh/result.h"
#include "render_target.h"
#include "vk_context.h"

namespace qp {

struct Image {
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
};

// A 2D image with its memory and a view (one mip level, one layer, optimal tiling), left in
// layout UNDEFINED.
Status createImage(const VulkanContext& context, Image& image, uint32_t width, uint32_t height, VkFormat format,
                   VkImageUsageFlags usage, VkImageAspectFlags aspect);
void destroyImage(const VulkanContext& context, Image& image);
// A RenderTarget over the whole of a colour image and `depth`, both width x height.
RenderTarget renderTargetOf(VkImage colorImage, VkImageView colorView, VkFormat colorFormat, const Image& depth,
                            uint32_t width, uint32_t height);
// A colour image (attachment and copy source) and a D32 depth image, already in the layouts every
// pass expects between passes (COLOR_ATTACHMENT_OPTIMAL, DEPTH_ATTACHMENT_OPTIMAL). On failure the
// caller destroys what was made.
Status createAttachments(const VulkanContext& context, uint32_t width, uint32_t height, VkFormat colorFormat, Image& color,
                         Image& depth);

struct OffscreenTarget {
    Image color;  // R8G8B8A8_SRGB (shaders write linear colour) or R8G8B8A8_UNORM
    Image depth;  // D32_SFLOAT
    uint32_t width = 0;
    uint32_t height = 0;
};

// Creates the images (colour also usable as a copy source) in the contract's layouts. `colorFormat` must be R8G8B8A8_SRGB or R8G8B8A8_UNORM.
Result<OffscreenTarget> createOffscreenTarget(const VulkanContext& context, uint32_t width, uint32_t height,
                                              VkFormat colorFormat = VK_FORMAT_R8G8B8A8_SRGB);
void destroyOffscreenTarget(const VulkanContext& context, OffscreenTarget& target);

// The whole target as a RenderTarget.
RenderTarget renderTarget(const OffscreenTarget& target);

// Copies the colour image to the host and waits: width * height RGBA8 pixels, rows top to
// bottom, as stored (sRGB-encoded for an SRGB target). Call after the rendering was submitted;
// it is ordered after everything already submitted to the context's queue.
Result<std::vector<uint8_t>> readPixels(const VulkanContext& context, const OffscreenTarget& target);

// Encodes RGBA8 pixels (rows top to bottom) as PNG and writes the file atomically.
Status writePng(const std::string& path, uint32_t width, uint32_t height, std::span<const uint8_t> rgba);

}  // namespace qp
