// One-shot command submission: record, submit to the context's queue, wait for completion.
// Simple and slow (a fence wait per call); for uploads, tests, read-backs and headless renders.
#pragma once

#include <functional>
#include <initializer_list>

#include "vk_context.h"

namespace qp {

// Records `record` into a fresh primary command buffer, submits it and waits until the GPU has
// finished. Fails only on device errors (out of memory, device lost).
Status submitAndWait(const VulkanContext& context, const std::function<void(VkCommandBuffer)>& record);

// An execution and memory dependency between the given stages and accesses.
void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                   VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess);
// A layout transition of an image's first mip level and layer, queue families ignored; the
// caller sets the stages and accesses.
VkImageMemoryBarrier2 imageBarrier(VkImage image, VkImageAspectFlags aspect, VkImageLayout from, VkImageLayout to);
// The barrier after a copy into `buffer` that the host then reads (a read-back).
VkBufferMemoryBarrier2 copyToHostBarrier(VkBuffer buffer);
// vkCmdPipelineBarrier2 with these image barriers and at most one buffer barrier.
void pipelineBarrier(VkCommandBuffer cmd, std::initializer_list<VkImageMemoryBarrier2> images,
                     const VkBufferMemoryBarrier2* buffer = nullptr);

}  // namespace qp
