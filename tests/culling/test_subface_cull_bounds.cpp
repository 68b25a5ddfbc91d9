// Culling bounds of planned sub-faces (core/culling/subface_cull_bounds.h) against the plans' own limit
// surface, densely sampled: boxes hold every point, cones every normal, and no back-patch test
// culls a sub-face with a point facing the eye.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include <glm/geometric.hpp>

#include "culling/subface_cull_bounds.h"
#include "mesh/generated_cage.h"
#include "plans/patch_basis.h"
#include "plans/planned_cage.h"
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
        const PatchCullSet bounds = buildSubfaceCullBounds(*planned);
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
                    for (const NormalCone* cone : {&bounds.tcones[s], &bounds.ncones[s]}) {
                        if (!cone->bounded) continue;
                        ASSERT_LE(angleBetween(n, cone->axis), cone->halfAngle) << c.name << " " << s;
                    }
                }
        }
        // Every sub-face has a cone but those with semi-sharp crease leaves (the benchmark cage
        // has semi-sharp creases).
        if (c.name != "benchmark cage") {
            EXPECT_EQ(withCones, planned->subfaceCount()) << c.name << ": every sub-face has a cone";
        }
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
        const PatchCullSet bounds = buildSubfaceCullBounds(*planned);
        const float diagonal = computeBounds(c.cage).diagonal();
        uint32_t away = 0, culled[3] = {};
        for (int view = 0; view < 12; ++view) {
            const glm::vec3 direction = glm::normalize(glm::vec3(unit(rng), unit(rng), unit(rng)));
            const glm::vec4 eye = view % 4 == 0 ? glm::vec4(direction, 0.0f) : glm::vec4(direction * diagonal * (1.0f + std::abs(unit(rng))), 1.0f);
            for (uint32_t s = 0; s < planned->subfaceCount(); ++s) {
                if (!planned->hasSurface(s)) continue;
                // Facing by the evaluator's normals and by the true surface's (differences of
                // positions: the evaluator drops the Gregory blend's derivative, as Far does).
                bool facing = false;
                for (uint32_t j = 0; j <= 12 && !facing; ++j)
                    for (uint32_t i = 0; i <= 12 && !facing; ++i) {
                        const float u = i / 12.0f, v = j / 12.0f, h = 1e-3f;
                        const LimitSample l = planned->evaluate(s, u, v);
                        const glm::vec3 toEye = glm::vec3(eye) - eye.w * l.position;
                        const float u0 = std::max(0.0f, u - h), u1 = std::min(1.0f, u + h);
                        const float v0 = std::max(0.0f, v - h), v1 = std::min(1.0f, v + h);
                        const glm::vec3 fu = planned->evaluate(s, u1, v).position - planned->evaluate(s, u0, v).position;
                        const glm::vec3 fv = planned->evaluate(s, u, v1).position - planned->evaluate(s, u, v0).position;
                        facing = glm::dot(glm::cross(l.du, l.dv), toEye) > 0.0f || glm::dot(glm::cross(fu, fv), toEye) > 0.0f;
                    }
                const bool t = backFacing(bounds.tcones[s], bounds.boxes[s], eye);
                const bool n = backFacing(bounds.ncones[s], bounds.boxes[s], eye);
                const bool p = tangentPlanesBackFacing(bounds, s, eye);
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
        // They do cull: on the regular torus most of what faces away, at the cube's valence-3
        // Gregory leaves (wider cones) less.
        if (c.name == "regular torus") {
            EXPECT_GT(culled[0], away / 2);
            EXPECT_EQ(culled[2], away);
        }
        if (c.name == "cube (valence 3)") {
            EXPECT_GT(culled[0], away / 10);
            EXPECT_GT(culled[2], away / 5);
        }
    }
}

