// Conservative patch culling (core/patch_culling.h): no test may cull a patch that shows a
// front-facing point or lies partly inside the frustum, checked against dense sampling of random
// patches from random eyes; and the tests do cull, the tighter ones more.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "patch_basis.h"
#include "patch_culling.h"

using namespace qp;

namespace {

glm::vec3 bezierPoint(const BicubicPoints& p, float u, float v, glm::vec3* du = nullptr, glm::vec3* dv = nullptr) {
    auto bern = [](float t, float* b, float* d) {
        const float s = 1.0f - t;
        b[0] = s * s * s, b[1] = 3 * t * s * s, b[2] = 3 * t * t * s, b[3] = t * t * t;
        d[0] = -3 * s * s, d[1] = 3 * s * s - 6 * t * s, d[2] = 6 * t * s - 3 * t * t, d[3] = 3 * t * t;
    };
    float bu[4], du1[4], bv[4], dv1[4];
    bern(u, bu, du1);
    bern(v, bv, dv1);
    glm::vec3 out(0.0f), ou(0.0f), ov(0.0f);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            out += bu[c] * bv[r] * p[4 * r + c];
            ou += du1[c] * bv[r] * p[4 * r + c];
            ov += bu[c] * dv1[r] * p[4 * r + c];
        }
    if (du) *du = ou;
    if (dv) *dv = ov;
    return out;
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
