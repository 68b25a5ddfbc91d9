#include "mesh_pass.h"

#include <cassert>
#include <cmath>

#include "pipeline_builder.h"
#include "shader_code.h"
#include "shared_pipelines.h"
#include "vk_check.h"

namespace qp {

namespace {

// Mirrors shaders/mesh_push.glsl.
struct MeshPush {
    glm::mat4 viewProj;
    glm::vec4 eye;
    glm::vec4 color;
    glm::vec4 params;
};
static_assert(sizeof(MeshPush) == 112 && sizeof(MeshPush) <= 128, "push constants: 128 bytes guaranteed");

// How far (in NDC depth) the wireframe is pulled toward the eye; ~1e-3 of the framed radius
// with frameBounds' near/far planes.
constexpr float kWireDepthPull = 2e-4f;

Result<VkPipeline> createPipeline(const VulkanContext& ctx, VkPipelineCache cache, const MeshPass& pass,
                                  VkShaderModule vert, VkShaderModule frag, bool wireframe, bool colorStream) {
    const ShaderStage stages[] = {{VK_SHADER_STAGE_VERTEX_BIT, vert}, {VK_SHADER_STAGE_FRAGMENT_BIT, frag}};
    const VkVertexInputBindingDescription bindings[2] = {
        {0, sizeof(MeshVertex), VK_VERTEX_INPUT_RATE_VERTEX},
        {1, sizeof(glm::vec3), VK_VERTEX_INPUT_RATE_VERTEX},
    };
    const VkVertexInputAttributeDescription attributes[3] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(MeshVertex, position)},
        {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(MeshVertex, normal)},
        {2, 1, VK_FORMAT_R32G32B32_SFLOAT, 0},
    };
    GraphicsPipelineDesc desc;
    desc.stages = stages;
    desc.layout = pass.layout;
    desc.colorFormat = pass.colorFormat;
    desc.depthFormat = pass.depthFormat;
    desc.vertexBindings = {bindings, colorStream ? 2u : 1u};
    desc.vertexAttributes = {attributes, colorStream ? 3u : 2u};
    desc.polygonMode = wireframe ? VK_POLYGON_MODE_LINE : VK_POLYGON_MODE_FILL;
    desc.depthWrite = !wireframe;
    desc.depthCompare = wireframe ? VK_COMPARE_OP_LESS_OR_EQUAL : VK_COMPARE_OP_LESS;
    return createGraphicsPipeline(ctx, cache, desc);
}

Status initPass(const VulkanContext& ctx, VkPipelineCache cache, MeshPass& pass) {
    VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(MeshPush)};
    VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layoutInfo.pushConstantRangeCount = 1;
    layoutInfo.pPushConstantRanges = &range;
    VK_CHECK(vkCreatePipelineLayout(ctx.device, &layoutInfo, nullptr, &pass.layout));

    // Modules are only needed while the pipelines are created.
    VkShaderModule vert = loadShaderModule(ctx, "mesh.vert");
    VkShaderModule coloredVert = loadShaderModule(ctx, "mesh_colored.vert");
    VkShaderModule frag = loadShaderModule(ctx, "mesh.frag");
    Result<VkPipeline> solid = createPipeline(ctx, cache, pass, vert, frag, false, false);
    Result<VkPipeline> colored = solid ? createPipeline(ctx, cache, pass, coloredVert, frag, false, true) : solid;
    Result<VkPipeline> wire = VK_NULL_HANDLE;
    if (colored && ctx.features.fillModeNonSolid) wire = createPipeline(ctx, cache, pass, vert, frag, true, false);
    vkDestroyShaderModule(ctx.device, vert, nullptr);
    vkDestroyShaderModule(ctx.device, coloredVert, nullptr);
    vkDestroyShaderModule(ctx.device, frag, nullptr);
    if (solid) pass.solid = *solid;
    if (colored && solid) pass.solidColored = *colored;
    if (!colored) return colored.error();
    if (!wire) return wire.error();
    pass.wireframe = *wire;
    return success();
}

void destroyPipelines(const VulkanContext& ctx, MeshPass& pass) {
    if (pass.solid) vkDestroyPipeline(ctx.device, pass.solid, nullptr);
    if (pass.solidColored) vkDestroyPipeline(ctx.device, pass.solidColored, nullptr);
    if (pass.wireframe) vkDestroyPipeline(ctx.device, pass.wireframe, nullptr);
    if (pass.layout) vkDestroyPipelineLayout(ctx.device, pass.layout, nullptr);
}

}  // namespace

