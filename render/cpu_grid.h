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
#include <vector>

#include <glm/geometric.hpp>

#include "displacement/displacement.h"
#include "displacement/displacement_users.h"
#include "grid_layout.h"
#include "plans/planned_cage.h"

namespace qp {

// With displacement, a sub-face corner is displaced and shaded with its own derivatives (at
// smooth extraordinary vertices they give the exact limit normal; those a step inside are
// tilted by 1-10 degrees there), unless they vanish: |du x dv| at most kCornerVanishing times
// that kCornerNormalStep inside the sub-face (in u and v), whose derivatives are then used. At
// some extraordinary vertices the plans' Gregory corners have none (shaders/displacement.glsl,
// evaluateWithNormal, has the same rule and constants and says more).
constexpr float kCornerNormalStep = 1.0f / 64.0f;
constexpr float kCornerVanishing = 1e-3f;
inline bool cornerDerivativesVanish(const glm::vec3& du, const glm::vec3& dv, const glm::vec3& insideDu,
                                    const glm::vec3& insideDv) {
    return !(glm::length(glm::cross(du, dv)) > kCornerVanishing * glm::length(glm::cross(insideDu, insideDv)));
}

// What the grid keeps per evaluated slot when there is a displacement: the undisplaced limit
// point and the derivatives it is displaced and shaded with (at sub-face corners where they
// vanish, those kCornerNormalStep inside). A brush dab then re-displaces slots from them without evaluating
// the surface again (redisplaceGridOnCpu). Stored as a structure of arrays per drawn
// sub-face, so that consecutive slots of a row load into SIMD lanes together: in the block of
// drawn sub-face d, component c (position x, y, z, du x, y, z, dv x, y, z) of its local slot k
// is at block(layout, d)[c * (n + 1)^2 + k].
constexpr uint32_t kFrameComponents = 9;
struct GridFrames {
    std::vector<float> components;  // kFrameComponents per slot, then padding for whole lanes

    void resize(const GridLayout& layout) { components.resize(size_t(kFrameComponents) * layout.slotCount() + 4); }
    float* block(const GridLayout& layout, uint32_t drawn) {
        return components.data() + size_t(kFrameComponents) * layout.subfaceOffset[drawn];
    }
    const float* block(const GridLayout& layout, uint32_t drawn) const {
        return components.data() + size_t(kFrameComponents) * layout.subfaceOffset[drawn];
    }
};

// Phase 1 (evaluated slots) for the drawn sub-faces in `evaluate`, then phase 2 (copied
// slots) for those in `copy`; `grid` holds layout.slotCount() vertices. `planned` must be the
// cage `data` was packed from, with current control points. With a `displacement` (matching
// `planned`), evaluated slots hold the displaced point and displacePoint's shading normal (as
// shaders/plan_grid.comp does); phase 2 copies carry them to the neighbours, so shared
// vertices stay bit-identical. A displacement needs `frames` (resized for `layout`): each
// evaluated slot's frame is kept there.
void evaluateGridOnCpu(const PlannedCage& planned, const GpuPlanData& data, const GridLayout& layout,
                       std::span<const uint32_t> evaluate, std::span<const uint32_t> copy, GridVertex* grid,
                       const Displacement* displacement = nullptr, GridFrames* frames = nullptr);

// Both phases for every drawn sub-face.
void evaluateWholeGridOnCpu(const PlannedCage& planned, const GpuPlanData& data, const GridLayout& layout,
                            GridVertex* grid, const Displacement* displacement = nullptr, GridFrames* frames = nullptr);

// After only the displacement's samples changed (those in `changed`): phase 1 from the kept
// frames (no surface evaluation) for the slots of the drawn sub-faces in `evaluate` whose D
// reads a changed sample (evaluateDisplacement: the 3 x 3 coefficients of the tile's span at
// the slot), then phase 2 for `copy`. The same bits as evaluateGridOnCpu. Returns the number of slots displaced.
uint32_t redisplaceGridOnCpu(const GpuPlanData& data, const GridLayout& layout, std::span<const uint32_t> evaluate,
                             std::span<const uint32_t> copy, const Displacement& displacement, const SampleBits& changed,
                             const GridFrames& frames, GridVertex* grid);

}  // namespace qp
