#include "render_target.h"

#include <algorithm>
#include <cmath>

#include "vk_commands.h"

namespace qp {

namespace {

float linearToSrgb(float c) {
    c = std::clamp(c, 0.0f, 1.0f);
    return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

bool coversImage(const RenderTarget& t) {
    return t.area.offset.x == 0 && t.area.offset.y == 0 && t.area.extent.width == t.width &&
           t.area.extent.height == t.height;
}

}  // namespace

RenderTarget subArea(const RenderTarget& target, VkRect2D area) {
    RenderTarget t = target;
    const int32_t x = std::clamp(area.offset.x, 0, int32_t(target.width));
    const int32_t y = std::clamp(area.offset.y, 0, int32_t(target.height));
    t.area.offset = {x, y};
    t.area.extent.width = std::min(area.extent.width, target.width - uint32_t(x));
    t.area.extent.height = std::min(area.extent.height, target.height - uint32_t(y));
    return t;
}

bool isSrgbFormat(VkFormat format) {
    return format == VK_FORMAT_R8G8B8A8_SRGB || format == VK_FORMAT_B8G8R8A8_SRGB;
}

void beginRendering(VkCommandBuffer cmd, const RenderTarget& t, bool clear, const glm::vec3& background) {
    // A clear of the whole image may discard the old contents (UNDEFINED); a clear of one
    // viewport must keep the others.
    const bool discard = clear && coversImage(t);
    VkImageMemoryBarrier2 toColor =
        imageBarrier(t.colorImage, VK_IMAGE_ASPECT_COLOR_BIT,
                     discard ? VK_IMAGE_LAYOUT_UNDEFINED : VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                     VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    toColor.srcStageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_2_COPY_BIT;
    toColor.srcAccessMask = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
    toColor.dstStageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    toColor.dstAccessMask = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT;
    const VkPipelineStageFlags2 depthStages =
        VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
    VkImageMemoryBarrier2 toDepth =
        imageBarrier(t.depthImage, VK_IMAGE_ASPECT_DEPTH_BIT,
                     discard ? VK_IMAGE_LAYOUT_UNDEFINED : VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                     VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
    toDepth.srcStageMask = depthStages;
    toDepth.srcAccessMask = VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    toDepth.dstStageMask = depthStages;
    toDepth.dstAccessMask = VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
    pipelineBarrier(cmd, {toColor, toDepth});

    // A clear value is stored as given: an sRGB attachment encodes it, a UNORM one needs it
    // encoded like the shaders' output.
    glm::vec3 clearColor = background;
    if (!isSrgbFormat(t.colorFormat))
        clearColor = {linearToSrgb(background.r), linearToSrgb(background.g), linearToSrgb(background.b)};
    const VkAttachmentLoadOp load = clear ? VK_ATTACHMENT_LOAD_OP_CLEAR : VK_ATTACHMENT_LOAD_OP_LOAD;
    VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    color.imageView = t.colorView;
    color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.loadOp = load;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    color.clearValue.color = {{clearColor.r, clearColor.g, clearColor.b, 1.0f}};
    VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    depth.imageView = t.depthView;
    depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    depth.loadOp = load;
    depth.storeOp = VK_ATTACHMENT_STORE_OP_STORE;  // overlays (cage lines) test against it
    depth.clearValue.depthStencil = {1.0f, 0};
    VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
    rendering.renderArea = t.area;
    rendering.layerCount = 1;
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachments = &color;
    rendering.pDepthAttachment = &depth;
    vkCmdBeginRendering(cmd, &rendering);
    const VkViewport viewport{float(t.area.offset.x), float(t.area.offset.y), float(t.area.extent.width),
                              float(t.area.extent.height), 0.0f, 1.0f};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &t.area);
}

}  // namespace qp
