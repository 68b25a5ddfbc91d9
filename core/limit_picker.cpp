// LimitPicker: ray picking on the limit surface (see picking.h).
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <tbb/parallel_for.h>

#include "picking.h"

namespace qp {

LimitPicker::LimitPicker(const PlannedCage& planned, uint32_t resolution) : resolution_(std::max(1u, resolution)) {
    EditReport everything;
    everything.topologyChanged = true;
    update(planned, everything);
}

void LimitPicker::sample(const PlannedCage& planned, uint32_t subface) {
    std::vector<glm::vec3>& grid = grids_[subface];
    boxes_[subface] = Box{};
    if (!planned.hasSurface(subface)) {
        grid.clear();
        return;
    }
    const uint32_t n = resolution_;
    grid.resize((n + 1) * (n + 1));
    for (uint32_t j = 0; j <= n; ++j)
        for (uint32_t i = 0; i <= n; ++i) {
            grid[j * (n + 1) + i] = planned.evaluate(subface, float(i) / float(n), float(j) / float(n)).position;
            boxes_[subface].add(grid[j * (n + 1) + i]);
        }
}

void LimitPicker::rebuildBvh() {
    bvh_ = BoxBvh(boxes_);
}

void LimitPicker::update(const PlannedCage& planned, const EditReport& report) {
    const bool carried = report.topologyChanged && report.previousSubfaceOf.size() == planned.subfaceCount() &&
                         !grids_.empty();
    if (carried) {  // kept sub-faces take their grids along; new and updated ones are sampled
        std::vector<std::vector<glm::vec3>> before = std::move(grids_);
        std::vector<Box> boxesBefore = std::move(boxes_);
        grids_.assign(planned.subfaceCount(), {});
        boxes_.assign(planned.subfaceCount(), Box{});
        std::vector<uint32_t> stale = report.updatedSubfaceList;
        for (uint32_t s = 0; s < planned.subfaceCount(); ++s) {
            const uint32_t previous = report.previousSubfaceOf[s];
            if (previous == kNewElement || previous >= before.size()) {
                stale.push_back(s);
                continue;
            }
            grids_[s] = std::move(before[previous]);
            boxes_[s] = boxesBefore[previous];
        }
        std::sort(stale.begin(), stale.end());
        stale.erase(std::unique(stale.begin(), stale.end()), stale.end());
        tbb::parallel_for(size_t(0), stale.size(), [&](size_t i) { sample(planned, stale[i]); });
    } else if (report.topologyChanged || grids_.size() != planned.subfaceCount()) {
        grids_.assign(planned.subfaceCount(), {});
        boxes_.assign(planned.subfaceCount(), Box{});
        tbb::parallel_for(uint32_t(0), planned.subfaceCount(), [&](uint32_t s) { sample(planned, s); });
    } else {
        const std::vector<uint32_t>& list = report.updatedSubfaceList;
        tbb::parallel_for(size_t(0), list.size(), [&](size_t i) { sample(planned, list[i]); });
    }
    rebuildBvh();
}

LimitPicker::Hit LimitPicker::intersect(const PlannedCage& planned, const Ray& ray, float maxDistance) const {
    Hit hit;
    const uint32_t n = resolution_;
    bvh_.traverse(ray.origin, ray.direction, maxDistance, [&](uint32_t s, float tMax) {
        const std::vector<glm::vec3>& g = grids_[s];
        for (uint32_t j = 0; j < n; ++j)
            for (uint32_t i = 0; i < n; ++i) {
                const glm::vec3& p00 = g[j * (n + 1) + i];
                const glm::vec3& p10 = g[j * (n + 1) + i + 1];
                const glm::vec3& p01 = g[(j + 1) * (n + 1) + i];
                const glm::vec3& p11 = g[(j + 1) * (n + 1) + i + 1];
                float t, b1, b2;
                // Triangles (00, 10, 11) and (00, 11, 01), parameters interpolated linearly.
                if (rayHitsTriangle(ray.origin, ray.direction, p00, p10, p11, t, b1, b2) && t < tMax) {
                    tMax = t;
                    hit = {s, (float(i) + b1 + b2) / float(n), (float(j) + b2) / float(n), ray.origin + t * ray.direction, t, false};
                }
                if (rayHitsTriangle(ray.origin, ray.direction, p00, p11, p01, t, b1, b2) && t < tMax) {
                    tMax = t;
                    hit = {s, (float(i) + b1) / float(n), (float(j) + b1 + b2) / float(n), ray.origin + t * ray.direction, t, false};
                }
            }
        return tMax;
    });
    if (hit.subface == kNoHit) return hit;

    // Newton on P(u, v) = origin + t direction, unknowns (u, v, t).
    const Box& box = boxes_[hit.subface];
    const float scale = std::max(glm::length(box.max - box.min), 1e-6f);
    const float tolerance = 1e-6f * std::max(scale, glm::length(hit.position));
    float u = hit.u, v = hit.v, t = hit.distance;
    for (int iteration = 0; iteration < 12; ++iteration) {
        const LimitSample sample = planned.evaluate(hit.subface, std::clamp(u, 0.0f, 1.0f), std::clamp(v, 0.0f, 1.0f));
        const glm::vec3 residual = sample.position - (ray.origin + t * ray.direction);
        if (glm::length(residual) <= tolerance) {
            if (std::fabs(t - hit.distance) < 0.25f * scale) {
                hit.u = std::clamp(u, 0.0f, 1.0f);
                hit.v = std::clamp(v, 0.0f, 1.0f);
                hit.position = sample.position;
                hit.distance = t;
                hit.refined = true;
            }
            break;
        }
        const glm::mat3 jacobian(sample.du, sample.dv, -ray.direction);
        if (!(std::fabs(glm::determinant(jacobian)) > 1e-20f)) break;
        const glm::vec3 step = glm::inverse(jacobian) * (-residual);
        u += step.x;
        v += step.y;
        t += step.z;
        if (u < -1e-3f || u > 1.001f || v < -1e-3f || v > 1.001f || !std::isfinite(t)) break;  // left the sub-face
    }
    return hit;
}

}  // namespace qp
