// Sculpted displacement on the GPU: the GLSL twin of core/displacement/displacement.cpp's
// evaluateDisplacement and displacePoint (docs/displacement.md; keep them in step). The three
// buffers are DisplacementLayout's tiles and padded blocks and Displacement::samples: per
// sub-face a bi-quadratic uniform B-spline over n x n cells whose (n + 2)^2 coefficients are
// padded[offset ..] (sample indices, row-major, i fastest) into the samples. A cage without
// displacement binds 16-byte placeholders: a padded block has at least 9 entries (36 bytes),
// so a placeholder holds none.
// Include after plan_eval.glsl.
#extension GL_EXT_control_flow_attributes : require

struct DispTile {
    uint cells;      // n cells per side
    uint offset;     // dispPadded[offset + (j + 1)(n + 2) + (i + 1)]: coefficient (i, j)'s sample
    uint edgeFlags;  // bits 4e..4e+3: edge e's flags (1 reversed, 2 split at a midpoint)
    uint unused;
};

#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 16) restrict readonly buffer DispTilesRef { DispTile data[]; };
#define dispTiles DispTilesRef(planBuffers.dispTilesAddress).data
#else
layout(std430, set = 0, binding = 18) readonly buffer DispTiles { DispTile dispTiles[]; };
#endif
#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 4) restrict readonly buffer DispPaddedRef { uint data[]; };
#define dispPadded DispPaddedRef(planBuffers.dispPaddedAddress).data
#else
layout(std430, set = 0, binding = 19) readonly buffer DispPadded { uint dispPadded[]; };
#endif
#ifdef QP_BY_ADDRESS
layout(buffer_reference, std430, buffer_reference_align = 4) restrict readonly buffer DispSamplesRef { float data[]; };
#define dispSamples DispSamplesRef(planBuffers.dispSamplesAddress).data
#else
layout(std430, set = 0, binding = 20) readonly buffer DispSamples { float dispSamples[]; };
#endif

const uint DISP_REVERSED = 1u, DISP_SPLIT = 2u;
const float DISP_SNAP = 16384.0;  // edge parameters snap to multiples of 2^-14

// The pipelines drawn without displacement compile their stages with QP_UNDISPLACED
// (render/plan_pipelines.h): the displacement code compiled in but unused doubled the cost of
// lavapipe's evaluation stage, and a specialisation constant removed only part of it.
#ifdef QP_UNDISPLACED
bool hasDisplacement() { return false; }
#else
bool hasDisplacement() { return PLAN_DISP_PADDED_COUNT > 4u; }
#endif

// Coefficient (i, j), -1 <= i, j <= n, of a tile.
float dispCoefficient(DispTile tile, int i, int j) {
    return dispSamples[dispPadded[tile.offset + uint(j + 1) * (tile.cells + 2u) + uint(i + 1)]];
}

// Padded (i, j) of the strip along tile edge e (core stripCell): row 0 is the tile's own cell
// next to the edge, row 1 the overlap across it; `along` in the edge's own direction.
ivec2 dispStripCell(uint e, int n, int along, int row) {
    int inner = row == 0 ? 0 : -1, outer = row == 0 ? n - 1 : n;
    if (e == 0u) return ivec2(along, inner);
    if (e == 1u) return ivec2(outer, along);
    if (e == 2u) return ivec2(along, outer);
    return ivec2(inner, along);
}

// std::round for t in [0, 1] (half away from zero, whatever the device's round() does with
// halves), then back to the 2^-14 grid: core's snapped().
float dispSnap(float t) {
    precise float x = clamp(t, 0.0, 1.0) * DISP_SNAP;
    precise float r = floor(x);
    if (x - r >= 0.5) r += 1.0;
    return r / DISP_SNAP;
}

