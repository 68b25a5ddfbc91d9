// RenderTarget: what every pass draws into, whatever owns the images: an OffscreenTarget
// (headless PNGs, tests, benchmarks) or the current image of a window's swapchain. Passes
// take a RenderTarget, so offscreen and on-screen frames share one drawing path.
//
// Layout contract: between passes the colour image is in COLOR_ATTACHMENT_OPTIMAL and the
// depth image in DEPTH_ATTACHMENT_OPTIMAL. The owner establishes it (at creation, or when a
// swapchain image is acquired) and restores it after anything else it does with the images
// (readPixels' copy, the transition to present).
//
// `area` is the part of the images a pass draws in and clears: the whole image, or one
// viewport of a window split into several (side-by-side schemes).
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>
#include <vulkan/vulkan.h>

namespace qp {

struct RenderTarget {
    VkImage colorImage = VK_NULL_HANDLE;
    VkImageView colorView = VK_NULL_HANDLE;
    VkFormat colorFormat = VK_FORMAT_UNDEFINED;
    VkImage depthImage = VK_NULL_HANDLE;
    VkImageView depthView = VK_NULL_HANDLE;
    VkFormat depthFormat = VK_FORMAT_UNDEFINED;
    uint32_t width = 0, height = 0;  // of the images
    VkRect2D area{};                 // where passes draw; inside the images
};

// The same target drawing into a sub-rectangle (clamped to the images).
RenderTarget subArea(const RenderTarget& target, VkRect2D area);

// True for formats whose writes the hardware encodes to sRGB.
bool isSrgbFormat(VkFormat format);

// Specialisation of shaders/color_encoding.glsl for a target format: fragment shaders encode
// their linear colour to sRGB themselves unless the format does it. Pass `info` as the
// fragment stage's pSpecializationInfo; it points into this object, so keep it alive (and in
// place) until the pipeline is created.
struct ColorEncoding {
    VkBool32 encodeInShader;
    VkSpecializationMapEntry entry{0, 0, sizeof(VkBool32)};
    VkSpecializationInfo info{1, &entry, sizeof(VkBool32), &encodeInShader};

    explicit ColorEncoding(VkFormat target) : encodeInShader(isSrgbFormat(target) ? VK_FALSE : VK_TRUE) {}
    ColorEncoding(const ColorEncoding&) = delete;
    ColorEncoding& operator=(const ColorEncoding&) = delete;
};

// Starts dynamic rendering into target.area with viewport and scissor set to it. With `clear`
// the area's colour is cleared to `background` (linear; encoded for UNORM targets with the sRGB
// curve, as the shaders encode their output: ColorEncoding) and its depth to 1; without, what earlier passes drew is kept.
// Waits for earlier passes' attachment writes and for earlier copies from the colour image.
// End with vkCmdEndRendering; the layout contract holds afterwards.
void beginRendering(VkCommandBuffer cmd, const RenderTarget& target, bool clear, const glm::vec3& background);

}  // namespace qp
