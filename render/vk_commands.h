// One-shot command submission: record, submit to the context's queue, wait for completion.
// Simple and slow (a fence wait per call); for uploads, tests, read-backs and headless renders.
#pragma once

#include <functional>

#include "vk_context.h"

namespace qp {

// Records `record` into a fresh primary command buffer, submits it and waits until the GPU has
// finished. Fails only on device errors (out of memory, device lost).
Status submitAndWait(const VulkanContext& context, const std::function<void(VkCommandBuffer)>& record);

}  // namespace qp
