// Picking on the cage and on the limit surface, visibility and box selection (core/edit/picking.h).
#include <algorithm>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "edit/picking.h"
#include "test_cages.h"

namespace {

using qp::Cage;
using qp::PickView;

// A Vulkan-style camera, as render/camera.h builds it (depth 0..1, Y flipped).
PickView camera(glm::vec3 eye, glm::vec3 target, glm::vec2 size = {800, 600}) {
    glm::mat4 projection = glm::perspective(glm::radians(40.0f), size.x / size.y, 0.1f, 100.0f);
    projection[1][1] *= -1.0f;
    return {projection * glm::lookAt(eye, target, glm::vec3(0, 1, 0)), size};
}

float distanceToRay(const qp::Ray& ray, const glm::vec3& p) {
    const glm::vec3 w = p - ray.origin;
    return glm::length(w - glm::dot(w, ray.direction) * ray.direction);
}

qp::PlannedCage plan(const Cage& cage, qp::PlanDatabase& db) {
    auto planned = qp::PlannedCage::create(cage, db, {}, "test cage");
    EXPECT_TRUE(planned.ok());
    return std::move(planned).value();
}

}  // namespace

TEST(Picking, PixelsFollowVulkanConventionsAndRaysRoundTrip) {
    PickView view = camera({0, 0, 5}, {0, 0, 0});
    PickView::Projected centre = view.project({0, 0, 0});
    EXPECT_NEAR(centre.pixel.x, 400.0f, 1e-3f);
    EXPECT_NEAR(centre.pixel.y, 300.0f, 1e-3f);
    EXPECT_TRUE(centre.inFront);
    EXPECT_LT(view.project({0, 1, 0}).pixel.y, 300.0f);  // up in the world is up on screen (smaller y)
    EXPECT_GT(view.project({1, 0, 0}).pixel.x, 400.0f);
    EXPECT_FALSE(view.project({0, 0, 10}).inFront);  // behind the camera
    glm::mat4 ortho = glm::ortho(-4.0f, 4.0f, -3.0f, 3.0f, 0.1f, 20.0f);
    ortho[1][1] *= -1.0f;
    PickView orthographic{ortho * glm::lookAt(glm::vec3(1, 2, 6), glm::vec3(0), glm::vec3(0, 1, 0)), {800, 600}};
    for (const PickView& v : {view, orthographic})
        for (glm::vec3 p : {glm::vec3(0.3f, -0.7f, 1.2f), glm::vec3(-1.5f, 0.9f, -2.0f)}) {
            qp::Ray ray = v.rayThrough(v.project(p).pixel);
            EXPECT_NEAR(glm::length(ray.direction), 1.0f, 1e-5f);
            EXPECT_LT(distanceToRay(ray, p), 1e-4f);
            EXPECT_GT(glm::dot(p - ray.origin, ray.direction), 0.0f);
        }
    // Orthographic rays are parallel.
    EXPECT_NEAR(glm::length(orthographic.rayThrough({10, 10}).direction - orthographic.rayThrough({700, 500}).direction), 0.0f, 1e-5f);
}

TEST(Picking, FacesVerticesAndEdgesOfACube) {
    Cage cube = qp::test::makeCube();
    qp::Topology t = qp::buildTopology(cube);
    qp::CageRaycaster raycaster(cube);
    PickView front = camera({0.3f, 0.2f, 6}, {0, 0, 0});
    qp::CageRaycaster::Hit hit = qp::pickFace(raycaster, front, front.project({0.1f, 0.1f, 1}).pixel);
    EXPECT_EQ(hit.face, 1u);  // the z = 1 face
    EXPECT_NEAR(hit.position.z, 1.0f, 1e-5f);
    EXPECT_EQ(qp::pickFace(raycaster, front, {5, 5}).face, qp::kNoHit);

    // A three-quarter view: vertex 6 (1, 1, 1) faces the camera, vertex 0 (-1, -1, -1) is hidden.
    PickView view = camera({4, 3, 2.5f}, {0, 0, 0});
    glm::vec2 p6 = view.project(cube.positions[6]).pixel;
    qp::VertexPick near6 = qp::pickVertex(cube, view, p6 + glm::vec2(3, -2), 8.0f);
    EXPECT_EQ(near6.vertex, 6u);
    EXPECT_NEAR(near6.pixelDistance, std::sqrt(13.0f), 1e-3f);
    EXPECT_EQ(qp::pickVertex(cube, view, p6 + glm::vec2(3, -2), 2.0f).vertex, qp::kNoHit);

    const float diagonal = 2.0f * std::sqrt(3.0f);
    qp::Occluder occluder = qp::cageOccluder(raycaster, 1e-4f * diagonal);
    glm::vec2 p0 = view.project(cube.positions[0]).pixel;
    EXPECT_EQ(qp::pickVertex(cube, view, p0, 4.0f).vertex, 0u);
    EXPECT_EQ(qp::pickVertex(cube, view, p0, 4.0f, &occluder).vertex, qp::kNoHit);
    EXPECT_TRUE(qp::isVisible(view, cube.positions[6], &occluder));
    EXPECT_FALSE(qp::isVisible(view, cube.positions[0], &occluder));

    // Edge 5-6 (x = 1, z = 1) at a quarter of its length from 5.
    glm::vec3 quarter = cube.positions[5] + 0.25f * (cube.positions[6] - cube.positions[5]);
    qp::EdgePick edge = qp::pickEdge(cube, t, view, view.project(quarter).pixel + glm::vec2(1, 1), 5.0f, &occluder);
    ASSERT_TRUE(edge.hit);
    EXPECT_EQ(edge.edge, (qp::EdgeKey{5, 6}));
    EXPECT_NEAR(edge.t, 0.25f, 0.02f);
    EXPECT_FALSE(qp::pickEdge(cube, t, view, {2, 2}, 5.0f).hit);
}

