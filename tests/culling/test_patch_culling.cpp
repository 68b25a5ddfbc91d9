// Conservative patch culling (core/culling/patch_culling.h): no test may cull a patch that shows a
// front-facing point or lies partly inside the frustum, checked against dense sampling of random
// patches from random eyes; and the tests do cull, the tighter ones more.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "bezier_test_support.h"
#include "culling/patch_cull_set.h"
#include "culling/patch_culling.h"
#include "plans/patch_basis.h"

using namespace qp;

namespace {

glm::vec3 bezierPoint(const BicubicPoints& p, float u, float v, glm::vec3* du = nullptr, glm::vec3* dv = nullptr) {
    return test::bicubicBezierAt(p, u, v, du, dv);
}

// A patch over [0, 1]^2 bent by a random quadratic height and jittered control points: from flat
// to strongly curved (normals spreading up to about 80 degrees), placed and turned at random.
BicubicPoints randomPatch(std::mt19937& rng) {
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    const float bend = 1.5f * std::abs(unit(rng)), twist = unit(rng), jitter = 0.15f * std::abs(unit(rng));
    const glm::mat4 turn = glm::rotate(glm::mat4(1.0f), 3.14159f * unit(rng), glm::normalize(glm::vec3(unit(rng), unit(rng), unit(rng)) + 0.01f));
    const glm::vec3 shift(3.0f * unit(rng), 3.0f * unit(rng), 3.0f * unit(rng));
    BicubicPoints p;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            const float x = float(c) / 3.0f - 0.5f, y = float(r) / 3.0f - 0.5f;
            const glm::vec3 local(x + jitter * unit(rng), y + jitter * unit(rng), bend * x * x + twist * x * y + jitter * unit(rng));
            p[4 * r + c] = glm::vec3(turn * glm::vec4(local, 1.0f)) + shift;
        }
    return p;
}

// Whether a sampled point of the patch faces the eye (homogeneous).
bool anyFrontFacing(const BicubicPoints& p, const glm::vec4& eye) {
    constexpr int kSteps = 40;
    for (int j = 0; j <= kSteps; ++j)
        for (int i = 0; i <= kSteps; ++i) {
            glm::vec3 du, dv;
            const glm::vec3 at = bezierPoint(p, float(i) / kSteps, float(j) / kSteps, &du, &dv);
            const glm::vec3 n = glm::cross(du, dv);
            const glm::vec3 toEye = glm::vec3(eye) - eye.w * at;
            if (glm::dot(n, toEye) > 0.0f) return true;
        }
    return false;
}

float widestNormalFrom(const BicubicPoints& p, const glm::vec3& axis) {
    float widest = 0.0f;
    for (int j = 0; j <= 30; ++j)
        for (int i = 0; i <= 30; ++i) {
            glm::vec3 du, dv;
            bezierPoint(p, float(i) / 30.0f, float(j) / 30.0f, &du, &dv);
            const glm::vec3 n = glm::cross(du, dv);
            if (glm::length(n) == 0.0f) continue;
            widest = std::max(widest, std::atan2(glm::length(glm::cross(n, axis)), glm::dot(n, axis)));
        }
    return widest;
}

// A cubic Bézier triangle as PN-triangles make them (CubicTrianglePoints' order): a random
// triangle whose edge and centre points bulge along its normal by random amounts and are
// jittered, from nearly flat to strongly curved, placed and turned at random.
CubicTrianglePoints randomTriangle(std::mt19937& rng) {
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    const glm::vec3 corners[3] = {{0, 0, 0}, {1.0f + 0.3f * unit(rng), 0.2f * unit(rng), 0}, {0.3f * unit(rng), 1.0f + 0.3f * unit(rng), 0}};
    const float bulge = 0.6f * unit(rng), jitter = 0.1f * std::abs(unit(rng));
    const glm::mat4 turn = glm::rotate(glm::mat4(1.0f), 3.14159f * unit(rng), glm::normalize(glm::vec3(unit(rng), unit(rng), unit(rng)) + 0.01f));
    const glm::vec3 shift(3.0f * unit(rng), 3.0f * unit(rng), 3.0f * unit(rng));
    // b_ijk in CubicTrianglePoints' order.
    const int ijk[10][3] = {{3, 0, 0}, {0, 3, 0}, {0, 0, 3}, {2, 1, 0}, {1, 2, 0}, {0, 2, 1}, {0, 1, 2}, {1, 0, 2}, {2, 0, 1}, {1, 1, 1}};
    CubicTrianglePoints p;
    for (int n = 0; n < 10; ++n) {
        const glm::vec3 b = glm::vec3(ijk[n][0], ijk[n][1], ijk[n][2]) / 3.0f;
        glm::vec3 local = b.x * corners[0] + b.y * corners[1] + b.z * corners[2];
        const bool corner = ijk[n][0] == 3 || ijk[n][1] == 3 || ijk[n][2] == 3;
        if (!corner) local += glm::vec3(jitter * unit(rng), jitter * unit(rng), bulge * (1.0f + 0.5f * unit(rng)));
        p[size_t(n)] = glm::vec3(turn * glm::vec4(local, 1.0f)) + shift;
    }
    return p;
}

