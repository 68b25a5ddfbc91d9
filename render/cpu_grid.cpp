#include "cpu_grid.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <cstring>
#include <optional>

#include <glm/geometric.hpp>
#if defined(__SSE2__)
#include <xmmintrin.h>
#include <emmintrin.h>
#endif
#include "plans/patch_basis.h"

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
// (GridFrames), so with SSE each operation runs on four lanes, and so does D inside the
// sub-face (insideFour). Each lane performs the IEEE operations of displacePoint and
// unitNormalOf in their order (no fused multiply-add: the build does not enable FMA), so the
// bits are those of the scalar functions, which builds without SSE use.
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

// ---- D at the grid's slots -------------------------------------------------------------
// A tile's bi-quadratic B-spline (core evaluateDisplacement; keep in step) is a tensor
// product: each padded row r of the block, combined along u at a grid column x, gives the
// `along` (and `slope`, its u derivative) that every grid row in a span reading r uses. So
// they are computed once per (row, column) and a slot combines three of them along v, four
// consecutive slots of a row at once (their columns are consecutive). The operations and their
// order are the evaluator's (no fused multiply-add: the build does not enable FMA), so inside
// the sub-face the values are SubfaceDisplacement::inside's bit for bit; on its border the
// evaluator itself gives them (the edge rule that makes both sides agree).

// The span of a tile of `cells` cells at t in [0, 1] and its quadratic B-spline weights
// {g^2 / 2, 1/2 + f g, f^2 / 2} with their derivatives {-g, 1 - 2f, f}.
void spanAt(float t, uint32_t cells, uint32_t& span, float* w, float* d) {
    const float x = t * float(cells);
    span = std::min(uint32_t(x), cells - 1);
    const float f = x - float(span), g = 1.0f - f;
    w[0] = 0.5f * g * g;
    w[1] = 0.5f + f * g;
    w[2] = 0.5f * f * f;
    d[0] = -g;
    d[1] = 1.0f - 2.0f * f;
    d[2] = f;
}

constexpr uint32_t kRow = kMaxGridFactor + kLanes;  // a grid row padded to whole lanes
constexpr uint32_t kMaxWidth = kMaxDisplacementResolution + 2;

// D at four consecutive slots of a grid row: `along` and `slope` point at the rows j, j + 1,
// j + 2 of the block combined at those columns; wv, dv the row's weights.
void insideFour(const float* const* along, const float* const* slope, const float* wv, const float* dv, float cells,
                float* value, float* du, float* dvOut) {
#if defined(__SSE2__)
    __m128 v = _mm_setzero_ps(), u = _mm_setzero_ps(), d = _mm_setzero_ps();
    for (int b = 0; b < 3; ++b) {
        const __m128 a = _mm_loadu_ps(along[b]), s = _mm_loadu_ps(slope[b]);
        const __m128 w = _mm_set1_ps(wv[b]), dw = _mm_set1_ps(dv[b]);
        v = _mm_add_ps(v, _mm_mul_ps(w, a));
        u = _mm_add_ps(u, _mm_mul_ps(w, s));
        d = _mm_add_ps(d, _mm_mul_ps(dw, a));
    }
    const __m128 n = _mm_set1_ps(cells);
    _mm_storeu_ps(value, v);
    _mm_storeu_ps(du, _mm_mul_ps(u, n));
    _mm_storeu_ps(dvOut, _mm_mul_ps(d, n));
#else
    for (uint32_t k = 0; k < kLanes; ++k) {
        float v = 0.0f, u = 0.0f, d = 0.0f;
        for (int b = 0; b < 3; ++b) {
            v += wv[b] * along[b][k];
            u += wv[b] * slope[b][k];
            d += dv[b] * along[b][k];
        }
        value[k] = v, du[k] = u * cells, dvOut[k] = d * cells;
    }
#endif
}

