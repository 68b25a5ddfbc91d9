// Plans updated in place after tag and topology edits (render/plan_update.h): the grid, the
// control points and the tessellated picture equal those of the edited cage uploaded from
// scratch, bit for bit, on every path; what cannot be applied in place is refused with a reason and changes nothing; and
// a new pass for the same formats creates no pipeline (render/shared_pipelines.h).
#include <gtest/gtest.h>

#include <cstring>
#include <functional>

#include "camera.h"
#include "draw_path.h"
#include "edit/edit_history.h"
#include "mesh/obj_io.h"
#include "offscreen_target.h"
#include "plan_pass.h"
#include "plan_update.h"
#include "plans/planned_cage.h"
#include "render_test_support.h"
#include "shared_pipelines.h"
#include "test_cages.h"
#include "test_support.h"
#include "vk_commands.h"

using namespace qp;

namespace {

constexpr uint32_t kImageSize = 160;

// Control points of drawn sub-face d, wherever its range is.
std::vector<glm::vec4> controlPointsOf(const PlanBuffers& buffers, const PlannedCage& planned, uint32_t d) {
    const GpuSubface& s = buffers.data.subfaces[d];
    const uint32_t count = planned.database().plan(s.plan).stencilCountByLevel[std::min(buffers.controlPointLevel, kMaxPlanDepth)];
    const auto* cp = static_cast<const glm::vec4*>(buffers.controlPoints.data) + s.cpOffset;
    return std::vector<glm::vec4>(cp, cp + count);
}

struct PlanUpdateTest : ::testing::Test {
    VulkanContext ctx;
    PlanPass pass, freshPass;
    OffscreenTarget target;

    void SetUp() override {
        Result<VulkanContext> created = test::createTestContext();
        ASSERT_TRUE(created.ok()) << created.error().message;
        ctx = std::move(created).value();
        for (PlanPass* p : {&pass, &freshPass}) {
            Result<PlanPass> made = createPlanPass(ctx, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM);
            ASSERT_TRUE(made.ok()) << made.error().message;
            *p = *made;
        }
        Result<OffscreenTarget> t = createOffscreenTarget(ctx, kImageSize, kImageSize, VK_FORMAT_R8G8B8A8_UNORM);
        ASSERT_TRUE(t.ok()) << t.error().message;
        target = *t;
    }
    void TearDown() override {
        if (!ctx.device) return;
        destroyOffscreenTarget(ctx, target);
        destroyPlanPass(ctx, pass);
        destroyPlanPass(ctx, freshPass);
        destroyContext(ctx);
        EXPECT_EQ(validationMessageCount(ctx), 0u) << test::describeMessages(ctx);
    }

    // The CPU grid path evaluates on the host, as the plans scheme draws it (hostEvaluation).
    PlanBuffers upload(PlanPass& p, const PlannedCage& planned, bool hostEvaluation = false) {
        Result<PlanBuffers> buffers = uploadPlans(ctx, planned, MacroChoice::Auto, hostEvaluation);
        EXPECT_TRUE(buffers.ok()) << buffers.error().message;
        EXPECT_TRUE(bindPlanBuffers(ctx, p, *buffers).ok());
        return std::move(buffers).value();
    }

    PlanView frame(const PlannedCage& planned) const {
        return test::framedPlanView(planned.cage(), kImageSize);
    }

