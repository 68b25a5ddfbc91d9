// Topology edits on plain cages (core/mesh/topology_edits.h): shapes, orientation, tags, refusals.
#include <algorithm>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "mesh/topology.h"
#include "mesh/topology_edits.h"
#include "test_cages.h"

namespace {

using qp::Cage;
using qp::TopologyEdit;
using qp::test::makeCube;
using qp::test::makeGrid;

std::vector<uint32_t> faceOf(const Cage& cage, uint32_t f) {
    return {cage.faceBegin(f), cage.faceBegin(f) + cage.faceSize(f)};
}

qp::CageStats stats(const Cage& cage) { return qp::computeStats(cage, qp::buildTopology(cage)); }

// The edit succeeded, its cage is valid and consistently oriented (no edge used twice in the
// same direction unless the input already had such edges).
TopologyEdit expectGood(qp::Result<TopologyEdit> edit) {
    EXPECT_TRUE(edit.ok()) << (edit.ok() ? "" : edit.error().message);
    if (!edit.ok()) return {};
    EXPECT_TRUE(qp::validateCage(edit->cage, "edited").ok());
    EXPECT_EQ(edit->oldFaceOf.size(), edit->cage.faceCount());
    EXPECT_EQ(edit->oldVertexOf.size(), edit->cage.vertexCount());
    return std::move(edit).value();
}

void expectRefused(const qp::Result<TopologyEdit>& edit, const std::string& fragment) {
    ASSERT_FALSE(edit.ok());
    EXPECT_NE(edit.error().message.find(fragment), std::string::npos) << edit.error().message;
}

}  // namespace

TEST(ExtrudeFaces, InteriorFaceGetsFourSideQuadsAndMovesAlongItsNormal) {
    Cage grid = makeGrid(3);
    const uint32_t face = 4;  // the centre quad 5, 6, 10, 9
    TopologyEdit e = expectGood(qp::extrudeFaces(grid, qp::buildTopology(grid), {&face, 1}, 0.5f));
    EXPECT_EQ(e.cage.faceCount(), 13u);
    EXPECT_EQ(e.cage.vertexCount(), 20u);
    // The region face keeps its index and takes the copies 16..19 of 5, 6, 9, 10.
    EXPECT_EQ(faceOf(e.cage, 4), (std::vector<uint32_t>{16, 17, 19, 18}));
    EXPECT_EQ(e.changedFaces, (std::vector<uint32_t>{4, 9, 10, 11, 12}));
    EXPECT_TRUE(e.removedFaces.empty());
    // Side quad of edge 5->6: (5, 6, 6', 5').
    EXPECT_EQ(faceOf(e.cage, 9), (std::vector<uint32_t>{5, 6, 17, 16}));
    qp::CageStats s = stats(e.cage);
    EXPECT_EQ(s.nonManifoldEdges, 0u);
    EXPECT_EQ(s.boundaryEdges, 12u);
    EXPECT_EQ(e.resultFaces, (std::vector<uint32_t>{4}));
    EXPECT_EQ(e.resultVertices, (std::vector<uint32_t>{16, 17, 18, 19}));
    // All four moved by exactly the distance, the same way, away from the +z side of the grid.
    glm::vec3 offset = e.cage.positions[16] - grid.positions[5];
    EXPECT_NEAR(glm::length(offset), 0.5f, 1e-5f);
    EXPECT_GT(offset.z, 0.0f);
    for (uint32_t k = 0; k < 4; ++k) {
        uint32_t original[4] = {5, 6, 9, 10};
        glm::vec3 d = e.cage.positions[16 + k] - grid.positions[original[k]];
        EXPECT_NEAR(glm::length(d - offset), 0.0f, 1e-5f);
    }
    // The old vertices stay where they were.
    EXPECT_EQ(e.cage.positions[5], grid.positions[5]);
}