// D on tile edge e at its own parameter t (core evaluateDisplacement on an edge): the same bits
// from both tiles that have the point. Pair sums (own + overlap) weighted in the edge segment's
// canonical direction at the snapped canonical parameter; at a knot crossing the mean of the
// four coefficients meeting there, added sorted. `precise` keeps the device from fusing
// multiply-adds: core's build does not (no FMA in its flags), so both sides and the CPU agree.
float dispEdgeValue(DispTile tile, uint e, float t) {
    int n = int(tile.cells);
    uint flags = (tile.edgeFlags >> (4u * e)) & 15u;
    bool split = (flags & DISP_SPLIT) != 0u;
    bool secondHalf = split && t > 0.5;
    int cells = split ? n / 2 : n;
    bool reversed = split ? secondHalf : (flags & DISP_REVERSED) != 0u;
    precise float local = split ? (secondHalf ? 2.0 * (1.0 - t) : 2.0 * t) : t;
    precise float canonicalT = reversed && !split ? 1.0 - local : local;
    precise float x = dispSnap(canonicalT) * float(cells);
    precise float fk = floor(x);
    int k = int(fk);
    // Canonical cell index -> the edge's own (core's ownAlong).
    int flip = secondHalf ? n - 1 : (reversed ? cells - 1 : -1);
    if (x == fk) {
        float four[4];
        [[unroll]] for (int r = 0; r < 2; ++r)
            [[unroll]] for (int side = 0; side < 2; ++side) {
                int c = k - 1 + side;
                ivec2 ij = dispStripCell(e, n, flip < 0 ? c : flip - c, r);
                four[2 * r + side] = dispCoefficient(tile, ij.x, ij.y);
            }
        // Sorted ascending as std::sort sorts (the sign of a zero cannot change the sum).
        float a = min(four[0], four[1]), b = max(four[0], four[1]);
        float c = min(four[2], four[3]), d = max(four[2], four[3]);
        float lo = min(a, c), hi = max(b, d);
        float m0 = max(a, c), m1 = min(b, d);
        float mid0 = min(m0, m1), mid1 = max(m0, m1);
        precise float mean = 0.25 * ((lo + mid0) + (mid1 + hi));
        return mean;
    }
    precise float f = x - fk;
    precise float g = 1.0 - f;
    precise float w0 = 0.5 * g * g;
    precise float w1 = 0.5 + f * g;
    precise float w2 = 0.5 * f * f;
    float pair[3];
    [[unroll]] for (int b = 0; b < 3; ++b) {
        int c = k - 1 + b;
        int along = flip < 0 ? c : flip - c;
        ivec2 own = dispStripCell(e, n, along, 0), over = dispStripCell(e, n, along, 1);
        pair[b] = dispCoefficient(tile, own.x, own.y) + dispCoefficient(tile, over.x, over.y);
    }
    precise float value = 0.0;
    value += w0 * (0.5 * pair[0]);
    value += w1 * (0.5 * pair[1]);
    value += w2 * (0.5 * pair[2]);
    return value;
}

