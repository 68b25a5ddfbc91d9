#include "cpu_grid.h"

#include <cassert>
#include <cmath>

#include <glm/geometric.hpp>
#include "patch_basis.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace qp {

namespace {

// Sub-faces per task: a few thousand evaluations, so scheduling is noise.
constexpr size_t kGrain = 16;

// Drawn sub-faces list[0 .. count), or 0 .. count when `list` is null.
template <class Body>
void forEachSubface(const uint32_t* list, size_t count, const Body& body) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, kGrain), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t k = range.begin(); k != range.end(); ++k) body(list ? list[k] : uint32_t(k));
    });
}

glm::vec3 unitNormalOf(const glm::vec3& du, const glm::vec3& dv) {
    const glm::vec3 normal = glm::cross(du, dv);
    const float length = glm::length(normal);
    return length > 0.0f ? normal / length : glm::vec3(0.0f);
}

// The frame a displaced slot is built from: at sub-face corners the derivatives
// kCornerNormalStep inside (shaders/displacement.glsl, evaluateWithNormal, says why).
GridFrame frameOf(const PlannedCage& planned, const LimitSample& s, uint32_t subface, float u, float v) {
    GridFrame frame{s.position, s.du, s.dv};
    if ((u == 0.0f || u == 1.0f) && (v == 0.0f || v == 1.0f)) {
        const LimitSample inside = planned.evaluate(subface, u + (u < 0.5f ? kCornerNormalStep : -kCornerNormalStep),
                                                    v + (v < 0.5f ? kCornerNormalStep : -kCornerNormalStep));
        frame.du = inside.du;
        frame.dv = inside.dv;
    }
    return frame;
}

// s + D N along the frame's unit normal, with displacePoint's shading normal.
GridVertex displacedVertex(const GridFrame& frame, const Displacement& displacement, uint32_t subface, float u, float v) {
    const DisplacedPoint p = displacePoint(frame.position, frame.du, frame.dv, unitNormalOf(frame.du, frame.dv),
                                           evaluateDisplacement(displacement, subface, u, v));
    return GridVertex{{p.position.x, p.position.y, p.position.z}, {p.normal.x, p.normal.y, p.normal.z}};
}

// Where phase 1 writes: the grid, and with a displacement optionally the frames.
struct Output {
    GridVertex* grid;
    const Displacement* displacement;
    GridFrame* frames;

    // Slot `slot` of sub-face `subface` at (u, v): the limit point and the unit normal of
    // du x dv (zero where that vanishes), or with a displacement the displaced vertex.
    void write(const PlannedCage& planned, uint32_t slot, const LimitSample& s, uint32_t subface, float u, float v) const {
        if (!displacement) {
            const glm::vec3 n = unitNormalOf(s.du, s.dv);
            grid[slot] = GridVertex{{s.position.x, s.position.y, s.position.z}, {n.x, n.y, n.z}};
            return;
        }
        const GridFrame frame = frameOf(planned, s, subface, u, v);
        if (frames) frames[slot] = frame;
        grid[slot] = displacedVertex(frame, *displacement, subface, u, v);
    }
};

bool isSingleBicubic(const Plan& plan) {
    return plan.nodes.size() == 1 && (plan.nodes[0].kind == NodeKind::Regular || plan.nodes[0].kind == NodeKind::Crease);
}

// The 1D bases of a Regular or Crease leaf along the plan's u (s) and v (t), as
// core/plan_eval.cpp's regularPatch builds them (keep the two in step).
Basis1D basisAlongU(const PlanNode& node, float s) {
    Basis1D b = bsplineBasis1D(s);
    if (node.kind == NodeKind::Crease && node.edge == 1) b = creaseBasis1DFar(s, node.sharpness);
    if (node.kind == NodeKind::Crease && node.edge == 3) b = creaseBasis1D(s, node.sharpness);
    if (node.boundaryMask & 8) foldNear(b);
    if (node.boundaryMask & 2) foldFar(b);
    return b;
}

Basis1D basisAlongV(const PlanNode& node, float t) {
    Basis1D b = bsplineBasis1D(t);
    if (node.kind == NodeKind::Crease && node.edge == 0) b = creaseBasis1D(t, node.sharpness);
    if (node.kind == NodeKind::Crease && node.edge == 2) b = creaseBasis1DFar(t, node.sharpness);
    if (node.boundaryMask & 1) foldNear(b);
    if (node.boundaryMask & 4) foldFar(b);
    return b;
}

