#include "bspline_pass.h"

#include <algorithm>
#include <cassert>
#include <vector>

#include <glm/exponential.hpp>

#include "plan_pipelines.h"
#include "shader_code.h"
#include "vk_check.h"

namespace qp {

Result<BSplinePass> createBSplinePass(const VulkanContext& ctx, VkPipelineCache cache, const PlanPass& plans) {
    if (!ctx.features.tessellationShader)
        return Error{"the Vulkan device '" + ctx.deviceName + "' has no tessellation shaders"};
    // The same fixed-function state as PlanPass's solid tessellated pipeline, so only the
    // evaluation stage differs.
    const std::pair<const char*, VkShaderStageFlagBits> names[] = {
        {"plan.vert", VK_SHADER_STAGE_VERTEX_BIT},
        {"plan.tesc", VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT},
        {"bspline.tese", VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT},
        {"plan.frag", VK_SHADER_STAGE_FRAGMENT_BIT}};
    std::vector<VkPipelineShaderStageCreateInfo> stages;
    const ColorEncoding encoding(plans.colorFormat);
    for (auto [name, stage] : names)
        stages.push_back({VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, stage,
                          loadShaderModule(ctx, planShaderVariant(plans, name)), "main",
                          stage == VK_SHADER_STAGE_FRAGMENT_BIT ? &encoding.info : nullptr});

    VkPipelineVertexInputStateCreateInfo vertexInput{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    assembly.topology = VK_PRIMITIVE_TOPOLOGY_PATCH_LIST;
    VkPipelineTessellationStateCreateInfo tessellation{VK_STRUCTURE_TYPE_PIPELINE_TESSELLATION_STATE_CREATE_INFO};
    tessellation.patchControlPoints = 1;
    VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_NONE;
    raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    raster.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    depth.depthTestEnable = VK_TRUE;
    depth.depthWriteEnable = VK_TRUE;
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
    rendering.pColorAttachmentFormats = &plans.colorFormat;
    rendering.depthAttachmentFormat = plans.depthFormat;

    VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO, &rendering};
    info.stageCount = uint32_t(stages.size());
    info.pStages = stages.data();
    info.pVertexInputState = &vertexInput;
    info.pInputAssemblyState = &assembly;
    info.pTessellationState = &tessellation;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &depth;
    info.pColorBlendState = &blend;
    info.pDynamicState = &dynamic;
    info.layout = plans.drawLayout;
    BSplinePass pass;
    VkResult result = vkCreateGraphicsPipelines(ctx.device, cache, 1, &info, nullptr, &pass.pipeline);
    for (const auto& stage : stages) vkDestroyShaderModule(ctx.device, stage.module, nullptr);
    VK_CHECK(result);
    return pass;
}

void destroyBSplinePass(const VulkanContext& ctx, BSplinePass& pass) {
    if (pass.pipeline) vkDestroyPipeline(ctx.device, pass.pipeline, nullptr);
    pass = BSplinePass{};
}

void recordBSplinePatches(VkCommandBuffer cmd, const BSplinePass& pass, const PlanPass& plans,
                          const PlanBuffers& buffers, const RenderTarget& target, const PlanView& view,
                          const TessellationSettings& settings) {
    assert(settings.uniformFactor > 0 && plans.colorFormat == target.colorFormat);
    beginRendering(cmd, target, view.clear, view.background);

    PlanDrawPush push = planDrawPush(view, &settings);
    push.colorMode = 0;  // lit: the colour modes would walk the plan in plan.frag
    push.capture = 0;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pass.pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, plans.drawLayout, 0, 1, &plans.set, 0, nullptr);
    vkCmdPushConstants(cmd, plans.drawLayout, kPlanDrawStages, 0, sizeof push, &push);
    // The same split as PlanPass: lavapipe corrupts draws over 65,535 tessellated vertices.
    const uint32_t perDraw = patchesPerDraw(std::min(settings.uniformFactor, 64u));
    for (const DrawnRun& run : drawnRuns(buffers, skippedDrawn(buffers, view, false)))
        for (uint32_t first = run.begin; first < run.end; first += perDraw)
            vkCmdDraw(cmd, std::min(perDraw, run.end - first), 1, first, 0);
    vkCmdEndRendering(cmd);
}

}  // namespace qp
