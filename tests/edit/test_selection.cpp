// Selection modes, conversions, grow/shrink and remapping (core/edit/selection.h), and transforms of
// selected vertices (core/edit/transform.h).
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <gtest/gtest.h>

#include "edit/selection.h"
#include "edit/transform.h"
#include "mesh/topology_edits.h"
#include "test_cages.h"

namespace {

using qp::Cage;
using qp::EdgeKey;
using qp::Selection;
using qp::SelectionMode;

Selection vertices(std::vector<uint32_t> v) {
    Selection s;
    s.mode = SelectionMode::Vertex;
    s.vertices = std::move(v);
    return s;
}

Selection faces(std::vector<uint32_t> f) {
    Selection s;
    s.mode = SelectionMode::Face;
    s.faces = std::move(f);
    return s;
}

}  // namespace

TEST(Selection, SelectAllInvertAndPickOperations) {
    Cage grid = qp::test::makeGrid(3);
    grid.positions.push_back({9, 9, 9});  // a bare vertex is not part of "all"
    qp::Topology t = qp::buildTopology(grid);
    EXPECT_EQ(qp::selectAll(grid, t, SelectionMode::Vertex).size(), 16u);
    EXPECT_EQ(qp::selectAll(grid, t, SelectionMode::Edge).size(), 24u);
    EXPECT_EQ(qp::selectAll(grid, t, SelectionMode::Face).size(), 9u);
    EXPECT_EQ(qp::invertSelection(vertices({0, 5}), grid, t).size(), 14u);
    EXPECT_TRUE(qp::invertSelection(qp::selectAll(grid, t, SelectionMode::Face), grid, t).empty());

    Selection s = vertices({});
    const uint32_t a[3] = {5, 1, 5}, b[2] = {5, 7}, c[1] = {1};
    qp::applyPick(s, qp::SelectOp::Replace, a);
    EXPECT_EQ(s.vertices, (std::vector<uint32_t>{1, 5}));
    qp::applyPick(s, qp::SelectOp::Toggle, b);
    EXPECT_EQ(s.vertices, (std::vector<uint32_t>{1, 7}));
    qp::applyPick(s, qp::SelectOp::Add, b);
    EXPECT_EQ(s.vertices, (std::vector<uint32_t>{1, 5, 7}));
    qp::applyPick(s, qp::SelectOp::Remove, c);
    EXPECT_EQ(s.vertices, (std::vector<uint32_t>{5, 7}));

    Selection e;
    e.mode = SelectionMode::Edge;
    const EdgeKey edges[2] = {{6, 5}, {5, 6}};
    qp::applyPick(e, qp::SelectOp::Add, edges);
    EXPECT_EQ(e.edges, (std::vector<EdgeKey>{{5, 6}}));
}

TEST(Selection, ConversionsFollowTheUsualRules) {
    Cage grid = qp::test::makeGrid(3);
    qp::Topology t = qp::buildTopology(grid);
    Selection square = vertices({5, 6, 9, 10});
    Selection asEdges = qp::convertSelection(square, SelectionMode::Edge, grid, t);
    EXPECT_EQ(asEdges.edges, (std::vector<EdgeKey>{{5, 6}, {5, 9}, {6, 10}, {9, 10}}));
    EXPECT_EQ(qp::convertSelection(square, SelectionMode::Face, grid, t).faces, (std::vector<uint32_t>{4}));
    EXPECT_EQ(qp::convertSelection(asEdges, SelectionMode::Face, grid, t).faces, (std::vector<uint32_t>{4}));
    Selection threeEdges = asEdges;
    threeEdges.edges.pop_back();
    EXPECT_TRUE(qp::convertSelection(threeEdges, SelectionMode::Face, grid, t).empty());
    EXPECT_EQ(qp::convertSelection(threeEdges, SelectionMode::Vertex, grid, t).vertices, (std::vector<uint32_t>{5, 6, 9, 10}));
    Selection face = faces({4});
    EXPECT_EQ(qp::convertSelection(face, SelectionMode::Vertex, grid, t).vertices, (std::vector<uint32_t>{5, 6, 9, 10}));
    EXPECT_EQ(qp::convertSelection(face, SelectionMode::Edge, grid, t).edges, asEdges.edges);
    EXPECT_EQ(qp::selectedVertices(threeEdges, grid), (std::vector<uint32_t>{5, 6, 9, 10}));
}

TEST(Selection, GrowAndShrinkAreInverseInsideTheCage) {
    Cage grid = qp::test::makeGrid(5);
    qp::Topology t = qp::buildTopology(grid);
    Selection centre = faces({12});
    Selection grown = qp::growSelection(centre, grid, t);
    EXPECT_EQ(grown.faces, (std::vector<uint32_t>{6, 7, 8, 11, 12, 13, 16, 17, 18}));
    EXPECT_EQ(qp::shrinkSelection(grown, grid, t), centre);

    Selection v = vertices({14});
    Selection vg = qp::growSelection(v, grid, t);
    EXPECT_EQ(vg.vertices, (std::vector<uint32_t>{8, 13, 14, 15, 20}));
    EXPECT_EQ(qp::shrinkSelection(vg, grid, t), v);

    Selection e;
    e.mode = SelectionMode::Edge;
    e.edges = {{14, 15}};
    Selection eg = qp::growSelection(e, grid, t);
    EXPECT_EQ(eg.edges.size(), 7u);  // 4 at each end, the edge itself counted once
    EXPECT_TRUE(qp::shrinkSelection(e, grid, t).empty());
}

