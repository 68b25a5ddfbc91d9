// Evaluation of a plan: quadtree descent, then one basis per leaf kind.
#include <algorithm>
#include <bit>
#include <cassert>

#include <glm/geometric.hpp>

#include "plans/patch_basis.h"
#include "plans/plan.h"

namespace qp {

namespace {

struct Combined {
    glm::vec3 p{0.0f}, ds{0.0f}, dt{0.0f};
};

// Sums weighted control points; points[k] indexes controlPoints.
Combined combine(const BasisWeights& w, const uint32_t* points, uint32_t count, const glm::vec3* controlPoints) {
    Combined c;
    for (uint32_t k = 0; k < count; ++k) {
        const glm::vec3& cp = controlPoints[points[k]];
        c.p += w.w[k] * cp;
        c.ds += w.du[k] * cp;
        c.dt += w.dv[k] * cp;
    }
    return c;
}

// Bicubic patch from its 1D bases: rows combine along u first, then along v.
Combined tensorPatch(const Basis1D& bu, const Basis1D& bv, const uint32_t* points, const glm::vec3* controlPoints) {
    Combined c;
    for (uint32_t row = 0; row < 4; ++row) {
        glm::vec3 along(0.0f), alongDu(0.0f);
        for (uint32_t col = 0; col < 4; ++col) {
            const glm::vec3& cp = controlPoints[points[4 * row + col]];
            along += bu.b[col] * cp;
            alongDu += bu.d[col] * cp;
        }
        c.p += bv.b[row] * along;
        c.ds += bv.b[row] * alongDu;
        c.dt += bv.d[row] * along;
    }
    return c;
}

// Regular or crease leaf: the crease and any boundary edges change only the 1D basis across
// them (see patch_basis.h).
Combined regularPatch(const PlanNode& node, const uint32_t* points, const glm::vec3* controlPoints, float s, float t) {
    Basis1D bu = bsplineBasis1D(s), bv = bsplineBasis1D(t);
    if (node.kind == NodeKind::Crease) {
        switch (node.edge) {
        case 0: bv = creaseBasis1D(t, node.sharpness); break;
        case 1: bu = creaseBasis1DFar(s, node.sharpness); break;
        case 2: bv = creaseBasis1DFar(t, node.sharpness); break;
        default: bu = creaseBasis1D(s, node.sharpness); break;
        }
    }
    if (node.boundaryMask & 1) foldNear(bv);
    if (node.boundaryMask & 4) foldFar(bv);
    if (node.boundaryMask & 8) foldNear(bu);
    if (node.boundaryMask & 2) foldFar(bu);
    return tensorPatch(bu, bv, points, controlPoints);
}

// Terminal node: find the level whose regular quadrant holds (s, t), or the Gregory patch at
// the bottom of the chain. Returns derivatives with respect to the node's own (s, t).
Combined evaluateTerminal(const Plan& plan, const PlanNode& node, const glm::vec3* controlPoints, float s, float t) {
    const bool mirrorU = node.edge == 1 || node.edge == 2, mirrorV = node.edge == 2 || node.edge == 3;
    float a = mirrorU ? 1.0f - s : s, b = mirrorV ? 1.0f - t : t;
    float scale = 1.0f;  // d(a at this level) / d(a at the node)
    const uint32_t* points = &plan.points[node.first];
    for (uint32_t level = 0; level < node.levels; ++level) {
        if (std::max(a, b) >= 0.5f) {
            const uint32_t qx = a >= 0.5f, qy = b >= 0.5f;
            uint32_t gathered[16];
            for (uint32_t k = 0; k < 16; ++k) {
                uint32_t gx = qx + k % 4, gy = qy + k / 4;  // 0..4 on the 5x5 grid
                gathered[k] = points[kTerminalPointsPerLevel * level + gy * 5 + gx - 1];
            }
            Combined c = tensorPatch(bsplineBasis1D(2.0f * a - float(qx)), bsplineBasis1D(2.0f * b - float(qy)),
                                     gathered, controlPoints);
            float d = 2.0f * scale;
            c.ds *= mirrorU ? -d : d;
            c.dt *= mirrorV ? -d : d;
            return c;
        }
        a *= 2.0f;
        b *= 2.0f;
        scale *= 2.0f;
    }
    BasisWeights w;
    gregoryWeights(mirrorU ? 1.0f - a : a, mirrorV ? 1.0f - b : b, w);
    Combined c = combine(w, points + kTerminalPointsPerLevel * node.levels, kGregoryPoints, controlPoints);
    c.ds *= scale;
    c.dt *= scale;
    return c;
}

}  // namespace

const char* nodeKindName(NodeKind kind) {
    switch (kind) {
    case NodeKind::Internal: return "internal";
    case NodeKind::Regular: return "regular";
    case NodeKind::Crease: return "crease";
    case NodeKind::Terminal: return "terminal";
    case NodeKind::Extraordinary: return "extraordinary";
    }
    return "?";
}

std::array<uint32_t, kNodeKindCount> countNodes(const Plan& plan) {
    std::array<uint32_t, kNodeKindCount> counts{};
    for (const PlanNode& node : plan.nodes) ++counts[uint32_t(node.kind)];
    return counts;
}

void applyStencils(const Plan& plan, const glm::vec3* ringPositions, uint32_t count, glm::vec3* controlPoints) {
    assert(count <= plan.stencilCount());
    const float* w = plan.stencilWeights.data();
    for (uint32_t i = 0; i < count; ++i, w += plan.ringSize) {
        glm::vec3 sum(0.0f);
        for (uint32_t j = 0; j < plan.ringSize; ++j) sum += w[j] * ringPositions[j];
        controlPoints[i] = sum;
    }
}

namespace {

// At a corner whose tangent plane the plan carries (Plan::cornerTangents), du and dv lose
// their part along its normal.
void onCornerTangentPlane(const Plan& plan, const glm::vec3* controlPoints, float u, float v, LimitSample& sample) {
    const int corner = domainCorner(u, v);
    if (corner < 0 || !(plan.cornerTangents & (1u << corner))) return;
    const uint32_t first = 2u * uint32_t(std::popcount(plan.cornerTangents & ((1u << corner) - 1u)));
    const glm::vec3 normal = glm::cross(controlPoints[first], controlPoints[first + 1]);
    const float length = glm::length(normal);
    if (!(length > 0.0f)) return;
    const glm::vec3 n = normal / length;
    sample.du -= glm::dot(sample.du, n) * n;
    sample.dv -= glm::dot(sample.dv, n) * n;
}

}  // namespace

LimitSample evaluatePlan(const Plan& plan, const glm::vec3* controlPoints, float u, float v) {
    u = std::clamp(u, 0.0f, 1.0f);
    v = std::clamp(v, 0.0f, 1.0f);
    // Descend; on a split line take the side towards the face centre (matches the level
    // assignment of stencils, see nodeNeededLevel).
    uint32_t index = 0;
    float u0 = 0.0f, v0 = 0.0f, size = 1.0f;
    while (plan.nodes[index].kind == NodeKind::Internal) {
        size *= 0.5f;
        float midU = u0 + size, midV = v0 + size;
        bool highU = u > midU || (u == midU && midU < 0.5f);
        bool highV = v > midV || (v == midV && midV < 0.5f);
        index = plan.nodes[index].first + uint32_t(highU) + 2 * uint32_t(highV);
        if (highU) u0 = midU;
        if (highV) v0 = midV;
    }
    const PlanNode& node = plan.nodes[index];
    const float s = std::clamp((u - u0) / size, 0.0f, 1.0f), t = std::clamp((v - v0) / size, 0.0f, 1.0f);
    const uint32_t* points = &plan.points[node.first];

    Combined c;
    BasisWeights w;
    switch (node.kind) {
    case NodeKind::Regular:
    case NodeKind::Crease:
        c = regularPatch(node, points, controlPoints, s, t);
        break;
    case NodeKind::Terminal:
        c = evaluateTerminal(plan, node, controlPoints, s, t);
        break;
    case NodeKind::Extraordinary:
        gregoryWeights(s, t, w);
        c = combine(w, points, kGregoryPoints, controlPoints);
        break;
    case NodeKind::Internal:
        assert(false);
        break;
    }
    LimitSample sample{c.p, c.ds / size, c.dt / size};
    if (plan.cornerTangents) onCornerTangentPlane(plan, controlPoints, u, v, sample);
    return sample;
}

}  // namespace qp
