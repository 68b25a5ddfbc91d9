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
//                  orientation), and the Gregory patch at the bottom (as Extraordinary).
//   Extraordinary  Gregory: the box of its 20 points (the patch is a convex blend of them) and a
//                  cone bounding its true normals (subface_cull_bounds.cpp, addGregory); it has
//                  no polynomial normal patch, so its ncone is that cone and pplane tests the
//                  leaf with it.
// A sub-face with a semi-sharp crease leaf cannot be back-patch culled: its cones are unbounded
// and it has no leaf tests.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "patch_culling.h"
#include "planned_cage.h"

namespace qp {

// A cone holding every true normal (the blend weights' derivatives included) of a Gregory patch
// (20 points in patch_basis.h's order); unbounded when its tangents spread too far.
NormalCone gregoryNormalCone(const std::array<glm::vec3, 20>& points);

struct SubfaceCullBounds {
    std::vector<CullBox> boxes;             // per sub-face, world coordinates
    std::vector<NormalCone> tcones, ncones;  // per sub-face
    std::vector<glm::vec3> origins;         // per sub-face: what its tangent planes are relative to
    std::vector<uint32_t> planeOffsets;     // CSR: sub-face -> its Bézier leaves' tangent planes
    std::vector<TangentPlanes> planes;      // relative to the sub-face's origin
    struct GregoryLeaf {
        NormalCone cone;
        CullBox box;  // world coordinates
    };
    std::vector<uint32_t> gregoryOffsets;   // CSR: sub-face -> its Gregory leaves
    std::vector<GregoryLeaf> gregories;
};

// For every sub-face with a surface (the others get an empty box and unbounded cones).
SubfaceCullBounds buildSubfaceCullBounds(const PlannedCage& planned);

// pplane for a sub-face: every Bézier leaf back-facing by its tangent planes and every Gregory
// leaf by its cone (false when it has no leaf tests).
bool subfaceTangentPlanesBackFacing(const SubfaceCullBounds& bounds, uint32_t subface, const glm::vec4& eye);

enum class CullMethod : uint32_t { None, Frustum, TCone, NCone, PPlane };
std::optional<CullMethod> parseCullMethod(std::string_view name);  // none, frustum, tcone, ncone, pplane
const char* cullMethodName(CullMethod method);

// The homogeneous eye of a view: (eye, 1) for a perspective view-projection, the direction
// towards the viewer (w = 0) for an orthographic one (its last row is (0, 0, 0, 1)).
glm::vec4 homogeneousEye(const glm::mat4& viewProjection, const glm::vec3& eyePoint);

// Whether back-patch tests may cull for this cage: every pipeline draws back sides, so a
// back-facing patch is hidden only on a closed surface (every edge between two faces, no hole)
// seen from outside it (the eye outside the box of all sub-faces).
bool closedSurface(const PlannedCage& planned);

// The sub-faces (sorted) `method` culls for a view: outside the frustum, or (tcone; ncone with
// tcone; pplane with both; only where `backPatch`, the eye is outside every sub-face's box and the near plane
// cuts none of them: a near plane through the surface shows its back side) facing away.
// `margins` (per sub-face; empty: none) widen each box in every direction first (a
// displacement's largest |D|); with margins only the frustum test applies (back-patch tests
// cannot bound a displaced surface's normals).
std::vector<uint32_t> culledSubfaces(const PlannedCage& planned, const SubfaceCullBounds& bounds, CullMethod method,
                                     const glm::mat4& viewProjection, const glm::vec4& eye, bool backPatch,
                                     std::span<const float> margins = {});

}  // namespace qp