// The point at barycentrics (x, y, z) and the normal B_y x B_z (derivatives towards corners 2 and 3).
glm::vec3 trianglePoint(const CubicTrianglePoints& c, float x, float y, float z, glm::vec3* normal) {
    const glm::vec3 position = x * x * x * c[0] + y * y * y * c[1] + z * z * z * c[2] + 3 * x * x * y * c[3] + 3 * x * y * y * c[4] +
                               3 * y * y * z * c[5] + 3 * y * z * z * c[6] + 3 * x * z * z * c[7] + 3 * x * x * z * c[8] +
                               6 * x * y * z * c[9];
    const glm::vec3 dx = 3 * x * x * c[0] + 6 * x * y * c[3] + 3 * y * y * c[4] + 3 * z * z * c[7] + 6 * x * z * c[8] + 6 * y * z * c[9];
    const glm::vec3 dy = 3 * y * y * c[1] + 3 * x * x * c[3] + 6 * x * y * c[4] + 6 * y * z * c[5] + 3 * z * z * c[6] + 6 * x * z * c[9];
    const glm::vec3 dz = 3 * z * z * c[2] + 3 * y * y * c[5] + 6 * y * z * c[6] + 6 * x * z * c[7] + 3 * x * x * c[8] + 6 * x * y * c[9];
    *normal = glm::cross(dy - dx, dz - dx);
    return position;
}

}  // namespace

TEST(PatchCulling, BsplineToBezierIsTheSameSurface) {
    std::mt19937 rng(3);
    for (int k = 0; k < 20; ++k) {
        const BicubicPoints spline = randomPatch(rng);
        const BicubicPoints bezier = bsplineToBezier(spline);
        for (float u : {0.0f, 0.3f, 0.77f, 1.0f})
            for (float v : {0.0f, 0.5f, 1.0f}) {
                BasisWeights w;
                bsplineWeights(u, v, w);
                glm::vec3 expected(0.0f);
                for (int i = 0; i < 16; ++i) expected += w.w[i] * spline[i];
                const glm::vec3 got = bezierPoint(bezier, u, v);
                EXPECT_LT(glm::length(got - expected), 1e-5f * (1.0f + glm::length(expected)));
            }
    }
}

TEST(PatchCulling, ConesHoldEveryNormalOfThePatch) {
    std::mt19937 rng(7);
    uint32_t boundedT = 0, boundedN = 0, tighter = 0;
    for (int k = 0; k < 400; ++k) {
        const BicubicPoints p = randomPatch(rng);
        const NormalCone t = tangentCone(p), n = normalPatchCone(p);
        if (t.bounded) {
            ++boundedT;
            ASSERT_LE(widestNormalFrom(p, t.axis), t.halfAngle) << "tcone, patch " << k;
        }
        if (n.bounded) {
            ++boundedN;
            ASSERT_LE(widestNormalFrom(p, n.axis), n.halfAngle) << "ncone, patch " << k;
        }
        if (t.bounded && n.bounded) tighter += n.halfAngle <= t.halfAngle;
    }
    EXPECT_GT(boundedT, 100u);
    EXPECT_GT(boundedN, 100u);
    RecordProperty("bounded_tcone_ncone", std::to_string(boundedT) + " " + std::to_string(boundedN));
    RecordProperty("ncone_at_most_tcone", std::to_string(tighter));
}

// The conservative promise, from perspective and orthographic eyes: a patch with any
// front-facing point is never culled by tcone, ncone or pplane. And they do cull: of the patches
// that face away entirely, each culls a share, tcone <= ncone <= pplane.
TEST(PatchCulling, BackPatchTestsNeverCullAFrontFacingPatch) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    uint32_t backFacingPatches = 0, culled[3] = {};
    for (int k = 0; k < 3000; ++k) {
        const BicubicPoints p = randomPatch(rng);
        const glm::vec3 direction = glm::normalize(glm::vec3(unit(rng), unit(rng), unit(rng)));
        const glm::vec4 eye = k % 5 == 0 ? glm::vec4(direction, 0.0f) : glm::vec4(direction * (2.0f + 8.0f * std::abs(unit(rng))), 1.0f);
        const CullBox box = boxOf(p);
        const bool t = backFacing(tangentCone(p), box, eye), n = backFacing(normalPatchCone(p), box, eye);
        const bool pp = tangentPlaneBackFacing(p, eye);
        if (anyFrontFacing(p, eye)) {
            ASSERT_FALSE(t) << "tcone culled a front-facing patch " << k;
            ASSERT_FALSE(n) << "ncone culled a front-facing patch " << k;
            ASSERT_FALSE(pp) << "pplane culled a front-facing patch " << k;
            continue;
        }
        ++backFacingPatches;
        culled[0] += t, culled[1] += n, culled[2] += pp;
    }
    ASSERT_GT(backFacingPatches, 300u);
    EXPECT_GT(culled[0], backFacingPatches / 10);
    EXPECT_LE(culled[0], culled[1]);
    EXPECT_LE(culled[1], culled[2]);
    RecordProperty("back_facing", std::to_string(backFacingPatches));
    RecordProperty("culled_tcone_ncone_pplane",
                   std::to_string(culled[0]) + " " + std::to_string(culled[1]) + " " + std::to_string(culled[2]));
}

