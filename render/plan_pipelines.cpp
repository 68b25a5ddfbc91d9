#include "plan_pipelines.h"

#include <string>
#include <vector>

#include "pipeline_builder.h"
#include "shader_code.h"
#include "vk_check.h"

namespace qp {

namespace {

Result<VkPipeline> createPlanComputePipeline(const VulkanContext& ctx, VkPipelineCache cache, const PlanPass& pass,
                                             const char* shader) {
    VkShaderModule module = loadShaderModule(ctx, planShaderVariant(pass, shader));
    Result<VkPipeline> pipeline = createComputePipeline(ctx, cache, module, pass.computeLayout);
    vkDestroyShaderModule(ctx.device, module, nullptr);
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
    std::vector<ShaderStage> stages;
    auto addStage = [&](const std::string& name, VkShaderStageFlagBits stage) {
        stages.push_back({stage, loadShaderModule(ctx, planShaderVariant(pass, name))});
    };
    addStage(names.vertex, VK_SHADER_STAGE_VERTEX_BIT);
    if (tessellated) {
        addStage(names.control, VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT);
        addStage(names.evaluation, VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT);
    }
    addStage(names.fragment, VK_SHADER_STAGE_FRAGMENT_BIT);

    GraphicsPipelineDesc desc;
    desc.stages = stages;
    desc.layout = pass.drawLayout;
    desc.colorFormat = pass.colorFormat;
    desc.depthFormat = pass.depthFormat;
    // The grid is also a vertex buffer: the device's vertex fetch beats loads from a storage
    // buffer in the vertex shader (measured on lavapipe, docs/renderer.md).
    const VkVertexInputBindingDescription gridBinding{0, sizeof(GridVertex), VK_VERTEX_INPUT_RATE_VERTEX};
    const VkVertexInputAttributeDescription gridAttributes[2] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(GridVertex, position)},
        {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(GridVertex, normal)}};
    if (tessellated) {
        desc.patchControlPoints = 1;
    } else {
        desc.vertexBindings = {&gridBinding, 1};
        desc.vertexAttributes = gridAttributes;
    }
    desc.polygonMode = wireframe ? VK_POLYGON_MODE_LINE : VK_POLYGON_MODE_FILL;
    desc.depthWrite = !wireframe;
    // The wireframe is drawn over the shaded surface: pull it towards the eye a little.
    desc.depthBias = wireframe;
    desc.depthBiasConstant = desc.depthBiasSlope = -1.0f;
    Result<VkPipeline> pipeline = createGraphicsPipeline(ctx, cache, desc);
    for (const ShaderStage& stage : stages) vkDestroyShaderModule(ctx.device, stage.module, nullptr);
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
    if (Status s = assign(createPlanComputePipeline(ctx, cache, pass, "plan_stencils.comp"), pass.stencils); !s) return s;
    if (Status s = assign(createPlanComputePipeline(ctx, cache, pass, "plan_grid_undisplaced.comp"), pass.grid); !s)
        return s;
    if (Status s = assign(createPlanComputePipeline(ctx, cache, pass, "plan_grid.comp"), pass.gridDisplaced); !s)
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
