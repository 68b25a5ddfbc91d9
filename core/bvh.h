// BoxBvh: a bounding-volume hierarchy over axis-aligned boxes, for ray queries (picking).
//
// Built top-down (split at the median of the longest axis of the box centres), stored as a
// flat node array; leaves hold up to four items. A query visits the items whose boxes the ray
// enters before the current nearest hit, nearer nodes first, and lets the caller test them.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace qp {

struct Box {
    glm::vec3 min{std::numeric_limits<float>::infinity()};
    glm::vec3 max{-std::numeric_limits<float>::infinity()};
    void add(const glm::vec3& p);
    void add(const Box& b);
    bool empty() const { return min.x > max.x; }
};

// Ray-box slab test: the distance at which the ray (origin, 1 / direction) enters the box, or
// +infinity when it misses it or enters it after tMax.
float rayEntersBox(const Box& box, const glm::vec3& origin, const glm::vec3& inverseDirection, float tMax);

// Möller-Trumbore: distance along the ray and barycentrics (b1, b2) of the hit with triangle
// (p0, p1, p2), both sides; false when the ray misses or the triangle is degenerate.
bool rayHitsTriangle(const glm::vec3& origin, const glm::vec3& direction, const glm::vec3& p0, const glm::vec3& p1,
                     const glm::vec3& p2, float& t, float& b1, float& b2);

class BoxBvh {
public:
    BoxBvh() = default;
    explicit BoxBvh(std::span<const Box> boxes);  // empty boxes are left out

    // Calls test(item, tMax) for candidate items; test returns the new tMax (its nearest hit
    // so far, or tMax unchanged). Returns the final tMax.
    float traverse(const glm::vec3& origin, const glm::vec3& direction, float tMax,
                   const std::function<float(uint32_t item, float tMax)>& test) const;

private:
    struct Node {
        Box box;
        uint32_t first = 0, count = 0;  // leaf: items_[first, first + count)
        uint32_t left = 0, right = 0;   // internal (count == 0): the children
    };
    uint32_t build(std::span<const Box> boxes, uint32_t begin, uint32_t end);

    std::vector<Node> nodes_;
    std::vector<uint32_t> items_;
    std::vector<glm::vec3> centres_;
};

}  // namespace qp
