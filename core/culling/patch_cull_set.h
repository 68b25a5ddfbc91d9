// The culling bounds of a set of patches, and the per-view decision for each (issue 20). One
// entry per drawn primitive of a scheme: a plans sub-face (core/culling/subface_cull_bounds.h), a
// tessellated scheme's patch, a uniform face. An entry is built from leaves (PatchCullLeaves):
// Bézier patches (box, tcone, ncone, tangent planes), Gregory patches (box and a cone bounding
// their true normals) and coneless boxes (the position bound only: such an entry is tested
// against the frustum alone).
//
// Every test is conservative (core/culling/patch_culling.h): an entry is culled only when none of its
// leaves can show a front-facing pixel inside the frustum.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "culling/patch_culling.h"

namespace qp {

enum class CullMethod : uint32_t { None, Frustum, TCone, NCone, PPlane };
std::optional<CullMethod> parseCullMethod(std::string_view name);  // none, frustum, tcone, ncone, pplane
const char* cullMethodName(CullMethod method);

// The homogeneous eye of a view: (eye, 1) for a perspective view-projection, the direction
// towards the viewer (w = 0) along its rays for an orthographic one (its last row is (0, 0, 0, 1)),
// also under an object's non-uniform scale or shear.
glm::vec4 homogeneousEye(const glm::mat4& viewProjection, const glm::vec3& eyePoint);

// A cone holding every true normal (the blend weights' derivatives included) of a Gregory patch
// (20 points in patch_basis.h's order); unbounded when its tangents spread too far.
NormalCone gregoryNormalCone(const std::array<glm::vec3, 20>& points);

// A leaf pplane tests by its cone: a Gregory patch (it has no polynomial normal patch), or a
// small Bézier patch whose 81 tangent-plane coefficients would cost more than they cull
// (addSmallBezierLeaf).
struct ConeCullLeaf {
    NormalCone cone;
    CullBox box;  // in the set's coordinates (PatchCullLeaves: relative to the entry's origin)
};

// The leaves of one entry as they are gathered, relative to the entry's origin (the tangent
// planes' coefficients stay small next to the distances they are compared with). `detail`: the
// costliest method the entry will serve; cheaper details skip what only costlier methods read
// (Frustum: boxes only; TCone: and tcones; NCone: and ncones; PPlane: and tangent planes).
struct PatchCullLeaves {
    CullMethod detail = CullMethod::PPlane;
    CullBox box{glm::vec3(INFINITY), glm::vec3(-INFINITY)};
    std::vector<NormalCone> tcones, ncones;
    std::vector<TangentPlanes> planes;
    std::vector<ConeCullLeaf> coneLeaves;
    std::vector<glm::vec4> flats;  // flat triangles' planes (n, n . corner): g = n . E - (n . corner) w
    bool coneless = false;  // a leaf without a cone: no back-patch test for the entry
};
// A Bézier patch; `reversed`: its (u, v) frame is mirrored, so its normals flip.
void addBezierLeaf(PatchCullLeaves& leaves, const BicubicPoints& bezier, bool reversed);
// The same, with pplane testing it by its ncone instead of its tangent planes (1.3 KB a leaf):
// for the small leaves deep in a plan's quadtree, nearly flat, where the two tests differ little.
void addSmallBezierLeaf(PatchCullLeaves& leaves, const BicubicPoints& bezier, bool reversed);
// A Gregory patch (20 points in patch_basis.h's order; `reversed` as above).
void addGregoryLeaf(PatchCullLeaves& leaves, const std::array<glm::vec3, 20>& points, bool reversed);
// A part known only by a box holding it (its normals unbounded).
void addConelessBox(PatchCullLeaves& leaves, const CullBox& box);
// A cubic triangular Bézier patch (patch_culling.h): the box of its points (it lies in their
// hull) and cubicTriangleNormalCone as its tcone and ncone; it has no tangent planes, so pplane
// takes the cones' answer for it.
void addCubicTriangleLeaf(PatchCullLeaves& leaves, const CubicTrianglePoints& points);
// A flat triangle (corners counter-clockwise): its box, its normal as a cone and its plane, which
// pplane tests exactly (a flat piece faces away from the eye exactly when its plane does). A
// degenerate one (no normal) makes the entry coneless: rasterised, it may still cover a pixel.
void addFlatTriangle(PatchCullLeaves& leaves, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c);

// The 16 points of a bicubic B-spline patch with the phantoms beyond its boundary edges made
// explicit: 2 p1 - p2 across the edge (bits as patch_basis.h's boundary mask: 1 v=0, 2 u=1,
// 4 v=1, 8 u=0), a corner the phantom of phantoms.
BicubicPoints withPhantoms(BicubicPoints bspline, uint32_t boundaryMask);
// A B-spline patch (16 points, patch_basis.h's order) with a semi-sharp crease along the edge
// `creaseBit` (a boundary-mask bit; boundaryMask: its other boundary edges). The surface is the
// infinitely sharp one plus c d, c in [0, 1/2], d the second differences across the crease
// (patch_basis.h), so the box of the sharp patch grown by [0, 1/2] of d's box holds it; no cone.
void addSemiSharpCreaseLeaf(PatchCullLeaves& leaves, const BicubicPoints& bspline, uint32_t boundaryMask,
                            uint32_t creaseBit);

// Where an entry's leaves lie in one of the set's leaf arrays.
struct LeafRange {
    uint32_t first = 0, count = 0;
};

// The leaf arrays are shared by the entries, each naming its ranges, so that an edit replaces or
// renumbers a few entries without moving the others' leaves (hundreds of MB on a large cage):
// replaced leaves that no longer fit go to the end, and the arrays are compacted once more than
// half of what they hold is no longer named.
struct PatchCullSet {
    std::vector<CullBox> boxes;              // per entry (lo > hi: no surface, never tested)
    std::vector<NormalCone> tcones, ncones;  // per entry
    std::vector<glm::vec3> origins;          // per entry: what its tangent planes are relative to
    std::vector<LeafRange> planeRanges;      // per entry: its Bézier leaves' tangent planes
    std::vector<LeafRange> coneLeafRanges;   // per entry: its cone leaves
    std::vector<LeafRange> flatRanges;       // per entry: its flat triangles' planes (relative to its origin)
    std::vector<TangentPlanes> planes;
    std::vector<ConeCullLeaf> coneLeaves;
    std::vector<glm::vec4> flats;

