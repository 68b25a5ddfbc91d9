// Comparison of planned limit surfaces with OpenSubdiv's (LimitReference), relative to the
// cage's bounding-box diagonal, as OpenSubdiv's own bfr_evaluate regression does.
#pragma once

#include "limit_reference.h"
#include "planned_cage.h"

namespace qp {

// Tolerances of `quadplan check-limit`, relative to the bounding-box diagonal (see
// docs/plan-engine.md for why the derivative tolerance is larger).
constexpr double kPositionTolerance = 5e-5;
constexpr double kDerivativeTolerance = 5e-4;

struct LimitCheck {
    uint32_t subfaces = 0;      // sub-faces with a surface (holes excluded)
    uint64_t samples = 0;
    double maxPositionError = 0.0, maxDerivativeError = 0.0;  // relative to the diagonal
    uint32_t worstPositionSubface = 0, worstDerivativeSubface = 0;
    bool pass() const { return maxPositionError <= kPositionTolerance && maxDerivativeError <= kDerivativeTolerance; }
};

// Evaluates an N x N grid (u, v = i / (N-1)) on every sub-face with both evaluators.
LimitCheck compareWithReference(const PlannedCage& planned, const LimitReference& reference, uint32_t samplesPerSide);

}  // namespace qp