TEST(Picking, BoxSelectWithAndWithoutVisibility) {
    Cage cube = qp::test::makeCube();
    qp::Topology t = qp::buildTopology(cube);
    qp::CageRaycaster raycaster(cube);
    qp::Occluder occluder = qp::cageOccluder(raycaster, 1e-3f);
    PickView view = camera({4, 3, 2.5f}, {0, 0, 0});
    const glm::vec2 a(0, 0), b(800, 600);
    EXPECT_EQ(qp::boxSelect(cube, t, qp::SelectionMode::Vertex, view, a, b).size(), 8u);
    EXPECT_EQ(qp::boxSelect(cube, t, qp::SelectionMode::Vertex, view, b, a, &occluder).size(), 7u);
    EXPECT_EQ(qp::boxSelect(cube, t, qp::SelectionMode::Face, view, a, b).size(), 6u);
    EXPECT_EQ(qp::boxSelect(cube, t, qp::SelectionMode::Face, view, a, b, &occluder).faces,
              (std::vector<uint32_t>{1, 3, 4}));  // z = 1, x = 1, y = 1
    EXPECT_EQ(qp::boxSelect(cube, t, qp::SelectionMode::Edge, view, a, b, &occluder).size(), 9u);
    // A small box around vertex 6 only.
    glm::vec2 p6 = view.project(cube.positions[6]).pixel;
    EXPECT_EQ(qp::boxSelect(cube, t, qp::SelectionMode::Vertex, view, p6 - 3.0f, p6 + 3.0f).vertices,
              (std::vector<uint32_t>{6}));
}

TEST(Picking, LimitSurfaceHitsAreOnTheExactSurfaceAndFollowEdits) {
    qp::PlanDatabase db;
    qp::PlannedCage planned = plan(qp::test::makeSubdividedCube(3), db);
    qp::LimitPicker picker(planned, 6);
    qp::CageRaycaster raycaster(planned.cage());
    PickView view = camera({3.5f, 2.5f, 3}, {0, 0, 0});
    uint32_t hits = 0, refined = 0;
    for (float x = 250; x <= 550; x += 25)
        for (float y = 150; y <= 450; y += 25) {
            qp::Ray ray = view.rayThrough({x, y});
            qp::LimitPicker::Hit hit = picker.intersect(planned, ray);
            if (hit.subface == qp::kNoHit) continue;
            ++hits;
            if (!hit.refined) continue;
            ++refined;
            // On the ray, and exactly the limit point of (sub-face, u, v).
            EXPECT_LT(distanceToRay(ray, hit.position), 1e-5f);
            EXPECT_LT(glm::length(planned.evaluate(hit.subface, hit.u, hit.v).position - hit.position), 1e-5f);
            // The limit surface of a convex cage lies inside it.
            EXPECT_GE(hit.distance, raycaster.intersect(ray).distance - 1e-5f);
        }
    EXPECT_GT(hits, 50u);
    EXPECT_GE(refined, hits * 9 / 10);

    // Pull the corner vertex (1, 1, 1) towards the camera; after update() the ray through its
    // old limit point hits the surface nearer than before.
    qp::Ray ray = view.rayThrough(view.project({0.62f, 0.62f, 0.62f}).pixel);
    const float before = picker.intersect(planned, ray).distance;
    uint32_t corner = 0;
    for (uint32_t v = 0; v < planned.cage().vertexCount(); ++v)
        if (planned.cage().positions[v] == glm::vec3(1, 1, 1)) corner = v;
    glm::vec3 pulled(1.6f, 1.6f, 1.6f);
    auto report = planned.moveVertices({&corner, 1}, {&pulled, 1});
    ASSERT_TRUE(report.ok());
    picker.update(planned, *report);
    const qp::LimitPicker::Hit after = picker.intersect(planned, ray);
    EXPECT_LT(after.distance, before - 0.05f);
    EXPECT_TRUE(after.refined);

    // Visibility against the limit surface: the far corner is hidden, the near one is not.
    qp::Occluder limit = qp::limitOccluder(picker, planned, 1e-4f);
    EXPECT_TRUE(qp::isVisible(view, pulled, &limit));
    EXPECT_FALSE(qp::isVisible(view, glm::vec3(-1, -1, -1), &limit));
}

