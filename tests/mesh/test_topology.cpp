#include <gtest/gtest.h>

#include <opensubdiv/far/topologyLevel.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "mesh/cage.h"
#include "mesh/generated_cage.h"
#include "mesh/topology.h"
#include "plans/osd_refiner.h"
#include "test_cages.h"

namespace {

using qp::test::makeCube;
using qp::test::makeGrid;

}  // namespace

TEST(Topology, GridCountsAndValences) {
    qp::Cage grid = makeGrid(3);
    ASSERT_TRUE(qp::validateCage(grid, "grid").ok());
    qp::Topology t = qp::buildTopology(grid);
    qp::CageStats s = qp::computeStats(grid, t);
    EXPECT_EQ(s.vertices, 16u);
    EXPECT_EQ(s.faces, 9u);
    EXPECT_EQ(s.edges, 24u);
    EXPECT_EQ(s.boundaryEdges, 12u);
    EXPECT_EQ(s.nonManifoldEdges, 0u);
    EXPECT_EQ(s.nonManifoldVertices, 0u);
    EXPECT_EQ(s.valenceHistogram[2], 4u);
    EXPECT_EQ(s.valenceHistogram[3], 8u);
    EXPECT_EQ(s.valenceHistogram[4], 4u);
    EXPECT_EQ(s.extraordinaryVertices, 0u);
    EXPECT_EQ(t.findEdge(5, 6), t.findEdge(6, 5));
    EXPECT_NE(t.findEdge(5, 6), UINT32_MAX);
    EXPECT_EQ(t.findEdge(0, 5), UINT32_MAX);  // diagonal
    EXPECT_EQ(t.edgeFaceCount(t.findEdge(5, 6)), 2u);
}

TEST(Topology, CubeIsClosedWithEightExtraordinaryVertices) {
    qp::Cage cube = makeCube();
    qp::CageStats s = qp::computeStats(cube, qp::buildTopology(cube));
    EXPECT_EQ(s.edges, 12u);
    EXPECT_EQ(s.boundaryEdges, 0u);
    EXPECT_EQ(s.extraordinaryVertices, 8u);
}

TEST(Topology, DetectsNonManifoldEdgeAndVertex) {
    qp::Cage fin = makeGrid(1);  // one quad 0-1-3-2 plus two more faces on edge 0-1
    fin.positions.push_back({0, 0, 1});
    fin.positions.push_back({0, 0, -1});
    uint32_t a[3] = {1, 0, 4}, b[3] = {1, 0, 5};
    fin.addFace(a, 3);
    fin.addFace(b, 3);
    qp::CageStats s = qp::computeStats(fin, qp::buildTopology(fin));
    EXPECT_EQ(s.nonManifoldEdges, 1u);
    EXPECT_GE(s.nonManifoldVertices, 2u);

    // Two quads touching at one vertex only (a bow tie).
    qp::Cage bowTie;
    bowTie.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 1, 0}, {2, 2, 0}, {1, 2, 0}};
    uint32_t q0[4] = {0, 1, 2, 3}, q1[4] = {2, 4, 5, 6};
    bowTie.addFace(q0, 4);
    bowTie.addFace(q1, 4);
    qp::CageStats t = qp::computeStats(bowTie, qp::buildTopology(bowTie));
    EXPECT_EQ(t.nonManifoldEdges, 0u);
    EXPECT_EQ(t.nonManifoldVertices, 1u);
}

TEST(Topology, InconsistentWindingIsNonManifold) {
    qp::Cage cage = makeGrid(2);
    std::swap(cage.faceVertices[1], cage.faceVertices[3]);  // flip face 0
    qp::CageStats s = qp::computeStats(cage, qp::buildTopology(cage));
    EXPECT_EQ(s.nonManifoldEdges, 2u);
}

TEST(Cage, TagSettersKeepListsSortedAndValid) {
    qp::Cage cube = makeCube();
    cube.setEdgeSharpness(5, 1, 2.5f);
    cube.setEdgeSharpness(0, 1, 1.0f);
    cube.setVertexSharpness(6, 3.0f);
    cube.setHole(2, true);
    EXPECT_EQ(cube.edgeSharpness(1, 5), 2.5f);
    EXPECT_EQ(cube.edgeSharpness(1, 0), 1.0f);
    EXPECT_EQ(cube.edgeSharpness(2, 3), 0.0f);
    EXPECT_EQ(cube.vertexSharpness(6), 3.0f);
    EXPECT_TRUE(cube.isHole(2));
    EXPECT_TRUE(qp::validateCage(cube, "cube").ok());
    cube.setEdgeSharpness(1, 5, 0.0f);
    EXPECT_EQ(cube.creases.size(), 1u);
    cube.setHole(2, false);
    EXPECT_TRUE(cube.holes.empty());
}

TEST(Cage, ValidationNamesTheProblem) {
    qp::Cage cube = makeCube();
    cube.positions[3].y = std::numeric_limits<float>::quiet_NaN();
    auto nan = qp::validateCage(cube, "cube.obj");
    ASSERT_FALSE(nan.ok());
    EXPECT_NE(nan.error().message.find("cube.obj: vertex 4"), std::string::npos);

    qp::Cage diagonal = makeCube();
    diagonal.creases.push_back({0, 6, 1.0f});
    auto notAnEdge = qp::validateCage(diagonal, "cube.obj");
    ASSERT_FALSE(notAnEdge.ok());
    EXPECT_NE(notAnEdge.error().message.find("no face has"), std::string::npos);

    qp::Cage negative = makeCube();
    negative.creases.push_back({0, 1, -1.0f});
    EXPECT_FALSE(qp::validateCage(negative, "cube.obj").ok());

    qp::Cage outOfRange = makeCube();
    outOfRange.faceVertices[5] = 42;
    auto range = qp::validateCage(outOfRange, "cube.obj");
    ASSERT_FALSE(range.ok());
    EXPECT_NE(range.error().message.find("face 2"), std::string::npos);
}

