// Sculpted displacement on the GPU: the GLSL twin of core/displacement.cpp's
// evaluateDisplacement and displacePoint (docs/displacement.md; keep them in step). The three
// buffers are DisplacementLayout's subfaces and segments and Displacement::samples; a cage
// without displacement binds 16-byte placeholders, which hold no sub-face record.
// Include after plan_eval.glsl.
#extension GL_EXT_control_flow_attributes : require

struct DispEdge {
    uint segment;
    uint secondHalf;
    uint flags;  // 1 reversed, 2 split at a midpoint, 4 finer than the sub-face's grid
    uint unused;
};
struct DispSubface {
    uint resolution;
    uint interiorOffset;
    uint unused0, unused1;
    uint corners[4];
    DispEdge edges[4];
};
struct DispSegment {
    uint pointA, pointB, resolution, offset;
};

layout(std430, set = 0, binding = 18) readonly buffer DispSubfaces { DispSubface dispSubfaces[]; };
layout(std430, set = 0, binding = 19) readonly buffer DispSegments { DispSegment dispSegments[]; };
layout(std430, set = 0, binding = 20) readonly buffer DispSamples { float dispSamples[]; };

const uint DISP_REVERSED = 1u, DISP_SPLIT = 2u, DISP_FINER = 4u;
const float DISP_SNAP = 16384.0;  // edge parameters snap to multiples of 2^-14

// The pipelines drawn without displacement compile their stages with QP_UNDISPLACED
// (render/plan_pipelines.h): the displacement code compiled in but unused doubled the cost of
// lavapipe's evaluation stage, and a specialisation constant removed only part of it.
#ifdef QP_UNDISPLACED
bool hasDisplacement() { return false; }
#else
bool hasDisplacement() { return dispSubfaces.length() > 0; }
#endif

uint dispSegmentSample(DispSegment s, uint k) {
    return k == 0u ? s.pointA : (k == s.resolution ? s.pointB : s.offset + k - 1u);
}

// Value and d/dt of a segment at canonical t; on a sample, the sample's bits.
vec2 dispSegmentValue(uint segment, float t) {
    DispSegment s = dispSegments[segment];
    float x = clamp(t, 0.0, 1.0) * float(s.resolution);
    uint k = min(uint(x), s.resolution - 1u);
    float f = x - float(k);
    float a = dispSamples[dispSegmentSample(s, k)], b = dispSamples[dispSegmentSample(s, k + 1u)];
    precise float value = f == 0.0 ? a : (f == 1.0 ? b : (1.0 - f) * a + f * b);
    return vec2(value, float(s.resolution) * (b - a));
}

float dispSnap(float t, bool snap) { return snap ? round(t * DISP_SNAP) / DISP_SNAP : t; }

// Edge function of a sub-face edge at its own parameter t: (value, dE/dt).
vec2 dispEdgeValue(DispEdge e, float t, bool snap) {
    if ((e.flags & DISP_SPLIT) == 0u) {
        bool reversed = (e.flags & DISP_REVERSED) != 0u;
        precise float tc = reversed ? 1.0 - t : t;
        vec2 v = dispSegmentValue(e.segment, dispSnap(tc, snap));
        return reversed ? vec2(v.x, -v.y) : v;
    }
    if (t <= 0.5) {
        precise float tc = 2.0 * t;
        vec2 v = dispSegmentValue(e.segment, dispSnap(tc, snap));
        return vec2(v.x, 2.0 * v.y);
    }
    precise float tc = 2.0 * (1.0 - t);
    vec2 v = dispSegmentValue(e.secondHalf, dispSnap(tc, snap));
    return vec2(v.x, -2.0 * v.y);
}

