#include "line_pass.h"

#include <algorithm>

#include "mesh/topology.h"
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
    const ColorEncoding encoding(pass.colorFormat);
    VkPipelineShaderStageCreateInfo stages[2] = {
        {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_VERTEX_BIT, vert, "main"},
        {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_FRAGMENT_BIT, frag, "main",
         &encoding.info}};
    const VkVertexInputBindingDescription binding{0, sizeof(LineVertex), VK_VERTEX_INPUT_RATE_VERTEX};
    const VkVertexInputAttributeDescription attributes[2] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(LineVertex, position)},
        {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(LineVertex, color)}};
    VkPipelineVertexInputStateCreateInfo vertexInput{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    vertexInput.vertexBindingDescriptionCount = 1;
    vertexInput.pVertexBindingDescriptions = &binding;
    vertexInput.vertexAttributeDescriptionCount = 2;
    vertexInput.pVertexAttributeDescriptions = attributes;
    VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    assembly.topology = VK_PRIMITIVE_TOPOLOGY_LINE_LIST;
    VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_NONE;
    raster.lineWidth = 1.0f;  // dynamic: recordLines sets it
    // The cage floats around the surface; a small pull keeps edges lying on it visible.
    raster.depthBiasEnable = VK_TRUE;
    raster.depthBiasConstantFactor = -2.0f;
    raster.depthBiasSlopeFactor = -2.0f;
    VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    depth.depthTestEnable = VK_TRUE;
    depth.depthWriteEnable = VK_FALSE;
    depth.depthCompareOp = VK_COMPARE_OP_LESS_OR_EQUAL;
    VkPipelineColorBlendAttachmentState blendAttachment{};
    blendAttachment.colorWriteMask =
        VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
    VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    blend.attachmentCount = 1;
    blend.pAttachments = &blendAttachment;
    const VkDynamicState dynamicStates[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR, VK_DYNAMIC_STATE_LINE_WIDTH};
    VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dynamic.dynamicStateCount = 3;
    dynamic.pDynamicStates = dynamicStates;
    VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachmentFormats = &pass.colorFormat;
    rendering.depthAttachmentFormat = pass.depthFormat;
    VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO, &rendering};
    info.stageCount = 2;
    info.pStages = stages;
    info.pVertexInputState = &vertexInput;
    info.pInputAssemblyState = &assembly;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &depth;
    info.pColorBlendState = &blend;
    info.pDynamicState = &dynamic;
    info.layout = pass.layout;
    VkResult result = vkCreateGraphicsPipelines(ctx.device, cache, 1, &info, nullptr, &pass.pipeline);
    vkDestroyShaderModule(ctx.device, vert, nullptr);
    vkDestroyShaderModule(ctx.device, frag, nullptr);
    VK_CHECK(result);
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