TEST(ExtrudeFaces, RegionsShareInteriorEdgesAndCageBoundaryEdgesGetWalls) {
    Cage grid = makeGrid(3);
    uint32_t region[2] = {3, 4};  // (0,1) and (1,1): share edge 5-9; face 3 touches the boundary
    TopologyEdit e = expectGood(qp::extrudeFaces(grid, qp::buildTopology(grid), region));
    EXPECT_EQ(e.cage.vertexCount(), 16u + 6u);
    EXPECT_EQ(e.cage.faceCount(), 9u + 6u);  // six region-boundary edges, one on the cage boundary
    EXPECT_EQ(stats(e.cage).nonManifoldEdges, 0u);
    // Copies of 4, 5, 6, 8, 9, 10 in order; a distance of 0 leaves them where they were.
    const uint32_t originals[6] = {4, 5, 6, 8, 9, 10};
    for (uint32_t k = 0; k < 6; ++k) EXPECT_EQ(e.cage.positions[16 + k], grid.positions[originals[k]]);
    EXPECT_EQ(faceOf(e.cage, 3), (std::vector<uint32_t>{16, 17, 20, 19}));
}

TEST(ExtrudeFaces, CubeTopKeepsItsRimCreaseAndCornerOnBothCopies) {
    Cage cube = makeCube();
    // Face 1 is the top (z = 1): 4, 5, 6, 7.
    cube.setEdgeSharpness(4, 5, 2.0f);
    cube.setEdgeSharpness(0, 1, 1.0f);  // far from the region: untouched
    cube.setVertexSharpness(6, 3.0f);
    cube.setHole(5, true);
    const uint32_t top = 1;
    TopologyEdit e = expectGood(qp::extrudeFaces(cube, qp::buildTopology(cube), {&top, 1}, 1.0f));
    EXPECT_EQ(e.cage.faceCount(), 10u);
    EXPECT_EQ(e.cage.vertexCount(), 12u);
    qp::CageStats s = stats(e.cage);
    EXPECT_EQ(s.boundaryEdges, 0u);
    EXPECT_EQ(s.nonManifoldEdges, 0u);
    EXPECT_EQ(e.cage.edgeSharpness(4, 5), 2.0f);   // base of the new wall
    EXPECT_EQ(e.cage.edgeSharpness(8, 9), 2.0f);   // the same edge on the moved top
    EXPECT_EQ(e.cage.edgeSharpness(0, 1), 1.0f);
    EXPECT_EQ(e.cage.creases.size(), 3u);
    EXPECT_EQ(e.cage.vertexSharpness(6), 3.0f);
    EXPECT_EQ(e.cage.vertexSharpness(10), 3.0f);
    EXPECT_EQ(e.cage.holes, (std::vector<uint32_t>{5}));
    EXPECT_NEAR(e.cage.positions[8].z, 2.0f, 1e-6f);
}

TEST(ExtrudeFaces, RefusesClosedSelectionsAndNonManifoldEdges) {
    Cage cube = makeCube();
    qp::Topology t = qp::buildTopology(cube);
    uint32_t all[6] = {0, 1, 2, 3, 4, 5};
    expectRefused(qp::extrudeFaces(cube, t, all), "closed surface");
    expectRefused(qp::extrudeFaces(cube, t, {}), "no faces");
    uint32_t missing = 6;
    expectRefused(qp::extrudeFaces(cube, t, {&missing, 1}), "face 7 does not exist");

    // Three faces on edge 0-1 (a fin): two of them selected.
    Cage fin = makeGrid(1);
    fin.positions.push_back({0, 0, 1});
    fin.positions.push_back({0, 0, -1});
    uint32_t a[3] = {1, 0, 4}, b[3] = {1, 0, 5};
    fin.addFace(a, 3);
    fin.addFace(b, 3);
    uint32_t two[2] = {0, 1};
    expectRefused(qp::extrudeFaces(fin, qp::buildTopology(fin), two), "non-manifold edge");
    // One of them alone is fine: the other two keep the edge.
    uint32_t one = 1;
    TopologyEdit e = expectGood(qp::extrudeFaces(fin, qp::buildTopology(fin), {&one, 1}));
    EXPECT_EQ(e.cage.faceCount(), 3u + 3u);
}