// Sample index of grid point (i, j) of a sub-face (core gridSample).
uint dispGridSample(uint subface, uint i, uint j) {
    DispSubface sf = dispSubfaces[subface];
    uint R = sf.resolution;
    if (i > 0u && i < R && j > 0u && j < R) return sf.interiorOffset + (j - 1u) * (R - 1u) + (i - 1u);
    uint edge = j == 0u ? 0u : (i == R ? 1u : (j == R ? 2u : 3u));
    uint along = edge == 0u || edge == 2u ? i : j;
    const uint edgeStart[4] = uint[4](0u, 1u, 3u, 0u), edgeEnd[4] = uint[4](1u, 2u, 2u, 3u);
    if (along == 0u) return sf.corners[edgeStart[edge]];
    if (along == R) return sf.corners[edgeEnd[edge]];
    DispEdge e = sf.edges[edge];
    uint segment = e.segment, k = along, intervals = R;  // edgeSite
    if ((e.flags & DISP_SPLIT) == 0u) {
        if ((e.flags & DISP_REVERSED) != 0u) k = R - along;
    } else {
        intervals = R / 2u;
        if (2u * along > R) {
            segment = e.secondHalf;
            k = R - along;
        }
    }
    DispSegment s = dispSegments[segment];
    return dispSegmentSample(s, k * (s.resolution / intervals));
}

// D(u, v) of a sub-face and its derivatives: (D, dD/du, dD/dv).
vec3 evaluateDisplacement(uint subface, vec2 uv) {
    DispSubface sf = dispSubfaces[subface];
    float u = clamp(uv.x, 0.0, 1.0), v = clamp(uv.y, 0.0, 1.0);
    uint R = sf.resolution;
    float Rf = float(R);
    float x = u * Rf, y = v * Rf;
    uint i = min(uint(x), R - 1u), j = min(uint(y), R - 1u);
    float fx = x - float(i), fy = y - float(j);
    float g00 = dispSamples[dispGridSample(subface, i, j)], g10 = dispSamples[dispGridSample(subface, i + 1u, j)];
    float g01 = dispSamples[dispGridSample(subface, i, j + 1u)], g11 = dispSamples[dispGridSample(subface, i + 1u, j + 1u)];
    float value = mix(mix(g00, g10, fx), mix(g01, g11, fx), fy);
    float du = Rf * mix(g10 - g00, g11 - g01, fy);
    float dv = Rf * mix(g01 - g00, g11 - g10, fx);

    // Boundary strips of edges finer than the grid: (E - L) fading over one cell.
    if (j == 0u && (sf.edges[0].flags & DISP_FINER) != 0u) {
        vec2 E = dispEdgeValue(sf.edges[0], u, false);
        float delta = E.x - mix(g00, g10, fx), w = 1.0 - fy;
        value += w * delta;
        du += w * (E.y - Rf * (g10 - g00));
        dv -= Rf * delta;
    }
    if (j == R - 1u && (sf.edges[2].flags & DISP_FINER) != 0u) {
        vec2 E = dispEdgeValue(sf.edges[2], u, false);
        float delta = E.x - mix(g01, g11, fx), w = fy;
        value += w * delta;
        du += w * (E.y - Rf * (g11 - g01));
        dv += Rf * delta;
    }
    if (i == 0u && (sf.edges[3].flags & DISP_FINER) != 0u) {
        vec2 E = dispEdgeValue(sf.edges[3], v, false);
        float delta = E.x - mix(g00, g01, fy), w = 1.0 - fx;
        value += w * delta;
        dv += w * (E.y - Rf * (g01 - g00));
        du -= Rf * delta;
    }
    if (i == R - 1u && (sf.edges[1].flags & DISP_FINER) != 0u) {
        vec2 E = dispEdgeValue(sf.edges[1], v, false);
        float delta = E.x - mix(g10, g11, fy), w = fx;
        value += w * delta;
        dv += w * (E.y - Rf * (g11 - g10));
        du += Rf * delta;
    }

    // On an edge the value comes from the shared edge samples alone.
    if (v == 0.0) value = dispEdgeValue(sf.edges[0], u, true).x;
    else if (u == 1.0) value = dispEdgeValue(sf.edges[1], v, true).x;
    else if (v == 1.0) value = dispEdgeValue(sf.edges[2], u, true).x;
    else if (u == 0.0) value = dispEdgeValue(sf.edges[3], v, true).x;
    return vec3(value, du, dv);
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
