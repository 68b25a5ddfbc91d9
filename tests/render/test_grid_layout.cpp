// The grid layout's bookkeeping, without a device (render/grid_layout.h): copies come from
// evaluated slots and the dependents list them, layouts built in recycled tables or carried
// from an earlier layout equal layouts built whole, and adaptive factors nest.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <set>

#include "camera.h"
#include "grid_layout.h"
#include "plan_pass.h"
#include "render_test_support.h"
#include "test_cages.h"

using namespace qp;

// The layout's bookkeeping, without a device: sources are evaluated slots, and the dependents
// of a sub-face are exactly the other sub-faces holding copies of its slots.
TEST(GridLayout, SourcesAndDependentsAgreeWithTheCopies) {
    PlanDatabase db;
    PlannedCage planned = test::planCage(test::makeFeatureCage(), db);
    const GpuPlanData data = packPlans(planned);
    for (uint32_t factor : {1u, 4u, 9u}) {
        const GridLayout layout = buildGridLayout(data, uniformGridFactors(data, factor));
        std::set<std::pair<uint32_t, uint32_t>> copies;  // (owner, copier)
        for (uint32_t slot = 0; slot < layout.slotCount(); ++slot) {
            const uint32_t source = layout.source[slot];
            ASSERT_EQ(layout.source[source], source) << "slot " << slot << " copies a copy";
            if (layout.slotSubface[source] != layout.slotSubface[slot])
                copies.insert({layout.slotSubface[source], layout.slotSubface[slot]});
        }
        std::set<std::pair<uint32_t, uint32_t>> listed;
        for (uint32_t d = 0; d < data.subfaces.size(); ++d)
            for (uint32_t k = layout.dependentOffsets[d]; k < layout.dependentOffsets[d + 1]; ++k)
                listed.insert({d, layout.dependents[k]});
        EXPECT_EQ(listed, copies) << "factor " << factor;
        EXPECT_FALSE(copies.empty());
        const uint32_t first = copies.begin()->first;
        const std::vector<uint32_t> closure = withDependents(layout, std::span(&first, 1));
        for (auto [owner, copier] : copies)
            if (owner == first) {
                EXPECT_TRUE(std::binary_search(closure.begin(), closure.end(), copier));
            }
    }
}

// A layout built in the arrays of another (relayouts recycle the old tables) equals one built
// from nothing, whether the other was larger or smaller.
TEST(GridLayout, RecycledTablesGiveTheSameLayout) {
    PlanDatabase db;
    PlannedCage planned = test::planCage(test::makeFeatureCage(), db);
    const GpuPlanData data = packPlans(planned);
    for (auto [factor, other] : {std::pair{4u, 9u}, std::pair{9u, 2u}, std::pair{3u, 3u}}) {
        const GridLayout fresh = buildGridLayout(data, uniformGridFactors(data, factor));
        GridLayout recycled = buildGridLayout(data, uniformGridFactors(data, other));
        recycled.uniformRequest = other;
        const GridLayout reused = buildGridLayout(data, uniformGridFactors(data, factor), std::move(recycled));
        SCOPED_TRACE("factor " + std::to_string(factor) + " in the tables of " + std::to_string(other));
        EXPECT_EQ(reused.factors, fresh.factors);
        EXPECT_EQ(reused.subfaceOffset, fresh.subfaceOffset);
        EXPECT_EQ(reused.source, fresh.source);
        EXPECT_EQ(reused.slotSubface, fresh.slotSubface);
        EXPECT_EQ(reused.indices, fresh.indices);
        EXPECT_EQ(reused.indexOffset, fresh.indexOffset);
        EXPECT_EQ(reused.dependentOffsets, fresh.dependentOffsets);
        EXPECT_EQ(reused.dependents, fresh.dependents);
        EXPECT_EQ(reused.maxFactor, fresh.maxFactor);
        EXPECT_EQ(reused.uniformRequest, fresh.uniformRequest);
    }
}

namespace {

void expectSameLayout(const GridLayout& carried, const GridLayout& whole) {
    EXPECT_EQ(carried.factors, whole.factors);
    EXPECT_EQ(carried.subfaceOffset, whole.subfaceOffset);
    EXPECT_EQ(carried.source, whole.source);
    EXPECT_EQ(carried.slotSubface, whole.slotSubface);
    EXPECT_EQ(carried.indices, whole.indices);
    EXPECT_EQ(carried.indexOffset, whole.indexOffset);
    EXPECT_EQ(carried.dependentOffsets, whole.dependentOffsets);
    EXPECT_EQ(carried.dependents, whole.dependents);
    EXPECT_EQ(carried.maxFactor, whole.maxFactor);
}

}  // namespace