TEST(ExtrudeFaces, KeepsTextureCoordinatesParallel) {
    Cage grid = makeGrid(2);
    for (uint32_t v = 0; v < grid.vertexCount(); ++v) grid.uvs.push_back({grid.positions[v].x, grid.positions[v].y});
    grid.faceUVIndices = grid.faceVertices;
    const uint32_t face = 0;
    TopologyEdit e = expectGood(qp::extrudeFaces(grid, qp::buildTopology(grid), {&face, 1}));
    EXPECT_EQ(e.cage.faceUVIndices.size(), e.cage.faceVertices.size());
}

TEST(DeleteFaces, LeavesAHoleAndRenumbersTags) {
    Cage grid = makeGrid(3);
    grid.setHole(7, true);
    grid.setEdgeSharpness(5, 6, 1.5f);   // shared with face 1: stays
    const uint32_t face = 4;
    TopologyEdit e = expectGood(qp::deleteFaces(grid, qp::buildTopology(grid), {&face, 1}));
    EXPECT_EQ(e.cage.faceCount(), 8u);
    EXPECT_EQ(e.cage.vertexCount(), 16u);  // every vertex is still used
    EXPECT_EQ(e.cage.holes, (std::vector<uint32_t>{6}));
    EXPECT_EQ(e.cage.edgeSharpness(5, 6), 1.5f);
    EXPECT_EQ(stats(e.cage).boundaryEdges, 16u);
    EXPECT_EQ(e.removedFaces, (std::vector<uint32_t>{4}));
    EXPECT_TRUE(e.changedFaces.empty());
    EXPECT_EQ(e.oldFaceOf[4], 5u);
}

TEST(DeleteFaces, RemovesOnlyTheVerticesItLeftUnused) {
    Cage grid = makeGrid(3);
    grid.positions.push_back({9, 9, 9});  // already unused: stays
    grid.setEdgeSharpness(0, 1, 2.0f);    // only face 0 has this edge: dropped
    grid.setEdgeSharpness(5, 6, 1.0f);    // becomes 4-5 after vertex 0 goes
    grid.setVertexSharpness(0, 1.0f);     // on the removed vertex: dropped
    grid.setVertexSharpness(15, 2.0f);    // becomes vertex 14
    const uint32_t face = 0;
    TopologyEdit e = expectGood(qp::deleteFaces(grid, qp::buildTopology(grid), {&face, 1}, true));
    EXPECT_EQ(e.cage.vertexCount(), 16u);  // 17 - vertex 0
    EXPECT_EQ(e.oldVertexOf[0], 1u);
    EXPECT_EQ(e.oldVertexOf[15], 16u);
    ASSERT_EQ(e.cage.creases.size(), 1u);
    EXPECT_EQ(e.cage.edgeSharpness(4, 5), 1.0f);
    ASSERT_EQ(e.cage.corners.size(), 1u);
    EXPECT_EQ(e.cage.vertexSharpness(14), 2.0f);

    TopologyEdit kept = expectGood(qp::deleteFaces(grid, qp::buildTopology(grid), {&face, 1}, false));
    EXPECT_EQ(kept.cage.vertexCount(), 17u);
    EXPECT_EQ(kept.cage.vertexSharpness(0), 1.0f);
}

TEST(DeleteFaces, RefusesEmptyAllAndMissing) {
    Cage cube = makeCube();
    qp::Topology t = qp::buildTopology(cube);
    uint32_t all[6] = {5, 4, 3, 2, 1, 0};
    expectRefused(qp::deleteFaces(cube, t, all), "every face");
    expectRefused(qp::deleteFaces(cube, t, {}), "no faces");
    uint32_t missing = 99;
    expectRefused(qp::deleteFaces(cube, t, {&missing, 1}), "does not exist");
}

