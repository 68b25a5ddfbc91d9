// Screen-adaptive grid factors with the camera among the faces (render/grid_layout.h): what lies
// behind the eye takes one piece, and no view lays out more than kMaxAdaptiveGridSlots slots.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "camera.h"
#include "gpu_plans.h"
#include "grid_layout.h"
#include "plan_pass.h"
#include "plans/planned_cage.h"
#include "test_cages.h"

using namespace qp;

namespace {

PlannedCage plan(const Cage& cage, PlanDatabase& db) {
    Result<PlannedCage> planned = PlannedCage::create(cage, db, {}, "test cage");
    EXPECT_TRUE(planned.ok()) << planned.error().message;
    return std::move(planned).value();
}

// An n x n grid of unit quads (the xy plane, gently bumped), planned and packed for the grid.
struct PlannedGrid {
    PlanDatabase db;  // before `planned`, which points into it
    PlannedCage planned;
    GpuPlanData data;
    std::vector<glm::vec4> points;
    explicit PlannedGrid(uint32_t n)
        : planned(plan(test::makeGrid(n), db)), data(packPlans(planned)), points(boundaryPointPositions(planned)) {}
};

// Standing on the middle of an n x n PlannedGrid, looking along +x just above it: the half at x
// below the middle is behind the eye.
RenderCamera standingOnGrid(uint32_t n) {
    RenderCamera camera;
    const float middle = 0.5f * float(n);
    camera.eye = {middle, middle, 0.6f};
    camera.target = {middle + 10.0f, middle, 0.3f};
    camera.up = {0.0f, 0.0f, 1.0f};
    camera.nearZ = 0.01f;
    camera.farZ = 10.0f * float(n);
    return camera;
}

void expectNested(const GpuPlanData& data, const GridFactors& factors) {
    for (uint32_t d = 0; d < data.subfaces.size(); ++d)
        for (const GpuEdgeRef& r : data.boundaries[d].edges) {
            const uint32_t pieces = factors.segmentPieces[r.segment] * ((r.flags & kEdgeRefSplit) ? 2 : 1);
            ASSERT_EQ(factors.subfaceFactor[d] % pieces, 0u) << "drawn sub-face " << d;
        }
}

}  // namespace

TEST(GridFactors, SegmentsBehindTheEyeTakeOnePiece) {
    constexpr uint32_t n = 24;
    const PlannedGrid grid(n);
    const GpuPlanData& data = grid.data;
    const std::vector<glm::vec4>& points = grid.points;
    const RenderCamera camera = standingOnGrid(n);
    const AdaptiveView view{viewProjection(camera), pixelsPerUnit(projectionMatrix(camera), 600), 4.0f};
    const GridFactors factors = adaptiveGridFactors(data, points, view);
    expectNested(data, factors);

    // Segments by where their ends are: wholly behind the eye by more than an edge, or in front.
    uint32_t behind = 0, inFrontFine = 0;
    for (uint32_t d = 0; d < data.subfaces.size(); ++d) {
        const GpuSubfaceBoundary& b = data.boundaries[d];
        static const uint32_t start[4] = {0, 1, 3, 0}, end[4] = {1, 2, 2, 3};
        for (uint32_t e = 0; e < 4; ++e) {
            if (b.edges[e].flags & (kEdgeRefSplit | kEdgeRefHalf)) continue;
            const float xa = points[b.corners[start[e]]].x, xb = points[b.corners[end[e]]].x;
            const uint32_t pieces = factors.segmentPieces[b.edges[e].segment];
            if (std::max(xa, xb) < camera.eye.x - 1.5f) {
                ++behind;
                EXPECT_EQ(pieces, 1u) << "a segment behind the eye, drawn sub-face " << d << " edge " << e;
            } else if (std::min(xa, xb) > camera.eye.x && std::min(xa, xb) < camera.eye.x + 2.0f && pieces > 1) {
                ++inFrontFine;
            }
        }
    }
    EXPECT_GT(behind, 200u);
    EXPECT_GT(inFrontFine, 10u);  // the faces just ahead are still divided
}

TEST(GridFactors, AViewAmongManyFacesStaysWithinTheSlotBudget) {
    // 4,900 quads at factor 64 would be 20.7 M slots.
    constexpr uint32_t n = 70;
    const PlannedGrid grid(n);
    const GpuPlanData& data = grid.data;
    const std::vector<glm::vec4>& points = grid.points;
    RenderCamera camera = standingOnGrid(n);
    camera.eye.z = 40.0f;  // high above the middle, looking down: every face in front
    camera.target = {camera.eye.x + 0.01f, camera.eye.y, 0.0f};
    camera.up = {1.0f, 0.0f, 0.0f};
    camera.fovY = glm::radians(120.0f);
    const AdaptiveView fine{viewProjection(camera), pixelsPerUnit(projectionMatrix(camera), 2000), 0.05f};
    const GridFactors factors = adaptiveGridFactors(data, points, fine);
    expectNested(data, factors);
    EXPECT_LE(gridSlots(factors), kMaxAdaptiveGridSlots);
    EXPECT_GT(gridSlots(factors), kMaxAdaptiveGridSlots / 8);  // coarser only as far as it had to be
    // A view that fits keeps its factors.
    const AdaptiveView coarse{fine.viewProjection, fine.pixelsPerUnit, 4.0f};
    const GridFactors fitting = adaptiveGridFactors(data, points, coarse);
    EXPECT_LT(gridSlots(fitting), kMaxAdaptiveGridSlots);
    EXPECT_GT(*std::max_element(fitting.subfaceFactor.begin(), fitting.subfaceFactor.end()), 1u);
}
