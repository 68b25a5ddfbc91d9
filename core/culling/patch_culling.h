// Conservative culling of parametric patches (STAR §5, seed digest §4): view-frustum culling of
// position bounds and three back-patch tests on bicubic Bézier patches. Every test says "culled"
// only when no point of the patch can show a front-facing pixel, so a renderer may skip the
// patch; a "not culled" answer may be wrong the other way (a back-facing patch drawn for
// nothing), never this way.
//
//   frustum  the patch's bounding box (its control points' box: a Bézier or B-spline patch lies
//            in the convex hull of its control points) is outside one clipping plane;
//   tcone    Sederberg and Meyers' approximate cone of normals: a cone holding every u-tangent
//            (the differences of control points along u) and one holding every v-tangent give
//            a cone holding every normal; back-facing when the eye sees the whole box from
//            behind that cone (cheapest, culls least);
//   ncone    the cone holding the 36 control vectors of the normal patch B_u x B_v (bidegree
//            (5, 5)): every normal is a positive combination of them (tighter, costlier);
//   pplane   Loop et al.'s parametric tangent plane: g(u, v) = N(u, v) . (E - B(u, v)), whose
//            sign is the facing of the point (u, v) seen from the eye E, written in Bernstein
//            form of bidegree (8, 8); back-facing when all 81 coefficients are negative (culls
//            most).
// The eye is homogeneous: (E, 1) for a perspective view's eye point, (D, 0) for an orthographic
// view looking along -D (D points from the scene towards the viewer).
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace qp {

// 16 control points, row-major 4 x 4: index 4 * row + column, row along v, column along u.
using BicubicPoints = std::array<glm::vec3, 16>;

// The Bézier points of a uniform bicubic B-spline patch (the same surface over [0, 1]^2).
BicubicPoints bsplineToBezier(const BicubicPoints& bspline);

struct CullBox {
    glm::vec3 lo{0.0f}, hi{0.0f};
};
CullBox boxOf(std::span<const glm::vec3> points);

// Clipping planes of a view-projection matrix (Vulkan clip space: depth 0 .. 1), each a vec4
// (n, d) with n . p + d >= 0 inside: left, right, bottom, top, near, far.
struct CullFrustum {
    std::array<glm::vec4, 6> planes;
};
CullFrustum frustumOf(const glm::mat4& viewProjection);
// The box lies wholly outside one of the planes.
bool outsideFrustum(const CullFrustum& frustum, const CullBox& box);

// A cone of directions: every direction within `halfAngle` (radians) of the unit `axis`.
// `bounded` false: no cone under a hemisphere holds them all (nothing can be culled with it).
struct NormalCone {
    glm::vec3 axis{0.0f, 0.0f, 1.0f};
    float halfAngle = 0.0f;
    bool bounded = false;
};
// A cone holding every non-zero vector of `vectors` (zero vectors are ignored: a positive
// combination gains no direction from them).
NormalCone coneOfVectors(std::span<const glm::vec3> vectors);

// Sederberg and Meyers: the cone holding every u x v for u in `alongU` and v in `alongV`
// (unbounded when the tangent cones come too close to parallel).
NormalCone normalConeOfTangents(const NormalCone& alongU, const NormalCone& alongV);

// A cubic triangular Bézier patch (PN-triangles' geometry), 10 points in the order b300 b030
// b003 b210 b120 b021 b012 b102 b201 b111, b_ijk weighing corners 1, 2, 3 as 1^i 2^j 3^k.
using CubicTrianglePoints = std::array<glm::vec3, 10>;
// A cone holding every normal B_2 x B_3 of the patch (B_2, B_3: the derivatives towards corners
// 2 and 3; counter-clockwise corners give the usual orientation). Each derivative is 3 times a
// combination, with the non-negative quadratic Bernstein weights, of the six differences of
// neighbouring points in its direction (b_{i,j+1,k} - b_{i+1,j,k} for B_2), so it lies in their
// cone, and Sederberg and Meyers' rule (normalConeOfTangents) gives the normals' cone.
NormalCone cubicTriangleNormalCone(const CubicTrianglePoints& points);

// The back-patch tests on a Bézier patch (positions in the same space as the eye).
NormalCone tangentCone(const BicubicPoints& bezier);  // tcone
NormalCone normalPatchCone(const BicubicPoints& bezier);  // ncone
// Every point of `box`, with any normal in `cone`, faces away from `eye` (strictly).
bool backFacing(const NormalCone& cone, const CullBox& box, const glm::vec4& eye);
// pplane: the 81 Bernstein coefficients (a, b) of g = a . E - b w for a homogeneous eye (E, w)
// (bidegree (8, 8)); the patch faces away from the eye everywhere when every coefficient is
// negative, beyond the rounding of float coefficients.
using TangentPlanes = std::array<glm::vec4, 81>;
TangentPlanes tangentPlanesOf(const BicubicPoints& bezier);
// (Any number of coefficients: a flat piece's plane is the one coefficient of its g.)
bool tangentPlanesBackFacing(std::span<const glm::vec4> planes, const glm::vec4& eye);
inline bool tangentPlaneBackFacing(const BicubicPoints& bezier, const glm::vec4& eye) {
    return tangentPlanesBackFacing(tangentPlanesOf(bezier), eye);
}

}  // namespace qp
