// Which of PlanPass's two paths draws a frame (plan_pass.h).
//
// Lavapipe runs the tessellator on one core but compute shaders on all of them, so on a CPU
// device evaluating a grid in compute and drawing triangles wins; a GPU's tessellator is fast
// and saves the grid's memory. `quadplan bench render` measures both (docs/renderer.md).
#pragma once

#include <optional>
#include <string_view>

#include "vk_context.h"

namespace qp {

enum class DrawPath { Auto, Tessellated, Grid };

// Auto becomes Grid on a CPU implementation and Tessellated on a GPU.
DrawPath resolveDrawPath(DrawPath requested, const VulkanContext& context);

const char* drawPathName(DrawPath path);
std::optional<DrawPath> parseDrawPath(std::string_view name);  // "auto", "tess", "grid"

}  // namespace qp
