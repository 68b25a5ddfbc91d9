// Picking the displaced limit surface (core/displacement/displaced_picker.h): hits on s + D N, the nearest
// one, at grazing angles on a tall bump, and updates after dabs equal to a rebuild.
#include <cmath>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <gtest/gtest.h>

#include "displacement/brush.h"
#include "displacement/displaced_picker.h"
#include "displacement/sculpt_samples.h"
#include "test_cages.h"

namespace {

using namespace qp;

// A flat 6 x 6 grid of unit quads in the xy-plane (diagonal 8.5): the bump's shape is all the
// displacement's, so what a ray should hit is easy to reason about.
Cage flatGrid() { return test::makeFlatGrid(6); }

constexpr glm::vec3 kCentre{3.0f, 3.0f, 0.0f};
constexpr float kBumpRadius = 1.5f;
constexpr float kBumpHeight = 2.0f;  // 24% of the diagonal

struct Scene {
    PlanDatabase database;
    std::optional<PlannedCage> planned;
    Displacement displacement;
    std::optional<SculptSamples> samples;

    explicit Scene(float height) {
        auto p = PlannedCage::create(flatGrid(), database, PlanOptions{}, "flat grid");
        EXPECT_TRUE(p) << p.error().message;
        planned.emplace(std::move(p).value());
        displacement = makeDisplacement(planned->cage(), planned->topology(), 16);
        samples.emplace(SculptSamples::build(*planned, displacement.layout));
        // A smooth bump (or dent, height < 0) set sample by sample: (1 - (r/R)^2)^2.
        for (uint32_t k = 0; k < samples->sampleCount(); ++k) {
            if (!samples->hasSite(k)) continue;
            const float r = glm::length(samples->position(k) - kCentre) / kBumpRadius;
            displacement.samples[k] = r < 1.0f ? height * (1.0f - r * r) * (1.0f - r * r) : 0.0f;
        }
    }
};

// The reference: every sub-face's displaced surface on a dense grid (6 points per sample
// interval, so the bilinear D's kinks are grid lines), every triangle tested.
class BruteForce {
public:
    BruteForce(const PlannedCage& planned, const Displacement& displacement, uint32_t n = 96) : n_(n) {
        for (uint32_t s = 0; s < planned.subfaceCount(); ++s) {
            std::vector<glm::vec3> grid;
            for (uint32_t j = 0; j <= n; ++j)
                for (uint32_t i = 0; i <= n; ++i)
                    grid.push_back(displacedSurfacePoint(planned, displacement, s, float(i) / float(n), float(j) / float(n)).position);
            grids_.push_back(std::move(grid));
        }
    }
    float distance(const Ray& ray) const {
        float best = kNoDistance;
        for (const std::vector<glm::vec3>& g : grids_)
            for (uint32_t j = 0; j < n_; ++j)
                for (uint32_t i = 0; i < n_; ++i) {
                    const glm::vec3 &p00 = g[j * (n_ + 1) + i], &p10 = g[j * (n_ + 1) + i + 1];
                    const glm::vec3 &p01 = g[(j + 1) * (n_ + 1) + i], &p11 = g[(j + 1) * (n_ + 1) + i + 1];
                    float t, b1, b2;
                    if (rayHitsTriangle(ray.origin, ray.direction, p00, p10, p11, t, b1, b2)) best = std::min(best, t);
                    if (rayHitsTriangle(ray.origin, ray.direction, p00, p11, p01, t, b1, b2)) best = std::min(best, t);
                }
        return best;
    }

private:
    uint32_t n_;
    std::vector<std::vector<glm::vec3>> grids_;
};

// A ray that reaches `target` at `degrees` above the plane with normal `normal`, coming from
// azimuth `azimuth` (radians, in that plane), from 20 units away.
Ray grazingRay(const glm::vec3& target, const glm::vec3& normal, float degrees, float azimuth) {
    const glm::vec3 t = glm::normalize(std::abs(normal.x) < 0.9f ? glm::cross(normal, glm::vec3(1, 0, 0))
                                                                 : glm::cross(normal, glm::vec3(0, 1, 0)));
    const glm::vec3 b = glm::cross(normal, t);
    const float a = glm::radians(degrees);
    const glm::vec3 along = std::cos(azimuth) * t + std::sin(azimuth) * b;
    const glm::vec3 direction = glm::normalize(std::cos(a) * along - std::sin(a) * normal);
    return {target - 20.0f * direction, direction};
}

// The hit lies on the ray, is the displaced point of its (sub-face, u, v), and is where the
// brute force finds the first surface.
void expectOnDisplacedSurface(const Scene& scene, const DisplacedPicker::Hit& hit, const Ray& ray, float reference) {
    ASSERT_NE(hit.subface, kNoHit);
    EXPECT_TRUE(hit.refined);
    const DisplacedPoint f = displacedSurfacePoint(*scene.planned, scene.displacement, hit.subface, hit.u, hit.v);
    EXPECT_LT(glm::length(f.position - hit.position), 2e-5f);
    EXPECT_LT(glm::length(f.normal - hit.normal), 1e-4f);
    EXPECT_LT(glm::length(ray.origin + hit.distance * ray.direction - hit.position), 2e-5f);
    EXPECT_NEAR(hit.distance, reference, 5e-3f);
}

}  // namespace