TEST(PatchCulling, FrustumCullsOnlyBoxesWhollyOutside) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    const glm::mat4 view = glm::lookAt(glm::vec3(0, 0, 8), glm::vec3(0), glm::vec3(0, 1, 0));
    const glm::mat4 projection = glm::perspective(glm::radians(40.0f), 1.5f, 0.5f, 30.0f);
    const CullFrustum frustum = frustumOf(projection * view);
    uint32_t outside = 0;
    for (int k = 0; k < 2000; ++k) {
        BicubicPoints p = randomPatch(rng);
        for (glm::vec3& q : p) q = 2.5f * q;  // some wholly off screen, some across its border
        const bool culled = outsideFrustum(frustum, boxOf(p));
        bool anyInside = false;
        for (int j = 0; j <= 20 && !anyInside; ++j)
            for (int i = 0; i <= 20 && !anyInside; ++i) {
                const glm::vec4 clip = projection * view * glm::vec4(bezierPoint(p, i / 20.0f, j / 20.0f), 1.0f);
                anyInside = std::abs(clip.x) <= clip.w && std::abs(clip.y) <= clip.w && clip.z >= 0.0f && clip.z <= clip.w;
            }
        if (anyInside) {
            ASSERT_FALSE(culled) << k;
        }
        outside += culled;
    }
    EXPECT_GT(outside, 200u);
}

// PN triangles (pn's culling): the cone of cubicTriangleNormalCone holds every normal of densely
// sampled random cubic triangles, and with it no triangle that shows a front-facing sample is
// culled from perspective or orthographic eyes.
TEST(PatchCulling, CubicTriangleConeHoldsEveryNormal) {
    std::mt19937 rng(13);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    constexpr int kSteps = 40;
    uint32_t bounded = 0, backFacingTriangles = 0, culled = 0;
    for (int t = 0; t < 1500; ++t) {
        const CubicTrianglePoints p = randomTriangle(rng);
        const NormalCone cone = cubicTriangleNormalCone(p);
        bounded += cone.bounded;
        const glm::vec3 direction = glm::normalize(glm::vec3(unit(rng), unit(rng), unit(rng)));
        const glm::vec4 eye = t % 5 == 0 ? glm::vec4(direction, 0.0f) : glm::vec4(direction * (2.0f + 8.0f * std::abs(unit(rng))), 1.0f);
        bool front = false;
        for (int j = 0; j <= kSteps; ++j)
            for (int i = 0; i + j <= kSteps; ++i) {
                const float y = float(i) / kSteps, z = float(j) / kSteps;
                glm::vec3 normal;
                const glm::vec3 at = trianglePoint(p, 1.0f - y - z, y, z, &normal);
                if (cone.bounded && glm::length(normal) > 0.0f) {
                    ASSERT_LE(std::atan2(glm::length(glm::cross(normal, cone.axis)), glm::dot(normal, cone.axis)), cone.halfAngle)
                        << "triangle " << t;
                }
                front |= glm::dot(normal, glm::vec3(eye) - eye.w * at) > 0.0f;
            }
        const bool away = backFacing(cone, boxOf(p), eye);
        if (front) {
            ASSERT_FALSE(away) << "culled a front-facing triangle " << t;
            continue;
        }
        ++backFacingTriangles;
        culled += away;
    }
    EXPECT_GT(bounded, 500u);
    EXPECT_GT(culled, backFacingTriangles / 10);
    RecordProperty("bounded", std::to_string(bounded));
    RecordProperty("back_facing_culled", std::to_string(backFacingTriangles) + " " + std::to_string(culled));
}

