// The GPU memory a planned cage needs, in the columns of Brainerd et al. 2016, Table 4: base
// vertices, index data, plans, quadtree, stencils and the scratch buffer filled every frame.
// Counted from the arrays packPlans (gpu_plans.h) builds and uploadPlans (plan_pass.h)
// uploads, so no device is needed.
#pragma once

#include <cstdint>

#include "plans/planned_cage.h"

namespace qp {

struct PlanMemory {
    uint64_t vertexBytes = 0;    // cage positions (vec4 each)
    uint64_t indexBytes = 0;     // 1-rings, sub-face records and the boundary-ownership tables
    uint32_t plans = 0;          // plans uploaded: the whole database (after edits, also plans no face uses now)
    uint64_t quadtreeBytes = 0;  // plan headers, quadtree nodes, leaf point indices
    uint64_t stencilBytes = 0;   // stencil weights
    uint64_t scratchBytes = 0;   // control points the stencil pass writes (vec4 each)
};

PlanMemory measurePlanMemory(const PlannedCage& planned);

}  // namespace qp
