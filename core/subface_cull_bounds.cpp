#include "subface_cull_bounds.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "plan_database.h"

namespace qp {

namespace {

// The box of several boxes, and of a box and points.
void grow(CullBox& box, const CullBox& other) {
    box.lo = glm::min(box.lo, other.lo);
    box.hi = glm::max(box.hi, other.hi);
}

// The cone holding several cones (each axis within its half-angle).
NormalCone unionOf(std::span<const NormalCone> cones) {
    NormalCone out;
    glm::vec3 sum(0.0f);
    for (const NormalCone& c : cones) {
        if (!c.bounded) return out;
        sum += c.axis;
    }
    const float length = glm::length(sum);
    if (cones.empty() || !(length > 1e-6f)) return out;
    out.axis = sum / length;
    float widest = 0.0f;
    for (const NormalCone& c : cones)
        widest = std::max(widest, std::atan2(glm::length(glm::cross(out.axis, c.axis)), glm::dot(out.axis, c.axis)) + c.halfAngle);
    out.halfAngle = widest;
    out.bounded = widest < 0.5f * 3.14159265f;
    return out;
}

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

struct LeafBounds {
    CullBox box{glm::vec3(INFINITY), glm::vec3(-INFINITY)};
    std::vector<NormalCone> tcones, ncones;
    std::vector<TangentPlanes> planes;
    bool coneless = false;  // a leaf without a cone: no back-patch test for the sub-face
};

// A Bézier-convertible patch (`reversed`: its (u, v) frame is mirrored, so its normals flip).
void addPatch(LeafBounds& out, const BicubicPoints& bspline, bool reversed) {
    const BicubicPoints bezier = bsplineToBezier(bspline);
    grow(out.box, boxOf(bezier));
    NormalCone t = tangentCone(bezier), n = normalPatchCone(bezier);
    TangentPlanes planes = tangentPlanesOf(bezier);
    if (reversed) {
        t.axis = -t.axis, n.axis = -n.axis;
        for (glm::vec4& p : planes) p = -p;
    }
    out.tcones.push_back(t);
    out.ncones.push_back(n);
    out.planes.push_back(planes);
}

void addLeaf(LeafBounds& out, const Plan& plan, const PlanNode& node, const glm::vec3* control) {
    const uint32_t* points = &plan.points[node.first];
    auto gather16 = [&](auto index) {
        BicubicPoints p;
        for (uint32_t k = 0; k < 16; ++k) p[k] = control[index(k)];
        return p;
    };
    switch (node.kind) {
    case NodeKind::Regular:
        addPatch(out, withPhantoms(gather16([&](uint32_t k) { return points[k]; }), node.boundaryMask), false);
        break;
    case NodeKind::Crease: {
        const BicubicPoints real = gather16([&](uint32_t k) { return points[k]; });
        const BicubicPoints sharp = withPhantoms(real, node.boundaryMask | creaseBit(node.edge));
        if (node.sharpness >= kInfiniteSharpness) {
            addPatch(out, sharp, false);
            break;
        }
        // Semi-sharp: sharp surface + c d, c in [0, 1/2], d = real - sharp beyond the crease.
        grow(out.box, boxOf(bsplineToBezier(sharp)));
        CullBox d{glm::vec3(0.0f), glm::vec3(0.0f)};
        for (uint32_t k = 0; k < 16; ++k) {
            const glm::vec3 difference = 0.5f * (withPhantoms(real, node.boundaryMask)[k] - sharp[k]);
            d.lo = glm::min(d.lo, difference), d.hi = glm::max(d.hi, difference);
        }
        out.box.lo += glm::min(d.lo, glm::vec3(0.0f));
        out.box.hi += glm::max(d.hi, glm::vec3(0.0f));
        out.coneless = true;
        break;
    }
    case NodeKind::Terminal: {
        const bool mirrorU = node.edge == 1 || node.edge == 2, mirrorV = node.edge == 2 || node.edge == 3;
        for (uint32_t level = 0; level < node.levels; ++level)
            for (const auto [qx, qy] : {std::pair{1u, 0u}, std::pair{0u, 1u}, std::pair{1u, 1u}})
                addPatch(out, gather16([&](uint32_t k) {
                             const uint32_t gx = qx + k % 4, gy = qy + k / 4;
                             return points[kTerminalPointsPerLevel * level + gy * 5 + gx - 1];
                         }),
                         mirrorU != mirrorV);
        const uint32_t* gregory = points + kTerminalPointsPerLevel * node.levels;
        for (uint32_t k = 0; k < kGregoryPoints; ++k) grow(out.box, CullBox{control[gregory[k]], control[gregory[k]]});
        out.coneless = true;
        break;
    }
    case NodeKind::Extraordinary:
        for (uint32_t k = 0; k < kGregoryPoints; ++k) grow(out.box, CullBox{control[points[k]], control[points[k]]});
        out.coneless = true;
        break;
    case NodeKind::Internal: break;
    }
}

}  // namespace

SubfaceCullBounds buildSubfaceCullBounds(const PlannedCage& planned) {
    const uint32_t count = planned.subfaceCount();
    SubfaceCullBounds out;
    out.boxes.assign(count, CullBox{});
    out.tcones.assign(count, NormalCone{});
    out.ncones.assign(count, NormalCone{});
    out.origins.assign(count, glm::vec3(0.0f));
    out.planeOffsets.assign(count + 1, 0);
    for (uint32_t s = 0; s < count; ++s) {
        out.planeOffsets[s + 1] = out.planeOffsets[s];
        if (!planned.hasSurface(s)) continue;
        const Plan& plan = planned.database().plan(planned.subfacePlan(s));
        const std::span<const glm::vec3> control = planned.subfaceControlPoints(s);
        LeafBounds leaves;
        for (const PlanNode& node : plan.nodes)
            if (node.kind != NodeKind::Internal) addLeaf(leaves, plan, node, control.data());
        const glm::vec3 origin = planned.subfaceOrigin(s);
        out.origins[s] = origin;
        out.boxes[s] = CullBox{leaves.box.lo + origin, leaves.box.hi + origin};
        if (leaves.coneless) continue;
        out.tcones[s] = unionOf(leaves.tcones);
        out.ncones[s] = unionOf(leaves.ncones);
        out.planes.insert(out.planes.end(), leaves.planes.begin(), leaves.planes.end());
        out.planeOffsets[s + 1] = uint32_t(out.planes.size());
    }
    return out;
}

bool subfaceTangentPlanesBackFacing(const SubfaceCullBounds& bounds, uint32_t subface, const glm::vec4& eye) {
    const uint32_t first = bounds.planeOffsets[subface], last = bounds.planeOffsets[subface + 1];
    if (first == last) return false;
    // The planes are relative to the sub-face's origin: move the eye there (a direction stays).
    const glm::vec4 relative(glm::vec3(eye) - eye.w * bounds.origins[subface], eye.w);
    for (uint32_t k = first; k < last; ++k)
        if (!tangentPlanesBackFacing(bounds.planes[k], relative)) return false;
    return true;
}

}  // namespace qp
