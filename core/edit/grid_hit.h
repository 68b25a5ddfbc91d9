// A ray against a surface sampled on a grid: (n + 1)^2 points, row after row, as 2 n^2
// triangles (00, 10, 11) and (00, 11, 01) per cell. What the limit-surface and displaced
// pickers test for every sub-face a picking ray's BVH query reaches.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include <glm/vec3.hpp>

namespace qp {

// Two unit vectors across a ray's direction (unit length): with it, the frame in which the
// cells a ray passes through are found without testing their triangles.
struct RayFrame {
    glm::vec3 origin{0.0f}, direction{0.0f, 0.0f, -1.0f};
    glm::vec3 across1{1.0f, 0.0f, 0.0f}, across2{0.0f, 1.0f, 0.0f};
    RayFrame(const glm::vec3& origin, const glm::vec3& direction);
};

struct GridHit {
    float distance = std::numeric_limits<float>::infinity();  // along the ray; infinity: none
    float u = 0.0f, v = 0.0f;  // in the grid's parameters, 0..1, interpolated linearly
    bool hit() const { return distance != std::numeric_limits<float>::infinity(); }
};

// Cells [i0, i1) x [j0, j1) of a grid of n x n cells.
struct CellRange {
    uint32_t i0 = 0, i1 = 0, j0 = 0, j1 = 0;
    static CellRange all(uint32_t n) { return {0, n, 0, n}; }
    // Quadrant q (0..3: i low/high, then j low/high), split at n / 2; n >= 2.
    static CellRange quadrant(uint32_t n, uint32_t q);
};

// The nearest hit before tMax with the triangles of the range's cells (each tested by
// rayHitsTriangle, both sides); cells whose projection across the ray cannot hold it are passed
// over first, with a slack that never passes over a cell rayHitsTriangle would hit. `scratch`
// is working memory (reused between calls to save allocations).
GridHit nearestGridHit(const RayFrame& ray, const glm::vec3* grid, uint32_t n, CellRange cells, float tMax,
                       std::vector<glm::vec3>& scratch);

}  // namespace qp
