// BoxBvh: a bounding-volume hierarchy over axis-aligned boxes, for ray queries (picking).
//
// Built top-down (split at the median of the longest axis of the box centres), stored as a
// flat node array; leaves hold up to four items. A query visits the items whose boxes the ray
// enters before the current nearest hit, nearer nodes first, and lets the caller test them.
#pragma once

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace qp {

struct Box {
    glm::vec3 min{std::numeric_limits<float>::infinity()};
    glm::vec3 max{-std::numeric_limits<float>::infinity()};
    void add(const glm::vec3& p) { min = glm::min(min, p), max = glm::max(max, p); }
    void add(const Box& b) { min = glm::min(min, b.min), max = glm::max(max, b.max); }
    bool empty() const { return min.x > max.x; }
};

// A box of samples grown by a hair (1e-4 of its size and the rounding of its coordinates), so
// the slab test's rounding cannot lose a ray through a sample on its boundary: an extreme
// point of the surface, a flat patch (a box of no thickness), a line two boxes share.
void growForRounding(Box& box);

// Ray-box slab test: the distance at which the ray (origin, 1 / direction) enters the box, or
// +infinity when it misses it or enters it after tMax. (This and the triangle test are inline:
// a picking ray calls them for every box and triangle it passes.)
inline float rayEntersBox(const Box& box, const glm::vec3& origin, const glm::vec3& inverseDirection, float tMax) {
    float t0 = 0.0f, t1 = tMax;
    for (int a = 0; a < 3; ++a) {
        // A ray parallel to the slab (an infinite inverse) is inside it or misses the box: the
        // products below would be 0 * inf = NaN for an origin on the slab's plane.
        if (std::isinf(inverseDirection[a])) {
            if (origin[a] < box.min[a] || origin[a] > box.max[a]) return std::numeric_limits<float>::infinity();
            continue;
        }
        float near = (box.min[a] - origin[a]) * inverseDirection[a];
        float far = (box.max[a] - origin[a]) * inverseDirection[a];
        if (near > far) std::swap(near, far);
        if (near > t0) t0 = near;
        if (far < t1) t1 = far;
        if (t0 > t1) return std::numeric_limits<float>::infinity();
    }
    return t0;
}

// Möller-Trumbore: distance along the ray and barycentrics (b1, b2) of the hit with triangle
// (p0, p1, p2), both sides; false when the ray misses or the triangle is degenerate.
inline bool rayHitsTriangle(const glm::vec3& origin, const glm::vec3& direction, const glm::vec3& p0,
                            const glm::vec3& p1, const glm::vec3& p2, float& t, float& b1, float& b2) {
    const glm::vec3 e1 = p1 - p0, e2 = p2 - p0;
    const glm::vec3 p = glm::cross(direction, e2);
    const float det = glm::dot(e1, p);
    if (std::fabs(det) < 1e-20f) return false;
    const float inv = 1.0f / det;
    const glm::vec3 s = origin - p0;
    // A ray through the edge two triangles share must hit one of them: rounding can put it a
    // hair outside both (a ray along a symmetry plane of the model does that every time), so the
    // test lets barycentrics a hair past the edges count.
    constexpr float kEdgeSlack = 1e-5f;
    b1 = glm::dot(s, p) * inv;
    if (b1 < -kEdgeSlack || b1 > 1.0f + kEdgeSlack) return false;
    const glm::vec3 q = glm::cross(s, e1);
    b2 = glm::dot(direction, q) * inv;
    if (b2 < -kEdgeSlack || b1 + b2 > 1.0f + kEdgeSlack) return false;
    b1 = std::clamp(b1, 0.0f, 1.0f);
    b2 = std::clamp(b2, 0.0f, 1.0f - b1);
    t = glm::dot(e2, q) * inv;
    return t >= 0.0f;
}

class BoxBvh {
public:
    BoxBvh() = default;
    explicit BoxBvh(std::span<const Box> boxes);  // empty boxes are left out

    // The same items with new boxes (say, after their contents moved): every node's box made
    // again from them, the tree kept. Valid while the same boxes are empty as at the build;
    // cheaper than a build, and the tree may fit less tightly than a new one would.
    void refit(std::span<const Box> boxes);

    // Calls test(item, tMax) for candidate items; test returns the new tMax (its nearest hit
    // so far, or tMax unchanged). Returns the final tMax. A template, so the test (called for
    // every item a picking ray reaches) is inlined rather than called through a pointer.
    template <typename Test>
    float traverse(const glm::vec3& origin, const glm::vec3& direction, float tMax, Test&& test) const;

private:
    struct Node {
        Box box;
        uint32_t first = 0, count = 0;  // leaf: items_[first, first + count)
        uint32_t left = 0, right = 0;   // internal (count == 0): the children
    };
    uint32_t build(std::span<const Box> boxes, uint32_t begin, uint32_t end);

    std::vector<Node> nodes_;
    std::vector<uint32_t> items_;
    std::vector<Box> itemBoxes_;  // items_[k]'s box
    std::vector<glm::vec3> centres_;
};

template <typename Test>
float BoxBvh::traverse(const glm::vec3& origin, const glm::vec3& direction, float tMax, Test&& test) const {
    if (nodes_.empty()) return tMax;
    const glm::vec3 inverse = 1.0f / direction;
    struct Entry {
        uint32_t node;
        float entry;
    };
    // A missed box enters at +infinity, which an unbounded query's tMax (+infinity) would admit.
    auto entered = [&](float entry) { return entry <= tMax && std::isfinite(entry); };
    // The tree splits at medians, so it is at most 32 levels deep and a stack holds at most one
    // entry a level plus one: no allocation per ray.
    std::array<Entry, 64> stack;
    size_t depth = 0;
    stack[depth++] = {0, rayEntersBox(nodes_[0].box, origin, inverse, tMax)};
    while (depth > 0) {
        const Entry e = stack[--depth];
        if (!entered(e.entry)) continue;
        const Node& node = nodes_[e.node];
        if (node.count > 0) {
            // A leaf holds several items: only those whose own box the ray enters are tested.
            for (uint32_t i = node.first; i < node.first + node.count; ++i)
                if (entered(rayEntersBox(itemBoxes_[i], origin, inverse, tMax))) tMax = test(items_[i], tMax);
            continue;
        }
        const uint32_t a = node.left, b = node.right;
        const float ta = rayEntersBox(nodes_[a].box, origin, inverse, tMax);
        const float tb = rayEntersBox(nodes_[b].box, origin, inverse, tMax);
        // Push the farther first so the nearer is visited first; missed children not at all.
        const Entry nearer = ta <= tb ? Entry{a, ta} : Entry{b, tb}, farther = ta <= tb ? Entry{b, tb} : Entry{a, ta};
        assert(depth + 2 <= stack.size());
        if (entered(farther.entry)) stack[depth++] = farther;
        if (entered(nearer.entry)) stack[depth++] = nearer;
    }
    return tMax;
}

}  // namespace qp