TEST(SplitFace, QuadIntoTrianglesAndPentagonIntoTriangleAndQuad) {
    Cage grid = makeGrid(2);
    grid.setHole(3, true);
    TopologyEdit e = expectGood(qp::splitFace(grid, qp::buildTopology(grid), 3, 4, 8));  // quad 4, 5, 8, 7
    EXPECT_EQ(faceOf(e.cage, 3), (std::vector<uint32_t>{4, 5, 8}));  // holds the first corner
    EXPECT_EQ(faceOf(e.cage, 4), (std::vector<uint32_t>{4, 8, 7}));
    EXPECT_EQ(e.cage.holes, (std::vector<uint32_t>{3, 4}));
    EXPECT_EQ(e.resultEdges, (std::vector<qp::EdgeKey>{{4, 8}}));
    EXPECT_EQ(stats(e.cage).nonManifoldEdges, 0u);

    Cage pentagon;
    pentagon.positions = {{0, 0, 0}, {1, 0, 0}, {1.5f, 1, 0}, {0.5f, 1.5f, 0}, {-0.5f, 1, 0}};
    uint32_t p[5] = {0, 1, 2, 3, 4};
    pentagon.addFace(p, 5);
    TopologyEdit q = expectGood(qp::splitFace(pentagon, qp::buildTopology(pentagon), 0, 1, 3));
    EXPECT_EQ(faceOf(q.cage, 0), (std::vector<uint32_t>{0, 1, 3, 4}));
    EXPECT_EQ(faceOf(q.cage, 1), (std::vector<uint32_t>{1, 2, 3}));
}

TEST(SplitFace, RefusesAdjacentMissingAndExistingEdges) {
    Cage grid = makeGrid(2);
    qp::Topology t = qp::buildTopology(grid);
    expectRefused(qp::splitFace(grid, t, 0, 0, 1), "adjacent");
    expectRefused(qp::splitFace(grid, t, 0, 0, 8), "not a corner");
    expectRefused(qp::splitFace(grid, t, 9, 0, 4), "does not exist");
    // After splitting face 0 along 0-4, splitting a face that also has 0 and 4 is impossible
    // here, so build the case directly: two quads sharing the diagonal's end points.
    Cage twin;
    twin.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1, 1, 1}};
    uint32_t a[4] = {0, 1, 2, 3}, b[3] = {0, 2, 4};
    twin.addFace(a, 4);
    twin.addFace(b, 3);
    expectRefused(qp::splitFace(twin, qp::buildTopology(twin), 0, 0, 2), "already exists");
}

TEST(InsertEdgeLoop, CutsAColumnOfAGridAtFractionT) {
    Cage grid = makeGrid(3);
    grid.setEdgeSharpness(4, 5, 2.5f);
    TopologyEdit e = expectGood(qp::insertEdgeLoop(grid, qp::buildTopology(grid), 0, 1, 0.25f));
    EXPECT_EQ(e.cage.vertexCount(), 20u);
    EXPECT_EQ(e.cage.faceCount(), 12u);
    EXPECT_EQ(e.resultVertices, (std::vector<uint32_t>{16, 17, 18, 19}));
    EXPECT_EQ(e.resultEdges.size(), 3u);
    for (uint32_t v : e.resultVertices) EXPECT_NEAR(e.cage.positions[v].x, 0.25f, 1e-6f);
    EXPECT_EQ(e.changedFaces, (std::vector<uint32_t>{0, 3, 6, 9, 10, 11}));
    // The cut crease passes to both halves.
    const qp::Topology after = qp::buildTopology(e.cage);
    uint32_t middle = UINT32_MAX;
    for (uint32_t v : e.resultVertices)
        if (after.findEdge(4, v) != UINT32_MAX) middle = v;
    ASSERT_NE(middle, UINT32_MAX);
    EXPECT_EQ(e.cage.edgeSharpness(4, middle), 2.5f);
    EXPECT_EQ(e.cage.edgeSharpness(middle, 5), 2.5f);
    EXPECT_EQ(e.cage.edgeSharpness(4, 5), 0.0f);
    EXPECT_EQ(stats(e.cage).nonManifoldEdges, 0u);

    // The direction of t follows the given edge.
    TopologyEdit r = expectGood(qp::insertEdgeLoop(grid, qp::buildTopology(grid), 1, 0, 0.25f));
    for (uint32_t v : r.resultVertices) EXPECT_NEAR(r.cage.positions[v].x, 0.75f, 1e-6f);
}

