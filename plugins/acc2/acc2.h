// ACC-2: Loop, Schaefer, Ni, Castano 2009, "Approximating Subdivision Surfaces with Gregory
// Patches for Hardware Tessellation" (S §3.6.3, L10 §4.4, digest §1.6). One bicubic Gregory
// patch of 20 control points per quad, G1 (tangent-plane continuous) everywhere, interpolating
// the Catmull-Clark limit position at every patch corner and a tangent plane close to the
// limit's (exactly the limit's with TangentRule::Exact).
//
// Construction (per quad, corner k with limit frame P_k, tangents t_j from limit_frame.h,
// c_k = cos(2 pi / n_k), the quad is face i of the ring of corner k, e_i its next corner):
//   P_k  = limit position                                         (corner point)
//   Ep_k = P_k + t_i,  Em_k = P_k + t_{i+1}                       (edge points, in the limit
//                                                                  tangent plane)
//   Fp_k = Ep_k + [2 c_k (Em_{k+1} - Ep_k) - c_{k+1} (Ep_k - P_k) + r_i] / 3
//   Fm_k = Em_k + [2 c_k (Ep_{k-1} - Em_k) - c_{k-1} (Em_k - P_k) - r_{i+1}] / 3
//   r_i  = (e_{i+1} - e_{i-1}) / 3 + (d_i - d_{i-1}) / 6
// Fp/Fm solve the G1 condition L + R = lambda(t) T across each edge, lambda linear from
// 2 c_k to -2 c_{k+1}, T the edge's derivative, L and R the two patches' cross derivatives,
// splitting the sum evenly and adding r (half the difference of the regular B-spline's
// interior points across the edge), so regular configurations reproduce the bicubic B-spline
// exactly. This is the construction OpenSubdiv implements for its Gregory-basis end caps
// (derived here from the G1 condition; see README.md), whose edge points use the Fourier mode
// of ACC-1's edge points (TangentRule::AccEdgeMode) rather than exact limit tangents.
// Interior point on a boundary edge (no neighbour, no G1 condition): the ACC-1 interior point
// (n v + 2 e_i + 2 e_{i+1} + d_i) / (n + 5) (exact for regular boundary patches).
// Evaluation: the rational interior blend and Bezier evaluation of core/plans/patch_basis.h
// (gregoryWeights); derivatives and normal as Acc2Settings::surfaceDerivatives says.
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

struct Acc2Settings {
    // AccEdgeMode (default): the published construction, as OpenSubdiv's Gregory-basis end caps
    // compute it (tests check that they agree). Exact: edge points in the exact limit tangent
    // plane instead (limit_frame.h), so patch corners carry the exact limit normal.
    TangentRule tangents = TangentRule::AccEdgeMode;
    // false (default): du, dv and the normal are those of the bicubic Bezier patch whose
    // interior points are the blended ones at (u, v), held fixed -- "once the blend has been
    // computed, the patch can be evaluated as a bicubic Bezier patch" (L10 §4.4), and what
    // OpenSubdiv's EvaluateBasis does. true: the derivatives of the rational surface itself.
    // Both agree on patch edges (so normals stay continuous across them) and at corners.
    bool surfaceDerivatives = false;
};

struct Acc2Stats {
    uint32_t patches = 0, controlPoints = 0, refinementSteps = 0;
    uint32_t regularPatches = 0;   // all four corners interior valence 4: exact B-spline
    uint32_t boundaryPatches = 0;  // a corner on the boundary
    uint32_t ignoredCreases = 0, ignoredCorners = 0;  // tags treated as smooth
    double setupMilliseconds = 0.0;
};

struct Acc2Patches {
    static constexpr uint32_t kControlPointsPerPatch = 20;
    // 20 per patch, OpenSubdiv's GREGORY_BASIS order: corner k = 0..3 at (0,0), (1,0), (1,1),
    // (0,1) owns P, Ep, Em, Fp, Fm at 5k .. 5k+4 (see gregoryWeights in core/plans/patch_basis.h).
    std::vector<glm::vec3> controlPoints;
    QuadPatchSource source;  // the quad cage, sub-face map and patch <-> face tables
    Acc2Settings settings;
    Acc2Stats stats;
};

struct Acc2Sample {
    glm::vec3 position{0.0f}, du{0.0f}, dv{0.0f}, normal{0.0f};  // du, dv in the sub-face frame
    bool valid = false;  // false where the sub-face has no surface (hole, boundary rule "none")
};

Result<Acc2Patches> buildAcc2(const Cage& cage, const Acc2Settings& settings = {}, const std::string& source = "cage");

// (u, v) in the frame of sub-face `subface` of the cage given to buildAcc2.
Acc2Sample evaluateAcc2(const Acc2Patches& patches, uint32_t subface, float u, float v);

// (s, t) in the frame of face patchFace[patch] of patches.source.quads.
Acc2Sample evaluateAcc2Patch(const Acc2Patches& patches, uint32_t patch, float s, float t);

// What the scheme cannot represent, in words for the user.
const char* acc2Restrictions();

}  // namespace qp
