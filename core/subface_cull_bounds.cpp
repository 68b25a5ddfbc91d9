#include "subface_cull_bounds.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "plan_database.h"
#include "topology.h"

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
    std::vector<SubfaceCullBounds::GregoryLeaf> gregories;  // boxes relative to the origin
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

// A Gregory patch (20 points in patch_basis.h's order, `reversed` as addPatch): the box of its
// points (the surface is a convex blend of them) and a cone bounding its true normals. With its
// interior points F_k(u, v), blends of Fp_k and Fm_k, B_u = D_u + e_u:
//   D_u, the Bézier net's u-derivative with the interior points held, 3 sum B2_i(u) B3_j(v) times
//       the net's u-differences, each interior point anywhere on [Fm_k, Fp_k] (so a positive
//       combination of the differences taken with either end): within the cone (a, alpha) of
//       those, and D_u . a >= m = 3 min(difference . a) (the weights sum to 1);
//   e_u = sum_k (d/du of the blend weight) B(interior point k) (Fp_k - Fm_k), each factor at most
//       4/3 in size (gregoryWeights: e.g. corner 0, v / (u + v)^2 * 9 u (1 - u)^2 v (1 - v)^2 <=
//       9 u (1 - u)^2 <= 4/3), so |e_u| <= E = 4/3 sum_k |Fp_k - Fm_k|.
// B_u then lies within alpha + asin(E / m) of a (when E < m); B_v likewise; Sederberg and
// Meyers' rule gives the normal cone. The patch has no polynomial normal patch: its ncone is
// that cone, and pplane tests the leaf with it.
NormalCone gregoryTangentCone(std::span<const glm::vec3> differences, float perturbation) {
    NormalCone cone = coneOfVectors(differences);
    if (!cone.bounded) return cone;
    float least = INFINITY;
    for (const glm::vec3& d : differences) least = std::min(least, 3.0f * glm::dot(d, cone.axis));
    if (!(perturbation < least)) return NormalCone{};
    cone.halfAngle += std::asin(perturbation / least);
    cone.bounded = cone.halfAngle < 0.5f * 3.14159265f;
    return cone;
}

}  // namespace

NormalCone gregoryNormalCone(const std::array<glm::vec3, 20>& g) {
    // The Bézier net, each interior point as its two ends: net(i, j) -> {a, b}.
    std::array<std::array<glm::vec3, 2>, 16> net;
    auto set = [&](int i, int j, const glm::vec3& a, const glm::vec3& b) { net[4 * j + i] = {a, b}; };
    // Corner k's P, Ep, Em and interior point in the net (patch_basis.h).
    const int corner[4][4][2] = {{{0, 0}, {1, 0}, {0, 1}, {1, 1}}, {{3, 0}, {3, 1}, {2, 0}, {2, 1}},
                                 {{3, 3}, {2, 3}, {3, 2}, {2, 2}}, {{0, 3}, {0, 2}, {1, 3}, {1, 2}}};
    float spread = 0.0f;
    for (int k = 0; k < 4; ++k) {
        for (int q = 0; q < 3; ++q) set(corner[k][q][0], corner[k][q][1], g[5 * k + q], g[5 * k + q]);
        set(corner[k][3][0], corner[k][3][1], g[5 * k + 3], g[5 * k + 4]);
        spread += glm::length(g[5 * k + 3] - g[5 * k + 4]);
    }
    std::vector<glm::vec3> alongU, alongV;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 3; ++i)
            for (const glm::vec3& a : net[4 * j + i + 1])
                for (const glm::vec3& b : net[4 * j + i]) alongU.push_back(a - b);
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 3; ++j)
            for (const glm::vec3& a : net[4 * (j + 1) + i])
                for (const glm::vec3& b : net[4 * j + i]) alongV.push_back(a - b);
    const float perturbation = 4.0f / 3.0f * spread;
    return normalConeOfTangents(gregoryTangentCone(alongU, perturbation), gregoryTangentCone(alongV, perturbation));
}

namespace {

void addGregory(LeafBounds& out, const std::array<glm::vec3, 20>& g, bool reversed) {
    CullBox box{glm::vec3(INFINITY), glm::vec3(-INFINITY)};
    for (const glm::vec3& p : g) grow(box, CullBox{p, p});
    grow(out.box, box);
    NormalCone cone = gregoryNormalCone(g);
    if (reversed) cone.axis = -cone.axis;
    out.tcones.push_back(cone);
    out.ncones.push_back(cone);
    out.gregories.push_back({cone, box});
}

void addLeaf(LeafBounds& out, const Plan& plan, const PlanNode& node, const glm::vec3* control) {
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
        // Per level the three regular windows of the 5 x 5 grid, quadrants (1, 0), (0, 1), (1, 1).
        constexpr uint32_t kQuadrants[3][2] = {{1, 0}, {0, 1}, {1, 1}};
        for (uint32_t level = 0; level < node.levels; ++level)
            for (const auto& quadrant : kQuadrants) {
                const uint32_t qx = quadrant[0], qy = quadrant[1];
                addPatch(out, gather16([&](uint32_t k) {
                             const uint32_t gx = qx + k % 4, gy = qy + k / 4;
                             return points[kTerminalPointsPerLevel * level + gy * 5 + gx - 1];
                         }),
                         mirrorU != mirrorV);
            }
        // The Gregory patch at the bottom, evaluated in the node's own frame (plan_eval.cpp
        // un-mirrors its parameters): not reversed.
        addGregory(out, gather20(points + kTerminalPointsPerLevel * node.levels), false);
        break;
    }
    case NodeKind::Extraordinary:
        addGregory(out, gather20(points), false);
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
    out.gregoryOffsets.assign(count + 1, 0);
    for (uint32_t s = 0; s < count; ++s) {
        out.planeOffsets[s + 1] = out.planeOffsets[s];
        out.gregoryOffsets[s + 1] = out.gregoryOffsets[s];
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
        for (SubfaceCullBounds::GregoryLeaf leaf : leaves.gregories) {
            leaf.box = CullBox{leaf.box.lo + origin, leaf.box.hi + origin};
            out.gregories.push_back(leaf);
        }
        out.gregoryOffsets[s + 1] = uint32_t(out.gregories.size());
    }
    return out;
}

