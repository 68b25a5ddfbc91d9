// Culling bounds of a planned cage's sub-faces (issue 20; core/patch_culling.h has the tests):
// per sub-face the box of its limit surface, its tcone and ncone, and the tangent-plane
// coefficients of its leaves for pplane, from the plan's leaves and control points.
//
// Leaves, in the plan's frame (a rotation of the sub-face's: orientation is kept):
//   Regular        the bicubic B-spline with the phantoms beyond boundary edges made explicit,
//                  as its Bézier patch: box, both cones, tangent planes.
//   Crease         infinitely sharp (sharpness >= 10): as Regular with the phantom beyond the
//                  crease. Semi-sharp: the surface is the infinitely sharp one plus c(v) d(u),
//                  0 <= c <= 1/2, d the second differences across the crease (patch_basis.h):
//                  the box grows by [0, 1/2] of d's box; no cone.
//   Terminal       per level its three regular windows (as Regular, mirrored windows with their
//                  orientation), and the Gregory patch at the bottom: box only.
//   Extraordinary  Gregory: the box of its 20 points (the patch is a convex blend of them); no
//                  cone (its normal bound needs a proof of its own, docs/culling-plan.md).
// A sub-face with a leaf that has no cone cannot be back-patch culled: its cones are unbounded
// and `tangentPlanes` is empty for it.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "patch_culling.h"
#include "planned_cage.h"

namespace qp {

struct SubfaceCullBounds {
    std::vector<CullBox> boxes;             // per sub-face, world coordinates
    std::vector<NormalCone> tcones, ncones;  // per sub-face
    std::vector<glm::vec3> origins;         // per sub-face: what its tangent planes are relative to
    std::vector<uint32_t> planeOffsets;     // CSR: sub-face -> its leaves' tangent planes
    std::vector<TangentPlanes> planes;      // relative to the sub-face's origin
};

// For every sub-face with a surface (the others get an empty box and unbounded cones).
SubfaceCullBounds buildSubfaceCullBounds(const PlannedCage& planned);

// pplane for a sub-face: every leaf back-facing (false when it has none bounded).
bool subfaceTangentPlanesBackFacing(const SubfaceCullBounds& bounds, uint32_t subface, const glm::vec4& eye);

}  // namespace qp
