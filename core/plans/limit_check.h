// Comparison of planned limit surfaces with OpenSubdiv's (LimitReference), relative to the
// cage's bounding-box diagonal, as OpenSubdiv's own bfr_evaluate regression does.
#pragma once

#include "plans/limit_reference.h"
#include "plans/planned_cage.h"

namespace qp {

// Tolerances of `quadplan check-limit`, relative to the bounding-box diagonal. Derivatives of
// float control points lose a factor 2 of precision per level inside deep nodes (measured in
// docs/plan-engine.md), so their tolerance grows with the depth beyond 6.
constexpr double kPositionTolerance = 5e-5;
constexpr double derivativeTolerance(uint32_t depth) { return 5e-4 * double(1u << (depth > 6 ? depth - 6 : 0)); }

struct LimitCheck {
    uint32_t subfaces = 0;      // sub-faces with a surface (holes excluded)
    uint64_t samples = 0;
    uint32_t depth = 6;
    double maxPositionError = 0.0, maxDerivativeError = 0.0;  // relative to the diagonal
    uint32_t worstPositionSubface = 0, worstDerivativeSubface = 0;
    bool pass() const {
        return maxPositionError <= kPositionTolerance && maxDerivativeError <= derivativeTolerance(depth);
    }
};

// Evaluates an N x N grid (u, v = i / (N-1)) on every sub-face with both evaluators.
LimitCheck compareWithReference(const PlannedCage& planned, const LimitReference& reference, uint32_t samplesPerSide);

}  // namespace qp
