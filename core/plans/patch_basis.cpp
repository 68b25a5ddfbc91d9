#include "plans/patch_basis.h"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace qp {

namespace {

// Uniform cubic B-spline basis on one span, x in [0,1], and its derivative.
void cubicBSpline(double x, double b[4], double d[4]) {
    double y = 1.0 - x, x2 = x * x, x3 = x2 * x;
    b[0] = y * y * y / 6.0;
    b[1] = (3.0 * x3 - 6.0 * x2 + 4.0) / 6.0;
    b[2] = (-3.0 * x3 + 3.0 * x2 + 3.0 * x + 1.0) / 6.0;
    b[3] = x3 / 6.0;
    d[0] = -0.5 * y * y;
    d[1] = 1.5 * x2 - 2.0 * x;
    d[2] = -1.5 * x2 + x + 0.5;
    d[3] = 0.5 * x2;
}

// Cubic Bernstein basis and its derivative.
void cubicBernstein(double x, double b[4], double d[4]) {
    double y = 1.0 - x;
    b[0] = y * y * y;
    b[1] = 3.0 * x * y * y;
    b[2] = 3.0 * x * x * y;
    b[3] = x * x * x;
    d[0] = -3.0 * y * y;
    d[1] = 3.0 * y * (y - 2.0 * x);
    d[2] = 3.0 * x * (2.0 * y - x);
    d[3] = 3.0 * x * x;
}

void tensor(const double bu[4], const double du[4], const double bv[4], const double dv[4],
            BasisWeights& out) {
    std::fill(std::begin(out.w), std::end(out.w), 0.0f);
    std::fill(std::begin(out.du), std::end(out.du), 0.0f);
    std::fill(std::begin(out.dv), std::end(out.dv), 0.0f);
    for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 4; ++col) {
            out.w[4 * row + col] = float(bu[col] * bv[row]);
            out.du[4 * row + col] = float(du[col] * bv[row]);
            out.dv[4 * row + col] = float(bu[col] * dv[row]);
        }
}

// Moves the weight of phantom point `ph` = 2 * p1 - p2 onto p1 and p2 (all three arrays).
void fold(BasisWeights& b, int ph, int p1, int p2) {
    for (float* a : {b.w, b.du, b.dv}) {
        a[p1] += 2.0f * a[ph];
        a[p2] -= a[ph];
        a[ph] = 0.0f;
    }
}

}  // namespace

Basis1D bsplineBasis1D(float x) {
    double b[4], d[4];
    cubicBSpline(x, b, d);
    Basis1D out;
    for (int i = 0; i < 4; ++i) {
        out.b[i] = float(b[i]);
        out.d[i] = float(d[i]);
    }
    return out;
}

Basis1D creaseBasis1D(float x, float sharpness) {
    double bx[4], dx[4];
    cubicBSpline(x, bx, dx);
    // c(x) and c'(x): the weight of d = p0 - 2 p1 + p2 on top of the infinitely sharp curve
    // (derivation in the header). s <= 0 gives c = B0(x), the plain B-spline.
    double c = bx[0], dc = dx[0];
    if (sharpness >= 10.0f) {
        c = dc = 0.0;
    } else if (sharpness > 0.0f) {
        double n = std::floor(double(sharpness)), f = double(sharpness) - n;
        double h = std::ldexp(1.0, -int(n) - 1);      // span length after n + 1 steps
        double a0 = h, a1 = (1.0 - f) * h * 0.25;      // offsets at index -1 and at the crease
        double t = double(x) / h, b[4], d[4];
        c = dc = 0.0;
        if (t < 1.0) {
            cubicBSpline(t, b, d);
            c = a0 * b[0] + a1 * b[1];
            dc = (a0 * d[0] + a1 * d[1]) / h;
        } else if (t < 2.0) {
            cubicBSpline(t - 1.0, b, d);
            c = a1 * b[0];
            dc = a1 * d[0] / h;
        }
    }
    // Sharp basis (point 0 replaced by the phantom 2 p1 - p2) plus c * (p0 - 2 p1 + p2).
    const double sb[4] = {c, bx[1] + 2.0 * bx[0] - 2.0 * c, bx[2] - bx[0] + c, bx[3]};
    const double sd[4] = {dc, dx[1] + 2.0 * dx[0] - 2.0 * dc, dx[2] - dx[0] + dc, dx[3]};
    Basis1D out;
    for (int i = 0; i < 4; ++i) {
        out.b[i] = float(sb[i]);
        out.d[i] = float(sd[i]);
    }
    return out;
}

Basis1D creaseBasis1DFar(float x, float sharpness) {
    Basis1D near = creaseBasis1D(1.0f - x, sharpness), out;
    for (int i = 0; i < 4; ++i) {
        out.b[i] = near.b[3 - i];
        out.d[i] = -near.d[3 - i];
    }
    return out;
}

