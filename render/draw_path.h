// Which of PlanPass's paths draws a frame (plan_pass.h), and one frame through it.
//
// `auto` picks per device: on a CPU implementation (lavapipe) the grid filled by the CPU
// evaluator, on a GPU the tessellated path. On lavapipe the tessellator runs on one core and
// the compute shader loses to compiled C++ (docs/renderer.md has the measurements of all three
// paths: `quadplan bench render`); on a GPU the tessellator is fast and needs no grid memory
// (documented, not measured here: the project's machines have no GPU).
#pragma once

#include <optional>
#include <string_view>

#include "plan_pass.h"
#include "plans/planned_cage.h"
#include "vk_context.h"

namespace qp {

enum class DrawPath { Auto, Tessellated, Grid, CpuGrid };

// Auto becomes CpuGrid on a CPU implementation and Tessellated on a GPU.
DrawPath resolveDrawPath(DrawPath requested, const VulkanContext& context);

const char* drawPathName(DrawPath path);                        // "auto", "tess", "grid", "cpu"
std::optional<DrawPath> parseDrawPath(std::string_view name);

// One frame, in two steps. preparePlanFrame does the host side: the grid paths lay the grid
// out for the settings (adaptive ones for `view`; raised where there is sculpted displacement,
// displaced_grid_factors.h) and the CPU grid is filled when it is not cached. recordPlanFrame records the device side into `target` (cleared): the tessellated
// path, or the grid (evaluated by the compute shader when not cached) drawn as triangles.
// A frame whose view moved but whose cage did not costs only the drawing on the grid paths
// (with adaptive factors: until a segment needs other factors). `path` is resolved.
Status preparePlanFrame(const VulkanContext& context, PlanPass& pass, PlanBuffers& buffers, const PlannedCage& planned,
                        DrawPath path, const PlanView& view, const TessellationSettings& settings);
void recordPlanFrame(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers, DrawPath path,
                     const RenderTarget& target, const PlanView& view, const TessellationSettings& settings);

}  // namespace qp
