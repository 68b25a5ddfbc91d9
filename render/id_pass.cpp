#include "id_pass.h"

#include <cassert>
#include <cstddef>

#include "pipeline_builder.h"
#include "shader_code.h"
#include "shared_pipelines.h"
#include "vk_check.h"

namespace qp {

namespace {

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
    const ShaderStage stages[] = {{VK_SHADER_STAGE_VERTEX_BIT, vert}, {VK_SHADER_STAGE_FRAGMENT_BIT, frag}};
    const VkVertexInputBindingDescription binding{0, sizeof(IdVertex), VK_VERTEX_INPUT_RATE_VERTEX};
    const VkVertexInputAttributeDescription attributes[2] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(IdVertex, position)},
        {1, 0, VK_FORMAT_R32_UINT, offsetof(IdVertex, id)},
    };
    GraphicsPipelineDesc desc;
    desc.stages = stages;
    desc.layout = pass.layout;
    desc.colorFormat = pass.colorFormat;
    desc.depthFormat = pass.depthFormat;
    desc.encodeColor = false;  // the pixels are numbers
    desc.vertexBindings = {&binding, 1};
    desc.vertexAttributes = attributes;
    desc.depthCompare = VK_COMPARE_OP_LESS;
    Result<VkPipeline> pipeline = createGraphicsPipeline(ctx, cache, desc);
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
    return sharedPass<IdPass>(
        ctx, sharedPassKey("id", colorFormat, depthFormat), colorFormat, depthFormat,
        [&](IdPass& pass) { return initPass(ctx, cache, pass); }, destroyPipelines);
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
