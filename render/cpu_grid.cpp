#include "cpu_grid.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>
#if defined(__SSE2__)
#include <xmmintrin.h>
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

// Where phase 1 writes: the grid, or with a displacement the frames (displaced afterwards,
// a sub-face at a time, by displaceSlots).
struct Output {
    GridVertex* grid;
    const Displacement* displacement;
    GridFrames* frames;
    const GridLayout& layout;

    // Slot `slot` of sub-face `subface` at (u, v): the limit point and the unit normal of
    // du x dv (zero where that vanishes), or with a displacement the frame: the limit point
    // and its derivatives, at sub-face corners where they vanish those kCornerNormalStep
    // inside (cornerDerivativesVanish).
    void write(const PlannedCage& planned, uint32_t slot, const LimitSample& s, uint32_t subface, float u, float v) const {
        if (!displacement) {
            const glm::vec3 n = unitNormalOf(s.du, s.dv);
            grid[slot] = GridVertex{{s.position.x, s.position.y, s.position.z}, {n.x, n.y, n.z}};
            return;
        }
        glm::vec3 du = s.du, dv = s.dv;
        if ((u == 0.0f || u == 1.0f) && (v == 0.0f || v == 1.0f)) {
            const LimitSample inside = planned.evaluate(subface, u + (u < 0.5f ? kCornerNormalStep : -kCornerNormalStep),
                                                        v + (v < 0.5f ? kCornerNormalStep : -kCornerNormalStep));
            if (cornerDerivativesVanish(du, dv, inside.du, inside.dv)) {
                du = inside.du;
                dv = inside.dv;
            }
        }
        const uint32_t drawn = layout.slotSubface[slot], first = layout.subfaceOffset[drawn];
        const uint32_t stride = layout.subfaceOffset[drawn + 1] - first;
        float* frame = frames->block(layout, drawn) + (slot - first);
        const float components[kFrameComponents] = {s.position.x, s.position.y, s.position.z, du.x, du.y, du.z,
                                                    dv.x,         dv.y,         dv.z};
        for (uint32_t c = 0; c < kFrameComponents; ++c) frame[c * stride] = components[c];
    }
};

// ---- displacing slots from their frames ------------------------------------------------
// s + D N along the frame's unit normal (unitNormalOf) with displacePoint's shading normal,
// four consecutive slots of a row at once: their frame components are consecutive
// (GridFrames), so with SSE each operation runs on four lanes, and so does D's bilinear
// interpolant. Each lane performs the IEEE operations of displacePoint, unitNormalOf and
// bilinearDisplacement in their order (no fused multiply-add: the build does not enable FMA),
// so the bits are those of the scalar functions, which builds without SSE use.
constexpr uint32_t kLanes = 4;
static_assert(sizeof(GridVertex) == 6 * sizeof(float));

