#include "plans/limit_check.h"

#include <algorithm>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

namespace qp {

LimitCheck compareWithReference(const PlannedCage& planned, const LimitReference& reference, uint32_t samplesPerSide) {
    const double diagonal = std::max(double(computeBounds(planned.cage()).diagonal()), 1e-30);
    const uint32_t n = std::max(samplesPerSide, 2u);
    struct FaceError {
        double position = 0.0, derivative = 0.0;
        uint32_t samples = 0;
    };
    std::vector<FaceError> errors(planned.subfaceCount());
    tbb::parallel_for(uint32_t(0), planned.subfaceCount(), [&](uint32_t s) {
        if (!planned.hasSurface(s)) return;
        FaceError& e = errors[s];
        for (uint32_t j = 0; j < n; ++j)
            for (uint32_t i = 0; i < n; ++i) {
                double u = double(i) / double(n - 1), v = double(j) / double(n - 1);
                LimitSample ours = planned.evaluate(s, float(u), float(v));
                ReferenceSample ref = reference.evaluate(s, u, v);
                e.position = std::max(e.position, glm::length(glm::dvec3(ours.position) - ref.position) / diagonal);
                e.derivative = std::max({e.derivative, glm::length(glm::dvec3(ours.du) - ref.du) / diagonal,
                                         glm::length(glm::dvec3(ours.dv) - ref.dv) / diagonal});
                ++e.samples;
            }
    });

    LimitCheck check;
    check.depth = planned.options().maxDepth;
    for (uint32_t s = 0; s < errors.size(); ++s) {
        if (errors[s].samples == 0) continue;
        ++check.subfaces;
        check.samples += errors[s].samples;
        if (errors[s].position > check.maxPositionError) {
            check.maxPositionError = errors[s].position;
            check.worstPositionSubface = s;
        }
        if (errors[s].derivative > check.maxDerivativeError) {
            check.maxDerivativeError = errors[s].derivative;
            check.worstDerivativeSubface = s;
        }
    }
    return check;
}

}  // namespace qp
