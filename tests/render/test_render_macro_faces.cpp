// Macro faces on the grid paths (render/macro_grid.h): far-away blocks of faces drawn with
// fewer than two triangles a face, and the surface stays closed (no crack, no T-junction)
// between coarse macro faces, single faces and n-gon sub-faces.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <map>

#include <glm/gtc/matrix_transform.hpp>

#include "draw_path.h"
#include "edit/edit_history.h"
#include "grid_relayout.h"
#include "mesh/generated_cage.h"
#include "mesh/obj_io.h"
#include "offscreen_target.h"
#include "plan_pass.h"
#include "plan_update.h"
#include "plans/macro_faces.h"
#include "plans/planned_cage.h"
#include "render_test_support.h"
#include "test_cages.h"
#include "test_support.h"
#include "vk_commands.h"

using namespace qp;

namespace {

constexpr uint32_t kImageSize = 320;

struct MacroFixture : test::PlanPassTest {};

// The layout's triangles over the slots that evaluate their vertices: degenerate ones (two
// corners one vertex, as snapping makes) dropped, each undirected edge counted with its
// direction. On a closed, consistently wound surface every edge is crossed as often one way as
// the other; a crack or a T-junction leaves an edge crossed once. Returns the triangles kept.
size_t expectClosed(const GridLayout& layout, std::span<const uint32_t> skipped, const std::string& what) {
    std::map<std::pair<uint32_t, uint32_t>, int> balance;  // (low, high) -> uses low->high minus high->low
    size_t kept = 0;
    for (uint32_t d = 0; d + 1 < layout.indexOffset.size(); ++d) {
        if (std::binary_search(skipped.begin(), skipped.end(), d)) continue;
        for (uint32_t i = layout.indexOffset[d]; i < layout.indexOffset[d + 1]; i += 3) {
            const uint32_t v[3] = {layout.source[layout.indices[i]], layout.source[layout.indices[i + 1]],
                                   layout.source[layout.indices[i + 2]]};
            if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;
            ++kept;
            for (int k = 0; k < 3; ++k) {
                const uint32_t a = v[k], b = v[(k + 1) % 3];
                balance[std::minmax(a, b)] += a < b ? 1 : -1;
            }
        }
    }
    size_t open = 0;
    for (const auto& [edge, count] : balance) open += count != 0;
    EXPECT_EQ(open, 0u) << what << ": edges crossed more often one way than the other (cracks or T-junctions)";
    return kept;
}

std::vector<std::pair<std::string, Cage>> closedCages() {
    std::vector<std::pair<std::string, Cage>> cages = {{"regular torus", test::makeTorus(48, 40)},
                                                       {"subdivided cube", test::makeSubdividedCube(8)},
                                                       {"generated", makeBenchmarkCage(3000, 1)}};
    return cages;
}

}  // namespace

TEST_F(MacroFixture, CoarseMacroFacesKeepClosedCagesClosed) {
    for (auto& [name, cage] : closedCages()) {
        for (MacroChoice choice : {MacroChoice::Rectangles, MacroChoice::Quartets, MacroChoice::Blocks}) {
            PlanDatabase db;
            PlannedCage planned = test::planCage(cage, db);
            PlanBuffers buffers = upload(planned);
            buffers.data.macros.choice = choice;
            rebuildMacroGrid(planned, buffers.data);
            ASSERT_FALSE(buffers.data.macros.faces.empty()) << name;
            const std::string base = name + ", " + macroChoiceName(choice);
            size_t single = 0;
            for (uint32_t minify : {1u, 2u, 4u, 16u}) {
                GridFactors factors = uniformGridFactors(buffers.data, 1);
                chooseMacroPieces(buffers.data, factors, buffers.pointPositionsHost, nullptr, minify, buffers.holeDrawn);
                // The generated cage has triangles: its uniform factor 1 is 2 (grid_layout.h), so minify 2
                // draws its macro faces at per-face factor 1.
                const bool coarse = minify > 1;
                EXPECT_EQ(factors.macroResolution.empty(), !coarse) << base << ", minify " << minify;
                ASSERT_TRUE(prepareGrid(ctx, pass, buffers, factors).ok());
                evaluateGridOnCpu(planned, buffers);
                const std::string what = base + ", per-face factor 1/" + std::to_string(minify);
                const size_t triangles = expectClosed(buffers.gridLayout, buffers.holeDrawn, what);
                if (minify == 1) {
                    single = triangles;
                } else if (coarse) {
                    EXPECT_LT(triangles, single) << what;
                }
                if (HasFatalFailure()) return;
            }
            destroyPlanBuffers(ctx, buffers);
        }
    }
}

