#include "edit/bvh.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

namespace qp {

void growForRounding(Box& box) {
    if (box.empty()) return;
    const glm::vec3 magnitude = glm::max(glm::abs(box.min), glm::abs(box.max));
    const glm::vec3 pad = glm::vec3(1e-4f * glm::length(box.max - box.min)) + 1e-6f * magnitude;
    box.min -= pad;
    box.max += pad;
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

}  // namespace qp
