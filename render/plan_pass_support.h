// What the plans renderer's two files share (plan_pass.cpp: buffers, the pass and the
// tessellated path; plan_grid_path.cpp: the grid paths): buffers filled from arrays, compute
// dispatches over sub-faces and the stencil pass that makes control points. Not part of the
// renderer's API.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "plan_pass.h"
#include "plan_pipelines.h"
#include "vk_buffer.h"

namespace qp {

// A compute push's subface range "every drawn sub-face".
inline constexpr uint32_t kWholeCage = UINT32_MAX;

// A storage buffer holding `values` (a 16-byte placeholder when empty: Vulkan buffers cannot be).
template <class T>
Result<Buffer> createFilled(const VulkanContext& ctx, const std::vector<T>& values, VkBufferUsageFlags extra = 0) {
    VkDeviceSize size = std::max<VkDeviceSize>(values.size() * sizeof(T), 16);
    Result<Buffer> buffer = createBuffer(ctx, size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | extra);
    if (buffer && !values.empty()) uploadBuffer(*buffer, values.data(), values.size() * sizeof(T));
    return buffer;
}

// One workgroup per sub-face of push.subfaceCount, in rows of at most 65,535 groups.
void dispatchPerSubface(VkCommandBuffer cmd, const PlanPass& pass, VkPipeline pipeline, PlanComputePush push);
// Compute results (control points, grid vertices) before any later shader or vertex fetch.
void computeWritesBeforeReads(VkCommandBuffer cmd);
// Control points for factors up to 2^level, visible to every later shader stage; nothing when
// they are cached for that level or a higher one.
void recordStencils(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers, uint32_t level);

}  // namespace qp
