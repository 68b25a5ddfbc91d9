// Pipeline builder: the fixed-function state every pass shares, written once.
//
// Every graphics pipeline here draws with dynamic rendering into one colour attachment and a
// depth attachment (a RenderTarget), with viewport and scissor set by beginRendering, one
// sample, no blending, both sides of every triangle (subdivision surfaces may be open) and a
// depth test. A pass fills a GraphicsPipelineDesc with what differs and calls
// createGraphicsPipeline.
//
// Shader modules stay the caller's: it may use one module in several pipelines and destroys it
// once they are made (success or not). Failure is the driver's (out of memory): the result is an
// Error from VK_CHECK (vk_check.h) and nothing is left to destroy.
#pragma once

#include <cstdint>
#include <span>

#include <vulkan/vulkan.h>

#include "mesh/result.h"
#include "vk_context.h"

namespace qp {

struct ShaderStage {
    VkShaderStageFlagBits stage;
    VkShaderModule module;  // entry point "main"
};

struct GraphicsPipelineDesc {
    std::span<const ShaderStage> stages;  // in pipeline order
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkFormat colorFormat = VK_FORMAT_UNDEFINED;
    VkFormat depthFormat = VK_FORMAT_UNDEFINED;
    // The fragment stage gets ColorEncoding(colorFormat) (render_target.h); false for shaders
    // without shaders/color_encoding.glsl, whose output is no colour.
    bool encodeColor = true;

    std::span<const VkVertexInputBindingDescription> vertexBindings;  // empty: the shaders read buffers
    std::span<const VkVertexInputAttributeDescription> vertexAttributes;
    VkPrimitiveTopology topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    uint32_t patchControlPoints = 0;  // non-zero: a patch list through the tessellator (topology unused)

    VkPolygonMode polygonMode = VK_POLYGON_MODE_FILL;
    bool depthWrite = true;
    VkCompareOp depthCompare = VK_COMPARE_OP_LESS_OR_EQUAL;
    // Overlays pull themselves towards the eye (factors are negative).
    bool depthBias = false;
    float depthBiasConstant = 0.0f, depthBiasSlope = 0.0f;
    bool dynamicLineWidth = false;  // else 1
};

Result<VkPipeline> createGraphicsPipeline(const VulkanContext& context, VkPipelineCache cache,
                                          const GraphicsPipelineDesc& desc);

// A compute pipeline of `module`'s "main"; the module stays the caller's.
Result<VkPipeline> createComputePipeline(const VulkanContext& context, VkPipelineCache cache, VkShaderModule module,
                                         VkPipelineLayout layout);

// A pool holding exactly one set of `setLayout` with `size`'s descriptors, and that set: what a
// pass that binds its own buffers needs. Destroying the pool frees the set.
Status createDescriptorSet(const VulkanContext& context, VkDescriptorSetLayout setLayout, VkDescriptorPoolSize size,
                           VkDescriptorPool& pool, VkDescriptorSet& set);

}  // namespace qp