// The renderer's own choice: far away, screen-adaptive factors make macro faces coarse; drawn
// on both grid paths with validation on, the picture covers the model, and it stays closed.
TEST_F(MacroFixture, FarViewsDrawCoarseMacroFacesOnBothGridPaths) {
    Result<OffscreenTarget> target = createOffscreenTarget(ctx, kImageSize, kImageSize, VK_FORMAT_R8G8B8A8_UNORM);
    ASSERT_TRUE(target.ok()) << target.error().message;
    const Cage cage = test::makeTorus(96, 40);
    PlanDatabase db;
    PlannedCage planned = test::planCage(cage, db);
    PlanBuffers buffers = upload(planned);
    // Factors as for a view ten times farther (fewer pixels per unit), drawn framed so that the
    // picture shows the coarse macro faces.
    PlanView view = test::framedPlanView(cage, kImageSize);
    view.pixelsPerUnit /= 10.0f;
    const TessellationSettings adaptive{0, 4.0f};
    for (DrawPath path : {DrawPath::CpuGrid, DrawPath::Grid}) {
        buffers.gridEvaluator = GridEvaluator::None;
        ASSERT_TRUE(preparePlanFrame(ctx, pass, buffers, planned, path, view, adaptive).ok());
        ASSERT_FALSE(buffers.gridLayout.factors.macroResolution.empty()) << drawPathName(path) << ": no macro face is coarse";
        Status drawn = submitAndWait(ctx, [&](VkCommandBuffer cmd) {
            recordPlanFrame(cmd, pass, buffers, path, renderTarget(*target), view, adaptive);
        });
        ASSERT_TRUE(drawn.ok()) << drawn.error().message;
        const size_t triangles = expectClosed(buffers.gridLayout, {}, drawPathName(path));
        EXPECT_LT(triangles, size_t(cage.faceCount())) << "fewer than one triangle a face when far away";
        Result<std::vector<uint8_t>> rgba = readPixels(ctx, *target);
        ASSERT_TRUE(rgba.ok());
        size_t covered = 0;
        for (size_t i = 0; i < rgba->size(); i += 4) covered += std::abs(int((*rgba)[i]) - int((*rgba)[0])) > 8;
        EXPECT_GT(covered, rgba->size() / 4 / 10) << "the torus covers the picture";
        const std::string png = (test::testOutputDir() / ("macro_faces_far_" + std::string(drawPathName(path)) + ".png")).string();
        ASSERT_TRUE(writePng(png, kImageSize, kImageSize, *rgba).ok());
    }
    // Close up, no macro face is coarse: the layout is the single faces' one.
    PlanView close = view;
    close.pixelsPerUnit *= 400.0f;
    ASSERT_TRUE(preparePlanFrame(ctx, pass, buffers, planned, DrawPath::CpuGrid, close, adaptive).ok());
    EXPECT_TRUE(buffers.gridLayout.factors.macroResolution.empty());
    destroyPlanBuffers(ctx, buffers);
    destroyOffscreenTarget(ctx, *target);
}

