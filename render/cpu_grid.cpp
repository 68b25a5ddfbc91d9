#include "cpu_grid.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>

#include <glm/geometric.hpp>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include "patch_basis.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace qp {

namespace {

// Sub-faces per task: a few thousand evaluations, so scheduling is noise.
constexpr size_t kGrain = 16;
constexpr uint32_t kMaxGridFactor = 64;

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

// Where phase 1 writes: the grid, or with a displacement the frames (displaced afterwards,
// a sub-face at a time, by displaceSlots).
struct Output {
    GridVertex* grid;
    const Displacement* displacement;
    GridFrame* frames;

    // Slot `slot` of sub-face `subface` at (u, v): the limit point and the unit normal of
    // du x dv (zero where that vanishes), or with a displacement the frame.
    void write(const PlannedCage& planned, uint32_t slot, const LimitSample& s, uint32_t subface, float u, float v) const {
        if (!displacement) {
            const glm::vec3 n = unitNormalOf(s.du, s.dv);
            grid[slot] = GridVertex{{s.position.x, s.position.y, s.position.z}, {n.x, n.y, n.z}};
            return;
        }
        frames[slot] = frameOf(planned, s, subface, u, v);
    }
};

// ---- displacing slots from their frames ------------------------------------------------
// s + D N along the frame's unit normal (unitNormalOf) with displacePoint's shading normal,
// for many slots at once: frames and D values are gathered into a structure of arrays and
// the arithmetic runs on SSE lanes, four slots per instruction. Each lane performs
// displacePoint's and unitNormalOf's IEEE operations in their order (no fused multiply-add:
// the build does not enable FMA), so a slot gets the same bits as the scalar functions,
// which the other targets use and the tests compare with.
class SlotDisplacer {
public:
    explicit SlotDisplacer(GridVertex* grid) : grid_(grid) {}
    ~SlotDisplacer() { flush(); }

    void add(uint32_t slot, const GridFrame& f, const DisplacementValue& d) {
        const uint32_t k = count_++;
        slot_[k] = slot;
        px_[k] = f.position.x, py_[k] = f.position.y, pz_[k] = f.position.z;
        ux_[k] = f.du.x, uy_[k] = f.du.y, uz_[k] = f.du.z;
        vx_[k] = f.dv.x, vy_[k] = f.dv.y, vz_[k] = f.dv.z;
        d_[k] = d.value, ddu_[k] = d.du, ddv_[k] = d.dv;
        if (count_ == kSize) flush();
    }