TEST(OsdRefiner, CarriesTagsIntoOpenSubdiv) {
    qp::Cage cube = makeCube();
    cube.setEdgeSharpness(0, 1, 2.5f);
    cube.setVertexSharpness(6, 4.0f);
    cube.setHole(1, true);
    cube.options.creaseMethod = qp::CreaseMethod::Chaikin;
    auto refiner = qp::createRefiner(cube, "cube");
    ASSERT_TRUE(refiner.ok()) << refiner.error().message;
    const auto& level = (*refiner)->GetLevel(0);
    EXPECT_EQ(level.GetNumVertices(), 8);
    EXPECT_EQ(level.GetNumFaces(), 6);
    EXPECT_FLOAT_EQ(level.GetEdgeSharpness(level.FindEdge(0, 1)), 2.5f);
    EXPECT_FLOAT_EQ(level.GetVertexSharpness(6), 4.0f);
    EXPECT_TRUE(level.IsFaceHole(1));
    EXPECT_EQ((*refiner)->GetSchemeOptions().GetCreasingMethod(), OpenSubdiv::Sdc::Options::CREASE_CHAIKIN);
}

// Edges as topology.h numbers them, from first principles: the distinct (smaller, larger) vertex
// pairs of the faces' edges in order, each face edge naming its pair, the adjacency lists in
// face and edge order. A fan with more corners at its centre than buildTopology sorts by
// insertion takes its other sorting path.
TEST(Topology, EdgesAreTheSortedDistinctPairsOfTheFaces) {
    qp::Cage fan;
    const uint32_t spokes = 24;
    fan.positions.push_back({0.0f, 0.0f, 0.0f});
    for (uint32_t k = 0; k < spokes; ++k) fan.positions.push_back({std::cos(0.26f * float(k)), std::sin(0.26f * float(k)), 0.0f});
    for (uint32_t k = 0; k < spokes; ++k) {
        const uint32_t face[3] = {0, 1 + k, 1 + (k + 1) % spokes};
        fan.addFace(face, 3);
    }
    for (const qp::Cage& cage : {fan, qp::makeBenchmarkCage(600, 3), makeGrid(4)}) {
        ASSERT_TRUE(qp::validateCage(cage, "cage").ok());
        const qp::Topology t = qp::buildTopology(cage);
        std::set<std::pair<uint32_t, uint32_t>> pairs;
        for (uint32_t f = 0; f < cage.faceCount(); ++f)
            for (uint32_t i = 0, n = cage.faceSize(f); i < n; ++i) {
                const uint32_t a = cage.faceBegin(f)[i], b = cage.faceBegin(f)[(i + 1) % n];
                pairs.insert({std::min(a, b), std::max(a, b)});
            }
        ASSERT_EQ(t.edgeCount(), pairs.size());
        uint32_t e = 0;
        for (auto [a, b] : pairs) {
            EXPECT_EQ(t.edgeVertices[2 * e], a);
            EXPECT_EQ(t.edgeVertices[2 * e + 1], b);
            ++e;
        }
        std::vector<std::vector<uint32_t>> edgeFaces(t.edgeCount()), vertexFaces(cage.vertexCount()), vertexEdges(cage.vertexCount());
        for (uint32_t f = 0; f < cage.faceCount(); ++f)
            for (uint32_t i = 0, n = cage.faceSize(f); i < n; ++i) {
                const uint32_t a = cage.faceBegin(f)[i], b = cage.faceBegin(f)[(i + 1) % n];
                const uint32_t edge = t.faceEdges[cage.faceOffsets[f] + i];
                EXPECT_EQ(edge, t.findEdge(a, b));
                edgeFaces[edge].push_back(f);
                vertexFaces[a].push_back(f);
            }
        for (uint32_t k = 0; k < t.edgeCount(); ++k) {
            vertexEdges[t.edgeVertices[2 * k]].push_back(k);
            vertexEdges[t.edgeVertices[2 * k + 1]].push_back(k);
            EXPECT_EQ(std::vector<uint32_t>(t.edgeFaces.begin() + t.edgeFaceOffsets[k], t.edgeFaces.begin() + t.edgeFaceOffsets[k + 1]),
                      edgeFaces[k]);
        }
        for (uint32_t v = 0; v < cage.vertexCount(); ++v) {
            EXPECT_EQ(std::vector<uint32_t>(t.vertexFaces.begin() + t.vertexFaceOffsets[v],
                                            t.vertexFaces.begin() + t.vertexFaceOffsets[v + 1]),
                      vertexFaces[v]);
            EXPECT_EQ(std::vector<uint32_t>(t.vertexEdges.begin() + t.vertexEdgeOffsets[v],
                                            t.vertexEdges.begin() + t.vertexEdgeOffsets[v + 1]),
                      vertexEdges[v]);
        }
    }
}