TEST(DisplacedPicking, GrazingAndHeadOnRaysHitTheNearestDisplacedPoint) {
    Scene scene(kBumpHeight);
    DisplacedPicker picker(*scene.planned, scene.displacement);
    EXPECT_EQ(picker.gridResolution(0), 16u);  // follows the tiles
    const BruteForce brute(*scene.planned, scene.displacement);
    uint32_t checked = 0;
    // Targets on the bump's flanks, its top and the flat base (off the grid lines of both the
    // picker and the brute force: a ray through a shared vertex may slip between triangles in
    // float, which would test the triangle test, not the picker); rays at 5-20 degrees to the
    // displaced surface's tangent plane there, from four sides, and head-on.
    for (const glm::vec2 uv : {glm::vec2(0.213f, 0.537f), glm::vec2(0.517f, 0.471f), glm::vec2(0.903f, 0.312f), glm::vec2(0.409f, 0.811f)})
        for (uint32_t s : {14u, 15u, 21u, 0u}) {
            const DisplacedPoint target = displacedSurfacePoint(*scene.planned, scene.displacement, s, uv.x, uv.y);
            for (float degrees : {5.0f, 10.0f, 20.0f, 90.0f})
                for (float azimuth : {0.3f, 1.9f, 3.4f, 5.0f}) {
                    const Ray ray = grazingRay(target.position, target.normal, degrees, azimuth);
                    const float reference = brute.distance(ray);
                    if (reference == kNoDistance) continue;
                    const DisplacedPicker::Hit hit = picker.intersect(*scene.planned, scene.displacement, ray);
                    SCOPED_TRACE(testing::Message() << "sub-face " << s << " degrees " << degrees << " azimuth " << azimuth);
                    expectOnDisplacedSurface(scene, hit, ray, reference);
                    ++checked;
                    if (degrees == 90.0f) break;  // head-on: one azimuth is enough
                }
        }
    EXPECT_GT(checked, 150u);
}

TEST(DisplacedPicking, ARayPastTheBumpsSideHitsTheBumpNotTheBaseBehindIt) {
    Scene scene(kBumpHeight);
    DisplacedPicker picker(*scene.planned, scene.displacement);
    LimitPicker undisplaced(*scene.planned, 8);
    const BruteForce brute(*scene.planned, scene.displacement);
    // 12 degrees down through the bump's axis at 30% of its height, on to the base beyond it.
    const glm::vec3 direction = glm::normalize(glm::vec3(1.0f, 0.05f, -std::tan(glm::radians(12.0f))));
    const glm::vec3 through = kCentre + glm::vec3(0.0f, 0.2f, 0.3f * kBumpHeight);
    const Ray ray{through - 10.0f * direction, direction};
    const DisplacedPicker::Hit hit = picker.intersect(*scene.planned, scene.displacement, ray);
    expectOnDisplacedSurface(scene, hit, ray, brute.distance(ray));
    EXPECT_GT(hit.position.z, 0.25f * kBumpHeight);
    EXPECT_LT(glm::length(glm::vec2(hit.position) - glm::vec2(kCentre)), kBumpRadius);
    // The undisplaced surface meets that ray only at the base, beyond the bump.
    const LimitPicker::Hit base = undisplaced.intersect(*scene.planned, ray);
    ASSERT_NE(base.subface, kNoHit);
    EXPECT_GT(base.distance, hit.distance + 1.0f);
}

