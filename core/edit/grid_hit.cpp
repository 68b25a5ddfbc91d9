#include "edit/grid_hit.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "edit/bvh.h"

namespace qp {

namespace {

// Whether the ray may pass through a cell whose corners are given in the ray's frame (across,
// across, along) before tMax: its axis (x = y = 0) inside the corners' rectangle, and the
// corners not all behind the origin nor all beyond tMax (a hit's distance lies between its
// corners'). The slack, a thousandth of the cell and the rounding of coordinates as far away
// as the cell, is far above rayHitsTriangle's own slack and rounding.
bool mayCross(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, const glm::vec3& d, float tMax) {
    const glm::vec3 lo = glm::min(glm::min(a, b), glm::min(c, d));
    const glm::vec3 hi = glm::max(glm::max(a, b), glm::max(c, d));
    const float extent = std::max(hi.x - lo.x, hi.y - lo.y);
    const float far = std::max(std::fabs(lo.z), std::fabs(hi.z)) + extent;
    const float slack = 1e-3f * extent + 1e-6f * far;
    return lo.x <= slack && hi.x >= -slack && lo.y <= slack && hi.y >= -slack && hi.z >= -slack &&
           lo.z <= tMax + slack;
}

}  // namespace

RayFrame::RayFrame(const glm::vec3& origin, const glm::vec3& direction) : origin(origin), direction(direction) {
    const glm::vec3 side = std::fabs(direction.x) < 0.5f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    across1 = glm::normalize(glm::cross(direction, side));
    across2 = glm::cross(direction, across1);
}

CellRange CellRange::quadrant(uint32_t n, uint32_t q) {
    const uint32_t half = n / 2;
    const bool highI = (q & 1) != 0, highJ = (q & 2) != 0;
    return {highI ? half : 0, highI ? n : half, highJ ? half : 0, highJ ? n : half};
}

GridHit nearestGridHit(const RayFrame& ray, const glm::vec3* grid, uint32_t n, CellRange cells, float tMax,
                       std::vector<glm::vec3>& scratch) {
    GridHit hit;
    if (cells.i0 >= cells.i1 || cells.j0 >= cells.j1) return hit;
    const uint32_t row = n + 1;
    if (scratch.size() < size_t(row) * row) scratch.resize(size_t(row) * row);
    for (uint32_t j = cells.j0; j <= cells.j1; ++j)
        for (uint32_t i = cells.i0; i <= cells.i1; ++i) {
            const glm::vec3 q = grid[j * row + i] - ray.origin;
            scratch[j * row + i] = {glm::dot(q, ray.across1), glm::dot(q, ray.across2), glm::dot(q, ray.direction)};
        }
    for (uint32_t j = cells.j0; j < cells.j1; ++j)
        for (uint32_t i = cells.i0; i < cells.i1; ++i) {
            const uint32_t c = j * row + i;
            if (!mayCross(scratch[c], scratch[c + 1], scratch[c + row], scratch[c + row + 1], tMax)) continue;
            const glm::vec3 &p00 = grid[c], &p10 = grid[c + 1], &p01 = grid[c + row], &p11 = grid[c + row + 1];
            float t, b1, b2;
            if (rayHitsTriangle(ray.origin, ray.direction, p00, p10, p11, t, b1, b2) && t < tMax) {
                tMax = t;
                hit = {t, (float(i) + b1 + b2) / float(n), (float(j) + b2) / float(n)};
            }
            if (rayHitsTriangle(ray.origin, ray.direction, p00, p11, p01, t, b1, b2) && t < tMax) {
                tMax = t;
                hit = {t, (float(i) + b1) / float(n), (float(j) + b1 + b2) / float(n)};
            }
        }
    return hit;
}

}  // namespace qp
