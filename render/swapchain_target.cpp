#include "swapchain_target.h"

#include <algorithm>
#include <cstring>

#include "vk_buffer.h"
#include "vk_check.h"
#include "vk_commands.h"

namespace qp {

namespace {

// UNORM first: the passes and Dear ImGui both write display-encoded colour.
Result<VkSurfaceFormatKHR> chooseFormat(const VulkanContext& ctx, VkSurfaceKHR surface) {
    uint32_t count = 0;
    VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physicalDevice, surface, &count, nullptr));
    std::vector<VkSurfaceFormatKHR> formats(count);
    VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physicalDevice, surface, &count, formats.data()));
    for (VkFormat wanted : {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM})
        for (const VkSurfaceFormatKHR& f : formats)
            if (f.format == wanted && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR) return f;
    return Error{"the window surface offers no B8G8R8A8_UNORM or R8G8B8A8_UNORM format on " + ctx.deviceName};
}

Result<VkPresentModeKHR> choosePresentMode(const VulkanContext& ctx, VkSurfaceKHR surface, bool vsync) {
    uint32_t count = 0;
    VK_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(ctx.physicalDevice, surface, &count, nullptr));
    std::vector<VkPresentModeKHR> modes(count);
    VK_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(ctx.physicalDevice, surface, &count, modes.data()));
    if (!vsync)
        for (VkPresentModeKHR wanted : {VK_PRESENT_MODE_MAILBOX_KHR, VK_PRESENT_MODE_IMMEDIATE_KHR})
            if (std::find(modes.begin(), modes.end(), wanted) != modes.end()) return wanted;
    return VK_PRESENT_MODE_FIFO_KHR;  // always supported
}

void destroyImages(const VulkanContext& ctx, SwapchainTarget& t) {
    for (VkImageView view : t.views) vkDestroyImageView(ctx.device, view, nullptr);
    for (VkSemaphore s : t.renderFinished) vkDestroySemaphore(ctx.device, s, nullptr);
    t.views.clear();
    t.renderFinished.clear();
    t.images.clear();
    destroyImage(ctx, t.depth);
}