    // One frame of `path` (grid prepared and, where not cached, evaluated), its pixels.
    std::vector<uint8_t> draw(PlanPass& p, PlanBuffers& buffers, const PlannedCage& planned, DrawPath path,
                              const TessellationSettings& settings, const std::vector<uint32_t>* refresh = nullptr) {
        const PlanView view = frame(planned);
        EXPECT_TRUE(preparePlanFrame(ctx, p, buffers, planned, path, view, settings).ok());
        EXPECT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) {
            if (refresh) recordSubfaceRefresh(cmd, p, buffers, planned, *refresh);
            recordPlanFrame(cmd, p, buffers, path, renderTarget(target), view, settings);
        }).ok());
        Result<std::vector<uint8_t>> read = readPixels(ctx, target);
        EXPECT_TRUE(read.ok());
        return read ? *read : std::vector<uint8_t>{};
    }

    // The frame after an update in place (drawing `refresh`) against the cage uploaded again:
    // the same pixels, records, grid and control points.
    void expectSameAsAFreshUpload(PlanBuffers& buffers, const PlannedCage& planned, DrawPath path,
                                  const TessellationSettings& settings, const std::vector<uint32_t>& refresh) {
        const std::vector<uint8_t> inPlace = draw(pass, buffers, planned, path, settings, &refresh);
        PlanBuffers fresh = upload(freshPass, planned, buffers.data.hostEvaluation);
        if (buffers.data.hostEvaluation) {
            EXPECT_LE(buffers.controlPoints.size, 16u) << "host evaluation keeps no device control points, edits included";
        }
        const std::vector<uint8_t> rebuilt = draw(freshPass, fresh, planned, path, settings);
        EXPECT_TRUE(inPlace == rebuilt) << "the picture differs from the edited cage uploaded again";
        ASSERT_EQ(buffers.data.subfaces.size(), fresh.data.subfaces.size());
        for (uint32_t d = 0; d < fresh.data.subfaces.size(); ++d) {
            ASSERT_EQ(buffers.data.subfaces[d].plan, fresh.data.subfaces[d].plan) << "drawn sub-face " << d;
            ASSERT_EQ(buffers.data.subfaces[d].rotation, fresh.data.subfaces[d].rotation) << "drawn sub-face " << d;
        }
        EXPECT_EQ(buffers.holeDrawn, fresh.holeDrawn) << "the holes a draw leaves out";
        EXPECT_EQ(buffers.data.vertexSubfaceOffsets, fresh.data.vertexSubfaceOffsets) << "ring users (what a move refreshes)";
        EXPECT_EQ(buffers.data.vertexSubfaces, fresh.data.vertexSubfaces) << "ring users (what a move refreshes)";
        if (path != DrawPath::Tessellated) {
            ASSERT_EQ(buffers.gridLayout.slotCount(), fresh.gridLayout.slotCount());
            EXPECT_EQ(std::memcmp(buffers.grid.data, fresh.grid.data, fresh.gridLayout.slotCount() * sizeof(GridVertex)), 0)
                << "the grid updated in place differs from a full evaluation";
            // The layout carried through the edit (grid_relayout.h) is the one laid out whole.
            const GridLayout &carried = buffers.gridLayout, &whole = fresh.gridLayout;
            EXPECT_EQ(carried.factors, whole.factors);
            EXPECT_EQ(carried.subfaceOffset, whole.subfaceOffset);
            EXPECT_EQ(carried.source, whole.source) << "copy sources";
            EXPECT_EQ(carried.slotSubface, whole.slotSubface);
            EXPECT_EQ(carried.indices, whole.indices);
            EXPECT_EQ(carried.dependentOffsets, whole.dependentOffsets);
            EXPECT_EQ(carried.dependents, whole.dependents);
        }
        if (path != DrawPath::CpuGrid && buffers.controlPointLevel == fresh.controlPointLevel) {
            for (uint32_t d = 0; d < fresh.data.subfaces.size(); ++d)
                ASSERT_TRUE(controlPointsOf(buffers, planned, d) == controlPointsOf(fresh, planned, d))
                    << "control points of drawn sub-face " << d;
        }
        destroyPlanBuffers(ctx, fresh);
    }
};

std::vector<uint32_t> subfacesOf(const PlannedCage& planned, const EditReport& report) {
    std::vector<uint32_t> out = report.updatedSubfaceList;
    for (uint32_t f : report.replannedFaceList)
        for (uint32_t s = planned.firstSubface(f); s < planned.firstSubface(f + 1); ++s) out.push_back(s);
    return out;
}

std::vector<std::pair<std::string, Cage>> cages() {
    std::vector<std::pair<std::string, Cage>> out = {{"subdivided cube", test::makeSubdividedCube()},
                                                     {"mixed grid", test::makeMixedGrid()}};
    if (test::haveSharedShapes())
        for (const char* name : {"catmark_car", "catmark_pole8"}) {
            Result<Cage> cage = loadObj((test::sharedShapesDir() / (std::string(name) + ".obj")).string());
            if (cage) out.push_back({name, std::move(cage).value()});
        }
    return out;
}

}  // namespace

