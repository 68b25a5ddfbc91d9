// Culling bounds of a planned cage's sub-faces (issue 20; core/culling/patch_cull_set.h decides per
// view): per sub-face the box of its limit surface, its tcone and ncone, and the tangent-plane
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
//                  orientation), and the Gregory patch at the bottom (as Extraordinary).
//   Extraordinary  Gregory: the box of its 20 points (the patch is a convex blend of them) and a
//                  cone bounding its true normals (patch_cull_set.h, gregoryNormalCone); it has
//                  no polynomial normal patch, so its ncone is that cone and pplane tests the
//                  leaf with it.
// A sub-face with a semi-sharp crease leaf cannot be back-patch culled: its cones are unbounded
// and it has no leaf tests. Nor can one whose Gregory leaf's cone is unbounded: its other leaves
// keep their boxes only (no cones, no tangent planes), which the tests would never read.
#pragma once

#include "culling/patch_cull_set.h"
#include "plans/planned_cage.h"

namespace qp {

// One entry per sub-face (those without a surface are absent entries), with what methods up to
// `detail` read (PatchCullLeaves::detail).
PatchCullSet buildSubfaceCullBounds(const PlannedCage& planned, CullMethod detail = CullMethod::PPlane);
// What the tangent planes of buildSubfaceCullBounds(planned, PPlane) take, at most (every sub-face
// counted as testable): 1.3 KB a Bézier leaf no deeper than depth 2 of its plan's quadtree. A
// caller compares it with the memory there is before asking for them.
uint64_t tangentPlaneBytes(const PlannedCage& planned);
// Rebuilds the entries of `subfaces` (sorted, unique) after their control points or plans changed.
void updateSubfaceCullBounds(PatchCullSet& set, const PlannedCage& planned, std::span<const uint32_t> subfaces,
                             CullMethod detail = CullMethod::PPlane);

}  // namespace qp
