// Patch bases shared by the GPU evaluators: the plans' (plan_eval.glsl) and osd-fas's
// tessellation stages (plugins/osd-fas). The GLSL twin of core/plans/patch_basis.cpp; keep them in step.
//
// Boundary folding and semi-sharp creases change only the 1D basis across the edge they sit
// on (every rule is a tensor product on a regular patch), so they are applied to the 1D
// basis vectors instead of to 16 weights.

#ifndef QP_PATCH_BASIS_GLSL
#define QP_PATCH_BASIS_GLSL

struct LimitSample {
    vec3 position;
    vec3 du;
    vec3 dv;
};

void bsplineBasis(float x, out vec4 b, out vec4 d) {
    float y = 1.0 - x, x2 = x * x, x3 = x2 * x;
    b = vec4(y * y * y, 3.0 * x3 - 6.0 * x2 + 4.0, -3.0 * x3 + 3.0 * x2 + 3.0 * x + 1.0, x3) / 6.0;
    d = vec4(-0.5 * y * y, 1.5 * x2 - 2.0 * x, -1.5 * x2 + x + 0.5, 0.5 * x2);
}

void bernsteinBasis(float x, out vec4 b, out vec4 d) {
    float y = 1.0 - x;
    b = vec4(y * y * y, 3.0 * x * y * y, 3.0 * x * x * y, x * x * x);
    d = vec4(-3.0 * y * y, 3.0 * y * (y - 2.0 * x), 3.0 * x * (2.0 * y - x), 3.0 * x * x);
}

// 1D basis across a semi-sharp crease through point 1 (point 0 beyond it); see
// core/plans/patch_basis.h for the derivation.
void creaseBasis(float x, float sharpness, out vec4 b, out vec4 d) {
    vec4 bx, dx;
    bsplineBasis(x, bx, dx);
    float c = bx.x, dc = dx.x;
    if (sharpness >= 10.0) {
        c = 0.0;
        dc = 0.0;
    } else if (sharpness > 0.0) {
        float n = floor(sharpness), f = sharpness - n;
        float h = exp2(-n - 1.0);
        float a0 = h, a1 = (1.0 - f) * h * 0.25;
        float t = x / h;
        vec4 bt, dt;
        c = 0.0;
        dc = 0.0;
        if (t < 1.0) {
            bsplineBasis(t, bt, dt);
            c = a0 * bt.x + a1 * bt.y;
            dc = (a0 * dt.x + a1 * dt.y) / h;
        } else if (t < 2.0) {
            bsplineBasis(t - 1.0, bt, dt);
            c = a1 * bt.x;
            dc = a1 * dt.x / h;
        }
    }
    b = vec4(c, bx.y + 2.0 * bx.x - 2.0 * c, bx.z - bx.x + c, bx.w);
    d = vec4(dc, dx.y + 2.0 * dx.x - 2.0 * dc, dx.z - dx.x + dc, dx.w);
}

// The same crease on the far edge (through point 2, point 3 beyond it).
void creaseBasisFar(float x, float sharpness, out vec4 b, out vec4 d) {
    vec4 rb, rd;
    creaseBasis(1.0 - x, sharpness, rb, rd);
    b = rb.wzyx;
    d = -rd.wzyx;
}

// Phantom point 0 = 2 p1 - p2 (boundary at the near edge), or 3 = 2 p2 - p1 (far edge).
vec4 foldNear(vec4 b) { return vec4(0.0, b.y + 2.0 * b.x, b.z - b.x, b.w); }
vec4 foldFar(vec4 b) { return vec4(b.x, b.y - b.w, b.z + 2.0 * b.w, 0.0); }

// One Bezier point's share of a sample: value, and derivatives along u and v.
void addBezier(inout LimitSample r, vec3 cp, float bu, float du, float bv, float dv) {
    r.position += bu * bv * cp;
    r.du += du * bv * cp;
    r.dv += bu * dv * cp;
}

// Weight of a corner's Fp point against its Fm point (s, t: distances along Ep's and Em's edges).
float gregoryWeight(float s, float t) {
    float st = s + t;
    return st > 0.0 ? s / st : 0.5;
}

// Gregory patch in OpenSubdiv's GREGORY_BASIS order (corner k: P, Ep, Em, Fp, Fm), written out
// per corner: as a loop over corners with tables of Bezier indices it took about half of the
// grid compute pass on lavapipe, although few samples reach it (docs/renderer.md).
LimitSample gregoryBasisPatch(vec3 p[20], float u, float v) {
    vec4 bu, du, bv, dv;
    bernsteinBasis(u, bu, du);
    bernsteinBasis(v, bv, dv);
    float g0 = gregoryWeight(u, v), g1 = gregoryWeight(v, 1.0 - u);
    float g2 = gregoryWeight(1.0 - u, 1.0 - v), g3 = gregoryWeight(1.0 - v, u);
    LimitSample r = LimitSample(vec3(0.0), vec3(0.0), vec3(0.0));
    // Corner 0 at Bezier (0, 0): P (0, 0), Ep (1, 0), Em (0, 1), F (1, 1).
    addBezier(r, p[0], bu.x, du.x, bv.x, dv.x);
    addBezier(r, p[1], bu.y, du.y, bv.x, dv.x);
    addBezier(r, p[2], bu.x, du.x, bv.y, dv.y);
    addBezier(r, g0 * p[3] + (1.0 - g0) * p[4], bu.y, du.y, bv.y, dv.y);
    // Corner 1 at (3, 0): P (3, 0), Ep (3, 1), Em (2, 0), F (2, 1).
    addBezier(r, p[5], bu.w, du.w, bv.x, dv.x);
    addBezier(r, p[6], bu.w, du.w, bv.y, dv.y);
    addBezier(r, p[7], bu.z, du.z, bv.x, dv.x);
    addBezier(r, g1 * p[8] + (1.0 - g1) * p[9], bu.z, du.z, bv.y, dv.y);
    // Corner 2 at (3, 3): P (3, 3), Ep (2, 3), Em (3, 2), F (2, 2).
    addBezier(r, p[10], bu.w, du.w, bv.w, dv.w);
    addBezier(r, p[11], bu.z, du.z, bv.w, dv.w);
    addBezier(r, p[12], bu.w, du.w, bv.z, dv.z);
    addBezier(r, g2 * p[13] + (1.0 - g2) * p[14], bu.z, du.z, bv.z, dv.z);
    // Corner 3 at (0, 3): P (0, 3), Ep (0, 2), Em (1, 3), F (1, 2).
    addBezier(r, p[15], bu.x, du.x, bv.w, dv.w);
    addBezier(r, p[16], bu.x, du.x, bv.z, dv.z);
    addBezier(r, p[17], bu.y, du.y, bv.w, dv.w);
    addBezier(r, g3 * p[18] + (1.0 - g3) * p[19], bu.y, du.y, bv.z, dv.z);
    return r;
}

#endif