// Slot k < 4 of the four: frame component c at frame[c * stride + k]; D at value[k], du[k],
// dv[k]. Writes the displaced vertex of slot k to vertices[k] where take[k].
void displaceFour(const float* frame, uint32_t stride, const float* value, const float* du, const float* dv,
                  const bool* take, GridVertex* vertices) {
#if defined(__SSE2__)
    auto component = [&](uint32_t c) { return _mm_loadu_ps(frame + size_t(c) * stride); };
    auto cross = [](__m128 ax, __m128 ay, __m128 az, __m128 bx, __m128 by, __m128 bz, __m128(&c)[3]) {
        c[0] = _mm_sub_ps(_mm_mul_ps(ay, bz), _mm_mul_ps(by, az));
        c[1] = _mm_sub_ps(_mm_mul_ps(az, bx), _mm_mul_ps(bz, ax));
        c[2] = _mm_sub_ps(_mm_mul_ps(ax, by), _mm_mul_ps(bx, ay));
    };
    auto length = [](const __m128(&c)[3]) {  // glm::length: sqrt((x x + y y) + z z)
        return _mm_sqrt_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(c[0], c[0]), _mm_mul_ps(c[1], c[1])), _mm_mul_ps(c[2], c[2])));
    };
    const __m128 ux = component(3), uy = component(4), uz = component(5);
    const __m128 vx = component(6), vy = component(7), vz = component(8);
    const __m128 zero = _mm_setzero_ps();
    // unitNormalOf: (du x dv) / length, zero where the length is not positive.
    __m128 c[3];
    cross(ux, uy, uz, vx, vy, vz, c);
    const __m128 l = length(c), positive = _mm_cmpgt_ps(l, zero);
    __m128 n[3];
    for (int a = 0; a < 3; ++a) n[a] = _mm_and_ps(positive, _mm_div_ps(c[a], l));
    // displacePoint.
    const __m128 d = _mm_loadu_ps(value), ddu = _mm_loadu_ps(du), ddv = _mm_loadu_ps(dv);
    __m128 p[3];
    for (int a = 0; a < 3; ++a) p[a] = _mm_add_ps(component(a), _mm_mul_ps(d, n[a]));
    __m128 m[3];
    cross(_mm_add_ps(ux, _mm_mul_ps(ddu, n[0])), _mm_add_ps(uy, _mm_mul_ps(ddu, n[1])), _mm_add_ps(uz, _mm_mul_ps(ddu, n[2])),
          _mm_add_ps(vx, _mm_mul_ps(ddv, n[0])), _mm_add_ps(vy, _mm_mul_ps(ddv, n[1])), _mm_add_ps(vz, _mm_mul_ps(ddv, n[2])), m);
    const __m128 ml = length(m), shaded = _mm_cmpgt_ps(ml, zero);
    __m128 normal[3];
    for (int a = 0; a < 3; ++a) normal[a] = _mm_or_ps(_mm_and_ps(shaded, _mm_div_ps(m[a], ml)), _mm_andnot_ps(shaded, n[a]));
    if (take[0] && take[1] && take[2] && take[3]) {
        // Four whole vertices: (px py pz nx) per slot, then the slots' (ny nz) pairs.
        __m128 a0 = p[0], a1 = p[1], a2 = p[2], a3 = normal[0];
        _MM_TRANSPOSE4_PS(a0, a1, a2, a3);
        const __m128 b01 = _mm_unpacklo_ps(normal[1], normal[2]), b23 = _mm_unpackhi_ps(normal[1], normal[2]);
        alignas(16) float packed[6 * kLanes];
        _mm_store_ps(packed + 0, a0);
        _mm_store_ps(packed + 4, _mm_movelh_ps(b01, a1));
        _mm_store_ps(packed + 8, _mm_shuffle_ps(a1, b01, _MM_SHUFFLE(3, 2, 3, 2)));
        _mm_store_ps(packed + 12, a2);
        _mm_store_ps(packed + 16, _mm_movelh_ps(b23, a3));
        _mm_store_ps(packed + 20, _mm_shuffle_ps(a3, b23, _MM_SHUFFLE(3, 2, 3, 2)));
        std::memcpy(vertices, packed, sizeof packed);
        return;
    }
    alignas(16) float out[6][kLanes];
    for (int a = 0; a < 3; ++a) {
        _mm_store_ps(out[a], p[a]);
        _mm_store_ps(out[3 + a], normal[a]);
    }
    for (uint32_t k = 0; k < kLanes; ++k)
        if (take[k]) vertices[k] = GridVertex{{out[0][k], out[1][k], out[2][k]}, {out[3][k], out[4][k], out[5][k]}};
#else
    for (uint32_t k = 0; k < kLanes; ++k) {
        if (!take[k]) continue;
        auto at = [&](uint32_t c) { return frame[size_t(c) * stride + k]; };
        const glm::vec3 dU(at(3), at(4), at(5)), dV(at(6), at(7), at(8));
        const DisplacedPoint p = displacePoint(glm::vec3(at(0), at(1), at(2)), dU, dV, unitNormalOf(dU, dV),
                                               DisplacementValue{value[k], du[k], dv[k]});
        vertices[k] = GridVertex{{p.position.x, p.position.y, p.position.z}, {p.normal.x, p.normal.y, p.normal.z}};
    }
#endif
}