bool subfaceTangentPlanesBackFacing(const SubfaceCullBounds& bounds, uint32_t subface, const glm::vec4& eye) {
    const uint32_t first = bounds.planeOffsets[subface], last = bounds.planeOffsets[subface + 1];
    const uint32_t firstGregory = bounds.gregoryOffsets[subface], lastGregory = bounds.gregoryOffsets[subface + 1];
    if (first == last && firstGregory == lastGregory) return false;
    for (uint32_t k = firstGregory; k < lastGregory; ++k)
        if (!backFacing(bounds.gregories[k].cone, bounds.gregories[k].box, eye)) return false;
    // The planes are relative to the sub-face's origin: move the eye there (a direction stays).
    const glm::vec4 relative(glm::vec3(eye) - eye.w * bounds.origins[subface], eye.w);
    for (uint32_t k = first; k < last; ++k)
        if (!tangentPlanesBackFacing(bounds.planes[k], relative)) return false;
    return true;
}

std::optional<CullMethod> parseCullMethod(std::string_view name) {
    for (CullMethod m : {CullMethod::None, CullMethod::Frustum, CullMethod::TCone, CullMethod::NCone, CullMethod::PPlane})
        if (name == cullMethodName(m)) return m;
    return std::nullopt;
}

const char* cullMethodName(CullMethod method) {
    switch (method) {
    case CullMethod::None: return "none";
    case CullMethod::Frustum: return "frustum";
    case CullMethod::TCone: return "tcone";
    case CullMethod::NCone: return "ncone";
    case CullMethod::PPlane: return "pplane";
    }
    return "?";
}

glm::vec4 homogeneousEye(const glm::mat4& m, const glm::vec3& eyePoint) {
    const glm::vec4 lastRow(m[0][3], m[1][3], m[2][3], m[3][3]);
    if (lastRow.x != 0.0f || lastRow.y != 0.0f || lastRow.z != 0.0f) return glm::vec4(eyePoint, 1.0f);
    // Orthographic: depth grows away from the viewer along row 2.
    return glm::vec4(-glm::normalize(glm::vec3(m[0][2], m[1][2], m[2][2])), 0.0f);
}

bool closedSurface(const PlannedCage& planned) {
    const Topology& topology = planned.topology();
    for (uint32_t e = 0; e < topology.edgeCount(); ++e)
        if (topology.edgeFaceCount(e) != 2) return false;
    for (uint32_t f = 0; f < planned.cage().faceCount(); ++f)
        if (planned.cage().isHole(f)) return false;
    return true;
}

std::vector<uint32_t> culledSubfaces(const PlannedCage& planned, const SubfaceCullBounds& bounds, CullMethod method,
                                     const glm::mat4& viewProjection, const glm::vec4& eye, bool backPatch,
                                     std::span<const float> margins) {
    std::vector<uint32_t> culled;
    if (method == CullMethod::None) return culled;
    const CullFrustum frustum = frustumOf(viewProjection);
    // Back-patch tests need the eye outside the surface (outside the box of every sub-face),
    // and the near plane clear of it: where the near plane cuts the surface open, its back
    // side shows through the cut.
    if (backPatch) {
        CullBox all{glm::vec3(INFINITY), glm::vec3(-INFINITY)};
        for (uint32_t s = 0; s < planned.subfaceCount(); ++s)
            if (planned.hasSurface(s)) grow(all, bounds.boxes[s]);
        if (eye.w != 0.0f) {
            const glm::vec3 e = glm::vec3(eye) / eye.w;
            backPatch = glm::any(glm::lessThan(e, all.lo)) || glm::any(glm::greaterThan(e, all.hi));
        }
        const glm::vec4& nearPlane = frustum.planes[4];
        for (int corner = 0; corner < 8 && backPatch; ++corner) {
            const glm::vec3 p(corner & 1 ? all.hi.x : all.lo.x, corner & 2 ? all.hi.y : all.lo.y, corner & 4 ? all.hi.z : all.lo.z);
            backPatch = glm::dot(glm::vec3(nearPlane), p) + nearPlane.w > 0.0f;
        }
    }
    for (uint32_t s = 0; s < planned.subfaceCount(); ++s) {
        if (!planned.hasSurface(s)) continue;
        CullBox box = bounds.boxes[s];
        if (!margins.empty()) box.lo -= glm::vec3(margins[s]), box.hi += glm::vec3(margins[s]);
        bool out = outsideFrustum(frustum, box);
        // Each back-patch method also takes the cheaper ones' answers (all are conservative), so
        // what tcone culls ncone culls too, and pplane both.
        if (!out && backPatch && margins.empty() && method >= CullMethod::TCone) {
            out = backFacing(bounds.tcones[s], box, eye);
            if (!out && method >= CullMethod::NCone) out = backFacing(bounds.ncones[s], box, eye);
            if (!out && method == CullMethod::PPlane) out = subfaceTangentPlanesBackFacing(bounds, s, eye);
        }
        if (out) culled.push_back(s);
    }
    return culled;
}

}  // namespace qp
