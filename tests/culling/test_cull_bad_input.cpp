// Culling on bad input (issue 20): degenerate patches (all points together, a collapsed edge,
// NaN-free but huge coordinates) and an eye inside the model are never culled by a back-patch
// test while any of their points faces the eye; a degenerate patch is simply not culled.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "bezier_test_support.h"
#include "culling/patch_cull_set.h"
#include "culling/subface_cull_bounds.h"
#include "mesh/closed_surface.h"
#include "plans/planned_cage.h"
#include "test_cages.h"

using namespace qp;

namespace {

// Position and normal (du x dv) of a bicubic Bézier patch, in double (huge coordinates stay
// exact enough).
glm::dvec3 pointAt(const BicubicPoints& p, double u, double v, glm::dvec3* normal) {
    glm::dvec3 du, dv;
    const glm::dvec3 out = test::bicubicBezierAt(p, u, v, &du, &dv);
    *normal = glm::cross(du, dv);
    return out;
}

// Whether a sampled point with a normal faces the eye. On a collapsed edge the normal is zero (up
// to rounding, whose sign means nothing): samples whose normal is a millionth of the largest
// are skipped.
bool anyPointFacesTheEye(const BicubicPoints& p, const glm::dvec3& eye) {
    std::vector<std::pair<glm::dvec3, glm::dvec3>> samples;
    double largest = 0.0;
    for (int i = 0; i <= 24; ++i)
        for (int j = 0; j <= 24; ++j) {
            glm::dvec3 n;
            const glm::dvec3 q = pointAt(p, i / 24.0, j / 24.0, &n);
            samples.push_back({q, n});
            largest = std::max(largest, glm::length(n));
        }
    for (const auto& [q, n] : samples)
        if (glm::length(n) > 1e-6 * largest && glm::dot(glm::normalize(n), glm::normalize(eye - q)) > 0.0) return true;
    return false;
}

// One patch as a set, every method from `eye` with the back-patch tests allowed; a view that
// holds the patch (so the frustum never decides).
CullCounts cullOne(const BicubicPoints& bezier, const glm::vec3& eye, const glm::vec3& target, float far) {
    PatchCullLeaves leaves;
    addBezierLeaf(leaves, bezier, false);
    PatchCullSet set;
    appendPatch(set, leaves, glm::vec3(0.0f));
    const glm::mat4 view = glm::lookAt(eye, target, glm::vec3(0, 1, 0));
    const glm::mat4 projection = glm::perspective(glm::radians(170.0f), 1.0f, far * 1e-6f, far);
    CullCounts counts;
    (void)cullPatches(set, CullMethod::PPlane, projection * view, glm::vec4(eye, 1.0f), true, {}, &counts);
    return counts;
}

BicubicPoints bentPatch(float scale) {
    BicubicPoints p;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            const float x = float(c) / 3.0f - 0.5f, y = float(r) / 3.0f - 0.5f;
            p[4 * r + c] = scale * glm::vec3(x, y, 0.6f * x * x - 0.4f * y * y);
        }
    return p;
}

}  // namespace

TEST(CullBadInput, APatchCollapsedToAPointIsNotBackPatchCulled) {
    BicubicPoints point;
    point.fill(glm::vec3(1, 2, 3));
    for (const glm::vec3 eye : {glm::vec3(0, 0, 10), glm::vec3(0, 0, -10), glm::vec3(7, -3, 1)}) {
        const CullCounts counts = cullOne(point, eye, glm::vec3(1, 2, 3), 100.0f);
        EXPECT_EQ(counts.backFacing, 0u) << "a degenerate patch was culled as facing away";
    }
}

TEST(CullBadInput, CollapsedEdgesAndHugeCoordinatesNeverCullWhatFacesTheEye) {
    std::mt19937 rng(20);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    uint32_t facing = 0, culledAway = 0;
    for (float scale : {1.0f, 1e6f, 1e15f, 1e30f}) {
        for (int k = 0; k < 60; ++k) {
            BicubicPoints p = bentPatch(scale);
            if (k % 2) {  // one edge collapsed to its first point (a triangle-shaped patch)
                for (int c = 1; c < 4; ++c) p[12 + c] = p[12];
            }
            const glm::vec3 eye = scale * 4.0f * glm::normalize(glm::vec3(unit(rng), unit(rng), unit(rng)));
            const CullCounts counts = cullOne(p, eye, glm::vec3(0.0f), scale * 100.0f);
            const bool faces = anyPointFacesTheEye(p, glm::dvec3(eye));
            facing += faces;
            if (faces) EXPECT_EQ(counts.backFacing, 0u) << "scale " << scale << ", patch " << k << ": culled while facing the eye";
            else culledAway += uint32_t(counts.backFacing);
        }
    }
    EXPECT_GT(facing, 0u);
    EXPECT_GT(culledAway, 0u) << "the tests never cull, even where the patch faces away";
}

TEST(CullBadInput, AnEyeInsideTheModelCullsNothingFacingAway) {
    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(test::makeTorus(), database, PlanOptions{}, "torus");
    ASSERT_TRUE(planned.ok());
    ASSERT_TRUE(closedOutwardSurface(planned->cage(), planned->topology()));
    const PatchCullSet bounds = buildSubfaceCullBounds(*planned);
    // Inside the tube (major radius 2, minor 0.7), looking along it.
    const glm::vec3 eye(2.0f, 0.0f, 0.0f);
    const glm::mat4 viewProjection = glm::perspective(glm::radians(60.0f), 1.0f, 0.01f, 50.0f) *
                                     glm::lookAt(eye, glm::vec3(2.0f, 2.0f, 0.0f), glm::vec3(0, 0, 1));
    CullCounts counts;
    (void)cullPatches(bounds, CullMethod::PPlane, viewProjection, glm::vec4(eye, 1.0f), true, {}, &counts);
    EXPECT_EQ(counts.backFacing, 0u) << "from inside, every patch's inside faces the eye";
    EXPECT_GT(counts.frustumOnly, 0u);
    EXPECT_GT(counts.frustum, 0u) << "what is behind the eye is still outside the view";
}