// (Re)creates the swapchain, retiring the old one, and everything sized by it.
Status buildSwapchain(const VulkanContext& ctx, SwapchainTarget& t, uint32_t width, uint32_t height) {
    VkSurfaceCapabilitiesKHR caps;
    VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(ctx.physicalDevice, t.surface, &caps));
    VkExtent2D extent = caps.currentExtent;
    if (extent.width == UINT32_MAX) {  // the surface follows the swapchain
        extent.width = std::clamp(width, caps.minImageExtent.width, caps.maxImageExtent.width);
        extent.height = std::clamp(height, caps.minImageExtent.height, caps.maxImageExtent.height);
    }
    if (extent.width == 0 || extent.height == 0) return Error{"the window has no area"};
    // Copies in both directions: read-backs (screenshots) and pictures composed elsewhere.
    const VkImageUsageFlags usage =
        VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    if ((caps.supportedUsageFlags & usage) != usage)
        return Error{"the window surface cannot be rendered to and copied to and from on " + ctx.deviceName};

    uint32_t imageCount = std::max(caps.minImageCount + 1, kFramesInFlight);
    if (caps.maxImageCount > 0) imageCount = std::min(imageCount, caps.maxImageCount);

    VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    info.surface = t.surface;
    info.minImageCount = imageCount;
    info.imageFormat = t.surfaceFormat.format;
    info.imageColorSpace = t.surfaceFormat.colorSpace;
    info.imageExtent = extent;
    info.imageArrayLayers = 1;
    info.imageUsage = usage;
    info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.preTransform = caps.currentTransform;
    info.compositeAlpha = (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR)
                              ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
                              : VkCompositeAlphaFlagBitsKHR(caps.supportedCompositeAlpha & -caps.supportedCompositeAlpha);
    info.presentMode = t.presentMode;
    info.clipped = VK_TRUE;
    info.oldSwapchain = t.swapchain;
    VkSwapchainKHR created = VK_NULL_HANDLE;
    VK_CHECK(vkCreateSwapchainKHR(ctx.device, &info, nullptr, &created));
    if (t.swapchain) vkDestroySwapchainKHR(ctx.device, t.swapchain, nullptr);
    t.swapchain = created;
    t.extent = extent;

    uint32_t count = 0;
    VK_CHECK(vkGetSwapchainImagesKHR(ctx.device, t.swapchain, &count, nullptr));
    t.images.resize(count);
    VK_CHECK(vkGetSwapchainImagesKHR(ctx.device, t.swapchain, &count, t.images.data()));
    for (VkImage image : t.images) {
        VkImageViewCreateInfo viewInfo{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        viewInfo.image = image;
        viewInfo.viewType = VK_IMAGE_VIEW_TYPE_2D;
        viewInfo.format = t.surfaceFormat.format;
        viewInfo.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        VkImageView view = VK_NULL_HANDLE;
        VK_CHECK(vkCreateImageView(ctx.device, &viewInfo, nullptr, &view));
        t.views.push_back(view);
        VkSemaphoreCreateInfo semaphoreInfo{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        VkSemaphore semaphore = VK_NULL_HANDLE;
        VK_CHECK(vkCreateSemaphore(ctx.device, &semaphoreInfo, nullptr, &semaphore));
        t.renderFinished.push_back(semaphore);
    }

    if (Status s = createImage(ctx, t.depth, extent.width, extent.height, VK_FORMAT_D32_SFLOAT,
                               VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, VK_IMAGE_ASPECT_DEPTH_BIT);
        !s)
        return s;
    // The depth half of the layout contract holds from now on; colour is established per frame.
    Status initialised = submitAndWait(ctx, [&](VkCommandBuffer cmd) {
        VkImageMemoryBarrier2 b = imageBarrier(t.depth.image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                                               VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
        b.dstStageMask = VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
        b.dstAccessMask = VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
        pipelineBarrier(cmd, {b});
    });
    if (!initialised) return initialised;
    t.needsRecreate = false;
    ++t.generation;
    return success();
}

Status createSlots(const VulkanContext& ctx, SwapchainTarget& t) {
    for (SwapchainFrameSlot& s : t.slots) {
        VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        alloc.commandPool = ctx.commandPool;
        alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        alloc.commandBufferCount = 1;
        VK_CHECK(vkAllocateCommandBuffers(ctx.device, &alloc, &s.cmd));
        VkSemaphoreCreateInfo semaphoreInfo{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        VK_CHECK(vkCreateSemaphore(ctx.device, &semaphoreInfo, nullptr, &s.imageAcquired));
        VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        fenceInfo.flags = VK_FENCE_CREATE_SIGNALED_BIT;  // the first wait returns at once
        VK_CHECK(vkCreateFence(ctx.device, &fenceInfo, nullptr, &s.inFlight));
    }
    return success();
}

// Copies the image (in TRANSFER_SRC) into `staging` and makes the copy visible to the host.
void recordCopyToBuffer(VkCommandBuffer cmd, VkImage image, VkExtent2D extent, const Buffer& staging) {
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {extent.width, extent.height, 1};
    vkCmdCopyImageToBuffer(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.buffer, 1, &region);
}

}  // namespace

std::vector<std::string> swapchainDeviceExtensions() { return {VK_KHR_SWAPCHAIN_EXTENSION_NAME}; }

Result<SwapchainTarget> createSwapchainTarget(const VulkanContext& ctx, VkSurfaceKHR surface, uint32_t width,
                                              uint32_t height, SwapchainOptions options) {
    VkBool32 canPresent = VK_FALSE;
    VK_CHECK(vkGetPhysicalDeviceSurfaceSupportKHR(ctx.physicalDevice, ctx.queueFamily, surface, &canPresent));
    if (!canPresent)
        return Error{"the Vulkan device '" + ctx.deviceName + "' cannot present to this window's surface"};
    SwapchainTarget t;
    t.surface = surface;
    t.options = options;
    Result<VkSurfaceFormatKHR> format = chooseFormat(ctx, surface);
    if (!format) return format.error();
    t.surfaceFormat = *format;
    Result<VkPresentModeKHR> mode = choosePresentMode(ctx, surface, options.vsync);
    if (!mode) return mode.error();
    t.presentMode = *mode;
    Status built = createSlots(ctx, t);
    if (built) built = buildSwapchain(ctx, t, width, height);
    if (!built) {
        destroySwapchainTarget(ctx, t);
        return built.error();
    }
    return t;
}

void destroySwapchainTarget(const VulkanContext& ctx, SwapchainTarget& t) {
    if (ctx.device) vkDeviceWaitIdle(ctx.device);
    destroyImages(ctx, t);
    for (SwapchainFrameSlot& s : t.slots) {
        if (s.cmd) vkFreeCommandBuffers(ctx.device, ctx.commandPool, 1, &s.cmd);
        if (s.imageAcquired) vkDestroySemaphore(ctx.device, s.imageAcquired, nullptr);
        if (s.inFlight) vkDestroyFence(ctx.device, s.inFlight, nullptr);
    }
    if (t.swapchain) vkDestroySwapchainKHR(ctx.device, t.swapchain, nullptr);
    t = SwapchainTarget{};
}

Status recreateSwapchain(const VulkanContext& ctx, SwapchainTarget& t, uint32_t width, uint32_t height) {
    VK_CHECK(vkDeviceWaitIdle(ctx.device));
    destroyImages(ctx, t);
    return buildSwapchain(ctx, t, width, height);
}

Result<std::optional<SwapchainFrame>> beginFrame(const VulkanContext& ctx, SwapchainTarget& t, uint32_t width,
                                                 uint32_t height) {
    if (width == 0 || height == 0) return std::optional<SwapchainFrame>{};
    SwapchainFrameSlot& slot = t.slots[t.slot];
    VK_CHECK(vkWaitForFences(ctx.device, 1, &slot.inFlight, VK_TRUE, UINT64_MAX));

    if (t.needsRecreate || t.extent.width != width || t.extent.height != height)
        if (Status s = recreateSwapchain(ctx, t, width, height); !s) return s.error();

    uint32_t imageIndex = 0;
    VkResult acquired = vkAcquireNextImageKHR(ctx.device, t.swapchain, UINT64_MAX, slot.imageAcquired, VK_NULL_HANDLE,
                                              &imageIndex);
    if (acquired == VK_ERROR_OUT_OF_DATE_KHR) {
        if (Status s = recreateSwapchain(ctx, t, width, height); !s) return s.error();
        acquired = vkAcquireNextImageKHR(ctx.device, t.swapchain, UINT64_MAX, slot.imageAcquired, VK_NULL_HANDLE,
                                         &imageIndex);
    }
    if (acquired == VK_SUBOPTIMAL_KHR) t.needsRecreate = true;  // draw this one, recreate next frame
    else VK_CHECK(acquired);

    VK_CHECK(vkResetCommandBuffer(slot.cmd, 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(slot.cmd, &begin));
    // Colour half of the layout contract. The old contents are not needed (presented or never
    // drawn); the wait on the acquire semaphore happens at the colour-output stage, which this
    // barrier's first scope continues.
    VkImageMemoryBarrier2 toAttachment = imageBarrier(t.images[imageIndex], VK_IMAGE_ASPECT_COLOR_BIT,
                                                      VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    toAttachment.srcStageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    toAttachment.dstStageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    toAttachment.dstAccessMask = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT;
    pipelineBarrier(slot.cmd, {toAttachment});

    SwapchainFrame frame;
    frame.cmd = slot.cmd;
    frame.imageIndex = imageIndex;
    frame.image = t.images[imageIndex];
    frame.target = renderTargetOf(t.images[imageIndex], t.views[imageIndex], t.surfaceFormat.format, t.depth,
                                  t.extent.width, t.extent.height);
    return std::optional<SwapchainFrame>{frame};
}

Status endFrame(const VulkanContext& ctx, SwapchainTarget& t, const SwapchainFrame& frame,
                std::vector<uint8_t>* readback) {
    SwapchainFrameSlot& slot = t.slots[t.slot];
    const VkCommandBuffer cmd = frame.cmd;
    Buffer staging;
    if (readback) {
        Result<Buffer> created =
            createBuffer(ctx, VkDeviceSize(t.extent.width) * t.extent.height * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT);
        if (!created) {
            vkEndCommandBuffer(cmd);
            return created.error();
        }
        staging = *created;
        VkImageMemoryBarrier2 toSource = imageBarrier(frame.image, VK_IMAGE_ASPECT_COLOR_BIT,
                                                      VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                                                      VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
        toSource.srcStageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
        toSource.srcAccessMask = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
        toSource.dstStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
        toSource.dstAccessMask = VK_ACCESS_2_TRANSFER_READ_BIT;
        pipelineBarrier(cmd, {toSource});
        recordCopyToBuffer(cmd, frame.image, t.extent, staging);
        const VkBufferMemoryBarrier2 toHost = copyToHostBarrier(staging.buffer);
        VkImageMemoryBarrier2 toPresent = imageBarrier(frame.image, VK_IMAGE_ASPECT_COLOR_BIT,
                                                       VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                                       VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
        toPresent.srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
        pipelineBarrier(cmd, {toPresent}, &toHost);
    } else {
        VkImageMemoryBarrier2 toPresent = imageBarrier(frame.image, VK_IMAGE_ASPECT_COLOR_BIT,
                                                       VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                                                       VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
        toPresent.srcStageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
        toPresent.srcAccessMask = VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT;
        pipelineBarrier(cmd, {toPresent});
    }
    VK_CHECK(vkEndCommandBuffer(cmd));

    VkSemaphoreSubmitInfo wait{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    wait.semaphore = slot.imageAcquired;
    wait.stageMask = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    VkSemaphoreSubmitInfo signal{VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO};
    signal.semaphore = t.renderFinished[frame.imageIndex];
    signal.stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    VkCommandBufferSubmitInfo cmdInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
    cmdInfo.commandBuffer = cmd;
    VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
    submit.waitSemaphoreInfoCount = 1;
    submit.pWaitSemaphoreInfos = &wait;
    submit.commandBufferInfoCount = 1;
    submit.pCommandBufferInfos = &cmdInfo;
    submit.signalSemaphoreInfoCount = 1;
    submit.pSignalSemaphoreInfos = &signal;
    VK_CHECK(vkResetFences(ctx.device, 1, &slot.inFlight));
    const VkResult submitted = vkQueueSubmit2(ctx.queue, 1, &submit, slot.inFlight);
    if (submitted != VK_SUCCESS) {
        if (staging.buffer) destroyBuffer(ctx, staging);
        return vkError("vkQueueSubmit2", submitted);
    }
    slot.submitted = true;

    if (readback) {
        const VkResult waited = vkWaitForFences(ctx.device, 1, &slot.inFlight, VK_TRUE, UINT64_MAX);
        if (waited == VK_SUCCESS) {
            // Swapchain formats are BGRA or RGBA; PNGs want RGBA.
            const size_t pixels = size_t(t.extent.width) * t.extent.height;
            readback->resize(pixels * 4);
            std::memcpy(readback->data(), staging.data, pixels * 4);
            if (t.surfaceFormat.format == VK_FORMAT_B8G8R8A8_UNORM)
                for (size_t i = 0; i < pixels; ++i) std::swap((*readback)[4 * i], (*readback)[4 * i + 2]);
        }
        destroyBuffer(ctx, staging);
        VK_CHECK(waited);
    }

    VkPresentInfoKHR present{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    present.waitSemaphoreCount = 1;
    present.pWaitSemaphores = &t.renderFinished[frame.imageIndex];
    present.swapchainCount = 1;
    present.pSwapchains = &t.swapchain;
    present.pImageIndices = &frame.imageIndex;
    const VkResult presented = vkQueuePresentKHR(ctx.queue, &present);
    t.slot = (t.slot + 1) % kFramesInFlight;
    if (presented == VK_ERROR_OUT_OF_DATE_KHR || presented == VK_SUBOPTIMAL_KHR) {
        t.needsRecreate = true;
        return success();
    }
    VK_CHECK(presented);
    return success();
}

VkFence slotFence(const SwapchainTarget& t, uint32_t slot) {
    return t.slots[slot].submitted ? t.slots[slot].inFlight : VK_NULL_HANDLE;
}

}  // namespace qp
