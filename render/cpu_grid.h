// The grid path's vertices evaluated on the CPU (DrawPath::CpuGrid): the plan evaluator of
// core/ (PlannedCage::evaluate, on every core through TBB) fills the same slots that
// shaders/plan_grid.comp fills on the device, in the same two phases (grid_layout.h).
//
// On a CPU Vulkan device (lavapipe) this beats the compute shader: the evaluator is compiled
// C++, while lavapipe runs a workgroup's invocations in SIMD lanes that diverge at every
// quadtree level and leaf kind (docs/renderer.md has the measurements).
#pragma once

#include <cstdint>
#include <span>

#include "grid_layout.h"
#include "planned_cage.h"

namespace qp {

// Phase 1 (evaluated slots) for the drawn sub-faces in `evaluate`, then phase 2 (copied
// slots) for those in `copy`; `grid` holds layout.slotCount() vertices. `planned` must be the
// cage `data` was packed from, with current control points.
void evaluateGridOnCpu(const PlannedCage& planned, const GpuPlanData& data, const GridLayout& layout,
                       std::span<const uint32_t> evaluate, std::span<const uint32_t> copy, GridVertex* grid);

// Both phases for every drawn sub-face.
void evaluateWholeGridOnCpu(const PlannedCage& planned, const GpuPlanData& data, const GridLayout& layout,
                            GridVertex* grid);

}  // namespace qp