TEST(Selection, RemapsAcrossATopologyEdit) {
    Cage grid = qp::test::makeGrid(3);
    const uint32_t first = 0;
    auto edit = qp::deleteFaces(grid, qp::buildTopology(grid), {&first, 1}, true);  // vertex 0 goes
    ASSERT_TRUE(edit.ok());
    qp::Topology after = qp::buildTopology(edit->cage);
    EXPECT_EQ(qp::remapSelection(vertices({0, 5}), *edit, after).vertices, (std::vector<uint32_t>{4}));
    EXPECT_EQ(qp::remapSelection(faces({0, 4}), *edit, after).faces, (std::vector<uint32_t>{3}));
    Selection e;
    e.mode = SelectionMode::Edge;
    e.edges = {{0, 1}, {5, 6}};
    EXPECT_EQ(qp::remapSelection(e, *edit, after).edges, (std::vector<EdgeKey>{{4, 5}}));
}

TEST(Transform, TranslateRotateScaleAboutThePivotInWorldAndLocalAxes) {
    Cage cube = qp::test::makeCube();
    qp::Topology t = qp::buildTopology(cube);
    const std::vector<uint32_t> top{4, 5, 6, 7};  // z = 1
    const std::vector<glm::vec3> start = qp::positionsOf(cube, top);

    qp::TransformFrame world = qp::makeTransformFrame(cube, t, top, qp::TransformSpace::World);
    EXPECT_EQ(world.pivot, glm::vec3(0, 0, 1));
    auto moved = qp::transformPoints(start, qp::translation(world, {1, 2, 3}));
    ASSERT_TRUE(moved.ok());
    for (size_t i = 0; i < 4; ++i) EXPECT_EQ((*moved)[i], start[i] + glm::vec3(1, 2, 3));

    auto turned = qp::transformPoints(start, qp::rotation(world, {0, 0, 1}, 90.0f));
    ASSERT_TRUE(turned.ok());
    // (1, -1, 1) turns counter-clockwise to (1, 1, 1).
    EXPECT_NEAR(glm::length((*turned)[1] - glm::vec3(1, 1, 1)), 0.0f, 1e-5f);

    auto scaled = qp::transformPoints(start, qp::scaling(world, {2, 2, 1}));
    ASSERT_TRUE(scaled.ok());
    EXPECT_NEAR(glm::length((*scaled)[0] - glm::vec3(-2, -2, 1)), 0.0f, 1e-5f);

    // The front face (y = -1: 0, 1, 5, 4) in local axes: z is its outward normal (0, -1, 0).
    const std::vector<uint32_t> front{0, 1, 4, 5};
    qp::TransformFrame local = qp::makeTransformFrame(cube, t, front, qp::TransformSpace::Local);
    EXPECT_NEAR(glm::length(local.axes[2] - glm::vec3(0, -1, 0)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::determinant(local.axes), 1.0f, 1e-5f);
    auto pushed = qp::transformPoints(qp::positionsOf(cube, front), qp::translation(local, {0, 0, 0.5f}));
    ASSERT_TRUE(pushed.ok());
    for (const glm::vec3& p : *pushed) EXPECT_NEAR(p.y, -1.5f, 1e-6f);

    // A given pivot: scaling by 0 along local z flattens onto the plane through it.
    glm::vec3 pivot(0, -3, 0);
    qp::TransformFrame at = qp::makeTransformFrame(cube, t, front, qp::TransformSpace::Local, &pivot);
    auto flat = qp::transformPoints(qp::positionsOf(cube, front), qp::scaling(at, {1, 1, 0}));
    ASSERT_TRUE(flat.ok());
    for (const glm::vec3& p : *flat) EXPECT_NEAR(p.y, -3.0f, 1e-6f);
}

TEST(Transform, BadNumbersAreRefused) {
    Cage cube = qp::test::makeCube();
    qp::Topology t = qp::buildTopology(cube);
    const std::vector<uint32_t> all{0, 1, 2, 3};
    qp::TransformFrame frame = qp::makeTransformFrame(cube, t, all, qp::TransformSpace::World);
    std::vector<glm::vec3> start = qp::positionsOf(cube, all);
    EXPECT_FALSE(qp::transformPoints(start, qp::rotation(frame, {0, 0, 0}, 30.0f)).ok());
    EXPECT_FALSE(qp::transformPoints(start, qp::translation(frame, {std::nanf(""), 0, 0})).ok());
    EXPECT_FALSE(qp::transformPoints(start, qp::scaling(frame, {1e38f, 1e38f, 1e38f}) * qp::scaling(frame, {1e38f, 1, 1})).ok());
}
