// Topology edits keep the sculpt (issue 19 part 3): displacement carried across edge loops,
// deleted faces, filled holes and extrudes (core/displacement/displacement_transfer.h,
// core/displacement/displaced_topology_edit.h).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>

#include "displacement/displaced_picker.h"
#include "displacement/displaced_topology_edit.h"
#include "mesh/topology_edits.h"
#include "sculpt_test_support.h"
#include "test_cages.h"

namespace qp {
namespace {

// A bump raised at the cage's point nearest to `where` (tall: 15% of the diagonal).
void raiseBump(test::Sculpt& s, const glm::vec3& where, float radius) {
    uint32_t nearest = 0;
    for (uint32_t i : s.sited())
        if (s.distance(i, where) < s.distance(nearest, where) || !s.samples->hasSite(nearest)) nearest = i;
    const glm::vec3 centre = s.samples->position(nearest);
    StrokeOptions options;
    options.brush = Brush{BrushKind::Raise, radius, 0.35f, Falloff::Smooth};
    for (int k = 0; k < 3; ++k) applyStroke(s.displacement, *s.samples, options, std::span(&centre, 1));
}

float largestD(const Displacement& d) {
    float m = 0.0f;
    for (float x : d.samples) m = std::max(m, std::abs(x));
    return m;
}

// One edit through the history as the editor and Python make it; returns the report.
EditReport perform(EditHistory& history, test::Sculpt& s, const TopologyEdit& edit, FollowingMove move = {}) {
    auto entry = makeDisplacedTopologyEdit(makeTopologyStep(*s.planned, edit), s.displacement, [](const DisplacementChange&) {},
                                           std::move(move));
    Result<EditReport> report = history.perform(*s.planned, "edit", std::move(entry));
    EXPECT_TRUE(report) << report.error().message;
    return report ? *report : EditReport{};
}

// Kept sub-faces: their own samples bit for bit, so D the same bits wherever it reads only them
// (a cell inside the tile's border cells), and everywhere (edges and corners included) on tiles
// whose whole padded block kept its values.
void expectKeptBitForBit(const DisplacementTransfer& transfer, const Displacement& old, const EditReport& report,
                         const PlannedCage& after) {
    std::vector<bool> updated(after.subfaceCount(), false);
    for (uint32_t s : report.updatedSubfaceList) updated[s] = true;
    const Displacement& next = transfer.displacement;
    uint32_t kept = 0, whole = 0;
    for (uint32_t s = 0; s < after.subfaceCount(); ++s) {
        const uint32_t from = report.previousSubfaceOf[s];
        if (from == kNewElement || updated[s]) continue;
        ++kept;
        const int n = int(next.layout.tiles[s].cells);
        ASSERT_EQ(uint32_t(n), old.layout.tiles[from].cells);
        bool blockKept = true;
        for (int j = -1; j <= n; ++j)
            for (int i = -1; i <= n; ++i) {
                const uint32_t a = std::bit_cast<uint32_t>(next.samples[next.layout.sampleAt(s, i, j)]);
                const uint32_t b = std::bit_cast<uint32_t>(old.samples[old.layout.sampleAt(from, i, j)]);
                if (i >= 0 && i < n && j >= 0 && j < n) {
                    ASSERT_EQ(a, b) << "sub-face " << s << " cell " << i << ", " << j;
                }
                blockKept &= a == b;
            }
        whole += blockKept;
        const float inner = 1.0f / float(n);
        for (uint32_t j = 0; j <= 16; ++j)
            for (uint32_t i = 0; i <= 16; ++i) {
                const float u = float(i) / 16.0f, v = float(j) / 16.0f;
                if (!blockKept && !(u >= inner && u <= 1.0f - inner && v >= inner && v <= 1.0f - inner)) continue;
                const DisplacementValue a = evaluateDisplacement(next, s, u, v);
                const DisplacementValue b = evaluateDisplacement(old, from, u, v);
                ASSERT_EQ(std::bit_cast<uint32_t>(a.value), std::bit_cast<uint32_t>(b.value))
                    << "sub-face " << s << " (was " << from << ") at " << u << ", " << v;
            }
    }
    EXPECT_EQ(kept, transfer.keptSubfaces);
    EXPECT_GT(kept, 0u);
    EXPECT_GT(whole, 0u);
}

// The resampling error on the changed sub-faces, at 9 x 9 points per sub-face that are not the
// samples themselves: |new D - old D| at the place where the point's normal line meets the old
// limit surface (found by ray casts refined by Newton), and how far the displaced surfaces lie
// apart there (the edit's own change of the limit surface plus that error).
struct TransferError {
    float value = 0.0f, surface = 0.0f;
};
TransferError transferError(const PlannedCage& before, const Displacement& old, const PlannedCage& after,
                            const Displacement& next, const EditReport& report) {
    std::vector<bool> updated(after.subfaceCount(), false);
    for (uint32_t s : report.updatedSubfaceList) updated[s] = true;
    const Displacement none;
    const DisplacedPicker picker(before, none);
    TransferError worst;
    for (uint32_t s = 0; s < after.subfaceCount(); ++s) {
        if ((report.previousSubfaceOf[s] != kNewElement && !updated[s]) || !after.hasSurface(s)) continue;
        for (uint32_t j = 0; j < 9; ++j)
            for (uint32_t i = 0; i < 9; ++i) {
                const float u = (float(i) + 0.37f) / 9.0f, v = (float(j) + 0.61f) / 9.0f;
                const LimitSample limit = after.evaluate(s, u, v);
                const glm::vec3 n = limitNormal(after, s, u, v, limit);
                DisplacedPicker::Hit nearest;
                for (float sign : {1.0f, -1.0f}) {
                    const DisplacedPicker::Hit hit = picker.intersect(before, none, Ray{limit.position, sign * n}, 0.5f);
                    if (hit.subface != kNoHit && hit.distance < nearest.distance) nearest = hit;
                }
                EXPECT_NE(nearest.subface, kNoHit);
                if (nearest.subface == kNoHit) continue;
                const float was = evaluateDisplacement(old, nearest.subface, nearest.u, nearest.v).value;
                const float now = evaluateDisplacement(next, s, u, v).value;
                worst.value = std::max(worst.value, std::abs(now - was));
                const glm::vec3 a = displacedSurfacePoint(after, next, s, u, v).position;
                const glm::vec3 b = displacedSurfacePoint(before, old, nearest.subface, nearest.u, nearest.v).position;
                worst.surface = std::max(worst.surface, glm::length(a - b));
            }
    }
    return worst;
}

TEST(DisplacementTransfer, AnEdgeLoopThroughABumpKeepsTheRestBitForBitAndTheBumpWhereItWas) {
    const Cage cage = test::makeSubdividedCube(4);
    test::Sculpt s(cage, 8);
    raiseBump(s, {0.1f, 0.2f, 1.2f}, 0.45f);
    const float height = largestD(s.displacement);
    ASSERT_GT(height, 0.2f);
    const Displacement old = s.displacement;
    const PlannedCage before = *s.planned;

    // An edge of the top face's grid near the bump: the loop runs around the cube through it.
    uint32_t a = 0, b = 0;
    for (uint32_t f = 0; f < cage.faceCount() && a == b; ++f) {
        const glm::vec3 p = cage.positions[cage.faceBegin(f)[0]], q = cage.positions[cage.faceBegin(f)[1]];
        if (p.z == 1.0f && q.z == 1.0f && std::abs(p.x - q.x) > 0.1f && p.y == 0.0f) a = cage.faceBegin(f)[0], b = cage.faceBegin(f)[1];
    }
    ASSERT_NE(a, b);
    Result<TopologyEdit> loop = insertEdgeLoop(s.planned->cage(), s.planned->topology(), a, b, 0.5f);
    ASSERT_TRUE(loop) << loop.error().message;
    EditHistory history;
    const EditReport report = perform(history, s, *loop);
    ASSERT_TRUE(report.topologyChanged);
    EXPECT_EQ(s.displacement.layout, buildDisplacementLayout(s.planned->cage(), s.planned->topology(), 8));

    const DisplacementTransfer transfer = transferDisplacement(before, old, *s.planned, report);
    EXPECT_EQ(transfer.displacement, s.displacement);  // the entry did exactly this
    expectKeptBitForBit(transfer, old, report, *s.planned);
    EXPECT_GT(transfer.projectedSamples, 0u);
    EXPECT_EQ(transfer.unreachedSamples, 0u);  // a closed surface barely moved: all found
    // The bump survives: its height within 3%, and D between the samples within 2% of the
    // bump's height of the old D at the same place (bilinear resampling at 8 samples per
    // sub-face). The displaced surfaces differ by the loop's own change of the limit surface.
    EXPECT_NEAR(largestD(s.displacement), height, 0.03f * height);
    const TransferError error = transferError(before, old, *s.planned, s.displacement, report);
    std::printf("edge loop: bump %.3f, kept %u / changed %u sub-faces, D within %.5f (%.2f%% of the bump), displaced "
                "surfaces within %.5f\n",
                height, transfer.keptSubfaces, transfer.changedSubfaces, error.value, 100.0f * error.value / height,
                error.surface);
    EXPECT_LT(error.value, 0.02f * height);

    // Undo gives the sculpt back bit for bit; redo the same transfer again.
    ASSERT_TRUE(history.undo(*s.planned));
    EXPECT_EQ(s.displacement, old);
    EXPECT_TRUE(s.planned->differencesFromRebuild().empty());
    ASSERT_TRUE(history.redo(*s.planned));
    EXPECT_EQ(s.displacement, transfer.displacement);
}

TEST(DisplacementTransfer, DeletingAndFillingFacesNextToASculptAcrossNonQuads) {
    const Cage cage = test::makeMixedGrid();
    test::Sculpt s(cage, 4);
    raiseBump(s, {1.5f, 1.5f, 0.5f}, 0.8f);
    const Displacement old = s.displacement;
    const PlannedCage before = *s.planned;

    // Delete a corner quad far from the bump: kept faces keep their bits, the changed ones near
    // the new boundary are projected.
    const uint32_t corner = 0;
    std::vector<uint32_t> cornerVertices(s.planned->cage().faceBegin(corner), s.planned->cage().faceBegin(corner) + 4);
    Result<TopologyEdit> removed = deleteFaces(s.planned->cage(), s.planned->topology(), std::span(&corner, 1), false);
    ASSERT_TRUE(removed) << removed.error().message;
    EditHistory history;
    const EditReport deleted = perform(history, s, *removed);
    const DisplacementTransfer transfer = transferDisplacement(before, old, *s.planned, deleted);
    expectKeptBitForBit(transfer, old, deleted, *s.planned);
    EXPECT_EQ(s.displacement, transfer.displacement);

    // Filling the hole again: the new face has no old surface in reach of most of its samples
    // (0 there), and undo brings both steps back exactly.
    const Displacement afterDelete = s.displacement;
    Result<TopologyEdit> filled = makeFace(s.planned->cage(), s.planned->topology(), cornerVertices);
    ASSERT_TRUE(filled) << filled.error().message;
    perform(history, s, *filled);
    EXPECT_EQ(s.displacement.layout.sampleCount, buildDisplacementLayout(s.planned->cage(), s.planned->topology(), 4).sampleCount);
    ASSERT_TRUE(history.undo(*s.planned));
    EXPECT_EQ(s.displacement, afterDelete);
    ASSERT_TRUE(history.undo(*s.planned));
    EXPECT_EQ(s.displacement, old);
}

TEST(DisplacementTransfer, AnExtrudedRegionTakesItsSculptAlong) {
    const Cage cage = test::makeSubdividedCube(3);
    test::Sculpt s(cage, 8);
    // The top face's centre quad carries the bump.
    uint32_t top = 0;
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        glm::vec3 c(0.0f);
        for (uint32_t i = 0; i < 4; ++i) c += cage.positions[cage.faceBegin(f)[i]] / 4.0f;
        if (std::abs(c.z - 1.0f) < 1e-5f && std::abs(c.x) < 1e-5f && std::abs(c.y) < 1e-5f) top = f;
    }
    raiseBump(s, {0.0f, 0.0f, 1.2f}, 0.3f);
    const float height = evaluateDisplacement(s.displacement, s.planned->firstSubface(top), 0.5f, 0.5f).value;
    ASSERT_GT(height, 0.1f);

    Result<SplitExtrude> split = splitExtrude(s.planned->cage(), s.planned->topology(), std::span(&top, 1), 0.8f);
    ASSERT_TRUE(split) << split.error().message;
    EditHistory history;
    perform(history, s, split->inPlace, split->move);
    // The face keeps its index; at its centre the sculpt moved out with it (the in-place
    // extrude changed the surface at the rim, hardly at the centre).
    const uint32_t subface = s.planned->firstSubface(top);
    EXPECT_NEAR(evaluateDisplacement(s.displacement, subface, 0.5f, 0.5f).value, height, 0.05f * height);
    const LimitSample centre = s.planned->evaluate(subface, 0.5f, 0.5f);
    EXPECT_GT(centre.position.z, 1.4f);  // moved out by the extrude
    ASSERT_TRUE(history.undo(*s.planned));
    EXPECT_TRUE(s.planned->differencesFromRebuild().empty());
}

}  // namespace
}  // namespace qp
