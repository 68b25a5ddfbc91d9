#include "bvh.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace qp {

void Box::add(const glm::vec3& p) {
    min = glm::min(min, p);
    max = glm::max(max, p);
}

void Box::add(const Box& b) {
    min = glm::min(min, b.min);
    max = glm::max(max, b.max);
}

float rayEntersBox(const Box& box, const glm::vec3& origin, const glm::vec3& inverseDirection, float tMax) {
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

bool rayHitsTriangle(const glm::vec3& origin, const glm::vec3& direction, const glm::vec3& p0, const glm::vec3& p1,
                     const glm::vec3& p2, float& t, float& b1, float& b2) {
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

BoxBvh::BoxBvh(std::span<const Box> boxes) {
    for (uint32_t i = 0; i < boxes.size(); ++i)
        if (!boxes[i].empty()) items_.push_back(i);
    centres_.resize(boxes.size());
    for (uint32_t i : items_) centres_[i] = 0.5f * (boxes[i].min + boxes[i].max);
    if (!items_.empty()) {
        nodes_.reserve(2 * items_.size());
        build(boxes, 0, uint32_t(items_.size()));
    }
    centres_.clear();
    centres_.shrink_to_fit();
}

uint32_t BoxBvh::build(std::span<const Box> boxes, uint32_t begin, uint32_t end) {
    const uint32_t index = uint32_t(nodes_.size());
    nodes_.push_back({});
    Box box, centres;
    for (uint32_t i = begin; i < end; ++i) {
        box.add(boxes[items_[i]]);
        centres.add(centres_[items_[i]]);
    }
    nodes_[index].box = box;
    if (end - begin <= 4) {
        nodes_[index].first = begin;
        nodes_[index].count = end - begin;
        return index;
    }
    const glm::vec3 extent = centres.max - centres.min;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const uint32_t middle = begin + (end - begin) / 2;
    std::nth_element(items_.begin() + begin, items_.begin() + middle, items_.begin() + end,
                     [&](uint32_t a, uint32_t b) { return centres_[a][axis] < centres_[b][axis]; });
    const uint32_t left = build(boxes, begin, middle);
    const uint32_t right = build(boxes, middle, end);
    nodes_[index].left = left;
    nodes_[index].right = right;
    return index;
}

float BoxBvh::traverse(const glm::vec3& origin, const glm::vec3& direction, float tMax,
                       const std::function<float(uint32_t, float)>& test) const {
    if (nodes_.empty()) return tMax;
    const glm::vec3 inverse = 1.0f / direction;
    struct Entry {
        uint32_t node;
        float entry;
    };
    std::vector<Entry> stack;
    stack.push_back({0, rayEntersBox(nodes_[0].box, origin, inverse, tMax)});
    while (!stack.empty()) {
        Entry e = stack.back();
        stack.pop_back();
        if (!(e.entry <= tMax)) continue;
        const Node& node = nodes_[e.node];
        if (node.count > 0) {
            for (uint32_t i = node.first; i < node.first + node.count; ++i) tMax = test(items_[i], tMax);
            continue;
        }
        const uint32_t a = node.left, b = node.right;
        const float ta = rayEntersBox(nodes_[a].box, origin, inverse, tMax);
        const float tb = rayEntersBox(nodes_[b].box, origin, inverse, tMax);
        // Push the farther first so the nearer is visited first.
        if (ta <= tb) {
            stack.push_back({b, tb});
            stack.push_back({a, ta});
        } else {
            stack.push_back({a, ta});
            stack.push_back({b, tb});
        }
    }
    return tMax;
}

}  // namespace qp