TEST_F(MacroFixture, HiddenMembersAndCullingKeepFacesDrawn) {
    const Cage cage = test::makeSubdividedCube(8);
    PlanDatabase db;
    PlannedCage planned = test::planCage(cage, db);
    PlanBuffers buffers = upload(planned);
    const MacroGrid& macros = buffers.data.macros;
    ASSERT_EQ(macros.faces.size(), 6u);  // one per side of the cube (test_macro_faces.cpp)
    // A hidden member keeps its macro face single; the other sides stay coarse.
    const uint32_t hidden = macros.cellDrawn[macros.faces[2].firstCell + 9];
    const std::vector<uint32_t> blocked{hidden};
    GridFactors factors = uniformGridFactors(buffers.data, 1);
    chooseMacroPieces(buffers.data, factors, buffers.pointPositionsHost, nullptr, 4, blocked);
    ASSERT_EQ(factors.macroResolution.size(), 12u);
    for (uint32_t m = 0; m < 6; ++m) {
        if (m == 2) EXPECT_EQ(macroColumns(factors, m), 0u);
        else EXPECT_GT(macroColumns(factors, m), 0u);
    }
    ASSERT_TRUE(prepareGrid(ctx, pass, buffers, factors).ok());
    evaluateGridOnCpu(planned, buffers);
    expectClosed(buffers.gridLayout, {}, "cube, one side single");
    // Culling: a coarse macro face's triangles go only when all its members are culled.
    const MacroGridFace& side = macros.faces[0];
    std::vector<uint32_t> someCulled, allCulled;
    for (uint32_t c = side.firstCell; c < side.firstCell + side.width * side.height; ++c) {
        allCulled.push_back(macros.cellDrawn[c]);
        if (macros.cellDrawn[c] != side.head && c % 2) someCulled.push_back(macros.cellDrawn[c]);
    }
    someCulled.push_back(side.head);
    std::sort(someCulled.begin(), someCulled.end());
    std::sort(allCulled.begin(), allCulled.end());
    const std::vector<uint32_t> partly = culledForDrawing(macros, buffers.gridLayout.factors, someCulled);
    EXPECT_FALSE(std::binary_search(partly.begin(), partly.end(), side.head)) << "the head draws its visible members";
    const std::vector<uint32_t> whole = culledForDrawing(macros, buffers.gridLayout.factors, allCulled);
    EXPECT_TRUE(std::binary_search(whole.begin(), whole.end(), side.head));
    destroyPlanBuffers(ctx, buffers);
}

// A camera move that changes only the macro faces (which are drawn as one, their spans' pieces)
// keeps every evaluated slot and writes the triangles again: the same as laying out anew.
TEST_F(MacroFixture, AChangeOfMacroFacesAloneRewritesOnlyTheTriangles) {
    const Cage cage = test::makeTorus(48, 40);
    PlanDatabase db;
    PlannedCage planned = test::planCage(cage, db);
    PlanBuffers buffers = upload(planned);
    auto minified = [&](uint32_t minify) {
        GridFactors factors = uniformGridFactors(buffers.data, 1);
        chooseMacroPieces(buffers.data, factors, buffers.pointPositionsHost, nullptr, minify, buffers.holeDrawn);
        return factors;
    };
    ASSERT_TRUE(prepareGrid(ctx, pass, buffers, minified(4)).ok());
    evaluateGridOnCpu(planned, buffers);
    const GridVertex* grid = static_cast<const GridVertex*>(buffers.grid.data);
    const std::vector<GridVertex> before(grid, grid + buffers.gridLayout.slotCount());
    const size_t trianglesBefore = buffers.gridLayout.indices.size() / 3;
    const GridFactors farther = minified(16);
    Result<bool> kept = relayoutGridKeepingSlots(ctx, pass, buffers, planned, farther);
    ASSERT_TRUE(kept.ok()) << kept.error().message;
    EXPECT_TRUE(*kept);
    EXPECT_EQ(buffers.gridEvaluator, GridEvaluator::Cpu);
    EXPECT_EQ(std::memcmp(before.data(), buffers.grid.data, before.size() * sizeof(GridVertex)), 0);
    EXPECT_EQ(buffers.gridLayout.indices, buildGridLayout(buffers.data, farther).indices);
    EXPECT_LT(buffers.gridLayout.indices.size() / 3, trianglesBefore);
    expectClosed(buffers.gridLayout, {}, "torus, 1/16 after 1/4");
    destroyPlanBuffers(ctx, buffers);
}

