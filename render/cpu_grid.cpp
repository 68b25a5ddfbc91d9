#include "cpu_grid.h"

#include <cmath>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace qp {

namespace {

// Sub-faces per task: a few thousand evaluations, so scheduling is noise.
constexpr size_t kGrain = 16;

// Drawn sub-faces list[0 .. count), or 0 .. count when `list` is null.
template <class Body>
void forEachSubface(const uint32_t* list, size_t count, const Body& body) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kGrain), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t k = range.begin(); k != range.end(); ++k) body(list ? list[k] : uint32_t(k));
    });
}

void evaluatePhase(const PlannedCage& planned, const GpuPlanData& data, const GridLayout& layout, const uint32_t* list,
                   size_t count, GridVertex* grid) {
    forEachSubface(list, count, [&](uint32_t drawn) {
        const uint32_t subface = data.subfaces[drawn].subface, n = layout.factors.subfaceFactor[drawn];
        const uint32_t first = layout.subfaceOffset[drawn], end = layout.subfaceOffset[drawn + 1];
        for (uint32_t slot = first; slot < end; ++slot) {
            if (layout.source[slot] != slot) continue;
            float u, v;
            slotParameter(slot - first, n, u, v);
            const LimitSample s = planned.evaluate(subface, u, v);
            glm::vec3 normal = glm::cross(s.du, s.dv);
            const float length = glm::length(normal);
            normal = length > 0.0f ? normal / length : glm::vec3(0.0f);
            grid[slot] = GridVertex{{s.position.x, s.position.y, s.position.z}, {normal.x, normal.y, normal.z}};
        }
    });
}

void copyPhase(const GridLayout& layout, const uint32_t* list, size_t count, GridVertex* grid) {
    forEachSubface(list, count, [&](uint32_t drawn) {
        for (uint32_t slot = layout.subfaceOffset[drawn]; slot < layout.subfaceOffset[drawn + 1]; ++slot)
            if (layout.source[slot] != slot) grid[slot] = grid[layout.source[slot]];
    });
}

}  // namespace

void evaluateGridOnCpu(const PlannedCage& planned, const GpuPlanData& data, const GridLayout& layout,
                       std::span<const uint32_t> evaluate, std::span<const uint32_t> copy, GridVertex* grid) {
    evaluatePhase(planned, data, layout, evaluate.data(), evaluate.size(), grid);
    copyPhase(layout, copy.data(), copy.size(), grid);
}

void evaluateWholeGridOnCpu(const PlannedCage& planned, const GpuPlanData& data, const GridLayout& layout,
                            GridVertex* grid) {
    evaluatePhase(planned, data, layout, nullptr, data.subfaces.size(), grid);
    copyPhase(layout, nullptr, data.subfaces.size(), grid);
}

}  // namespace qp