    void flush() {
        uint32_t k = 0;
#if defined(__SSE2__)
        for (; k + 4 <= count_; k += 4) displaceFour(k);
#endif
        for (; k < count_; ++k) {
            const glm::vec3 du(ux_[k], uy_[k], uz_[k]), dv(vx_[k], vy_[k], vz_[k]);
            const DisplacedPoint p = displacePoint(glm::vec3(px_[k], py_[k], pz_[k]), du, dv, unitNormalOf(du, dv),
                                                   DisplacementValue{d_[k], ddu_[k], ddv_[k]});
            grid_[slot_[k]] = GridVertex{{p.position.x, p.position.y, p.position.z}, {p.normal.x, p.normal.y, p.normal.z}};
        }
        count_ = 0;
    }

private:
    static constexpr uint32_t kSize = 64;

#if defined(__SSE2__)
    void displaceFour(uint32_t k) {
        auto load = [k](const float* a) { return _mm_loadu_ps(a + k); };
        auto cross = [](__m128 ax, __m128 ay, __m128 az, __m128 bx, __m128 by, __m128 bz, __m128* c) {
            c[0] = _mm_sub_ps(_mm_mul_ps(ay, bz), _mm_mul_ps(by, az));
            c[1] = _mm_sub_ps(_mm_mul_ps(az, bx), _mm_mul_ps(bz, ax));
            c[2] = _mm_sub_ps(_mm_mul_ps(ax, by), _mm_mul_ps(bx, ay));
        };
        auto length = [](const __m128* c) {  // glm::length: sqrt((x x + y y) + z z)
            return _mm_sqrt_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(c[0], c[0]), _mm_mul_ps(c[1], c[1])), _mm_mul_ps(c[2], c[2])));
        };
        const __m128 ux = load(ux_), uy = load(uy_), uz = load(uz_), vx = load(vx_), vy = load(vy_), vz = load(vz_);
        const __m128 zero = _mm_setzero_ps();
        // unitNormalOf: (du x dv) / length, zero where the length is not positive.
        __m128 c[3];
        cross(ux, uy, uz, vx, vy, vz, c);
        const __m128 l = length(c), positive = _mm_cmpgt_ps(l, zero);
        __m128 n[3];
        for (int a = 0; a < 3; ++a) n[a] = _mm_and_ps(positive, _mm_div_ps(c[a], l));
        // displacePoint.
        const __m128 d = load(d_), ddu = load(ddu_), ddv = load(ddv_);
        const __m128 p[3] = {_mm_add_ps(load(px_), _mm_mul_ps(d, n[0])), _mm_add_ps(load(py_), _mm_mul_ps(d, n[1])),
                             _mm_add_ps(load(pz_), _mm_mul_ps(d, n[2]))};
        const __m128 fux = _mm_add_ps(ux, _mm_mul_ps(ddu, n[0])), fuy = _mm_add_ps(uy, _mm_mul_ps(ddu, n[1])),
                     fuz = _mm_add_ps(uz, _mm_mul_ps(ddu, n[2]));
        const __m128 fvx = _mm_add_ps(vx, _mm_mul_ps(ddv, n[0])), fvy = _mm_add_ps(vy, _mm_mul_ps(ddv, n[1])),
                     fvz = _mm_add_ps(vz, _mm_mul_ps(ddv, n[2]));
        __m128 m[3];
        cross(fux, fuy, fuz, fvx, fvy, fvz, m);
        const __m128 ml = length(m), shaded = _mm_cmpgt_ps(ml, zero);
        __m128 normal[3];
        for (int a = 0; a < 3; ++a)
            normal[a] = _mm_or_ps(_mm_and_ps(shaded, _mm_div_ps(m[a], ml)), _mm_andnot_ps(shaded, n[a]));
        alignas(16) float out[6][4];
        for (int a = 0; a < 3; ++a) {
            _mm_store_ps(out[a], p[a]);
            _mm_store_ps(out[3 + a], normal[a]);
        }
        for (uint32_t lane = 0; lane < 4; ++lane)
            grid_[slot_[k + lane]] = GridVertex{{out[0][lane], out[1][lane], out[2][lane]}, {out[3][lane], out[4][lane], out[5][lane]}};
    }
#endif

    GridVertex* grid_;
    uint32_t count_ = 0;
    uint32_t slot_[kSize];
    float px_[kSize], py_[kSize], pz_[kSize], ux_[kSize], uy_[kSize], uz_[kSize], vx_[kSize], vy_[kSize], vz_[kSize];
    float d_[kSize], ddu_[kSize], ddv_[kSize];
};

// Displaces the evaluated slots of drawn sub-face `drawn` from their frames: all of them, or
// with `cells` (R x R flags of its displacement grid) those in a flagged cell, the cell
// evaluateDisplacement reads at the slot. Returns how many.
uint32_t displaceSlots(const GpuPlanData& data, const GridLayout& layout, uint32_t drawn, const Displacement& displacement,
                       const bool* cells, const GridFrame* frames, GridVertex* grid) {
    const uint32_t subface = data.subfaces[drawn].subface, n = layout.factors.subfaceFactor[drawn];
    const uint32_t first = layout.subfaceOffset[drawn];
    const SubfaceDisplacement D(displacement, subface);
    const uint32_t R = D.resolution();
    // (u, v) of column / row k as slotParameter computes them, and where in the displacement
    // grid evaluateDisplacement finds them (displacementCell splits into u and v).
    float at[kMaxGridFactor + 1];
    DisplacementCell along[kMaxGridFactor + 1];  // i and fx of column k (= j and fy of row k)
    for (uint32_t k = 0; k <= n; ++k) {
        at[k] = float(k) / float(n);
        along[k] = displacementCell(R, at[k], at[k]);
    }
    SlotDisplacer displacer(grid);
    uint32_t count = 0;
    for (uint32_t y = 0; y <= n; ++y) {
        const bool* row = cells ? cells + along[y].j * R : nullptr;
        const uint32_t* source = layout.source.data() + first + y * (n + 1);
        for (uint32_t x = 0; x <= n; ++x) {
            const uint32_t slot = first + y * (n + 1) + x;
            if (source[x] != slot || (row && !row[along[x].i])) continue;
            const DisplacementCell c{along[x].i, along[y].j, along[x].fx, along[y].fy};
            displacer.add(slot, frames[slot], D.isBilinear(c, at[x], at[y]) ? D.bilinear(c) : D.evaluate(at[x], at[y]));
            ++count;
        }
    }
    return count;
}

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
        if (isSingleBicubic(plan)) {
            evaluateBicubicSubface(planned, plan, subface, layout, drawn, out);
        } else {
            const uint32_t first = layout.subfaceOffset[drawn], end = layout.subfaceOffset[drawn + 1];
            for (uint32_t slot = first; slot < end; ++slot) {
                if (layout.source[slot] != slot) continue;
                float u, v;
                slotParameter(slot - first, n, u, v);
                out.write(planned, slot, planned.evaluate(subface, u, v), subface, u, v);
            }
        }
        if (out.displacement) displaceSlots(data, layout, drawn, *out.displacement, nullptr, out.frames, out.grid);
    });
}

