// Grid relayout that keeps what is evaluated: when the grid paths' factors change for some
// sub-faces only (a brush stroke reaching tiles that were zero raises their factors; a small
// camera move changes a few adaptive segments), or a topology or hole edit renumbers the drawn
// sub-faces, the new layout takes the evaluated vertices (and, with a displacement on the CPU
// path, their frames) of every sub-face whose slots mean the same as before, and only the
// others are evaluated again. The result equals laying out and evaluating the whole grid, bit
// for bit (tests/render/test_render_displacement.cpp, test_render_plans.cpp, test_render_macro_faces.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "plan_pass.h"

namespace qp {

// The grid laid out for `factors`, the evaluated vertices (and displacement frames) of kept
// sub-faces moved to their new slots. `oldOf`: drawn index now -> before, or UINT32_MAX for a
// sub-face whose slots are not kept (new, or laid out differently): its factor and every edge's
// pieces must be unchanged for a kept one. `ownersChanged` (empty: none): kept sub-faces whose
// edges or corners now have another owner (grid_layout.h carryGridLayout).
Status carryGrid(const VulkanContext& context, PlanPass& pass, PlanBuffers& buffers, GridFactors factors,
                 const std::vector<uint32_t>& oldOf, std::span<const char> ownersChanged = {});

// When the grid is evaluated and a few sub-faces change factors: carries the others into the
// layout for `factors` and evaluates the changed ones and the neighbours that copy from them (on
// the CPU at once; for the compute shader at the next recordGrid). Returns false, changing
// nothing, when there is nothing to keep or most sub-faces change (lay out and evaluate whole).
Result<bool> relayoutGridKeepingSlots(const VulkanContext& context, PlanPass& pass, PlanBuffers& buffers,
                                      const PlannedCage& planned, const GridFactors& factors);

}  // namespace qp
