// The edited cage's extent (editor/app/cage_extent.h) carried through drag steps equals the
// extent measured over the whole cage, with moved vertices inside the box, on it and pairs of
// neighbours; the document records each drag step and drops it after any other change.
#include <gtest/gtest.h>

#include <random>

#include "cage_extent.h"
#include "document.h"
#include "mesh/topology.h"
#include "test_cages.h"

using namespace qp;
using namespace qp::editor;

namespace {

void expectSameExtent(const CageExtent& carried, const CageExtent& measured, const std::string& what) {
    EXPECT_EQ(carried.bounds.min, measured.bounds.min) << what;
    EXPECT_EQ(carried.bounds.max, measured.bounds.max) << what;
    EXPECT_EQ(carried.faceEdges, measured.faceEdges) << what;
    EXPECT_NEAR(carried.edgeLengthSum, measured.edgeLengthSum, 1e-9 * measured.edgeLengthSum) << what;
}

}  // namespace

TEST(CageExtent, DragStepsCarryItAsMeasuringTheWholeCageWould) {
    Cage cage = test::makeSubdividedCube(4);
    const Topology topology = buildTopology(cage);
    CageExtent extent = measureCage(cage);
    std::mt19937 random(5);
    std::uniform_int_distribution<uint32_t> vertex(0, cage.vertexCount() - 1);
    std::uniform_real_distribution<float> offset(-0.3f, 0.3f);
    for (int round = 0; round < 60; ++round) {
        PositionStep step;
        // One vertex, or a vertex and a neighbour (their shared edge counted once), or one on
        // the box's side pulled inwards (the box shrinks: measured again).
        const uint32_t v = vertex(random);
        step.vertices = {v};
        if (round % 3 == 1) {
            const uint32_t e = topology.vertexEdges[topology.vertexEdgeOffsets[v]];
            const uint32_t other = topology.edgeVertices[2 * e] == v ? topology.edgeVertices[2 * e + 1] : topology.edgeVertices[2 * e];
            step.vertices = {std::min(v, other), std::max(v, other)};
        }
        for (uint32_t u : step.vertices) step.before.push_back(cage.positions[u]);
        for (uint32_t u : step.vertices) {
            const glm::vec3 d(offset(random), offset(random), offset(random));
            cage.positions[u] = round % 3 == 2 ? 0.5f * cage.positions[u] : cage.positions[u] + d;
        }
        carryExtent(extent, cage, topology, step);
        expectSameExtent(extent, measureCage(cage), "after step " + std::to_string(round));
    }
}

TEST(CageExtent, TheDocumentRecordsDragStepsAndFollowsThem) {
    Result<std::unique_ptr<Document>> opened = createDocument(sceneOfCage(test::makeSubdividedCube(3), "cage"), "", PlanOptions{});
    ASSERT_TRUE(opened.ok()) << opened.error().message;
    Document& doc = **opened;
    expectSameExtent(cageExtent(doc), measureCage(doc.planned->cage()), "opened");
    const glm::vec3 start = doc.planned->cage().positions[5];
    for (int step = 0; step < 4; ++step) {
        const uint64_t before = doc.positionRevision;
        ASSERT_TRUE(applyEdit(doc, MoveVertices{{5, 5}, {start + glm::vec3(0.0f, 2.0f * float(step + 1), 0.0f), start}, step > 0}, 1)
                        .ok());
        EXPECT_EQ(doc.lastMove.from, before);
        EXPECT_EQ(doc.lastMove.vertices, std::vector<uint32_t>{5}) << "each vertex once";
        ASSERT_EQ(doc.lastMove.before.size(), 1u);
        expectSameExtent(cageExtent(doc), measureCage(doc.planned->cage()), "drag step " + std::to_string(step));
    }
    // Other changes of the positions drop the step: consumers compare positions again.
    ASSERT_TRUE(undoEdit(doc, 2).ok());
    EXPECT_EQ(doc.lastMove.from, PositionStep::kNone);
    expectSameExtent(cageExtent(doc), measureCage(doc.planned->cage()), "undone");
    // Tag edits, and their undo and redo, are steps of no vertex.
    const uint32_t* quad = doc.planned->cage().faceBegin(2);
    const std::vector<glm::vec3> positions = doc.planned->cage().positions;
    auto expectNoneMoved = [&](const std::string& what) {
        EXPECT_EQ(doc.lastMove.from, doc.positionRevision - 1) << what;
        EXPECT_TRUE(doc.lastMove.vertices.empty()) << what;
        EXPECT_EQ(doc.planned->cage().positions, positions) << what;
        expectSameExtent(cageExtent(doc), measureCage(doc.planned->cage()), what);
    };
    ASSERT_TRUE(applyEdit(doc, SetEdgeSharpness{{{std::min(quad[0], quad[1]), std::max(quad[0], quad[1]), 2.0f}}}, 3).ok());
    expectNoneMoved("crease");
    ASSERT_TRUE(applyEdit(doc, SetVertexSharpness{{{quad[2], 3.0f}}}, 4).ok());
    expectNoneMoved("corner");
    ASSERT_TRUE(undoEdit(doc, 5).ok());
    expectNoneMoved("corner undone");
    ASSERT_TRUE(redoEdit(doc, 6).ok());
    expectNoneMoved("corner redone");
    ASSERT_TRUE(jumpToHistory(doc, 1, 7).ok());
    expectNoneMoved("back to the crease");
    // A jump across a move is not one.
    ASSERT_TRUE(applyEdit(doc, MoveVertices{{5}, {start + glm::vec3(1.0f, 0.0f, 0.0f)}, false}, 8).ok());
    ASSERT_TRUE(jumpToHistory(doc, 0, 9).ok());
    EXPECT_EQ(doc.lastMove.from, PositionStep::kNone);
    expectSameExtent(cageExtent(doc), measureCage(doc.planned->cage()), "before the drag");
}
