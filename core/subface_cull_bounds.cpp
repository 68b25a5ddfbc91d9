#include "subface_cull_bounds.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "plan_database.h"
#include "topology.h"

namespace qp {

namespace {

// The 16 points of a regular leaf with the phantoms beyond its boundary edges made explicit:
// 2 p1 - p2 across the edge (bits as PlanNode::boundaryMask), corners phantoms of phantoms.
BicubicPoints withPhantoms(BicubicPoints p, uint32_t mask) {
    auto at = [&](int column, int row) -> glm::vec3& { return p[4 * row + column]; };
    for (int c = 0; c < 4; ++c) {
        if (mask & 1) at(c, 0) = 2.0f * at(c, 1) - at(c, 2);
        if (mask & 4) at(c, 3) = 2.0f * at(c, 2) - at(c, 1);
    }
    for (int r = 0; r < 4; ++r) {
        if (mask & 8) at(0, r) = 2.0f * at(1, r) - at(2, r);
        if (mask & 2) at(3, r) = 2.0f * at(2, r) - at(1, r);
    }
    return p;
}

// The crease edge of a Crease leaf as a boundary bit (the phantom rows are those of an
// infinitely sharp crease).
uint32_t creaseBit(uint32_t edge) { return edge == 0 ? 1u : edge == 1 ? 2u : edge == 2 ? 4u : 8u; }

void addLeaf(PatchCullLeaves& out, const Plan& plan, const PlanNode& node, const glm::vec3* control) {
    const uint32_t* points = &plan.points[node.first];
    auto gather20 = [&](const uint32_t* from) {
        std::array<glm::vec3, 20> g;
        for (uint32_t k = 0; k < 20; ++k) g[k] = control[from[k]];
        return g;
    };
    auto gather16 = [&](auto index) {
        BicubicPoints p;
        for (uint32_t k = 0; k < 16; ++k) p[k] = control[index(k)];
        return p;
    };
    switch (node.kind) {
    case NodeKind::Regular:
        addBezierLeaf(out, bsplineToBezier(withPhantoms(gather16([&](uint32_t k) { return points[k]; }), node.boundaryMask)),
                      false);
        break;
    case NodeKind::Crease: {
        const BicubicPoints real = gather16([&](uint32_t k) { return points[k]; });
        const BicubicPoints sharp = withPhantoms(real, node.boundaryMask | creaseBit(node.edge));
        if (node.sharpness >= kInfiniteSharpness) {
            addBezierLeaf(out, bsplineToBezier(sharp), false);
            break;
        }
        // Semi-sharp: sharp surface + c d, c in [0, 1/2], d = real - sharp beyond the crease.
        CullBox box = boxOf(bsplineToBezier(sharp));
        CullBox d{glm::vec3(0.0f), glm::vec3(0.0f)};
        for (uint32_t k = 0; k < 16; ++k) {
            const glm::vec3 difference = 0.5f * (withPhantoms(real, node.boundaryMask)[k] - sharp[k]);
            d.lo = glm::min(d.lo, difference), d.hi = glm::max(d.hi, difference);
        }
        box.lo += glm::min(d.lo, glm::vec3(0.0f));
        box.hi += glm::max(d.hi, glm::vec3(0.0f));
        addConelessBox(out, box);
        break;
    }
    case NodeKind::Terminal: {
        const bool mirrorU = node.edge == 1 || node.edge == 2, mirrorV = node.edge == 2 || node.edge == 3;
        // Per level the three regular windows of the 5 x 5 grid, quadrants (1, 0), (0, 1), (1, 1).
        constexpr uint32_t kQuadrants[3][2] = {{1, 0}, {0, 1}, {1, 1}};
        for (uint32_t level = 0; level < node.levels; ++level)
            for (const auto& quadrant : kQuadrants) {
                const uint32_t qx = quadrant[0], qy = quadrant[1];
                addBezierLeaf(out, bsplineToBezier(gather16([&](uint32_t k) {
                                  const uint32_t gx = qx + k % 4, gy = qy + k / 4;
                                  return points[kTerminalPointsPerLevel * level + gy * 5 + gx - 1];
                              })),
                              mirrorU != mirrorV);
            }
        // The Gregory patch at the bottom, evaluated in the node's own frame (plan_eval.cpp
        // un-mirrors its parameters): not reversed.
        addGregoryLeaf(out, gather20(points + kTerminalPointsPerLevel * node.levels), false);
        break;
    }
    case NodeKind::Extraordinary:
        addGregoryLeaf(out, gather20(points), false);
        break;
    case NodeKind::Internal: break;
    }
}

}  // namespace

PatchCullSet buildSubfaceCullBounds(const PlannedCage& planned) {
    PatchCullSet out;
    for (uint32_t s = 0; s < planned.subfaceCount(); ++s) {
        if (!planned.hasSurface(s)) {
            appendAbsentPatch(out);
            continue;
        }
        const Plan& plan = planned.database().plan(planned.subfacePlan(s));
        const std::span<const glm::vec3> control = planned.subfaceControlPoints(s);
        PatchCullLeaves leaves;
        for (const PlanNode& node : plan.nodes)
            if (node.kind != NodeKind::Internal) addLeaf(leaves, plan, node, control.data());
        appendPatch(out, leaves, planned.subfaceOrigin(s));
    }
    return out;
}

}  // namespace qp
