// Batched CPU evaluation of planned limit surfaces, spread over all cores with TBB.
#pragma once

#include <span>

#include "plans/planned_cage.h"

namespace qp {

struct SampleRequest {
    uint32_t subface;
    float u, v;
};

// out[i] = planned.evaluate(requests[i]); sub-faces without a surface give zeros.
void evaluateBatch(const PlannedCage& planned, std::span<const SampleRequest> requests, std::span<LimitSample> out);

}  // namespace qp
