#include "line_pass.h"

#include <algorithm>

#include "mesh/topology.h"
#include "pipeline_builder.h"
#include "shader_code.h"
#include "vk_check.h"

namespace qp {

namespace {

Status initPass(const VulkanContext& ctx, VkPipelineCache cache, LinePass& pass) {
    VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(glm::mat4)};
    VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layoutInfo.pushConstantRangeCount = 1;
    layoutInfo.pPushConstantRanges = &range;
    VK_CHECK(vkCreatePipelineLayout(ctx.device, &layoutInfo, nullptr, &pass.layout));

    VkShaderModule vert = loadShaderModule(ctx, "line.vert"), frag = loadShaderModule(ctx, "line.frag");
    const ShaderStage stages[] = {{VK_SHADER_STAGE_VERTEX_BIT, vert}, {VK_SHADER_STAGE_FRAGMENT_BIT, frag}};
    const VkVertexInputBindingDescription binding{0, sizeof(LineVertex), VK_VERTEX_INPUT_RATE_VERTEX};
    const VkVertexInputAttributeDescription attributes[2] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(LineVertex, position)},
        {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(LineVertex, color)}};
    GraphicsPipelineDesc desc;
    desc.stages = stages;
    desc.layout = pass.layout;
    desc.colorFormat = pass.colorFormat;
    desc.depthFormat = pass.depthFormat;
    desc.vertexBindings = {&binding, 1};
    desc.vertexAttributes = attributes;
    desc.topology = VK_PRIMITIVE_TOPOLOGY_LINE_LIST;
    desc.depthWrite = false;
    // The cage floats around the surface; a small pull keeps edges lying on it visible.
    desc.depthBias = true;
    desc.depthBiasConstant = desc.depthBiasSlope = -2.0f;
    desc.dynamicLineWidth = true;  // recordLines sets it
    Result<VkPipeline> pipeline = createGraphicsPipeline(ctx, cache, desc);
    vkDestroyShaderModule(ctx.device, vert, nullptr);
    vkDestroyShaderModule(ctx.device, frag, nullptr);
    if (!pipeline) return pipeline.error();
    pass.pipeline = *pipeline;
    return success();
}

glm::vec3 sharpnessColor(float sharpness) {
    float t = std::min(sharpness / kInfiniteSharpness, 1.0f);
    return glm::mix(glm::vec3(1.0f, 0.85f, 0.1f), glm::vec3(0.9f, 0.05f, 0.02f), t);
}

}  // namespace

glm::vec3 cageEdgeColor(float sharpness, bool boundary) {
    return sharpness > 0.0f ? sharpnessColor(sharpness) : boundary ? glm::vec3(0.05f, 0.25f, 0.8f) : glm::vec3(0.06f);
}

std::vector<LineVertex> cageLines(const Cage& cage) {
    const Topology topology = buildTopology(cage);
    const std::vector<float> sharpness = edgeSharpnesses(cage, topology);
    std::vector<LineVertex> plain, creased;
    for (uint32_t e = 0; e < topology.edgeCount(); ++e) {
        const glm::vec3 color = cageEdgeColor(sharpness[e], topology.edgeFaceCount(e) == 1);
        std::vector<LineVertex>& lines = sharpness[e] > 0.0f ? creased : plain;
        lines.push_back({cage.positions[topology.edgeVertices[2 * e]], color});
        lines.push_back({cage.positions[topology.edgeVertices[2 * e + 1]], color});
    }
    plain.insert(plain.end(), creased.begin(), creased.end());
    return plain;
}

Result<LinePass> createLinePass(const VulkanContext& ctx, VkPipelineCache cache, VkFormat colorFormat,
                                VkFormat depthFormat) {
    LinePass pass;
    pass.colorFormat = colorFormat;
    pass.depthFormat = depthFormat;
    pass.maxLineWidth = ctx.features.wideLines ? ctx.properties.limits.lineWidthRange[1] : 1.0f;
    if (Status s = initPass(ctx, cache, pass); !s) {
        destroyLinePass(ctx, pass);
        return s.error();
    }
    return pass;
}

void destroyLinePass(const VulkanContext& ctx, LinePass& pass) {
    if (pass.pipeline) vkDestroyPipeline(ctx.device, pass.pipeline, nullptr);
    if (pass.layout) vkDestroyPipelineLayout(ctx.device, pass.layout, nullptr);
    pass = LinePass{};
}

void recordLines(VkCommandBuffer cmd, const LinePass& pass, const RenderTarget& target, const glm::mat4& viewProjection,
                 const Buffer& lines, uint32_t vertexCount, float width) {
    beginRendering(cmd, target, false, glm::vec3(0.0f));
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pass.pipeline);
    vkCmdSetLineWidth(cmd, std::clamp(width, 1.0f, pass.maxLineWidth));
    vkCmdPushConstants(cmd, pass.layout, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(glm::mat4), &viewProjection);
    VkDeviceSize offset = 0;
    vkCmdBindVertexBuffers(cmd, 0, 1, &lines.buffer, &offset);
    vkCmdDraw(cmd, vertexCount, 1, 0, 0);
    vkCmdEndRendering(cmd);
}

}  // namespace qp