TEST_F(PlanUpdateTest, TagEditsInPlaceEqualAFreshUploadOnEveryPath) {
    for (auto& [name, cage] : cages()) {
        for (DrawPath path : {DrawPath::Grid, DrawPath::CpuGrid, DrawPath::Tessellated}) {
            const std::string what = name + (path == DrawPath::Grid ? ", grid" : path == DrawPath::CpuGrid ? ", cpu grid" : ", tess");
            SCOPED_TRACE(what);
            PlanDatabase db;
            Result<PlannedCage> created = PlannedCage::create(cage, db, {}, name);
            ASSERT_TRUE(created.ok()) << created.error().message;
            PlannedCage planned = std::move(created).value();
            PlanBuffers buffers = upload(pass, planned, path == DrawPath::CpuGrid);
            const TessellationSettings settings{8, 8.0f};
            (void)draw(pass, buffers, planned, path, settings);  // caches control points and the grid

            // A semi-sharp crease, then infinitely sharp (more stencils: ranges move), a corner,
            // the crease cleared, the crease method: new plans, relocations, garbage.
            const Topology& topology = planned.topology();
            const uint32_t e = topology.edgeCount() / 3;
            const uint32_t a = topology.edgeVertices[2 * e], b = topology.edgeVertices[2 * e + 1];
            const uint32_t corner = planned.cage().vertexCount() / 2;
            // Holes: a face in the middle and the last but one (an n-gon on the mixed grid), made
            // and filled again: they stay in the tables, hidden, so only their records change.
            const uint32_t middle = planned.cage().faceCount() / 2, late = planned.cage().faceCount() - 2;
            std::vector<std::function<Result<EditReport>()>> edits = {
                [&] { return planned.setEdgeSharpness(a, b, 2.5f); },
                [&] { return planned.setEdgeSharpness(a, b, kInfiniteSharpness); },
                [&] { return planned.setVertexSharpness(corner, 3.0f); },
                [&] { return planned.setHole(middle, true); },
                [&] { return planned.setHole(late, true); },
                [&] { return planned.setEdgeSharpness(a, b, 0.0f); },
                [&] { return planned.setHole(middle, false); },
                [&] { return planned.setHole(late, false); },
                [&] { return planned.setCreaseMethod(CreaseMethod::Chaikin); },
            };
            for (size_t k = 0; k < edits.size(); ++k) {
                SCOPED_TRACE("edit " + std::to_string(k));
                Result<EditReport> report = edits[k]();
                ASSERT_TRUE(report.ok()) << report.error().message;
                Result<PlanTableUpdate> updated = updatePlanTables(ctx, pass, buffers, planned, subfacesOf(planned, *report));
                ASSERT_TRUE(updated.ok()) << updated.error().message;
                ASSERT_TRUE(updated->applied) << updated->reason;
                if (k < 8 && buffers.data.subfaces.size() > 100) {
                    EXPECT_LT(updated->refresh.size(), buffers.data.subfaces.size() / 10) << "refreshed more than the edit touched";
                }
                const bool holeEdit = k == 3 || k == 4 || k == 6 || k == 7;
                if (holeEdit) {
                    const uint32_t face = k == 3 || k == 6 ? middle : late;
                    const uint32_t subfaces = planned.firstSubface(face + 1) - planned.firstSubface(face);
                    EXPECT_EQ(updated->rewrittenSubfaces, subfaces) << "a hole edit rewrote other sub-faces' records";
                    EXPECT_FALSE(updated->gridDropped);
                    const uint32_t drawn = buffers.drawnOfSubface[planned.firstSubface(face)];
                    bool covered = false;
                    for (const DrawnRun& run : drawnRuns(buffers, {})) covered |= run.begin <= drawn && drawn < run.end;
                    EXPECT_EQ(covered, !planned.cage().isHole(face)) << "a hole is drawn, or a filled one is not";
                }
                expectSameAsAFreshUpload(buffers, planned, path, settings, updated->refresh);
            }
            destroyPlanBuffers(ctx, buffers);
        }
    }
}