void foldNear(Basis1D& basis) {
    for (float* a : {basis.b, basis.d}) {
        a[1] += 2.0f * a[0];
        a[2] -= a[0];
        a[0] = 0.0f;
    }
}

void foldFar(Basis1D& basis) {
    for (float* a : {basis.b, basis.d}) {
        a[2] += 2.0f * a[3];
        a[1] -= a[3];
        a[3] = 0.0f;
    }
}

void bsplineWeights(float u, float v, BasisWeights& out) {
    double bu[4], du[4], bv[4], dv[4];
    cubicBSpline(u, bu, du);
    cubicBSpline(v, bv, dv);
    tensor(bu, du, bv, dv, out);
}

void creaseWeights(float u, float v, float sharpness, BasisWeights& out) {
    double bu[4], du[4];
    cubicBSpline(u, bu, du);
    Basis1D across = creaseBasis1D(v, sharpness);
    double sb[4], sd[4];
    for (int i = 0; i < 4; ++i) {
        sb[i] = across.b[i];
        sd[i] = across.d[i];
    }
    tensor(bu, du, sb, sd, out);
}

void foldBoundaryWeights(int boundaryMask, BasisWeights& inOut) {
    // Rows first, then columns: a corner phantom is folded twice, i.e. it is the phantom of the
    // phantoms next to it.
    for (int i = 0; i < 4; ++i) {
        if (boundaryMask & 1) fold(inOut, 0 * 4 + i, 1 * 4 + i, 2 * 4 + i);  // v=0: row 0
        if (boundaryMask & 4) fold(inOut, 3 * 4 + i, 2 * 4 + i, 1 * 4 + i);  // v=1: row 3
    }
    for (int i = 0; i < 4; ++i) {
        if (boundaryMask & 8) fold(inOut, 4 * i + 0, 4 * i + 1, 4 * i + 2);  // u=0: col 0
        if (boundaryMask & 2) fold(inOut, 4 * i + 3, 4 * i + 2, 4 * i + 1);  // u=1: col 3
    }
}

void gregoryWeights(float u, float v, BasisWeights& out, bool exactDerivatives) {
    double bu[4], du[4], bv[4], dv[4];
    cubicBernstein(u, bu, du);
    cubicBernstein(v, bv, dv);
    std::fill(std::begin(out.w), std::end(out.w), 0.0f);
    std::fill(std::begin(out.du), std::end(out.du), 0.0f);
    std::fill(std::begin(out.dv), std::end(out.dv), 0.0f);

    struct Corner {
        int p[2], ep[2], em[2], f[2];  // Bezier (i,j) of P, Ep, Em and the interior point
        double s0, su, sv;              // s = s0 + su*u + sv*v: distance along Ep's edge
        double t0, tu, tv;              // t: distance along Em's edge
    };
    static const Corner corners[4] = {
        {{0, 0}, {1, 0}, {0, 1}, {1, 1}, 0, 1, 0, 0, 0, 1},    // s = u,     t = v
        {{3, 0}, {3, 1}, {2, 0}, {2, 1}, 0, 0, 1, 1, -1, 0},   // s = v,     t = 1 - u
        {{3, 3}, {2, 3}, {3, 2}, {2, 2}, 1, -1, 0, 1, 0, -1},  // s = 1 - u, t = 1 - v
        {{0, 3}, {0, 2}, {1, 3}, {1, 2}, 1, 0, -1, 0, 1, 0},   // s = 1 - v, t = u
    };
    auto put = [&](int k, const int ij[2], double g, double gu, double gv) {
        double b = bu[ij[0]] * bv[ij[1]];
        out.w[k] = float(g * b);
        out.du[k] = float(g * du[ij[0]] * bv[ij[1]] + gu * b);
        out.dv[k] = float(g * bu[ij[0]] * dv[ij[1]] + gv * b);
    };
    for (int k = 0; k < 4; ++k) {
        const Corner& c = corners[k];
        put(5 * k + 0, c.p, 1, 0, 0);
        put(5 * k + 1, c.ep, 1, 0, 0);
        put(5 * k + 2, c.em, 1, 0, 0);
        // Fp gets s/(s+t), Fm t/(s+t); the derivative of a/(a+b) is (a'b - ab')/(a+b)^2.
        double s = c.s0 + c.su * u + c.sv * v, t = c.t0 + c.tu * u + c.tv * v, st = s + t;
        double g = 0.5, gu = 0.0, gv = 0.0;  // at the corner: see the header
        if (st > 0.0) g = s / st;
        if (st > 0.0 && exactDerivatives) {
            gu = (c.su * t - s * c.tu) / (st * st);
            gv = (c.sv * t - s * c.tv) / (st * st);
        }
        put(5 * k + 3, c.f, g, gu, gv);
        put(5 * k + 4, c.f, 1.0 - g, -gu, -gv);
    }
}

}  // namespace qp
