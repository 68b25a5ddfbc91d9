#include "plan_memory.h"

#include <glm/vec4.hpp>

#include "gpu_plans.h"

namespace qp {

namespace {

template <class T>
uint64_t bytes(const std::vector<T>& v) {
    return uint64_t(v.size()) * sizeof(T);
}

}  // namespace

PlanMemory measurePlanMemory(const PlannedCage& planned) {
    const GpuPlanData d = packPlans(planned);
    PlanMemory m;
    m.vertexBytes = uint64_t(planned.cage().vertexCount()) * sizeof(glm::vec4);
    m.indexBytes = bytes(d.rings) + bytes(d.subfaces) + bytes(d.boundaries) + bytes(d.segments) + bytes(d.boundaryPoints);
    m.plans = uint32_t(d.plans.size());
    m.quadtreeBytes = bytes(d.plans) + bytes(d.nodes) + bytes(d.points);
    m.stencilBytes = bytes(d.weights);
    m.scratchBytes = uint64_t(d.controlPointCount) * sizeof(glm::vec4);
    return m;
}

}  // namespace qp
