#include "culling/subface_cull_bounds.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include "mesh/topology.h"
#include "plans/plan_database.h"

namespace qp {

namespace {

// The crease edge of a Crease leaf as a boundary bit (the phantom rows are those of an
// infinitely sharp crease).
uint32_t creaseBit(uint32_t edge) { return edge == 0 ? 1u : edge == 1 ? 2u : edge == 2 ? 4u : 8u; }

std::array<glm::vec3, 20> gather20(const glm::vec3* control, const uint32_t* from) {
    std::array<glm::vec3, 20> g;
    for (uint32_t k = 0; k < 20; ++k) g[k] = control[from[k]];
    return g;
}

// Where the Gregory patch of a Terminal or Extraordinary node starts in plan.points.
const uint32_t* gregoryPoints(const Plan& plan, const PlanNode& node) {
    const uint32_t* points = &plan.points[node.first];
    return node.kind == NodeKind::Terminal ? points + kTerminalPointsPerLevel * node.levels : points;
}

// Whether the back-patch tests can ever cull the sub-face: each needs every leaf facing away, so
// not when a leaf has no cone (a semi-sharp crease) or a Gregory leaf's cone is unbounded. Then
// the entry's other leaves are read for their boxes only: their cones would join an unbounded
// union and their tangent planes would never be reached (the Gregory leaf fails first), so the
// results are the same without them, and near an extraordinary vertex a plan has 3 Bézier leaves
// a level, 1.3 KB of tangent planes each.
bool backTestable(const Plan& plan, const glm::vec3* control) {
    for (const PlanNode& node : plan.nodes) {
        if (node.kind == NodeKind::Crease && node.sharpness < kInfiniteSharpness) return false;
        if ((node.kind == NodeKind::Terminal || node.kind == NodeKind::Extraordinary) &&
            !gregoryNormalCone(gather20(control, gregoryPoints(plan, node))).bounded)
            return false;
    }
    return true;
}

// Bézier leaves deeper in the quadtree than this (a sixteenth of the sub-face's side and less)
// are tested by pplane with their ncone (addSmallBezierLeaf): near an extraordinary vertex or a
// crease a plan has 3 leaves a level down to depth 6, and their tangent planes (1.3 KB each) made
// the bounds of a 100,000-face cage 2 GB.
constexpr uint32_t kTangentPlaneDepth = 2;
bool keepsTangentPlanes(uint32_t leafDepth) { return leafDepth <= kTangentPlaneDepth; }

// The depth of every node of `plan` in its quadtree (the root 0).
void nodeDepths(const Plan& plan, std::vector<uint32_t>& depth) {
    depth.assign(plan.nodes.size(), 0);
    for (size_t i = 0; i < plan.nodes.size(); ++i)
        if (plan.nodes[i].kind == NodeKind::Internal)
            for (uint32_t child = 0; child < 4; ++child) depth[plan.nodes[i].first + child] = depth[i] + 1;
}

// The leaves of `node` at quadtree depth `depth`; with `boxesOnly` its Bézier leaves give their
// boxes only (backTestable).
void addLeaf(PatchCullLeaves& out, const Plan& plan, const PlanNode& node, uint32_t depth, const glm::vec3* control,
             bool boxesOnly) {
    const uint32_t* points = &plan.points[node.first];
    const CullMethod detail = out.detail;
    if (boxesOnly) out.detail = std::min(detail, CullMethod::Frustum);
    auto addBezier = [&](const BicubicPoints& bezier, bool reversed, uint32_t leafDepth) {
        if (keepsTangentPlanes(leafDepth)) addBezierLeaf(out, bezier, reversed);
        else addSmallBezierLeaf(out, bezier, reversed);
    };
    auto gather16 = [&](auto index) {
        BicubicPoints p;
        for (uint32_t k = 0; k < 16; ++k) p[k] = control[index(k)];
        return p;
    };
    switch (node.kind) {
    case NodeKind::Regular:
        addBezier(bsplineToBezier(withPhantoms(gather16([&](uint32_t k) { return points[k]; }), node.boundaryMask)), false,
                  depth);
        break;
    case NodeKind::Crease: {
        const BicubicPoints real = gather16([&](uint32_t k) { return points[k]; });
        if (node.sharpness >= kInfiniteSharpness)
            addBezier(bsplineToBezier(withPhantoms(real, node.boundaryMask | creaseBit(node.edge))), false, depth);
        else
            addSemiSharpCreaseLeaf(out, real, node.boundaryMask, creaseBit(node.edge));
        break;
    }
    case NodeKind::Terminal: {
        const bool mirrorU = node.edge == 1 || node.edge == 2, mirrorV = node.edge == 2 || node.edge == 3;
        // Per level the three regular windows of the 5 x 5 grid, quadrants (1, 0), (0, 1), (1, 1).
        constexpr uint32_t kQuadrants[3][2] = {{1, 0}, {0, 1}, {1, 1}};
        for (uint32_t level = 0; level < node.levels; ++level)
            for (const auto& quadrant : kQuadrants) {
                const uint32_t qx = quadrant[0], qy = quadrant[1];
                addBezier(bsplineToBezier(gather16([&](uint32_t k) {
                              const uint32_t gx = qx + k % 4, gy = qy + k / 4;
                              return points[kTerminalPointsPerLevel * level + gy * 5 + gx - 1];
                          })),
                          mirrorU != mirrorV, depth + 1 + level);
            }
        // The Gregory patch at the bottom, evaluated in the node's own frame (plan_eval.cpp
        // un-mirrors its parameters): not reversed.
        out.detail = detail;
        addGregoryLeaf(out, gather20(control, gregoryPoints(plan, node)), false);
        break;
    }
    case NodeKind::Extraordinary:
        out.detail = detail;
        addGregoryLeaf(out, gather20(control, gregoryPoints(plan, node)), false);
        break;
    case NodeKind::Internal: break;
    }
    out.detail = detail;
}


// The leaves of `subfaces`, gathered on all cores (a leaf's tangent planes cost some microseconds).
std::vector<PatchCullLeaves> gatherLeaves(const PlannedCage& planned, std::span<const uint32_t> subfaces, CullMethod detail) {
    std::vector<PatchCullLeaves> out(subfaces.size());
    tbb::parallel_for(size_t(0), subfaces.size(), [&](size_t k) {
        const uint32_t s = subfaces[k];
        out[k].detail = detail;
        if (!planned.hasSurface(s)) return;
        const Plan& plan = planned.database().plan(planned.subfacePlan(s));
        std::vector<glm::vec3> scratch;  // the leaves read every control point
        const std::span<const glm::vec3> control = planned.controlPointsFor(s, kMaxPlanDepth, scratch);
        const bool boxesOnly = detail >= CullMethod::TCone && !backTestable(plan, control.data());
        std::vector<uint32_t> depth;
        nodeDepths(plan, depth);
        for (size_t n = 0; n < plan.nodes.size(); ++n)
            if (plan.nodes[n].kind != NodeKind::Internal) addLeaf(out[k], plan, plan.nodes[n], depth[n], control.data(), boxesOnly);
        // A small leaf's unbounded cone fails pplane as a Gregory leaf's does: no planes needed.
        if (std::any_of(out[k].coneLeaves.begin(), out[k].coneLeaves.end(), [](const ConeCullLeaf& leaf) { return !leaf.cone.bounded; }))
            out[k].planes.clear();
    });
    return out;
}

// Bézier leaves of `plan` that keep tangent planes (addLeaf's rule).
uint32_t planeLeaves(const Plan& plan) {
    std::vector<uint32_t> depth;
    nodeDepths(plan, depth);
    uint32_t count = 0;
    for (size_t n = 0; n < plan.nodes.size(); ++n) {
        const PlanNode& node = plan.nodes[n];
        if (node.kind == NodeKind::Regular || (node.kind == NodeKind::Crease && node.sharpness >= kInfiniteSharpness))
            count += keepsTangentPlanes(depth[n]);
        if (node.kind == NodeKind::Terminal)
            for (uint32_t level = 0; level < node.levels; ++level) count += 3 * keepsTangentPlanes(depth[n] + 1 + level);
    }
    return count;
}

std::vector<glm::vec3> originsOf(const PlannedCage& planned, std::span<const uint32_t> subfaces) {
    std::vector<glm::vec3> out;
    out.reserve(subfaces.size());
    for (uint32_t s : subfaces) out.push_back(planned.hasSurface(s) ? planned.subfaceOrigin(s) : glm::vec3(0.0f));
    return out;
}

}  // namespace

PatchCullSet buildSubfaceCullBounds(const PlannedCage& planned, CullMethod detail) {
    std::vector<uint32_t> all(planned.subfaceCount());
    std::iota(all.begin(), all.end(), 0u);
    const std::vector<PatchCullLeaves> leaves = gatherLeaves(planned, all, detail);
    PatchCullSet out;
    for (uint32_t s = 0; s < planned.subfaceCount(); ++s) {
        if (planned.hasSurface(s)) appendPatch(out, leaves[s], planned.subfaceOrigin(s));
        else appendAbsentPatch(out);
    }
    return out;
}

uint64_t tangentPlaneBytes(const PlannedCage& planned) {
    std::vector<uint32_t> leavesOfPlan(planned.database().size(), UINT32_MAX);  // each plan counted once
    uint64_t leaves = 0;
    for (uint32_t s = 0; s < planned.subfaceCount(); ++s) {
        if (!planned.hasSurface(s)) continue;
        uint32_t& count = leavesOfPlan[planned.subfacePlan(s)];
        if (count == UINT32_MAX) count = planeLeaves(planned.database().plan(planned.subfacePlan(s)));
        leaves += count;
    }
    return leaves * sizeof(TangentPlanes);
}

void updateSubfaceCullBounds(PatchCullSet& set, const PlannedCage& planned, std::span<const uint32_t> subfaces,
                             CullMethod detail) {
    replacePatches(set, subfaces, gatherLeaves(planned, subfaces, detail), originsOf(planned, subfaces));
}

}  // namespace qp
