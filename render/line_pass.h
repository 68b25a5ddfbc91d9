// LinePass: coloured line segments drawn over what a target already holds (the cage overlay),
// depth-tested against it so the surface hides the cage where it is in front.
#pragma once

#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "mesh/cage.h"
#include "render_target.h"
#include "vk_buffer.h"
#include "vk_context.h"

namespace qp {

struct LineVertex {
    glm::vec3 position;
    glm::vec3 color;  // linear
};

// The cage's edges, two vertices each: plain edges dark grey, creased edges on a ramp from
// yellow (soft) to red (infinitely sharp), boundary edges blue; creased edges last.
std::vector<LineVertex> cageLines(const Cage& cage);

// The colour cageLines gives an edge of that sharpness (0: none), on the boundary or not.
glm::vec3 cageEdgeColor(float sharpness, bool boundary);

struct LinePass {
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline pipeline = VK_NULL_HANDLE;
    VkFormat colorFormat = VK_FORMAT_UNDEFINED, depthFormat = VK_FORMAT_UNDEFINED;
    float maxLineWidth = 1.0f;  // 1 without the wideLines feature, else the device's limit
};

Result<LinePass> createLinePass(const VulkanContext& context, VkPipelineCache cache, VkFormat colorFormat,
                                VkFormat depthFormat = VK_FORMAT_D32_SFLOAT);
void destroyLinePass(const VulkanContext& context, LinePass& pass);

// Draws `lines` (a vertex buffer of LineVertex pairs) into `target`, keeping its colour and
// depth (written by a previous pass in the same command buffer, e.g. recordTessellated), with
// lines `width` pixels wide (clamped to what the device draws: lavapipe has wide lines up to 255).
void recordLines(VkCommandBuffer cmd, const LinePass& pass, const RenderTarget& target, const glm::mat4& viewProjection,
                 const Buffer& lines, uint32_t vertexCount, float width = 2.0f);

}  // namespace qp