// A sub-face whose plan is one Regular or Crease leaf (most faces of most cages): the patch is
// a tensor product, so its rows of control points are combined along the plan's u once per grid
// column, and each slot only combines four of those along v. The operations and their order
// are core/plan_eval.cpp's tensorPatch, so the values are PlannedCage::evaluate's.
void evaluateBicubicSubface(const PlannedCage& planned, const Plan& plan, uint32_t subface, const GridLayout& layout,
                            uint32_t drawn, const Output& out) {
    const PlanNode& node = plan.nodes[0];
    const uint32_t* points = plan.points.data() + node.first;
    const glm::vec3* controlPoints = planned.subfaceControlPoints(subface).data();
    const uint32_t rotation = planned.subfaceRotation(subface), n = layout.factors.subfaceFactor[drawn];
    // The plan's (s, t) of grid column / row k, as PlannedCage::evaluate rotates (u, v) = k / n.
    // Rotations 0 and 2 take s from the column, 1 and 3 from the row.
    const bool sFromColumn = rotation == 0 || rotation == 2;
    constexpr uint32_t kMaxSide = 65;  // factors are at most 64
    assert(n < kMaxSide);
    glm::vec3 along[kMaxSide][4], alongDu[kMaxSide][4];
    Basis1D bv[kMaxSide];
    for (uint32_t k = 0; k <= n; ++k) {
        const float x = float(k) / float(n);
        const float s = rotation == 0 || rotation == 1 ? x : 1.0f - x;
        const float t = rotation == 0 || rotation == 3 ? x : 1.0f - x;
        const Basis1D bu = basisAlongU(node, s);
        bv[k] = basisAlongV(node, t);
        for (uint32_t row = 0; row < 4; ++row) {
            glm::vec3 a(0.0f), aDu(0.0f);
            for (uint32_t col = 0; col < 4; ++col) {
                const glm::vec3& cp = controlPoints[points[4 * row + col]];
                a += bu.b[col] * cp;
                aDu += bu.d[col] * cp;
            }
            along[k][row] = a;
            alongDu[k][row] = aDu;
        }
    }
    const uint32_t first = layout.subfaceOffset[drawn], side = n + 1;
    for (uint32_t y = 0; y <= n; ++y)
        for (uint32_t x = 0; x <= n; ++x) {
            const uint32_t slot = first + y * side + x;
            if (layout.source[slot] != slot) continue;
            const uint32_t ks = sFromColumn ? x : y, kt = sFromColumn ? y : x;
            LimitSample sample;
            for (uint32_t row = 0; row < 4; ++row) {
                sample.position += bv[kt].b[row] * along[ks][row];
                sample.du += bv[kt].b[row] * alongDu[ks][row];
                sample.dv += bv[kt].d[row] * along[ks][row];
            }
            // To the sub-face's frame, as PlannedCage::evaluate does.
            const glm::vec3 du = sample.du, dv = sample.dv;
            if (rotation == 1) sample.du = -dv, sample.dv = du;
            else if (rotation == 2) sample.du = -du, sample.dv = -dv;
            else if (rotation == 3) sample.du = dv, sample.dv = -du;
            float u, v;
            slotParameter(slot - first, n, u, v);
            out.write(planned, slot, sample, subface, u, v);
        }
}

void evaluatePhase(const PlannedCage& planned, const GpuPlanData& data, const GridLayout& layout, const uint32_t* list,
                   size_t count, const Output& out) {
    forEachSubface(list, count, [&](uint32_t drawn) {
        const uint32_t subface = data.subfaces[drawn].subface, n = layout.factors.subfaceFactor[drawn];
        const Plan& plan = planned.database().plan(planned.subfacePlan(subface));
        if (isSingleBicubic(plan)) return evaluateBicubicSubface(planned, plan, subface, layout, drawn, out);
        const uint32_t first = layout.subfaceOffset[drawn], end = layout.subfaceOffset[drawn + 1];
        for (uint32_t slot = first; slot < end; ++slot) {
            if (layout.source[slot] != slot) continue;
            float u, v;
            slotParameter(slot - first, n, u, v);
            out.write(planned, slot, planned.evaluate(subface, u, v), subface, u, v);
        }
    });
}

void copyPhase(const GridLayout& layout, const uint32_t* list, size_t count, GridVertex* grid) {
    forEachSubface(list, count, [&](uint32_t drawn) {
        for (uint32_t slot = layout.subfaceOffset[drawn]; slot < layout.subfaceOffset[drawn + 1]; ++slot)
            if (layout.source[slot] != slot) grid[slot] = grid[layout.source[slot]];
    });
}

}  // namespace

void evaluateGridOnCpu(const PlannedCage& planned, const GpuPlanData& data, const GridLayout& layout,
                       std::span<const uint32_t> evaluate, std::span<const uint32_t> copy, GridVertex* grid,
                       const Displacement* displacement, GridFrame* frames) {
    evaluatePhase(planned, data, layout, evaluate.data(), evaluate.size(), Output{grid, displacement, frames});
    copyPhase(layout, copy.data(), copy.size(), grid);
}

void evaluateWholeGridOnCpu(const PlannedCage& planned, const GpuPlanData& data, const GridLayout& layout,
                            GridVertex* grid, const Displacement* displacement, GridFrame* frames) {
    evaluatePhase(planned, data, layout, nullptr, data.subfaces.size(), Output{grid, displacement, frames});
    copyPhase(layout, nullptr, data.subfaces.size(), grid);
}

void redisplaceGridOnCpu(const GpuPlanData& data, const GridLayout& layout, std::span<const uint32_t> evaluate,
                         std::span<const uint32_t> copy, const Displacement& displacement, const GridFrame* frames,
                         GridVertex* grid) {
    forEachSubface(evaluate.data(), evaluate.size(), [&](uint32_t drawn) {
        const uint32_t subface = data.subfaces[drawn].subface, n = layout.factors.subfaceFactor[drawn];
        const uint32_t first = layout.subfaceOffset[drawn], end = layout.subfaceOffset[drawn + 1];
        for (uint32_t slot = first; slot < end; ++slot) {
            if (layout.source[slot] != slot) continue;
            float u, v;
            slotParameter(slot - first, n, u, v);
            grid[slot] = displacedVertex(frames[slot], displacement, subface, u, v);
        }
    });
    copyPhase(layout, copy.data(), copy.size(), grid);
}

}  // namespace qp
