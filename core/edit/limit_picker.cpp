// LimitPicker: ray picking on the limit surface (see picking.h).
#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <tbb/parallel_for.h>

#include "edit/grid_hit.h"
#include "edit/picking.h"

namespace qp {

namespace {

// Newton may move a sampled hit along the ray by less than this fraction of its sub-face's size
// (farther, it has converged onto another sheet of the surface and the sampled hit is kept).
constexpr float kRefineWindow = 0.25f;

float sizeOf(const Box& box) {
    return std::max(glm::length(box.max - box.min), 1e-6f);
}

}  // namespace

LimitPicker::LimitPicker(const PlannedCage& planned, uint32_t resolution) : resolution_(std::max(1u, resolution)) {
    EditReport everything;
    everything.topologyChanged = true;
    update(planned, everything);
}

uint32_t LimitPicker::resolutionFor(uint32_t subfaces) {
    constexpr double kSampleBudget = double(1u << 24);
    const double side = std::sqrt(kSampleBudget / std::max(1u, subfaces));
    return uint32_t(std::clamp(side - 1.0, 2.0, 8.0));
}

void LimitPicker::sample(const PlannedCage& planned, uint32_t subface) {
    boxes_[subface] = Box{};
    if (hasQuadrants()) quadrantBoxes_[subface] = {};
    if (!planned.hasSurface(subface)) return;
    const uint32_t n = resolution_;
    glm::vec3* grid = samples_.data() + size_t(subface) * stride();
    thread_local std::vector<glm::vec3> scratch;
    const std::span<const glm::vec3> controlPoints = planned.controlPointsFor(subface, stencilLevelFor(n), scratch);
    for (uint32_t j = 0; j <= n; ++j)
        for (uint32_t i = 0; i <= n; ++i) {
            grid[j * (n + 1) + i] = planned.evaluate(subface, controlPoints, float(i) / float(n), float(j) / float(n)).position;
            boxes_[subface].add(grid[j * (n + 1) + i]);
        }
    growForRounding(boxes_[subface]);
    if (hasQuadrants())
        for (uint32_t q = 0; q < 4; ++q) {
            Box& box = quadrantBoxes_[subface][q];
            const CellRange cells = CellRange::quadrant(n, q);
            for (uint32_t j = cells.j0; j <= cells.j1; ++j)
                for (uint32_t i = cells.i0; i <= cells.i1; ++i) box.add(grid[j * (n + 1) + i]);
            growForRounding(box);
        }
}

void LimitPicker::rebuildBvh() {
    bvh_ = BoxBvh(boxes_);
    largestSubface_ = 0.0f;
    for (const Box& box : boxes_)
        if (!box.empty()) largestSubface_ = std::max(largestSubface_, sizeOf(box));
}

void LimitPicker::update(const PlannedCage& planned, const EditReport& report) {
    const uint32_t count = planned.subfaceCount();
    const bool carried = report.topologyChanged && report.previousSubfaceOf.size() == count && !boxes_.empty();
    if (carried) {  // kept sub-faces take their samples along; new and updated ones are sampled
        const std::vector<Box> boxesBefore = std::move(boxes_);
        const std::vector<std::array<Box, 4>> quadrantsBefore = std::move(quadrantBoxes_);
        const uint32_t before = uint32_t(boxesBefore.size());
        boxes_.assign(count, Box{});
        quadrantBoxes_.assign(hasQuadrants() ? count : 0, {});
        std::vector<uint32_t> stale = report.updatedSubfaceList;
        std::vector<std::pair<uint32_t, uint32_t>> kept;  // (now, before), ascending in both
        for (uint32_t s = 0; s < count; ++s) {
            const uint32_t previous = report.previousSubfaceOf[s];
            if (previous == kNewElement || previous >= before || (!kept.empty() && previous <= kept.back().second)) {
                stale.push_back(s);  // new, or out of order (sampled again rather than moved)
                continue;
            }
            kept.push_back({s, previous});
            boxes_[s] = boxesBefore[previous];
            if (hasQuadrants()) quadrantBoxes_[s] = quadrantsBefore[previous];
        }
        // The samples move inside their own array (a fresh one of a million sub-faces' samples
        // costs more in page faults than sampling them): kept sub-faces keep their order, so
        // moving down in ascending order, then up in descending order, overwrites nothing unmoved.
        const size_t largest = size_t(std::max(count, before)) * stride();
        if (samples_.capacity() < largest) samples_.reserve(largest + largest / 8);
        samples_.resize(largest);
        auto move = [&](const std::pair<uint32_t, uint32_t>& k) {
            std::memmove(samples_.data() + size_t(k.first) * stride(), samples_.data() + size_t(k.second) * stride(),
                         stride() * sizeof(glm::vec3));
        };
        for (const auto& k : kept)
            if (k.first < k.second) move(k);
        for (auto k = kept.rbegin(); k != kept.rend(); ++k)
            if (k->first > k->second) move(*k);
        samples_.resize(size_t(count) * stride());
        std::sort(stale.begin(), stale.end());
        stale.erase(std::unique(stale.begin(), stale.end()), stale.end());
        tbb::parallel_for(size_t(0), stale.size(), [&](size_t i) { sample(planned, stale[i]); });
    } else if (report.topologyChanged || boxes_.size() != count) {
        // Room for sub-faces that topology edits add later (reserved, so never touched until used).
        samples_.reserve(size_t(count) * stride() + size_t(count) * stride() / 8);
        samples_.resize(size_t(count) * stride());
        boxes_.assign(count, Box{});
        quadrantBoxes_.assign(hasQuadrants() ? count : 0, {});
        tbb::parallel_for(uint32_t(0), count, [&](uint32_t s) { sample(planned, s); });
    } else {
        const std::vector<uint32_t>& list = report.updatedSubfaceList;
        std::vector<uint8_t> hadSurface(list.size());
        for (size_t i = 0; i < list.size(); ++i) hadSurface[i] = !boxes_[list[i]].empty();
        tbb::parallel_for(size_t(0), list.size(), [&](size_t i) { sample(planned, list[i]); });
        bool sameSurfaces = true;
        for (size_t i = 0; i < list.size(); ++i) sameSurfaces = sameSurfaces && hadSurface[i] == !boxes_[list[i]].empty();
        if (sameSurfaces) {
            bvh_.refit(boxes_);
            for (uint32_t s : list) largestSubface_ = std::max(largestSubface_, boxes_[s].empty() ? 0.0f : sizeOf(boxes_[s]));
            return;
        }
    }
    rebuildBvh();
}

LimitPicker::Hit LimitPicker::sampledHit(const Ray& ray, float maxDistance) const {
    Hit hit;
    const RayFrame frame(ray.origin, ray.direction);
    thread_local std::vector<glm::vec3> scratchOfThread;
    std::vector<glm::vec3>& scratch = scratchOfThread;
    const glm::vec3 inverse = 1.0f / ray.direction;
    bvh_.traverse(ray.origin, ray.direction, maxDistance, [&](uint32_t s, float tMax) {
        const glm::vec3* grid = samples_.data() + size_t(s) * stride();
        auto test = [&](CellRange cells) {
            const GridHit g = nearestGridHit(frame, grid, resolution_, cells, tMax, scratch);
            if (!g.hit()) return;
            hit = {s, g.u, g.v, ray.origin + g.distance * ray.direction, g.distance, false};
            tMax = g.distance;
        };
        if (!hasQuadrants()) {
            test(CellRange::all(resolution_));
            return tMax;
        }
        for (uint32_t q = 0; q < 4; ++q)
            if (std::isfinite(rayEntersBox(quadrantBoxes_[s][q], ray.origin, inverse, tMax)))
                test(CellRange::quadrant(resolution_, q));
        return tMax;
    });
    return hit;
}

LimitPicker::Hit LimitPicker::refined(const PlannedCage& planned, const Ray& ray, Hit hit) const {
    // Newton on P(u, v) = origin + t direction, unknowns (u, v, t).
    const float scale = sizeOf(boxes_[hit.subface]);
    const float tolerance = 1e-6f * std::max(scale, glm::length(hit.position));
    float u = hit.u, v = hit.v, t = hit.distance;
    for (int iteration = 0; iteration < 12; ++iteration) {
        const LimitSample sample = planned.evaluate(hit.subface, std::clamp(u, 0.0f, 1.0f), std::clamp(v, 0.0f, 1.0f));
        const glm::vec3 residual = sample.position - (ray.origin + t * ray.direction);
        if (glm::length(residual) <= tolerance) {
            if (std::fabs(t - hit.distance) < kRefineWindow * scale) {
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

LimitPicker::Hit LimitPicker::intersect(const PlannedCage& planned, const Ray& ray, float maxDistance) const {
    const Hit hit = sampledHit(ray, maxDistance);
    return hit.subface == kNoHit ? hit : refined(planned, ray, hit);
}

bool LimitPicker::hides(const PlannedCage& planned, const Ray& ray, float distance) const {
    if (!(distance > 0.0f)) return false;
    // Refining moves a hit by less than its window, so a nearest sampled hit beyond `reach`
    // cannot refine to before `distance`, and one whose whole window lies before (or after) it
    // needs no refining.
    const float reach = distance + kRefineWindow * largestSubface_;
    const Hit hit = sampledHit(ray, reach);
    if (hit.subface == kNoHit) return false;
    const float window = kRefineWindow * sizeOf(boxes_[hit.subface]);
    if (hit.distance + window < distance) return true;
    if (hit.distance - window >= distance) return false;
    return refined(planned, ray, hit).distance < distance;
}

}  // namespace qp
