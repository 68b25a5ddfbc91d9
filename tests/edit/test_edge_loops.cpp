// Edge loops, edge rings and face loops (core/edit/edge_loops.h) on grids and a subdivided cube.
#include <gtest/gtest.h>

#include "edit/edge_loops.h"
#include "test_cages.h"

namespace {

using qp::EdgeKey;
using qp::makeEdgeKey;

// Vertex (x, y) of test::makeGrid(4): 5 per row.
uint32_t at(uint32_t x, uint32_t y) { return y * 5 + x; }

std::vector<EdgeKey> keys(std::initializer_list<std::pair<uint32_t, uint32_t>> pairs) {
    std::vector<EdgeKey> out;
    for (auto [a, b] : pairs) out.push_back(makeEdgeKey(a, b));
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

TEST(EdgeLoops, LoopRunsThroughRegularVerticesAndStopsAtTheBoundary) {
    const qp::Cage grid = qp::test::makeGrid(4);
    const qp::Topology t = qp::buildTopology(grid);
    // An interior row: from the left boundary to the right one.
    EXPECT_EQ(qp::edgeLoop(grid, t, makeEdgeKey(at(1, 2), at(2, 2))),
              keys({{at(0, 2), at(1, 2)}, {at(1, 2), at(2, 2)}, {at(2, 2), at(3, 2)}, {at(3, 2), at(4, 2)}}));
    // A boundary edge follows the boundary through its valence-3 vertices, stopping at the corners.
    EXPECT_EQ(qp::edgeLoop(grid, t, makeEdgeKey(at(1, 0), at(2, 0))),
              keys({{at(0, 0), at(1, 0)}, {at(1, 0), at(2, 0)}, {at(2, 0), at(3, 0)}, {at(3, 0), at(4, 0)}}));
    EXPECT_TRUE(qp::edgeLoop(grid, t, makeEdgeKey(at(0, 0), at(2, 2))).empty());  // no such edge
}

TEST(EdgeLoops, LoopClosesAroundACubeAndStopsAtPoles) {
    const qp::Cage cube = qp::test::makeSubdividedCube(3);
    const qp::Topology t = qp::buildTopology(cube);
    // Find an edge between two regular vertices in a face's middle: both ends valence 4.
    uint32_t middle = UINT32_MAX, poleEdge = UINT32_MAX;
    for (uint32_t e = 0; e < t.edgeCount(); ++e) {
        const uint32_t a = t.edgeVertices[2 * e], b = t.edgeVertices[2 * e + 1];
        if (t.vertexEdgeCount(a) == 4 && t.vertexEdgeCount(b) == 4 && middle == UINT32_MAX) middle = e;
        if ((t.vertexEdgeCount(a) == 3) != (t.vertexEdgeCount(b) == 3) && poleEdge == UINT32_MAX) poleEdge = e;
    }
    ASSERT_NE(middle, UINT32_MAX);
    ASSERT_NE(poleEdge, UINT32_MAX);
    const auto key = [&](uint32_t e) { return makeEdgeKey(t.edgeVertices[2 * e], t.edgeVertices[2 * e + 1]); };
    // Every loop of a 3x3-split cube either closes around it (12 edges) or runs between two
    // corners (3 edges along a cube edge).
    const size_t loop = qp::edgeLoop(cube, t, key(middle)).size();
    EXPECT_TRUE(loop == 12 || loop == 3) << loop;
    EXPECT_EQ(qp::edgeLoop(cube, t, key(poleEdge)).size(), 3u);  // corner to corner along the cube's edge
}

TEST(EdgeLoops, RingCrossesQuadsAndFaceLoopIsItsStrip) {
    const qp::Cage grid = qp::test::makeGrid(4);
    const qp::Topology t = qp::buildTopology(grid);
    const EdgeKey edge = makeEdgeKey(at(1, 2), at(2, 2));
    EXPECT_EQ(qp::edgeRing(grid, t, edge), keys({{at(1, 0), at(2, 0)},
                                                 {at(1, 1), at(2, 1)},
                                                 {at(1, 2), at(2, 2)},
                                                 {at(1, 3), at(2, 3)},
                                                 {at(1, 4), at(2, 4)}}));
    EXPECT_EQ(qp::faceLoop(grid, t, edge), (std::vector<uint32_t>{1, 5, 9, 13}));

    const qp::Cage cube = qp::test::makeSubdividedCube(3);
    const qp::Topology ct = qp::buildTopology(cube);
    const EdgeKey any = makeEdgeKey(ct.edgeVertices[0], ct.edgeVertices[1]);
    EXPECT_EQ(qp::edgeRing(cube, ct, any).size(), 12u);  // closes around the cube
    EXPECT_EQ(qp::faceLoop(cube, ct, any).size(), 12u);
}

TEST(EdgeLoops, RingStopsAtNonQuads) {
    const qp::Cage mixed = qp::test::makeMixedGrid();
    const qp::Topology t = qp::buildTopology(mixed);
    // Column x = 1 of the 4x4 grid passes the replaced quad (1, 1): the ring from its bottom
    // edge stops there, so it has the two edges below the triangle/pentagon pair.
    const std::vector<EdgeKey> ring = qp::edgeRing(mixed, t, makeEdgeKey(at(1, 0), at(2, 0)));
    EXPECT_EQ(ring, keys({{at(1, 0), at(2, 0)}, {at(1, 1), at(2, 1)}}));
    EXPECT_EQ(qp::faceLoop(mixed, t, makeEdgeKey(at(1, 0), at(2, 0))), (std::vector<uint32_t>{1}));
}
