// SwapchainTarget: a window's swapchain as RenderTargets, so on-screen frames go through the
// same passes as offscreen ones (render_target.h).
//
// The caller owns the window and its VkSurfaceKHR (render/ never touches GLFW): create the
// context with the surface's instance extensions and VK_KHR_swapchain as a device extension
// (swapchainDeviceExtensions()), create the surface, then the target.
//
// Images can be rendered to and be the source or destination of copies (read-backs, pictures
// composed elsewhere), so SwapchainFrame::image may be used with vkCmdCopyImage as long as the
// layout contract is restored.
//
// Per frame: beginFrame waits for the frame-in-flight slot's fence, acquires an image
// (recreating the swapchain when it is out of date or the window size changed), begins the
// slot's command buffer and establishes render_target.h's layout contract for that image; the
// caller records passes into frame.target; endFrame moves the image to PRESENT_SRC, submits
// (waiting on the acquire semaphore, signalling the image's render-finished semaphore and the
// slot's fence) and presents. One depth image serves every swapchain image: each pass's
// beginRendering barrier orders its depth use after the previous frame's, and the queue runs
// frames in submission order.
//
// Semaphores: one "image acquired" per frame-in-flight slot (free again once the slot's fence
// signalled), one "render finished" per swapchain image (free again once that image is
// re-acquired, the only point at which presentation is known to be done with it).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "mesh/result.h"
#include "offscreen_target.h"
#include "render_target.h"
#include "vk_context.h"

namespace qp {

inline constexpr uint32_t kFramesInFlight = 2;

// Device extensions a swapchain needs (add to ContextOptions::deviceExtensions).
std::vector<std::string> swapchainDeviceExtensions();

struct SwapchainOptions {
    // FIFO (vsync) when true; otherwise MAILBOX or IMMEDIATE when the surface offers them.
    bool vsync = true;
};

struct SwapchainFrameSlot {
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkSemaphore imageAcquired = VK_NULL_HANDLE;
    VkFence inFlight = VK_NULL_HANDLE;  // signalled when the slot's last submission finished
    bool submitted = false;             // the fence belongs to a submission (else it is unsignalled-free)
};

struct SwapchainTarget {
    VkSurfaceKHR surface = VK_NULL_HANDLE;  // not owned
    VkSwapchainKHR swapchain = VK_NULL_HANDLE;
    VkSurfaceFormatKHR surfaceFormat{};  // a UNORM format: the passes encode sRGB themselves
    VkPresentModeKHR presentMode = VK_PRESENT_MODE_FIFO_KHR;
    VkExtent2D extent{};
    SwapchainOptions options;
    std::vector<VkImage> images;
    std::vector<VkImageView> views;
    std::vector<VkSemaphore> renderFinished;  // per image
    Image depth;                              // D32_SFLOAT, shared by all images
    SwapchainFrameSlot slots[kFramesInFlight];
    uint32_t slot = 0;       // the slot of the frame being recorded or recorded next
    uint32_t generation = 0; // increases whenever images are recreated (framebuffers must follow)
    bool needsRecreate = false;
};

// Creates the swapchain for `surface` at the window's framebuffer size (used when the surface
// does not dictate its extent). Fails with a message when the context's queue cannot present
// to the surface or the surface offers no usable format.
Result<SwapchainTarget> createSwapchainTarget(const VulkanContext& context, VkSurfaceKHR surface, uint32_t width,
                                              uint32_t height, SwapchainOptions options = {});
// Waits for the device, then destroys the swapchain and everything the target created (not the surface).
void destroySwapchainTarget(const VulkanContext& context, SwapchainTarget& target);

// Recreates images, views, depth and semaphores at the new size (after waiting for the device).
Status recreateSwapchain(const VulkanContext& context, SwapchainTarget& target, uint32_t width, uint32_t height);

struct SwapchainFrame {
    VkCommandBuffer cmd = VK_NULL_HANDLE;  // begun; record passes, then call endFrame
    RenderTarget target;                   // the acquired image, whole area
    uint32_t imageIndex = 0;
    VkImage image = VK_NULL_HANDLE;
};

// Waits for the slot, acquires an image and begins the frame. `width` x `height` is the
// window's current framebuffer size: a change recreates the swapchain first. Returns no frame
// (std::nullopt inside the Result) when the window has no area (minimised): skip drawing.
Result<std::optional<SwapchainFrame>> beginFrame(const VulkanContext& context, SwapchainTarget& target,
                                                 uint32_t width, uint32_t height);

// Ends, submits and presents the frame. With `readback` the image is also copied to host
// memory before presentation (the call then waits for the frame to finish) and returned as
// RGBA8 rows top to bottom, exactly as presented.
Status endFrame(const VulkanContext& context, SwapchainTarget& target, const SwapchainFrame& frame,
                std::vector<uint8_t>* readback = nullptr);

// The fence of the frame most recently submitted from `slot`, e.g. to read its GPU timer once
// it has finished; VK_NULL_HANDLE when the slot never submitted.
VkFence slotFence(const SwapchainTarget& target, uint32_t slot);

}  // namespace qp