// The Gregory cone holds the true normals (exact derivatives, the blend's included) of random
// Gregory patches: a bent bicubic net whose interior points split into Fp and Fm apart.
TEST(SubfaceCullBounds, GregoryConeHoldsTheTrueNormals) {
    std::mt19937 rng(23);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    const int corner[4][4][2] = {{{0, 0}, {1, 0}, {0, 1}, {1, 1}}, {{3, 0}, {3, 1}, {2, 0}, {2, 1}},
                                 {{3, 3}, {2, 3}, {3, 2}, {2, 2}}, {{0, 3}, {0, 2}, {1, 3}, {1, 2}}};
    uint32_t bounded = 0;
    for (int k = 0; k < 500; ++k) {
        const float bend = 0.8f * unit(rng), split = 0.15f * std::abs(unit(rng)), jitter = 0.1f * std::abs(unit(rng));
        auto net = [&](int i, int j) {
            const float x = float(i) / 3.0f, y = float(j) / 3.0f;
            return glm::vec3(x + jitter * unit(rng), y + jitter * unit(rng), bend * (x - 0.5f) * (y - 0.3f) + jitter * unit(rng));
        };
        std::array<glm::vec3, 20> g;
        for (int c = 0; c < 4; ++c) {
            for (int q = 0; q < 3; ++q) g[5 * c + q] = net(corner[c][q][0], corner[c][q][1]);
            const glm::vec3 f = net(corner[c][3][0], corner[c][3][1]);
            const glm::vec3 offset(split * unit(rng), split * unit(rng), split * unit(rng));
            g[5 * c + 3] = f + offset, g[5 * c + 4] = f - offset;
        }
        const NormalCone cone = gregoryNormalCone(g);
        if (!cone.bounded) continue;
        ++bounded;
        for (int j = 0; j <= 24; ++j)
            for (int i = 0; i <= 24; ++i) {
                BasisWeights w;
                gregoryWeights(i / 24.0f, j / 24.0f, w, true);
                glm::vec3 du(0.0f), dv(0.0f);
                for (int q = 0; q < 20; ++q) du += w.du[q] * g[q], dv += w.dv[q] * g[q];
                const glm::vec3 n = glm::cross(du, dv);
                if (glm::length(n) == 0.0f) continue;
                ASSERT_LE(angleBetween(n, cone.axis), cone.halfAngle) << "patch " << k << " at " << i << ", " << j;
            }
    }
    EXPECT_GT(bounded, 50u);  // the test exercises the cone (wide splits leave it unbounded)
}

// A sub-face that no back-patch test can cull (a Gregory leaf with an unbounded cone, or a
// semi-sharp crease leaf without a cone) keeps no tangent planes: its other leaves give their
// boxes only. The benchmark cage has both kinds; the boxes still hold the whole surface
// (BoxesAndConesHoldTheSampledSurface) and what can be culled keeps its planes.
TEST(SubfaceCullBounds, SubfacesNoTestCanCullKeepNoTangentPlanes) {
    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(makeBenchmarkCage(2000, 4), database, PlanOptions{}, "benchmark cage");
    ASSERT_TRUE(planned) << planned.error().message;
    const PatchCullSet bounds = buildSubfaceCullBounds(*planned);
    uint32_t untestable = 0, withPlanes = 0;
    for (uint32_t s = 0; s < bounds.size(); ++s) {
        const LeafRange cones = bounds.coneLeafRanges[s];
        const bool unboundedGregory = std::any_of(bounds.coneLeaves.begin() + cones.first, bounds.coneLeaves.begin() + cones.first + cones.count,
                                                  [](const ConeCullLeaf& leaf) { return !leaf.cone.bounded; });
        const uint32_t planes = bounds.planeRanges[s].count;
        const bool coneless = bounds.boxes[s].lo.x <= bounds.boxes[s].hi.x && !bounds.tcones[s].bounded && cones.count == 0 &&
                              planes == 0;
        if (unboundedGregory || coneless) {
            ++untestable;
            EXPECT_EQ(planes, 0u) << "sub-face " << s;
            EXPECT_FALSE(bounds.tcones[s].bounded || bounds.ncones[s].bounded) << "sub-face " << s;
        }
        withPlanes += planes > 0;
    }
    EXPECT_GT(untestable, 0u) << "the cage has sub-faces no test can cull";
    EXPECT_GT(withPlanes, bounds.size() / 2) << "the regular sub-faces keep theirs";
    RecordProperty("sub-faces", std::to_string(untestable) + " untestable, " + std::to_string(withPlanes) + " with planes of " +
                                    std::to_string(bounds.size()));
}

// The estimate a caller checks before asking for pplane's bounds holds what they take: exactly
// the planes kept when every sub-face can be culled (the regular torus), at least them otherwise.
TEST(SubfaceCullBounds, TangentPlaneBytesBoundWhatTheBoundsKeep) {
    for (const Case& c : cases()) {
        PlanDatabase database;
        Result<PlannedCage> planned = PlannedCage::create(c.cage, database, PlanOptions{}, c.name);
        ASSERT_TRUE(planned) << planned.error().message;
        const PatchCullSet bounds = buildSubfaceCullBounds(*planned);
        uint64_t kept = 0;
        for (const LeafRange& range : bounds.planeRanges) kept += uint64_t(range.count) * sizeof(TangentPlanes);
        const uint64_t estimate = tangentPlaneBytes(*planned);
        EXPECT_GE(estimate, kept) << c.name;
        if (c.name == "regular torus") {
            EXPECT_EQ(estimate, kept) << c.name;
            EXPECT_EQ(estimate, uint64_t(planned->subfaceCount()) * sizeof(TangentPlanes)) << "one leaf a sub-face";
        }
    }
}
