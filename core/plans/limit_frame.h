// Catmull-Clark limit position and limit tangents at a vertex of an all-quad cage, computed
// from its QuadRing in the scaling a bicubic Bezier corner uses: the patch corner is
// `position` and its edge control point towards ring neighbour e_j is position + tangents[j]
// (a third of the derivative along that edge, as for Bezier curves). Shared by ACC-1 and ACC-2.
//
// Interior vertex, valence n, theta = 2 pi / n, c = cos theta, lambda the subdominant
// eigenvalue of the Catmull-Clark subdivision matrix, (5 + c + cos(pi/n) sqrt(18 + 2c)) / 16:
//   position  = (n^2 v + 4 sum e_i + sum d_i) / (n (n + 5))                 (course eq. 9)
//   tangent_j = 1 / (n lambda (n + 5)) * sum_i [ a cos(theta (i-j)) (e_i - v)
//               + (cos(theta (i-j)) + cos(theta (i+1-j))) / 2 * (d_i - v) ]
// with a = 2 + 2c for TangentRule::AccEdgeMode: the first Fourier mode of ACC-1's edge points
// (the average of the two interior points beside each edge), divided by n lambda -- the
// construction OpenSubdiv's Gregory-basis end caps use for Loop et al. 2009. Its plane is not
// the limit tangent plane for n != 4: it moves when the cage is subdivided.
// TangentRule::Exact uses a = 8 lambda - 2, which makes the mask the left eigenvector of the
// subdivision matrix for lambda (OpenSubdiv's Sdc limit tangent masks have the same ratio of
// edge to face weights), so every tangent_j lies in the exact limit tangent plane; it is then
// divided by ((8 lambda - 2) + q) / ((2 + 2c) + q), q = (1 + c) / (4 lambda - 1), which makes
// both rules give the same vectors on the characteristic ring (the right eigenvector), so
// the two differ in direction only, not in typical length. For n = 4 both are the B-spline's
// Bezier edge points.
// TangentRule::LoopSchaefer has Exact's direction with the length of Loop and Schaefer 2008's
// limit tangent mask, as production ACC-1 implementations compute it (Valve's Source engine
// and Microsoft's SubD11 sample; plugins/acc1/README.md): 3 tangent_j =
//   sum_i (1/n + cos(pi/n) beta) cos(theta (i-j)) e_i + beta cos(theta (i-j) + pi/n) d_i,
//   beta = 1 / (n sqrt(4 + cos^2(pi/n))),
// the derivative of the patch along edge j for n = 4; for n != 4 it is 1.23 (n = 3) to 0.99
// (n = 5) to 1.46 (n = 12) times Exact's length. Boundary vertices: as Exact.
//
// Boundary vertex with k >= 2 faces, edge neighbours e_0 .. e_k (e_0, e_k on the boundary):
//   position  = (e_0 + 4 v + e_k) / 6                        (limit of the boundary B-spline)
//   tangent_j = A cos(pi j / k) + B sin(pi j / k),  A = (e_0 - e_k) / 6,
//   B = 1/3 [ g v + a0 (e_0 + e_k) + sum_{x=1}^{k-1} a_x e_x + sum_{x=0}^{k-1} b_x d_x ]
//   with c = cos(pi/k), s = sin(pi/k), g = -4 s / (3k + c),
//   a0 = -(1 + 2c) sqrt(1 + c) / ((3k + c) sqrt(1 - c)), a_x = 4 sin(pi x / k) / (3k + c),
//   b_x = (sin(pi x / k) + sin(pi (x+1) / k)) / (3k + c):
//   the cross-boundary limit tangent of Catmull-Clark boundary rules (the weights OpenSubdiv's
//   Gregory-basis end caps use; exact for k = 2, checked against the exact limit in the tests).
// Corner (one face, boundary rule "edges and corners"): position v, tangent_j = (e_j - v) / 3.
// One face without the corner rule: position (e_0 + 4 v + e_1) / 6, tangent_j = (e_j - v) / 3
// (an approximation: the exact limit has both edges along the boundary tangent there).
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "mesh/cage.h"
#include "plans/quad_ring.h"

namespace qp {

enum class TangentRule { Exact, AccEdgeMode, LoopSchaefer };

struct VertexLimit {
    glm::dvec3 position{0.0};
    std::vector<glm::dvec3> tangents;  // one per ring edge neighbour
    // cos(2 pi / effective valence): tangents satisfy t_{j-1} + t_{j+1} = 2 cosine t_j, the
    // vertex term of the G1 conditions. 0 at a corner, whose two edges are independent.
    double cosine = 0.0;
    bool corner = false;
};

// Subdominant eigenvalue of the Catmull-Clark subdivision matrix at an interior vertex.
double subdominantEigenvalue(uint32_t valence);

VertexLimit computeVertexLimit(const Cage& cage, const QuadRing& ring, TangentRule rule = TangentRule::Exact);

// The interior Bezier point of face i of the ring at its centre (course eq. 10, corrected):
// (n v + 2 e_i + 2 e_{i+1} + d_i) / (n + 5), n the effective valence (4 at a corner), which is
// the B-spline-to-Bezier rule for n = 4.
glm::dvec3 interiorBezierPoint(const Cage& cage, const QuadRing& ring, uint32_t face);

}  // namespace qp
