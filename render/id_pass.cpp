#include "id_pass.h"

#include <cassert>
#include <cstddef>

#include "shader_code.h"
#include "shared_pipelines.h"
#include "vk_check.h"

namespace qp {

namespace {

Result<VkPipeline> createPipeline(const VulkanContext& ctx, VkPipelineCache cache, const IdPass& pass, VkShaderModule vert,
                                  VkShaderModule frag) {
    const VkPipelineShaderStageCreateInfo stages[2] = {
        {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_VERTEX_BIT, vert, "main"},
        {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_FRAGMENT_BIT, frag, "main"},
    };
    const VkVertexInputBindingDescription binding{0, sizeof(IdVertex), VK_VERTEX_INPUT_RATE_VERTEX};
    const VkVertexInputAttributeDescription attributes[2] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(IdVertex, position)},
        {1, 0, VK_FORMAT_R32_UINT, offsetof(IdVertex, id)},
    };
    VkPipelineVertexInputStateCreateInfo vertexInput{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    vertexInput.vertexBindingDescriptionCount = 1;
    vertexInput.pVertexBindingDescriptions = &binding;
    vertexInput.vertexAttributeDescriptionCount = 2;
    vertexInput.pVertexAttributeDescriptions = attributes;

    VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;

    VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;

    VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_NONE;  // the schemes draw back sides too
    raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    raster.lineWidth = 1.0f;

    VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;

    VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    depth.depthTestEnable = VK_TRUE;
    depth.depthWriteEnable = VK_TRUE;
    depth.depthCompareOp = VK_COMPARE_OP_LESS;

    VkPipelineColorBlendAttachmentState blendAttachment{};
    blendAttachment.colorWriteMask =
        VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
    VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    blend.attachmentCount = 1;
    blend.pAttachments = &blendAttachment;

    const VkDynamicState dynamicStates[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dynamic.dynamicStateCount = 2;
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

    VkPipeline pipeline = VK_NULL_HANDLE;
    VK_CHECK(vkCreateGraphicsPipelines(ctx.device, cache, 1, &info, nullptr, &pipeline));
    return pipeline;
}

void destroyPipelines(const VulkanContext& ctx, IdPass& pass) {
    if (pass.pipeline) vkDestroyPipeline(ctx.device, pass.pipeline, nullptr);
    if (pass.layout) vkDestroyPipelineLayout(ctx.device, pass.layout, nullptr);
}

Status initPass(const VulkanContext& ctx, VkPipelineCache cache, IdPass& pass) {
    const VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(glm::mat4)};
    VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layoutInfo.pushConstantRangeCount = 1;
    layoutInfo.pPushConstantRanges = &range;
    VK_CHECK(vkCreatePipelineLayout(ctx.device, &layoutInfo, nullptr, &pass.layout));
    // Modules are only needed while the pipeline is created.
    VkShaderModule vert = loadShaderModule(ctx, "id.vert");
    VkShaderModule frag = loadShaderModule(ctx, "id.frag");
    Result<VkPipeline> pipeline = createPipeline(ctx, cache, pass, vert, frag);
    vkDestroyShaderModule(ctx.device, vert, nullptr);
    vkDestroyShaderModule(ctx.device, frag, nullptr);
    if (!pipeline) return pipeline.error();
    pass.pipeline = *pipeline;
    return success();
}

}  // namespace

Result<IdMesh> uploadIdMesh(const VulkanContext& ctx, std::span<const IdVertex> vertices, std::span<const uint32_t> indices) {
    assert(!vertices.empty() && !indices.empty() && indices.size() % 3 == 0);
    IdMesh mesh;
    Result<Buffer> vb = createBuffer(ctx, vertices.size_bytes(), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    if (!vb) return vb.error();
    mesh.vertices = *vb;
    Result<Buffer> ib = createBuffer(ctx, indices.size_bytes(), VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
    if (!ib) {
        destroyBuffer(ctx, mesh.vertices);
        return ib.error();
    }
    mesh.indices = *ib;
    uploadBuffer(mesh.vertices, vertices.data(), vertices.size_bytes());
    uploadBuffer(mesh.indices, indices.data(), indices.size_bytes());
    mesh.indexCount = uint32_t(indices.size());
    return mesh;
}

void destroyIdMesh(const VulkanContext& ctx, IdMesh& mesh) {
    destroyBuffer(ctx, mesh.vertices);
    destroyBuffer(ctx, mesh.indices);
    mesh.indexCount = 0;
}

Result<IdPass> createIdPass(const VulkanContext& ctx, VkPipelineCache cache, VkFormat colorFormat, VkFormat depthFormat) {
    if (isSrgbFormat(colorFormat)) return Error{"an ID buffer needs a UNORM colour format: sRGB would re-encode its numbers"};
    return sharedDeviceObject<IdPass>(
        ctx, sharedPassKey("id", colorFormat, depthFormat),
        [&]() -> Result<IdPass> {
            IdPass pass;
            pass.colorFormat = colorFormat;
            pass.depthFormat = depthFormat;
            if (Status s = initPass(ctx, cache, pass); !s) {
                destroyPipelines(ctx, pass);
                return s.error();
            }
            return pass;
        },
        destroyPipelines);
}

void destroyIdPass(const VulkanContext&, IdPass& pass) {
    pass = IdPass{};  // the pipeline is the device's (shared_pipelines.h)
}

void recordIdPass(VkCommandBuffer cmd, const IdPass& pass, const RenderTarget& target, const glm::mat4& viewProjection,
                  bool clear, const IdMesh& mesh) {
    assert(pass.colorFormat == target.colorFormat && pass.depthFormat == target.depthFormat);
    beginRendering(cmd, target, clear, glm::vec3(0.0f));  // black: code 0, no number
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pass.pipeline);
    vkCmdPushConstants(cmd, pass.layout, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof viewProjection, &viewProjection);
    const VkDeviceSize offset = 0;
    vkCmdBindVertexBuffers(cmd, 0, 1, &mesh.vertices.buffer, &offset);
    vkCmdBindIndexBuffer(cmd, mesh.indices.buffer, 0, VK_INDEX_TYPE_UINT32);
    vkCmdDrawIndexed(cmd, mesh.indexCount, 1, 0, 0, 0);
    vkCmdEndRendering(cmd);
}

}  // namespace qp