namespace {

// A lattice of unit boxes 10 x 10 x 10, spaced 2 apart.
std::vector<qp::Box> latticeBoxes(glm::vec3 shift = glm::vec3(0.0f)) {
    std::vector<qp::Box> boxes;
    for (int z = 0; z < 10; ++z)
        for (int y = 0; y < 10; ++y)
            for (int x = 0; x < 10; ++x) {
                qp::Box b;
                b.add(glm::vec3(2 * x, 2 * y, 2 * z) + shift);
                b.add(glm::vec3(2 * x + 1, 2 * y + 1, 2 * z + 1) + shift);
                boxes.push_back(b);
            }
    return boxes;
}

}  // namespace

TEST(Picking, BvhQueriesVisitOnlyTheBoxesTheRayEnters) {
    const std::vector<qp::Box> boxes = latticeBoxes();
    const qp::BoxBvh bvh(boxes);
    auto visited = [&](glm::vec3 origin, glm::vec3 direction) {
        std::vector<uint32_t> items;
        bvh.traverse(origin, glm::normalize(direction), qp::kNoDistance, [&](uint32_t item, float tMax) {
            items.push_back(item);
            return tMax;  // no hit: an unbounded query must still skip every box it misses
        });
        return items;
    };
    EXPECT_TRUE(visited({-5, 0.5f, 0.5f}, {0, 1, 0}).empty());  // passes beside the lattice
    EXPECT_TRUE(visited({0.5f, 1.5f, 0.5f}, {1, 0, 0}).empty());  // between two layers of boxes
    // Along the row y = z = 0.5: its ten boxes, and no other.
    std::vector<uint32_t> row = visited({-5, 0.5f, 0.5f}, {1, 0, 0});
    std::sort(row.begin(), row.end());
    EXPECT_EQ(row, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9}));
}

TEST(Picking, BvhRefitFindsWhatAFreshBuildFinds) {
    qp::BoxBvh refitted(latticeBoxes());
    std::vector<qp::Box> moved = latticeBoxes();
    for (size_t i = 0; i < moved.size(); ++i) {  // every box shifted its own way
        const glm::vec3 shift(float(i % 7) * 0.3f, float(i % 5) * -0.4f, float(i % 3) * 0.5f);
        moved[i].min += shift, moved[i].max += shift;
    }
    refitted.refit(moved);
    const qp::BoxBvh fresh(moved);
    auto nearest = [&](const qp::BoxBvh& bvh, const qp::Ray& ray) {
        uint32_t best = qp::kNoHit;
        const glm::vec3 inverse = 1.0f / ray.direction;
        bvh.traverse(ray.origin, ray.direction, qp::kNoDistance, [&](uint32_t item, float tMax) {
            const float t = qp::rayEntersBox(moved[item], ray.origin, inverse, tMax);
            if (t < tMax) best = item, tMax = t;
            return tMax;
        });
        return best;
    };
    uint32_t hits = 0;
    for (int i = 0; i < 400; ++i) {
        const glm::vec3 target(float(i % 20), float((i / 20) % 20), float((i * 7) % 20));
        const qp::Ray ray{glm::vec3(-10, 25, -12), glm::normalize(target - glm::vec3(-10, 25, -12))};
        const uint32_t expected = nearest(fresh, ray);
        EXPECT_EQ(nearest(refitted, ray), expected) << "ray " << i;
        hits += expected != qp::kNoHit;
    }
    EXPECT_GT(hits, 200u);
}

TEST(Picking, LimitOccluderAnswersAsTheNearestHitWould) {
    qp::PlanDatabase db;
    qp::PlannedCage planned = plan(qp::test::makeSubdividedCube(3), db);
    const qp::LimitPicker picker(planned, 6);
    const PickView view = camera({3.5f, 2.5f, 3}, {0, 0, 0});
    uint32_t near = 0, hidden = 0;
    for (float x = 200; x <= 600; x += 20)
        for (float y = 100; y <= 500; y += 20) {
            const qp::Ray ray = view.rayThrough({x, y});
            const float first = picker.intersect(planned, ray).distance;
            // Distances well before, just around and well after the first hit, and past the cube.
            for (float d : {0.5f * first, first - 1e-3f, first + 1e-3f, first + 0.05f, first + 5.0f, 20.0f}) {
                if (!std::isfinite(d)) continue;
                EXPECT_EQ(picker.hides(planned, ray, d), first < d) << x << ", " << y << " at " << d;
                near += std::fabs(d - first) < 0.01f;
                hidden += first < d;
            }
        }
    EXPECT_GT(near, 100u);  // the refinement's window was crossed, not only skipped
    EXPECT_GT(hidden, 300u);
}