TEST(InsertEdgeLoop, ClosesAroundACubeAndStopsAtNonQuads) {
    Cage cube = makeCube();
    TopologyEdit e = expectGood(qp::insertEdgeLoop(cube, qp::buildTopology(cube), 0, 1, 0.5f));
    EXPECT_EQ(e.cage.vertexCount(), 12u);
    EXPECT_EQ(e.cage.faceCount(), 10u);
    EXPECT_EQ(e.resultEdges.size(), 4u);
    qp::CageStats s = stats(e.cage);
    EXPECT_EQ(s.boundaryEdges, 0u);
    EXPECT_EQ(s.nonManifoldEdges, 0u);

    // Mixed grid: the column through the triangle/pentagon stops there; they gain a vertex.
    Cage mixed = qp::test::makeMixedGrid();
    qp::Topology t = qp::buildTopology(mixed);
    TopologyEdit m = expectGood(qp::insertEdgeLoop(mixed, t, 1, 2, 0.5f));  // column x = 1 of the 4x4 grid
    EXPECT_EQ(m.resultVertices.size(), 2u);  // edge 1-2 and edge 6-7, which the triangle has
    const uint32_t triangle = mixed.faceCount() - 2;
    EXPECT_EQ(m.cage.faceSize(triangle), 4u);
    EXPECT_EQ(stats(m.cage).nonManifoldEdges, 0u);

    expectRefused(qp::insertEdgeLoop(cube, qp::buildTopology(cube), 0, 6, 0.5f), "no edge");
    expectRefused(qp::insertEdgeLoop(cube, qp::buildTopology(cube), 0, 1, 1.0f), "between 0 and 1");
    Cage triangleOnly;
    triangleOnly.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    uint32_t tri[3] = {0, 1, 2};
    triangleOnly.addFace(tri, 3);
    expectRefused(qp::insertEdgeLoop(triangleOnly, qp::buildTopology(triangleOnly), 0, 1, 0.5f), "no quad");
}

TEST(InsertEdgeLoop, InterpolatesTextureCoordinates) {
    Cage grid = makeGrid(2);
    for (uint32_t v = 0; v < grid.vertexCount(); ++v) grid.uvs.push_back({grid.positions[v].x, grid.positions[v].y});
    grid.faceUVIndices = grid.faceVertices;
    TopologyEdit e = expectGood(qp::insertEdgeLoop(grid, qp::buildTopology(grid), 0, 1, 0.5f));
    ASSERT_EQ(e.cage.faceUVIndices.size(), e.cage.faceVertices.size());
    for (size_t i = 0; i < e.cage.faceVertices.size(); ++i) {
        glm::vec3 p = e.cage.positions[e.cage.faceVertices[i]];
        glm::vec2 uv = e.cage.uvs[e.cage.faceUVIndices[i]];
        EXPECT_NEAR(uv.x, p.x, 1e-6f);
        EXPECT_NEAR(uv.y, p.y, 1e-6f);
    }
    EXPECT_EQ(e.cage.uvs.size(), grid.uvs.size() + 3u);  // one per new vertex, shared by both sides
}