void copyPhase(const GridLayout& layout, const uint32_t* list, size_t count, GridVertex* grid) {
    forEachSubface(list, count, [&](uint32_t drawn) {
        // Copied slots lie on the sub-face's boundary: rows 0 and n, columns 0 and n.
        const uint32_t first = layout.subfaceOffset[drawn], n = layout.factors.subfaceFactor[drawn];
        auto copy = [&](uint32_t slot) {
            if (layout.source[slot] != slot) grid[slot] = grid[layout.source[slot]];
        };
        for (uint32_t y = 0; y <= n; ++y) {
            const uint32_t row = first + y * (n + 1);
            if (y == 0 || y == n) {
                for (uint32_t x = 0; x <= n; ++x) copy(row + x);
            } else {
                copy(row);
                copy(row + n);
            }
        }
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

namespace {

// Cells (i, j), 0 <= i, j < R, of a sub-face's displacement grid whose D reads a changed
// sample (evaluateDisplacement): one of its four corners, or, in the row of cells along an
// edge finer than the grid, a sample of that edge's segments.
void markChangedCells(const DisplacementLayout& layout, uint32_t subface, SampleMarks changed, bool* cells) {
    const DisplacementSubface& sf = layout.subfaces[subface];
    const uint32_t R = sf.resolution, side = R + 1;
    bool point[(kMaxDisplacementResolution + 1) * (kMaxDisplacementResolution + 1)];
    for (uint32_t j = 0; j < side; ++j)
        for (uint32_t i = 0; i < side; ++i) point[j * side + i] = changed.marked(gridSample(layout, subface, i, j));
    for (uint32_t j = 0; j < R; ++j)
        for (uint32_t i = 0; i < R; ++i)
            cells[j * R + i] = point[j * side + i] || point[j * side + i + 1] || point[(j + 1) * side + i] ||
                               point[(j + 1) * side + i + 1];
    for (uint32_t e = 0; e < 4; ++e) {
        const DisplacementEdge& edge = sf.edges[e];
        if (!(edge.flags & kEdgeFiner)) continue;
        bool any = false;
        for (uint32_t segment : {edge.segment, edge.secondHalf}) {
            if (segment == kNoSegment) continue;
            const DisplacementSegment& s = layout.segments[segment];
            for (uint32_t k = 0; k <= s.resolution && !any; ++k) any = changed.marked(segmentSample(s, k));
        }
        if (!any) continue;
        for (uint32_t k = 0; k < R; ++k) {
            const uint32_t i = e == 0 || e == 2 ? k : e == 1 ? R - 1 : 0;
            const uint32_t j = e == 1 || e == 3 ? k : e == 2 ? R - 1 : 0;
            cells[j * R + i] = true;
        }
    }
}

}  // namespace

uint32_t redisplaceGridOnCpu(const GpuPlanData& data, const GridLayout& layout, std::span<const uint32_t> evaluate,
                             std::span<const uint32_t> copy, const Displacement& displacement, SampleMarks changed,
                             const GridFrame* frames, GridVertex* grid) {
    std::atomic<uint32_t> displaced{0};
    forEachSubface(evaluate.data(), evaluate.size(), [&](uint32_t drawn) {
        bool cells[kMaxDisplacementResolution * kMaxDisplacementResolution];
        markChangedCells(displacement.layout, data.subfaces[drawn].subface, changed, cells);
        displaced += displaceSlots(data, layout, drawn, displacement, cells, frames, grid);
    });
    copyPhase(layout, copy.data(), copy.size(), grid);
    return displaced;
}

}  // namespace qp
