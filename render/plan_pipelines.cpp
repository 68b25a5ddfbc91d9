#include "plan_pipelines.h"

#include <string>
#include <vector>

#include "shader_code.h"
#include "vk_check.h"

namespace qp {

namespace {

Result<VkPipeline> createComputePipeline(const VulkanContext& ctx, VkPipelineCache cache, const PlanPass& pass,
                                         const char* shader) {
    VkShaderModule module = loadShaderModule(ctx, planShaderVariant(pass, shader));
    const VkPipelineLayout layout = pass.computeLayout;
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
    std::string vertex;
    std::string control;     // empty: no tessellation
    std::string evaluation;
    std::string fragment;
};

Result<VkPipeline> createDrawPipeline(const VulkanContext& ctx, VkPipelineCache cache, const PlanPass& pass,
                                      const GraphicsStages& names, bool wireframe) {
    const bool tessellated = !names.control.empty();
    std::vector<VkShaderModule> modules;
    std::vector<VkPipelineShaderStageCreateInfo> stages;
    const ColorEncoding encoding(pass.colorFormat);
    auto addStage = [&](const std::string& name, VkShaderStageFlagBits stage) {
        modules.push_back(loadShaderModule(ctx, planShaderVariant(pass, name)));
        stages.push_back({VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, stage, modules.back(), "main",
                          stage == VK_SHADER_STAGE_FRAGMENT_BIT ? &encoding.info : nullptr});
    };
    addStage(names.vertex, VK_SHADER_STAGE_VERTEX_BIT);
    if (tessellated) {
        addStage(names.control, VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT);
        addStage(names.evaluation, VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT);
    }
    addStage(names.fragment, VK_SHADER_STAGE_FRAGMENT_BIT);

    // The grid is also a vertex buffer: the device's vertex fetch beats loads from a storage
    // buffer in the vertex shader (measured on lavapipe, docs/renderer.md).
    VkPipelineVertexInputStateCreateInfo vertexInput{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    const VkVertexInputBindingDescription gridBinding{0, sizeof(GridVertex), VK_VERTEX_INPUT_RATE_VERTEX};
    const VkVertexInputAttributeDescription gridAttributes[2] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(GridVertex, position)},
        {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(GridVertex, normal)}};
    if (!tessellated) {
        vertexInput.vertexBindingDescriptionCount = 1;
        vertexInput.pVertexBindingDescriptions = &gridBinding;
        vertexInput.vertexAttributeDescriptionCount = 2;
        vertexInput.pVertexAttributeDescriptions = gridAttributes;
    }
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

}  // namespace

std::string planShaderVariant(const PlanPass& pass, const std::string& name) {
    if (!pass.byAddress || name.empty() || name == "plan.vert") return name;
    const size_t dot = name.find('.');
    return name.substr(0, dot) + "_by_address" + name.substr(dot);
}

Status createPlanPipelines(const VulkanContext& ctx, VkPipelineCache cache, PlanPass& pass) {
    // By address: one uniform block of addresses; else the buffers themselves, in that order.
    VkDescriptorSetLayoutBinding bindings[kPlanBufferCount];
    for (uint32_t b = 0; b < kPlanBufferCount; ++b)
        bindings[b] = {b, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, kPlanAllStages, nullptr};
    if (pass.byAddress) bindings[0].descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    setInfo.bindingCount = pass.byAddress ? 1 : kPlanBufferCount;
    setInfo.pBindings = bindings;
    VK_CHECK(vkCreateDescriptorSetLayout(ctx.device, &setInfo, nullptr, &pass.setLayout));

    VkPushConstantRange computeRange{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(PlanComputePush)};
    VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layoutInfo.setLayoutCount = 1;
    layoutInfo.pSetLayouts = &pass.setLayout;
    layoutInfo.pushConstantRangeCount = 1;
    layoutInfo.pPushConstantRanges = &computeRange;
    VK_CHECK(vkCreatePipelineLayout(ctx.device, &layoutInfo, nullptr, &pass.computeLayout));
    VkPushConstantRange drawRange{kPlanDrawStages, 0, sizeof(PlanDrawPush)};
    layoutInfo.pPushConstantRanges = &drawRange;
    VK_CHECK(vkCreatePipelineLayout(ctx.device, &layoutInfo, nullptr, &pass.drawLayout));

    auto assign = [](Result<VkPipeline> r, VkPipeline& out) -> Status {
        if (!r) return r.error();
        out = *r;
        return success();
    };
    if (Status s = assign(createComputePipeline(ctx, cache, pass, "plan_stencils.comp"), pass.stencils); !s) return s;
    if (Status s = assign(createComputePipeline(ctx, cache, pass, "plan_grid_undisplaced.comp"), pass.grid); !s)
        return s;
    if (Status s = assign(createComputePipeline(ctx, cache, pass, "plan_grid.comp"), pass.gridDisplaced); !s)
        return s;
    const GraphicsStages tess{"plan.vert", "plan.tesc", "plan_undisplaced.tese", "plan.frag"};
    const GraphicsStages tessDisplaced{"plan.vert", "plan.tesc", "plan.tese", "plan.frag"};
    // Plain shading and the wireframe pass only normals; the colour modes also the sub-face and (u, v).
    const GraphicsStages grid{"plan_grid_lit.vert", "", "", "plan_lit.frag"};
    const GraphicsStages gridColored{"plan_grid.vert", "", "", "plan.frag"};
    if (!ctx.features.tessellationShader)
        return Error{"the Vulkan device '" + ctx.deviceName + "' has no tessellation shaders"};
    if (Status s = assign(createDrawPipeline(ctx, cache, pass, tess, false), pass.tessellated); !s) return s;
    if (Status s = assign(createDrawPipeline(ctx, cache, pass, tessDisplaced, false), pass.tessellatedDisplaced); !s) return s;
    if (Status s = assign(createDrawPipeline(ctx, cache, pass, grid, false), pass.gridTriangles); !s) return s;
    if (Status s = assign(createDrawPipeline(ctx, cache, pass, gridColored, false), pass.gridColored); !s) return s;
    if (ctx.features.fillModeNonSolid) {
        if (Status s = assign(createDrawPipeline(ctx, cache, pass, tess, true), pass.tessellatedWire); !s) return s;
        if (Status s = assign(createDrawPipeline(ctx, cache, pass, tessDisplaced, true), pass.tessellatedDisplacedWire); !s)
            return s;
        if (Status s = assign(createDrawPipeline(ctx, cache, pass, grid, true), pass.gridWire); !s) return s;
    }
    return success();
}

void destroyPlanPipelines(const VulkanContext& ctx, PlanPass& pass) {
    for (VkPipeline p : {pass.stencils, pass.grid, pass.gridDisplaced, pass.tessellated, pass.tessellatedWire,
                         pass.tessellatedDisplaced, pass.tessellatedDisplacedWire, pass.gridTriangles, pass.gridColored,
                         pass.gridWire})
        if (p) vkDestroyPipeline(ctx.device, p, nullptr);
    if (pass.computeLayout) vkDestroyPipelineLayout(ctx.device, pass.computeLayout, nullptr);
    if (pass.drawLayout) vkDestroyPipelineLayout(ctx.device, pass.drawLayout, nullptr);
    if (pass.setLayout) vkDestroyDescriptorSetLayout(ctx.device, pass.setLayout, nullptr);
}

}  // namespace qp