TEST(MergeVertices, EdgeCollapseMakesTrianglesAndResolvesTags) {
    Cage grid = makeGrid(3);
    grid.setEdgeSharpness(5, 6, 3.0f);   // between merged vertices: disappears
    grid.setEdgeSharpness(1, 5, 1.0f);   // 1-5 and 1-6? 1-6 is no edge; 1-5 becomes 1-s
    grid.setEdgeSharpness(5, 9, 1.0f);
    grid.setEdgeSharpness(6, 10, 2.0f);  // 9-s and s-10 stay separate edges
    grid.setVertexSharpness(5, 2.0f);
    grid.setVertexSharpness(6, 1.0f);
    uint32_t pair[2] = {5, 6};
    TopologyEdit e = expectGood(qp::mergeVertices(grid, qp::buildTopology(grid), pair));
    EXPECT_EQ(e.cage.vertexCount(), 15u);
    EXPECT_EQ(e.cage.faceCount(), 9u);
    EXPECT_EQ(e.resultVertices, (std::vector<uint32_t>{5}));  // vertex 6, shifted down by one
    EXPECT_EQ(e.oldVertexOf[5], 6u);
    EXPECT_NEAR(e.cage.positions[5].x, 1.5f, 1e-6f);
    EXPECT_EQ(e.cage.faceSize(1), 3u);
    EXPECT_EQ(e.cage.faceSize(4), 3u);
    EXPECT_EQ(e.cage.edgeSharpness(1, 5), 1.0f);
    EXPECT_EQ(e.cage.edgeSharpness(5, 8), 1.0f);  // old 5-9
    EXPECT_EQ(e.cage.edgeSharpness(5, 9), 2.0f);  // old 6-10
    EXPECT_EQ(e.cage.creases.size(), 3u);
    EXPECT_EQ(e.cage.vertexSharpness(5), 2.0f);
    EXPECT_EQ(e.cage.corners.size(), 1u);
    EXPECT_EQ(stats(e.cage).nonManifoldEdges, 0u);

    TopologyEdit last = expectGood(qp::mergeVertices(grid, qp::buildTopology(grid), pair, qp::MergeTarget::Last));
    EXPECT_EQ(last.cage.positions[5], grid.positions[6]);
}

TEST(MergeVertices, CollapsingAFaceOrADiagonalRemovesDegenerateFacesAndMergesEdges) {
    Cage grid = makeGrid(3);
    grid.setHole(8, true);
    uint32_t quad[4] = {5, 6, 10, 9};
    TopologyEdit whole = expectGood(qp::mergeVertices(grid, qp::buildTopology(grid), quad));
    EXPECT_EQ(whole.cage.faceCount(), 8u);
    EXPECT_EQ(whole.removedFaces, (std::vector<uint32_t>{4}));
    EXPECT_EQ(whole.cage.holes, (std::vector<uint32_t>{7}));
    for (uint32_t f : {1u, 3u, 4u, 6u}) EXPECT_EQ(whole.cage.faceSize(f), 3u) << f;

    // Opposite corners 5 and 10: the quad folds into nothing, edges 5-6 and 6-10 become one.
    grid.setEdgeSharpness(5, 6, 1.0f);
    grid.setEdgeSharpness(6, 10, 4.0f);
    uint32_t diagonal[2] = {5, 10};
    TopologyEdit d = expectGood(qp::mergeVertices(grid, qp::buildTopology(grid), diagonal));
    EXPECT_EQ(d.cage.faceCount(), 8u);
    const uint32_t s = d.resultVertices[0];
    EXPECT_EQ(d.oldVertexOf[5], 6u);
    EXPECT_EQ(d.cage.edgeSharpness(s, 5), 4.0f);  // old 5-6 and 6-10: the larger of the two
    EXPECT_EQ(stats(d.cage).nonManifoldEdges, 0u);
}

