#include "bspline_pass.h"

#include <algorithm>
#include <cassert>
#include <vector>

#include <glm/exponential.hpp>

#include "pipeline_builder.h"
#include "plan_pipelines.h"
#include "shader_code.h"

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
    std::vector<ShaderStage> stages;
    for (auto [name, stage] : names) stages.push_back({stage, loadShaderModule(ctx, planShaderVariant(plans, name))});
    GraphicsPipelineDesc desc;
    desc.stages = stages;
    desc.layout = plans.drawLayout;
    desc.colorFormat = plans.colorFormat;
    desc.depthFormat = plans.depthFormat;
    desc.patchControlPoints = 1;
    Result<VkPipeline> pipeline = createGraphicsPipeline(ctx, cache, desc);
    for (const ShaderStage& stage : stages) vkDestroyShaderModule(ctx.device, stage.module, nullptr);
    if (!pipeline) return pipeline.error();
    BSplinePass pass;
    pass.pipeline = *pipeline;
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