// While the view stays, a frame after a vertex drag chooses adaptive factors only around the
// moved vertices: the same factors as a full pass from the layout's.
TEST_F(MacroFixture, AdaptiveFactorsAfterADragEqualAFullPass) {
    const Cage cage = makeBenchmarkCage(2000, 4);
    PlanDatabase db;
    PlannedCage planned = test::planCage(cage, db);
    PlanBuffers buffers = upload(planned);
    const PlanView view = test::framedPlanView(cage, kImageSize);
    const TessellationSettings adaptive{0, 3.0f};
    ASSERT_TRUE(preparePlanFrame(ctx, pass, buffers, planned, DrawPath::CpuGrid, view, adaptive).ok());
    const float diagonal = computeBounds(cage).diagonal();
    for (uint32_t round = 0; round < 3; ++round) {
        // A few vertices pulled far toward the camera's side, so their edges want other factors.
        std::vector<uint32_t> moved{7 + 50 * round, 400 + 31 * round, 900 + 3 * round};
        std::sort(moved.begin(), moved.end());
        std::vector<glm::vec3> to;
        for (uint32_t v : moved) to.push_back(planned.cage().positions[v] * (1.0f + 0.15f * diagonal));
        ASSERT_TRUE(planned.moveVertices(moved, to).ok());
        ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) { recordMovedVertices(cmd, pass, buffers, planned, moved); }).ok());
        const GridFactors before = buffers.gridLayout.factors;
        const GridFactors full = adaptiveGridFactors(buffers.data, buffers.pointPositionsHost,
                                                     AdaptiveView{view.viewProjection, view.pixelsPerUnit, adaptive.pixelsPerSegment},
                                                     &before);
        ASSERT_FALSE(buffers.movedSinceFactors.empty()) << "the drag is remembered for the next frame";
        ASSERT_TRUE(preparePlanFrame(ctx, pass, buffers, planned, DrawPath::CpuGrid, view, adaptive).ok());
        EXPECT_EQ(buffers.gridLayout.factors.segmentPieces, full.segmentPieces) << "round " << round;
        EXPECT_EQ(buffers.gridLayout.factors.subfaceFactor, full.subfaceFactor) << "round " << round;
        EXPECT_NE(buffers.gridLayout.factors.segmentPieces, before.segmentPieces) << "the drag changed some factors";
        EXPECT_TRUE(buffers.movedSinceFactors.empty());
    }
    destroyPlanBuffers(ctx, buffers);
}

// Progressive refinement (PlanView::keepFactors): the first moving frame chooses factors and
// macro faces for its own (coarsened) view, later moving frames keep that layout whatever the
// camera does, and the first still frame chooses again for its view: equal to a fresh choice.
TEST_F(MacroFixture, MovingFramesKeepTheFactorsOfTheirFirstFrame) {
    const Cage cage = test::makeTorus(48, 40);
    PlanDatabase db;
    PlannedCage planned = test::planCage(cage, db);
    PlanBuffers buffers = upload(planned);
    const TessellationSettings adaptive{0, 3.0f};
    auto prepare = [&](PlanView view) {
        EXPECT_TRUE(preparePlanFrame(ctx, pass, buffers, planned, DrawPath::CpuGrid, view, adaptive).ok());
        return buffers.gridLayout.factors;
    };
    PlanView still = test::framedPlanView(cage, kImageSize);
    const GridFactors full = prepare(still);

    PlanView moving = still;
    moving.keepFactors = true;
    moving.pixelsPerUnit = still.pixelsPerUnit / 4.0f;  // as the editor coarsens
    const GridFactors coarse = prepare(moving);
    EXPECT_NE(coarse.segmentPieces, full.segmentPieces) << "the first moving frame chose for its coarser view";
    const size_t trianglesCoarse = buffers.gridLayout.indices.size() / 3;

    // Zoomed in 3x and turned: the layout stays as it was.
    moving.viewProjection = glm::scale(glm::rotate(glm::mat4(1.0f), 0.4f, glm::vec3(0, 1, 0)), glm::vec3(3.0f)) *
                            still.viewProjection;
    moving.pixelsPerUnit = 3.0f * still.pixelsPerUnit / 4.0f;
    const GridFactors kept = prepare(moving);
    EXPECT_EQ(kept.segmentPieces, coarse.segmentPieces);
    EXPECT_EQ(kept.subfaceFactor, coarse.subfaceFactor);
    EXPECT_EQ(kept.macroSpanPieces, coarse.macroSpanPieces);
    EXPECT_EQ(buffers.gridLayout.indices.size() / 3, trianglesCoarse);
    expectClosed(buffers.gridLayout, {}, "torus, kept while moving");

    // Still again, in the zoomed view: what a fresh choice for it gives.
    PlanView settled = moving;
    settled.keepFactors = false;
    settled.pixelsPerUnit = 3.0f * still.pixelsPerUnit;
    const GridFactors refined = prepare(settled);
    PlanBuffers fresh = upload(planned);
    ASSERT_TRUE(preparePlanFrame(ctx, pass, fresh, planned, DrawPath::CpuGrid, settled, adaptive).ok());
    EXPECT_EQ(refined.segmentPieces, fresh.gridLayout.factors.segmentPieces);
    EXPECT_EQ(refined.subfaceFactor, fresh.gridLayout.factors.subfaceFactor);
    EXPECT_EQ(buffers.gridLayout.indices, fresh.gridLayout.indices);
    EXPECT_GT(buffers.gridLayout.indices.size() / 3, trianglesCoarse);
    destroyPlanBuffers(ctx, fresh);
    destroyPlanBuffers(ctx, buffers);
}