TEST(Picking, LimitPickerAfterMovesEqualsAFreshOne) {
    qp::PlanDatabase db;
    qp::PlannedCage planned = plan(qp::test::makeSubdividedCube(3), db);
    qp::LimitPicker picker(planned, 6);
    const PickView view = camera({3.5f, 2.5f, 3}, {0, 0, 0});
    for (uint32_t step = 0; step < 3; ++step) {  // moves that refit the tree
        const uint32_t v = 5 + 11 * step;
        const glm::vec3 p = planned.cage().positions[v] * 1.3f;
        auto report = planned.moveVertices({&v, 1}, {&p, 1});
        ASSERT_TRUE(report.ok());
        picker.update(planned, *report);
    }
    const qp::LimitPicker fresh(planned, 6);
    for (float x = 200; x <= 600; x += 25)
        for (float y = 100; y <= 500; y += 25) {
            const qp::Ray ray = view.rayThrough({x, y});
            const qp::LimitPicker::Hit a = picker.intersect(planned, ray), b = fresh.intersect(planned, ray);
            EXPECT_EQ(a.subface, b.subface) << x << ", " << y;
            EXPECT_EQ(a.distance, b.distance) << x << ", " << y;
        }
    EXPECT_EQ(qp::LimitPicker::resolutionFor(1000), 8u);
    EXPECT_EQ(qp::LimitPicker::resolutionFor(1'000'000), 3u);
    EXPECT_EQ(qp::LimitPicker::resolutionFor(100'000'000), 2u);
}

// Rays aimed at the sampled points themselves: the corners of cells and the lines quadrants
// share, where a test that skips cells or quadrants before the triangle tests could lose a hit
// to rounding. Grids with and without quadrant boxes, odd and even; a curved closed cage and a
// flat one (boxes of no thickness).
TEST(Picking, RaysAimedAtSampledPointsHitThem) {
    qp::PlanDatabase db;
    struct Case {
        qp::Cage cage;
        glm::vec3 eye;
        bool aroundOrigin;  // closed and convex about the origin, else flat
    };
    const Case cases[] = {{qp::test::makeSubdividedCube(3), {3.5f, 2.5f, 3.0f}, true},
                          {qp::test::makeFlatGrid(6), {1.0f, -2.0f, 7.0f}, false}};
    for (const Case& c : cases) {
        qp::PlannedCage planned = plan(c.cage, db);
        for (uint32_t resolution : {3u, 5u, 6u, 8u}) {
            const qp::LimitPicker picker(planned, resolution);
            uint32_t aimed = 0;
            for (uint32_t s = 0; s < planned.subfaceCount(); ++s) {
                if (!planned.hasSurface(s)) continue;
                for (uint32_t j = 0; j <= resolution; ++j)
                    for (uint32_t i = 0; i <= resolution; ++i) {
                        const float u = float(i) / float(resolution), v = float(j) / float(resolution);
                        const qp::LimitSample sample = planned.evaluate(s, u, v);
                        const glm::vec3 toPoint = sample.position - c.eye;
                        const qp::Ray ray{c.eye, glm::normalize(toPoint)};
                        const glm::vec3 normal = glm::normalize(glm::cross(sample.du, sample.dv));
                        // Facing the eye, not grazing: on these convex or flat surfaces nothing
                        // else lies before the point.
                        const glm::vec3 outwards = glm::dot(normal, sample.position) >= 0.0f ? normal : -normal;
                        const float facing = c.aroundOrigin ? glm::dot(outwards, -ray.direction)
                                                            : std::fabs(glm::dot(normal, ray.direction));
                        if (facing < 0.3f) continue;
                        ++aimed;
                        const qp::LimitPicker::Hit hit = picker.intersect(planned, ray);
                        const std::string where = "resolution " + std::to_string(resolution) + " sub-face " +
                                                  std::to_string(s) + " (" + std::to_string(i) + ", " + std::to_string(j) + ")";
                        ASSERT_NE(hit.subface, qp::kNoHit) << where;
                        EXPECT_NEAR(hit.distance, glm::length(toPoint), 1e-4f) << where;
                    }
            }
            EXPECT_GT(aimed, 200u) << "resolution " << resolution;
        }
    }
}