    uint32_t size() const { return uint32_t(boxes.size()); }
    // The union of the entries' boxes (inverted when none has a surface).
    CullBox bounds() const;
};
// Appends an entry from its leaves (relative to `origin`), or one without a surface.
void appendPatch(PatchCullSet& set, const PatchCullLeaves& leaves, const glm::vec3& origin);
void appendAbsentPatch(PatchCullSet& set);
// Replaces entries `entries` (sorted, unique) by new leaves (parallel to them; an empty box makes
// an absent entry): in the room the entry had when they fit (a moved sub-face keeps its plan),
// else at the end of the leaf arrays.
void replacePatches(PatchCullSet& set, std::span<const uint32_t> entries, std::span<const PatchCullLeaves> leaves,
                    std::span<const glm::vec3> origins);

// Renumbers the entries (a topology edit): entry k becomes the entry previousOf[k] was, an absent
// one where previousOf[k] names none (UINT32_MAX), for the caller to replace. The leaves stay
// where they are.
void renumberPatches(PatchCullSet& set, std::span<const uint32_t> previousOf);

// pplane for an entry: every Bézier leaf back-facing by its tangent planes, every cone leaf
// by its cone and every flat triangle by its plane (false when it has no leaf tests).
bool tangentPlanesBackFacing(const PatchCullSet& set, uint32_t entry, const glm::vec4& eye);

// What one view's culling did.
struct CullCounts {
    uint64_t tested = 0;       // entries with a surface
    uint64_t frustum = 0;      // culled: outside the view frustum
    uint64_t backFacing = 0;   // culled: inside it, facing away (tcone, ncone or pplane)
    uint64_t frustumOnly = 0;  // a back-patch method was asked for but only the frustum could
                               // test the entry (coneless, displaced, or the view rules them out)
    CullCounts& operator+=(const CullCounts& other) {
        tested += other.tested, frustum += other.frustum, backFacing += other.backFacing, frustumOnly += other.frustumOnly;
        return *this;
    }
};

// The entries (sorted) `method` culls for a view: outside the frustum, or (tcone; ncone with
// tcone; pplane with both; only where `backPatch`, the eye is outside every entry's box and the
// near plane cuts none of them: a near plane through the surface shows its back side) facing
// away. `backPatch` says the surface is closed (every pipeline draws back sides, so a back-facing
// patch is hidden only by the surface in front of it). `margins` (per entry; empty: none) widen
// each box in every direction first (a displacement's largest |D|); with margins only the frustum
// test applies (the cones bound the undisplaced surface; a displacement can turn it inside out).
std::vector<uint32_t> cullPatches(const PatchCullSet& set, CullMethod method, const glm::mat4& viewProjection,
                                  const glm::vec4& eye, bool backPatch, std::span<const float> margins = {},
                                  CullCounts* counts = nullptr);

// Whether a closed surface inside `bounds` hides its own back side from this view: the eye is
// outside the box and the near plane clear of it (what cullPatches asks before its back-patch tests).
bool backSideHidden(const CullBox& bounds, const glm::mat4& viewProjection, const glm::vec4& eye);

}  // namespace qp