TEST(MergeVertices, DuplicateFacesCollapseToOneAndPinchesAreRefused) {
    Cage pillow;  // two triangles a-b-c and a-c-d; merging b and d makes them one cycle
    pillow.positions = {{0, 0, 0}, {1, -1, 0}, {2, 0, 0}, {1, 1, 0}, {1, 0, 1}};
    uint32_t t0[3] = {0, 1, 2}, t1[3] = {0, 2, 3}, t2[3] = {0, 3, 4};
    pillow.addFace(t0, 3);
    pillow.addFace(t1, 3);
    pillow.addFace(t2, 3);
    uint32_t bd[2] = {1, 3};
    TopologyEdit e = expectGood(qp::mergeVertices(pillow, qp::buildTopology(pillow), bd));
    EXPECT_EQ(e.cage.faceCount(), 2u);
    EXPECT_EQ(e.removedFaces, (std::vector<uint32_t>{1}));

    Cage hexagon;
    for (int i = 0; i < 6; ++i) hexagon.positions.push_back({std::cos(i * 1.047f), std::sin(i * 1.047f), 0});
    uint32_t h[6] = {0, 1, 2, 3, 4, 5};
    hexagon.addFace(h, 6);
    uint32_t opposite[2] = {0, 3};
    expectRefused(qp::mergeVertices(hexagon, qp::buildTopology(hexagon), opposite), "twice");
    uint32_t one[2] = {2, 2};
    expectRefused(qp::mergeVertices(hexagon, qp::buildTopology(hexagon), one), "two different");
    uint32_t missing[2] = {0, 6};
    expectRefused(qp::mergeVertices(hexagon, qp::buildTopology(hexagon), missing), "does not exist");
    uint32_t triangle[3] = {0, 1, 2};
    Cage tri;
    tri.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    tri.addFace(triangle, 3);
    uint32_t two[2] = {0, 1};
    expectRefused(qp::mergeVertices(tri, qp::buildTopology(tri), two), "without faces");
}

TEST(MakeFace, FillsAHoleWithTheNeighboursOrientation) {
    Cage grid = makeGrid(3);
    const uint32_t centre = 4;
    TopologyEdit hole = expectGood(qp::deleteFaces(grid, qp::buildTopology(grid), {&centre, 1}));
    uint32_t reversed[4] = {5, 9, 10, 6};  // the wrong way round
    TopologyEdit e = expectGood(qp::makeFace(hole.cage, qp::buildTopology(hole.cage), reversed));
    EXPECT_EQ(faceOf(e.cage, 8), (std::vector<uint32_t>{5, 6, 10, 9}));
    EXPECT_EQ(stats(e.cage).nonManifoldEdges, 0u);
    EXPECT_EQ(stats(e.cage).boundaryEdges, 12u);
    EXPECT_EQ(e.resultFaces, (std::vector<uint32_t>{8}));

    qp::Topology t = qp::buildTopology(grid);
    uint32_t existing[4] = {0, 1, 5, 4};
    expectRefused(qp::makeFace(grid, t, existing), "non-manifold");  // edge 1-5 has two faces
    Cage single = makeGrid(1);
    uint32_t same[4] = {3, 2, 0, 1};
    expectRefused(qp::makeFace(single, qp::buildTopology(single), same), "already joins");
    uint32_t repeated[3] = {0, 1, 0};
    expectRefused(qp::makeFace(grid, t, repeated), "twice");
    uint32_t two[2] = {0, 1};
    expectRefused(qp::makeFace(grid, t, two), "at least 3");
}

TEST(TopologyEdits, FinishRejectsReorderedMaps) {
    Cage grid = makeGrid(2);
    TopologyEdit e;
    e.cage = grid;
    e.oldFaceOf = {1, 0, 2, 3};
    e.oldVertexOf.resize(grid.vertexCount());
    for (uint32_t v = 0; v < grid.vertexCount(); ++v) e.oldVertexOf[v] = v;
    EXPECT_FALSE(qp::finishTopologyEdit(grid, e, "test").ok());
    e.oldFaceOf = {0, 1, 2};
    EXPECT_FALSE(qp::finishTopologyEdit(grid, e, "test").ok());
}