// bilinearDisplacement at four points of one cell row (row j of the grid, at fy): lane k in
// cell column i[k] at fx[k].
void bilinearFour(const float* grid, uint32_t R, uint32_t j, float fy, const uint32_t* i, const float* fx, float* value,
                  float* du, float* dv) {
    const float* row0 = grid + j * (R + 1);
    const float* row1 = row0 + R + 1;
#if defined(__SSE2__)
    const __m128 g00 = _mm_setr_ps(row0[i[0]], row0[i[1]], row0[i[2]], row0[i[3]]);
    const __m128 g10 = _mm_setr_ps(row0[i[0] + 1], row0[i[1] + 1], row0[i[2] + 1], row0[i[3] + 1]);
    const __m128 g01 = _mm_setr_ps(row1[i[0]], row1[i[1]], row1[i[2]], row1[i[3]]);
    const __m128 g11 = _mm_setr_ps(row1[i[0] + 1], row1[i[1] + 1], row1[i[2] + 1], row1[i[3] + 1]);
    const __m128 one = _mm_set1_ps(1.0f), x = _mm_loadu_ps(fx), y = _mm_set1_ps(fy), r = _mm_set1_ps(float(R));
    auto lerp = [&](__m128 a, __m128 b, __m128 f) {  // displacementLerp: (1 - f) a + f b
        return _mm_add_ps(_mm_mul_ps(_mm_sub_ps(one, f), a), _mm_mul_ps(f, b));
    };
    _mm_storeu_ps(value, lerp(lerp(g00, g10, x), lerp(g01, g11, x), y));
    _mm_storeu_ps(du, _mm_mul_ps(r, lerp(_mm_sub_ps(g10, g00), _mm_sub_ps(g11, g01), y)));
    _mm_storeu_ps(dv, _mm_mul_ps(r, lerp(_mm_sub_ps(g01, g00), _mm_sub_ps(g11, g10), x)));
#else
    for (uint32_t k = 0; k < kLanes; ++k) {
        const DisplacementValue d =
            bilinearDisplacement(row0[i[k]], row0[i[k] + 1], row1[i[k]], row1[i[k] + 1], {i[k], j, fx[k], fy}, float(R));
        value[k] = d.value, du[k] = d.du, dv[k] = d.dv;
    }
#endif
}

