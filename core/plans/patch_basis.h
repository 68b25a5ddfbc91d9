// Basis weights (value, d/du, d/dv) of the patch kinds of a subdivision plan (see plan.h).
//
// Plain functions of (u,v) in [0,1]^2; a surface point is sum_i w[i] * P[i] over the patch's
// control points P, in the order each function documents. Computed in double, stored as float.
// All weight sets are affine: w sums to 1, du and dv sum to 0.
#pragma once

namespace qp {

// Up to 20 control points (Gregory). Unused entries are left 0.
struct BasisWeights {
    float w[20], du[20], dv[20];
};

// One direction of a tensor-product patch: 4 basis values and their derivatives. Boundary
// folding and semi-sharp creases change only the basis across the edge they lie on, so the plan
// evaluator works on these instead of on 16 weights (render/shaders/plan_eval.glsl does the same).
struct Basis1D {
    float b[4], d[4];
};

Basis1D bsplineBasis1D(float x);
// Across a semi-sharp crease through point 1 (point 0 beyond it), as in creaseWeights below.
Basis1D creaseBasis1D(float x, float sharpness);
// The same crease on the far side: through point 2, point 3 beyond it.
Basis1D creaseBasis1DFar(float x, float sharpness);
// Phantom point 0 = 2 p1 - p2 (boundary at the near edge) or 3 = 2 p2 - p1 (far edge).
void foldNear(Basis1D& basis);
void foldFar(Basis1D& basis);

// Uniform bicubic B-spline over [0,1]^2. 16 control points, row-major 4x4: index = 4*row + col,
// row along v, col along u. Point (col,row) = (1,1) is the patch corner at (u,v) = (0,0) and
// (2,2) the corner at (1,1). This is OpenSubdiv's REGULAR patch order.
void bsplineWeights(float u, float v, BasisWeights& out);

// Regular patch (16 points, order as bsplineWeights) with a semi-sharp crease of constant
// sharpness `sharpness` along its v=0 edge: the crease runs through control row 1, row 0 lies
// on the far side. Exact for OpenSubdiv's rules (uniform crease method), fractional sharpness
// included. sharpness <= 0: plain B-spline; >= 10: infinitely sharp (row 0 gets weight 0).
//
// Why it is exact. On a regular grid every Catmull-Clark rule, the crease rules included, is a
// tensor product of 1D rules: along the crease (u) the cubic B-spline rules, across it (v) the
// B-spline rules except at the crease row, whose vertex rule is lerp(smooth, identity, f) with
// f the blend weight of that level (edge points on the crease use the same v-rule). So the
// surface is B_u(u) x C(v) and only the v cross-section needs study. Across the crease:
//  - The sharp rule (identity at p1) is the B-spline rule applied to the polygon with the
//    phantom p0* = 2 p1 - p2 in place of p0 ((p0* + 6 p1 + p2)/8 = p1), and the phantom is
//    reproduced at every level, so an infinitely sharp crease is the B-spline with row 0
//    replaced by 2 row1 - row2.
//  - Write p0 = p0* + d, d = row0 - 2 row1 + row2. Sharp steps never read p0 for points at or
//    beyond p1; the new point left of the crease is (p0 + p1)/2 = phantom + d/2. After n = floor(s)
//    sharp steps the polygon is the phantom polygon plus d / 2^n at index -1 (left of crease).
//  - One blended step with f = s - n (uniform method: edge sharpness decays by 1 per level; at
//    the level where it drops to 0, OpenSubdiv blends the crease vertex rule with weight equal to
//    the parent sharpness f, clamped to 1, so integer s gives f = 0 here after s sharp steps)
//    gives offsets d/2^(n+1) at index -1 and (1-f) d/2^(n+3) at index 0 (the crease); every
//    other point at or beyond the crease is unchanged. Then everything is smooth and the limit
//    is the uniform B-spline of that polygon at spacing h = 2^-(n+1).
// Hence surface = infinitely-sharp surface + c(v) * (row0 - 2 row1 + row2), with
//    v in [0,h]:   c = 2^-(n+1) B0(v/h) + (1-f) 2^-(n+3) B1(v/h)
//    v in [h,2h]:  c = (1-f) 2^-(n+3) B0(v/h - 1)
//    otherwise 0,  where B0(x) = (1-x)^3/6, B1(x) = (3x^3 - 6x^2 + 4)/6.
// For s = 0 this is the B-spline refinement relation c = B0(v), the plain patch. Verified
// against OpenSubdiv's adaptive refinement in tests/plans/test_patch_basis.cpp.
void creaseWeights(float u, float v, float sharpness, BasisWeights& out);

// Boundary (or infinitely sharp) patch edges of a 16-point patch. Bits as OpenSubdiv's
// PatchParam boundary mask (edges in order from the patch's first corner): bit 0 = v=0 edge,
// bit 1 = u=1 edge, bit 2 = v=1 edge, bit 3 = u=0 edge. The control points beyond such an edge
// are phantoms, 2 p1 - p2 along the cross direction (row 0 = 2 row1 - row2 for bit 0, etc.;
// a corner phantom is the phantom of phantoms). Their weights are folded into the real points
// and set to 0, so callers never need phantom values. Apply after bsplineWeights or
// creaseWeights (whose crease edge, v=0, must then not be a boundary too).
void foldBoundaryWeights(int boundaryMask, BasisWeights& inOut);

// Gregory patch, 20 control points in OpenSubdiv's GREGORY_BASIS order: corner k = 0..3 at
// (0,0), (1,0), (1,1), (0,1) owns points 5k .. 5k+4 = P, Ep, Em, Fp, Fm:
//   P   the corner point;
//   Ep  the edge point towards the next corner (k+1, counter-clockwise), Em towards the previous;
//   Fp  the interior point belonging to Ep's edge, Fm the one belonging to Em's edge.
// As a bicubic Bezier net b(i,j) (i along u, j along v):
//   corner 0: P=b00 Ep=b10 Em=b01   corner 1: P=b30 Ep=b31 Em=b20
//   corner 2: P=b33 Ep=b23 Em=b32   corner 3: P=b03 Ep=b02 Em=b13
// and the interior point of corner k (b11, b21, b22, b12) is the rational blend
//   (s Fp + t Fm) / (s + t),   s, t = distance from the corner along Ep's and Em's edge,
// so each face point wins on its own edge (cross-boundary tangents come from it alone). At the
// corner itself s + t = 0; the interior point's Bernstein weight and its first derivatives
// vanish there, so the value is the limit corner P and any blend (we use 1/2) gives it.
//
// Derivatives: OpenSubdiv 3.5's PatchTable::EvaluateBasis differentiates the Bezier net with the
// blended interior points held fixed, i.e. it drops the derivative of the rational blend
// weights (checked numerically: its du/dv differ from finite differences of its own weights for
// Fp/Fm). By default we do the same, so plans agree with Far. exactDerivatives = true adds the
// blend terms and gives the true derivatives of the surface. The two differ only inside the
// patch: on its edges the interior Bernstein weights vanish, so edge tangents and normals (and
// thus continuity with neighbouring patches) are the same, and the Fp+Fm sums always agree.
void gregoryWeights(float u, float v, BasisWeights& out, bool exactDerivatives = false);

}  // namespace qp