// D(u, v) of a sub-face and its derivatives: (D, dD/du, dD/dv) (core evaluateDisplacement).
// Inside, the tile's span: the 3 x 3 coefficients around the point with the quadratic B-spline
// weights {g^2 / 2, 1/2 + f g, f^2 / 2} and their derivatives {-g, 1 - 2f, f}.
vec3 evaluateDisplacement(uint subface, vec2 uv) {
    DispTile tile = dispTiles[subface];
    float u = clamp(uv.x, 0.0, 1.0), v = clamp(uv.y, 0.0, 1.0);
    uint n = tile.cells;
    float nf = float(n);
    float x = u * nf, y = v * nf;
    uint i = min(uint(x), n - 1u), j = min(uint(y), n - 1u);
    float fu = x - float(i), gu = 1.0 - fu, fv = y - float(j), gv = 1.0 - fv;
    vec3 wu = vec3(0.5 * gu * gu, 0.5 + fu * gu, 0.5 * fu * fu), du = vec3(-gu, 1.0 - 2.0 * fu, fu);
    vec3 wv = vec3(0.5 * gv * gv, 0.5 + fv * gv, 0.5 * fv * fv), dv = vec3(-gv, 1.0 - 2.0 * fv, fv);
    // Span (i, j) reads cells i-1..i+1 x j-1..j+1: padded columns i..i+2, rows j..j+2.
    uint base = tile.offset + j * (n + 2u) + i;
    vec3 d = vec3(0.0);
    [[unroll]] for (uint b = 0u; b < 3u; ++b) {
        uint row = base + b * (n + 2u);
        vec3 c = vec3(dispSamples[dispPadded[row]], dispSamples[dispPadded[row + 1u]], dispSamples[dispPadded[row + 2u]]);
        float along = dot(wu, c), slope = dot(du, c);
        d += vec3(wv[b] * along, wv[b] * slope, dv[b] * along);
    }
    d.yz *= nf;
    // On an edge the value has the bits both tiles there compute.
    if (v == 0.0) d.x = dispEdgeValue(tile, 0u, u);
    else if (u == 1.0) d.x = dispEdgeValue(tile, 1u, v);
    else if (v == 1.0) d.x = dispEdgeValue(tile, 2u, u);
    else if (u == 0.0) d.x = dispEdgeValue(tile, 3u, v);
    return d;
}

// The limit sample of drawn sub-face `drawn` at uv and the unit normal to shade and displace
// with: the normal of du x dv (zero where that vanishes). With displacement, at the sub-face's
// corners the corner's own derivatives — at smooth extraordinary vertices they give the exact
// limit normal — unless they vanish next to those a step inside, and then the ones inside
// (cpu_grid.h, cornerDerivativesVanish, has the same rule and constants): at some extraordinary
// vertices the Gregory corner has none — exactly on the CPU, as rounding noise on the device —
// and a vertex must not be left undisplaced or pushed (or shaded) along noise. One evaluator
// call site, so the shaders stay small.
//
// The step is 1/64 of the sub-face: a parameter of factor 64, whose control points the pass
// computes whenever there is displacement (plan_pass.cpp, recordStencils); a step between
// those levels would read control points the stencil pass has not written.
const float kCornerNormalStep = 1.0 / 64.0;
const float kCornerVanishing = 1e-3;
LimitSample evaluateWithNormal(uint drawn, vec2 uv, out vec3 unitNormal) {
    bool corner = (uv.x == 0.0 || uv.x == 1.0) && (uv.y == 0.0 || uv.y == 1.0);
    bool lookInside = corner && hasDisplacement();
    LimitSample first;
    vec2 at = uv;
    [[dont_unroll]] for (uint attempt = 0u; attempt < 2u; ++attempt) {
        LimitSample s = evaluateSubface(drawn, at);
        if (attempt == 0u) {
            first = s;
            if (!lookInside) break;
            at = vec2(uv.x + (uv.x < 0.5 ? kCornerNormalStep : -kCornerNormalStep), uv.y + (uv.y < 0.5 ? kCornerNormalStep : -kCornerNormalStep));
            continue;
        }
        if (!(length(cross(first.du, first.dv)) > kCornerVanishing * length(cross(s.du, s.dv)))) {
            first.du = s.du;
            first.dv = s.dv;
        }
    }
    vec3 n = cross(first.du, first.dv);
    float len = length(n);
    unitNormal = len > 0.0 ? n / len : vec3(0.0);
    return first;
}

// s + D N with displacePoint's shading normal (normalize(f_u x f_v), f_u ~ s_u + D_u N;
// unitNormal where that vanishes). Does nothing without displacement.
void displaceSurfacePoint(uint subface, vec2 uv, vec3 du, vec3 dv, vec3 unitNormal, inout vec3 position, out vec3 normal) {
    normal = unitNormal;
    if (!hasDisplacement()) return;
    vec3 d = evaluateDisplacement(subface, uv);
    position += d.x * unitNormal;
    vec3 n = cross(du + d.y * unitNormal, dv + d.z * unitNormal);
    float len = length(n);
    if (len > 0.0) normal = n / len;
}
