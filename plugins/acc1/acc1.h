// ACC-1: Loop and Schaefer 2008, "Approximating Catmull-Clark Subdivision Surfaces with Bicubic
// Patches" (C §1.8.2, §2.3.2-2.3.3; S §3.6.2; digest §1.5). Per quad a bicubic Bezier geometry
// patch (16 points, C0 across edges at extraordinary vertices) and a pair of tangent patches
// (degree 2x3 for d/du and 3x2 for d/dv, 12 points each) whose cross product is a continuous
// normal field: 40 control points per quad.
//
// Geometry patch (corner k, the quad is face i of the ring of corner k, limit_frame.h):
//   corner    b00 = limit position                                (course eq. 9)
//   interior  b11 = (n v + 2 e_i + 2 e_{i+1} + d_i) / (n + 5)      (course eq. 10, corrected)
//   edge      b10 = average of the two interior points beside the edge (digest §1.5); on a
//             boundary edge the limit boundary curve's point P + t_i instead.
// Tangent patches (the course's u_ij, v_ij; corner and "tangent" vectors adjusted, the middle
// row taken from the geometry patch, §2.3.2). Along each edge, t from corner k to k+1:
//   T(t)  the along-edge derivative, quadratic: 3 t_i at corner k (limit tangent), 3 (b20 - b10)
//         from the geometry patch in the middle, the limit tangent at corner k+1;
//   L(t)  the cross derivative into the patch, cubic: the limit tangents of the other edges at
//         both corners; inside, the G1 condition L + R = lambda(t) T with lambda linear from
//         2 cos(2 pi / n_k) to -2 cos(2 pi / n_{k+1}) is split evenly between the two patches
//         and the difference L - R taken from the geometry patches:
//           L_1 = (lambda T)_1 / 2 + 3 (b11 - b11') / 2,  b11' the neighbour's interior point;
//         on a boundary edge L is the geometry patch's own cross derivative (corners excepted).
// So the normal field is continuous across every edge, equals the exact limit normal at every
// patch corner, and on regular quads both tangent patches are the bicubic B-spline's exact
// derivatives. The course notes (C §2.3.2) only describe this; the weights are checked
// against the public production implementations (Valve's Source engine, Microsoft's SubD11
// sample), which compute the same tangent patches (README.md, test_acc1.cpp).
// Corner vectors: the exact limit tangents scaled by Loop and Schaefer's mask (limit_frame.h).
//
// Non-quad cages are refined once first (refine_once.h); a quad's (u, v) then lands on one of
// its four children as documented there, an n-gon sub-face k is child k with the same (u, v).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "mesh/cage.h"
#include "mesh/result.h"
#include "plans/quad_patch_source.h"

namespace qp {

struct Acc1Settings {
    // Corner vectors of the tangent patches. LoopSchaefer (default): the exact limit tangents
    // with the length of Loop and Schaefer's tangent mask, as production ACC-1 computes them
    // (limit_frame.h); Exact: the same directions, our length; AccEdgeMode: the Fourier mode of
    // the geometry's edge points (as OpenSubdiv's Gregory end caps; not the limit normal).
    TangentRule tangents = TangentRule::LoopSchaefer;
};

struct Acc1Stats {
    uint32_t patches = 0, controlPoints = 0, refinementSteps = 0;
    uint32_t regularPatches = 0, boundaryPatches = 0;
    uint32_t ignoredCreases = 0, ignoredCorners = 0;
    double setupMilliseconds = 0.0;
};

struct Acc1Patches {
    static constexpr uint32_t kGeometryPoints = 16, kTangentPoints = 12;
    static constexpr uint32_t kControlPointsPerPatch = kGeometryPoints + 2 * kTangentPoints;  // 40
    // Per patch, 40 points: geometry b(i,j) at 4 j + i (i along u, j along v); then the d/du
    // patch, degree 2 in u and 3 in v, at 16 + 3 j + i (i = 0..2, j = 0..3); then the d/dv
    // patch, degree 3 in u and 2 in v, at 28 + 4 j + i (i = 0..3, j = 0..2). All Bernstein.
    std::vector<glm::vec3> controlPoints;
    QuadPatchSource source;
    Acc1Stats stats;
};

struct Acc1Sample {
    glm::vec3 position{0.0f};
    glm::vec3 du{0.0f}, dv{0.0f};  // the tangent patches (the shading frame), sub-face frame
    glm::vec3 normal{0.0f};        // normalize(du x dv)
    bool valid = false;
};

Result<Acc1Patches> buildAcc1(const Cage& cage, const Acc1Settings& settings = {}, const std::string& source = "cage");

// (u, v) in the frame of sub-face `subface` of the cage given to buildAcc1.
Acc1Sample evaluateAcc1(const Acc1Patches& patches, uint32_t subface, float u, float v);
// (s, t) in the frame of face patchFace[patch] of patches.source.quads.
Acc1Sample evaluateAcc1Patch(const Acc1Patches& patches, uint32_t patch, float s, float t);

const char* acc1Restrictions();

}  // namespace qp
