// The plan pass's device objects: its descriptor set layout (the 21 buffers as storage buffers,
// or, in the by-address variant, one uniform block of their addresses: PlanAddresses), the
// push-constant blocks its shaders read, and its pipelines (compute: stencils and grid; draw:
// tessellated, grid triangles, the grid's colour modes, wireframes).
// The grid and tessellated pipelines come twice, with and without the displacement code (the
// *_undisplaced stages, compiled with QP_UNDISPLACED: shaders/displacement.glsl): compiled in but
// unused it doubled the tessellated path's per-vertex cost on lavapipe.
// PlanPass (plan_pass.h) makes them once per device and formats through shared_pipelines.h; the
// B-spline ablation (bspline_pass.h) draws with the same layout and push block.
#pragma once

#include <cstdint>
#include <string>

#include <glm/mat4x4.hpp>

#include "plan_pass.h"

namespace qp {

// Mirrors DrawPush in shaders/plan_draw.glsl (std430: the vec4s start at byte 96).
struct PlanDrawPush {
    glm::mat4 viewProjection;
    float uniformFactor;
    float pixelsPerSegment;
    float pixelsPerUnit;
    uint32_t colorMode;
    uint32_t capture;
    uint32_t padding[3];
    glm::vec4 keyLight, fillLight;  // xyz: PlanView's, in the cage's coordinates
};
static_assert(sizeof(PlanDrawPush) == 128, "push constants: 128 bytes guaranteed; the layout of plan_draw.glsl");

// The push constants of a plan draw for `view` (`settings` null: the grid paths).
PlanDrawPush planDrawPush(const PlanView& view, const TessellationSettings* settings);

// Mirrors the push blocks of plan_stencils.comp and plan_grid.comp.
struct PlanComputePush {
    uint32_t subfaceCount;  // workgroups: sub-faces, or entries of the update list
    uint32_t levelOrPhase;  // stencils: tessellation level; grid: 0 evaluate, 1 copy
    uint32_t groupsPerRow;
    uint32_t listOffset;    // UINT32_MAX: every sub-face; else where the list starts in updateList
};

// Mirrors PlanAddresses in shaders/plan_buffers.glsl (std140: 8-byte addresses, then the counts).
inline constexpr uint32_t kPlanBufferCount = 21;
struct PlanAddresses {
    VkDeviceAddress buffers[kPlanBufferCount];
    uint32_t controlPointCount;
    uint32_t dispPaddedCount;
};
static_assert(sizeof(PlanAddresses) == 8 * 21 + 8);

inline constexpr VkShaderStageFlags kPlanAllStages = VK_SHADER_STAGE_COMPUTE_BIT | VK_SHADER_STAGE_VERTEX_BIT |
                                                     VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT |
                                                     VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT |
                                                     VK_SHADER_STAGE_FRAGMENT_BIT;
// The draw layout's push range covers every drawing stage.
inline constexpr VkShaderStageFlags kPlanDrawStages = kPlanAllStages & ~VK_SHADER_STAGE_COMPUTE_BIT;

// The shader `name` (stem.stage) in the pass's variant: stem_by_address.stage when the pass
// reaches its buffers by address (plan.vert reads none and has no variant).
std::string planShaderVariant(const PlanPass& pass, const std::string& name);

// The layouts and pipelines into `pass` (its colorFormat and depthFormat set); on failure the
// caller destroys what was made with destroyPlanPipelines.
Status createPlanPipelines(const VulkanContext& context, VkPipelineCache cache, PlanPass& pass);
void destroyPlanPipelines(const VulkanContext& context, PlanPass& pass);

}  // namespace qp