// Extrudes, a delete that renumbers vertices, and their undo and redo: the sub-face tables are
// packed again, kept sub-faces keep their control points and grid vertices, and the frame after
// evaluates only what the edit touched.
TEST_F(PlanUpdateTest, TopologyEditsInPlaceEqualAFreshUploadOnEveryPath) {
    for (auto& [name, cage] : cages()) {
        for (DrawPath path : {DrawPath::Grid, DrawPath::CpuGrid, DrawPath::Tessellated}) {
            const std::string what = name + (path == DrawPath::Grid ? ", grid" : path == DrawPath::CpuGrid ? ", cpu grid" : ", tess");
            SCOPED_TRACE(what);
            PlanDatabase db;
            Result<PlannedCage> created = PlannedCage::create(cage, db, {}, name);
            ASSERT_TRUE(created.ok()) << created.error().message;
            PlannedCage planned = std::move(created).value();
            PlanBuffers buffers = upload(pass, planned, path == DrawPath::CpuGrid);
            const TessellationSettings settings{8, 8.0f};
            (void)draw(pass, buffers, planned, path, settings);
            EditHistory history;
            const uint32_t middle = planned.cage().faceCount() / 2, late = planned.cage().faceCount() - 2;
            auto extrude = [&](uint32_t face, float distance) {
                Result<TopologyEdit> edit = extrudeFaces(planned.cage(), planned.topology(), std::vector<uint32_t>{face}, distance);
                if (!edit) return Result<EditReport>(edit.error());
                return history.applyTopologyEdit(planned, "extrude", std::move(edit).value());
            };
            std::vector<std::pair<std::string, std::function<Result<EditReport>()>>> edits = {
                {"extrude the middle face", [&] { return extrude(middle, 0.3f); }},
                {"extrude another", [&] { return extrude(late, 0.2f); }},
                {"undo", [&] { return history.undo(planned); }},
                {"redo", [&] { return history.redo(planned); }},
                {"delete a face and its vertices", [&] {
                     Result<TopologyEdit> edit = deleteFaces(planned.cage(), planned.topology(), std::vector<uint32_t>{1}, true);
                     if (!edit) return Result<EditReport>(edit.error());
                     return history.applyTopologyEdit(planned, "delete", std::move(edit).value());
                 }},
                {"undo the delete", [&] { return history.undo(planned); }},
                {"undo both extrudes", [&] {  // two edits before one frame: their reports add up
                     Result<EditReport> first = history.undo(planned);
                     if (!first) return first;
                     Result<EditReport> second = history.undo(planned);
                     if (!second) return second;
                     EditReport total = *first;
                     accumulateReport(total, *second);
                     return Result<EditReport>(total);
                 }},
            };
            for (auto& [label, edit] : edits) {
                SCOPED_TRACE(label);
                Result<EditReport> report = edit();
                ASSERT_TRUE(report.ok()) << report.error().message;
                ASSERT_TRUE(report->topologyChanged);
                Result<PlanTableUpdate> updated =
                    updatePlanTables(ctx, pass, buffers, planned, subfacesOf(planned, *report), report->previousSubfaceOf);
                ASSERT_TRUE(updated.ok()) << updated.error().message;
                ASSERT_TRUE(updated->applied) << updated->reason;
                if (buffers.data.subfaces.size() > 100) {
                    EXPECT_LT(updated->refresh.size(), buffers.data.subfaces.size() / 4) << "refreshed more than the edit touched";
                }
                if (path != DrawPath::Tessellated) {
                    EXPECT_FALSE(updated->gridDropped) << "uniform factors: the grid keeps what was there";
                }
                expectSameAsAFreshUpload(buffers, planned, path, settings, updated->refresh);
            }
            EXPECT_EQ(planned.cage().faceVertices, cage.faceVertices) << "undoing everything gives the cage back";
            destroyPlanBuffers(ctx, buffers);
        }
    }
}

TEST_F(PlanUpdateTest, ChangesItCannotApplyAreRefusedAndChangeNothing) {
    PlanDatabase db;
    Result<PlannedCage> created = PlannedCage::create(test::makeSubdividedCube(), db, {}, "cube");
    ASSERT_TRUE(created.ok());
    PlannedCage planned = std::move(created).value();
    PlanBuffers buffers = upload(pass, planned);
    const GpuPlanData before = buffers.data;
    // A topology edit renumbers the sub-faces: without the renumbering, only a new upload can
    // follow it.
    Result<EditReport> removed = planned.removeFace(0);
    ASSERT_TRUE(removed.ok());
    Result<PlanTableUpdate> updated = updatePlanTables(ctx, pass, buffers, planned, subfacesOf(planned, *removed));
    ASSERT_TRUE(updated.ok());
    EXPECT_FALSE(updated->applied);
    EXPECT_NE(updated->reason.find("renumbered"), std::string::npos) << updated->reason;
    EXPECT_EQ(buffers.data.plans.size(), before.plans.size());
    EXPECT_EQ(std::memcmp(buffers.data.subfaces.data(), before.subfaces.data(), before.subfaces.size() * sizeof(GpuSubface)), 0);
    destroyPlanBuffers(ctx, buffers);
}

TEST_F(PlanUpdateTest, ANewPassForTheSameFormatsCreatesNoPipeline) {
    const uint64_t created = sharedObjectsCreated(ctx);
    EXPECT_GE(created, 1u);  // the fixture's passes
    for (int i = 0; i < 3; ++i) {
        Result<PlanPass> another = createPlanPass(ctx, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM);
        ASSERT_TRUE(another.ok());
        EXPECT_EQ(another->tessellated, pass.tessellated);
        EXPECT_NE(another->set, pass.set);  // the descriptor set is the pass's own
        destroyPlanPass(ctx, *another);
    }
    EXPECT_EQ(sharedObjectsCreated(ctx), created);
    Result<PlanPass> srgb = createPlanPass(ctx, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_SRGB);
    ASSERT_TRUE(srgb.ok());
    EXPECT_EQ(sharedObjectsCreated(ctx), created + 1);  // another format: its own pipelines
    destroyPlanPass(ctx, *srgb);
}