// Displaces the evaluated slots of drawn sub-face `drawn` from its frames (its GridFrames
// block): all of them, or with `cells` (R x R flags of its displacement grid) those in a
// flagged cell, the cell evaluateDisplacement reads at the slot. `samples`: its gridSamples
// if at hand. Returns how many.
uint32_t displaceSlots(const GpuPlanData& data, const GridLayout& layout, uint32_t drawn, const Displacement& displacement,
                       const bool* cells, const uint32_t* samples, const float* frames, GridVertex* grid) {
    const uint32_t subface = data.subfaces[drawn].subface, n = layout.factors.subfaceFactor[drawn];
    const uint32_t first = layout.subfaceOffset[drawn], side = n + 1, stride = side * side;
    const SubfaceDisplacement D(displacement, subface, samples);
    const uint32_t R = D.resolution();
    // Per column (and row) k: (u, v) as slotParameter computes them, where in the displacement
    // grid evaluateDisplacement finds them (displacementCell splits into u and v), and whether
    // D is the bilinear interpolant there. Padded to whole lanes (cell 0, not bilinear).
    constexpr uint32_t kRow = kMaxGridFactor + kLanes;
    float at[kRow] = {}, fraction[kRow] = {};
    uint32_t cell[kRow] = {};
    bool bilinear[kRow] = {}, take[kRow] = {};
    for (uint32_t k = 0; k <= n; ++k) {
        at[k] = float(k) / float(n);
        const DisplacementCell c = displacementCell(R, at[k], at[k]);
        cell[k] = c.i, fraction[k] = c.fx;
        bilinear[k] = D.isBilinearAlongU(c.i, at[k]);
    }
    alignas(16) float value[kRow] = {}, du[kRow] = {}, dv[kRow] = {};
    uint32_t count = 0;
    for (uint32_t y = 0; y <= n; ++y) {
        const bool* cellRow = cells ? cells + cell[y] * R : nullptr;
        const uint32_t row = first + y * side;
        uint32_t taken = 0;
        for (uint32_t x = 0; x <= n; ++x) {
            take[x] = layout.source[row + x] == row + x && (!cellRow || cellRow[cell[x]]);
            taken += take[x];
        }
        if (taken == 0) continue;
        count += taken;
        const bool rowBilinear = D.isBilinearAlongV(cell[y], at[y]);
        for (uint32_t x0 = 0; x0 <= n; x0 += kLanes) {
            if (!(take[x0] || take[x0 + 1] || take[x0 + 2] || take[x0 + 3])) continue;
            if (rowBilinear) bilinearFour(D.grid(), R, cell[y], fraction[y], cell + x0, fraction + x0, value + x0, du + x0, dv + x0);
            for (uint32_t x = x0; x < x0 + kLanes; ++x) {
                if (!take[x] || (rowBilinear && bilinear[x])) continue;
                const DisplacementValue d = D.evaluate(at[x], at[y]);
                value[x] = d.value, du[x] = d.du, dv[x] = d.dv;
            }
            displaceFour(frames + y * side + x0, stride, value + x0, du + x0, dv + x0, take + x0, grid + row + x0);
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
    const glm::vec3* controlPoints = planned.subfaceControlPoints(subface).data();  // relative to `origin`
    const glm::vec3 origin = planned.subfaceOrigin(subface);
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
            sample.position += origin;
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
        if (out.displacement)
            displaceSlots(data, layout, drawn, *out.displacement, nullptr, nullptr, out.frames->block(layout, drawn), out.grid);
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
                       const Displacement* displacement, GridFrames* frames) {
    evaluatePhase(planned, data, layout, evaluate.data(), evaluate.size(), Output{grid, displacement, frames, layout});
    copyPhase(layout, copy.data(), copy.size(), grid);
}

void evaluateWholeGridOnCpu(const PlannedCage& planned, const GpuPlanData& data, const GridLayout& layout,
                            GridVertex* grid, const Displacement* displacement, GridFrames* frames) {
    evaluatePhase(planned, data, layout, nullptr, data.subfaces.size(), Output{grid, displacement, frames, layout});
    copyPhase(layout, nullptr, data.subfaces.size(), grid);
}

namespace {

// Cells (i, j), 0 <= i, j < R, of a sub-face's displacement grid whose D reads a changed
// sample (evaluateDisplacement): one of its four corners, or, in the row of cells along an
// edge finer than the grid, a sample of that edge's segments. `samples`: its gridSamples.
// Returns whether any cell is.
bool markChangedCells(const DisplacementLayout& layout, uint32_t subface, const uint32_t* samples, const SampleBits& changed,
                      bool* cells) {
    const DisplacementSubface& sf = layout.subfaces[subface];
    const uint32_t R = sf.resolution, side = R + 1;
    bool point[(kMaxDisplacementResolution + 1) * (kMaxDisplacementResolution + 1)];
    for (uint32_t k = 0; k < side * side; ++k) point[k] = changed.contains(samples[k]);
    bool anyCell = false;
    for (uint32_t j = 0; j < R; ++j)
        for (uint32_t i = 0; i < R; ++i) {
            cells[j * R + i] = point[j * side + i] || point[j * side + i + 1] || point[(j + 1) * side + i] ||
                               point[(j + 1) * side + i + 1];
            anyCell = anyCell || cells[j * R + i];
        }
    for (uint32_t e = 0; e < 4; ++e) {
        const DisplacementEdge& edge = sf.edges[e];
        if (!(edge.flags & kEdgeFiner)) continue;
        bool any = false;
        for (uint32_t segment : {edge.segment, edge.secondHalf}) {
            if (segment == kNoSegment) continue;
            const DisplacementSegment& s = layout.segments[segment];
            for (uint32_t k = 0; k <= s.resolution && !any; ++k) any = changed.contains(segmentSample(s, k));
        }
        if (!any) continue;
        for (uint32_t k = 0; k < R; ++k) {
            const uint32_t i = e == 0 || e == 2 ? k : e == 1 ? R - 1 : 0;
            const uint32_t j = e == 1 || e == 3 ? k : e == 2 ? R - 1 : 0;
            cells[j * R + i] = true;
        }
        anyCell = true;
    }
    return anyCell;
}

}  // namespace

uint32_t redisplaceGridOnCpu(const GpuPlanData& data, const GridLayout& layout, std::span<const uint32_t> evaluate,
                             std::span<const uint32_t> copy, const Displacement& displacement, const SampleBits& changed,
                             const GridFrames& frames, GridVertex* grid) {
    std::atomic<uint32_t> displaced{0};
    forEachSubface(evaluate.data(), evaluate.size(), [&](uint32_t drawn) {
        bool cells[kMaxDisplacementResolution * kMaxDisplacementResolution];
        const uint32_t subface = data.subfaces[drawn].subface;
        uint32_t samples[(kMaxDisplacementResolution + 1) * (kMaxDisplacementResolution + 1)];
        gridSamples(displacement.layout, subface, samples);
        if (!markChangedCells(displacement.layout, subface, samples, changed, cells)) return;
        displaced += displaceSlots(data, layout, drawn, displacement, cells, samples, frames.block(layout, drawn), grid);
    });
    copyPhase(layout, copy.data(), copy.size(), grid);
    return displaced;
}

}  // namespace qp