// Displaces the evaluated slots of drawn sub-face `drawn` from its frames (its GridFrames
// block): all of them, or with `spans` (cells x cells flags of its tile) those in a flagged
// span, the span whose 3 x 3 coefficients evaluateDisplacement reads at the slot (on the
// border too: the edge rule reads the own row and the overlap within them). Returns how many.
uint32_t displaceSlots(const GpuPlanData& data, const GridLayout& layout, uint32_t drawn, const Displacement& displacement,
                       const bool* spans, const float* frames, GridVertex* grid) {
    const uint32_t subface = data.subfaces[drawn].subface, n = layout.factors.subfaceFactor[drawn];
    const uint32_t first = layout.subfaceOffset[drawn], side = n + 1, stride = side * side;
    const DisplacementTile& tile = displacement.layout.tiles[subface];
    const uint32_t cells = tile.cells, width = cells + 2;
    // The border's slots go through the evaluator, gathered when first needed.
    std::optional<SubfaceDisplacement> border;
    // Per column (and row) k: (u, v) as slotParameter computes them, the span and its weights.
    float at[kRow] = {}, w[3][kRow] = {}, dw[3][kRow] = {};
    uint32_t span[kRow] = {};
    bool take[kRow] = {};
    for (uint32_t k = 0; k <= n; ++k) {
        at[k] = float(k) / float(n);
        float wk[3], dk[3];
        spanAt(at[k], cells, span[k], wk, dk);
        for (int b = 0; b < 3; ++b) w[b][k] = wk[b], dw[b][k] = dk[b];
    }
    // The block's rows combined along u at every column, when a grid row first reads them.
    float along[kMaxWidth][kRow], slope[kMaxWidth][kRow];
    bool ready[kMaxWidth] = {};
    const uint32_t* padded = displacement.layout.padded.data() + tile.offset;
    const float* samples = displacement.samples.data();
    auto prepare = [&](uint32_t r) {
        if (ready[r]) return;
        ready[r] = true;
        float c[kMaxWidth];
        for (uint32_t i = 0; i < width; ++i) c[i] = samples[padded[r * width + i]];
        for (uint32_t x = 0; x <= n; ++x) {
            const float* s = c + span[x];
            along[r][x] = w[0][x] * s[0] + w[1][x] * s[1] + w[2][x] * s[2];
            slope[r][x] = dw[0][x] * s[0] + dw[1][x] * s[1] + dw[2][x] * s[2];
        }
        for (uint32_t x = n + 1; x < n + kLanes; ++x) along[r][x] = slope[r][x] = 0.0f;
    };
    alignas(16) float value[kRow] = {}, du[kRow] = {}, dv[kRow] = {};
    uint32_t count = 0;
    for (uint32_t y = 0; y <= n; ++y) {
        const bool* spanRow = spans ? spans + span[y] * cells : nullptr;
        const uint32_t row = first + y * side;
        uint32_t taken = 0;
        for (uint32_t x = 0; x <= n; ++x) {
            take[x] = layout.source[row + x] == row + x && (!spanRow || spanRow[span[x]]);
            taken += take[x];
        }
        if (taken == 0) continue;
        count += taken;
        const bool borderRow = y == 0 || y == n;
        const uint32_t j = span[y];
        const float* alongRows[3] = {along[j], along[j + 1], along[j + 2]};
        const float* slopeRows[3] = {slope[j], slope[j + 1], slope[j + 2]};
        if (!borderRow)
            for (uint32_t r = j; r < j + 3; ++r) prepare(r);
        const float wv[3] = {w[0][y], w[1][y], w[2][y]}, dvw[3] = {dw[0][y], dw[1][y], dw[2][y]};
        for (uint32_t x0 = 0; x0 <= n; x0 += kLanes) {
            if (!(take[x0] || take[x0 + 1] || take[x0 + 2] || take[x0 + 3])) continue;
            if (!borderRow) {
                const float* a[3] = {alongRows[0] + x0, alongRows[1] + x0, alongRows[2] + x0};
                const float* s[3] = {slopeRows[0] + x0, slopeRows[1] + x0, slopeRows[2] + x0};
                insideFour(a, s, wv, dvw, float(cells), value + x0, du + x0, dv + x0);
            }
            for (uint32_t x = x0; x < x0 + kLanes; ++x) {
                if (!take[x] || !(borderRow || x == 0 || x == n)) continue;
                if (!border) border.emplace(displacement, subface);
                const DisplacementValue d = border->evaluate(at[x], at[y]);
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
// core/plans/plan_eval.cpp's regularPatch builds them (keep the two in step).
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
// are core/plans/plan_eval.cpp's tensorPatch, so the values are PlannedCage::evaluate's.
void evaluateBicubicSubface(const PlannedCage& planned, const Plan& plan, uint32_t subface,
                            const glm::vec3* controlPoints, const GridLayout& layout, uint32_t drawn, const Output& out) {
    const PlanNode& node = plan.nodes[0];
    const uint32_t* points = plan.points.data() + node.first;
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
        thread_local std::vector<glm::vec3> scratch;
        // Relative to the sub-face's origin (PlannedCage::storedControlPoints).
        const std::span<const glm::vec3> controlPoints = planned.controlPointsFor(subface, stencilLevelFor(n), scratch);
        if (isSingleBicubic(plan)) {
            evaluateBicubicSubface(planned, plan, subface, controlPoints.data(), layout, drawn, out);
        } else {
            const uint32_t first = layout.subfaceOffset[drawn], end = layout.subfaceOffset[drawn + 1];
            for (uint32_t slot = first; slot < end; ++slot) {
                if (layout.source[slot] != slot) continue;
                float u, v;
                slotParameter(slot - first, n, u, v);
                out.write(planned, slot, planned.evaluate(subface, controlPoints, u, v), subface, u, v);
            }
        }
        if (out.displacement)
            displaceSlots(data, layout, drawn, *out.displacement, nullptr, out.frames->block(layout, drawn), out.grid);
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

// Spans (i, j), 0 <= i, j < cells, of a tile whose D reads a changed sample: one of the 3 x 3
// coefficients around the span (padded columns i..i+2, rows j..j+2). Returns whether any is.
bool markChangedSpans(const DisplacementLayout& layout, uint32_t subface, const SampleBits& changed, bool* spans) {
    const DisplacementTile& tile = layout.tiles[subface];
    const uint32_t cells = tile.cells, width = cells + 2;
    bool coefficient[kMaxWidth * kMaxWidth];
    bool anyCoefficient = false;
    for (uint32_t k = 0; k < width * width; ++k) {
        coefficient[k] = changed.contains(layout.padded[tile.offset + k]);
        anyCoefficient = anyCoefficient || coefficient[k];
    }
    if (!anyCoefficient) return false;
    // Along u first (three padded columns), then along v (three padded rows).
    bool acrossU[kMaxWidth * kMaxDisplacementResolution];
    for (uint32_t r = 0; r < width; ++r)
        for (uint32_t i = 0; i < cells; ++i) {
            const bool* c = coefficient + r * width + i;
            acrossU[r * cells + i] = c[0] || c[1] || c[2];
        }
    bool any = false;
    for (uint32_t j = 0; j < cells; ++j)
        for (uint32_t i = 0; i < cells; ++i) {
            const bool* c = acrossU + j * cells + i;
            spans[j * cells + i] = c[0] || c[cells] || c[2 * cells];
            any = any || spans[j * cells + i];
        }
    return any;
}

}  // namespace

uint32_t redisplaceGridOnCpu(const GpuPlanData& data, const GridLayout& layout, std::span<const uint32_t> evaluate,
                             std::span<const uint32_t> copy, const Displacement& displacement, const SampleBits& changed,
                             const GridFrames& frames, GridVertex* grid) {
    std::atomic<uint32_t> displaced{0};
    forEachSubface(evaluate.data(), evaluate.size(), [&](uint32_t drawn) {
        bool spans[kMaxDisplacementResolution * kMaxDisplacementResolution];
        const uint32_t subface = data.subfaces[drawn].subface;
        if (!markChangedSpans(displacement.layout, subface, changed, spans)) return;
        displaced += displaceSlots(data, layout, drawn, displacement, spans, frames.block(layout, drawn), grid);
    });
    copyPhase(layout, copy.data(), copy.size(), grid);
    return displaced;
}

}  // namespace qp