// A layout carried from another (grid_layout.h carryGridLayout) equals the layout built whole:
// screen-adaptive factors chosen again for a closer look (the sub-faces whose factors or edges
// changed laid out anew, the others and their copies carried), and sub-faces said to have new
// owners laid out anew among carried ones, in the tables of another layout.
TEST(GridLayout, CarriedLayoutsEqualLayoutsBuiltWhole) {
    PlanDatabase db;
    {
        PlannedCage planned = test::planCage(test::makeTorus(24, 12), db);
        const GpuPlanData data = packPlans(planned);
        const std::vector<glm::vec4> points = boundaryPointPositions(planned);
        const PlanView view = test::framedPlanView(planned.cage(), 256);
        const uint32_t count = uint32_t(data.subfaces.size());
        const GridFactors far = adaptiveGridFactors(data, points, AdaptiveView{view.viewProjection, view.pixelsPerUnit, 24.0f});
        const GridFactors near =
            adaptiveGridFactors(data, points, AdaptiveView{view.viewProjection, view.pixelsPerUnit, 12.0f}, &far);
        const std::vector<uint32_t> changed = subfacesWithNewFactors(data, far, near);
        ASSERT_FALSE(changed.empty());
        ASSERT_LT(changed.size(), count) << "some sub-faces keep their slots";
        std::vector<uint32_t> oldOf(count);
        std::iota(oldOf.begin(), oldOf.end(), 0u);
        for (uint32_t d : changed) oldOf[d] = UINT32_MAX;
        SCOPED_TRACE("adaptive factors chosen again");
        expectSameLayout(carryGridLayout(data, near, buildGridLayout(data, far), oldOf), buildGridLayout(data, near));

        // A face deleted: the later sub-faces renumbered, the faces around it re-planned (only
        // they may see new owners: plan_update.cpp).
        const GridLayout before = buildGridLayout(data, uniformGridFactors(data, 3));
        Result<EditReport> removed = planned.removeFace(count / 2);
        ASSERT_TRUE(removed.ok()) << removed.error().message;
        const GpuPlanData after = packPlans(planned);
        ASSERT_EQ(after.subfaces.size(), planned.subfaceCount()) << "every sub-face is drawn";
        const std::vector<uint32_t>& previous = removed->previousSubfaceOf;  // kNewElement is UINT32_MAX
        std::vector<char> replanned(after.subfaces.size(), 0);
        for (uint32_t f : removed->replannedFaceList)
            for (uint32_t s = planned.firstSubface(f); s < planned.firstSubface(f + 1); ++s) replanned[s] = 1;
        ASSERT_NE(std::count(previous.begin(), previous.end(), count / 2 + 1), 0) << "later sub-faces renumbered";
        SCOPED_TRACE("a face deleted");
        expectSameLayout(carryGridLayout(after, uniformGridFactors(after, 3), before, previous, replanned),
                         buildGridLayout(after, uniformGridFactors(after, 3)));
    }
    PlannedCage planned = test::planCage(test::makeFeatureCage(), db);
    const GpuPlanData data = packPlans(planned);
    const uint32_t count = uint32_t(data.subfaces.size());
    // The same factors, every third sub-face with new owners, in the tables of a coarser layout.
    const GridLayout uniform = buildGridLayout(data, uniformGridFactors(data, 4));
    std::vector<uint32_t> all(count);
    std::iota(all.begin(), all.end(), 0u);
    std::vector<char> ownersChanged(count, 0);
    for (uint32_t d = 0; d < count; d += 3) ownersChanged[d] = 1;
    SCOPED_TRACE("owners changed, recycled tables");
    expectSameLayout(
        carryGridLayout(data, uniformGridFactors(data, 4), uniform, all, ownersChanged, buildGridLayout(data, uniformGridFactors(data, 2))),
        uniform);
}

// Adaptive factors after any earlier layout still nest: every edge's pieces divide its
// sub-face's factor (a uniform layout's odd pieces must not be kept by the hysteresis).
TEST(GridLayout, AdaptiveFactorsNestWhateverCameBefore) {
    PlanDatabase db;
    PlannedCage planned = test::planCage(test::makeFeatureCage(), db);
    const GpuPlanData data = packPlans(planned);
    const std::vector<glm::vec4> points = boundaryPointPositions(planned);
    Bounds bounds = computeBounds(planned.cage());
    RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
    camera.eye = camera.target + 0.4f * (camera.eye - camera.target);
    const AdaptiveView view{viewProjection(camera), pixelsPerUnit(projectionMatrix(camera), 320), 6.0f};
    for (uint32_t before : {3u, 5u, 8u, 12u}) {
        const GridFactors uniform = uniformGridFactors(data, before);
        const GridFactors adaptive = adaptiveGridFactors(data, points, view, &uniform);
        for (uint32_t d = 0; d < data.subfaces.size(); ++d)
            for (const GpuEdgeRef& r : data.boundaries[d].edges) {
                const uint32_t pieces = adaptive.segmentPieces[r.segment] * ((r.flags & 2) ? 2 : 1);
                EXPECT_EQ(adaptive.subfaceFactor[d] % pieces, 0u) << "after uniform " << before << ", drawn sub-face " << d;
            }
    }
}
