#include "edit/bvh.h"

#include <algorithm>
#include <array>
#include <cassert>
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
    itemBoxes_.resize(items_.size());
    for (size_t k = 0; k < items_.size(); ++k) itemBoxes_[k] = boxes[items_[k]];
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

void BoxBvh::refit(std::span<const Box> boxes) {
    // Children come after their parent in nodes_ (built depth first), so a backward pass sees
    // both children of a node before the node.
    for (size_t i = nodes_.size(); i-- > 0;) {
        Node& node = nodes_[i];
        node.box = Box{};
        if (node.count > 0) {
            for (uint32_t k = node.first; k < node.first + node.count; ++k) {
                assert(!boxes[items_[k]].empty());
                itemBoxes_[k] = boxes[items_[k]];
                node.box.add(itemBoxes_[k]);
            }
        } else {
            node.box.add(nodes_[node.left].box);
            node.box.add(nodes_[node.right].box);
        }
    }
}

float BoxBvh::traverse(const glm::vec3& origin, const glm::vec3& direction, float tMax,
                       const std::function<float(uint32_t, float)>& test) const {
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
