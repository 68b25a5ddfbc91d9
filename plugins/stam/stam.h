// Stam 1998, "Exact Evaluation of Catmull-Clark Subdivision Surfaces at Arbitrary Parameter
// Values" (S §3.5, L10 §4.2, C §1.7.3, digest §1.3): the exact limit surface, patch by patch,
// once every quad has at most one extraordinary corner.
//
// The cage is refined until extraordinary vertices are isolated (refine_once.h): not at all if
// it is already an all-quad cage with at most one extraordinary vertex per quad, once for other
// all-quad cages, twice otherwise. Then per quad of the refined cage:
//   - regular (four valence-4 corners): a bicubic B-spline patch, 16 points (patch_basis.h order);
//   - one extraordinary corner of valence n: the 2n+8 points of stam_eigen.h around it, and
//     their projection to eigenspace (V^-1 C), evaluated as stam_eigen.h describes.
// (u, v) of a sub-face of the original cage maps onto the refined quads as refine_once.h
// documents (a quad's four children per step; n-gon sub-face k = child k).
//
// Not supported: boundaries (Stam's construction is interior-only: buildStam fails with a
// message on a cage with boundary edges) and non-manifold cages (rejected). Creases and corner
// tags are honoured by the refinement steps, then ignored: the rest of the surface follows the
// smooth rules (the stats count the ignored tags), so tagged cages are not exact.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "mesh/cage.h"
#include "mesh/result.h"
#include "plans/quad_patch_source.h"

namespace qp {

struct StamStats {
    uint32_t patches = 0, regularPatches = 0, extraordinaryPatches = 0;
    uint32_t controlPoints = 0;  // 16 per regular patch, 2n+8 per extraordinary one
    uint32_t refinementSteps = 0, maxValence = 0;
    uint32_t ignoredCreases = 0, ignoredCorners = 0;
    double setupMilliseconds = 0.0;
};

struct StamPatches {
    // Per patch: its points start at pointOffset[patch]; valence[patch] is 4 for a regular
    // patch (16 B-spline points) or n for an extraordinary one (2n+8 points in stam_eigen.h's
    // order, whose extraordinary vertex is the patch's corner `rotation[patch]`).
    std::vector<glm::vec3> controlPoints;
    // Extraordinary patches only, at the same offsets: the points projected to eigenspace,
    // V^-1 C, in double (what the evaluation uses; float is kept for a GPU upload).
    std::vector<glm::dvec3> eigenCoefficients;
    std::vector<uint32_t> pointOffset, valence, rotation;
    QuadPatchSource source;
    StamStats stats;
};

struct StamSample {
    glm::dvec3 position{0.0}, du{0.0}, dv{0.0}, normal{0.0};  // sub-face frame
    bool valid = false;
};

Result<StamPatches> buildStam(const Cage& cage, const std::string& source = "cage");

// (u, v) in the frame of sub-face `subface` of the cage given to buildStam. At an extraordinary
// vertex itself the derivatives are those at a point 2^-40 away (their length tends to 0 or
// infinity there); the normal is the limit normal.
StamSample evaluateStam(const StamPatches& patches, uint32_t subface, double u, double v);
// (s, t) in the frame of face patchFace[patch] of patches.source.quads.
StamSample evaluateStamPatch(const StamPatches& patches, uint32_t patch, double s, double t);

const char* stamRestrictions();

}  // namespace qp
