// Culling bounds of planned sub-faces (core/subface_cull_bounds.h) against the plans' own limit
// surface, densely sampled: boxes hold every point, cones every normal, and no back-patch test
// culls a sub-face with a point facing the eye.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <glm/geometric.hpp>

#include "generated_cage.h"
#include "planned_cage.h"
#include "subface_cull_bounds.h"
#include "test_cages.h"

using namespace qp;

namespace {

// A closed all-regular cage: a torus of n x m quads (every vertex of valence 4).
Cage makeRegularTorus(uint32_t n, uint32_t m) {
    Cage cage;
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = 0; j < m; ++j) {
            const float a = 6.2831853f * float(i) / float(n), b = 6.2831853f * float(j) / float(m);
            cage.positions.push_back({(2.0f + 0.8f * std::cos(b)) * std::cos(a), (2.0f + 0.8f * std::cos(b)) * std::sin(a),
                                      0.8f * std::sin(b)});
            const uint32_t i1 = (i + 1) % n, j1 = (j + 1) % m;
            const uint32_t face[4] = {i * m + j, i1 * m + j, i1 * m + j1, i * m + j1};
            cage.addFace(face, 4);
        }
    return cage;
}

struct Case {
    std::string name;
    Cage cage;
};
std::vector<Case> cases() {
    Cage creased = makeRegularTorus(8, 6);
    creased.setEdgeSharpness(0, 6, 1.5f);    // semi-sharp
    creased.setEdgeSharpness(6, 12, 10.0f);  // infinitely sharp
    return {{"regular torus", makeRegularTorus(12, 8)}, {"creased torus", std::move(creased)},
            {"cube (valence 3)", test::makeSubdividedCube(2)}, {"grid (boundary)", test::makeGrid(4)},
            {"benchmark cage", makeBenchmarkCage(200, 4)}};
}

float angleBetween(const glm::vec3& a, const glm::vec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

}  // namespace

TEST(SubfaceCullBounds, BoxesAndConesHoldTheSampledSurface) {
    for (const Case& c : cases()) {
        PlanDatabase database;
        Result<PlannedCage> planned = PlannedCage::create(c.cage, database, PlanOptions{}, c.name);
        ASSERT_TRUE(planned) << planned.error().message;
        const SubfaceCullBounds bounds = buildSubfaceCullBounds(*planned);
        uint32_t withCones = 0;
        const float tolerance = 1e-5f * computeBounds(c.cage).diagonal();
        for (uint32_t s = 0; s < planned->subfaceCount(); ++s) {
            if (!planned->hasSurface(s)) continue;
            const CullBox& box = bounds.boxes[s];
            withCones += bounds.ncones[s].bounded;
            for (uint32_t j = 0; j <= 16; ++j)
                for (uint32_t i = 0; i <= 16; ++i) {
                    const LimitSample l = planned->evaluate(s, i / 16.0f, j / 16.0f);
                    ASSERT_TRUE(glm::all(glm::greaterThanEqual(l.position, box.lo - tolerance)) &&
                                glm::all(glm::lessThanEqual(l.position, box.hi + tolerance)))
                        << c.name << " sub-face " << s;
                    const glm::vec3 n = glm::cross(l.du, l.dv);
                    if (glm::length(n) == 0.0f) continue;
                    if (bounds.tcones[s].bounded) ASSERT_LE(angleBetween(n, bounds.tcones[s].axis), bounds.tcones[s].halfAngle) << c.name << " " << s;
                    if (bounds.ncones[s].bounded) ASSERT_LE(angleBetween(n, bounds.ncones[s].axis), bounds.ncones[s].halfAngle) << c.name << " " << s;
                }
        }
        if (c.name == "regular torus") EXPECT_EQ(withCones, planned->subfaceCount()) << "every regular sub-face has a cone";
        RecordProperty(c.name, std::to_string(withCones) + " of " + std::to_string(planned->subfaceCount()) + " with cones");
    }
}

// From random eyes outside the cage's box: a sub-face with any sampled point facing the eye is
// never culled by tcone, ncone or pplane; on the closed regular torus each culls a share of the
// rest.
TEST(SubfaceCullBounds, BackPatchTestsNeverCullASubfaceFacingTheEye) {
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    for (const Case& c : cases()) {
        PlanDatabase database;
        Result<PlannedCage> planned = PlannedCage::create(c.cage, database, PlanOptions{}, c.name);
        ASSERT_TRUE(planned) << planned.error().message;
        const SubfaceCullBounds bounds = buildSubfaceCullBounds(*planned);
        const float diagonal = computeBounds(c.cage).diagonal();
        uint32_t away = 0, culled[3] = {};
        for (int view = 0; view < 12; ++view) {
            const glm::vec3 direction = glm::normalize(glm::vec3(unit(rng), unit(rng), unit(rng)));
            const glm::vec4 eye = view % 4 == 0 ? glm::vec4(direction, 0.0f) : glm::vec4(direction * diagonal * (1.0f + std::abs(unit(rng))), 1.0f);
            for (uint32_t s = 0; s < planned->subfaceCount(); ++s) {
                if (!planned->hasSurface(s)) continue;
                bool facing = false;
                for (uint32_t j = 0; j <= 12 && !facing; ++j)
                    for (uint32_t i = 0; i <= 12 && !facing; ++i) {
                        const LimitSample l = planned->evaluate(s, i / 12.0f, j / 12.0f);
                        facing = glm::dot(glm::cross(l.du, l.dv), glm::vec3(eye) - eye.w * l.position) > 0.0f;
                    }
                const bool t = backFacing(bounds.tcones[s], bounds.boxes[s], eye);
                const bool n = backFacing(bounds.ncones[s], bounds.boxes[s], eye);
                const bool p = subfaceTangentPlanesBackFacing(bounds, s, eye);
                if (facing) {
                    ASSERT_FALSE(t || n || p) << c.name << " sub-face " << s << " view " << view << ": " << t << n << p;
                    continue;
                }
                ++away;
                culled[0] += t, culled[1] += n, culled[2] += p;
            }
        }
        RecordProperty(c.name, std::to_string(away) + " facing away; culled " + std::to_string(culled[0]) + " " +
                                   std::to_string(culled[1]) + " " + std::to_string(culled[2]));
        if (c.name == "regular torus") {
            EXPECT_GT(culled[0], away / 10);
            EXPECT_GT(culled[2], away / 2);
        }
    }
}