Result<GpuMesh> uploadMesh(const VulkanContext& ctx, std::span<const MeshVertex> vertices,
                           std::span<const uint32_t> indices, std::span<const glm::vec3> colors) {
    assert(!vertices.empty() && !indices.empty() && indices.size() % 3 == 0);
    assert(colors.empty() || colors.size() == vertices.size());
    GpuMesh mesh;
    Result<Buffer> vb = createBuffer(ctx, vertices.size_bytes(),
                                     VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    if (!vb) return vb.error();
    mesh.vertices = *vb;
    Result<Buffer> ib = createBuffer(ctx, indices.size_bytes(), VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
    if (!ib) {
        destroyMesh(ctx, mesh);
        return ib.error();
    }
    mesh.indices = *ib;
    if (!colors.empty()) {
        Result<Buffer> cb = createBuffer(ctx, colors.size_bytes(), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
        if (!cb) {
            destroyMesh(ctx, mesh);
            return cb.error();
        }
        mesh.colors = *cb;
        uploadBuffer(mesh.colors, colors.data(), colors.size_bytes());
    }
    uploadBuffer(mesh.vertices, vertices.data(), vertices.size_bytes());
    uploadBuffer(mesh.indices, indices.data(), indices.size_bytes());
    mesh.indexCount = uint32_t(indices.size());
    return mesh;
}

void destroyMesh(const VulkanContext& ctx, GpuMesh& mesh) {
    destroyBuffer(ctx, mesh.vertices);
    destroyBuffer(ctx, mesh.indices);
    if (mesh.colors.buffer) destroyBuffer(ctx, mesh.colors);
    mesh.indexCount = 0;
}

Result<MeshPass> createMeshPass(const VulkanContext& ctx, VkPipelineCache cache, VkFormat colorFormat,
                                VkFormat depthFormat) {
    return sharedPass<MeshPass>(
        ctx, sharedPassKey("mesh", colorFormat, depthFormat), colorFormat, depthFormat,
        [&](MeshPass& pass) { return initPass(ctx, cache, pass); }, destroyPipelines);
}

void destroyMeshPass(const VulkanContext&, MeshPass& pass) {
    pass = MeshPass{};  // the pipelines are the device's (shared_pipelines.h)
}

void recordMeshPass(VkCommandBuffer cmd, const MeshPass& pass, const RenderTarget& target, const MeshView& view,
                    std::span<const MeshDraw> draws) {
    assert(pass.colorFormat == target.colorFormat && pass.depthFormat == target.depthFormat);
    beginRendering(cmd, target, view.clear, view.background);

    auto draw = [&](const MeshDraw& d, bool wire) {
        const bool colorStream = !wire && d.mesh->colors.buffer != VK_NULL_HANDLE;
        MeshPush push;
        push.viewProj = view.viewProjection;
        push.eye = glm::vec4(view.eye, 1.0f);
        push.color = glm::vec4(wire ? d.wireColor : d.color, 1.0f);
        const float lighting = (wire || !d.lit) ? 1.0f : colorStream ? 2.0f : 0.0f;
        push.params = glm::vec4(wire ? kWireDepthPull : 0.0f, lighting, view.shading == Shading::Matcap ? 1.0f : 0.0f, 0.0f);
        vkCmdPushConstants(cmd, pass.layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                           sizeof push, &push);
        const VkBuffer buffers[2] = {d.mesh->vertices.buffer, d.mesh->colors.buffer};
        const VkDeviceSize offsets[2] = {0, 0};
        vkCmdBindVertexBuffers(cmd, 0, colorStream ? 2 : 1, buffers, offsets);
        vkCmdBindIndexBuffer(cmd, d.mesh->indices.buffer, 0, VK_INDEX_TYPE_UINT32);
        if (d.ranges.empty()) vkCmdDrawIndexed(cmd, d.mesh->indexCount, 1, 0, 0, 0);
        for (const IndexRange& range : d.ranges) vkCmdDrawIndexed(cmd, range.count, 1, range.first, 0, 0);
    };
    // Plain meshes first, then meshes with a colour stream (one pipeline switch at most).
    for (bool colored : {false, true}) {
        bool bound = false;
        for (const MeshDraw& d : draws) {
            if ((d.mesh->colors.buffer != VK_NULL_HANDLE) != colored) continue;
            if (!bound) vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, colored ? pass.solidColored : pass.solid);
            bound = true;
            draw(d, false);
        }
    }
    // Overlays after every solid draw, so that lines are hidden by any nearer surface.
    if (pass.wireframe) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pass.wireframe);
        for (const MeshDraw& d : draws)
            if (d.wireframe) draw(d, true);
    }
    vkCmdEndRendering(cmd);
}

}  // namespace qp