TEST(DisplacedPicking, WhereOnlyTheUndisplacedSurfaceIsTheRayGoesOn) {
    // A dent: a ray at 10 degrees aimed at the dent's rim level over its centre finds no surface
    // there (it is 2 units deeper) and hits the dent's far wall instead.
    Scene scene(-kBumpHeight);
    DisplacedPicker picker(*scene.planned, scene.displacement);
    LimitPicker undisplaced(*scene.planned, 8);
    const BruteForce brute(*scene.planned, scene.displacement);
    const Ray ray = grazingRay(kCentre, glm::vec3(0, 0, 1), 10.0f, 0.7f);
    const LimitPicker::Hit flat = undisplaced.intersect(*scene.planned, ray);
    ASSERT_NE(flat.subface, kNoHit);
    const DisplacedPicker::Hit hit = picker.intersect(*scene.planned, scene.displacement, ray);
    expectOnDisplacedSurface(scene, hit, ray, brute.distance(ray));
    EXPECT_GT(hit.distance, flat.distance + 0.5f);
    EXPECT_LT(hit.position.z, -0.1f);
    // Parallel to the base just below it, the ray would graze nothing undisplaced, and under
    // the dent's rim it passes through the dent: it hits the near wall.
    const Ray under{kCentre + glm::vec3(-5.0f, 0.0f, -0.5f), glm::vec3(1, 0, 0)};
    const DisplacedPicker::Hit wall = picker.intersect(*scene.planned, scene.displacement, under);
    expectOnDisplacedSurface(scene, wall, under, brute.distance(under));
    EXPECT_LT(wall.position.x, kCentre.x);
    // A ray below the dent's bottom misses everything.
    const Ray below{kCentre + glm::vec3(-5.0f, 0.0f, -2.5f), glm::vec3(1, 0, 0)};
    EXPECT_EQ(picker.intersect(*scene.planned, scene.displacement, below).subface, kNoHit);
}

TEST(DisplacedPicking, UpdatingAfterDabsEqualsARebuild) {
    Scene scene(kBumpHeight);
    DisplacedPicker picker(*scene.planned, scene.displacement);
    Sculptor sculptor(scene.displacement, *scene.samples);
    sculptor.beginStroke();
    const Brush brush{BrushKind::Raise, 0.6f, 0.5f, Falloff::Smooth};
    for (const glm::vec3 centre : {glm::vec3(1.2f, 1.5f, 0.0f), glm::vec3(4.5f, 3.2f, 0.0f)}) {
        ASSERT_GT(sculptor.dab(brush, MirrorAxis::None, centre), 0u);
        picker.updateSamples(*scene.planned, scene.displacement, sculptor.lastDabSamples());
        EXPECT_GT(picker.lastUpdated().size(), 0u);
        EXPECT_LT(picker.lastUpdated().size(), 16u);  // of 36: only those the dab reached
    }
    sculptor.endStroke();
    const DisplacedPicker rebuilt(*scene.planned, scene.displacement);
    uint32_t hits = 0;
    for (float x = 0.25f; x < 6.0f; x += 0.5f)
        for (float y = 0.25f; y < 6.0f; y += 0.5f) {
            const Ray ray = grazingRay({x, y, 0.0f}, glm::vec3(0, 0, 1), 15.0f, 0.4f);
            const DisplacedPicker::Hit a = picker.intersect(*scene.planned, scene.displacement, ray);
            const DisplacedPicker::Hit b = rebuilt.intersect(*scene.planned, scene.displacement, ray);
            ASSERT_EQ(a.subface, b.subface);
            if (a.subface == kNoHit) continue;
            ++hits;
            EXPECT_EQ(a.u, b.u);
            EXPECT_EQ(a.v, b.v);
            EXPECT_EQ(a.distance, b.distance);
            EXPECT_EQ(a.refined, b.refined);
        }
    EXPECT_GT(hits, 100u);
}

TEST(DisplacedPicking, WithoutDisplacementItPicksTheLimitSurface) {
    Scene scene(0.0f);
    const Displacement none;
    DisplacedPicker picker(*scene.planned, none);
    LimitPicker limit(*scene.planned, 8);
    const Ray ray = grazingRay({2.3f, 4.1f, 0.0f}, glm::vec3(0, 0, 1), 30.0f, 1.0f);
    const DisplacedPicker::Hit hit = picker.intersect(*scene.planned, none, ray);
    const LimitPicker::Hit reference = limit.intersect(*scene.planned, ray);
    ASSERT_TRUE(hit.refined && reference.refined);
    EXPECT_LT(glm::length(hit.position - reference.position), 1e-5f);
    EXPECT_LT(glm::length(hit.normal - glm::vec3(0, 0, 1)), 1e-5f);
}
