#include "plan_pass.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>

#include "shader_code.h"
#include "vk_check.h"

namespace qp {

namespace {

// Mirrors DrawPush in shaders/plan_draw.glsl.
struct DrawPush {
    glm::mat4 viewProjection;
    float uniformFactor;
    float pixelsPerSegment;
    float pixelsPerUnit;
    uint32_t colorMode;
    uint32_t capture;
    uint32_t gridStride;
};
static_assert(sizeof(DrawPush) <= 128, "push constants: 128 bytes guaranteed");

// Mirrors the push blocks of plan_stencils.comp and plan_grid.comp.
struct ComputePush {
    uint32_t subfaceCount;
    uint32_t levelOrFactor;
    uint32_t groupsPerRow;
    uint32_t vertexStride;
};

constexpr uint32_t kBindingCount = 15;
constexpr uint32_t kMaxGroupsPerRow = 65535;
constexpr uint32_t kCaptureHeaderBytes = 16;
constexpr VkShaderStageFlags kAllStages = VK_SHADER_STAGE_COMPUTE_BIT | VK_SHADER_STAGE_VERTEX_BIT |
                                          VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT |
                                          VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
constexpr VkShaderStageFlags kDrawStages = kAllStages & ~VK_SHADER_STAGE_COMPUTE_BIT;

VkShaderModule loadShader(const VulkanContext& ctx, const char* name) {
    std::span<const uint32_t> code = shaderCode(name);
    assert(!code.empty() && "shader not embedded: is it in render/shaders/?");
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = code.size_bytes();
    info.pCode = code.data();
    VkShaderModule module = VK_NULL_HANDLE;
    VK_ASSERT(vkCreateShaderModule(ctx.device, &info, nullptr, &module));
    return module;
}

Result<VkPipeline> createComputePipeline(const VulkanContext& ctx, VkPipelineCache cache, VkPipelineLayout layout,
                                         const char* shader) {
    VkShaderModule module = loadShader(ctx, shader);
    VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_COMPUTE_BIT, module, "main"};
    info.layout = layout;
    VkPipeline pipeline = VK_NULL_HANDLE;
    VkResult result = vkCreateComputePipelines(ctx.device, cache, 1, &info, nullptr, &pipeline);
    vkDestroyShaderModule(ctx.device, module, nullptr);
    VK_CHECK(result);
    return pipeline;
}

struct GraphicsStages {
    const char* vertex;
    const char* control;     // null: no tessellation
    const char* evaluation;
    const char* fragment;
};

Result<VkPipeline> createDrawPipeline(const VulkanContext& ctx, VkPipelineCache cache, const PlanPass& pass,
                                      const GraphicsStages& names, bool wireframe) {
    const bool tessellated = names.control != nullptr;
    std::vector<VkShaderModule> modules;
    std::vector<VkPipelineShaderStageCreateInfo> stages;
    const ColorEncoding encoding(pass.colorFormat);
    auto addStage = [&](const char* name, VkShaderStageFlagBits stage) {
        modules.push_back(loadShader(ctx, name));
        stages.push_back({VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, stage, modules.back(), "main",
                          stage == VK_SHADER_STAGE_FRAGMENT_BIT ? &encoding.info : nullptr});
    };
    addStage(names.vertex, VK_SHADER_STAGE_VERTEX_BIT);
    if (tessellated) {
        addStage(names.control, VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT);
        addStage(names.evaluation, VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT);
    }
    addStage(names.fragment, VK_SHADER_STAGE_FRAGMENT_BIT);

    VkPipelineVertexInputStateCreateInfo vertexInput{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    assembly.topology = tessellated ? VK_PRIMITIVE_TOPOLOGY_PATCH_LIST : VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkPipelineTessellationStateCreateInfo tessellation{VK_STRUCTURE_TYPE_PIPELINE_TESSELLATION_STATE_CREATE_INFO};
    tessellation.patchControlPoints = 1;
    VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = wireframe ? VK_POLYGON_MODE_LINE : VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_NONE;  // open cages show their back side
    raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    raster.lineWidth = 1.0f;
    // The wireframe is drawn over the shaded surface: pull it towards the eye a little.
    raster.depthBiasEnable = wireframe ? VK_TRUE : VK_FALSE;
    raster.depthBiasConstantFactor = -1.0f;
    raster.depthBiasSlopeFactor = -1.0f;
    VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    depth.depthTestEnable = VK_TRUE;
    depth.depthWriteEnable = wireframe ? VK_FALSE : VK_TRUE;
    depth.depthCompareOp = VK_COMPARE_OP_LESS_OR_EQUAL;
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
    info.stageCount = uint32_t(stages.size());
    info.pStages = stages.data();
    info.pVertexInputState = &vertexInput;
    info.pInputAssemblyState = &assembly;
    info.pTessellationState = tessellated ? &tessellation : nullptr;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &depth;
    info.pColorBlendState = &blend;
    info.pDynamicState = &dynamic;
    info.layout = pass.drawLayout;
    VkPipeline pipeline = VK_NULL_HANDLE;
    VkResult result = vkCreateGraphicsPipelines(ctx.device, cache, 1, &info, nullptr, &pipeline);
    for (VkShaderModule m : modules) vkDestroyShaderModule(ctx.device, m, nullptr);
    VK_CHECK(result);
    return pipeline;
}

Status initPass(const VulkanContext& ctx, VkPipelineCache cache, PlanPass& pass) {
    VkDescriptorSetLayoutBinding bindings[kBindingCount];
    for (uint32_t b = 0; b < kBindingCount; ++b)
        bindings[b] = {b, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, kAllStages, nullptr};
    VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    setInfo.bindingCount = kBindingCount;
    setInfo.pBindings = bindings;
    VK_CHECK(vkCreateDescriptorSetLayout(ctx.device, &setInfo, nullptr, &pass.setLayout));

    VkPushConstantRange computeRange{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(ComputePush)};
    VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layoutInfo.setLayoutCount = 1;
    layoutInfo.pSetLayouts = &pass.setLayout;
    layoutInfo.pushConstantRangeCount = 1;
    layoutInfo.pPushConstantRanges = &computeRange;
    VK_CHECK(vkCreatePipelineLayout(ctx.device, &layoutInfo, nullptr, &pass.computeLayout));
    VkPushConstantRange drawRange{kDrawStages, 0, sizeof(DrawPush)};
    layoutInfo.pPushConstantRanges = &drawRange;
    VK_CHECK(vkCreatePipelineLayout(ctx.device, &layoutInfo, nullptr, &pass.drawLayout));

    VkDescriptorPoolSize poolSize{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kBindingCount};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = 1;
    poolInfo.poolSizeCount = 1;
    poolInfo.pPoolSizes = &poolSize;
    VK_CHECK(vkCreateDescriptorPool(ctx.device, &poolInfo, nullptr, &pass.pool));
    VkDescriptorSetAllocateInfo allocInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    allocInfo.descriptorPool = pass.pool;
    allocInfo.descriptorSetCount = 1;
    allocInfo.pSetLayouts = &pass.setLayout;
    VK_CHECK(vkAllocateDescriptorSets(ctx.device, &allocInfo, &pass.set));

    auto assign = [](Result<VkPipeline> r, VkPipeline& out) -> Status {
        if (!r) return r.error();
        out = *r;
        return success();
    };
    if (Status s = assign(createComputePipeline(ctx, cache, pass.computeLayout, "plan_stencils.comp"), pass.stencils); !s) return s;
    if (Status s = assign(createComputePipeline(ctx, cache, pass.computeLayout, "plan_grid.comp"), pass.grid); !s) return s;
    const GraphicsStages tess{"plan.vert", "plan.tesc", "plan.tese", "plan.frag"};
    const GraphicsStages grid{"plan_grid.vert", nullptr, nullptr, "plan.frag"};
    if (!ctx.features.tessellationShader)
        return Error{"the Vulkan device '" + ctx.deviceName + "' has no tessellation shaders"};
    if (Status s = assign(createDrawPipeline(ctx, cache, pass, tess, false), pass.tessellated); !s) return s;
    if (Status s = assign(createDrawPipeline(ctx, cache, pass, grid, false), pass.gridTriangles); !s) return s;
    if (ctx.features.fillModeNonSolid) {
        if (Status s = assign(createDrawPipeline(ctx, cache, pass, tess, true), pass.tessellatedWire); !s) return s;
        if (Status s = assign(createDrawPipeline(ctx, cache, pass, grid, true), pass.gridWire); !s) return s;
    }
    return success();
}

template <class T>
Result<Buffer> createFilled(const VulkanContext& ctx, const std::vector<T>& values, VkBufferUsageFlags extra = 0) {
    // Vulkan buffers cannot be empty; a 16-byte placeholder keeps the descriptor valid.
    VkDeviceSize size = std::max<VkDeviceSize>(values.size() * sizeof(T), 16);
    Result<Buffer> buffer = createBuffer(ctx, size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | extra);
    if (buffer && !values.empty()) uploadBuffer(*buffer, values.data(), values.size() * sizeof(T));
    return buffer;
}

std::vector<float> cagePositions(const PlannedCage& planned) {
    std::vector<float> out;
    out.reserve(planned.cage().vertexCount() * 3);
    for (const glm::vec3& p : planned.cage().positions) out.insert(out.end(), {p.x, p.y, p.z});
    return out;
}

void barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dstStage,
             VkAccessFlags2 dstAccess) {
    VkMemoryBarrier2 memory{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
    memory.srcStageMask = srcStage;
    memory.srcAccessMask = srcAccess;
    memory.dstStageMask = dstStage;
    memory.dstAccessMask = dstAccess;
    VkDependencyInfo dependency{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dependency.memoryBarrierCount = 1;
    dependency.pMemoryBarriers = &memory;
    vkCmdPipelineBarrier2(cmd, &dependency);
}

constexpr VkPipelineStageFlags2 kShaderStagesReading =
    VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_TESSELLATION_CONTROL_SHADER_BIT |
    VK_PIPELINE_STAGE_2_TESSELLATION_EVALUATION_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT |
    VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;

void dispatchPerSubface(VkCommandBuffer cmd, const PlanPass& pass, VkPipeline pipeline, ComputePush push) {
    uint32_t count = push.subfaceCount;
    if (count == 0) return;
    push.groupsPerRow = std::min(count, kMaxGroupsPerRow);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pass.computeLayout, 0, 1, &pass.set, 0, nullptr);
    vkCmdPushConstants(cmd, pass.computeLayout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    vkCmdDispatch(cmd, push.groupsPerRow, (count + push.groupsPerRow - 1) / push.groupsPerRow, 1);
}

// Control points for factors up to 2^level, visible to every later shader stage.
void recordStencils(VkCommandBuffer cmd, const PlanPass& pass, const PlanBuffers& buffers, uint32_t level) {
    dispatchPerSubface(cmd, pass, pass.stencils, ComputePush{uint32_t(buffers.data.subfaces.size()), level, 0, 0});
    barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, kShaderStagesReading,
            VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
}

uint32_t levelFor(uint32_t factor) {
    uint32_t level = 0;
    while ((1u << level) < factor) ++level;
    return level;
}

DrawPush drawPush(const PlanView& view, const TessellationSettings* settings, uint32_t gridStride) {
    DrawPush push{};
    push.viewProjection = view.viewProjection;
    push.uniformFactor = settings ? float(settings->uniformFactor) : 0.0f;
    push.pixelsPerSegment = settings ? settings->pixelsPerSegment : 8.0f;
    push.pixelsPerUnit = view.pixelsPerUnit;
    push.colorMode = uint32_t(view.colorBy);
    push.capture = view.capture ? 1u : 0u;
    push.gridStride = gridStride;
    return push;
}

}  // namespace

Result<PlanBuffers> uploadPlans(const VulkanContext& ctx, const PlannedCage& planned) {
    PlanBuffers b;
    b.data = packPlans(planned);
    const GpuPlanData& d = b.data;
    struct Item {
        Buffer& buffer;
        Result<Buffer> result;
    };
    Item items[] = {
        {b.planHeaders, createFilled(ctx, d.plans)},
        {b.nodes, createFilled(ctx, d.nodes)},
        {b.points, createFilled(ctx, d.points)},
        {b.weights, createFilled(ctx, d.weights)},
        {b.subfaces, createFilled(ctx, d.subfaces)},
        {b.rings, createFilled(ctx, d.rings)},
        {b.positions, createFilled(ctx, cagePositions(planned))},
        {b.controlPoints, createFilled(ctx, std::vector<glm::vec4>(d.controlPointCount))},
        {b.boundaries, createFilled(ctx, d.boundaries)},
        {b.segments, createFilled(ctx, d.segments)},
        {b.boundaryPoints, createFilled(ctx, d.boundaryPoints)},
        {b.pointPositions, createFilled(ctx, boundaryPointPositions(planned))},
        {b.subfaceFactors, createFilled(ctx, std::vector<uint32_t>(d.subfaces.size(), 1))},
        {b.grid, createFilled(ctx, std::vector<float>(6))},
        {b.capture, createFilled(ctx, std::vector<uint32_t>(4), VK_BUFFER_USAGE_TRANSFER_DST_BIT)},
    };
    for (Item& item : items) {
        if (!item.result) {
            Error error = item.result.error();
            for (Item& other : items)
                if (other.result) destroyBuffer(ctx, *other.result);
            return error;
        }
        item.buffer = *item.result;
    }
    return b;
}

void updatePositions(const PlanBuffers& buffers, const PlannedCage& planned) {
    std::vector<float> positions = cagePositions(planned);
    assert(positions.size() * sizeof(float) <= buffers.positions.size);
    uploadBuffer(buffers.positions, positions.data(), positions.size() * sizeof(float));
    std::vector<glm::vec4> points = boundaryPointPositions(planned);
    uploadBuffer(buffers.pointPositions, points.data(), points.size() * sizeof(glm::vec4));
}

void destroyPlanBuffers(const VulkanContext& ctx, PlanBuffers& b) {
    for (Buffer* buffer : {&b.planHeaders, &b.nodes, &b.points, &b.weights, &b.subfaces, &b.rings, &b.positions,
                           &b.controlPoints, &b.boundaries, &b.segments, &b.boundaryPoints, &b.pointPositions,
                           &b.subfaceFactors, &b.grid, &b.capture})
        destroyBuffer(ctx, *buffer);
    b = PlanBuffers{};
}

Result<PlanPass> createPlanPass(const VulkanContext& ctx, VkPipelineCache cache, VkFormat colorFormat,
                                VkFormat depthFormat) {
    PlanPass pass;
    pass.colorFormat = colorFormat;
    pass.depthFormat = depthFormat;
    if (Status s = initPass(ctx, cache, pass); !s) {
        destroyPlanPass(ctx, pass);
        return s.error();
    }
    return pass;
}

void destroyPlanPass(const VulkanContext& ctx, PlanPass& pass) {
    for (VkPipeline p : {pass.stencils, pass.grid, pass.tessellated, pass.tessellatedWire, pass.gridTriangles, pass.gridWire})
        if (p) vkDestroyPipeline(ctx.device, p, nullptr);
    if (pass.computeLayout) vkDestroyPipelineLayout(ctx.device, pass.computeLayout, nullptr);
    if (pass.drawLayout) vkDestroyPipelineLayout(ctx.device, pass.drawLayout, nullptr);
    if (pass.pool) vkDestroyDescriptorPool(ctx.device, pass.pool, nullptr);
    if (pass.setLayout) vkDestroyDescriptorSetLayout(ctx.device, pass.setLayout, nullptr);
    destroyBuffer(ctx, pass.gridIndices);
    pass = PlanPass{};
}

void bindPlanBuffers(const VulkanContext& ctx, PlanPass& pass, const PlanBuffers& b) {
    const Buffer* order[kBindingCount] = {&b.planHeaders, &b.nodes,      &b.points,         &b.weights,
                                          &b.subfaces,    &b.rings,      &b.positions,      &b.controlPoints,
                                          &b.grid,        &b.boundaries, &b.segments,       &b.boundaryPoints,
                                          &b.subfaceFactors, &b.pointPositions, &b.capture};
    VkDescriptorBufferInfo infos[kBindingCount];
    VkWriteDescriptorSet writes[kBindingCount];
    for (uint32_t i = 0; i < kBindingCount; ++i) {
        infos[i] = {order[i]->buffer, 0, VK_WHOLE_SIZE};
        writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, nullptr, pass.set, i, 0, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                     nullptr, &infos[i], nullptr};
    }
    vkUpdateDescriptorSets(ctx.device, kBindingCount, writes, 0, nullptr);
}

float pixelsPerUnit(const glm::mat4& projection, uint32_t viewportHeight) {
    return 0.5f * float(viewportHeight) * std::fabs(projection[1][1]);
}

uint32_t maxTessellationLevel(const TessellationSettings& settings) {
    return levelFor(settings.uniformFactor == 0 ? 64 : std::min(settings.uniformFactor, 64u));
}

uint32_t patchesPerDraw(uint32_t maxFactor) {
    uint32_t side = maxFactor + 1;
    return std::max(1u, 65535u / (side * side));
}

void recordTessellated(VkCommandBuffer cmd, const PlanPass& pass, const PlanBuffers& buffers,
                       const RenderTarget& target, const PlanView& view, const TessellationSettings& settings) {
    assert(pass.colorFormat == target.colorFormat && pass.depthFormat == target.depthFormat);
    if (view.capture) {
        vkCmdFillBuffer(cmd, buffers.capture.buffer, 0, 4, 0);
        barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_2_TESSELLATION_EVALUATION_SHADER_BIT,
                VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    }
    recordStencils(cmd, pass, buffers, maxTessellationLevel(settings));
    beginRendering(cmd, target, true, view.background);
    const DrawPush push = drawPush(view, &settings, 0);
    const uint32_t count = uint32_t(buffers.data.subfaces.size());
    const uint32_t perDraw = patchesPerDraw(settings.uniformFactor == 0 ? 64 : std::min(settings.uniformFactor, 64u));
    for (VkPipeline pipeline : {pass.tessellated, view.wireframe ? pass.tessellatedWire : VkPipeline(VK_NULL_HANDLE)}) {
        if (!pipeline) continue;
        DrawPush p = push;
        if (pipeline == pass.tessellatedWire) {
            p.colorMode = 0xffffffffu;  // plan.frag: flat wire colour
            p.capture = 0;
        }
        for (uint32_t first = 0; first < count; first += perDraw) {
            // Captured draws all append to one buffer: order them (barriers may not sit inside
            // a rendering instance at these stages, so each chunk gets its own).
            if (p.capture && first > 0) {
                vkCmdEndRendering(cmd);
                barrier(cmd, VK_PIPELINE_STAGE_2_TESSELLATION_EVALUATION_SHADER_BIT,
                        VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                        VK_PIPELINE_STAGE_2_TESSELLATION_EVALUATION_SHADER_BIT,
                        VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
                beginRendering(cmd, target, false, view.background);
            }
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pass.drawLayout, 0, 1, &pass.set, 0, nullptr);
            vkCmdPushConstants(cmd, pass.drawLayout, kDrawStages, 0, sizeof(p), &p);
            vkCmdDraw(cmd, std::min(perDraw, count - first), 1, first, 0);
        }
    }
    vkCmdEndRendering(cmd);
}

uint32_t gridVerticesPerSubface(uint32_t factor) { return (factor + 1) * (factor + 1); }

uint32_t gridFactorOf(const GpuPlanData& data, uint32_t drawn, uint32_t factor) {
    const bool ngon = (data.boundaries[drawn].edges[0].flags & 4u) != 0;
    return ngon ? std::max(1u, factor / 2) : factor;
}

Status prepareGrid(const VulkanContext& ctx, PlanPass& pass, PlanBuffers& buffers, uint32_t factor) {
    assert(factor >= 1 && factor <= 64);
    const GpuPlanData& d = buffers.data;
    // Non-quads need an even factor so their half-size sub-faces line up with the quads.
    bool anyNgon = false;
    for (uint32_t i = 0; i < d.subfaces.size(); ++i) anyNgon |= gridFactorOf(d, i, 2) == 1;
    if (anyNgon && factor % 2) ++factor;
    if (buffers.gridFactor == factor && pass.gridIndexFactor == factor) return success();

    const uint32_t stride = gridVerticesPerSubface(factor);
    std::vector<uint32_t> factors(d.subfaces.size()), indices;
    for (uint32_t i = 0; i < d.subfaces.size(); ++i) {
        uint32_t n = factors[i] = gridFactorOf(d, i, factor), side = n + 1, base = i * stride;
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x) {
                uint32_t a = base + y * side + x, b = a + 1, c = a + side + 1, e = a + side;
                indices.insert(indices.end(), {a, b, c, a, c, e});
            }
    }
    Result<Buffer> grid = createBuffer(ctx, VkDeviceSize(stride) * d.subfaces.size() * sizeof(GridVertex) + 16,
                                       VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    if (!grid) return grid.error();
    Result<Buffer> indexBuffer = createBuffer(ctx, std::max<size_t>(indices.size(), 4) * sizeof(uint32_t),
                                              VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
    if (!indexBuffer) {
        destroyBuffer(ctx, *grid);
        return indexBuffer.error();
    }
    uploadBuffer(*indexBuffer, indices.data(), indices.size() * sizeof(uint32_t));
    uploadBuffer(buffers.subfaceFactors, factors.data(), factors.size() * sizeof(uint32_t));
    destroyBuffer(ctx, buffers.grid);
    destroyBuffer(ctx, pass.gridIndices);
    buffers.grid = *grid;
    buffers.gridFactor = factor;
    pass.gridIndices = *indexBuffer;
    pass.gridIndexFactor = factor;
    bindPlanBuffers(ctx, pass, buffers);
    return success();
}

void recordGridEvaluation(VkCommandBuffer cmd, const PlanPass& pass, const PlanBuffers& buffers) {
    assert(buffers.gridFactor > 0 && "prepareGrid first");
    recordStencils(cmd, pass, buffers, levelFor(buffers.gridFactor));
    dispatchPerSubface(cmd, pass, pass.grid,
                       ComputePush{uint32_t(buffers.data.subfaces.size()), buffers.gridFactor, 0,
                                   gridVerticesPerSubface(buffers.gridFactor)});
    barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
            kShaderStagesReading | VK_PIPELINE_STAGE_2_HOST_BIT,
            VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_HOST_READ_BIT);
}

void recordGrid(VkCommandBuffer cmd, const PlanPass& pass, const PlanBuffers& buffers, const RenderTarget& target,
                const PlanView& view) {
    recordGridEvaluation(cmd, pass, buffers);
    beginRendering(cmd, target, true, view.background);
    DrawPush push = drawPush(view, nullptr, gridVerticesPerSubface(buffers.gridFactor));
    push.capture = 0;
    const uint32_t indexCount = uint32_t(pass.gridIndices.size / sizeof(uint32_t));
    for (VkPipeline pipeline : {pass.gridTriangles, view.wireframe ? pass.gridWire : VkPipeline(VK_NULL_HANDLE)}) {
        if (!pipeline) continue;
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pass.drawLayout, 0, 1, &pass.set, 0, nullptr);
        vkCmdBindIndexBuffer(cmd, pass.gridIndices.buffer, 0, VK_INDEX_TYPE_UINT32);
        DrawPush p = push;
        if (pipeline == pass.gridWire) p.colorMode = 0xffffffffu;
        vkCmdPushConstants(cmd, pass.drawLayout, kDrawStages, 0, sizeof(p), &p);
        vkCmdDrawIndexed(cmd, indexCount, 1, 0, 0, 0);
    }
    vkCmdEndRendering(cmd);
}

Status enableCapture(const VulkanContext& ctx, PlanBuffers& buffers, uint32_t capacity) {
    Result<Buffer> capture = createBuffer(ctx, kCaptureHeaderBytes + VkDeviceSize(capacity) * sizeof(CaptureRecord),
                                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT);
    if (!capture) return capture.error();
    destroyBuffer(ctx, buffers.capture);
    buffers.capture = *capture;
    buffers.captureCapacity = capacity;
    const uint32_t header[4] = {0, capacity, 0, 0};
    uploadBuffer(buffers.capture, header, sizeof(header));
    return success();
}

std::vector<CaptureRecord> readCapture(const PlanBuffers& buffers, uint32_t* overflowed) {
    uint32_t header[2];
    std::memcpy(header, buffers.capture.data, sizeof(header));
    uint32_t count = std::min(header[0], buffers.captureCapacity);
    if (overflowed) *overflowed = header[0] - count;
    std::vector<CaptureRecord> records(count);
    std::memcpy(records.data(), static_cast<const char*>(buffers.capture.data) + kCaptureHeaderBytes,
                count * sizeof(CaptureRecord));
    return records;
}

}  // namespace qp