// A topology edit taken in place leaves the macro faces empty and stale: frames that cannot draw
// one (uniform factors) never build them, the first adaptive frame does, and then they, its
// factors and its triangle count are those of the edited cage uploaded afresh.
TEST_F(MacroFixture, TopologyEditsLeaveMacroFacesToTheFirstFrameThatDrawsThem) {
    const Cage cage = test::makeTorus(48, 40);
    PlanDatabase db;
    PlannedCage planned = test::planCage(cage, db);
    PlanBuffers buffers = upload(planned);
    ASSERT_FALSE(buffers.data.macros.faces.empty());
    const PlanView far = [&] {  // far enough for coarse macro faces
        PlanView view = test::framedPlanView(cage, kImageSize);
        view.pixelsPerUnit /= 8.0f;
        return view;
    }();
    const TessellationSettings uniform{2, 8.0f}, adaptive{0, 4.0f};
    ASSERT_TRUE(preparePlanFrame(ctx, pass, buffers, planned, DrawPath::CpuGrid, far, adaptive).ok());

    EditHistory history;
    Result<TopologyEdit> edit = extrudeFaces(planned.cage(), planned.topology(), std::vector<uint32_t>{100}, 0.2f);
    ASSERT_TRUE(edit.ok()) << edit.error().message;
    Result<EditReport> report = history.applyTopologyEdit(planned, "extrude", std::move(edit).value());
    ASSERT_TRUE(report.ok()) << report.error().message;
    std::vector<uint32_t> changed = report->updatedSubfaceList;
    for (uint32_t f : report->replannedFaceList)
        for (uint32_t s = planned.firstSubface(f); s < planned.firstSubface(f + 1); ++s) changed.push_back(s);
    Result<PlanTableUpdate> updated = updatePlanTables(ctx, pass, buffers, planned, changed, report->previousSubfaceOf);
    ASSERT_TRUE(updated.ok() && updated->applied);
    EXPECT_TRUE(buffers.data.macros.stale);
    EXPECT_TRUE(buffers.data.macros.faces.empty());

    ASSERT_TRUE(preparePlanFrame(ctx, pass, buffers, planned, DrawPath::CpuGrid, far, uniform).ok());
    EXPECT_TRUE(buffers.data.macros.stale) << "a uniform frame draws no macro face: nothing to build";
    ASSERT_TRUE(preparePlanFrame(ctx, pass, buffers, planned, DrawPath::CpuGrid, far, adaptive).ok());
    EXPECT_FALSE(buffers.data.macros.stale);

    PlanBuffers fresh = upload(planned);  // through the same frames (factors keep some of the last layout's)
    ASSERT_TRUE(preparePlanFrame(ctx, pass, fresh, planned, DrawPath::CpuGrid, far, uniform).ok());
    ASSERT_TRUE(preparePlanFrame(ctx, pass, fresh, planned, DrawPath::CpuGrid, far, adaptive).ok());
    EXPECT_EQ(buffers.data.macros.faces.size(), fresh.data.macros.faces.size());
    EXPECT_EQ(buffers.data.macros.cellDrawn, fresh.data.macros.cellDrawn);
    EXPECT_FALSE(fresh.gridLayout.factors.macroResolution.empty()) << "the view draws coarse macro faces";
    // The in-place layout keeps its slots (numbered otherwise than a fresh one's): the same
    // factors, macro faces and triangle count.
    EXPECT_EQ(buffers.gridLayout.factors, fresh.gridLayout.factors);
    EXPECT_EQ(buffers.gridLayout.indices.size(), fresh.gridLayout.indices.size());
    expectClosed(buffers.gridLayout, {}, "torus after an extrude");
    destroyPlanBuffers(ctx, fresh);
    destroyPlanBuffers(ctx, buffers);
}
