// The eigen structure of Catmull-Clark subdivision around an isolated extraordinary vertex of
// valence n, for Stam's exact evaluation (Stam 1998; S §3.5; L10 §4.2; digest §1.3).
//
// The 2n+8 control points of a quad whose corner 0 is the extraordinary vertex v, in this order:
//   0              v
//   1 + 2i, 2 + 2i e_i, d_i   (i = 0..n-1; face i = (v, e_i, d_i, e_{i+1}); the patch is face 0,
//                             so e_0 is its corner 1, d_0 its corner 2, e_1 its corner 3)
//   2n+1 .. 2n+7   the regular grid beyond: in the patch's B-spline grid (col, row), with v at
//                  (1,1), e_0 at (2,1), d_0 at (2,2), e_1 at (1,2): (3,0), (3,1), (3,2), (3,3),
//                  (2,3), (1,3), (0,3).
// One subdivision step maps them to the same 2n+8 points around the child of v (matrix A,
// (2n+8)^2) and to the three regular B-spline patches of the child level that cover the patch
// minus its corner quarter (sub-patch 1: u >= 1/2, v < 1/2; 2: both >= 1/2; 3: u < 1/2, v >= 1/2),
// 16 points each in core/plans/patch_basis.h's order (matrices P_k A-bar, 16 x (2n+8)).
// Both are computed, not typed in: one Catmull-Clark step on a small template mesh of the
// 2n+8 points (the n faces around v and the 5 regular faces beyond).
//
// Evaluation at level m (m = floor(-log2 max(u, v)) + 1) on sub-patch k:
//   x(u, v) = b(u', v') . P_k A-bar A^(m-1) C = [b . Phi_k] Lambda^(m-1) [V^-1 C]
// with A = V Lambda V^-1 computed numerically with Eigen (eigenvalues from EigenSolver, each
// eigenspace as the null space of A - lambda I by SVD, because most eigenvalues are double),
// Phi_k = P_k A-bar V the eigenbasis coefficients and V^-1 C the control points projected to
// eigenspace once per patch. The eigenvalue-1 eigenvector is scaled to all ones.
// Why the eigen decomposition and not explicit powers of A: it is Stam's method (constant
// cost per evaluation at any depth, tables of O((2n+8)^2) per valence), and A is
// diagonalisable with real eigenvalues for every valence tested (3..32): `reconstructionError`
// (max |V Lambda^m V^-1 - A^m| over m = 1..64, plus the residual of each null space) is
// checked by the tests.
#pragma once

#include <cstdint>
#include <vector>

namespace qp {

struct StamEigenStructure {
    uint32_t valence = 0, size = 0;             // size = 2n + 8
    std::vector<double> eigenvalues;            // size, descending (1 first)
    std::vector<double> inverseEigenvectors;    // V^-1, size x size, row-major
    std::vector<double> basis[3];               // Phi_k = P_k A-bar V, 16 x size, row-major
    std::vector<double> subdivision;            // A, size x size (for tests)
    std::vector<double> subpatches[3];          // P_k A-bar, 16 x size (for tests)
    double reconstructionError = 0.0;           // see above
};

// Computed once per valence (thread-safe) and kept. valence >= 3.
const StamEigenStructure& stamEigenStructure(uint32_t valence);

}  // namespace qp