// uniform's leaves: a flat triangle's plane decides exactly (up to float rounding) whether it
// faces away, relative to an entry's origin.
TEST(PatchCulling, FlatTrianglePlanesDecideExactly) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    uint32_t away = 0;
    for (int t = 0; t < 2000; ++t) {
        const glm::vec3 origin(10.0f * unit(rng), 10.0f * unit(rng), 10.0f * unit(rng));
        const glm::vec3 a(unit(rng), unit(rng), unit(rng)), b(unit(rng), unit(rng), unit(rng)), c(unit(rng), unit(rng), unit(rng));
        PatchCullLeaves leaves;
        addFlatTriangle(leaves, a, b, c);
        PatchCullSet set;
        appendPatch(set, leaves, origin);
        const glm::vec3 direction = glm::normalize(glm::vec3(unit(rng), unit(rng), unit(rng)));
        const glm::vec4 eye = t % 4 == 0 ? glm::vec4(direction, 0.0f) : glm::vec4(origin + 5.0f * direction, 1.0f);
        const glm::dvec3 normal = glm::cross(glm::dvec3(b - a), glm::dvec3(c - a));
        const double facing = glm::dot(normal, glm::dvec3(glm::vec3(eye)) - double(eye.w) * (glm::dvec3(origin) + glm::dvec3(a)));
        const bool culled = tangentPlanesBackFacing(set, 0, eye);
        if (facing >= 0.0) {
            ASSERT_FALSE(culled) << t;
        } else if (facing < -1e-3 * glm::length(normal)) {
            EXPECT_TRUE(culled) << t;  // clearly away: the exact test culls it
        }
        away += culled;
    }
    EXPECT_GT(away, 700u);
}

// Sederberg and Meyers' rule for any angle between the tangent cones' axes: u x v for u, v on
// the cones' rims (where the normals spread most) stays within the cone, acute or obtuse (an
// obtuse frame once got a cone too narrow: the signed cosine in the bound).
TEST(PatchCulling, NormalConeOfTangentsHoldsAcuteAndObtuseFrames) {
    std::mt19937 rng(19);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    auto rim = [](const glm::vec3& axis, float angle, float turn) {
        const glm::vec3 p = glm::normalize(glm::cross(axis, glm::vec3(0.3f, 0.5f, 0.8f))), q = glm::cross(axis, p);
        return std::cos(angle) * axis + std::sin(angle) * (std::cos(turn) * p + std::sin(turn) * q);
    };
    uint32_t obtuse = 0;
    for (int k = 0; k < 400; ++k) {
        const float t = 0.3f + 2.5f * unit(rng);
        const NormalCone u{glm::vec3(1, 0, 0), 0.5f * unit(rng), true};
        const NormalCone v{glm::vec3(std::cos(t), std::sin(t), 0.0f), 0.5f * unit(rng), true};
        const NormalCone n = normalConeOfTangents(u, v);
        if (!n.bounded) continue;
        obtuse += t > 0.5f * 3.14159f;
        for (int i = 0; i < 32; ++i)
            for (int j = 0; j < 32; ++j) {
                const glm::vec3 normal = glm::cross(rim(u.axis, u.halfAngle, 0.19635f * float(i)), rim(v.axis, v.halfAngle, 0.19635f * float(j)));
                ASSERT_LE(std::atan2(glm::length(glm::cross(normal, n.axis)), glm::dot(normal, n.axis)), n.halfAngle)
                    << "axes " << t << " apart, half-angles " << u.halfAngle << ", " << v.halfAngle;
            }
    }
    EXPECT_GT(obtuse, 50u);
}

// The homogeneous eye of an orthographic view runs along its rays in the object's coordinates, also
// when the object is stretched and mirrored (the depth gradient does not then); a perspective view's
// is the eye point given.
TEST(PatchCulling, HomogeneousEyeFollowsTheRaysUnderAnyObjectTransform) {
    const glm::mat4 view = glm::lookAt(glm::vec3(3, 2, 5), glm::vec3(0), glm::vec3(0, 1, 0));
    const glm::mat4 ortho = glm::orthoRH_ZO(-2.0f, 2.0f, -2.0f, 2.0f, 0.1f, 20.0f);
    const glm::mat4 object = glm::scale(glm::rotate(glm::mat4(1.0f), 0.7f, glm::vec3(0, 0, 1)), glm::vec3(3.0f, -0.5f, 1.0f));
    const glm::vec4 eye = homogeneousEye(ortho * view * object, glm::vec3(0));
    EXPECT_EQ(eye.w, 0.0f);
    // Toward the viewer in the world, brought into the object's coordinates.
    const glm::vec3 expected = glm::normalize(glm::vec3(glm::inverse(object) * glm::vec4(glm::normalize(glm::vec3(3, 2, 5)), 0.0f)));
    EXPECT_NEAR(glm::dot(glm::vec3(eye), expected), 1.0f, 1e-5f);
    const glm::mat4 perspective = glm::perspectiveRH_ZO(0.8f, 1.0f, 0.1f, 20.0f);
    EXPECT_EQ(homogeneousEye(perspective * view * object, glm::vec3(1, 2, 3)), glm::vec4(1, 2, 3, 1));
}
