#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <map>
#include <set>

#include "mesh/generated_cage.h"
#include "mesh/obj_io.h"
#include "mesh/topology.h"
#include "plans/macro_faces.h"
#include "test_cages.h"
#include "test_support.h"

namespace {

// What every partition promises: each face in at most one macro face, each macro face a
// rectangle of quads whose cells' corners are its lattice's vertices (neighbouring cells agree),
// its sides tiled by spans, and a span id shared by two macro faces the same chain of cage
// vertices in both.
void expectValidPartition(const qp::Cage& cage, const qp::MacroFaces& macros, const std::string& name) {
    std::set<uint32_t> seen;
    std::map<uint32_t, std::set<uint32_t>> spanVertices;  // span id -> its lattice vertices
    for (uint32_t m = 0; m < macros.faces.size(); ++m) {
        const qp::MacroFace& face = macros.faces[m];
        ASSERT_GE(face.width * face.height, 2u) << name;
        for (uint32_t j = 0; j < face.height; ++j)
            for (uint32_t i = 0; i < face.width; ++i) {
                const qp::MacroCell& cell = macros.cells[face.firstCell + j * face.width + i];
                ASSERT_EQ(cage.faceSize(cell.face), 4u) << name;
                EXPECT_TRUE(seen.insert(cell.face).second) << name << ": face " << cell.face << " in two macro faces";
                const uint32_t* v = cage.faceBegin(cell.face);
                const uint32_t lattice[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
                for (uint32_t k = 0; k < 4; ++k)
                    EXPECT_EQ(v[(cell.rotation + k) & 3], qp::macroLatticeVertex(cage, macros, m, lattice[k][0], lattice[k][1]))
                        << name << ": macro face " << m << " cell (" << i << ", " << j << ") corner " << k;
            }
        for (uint32_t s = 0; s < 4; ++s) {
            // The side's spans tile it in order; a span shared by two macro faces is the same
            // chain of cage vertices in both.
            const uint32_t length = s % 2 ? face.height : face.width;
            uint32_t at = 0;
            for (uint32_t k = face.spanBegin[s]; k < face.spanBegin[s + 1]; ++k) {
                const qp::MacroSpan& span = macros.spans[k];
                EXPECT_EQ(span.start, at) << name;
                at += span.length;
                std::set<uint32_t> chain;
                for (uint32_t t = span.start; t <= span.start + span.length; ++t) {
                    const uint32_t a = s == 0 || s == 2 ? t : (s == 1 ? face.width : 0);
                    const uint32_t b = s == 1 || s == 3 ? t : (s == 2 ? face.height : 0);
                    chain.insert(qp::macroLatticeVertex(cage, macros, m, a, b));
                }
                auto [it, added] = spanVertices.try_emplace(span.id, chain);
                if (!added) {
                    EXPECT_EQ(it->second, chain) << name << ": span " << span.id;
                    EXPECT_TRUE(macros.spanShared[span.id]) << name << ": span " << span.id << " has two users";
                }
            }
            EXPECT_EQ(at, length) << name;
        }
    }
    EXPECT_EQ(seen.size(), macros.facesInMacroFaces()) << name;
}

}  // namespace

TEST(MacroFaces, RegularTorusIsCutIntoRectanglesThatMeetWhole) {
    const qp::Cage torus = qp::test::makeTorus(48, 20);
    const qp::Topology topology = qp::buildTopology(torus);
    const qp::MacroFaces macros = qp::rectangularMacroFaces(torus, topology, 16);
    expectValidPartition(torus, macros, "torus");
    // No singular vertex anywhere: every face is in a macro face, none longer than 16, and with
    // no boundary and no T-junction every side is shared whole.
    EXPECT_EQ(macros.facesInMacroFaces(), torus.faceCount());
    for (const qp::MacroFace& face : macros.faces) {
        EXPECT_LE(face.width, 16u);
        EXPECT_LE(face.height, 16u);
    }
    for (uint8_t shared : macros.spanShared) EXPECT_TRUE(shared);
    for (const qp::MacroFace& face : macros.faces) EXPECT_EQ(face.spanBegin[4] - face.spanBegin[0], 4u) << "one span a side";
    EXPECT_LE(macros.faces.size(), 12u);  // 48 x 20 in parts of at most 16: 3 or 4 columns by 2 rows
}

TEST(MacroFaces, ExtraordinaryVerticesEndRectanglesAtTheirSeparatrices) {
    // The subdivided cube: eight valence-3 corners, whose separatrices run along the cube's
    // edges, so each side is one n x n macro face meeting four others whole.
    const qp::Cage cube = qp::test::makeSubdividedCube(4);
    const qp::MacroFaces macros = qp::rectangularMacroFaces(cube, qp::buildTopology(cube), 16);
    expectValidPartition(cube, macros, "cube");
    ASSERT_EQ(macros.faces.size(), 6u);
    for (const qp::MacroFace& face : macros.faces) {
        EXPECT_EQ(face.width, 4u);
        EXPECT_EQ(face.height, 4u);
    }
    EXPECT_EQ(macros.spanCount(), 12u);  // the cube's edges
    for (uint8_t shared : macros.spanShared) EXPECT_TRUE(shared);
    // A span limit below the side's length cuts every side into halves, still meeting whole.
    const qp::MacroFaces halves = qp::rectangularMacroFaces(cube, qp::buildTopology(cube), 2);
    expectValidPartition(cube, halves, "cube, span 2");
    EXPECT_EQ(halves.faces.size(), 24u);
    for (uint8_t shared : halves.spanShared) EXPECT_TRUE(shared);
}

TEST(MacroFaces, BoundariesAndNonQuadsStayOutside) {
    const qp::Cage grid = qp::test::makeMixedGrid();
    const qp::MacroFaces macros = qp::rectangularMacroFaces(grid, qp::buildTopology(grid));
    expectValidPartition(grid, macros, "mixed grid");
    const qp::Cage flat = qp::test::makeFlatGrid(5);
    const qp::MacroFaces open = qp::rectangularMacroFaces(flat, qp::buildTopology(flat));
    expectValidPartition(flat, open, "flat grid");
    ASSERT_EQ(open.faces.size(), 1u);  // one 5 x 5 rectangle; its sides are the boundary
    EXPECT_EQ(open.faces[0].width * open.faces[0].height, 25u);
    for (uint8_t shared : open.spanShared) EXPECT_FALSE(shared);
}

TEST(MacroFaces, QuartetsAreTwoByTwoBlocksOfRegularFaces) {
    const qp::Cage cage = qp::makeBenchmarkCage(3000, 2);
    const qp::Topology topology = qp::buildTopology(cage);
    const qp::MacroFaces quartets = qp::quartetMacroFaces(cage, topology);
    expectValidPartition(cage, quartets, "generated, quartets");
    ASSERT_GT(quartets.faces.size(), 100u);
    const qp::CageStats stats = qp::computeStats(cage, topology);
    for (const qp::MacroFace& face : quartets.faces) {
        EXPECT_EQ(face.width, 2u);
        EXPECT_EQ(face.height, 2u);
    }
    EXPECT_GT(stats.extraordinaryVertices, 0u);
    const qp::MacroFaces rectangles = qp::rectangularMacroFaces(cage, topology);
    expectValidPartition(cage, rectangles, "generated, rectangles");
}

TEST(MacroFaces, SharedCagesArePartitionedValidly) {
    QP_REQUIRE_SHARED_SHAPES();
    for (const auto& path : qp::test::sharedShapes()) {
        qp::Result<qp::Cage> cage = qp::loadObj(path.string());
        ASSERT_TRUE(cage) << path;
        const qp::Topology topology = qp::buildTopology(*cage);
        expectValidPartition(*cage, qp::rectangularMacroFaces(*cage, topology), path.filename().string());
        expectValidPartition(*cage, qp::quartetMacroFaces(*cage, topology), path.filename().string() + ", quartets");
    }
}

TEST(MacroFaces, AlignedBlocksAndQuartetsShareWholeSidesAroundScatteredExtraordinaryVertices) {
    // One poked quad in a hundred makes separatrices cut the generated cage into slivers; blocks
    // and quartets aligned on the lattice of its regular faces still meet whole.
    const qp::Cage cage = qp::makeBenchmarkCage(20000, 3);
    const qp::Topology topology = qp::buildTopology(cage);
    const qp::MacroFaces rectangles = qp::rectangularMacroFaces(cage, topology);
    const qp::MacroFaces quartets = qp::quartetMacroFaces(cage, topology);
    const qp::MacroFaces blocks = qp::blockMacroFaces(cage, topology, 16);
    expectValidPartition(cage, quartets, "generated 20k, quartets");
    expectValidPartition(cage, blocks, "generated 20k, blocks");
    auto sharedFraction = [](const qp::MacroFaces& m) {
        uint32_t shared = 0;
        for (uint8_t s : m.spanShared) shared += s;
        return double(shared) / double(m.spanCount());
    };
    // Faces left to be drawn alone when every macro face is one quad: far fewer with blocks.
    auto quadsAfter = [&](const qp::MacroFaces& m) { return cage.faceCount() - m.facesInMacroFaces() + m.faces.size(); };
    EXPECT_LT(quadsAfter(blocks), quadsAfter(quartets));
    EXPECT_LT(quadsAfter(quartets), quadsAfter(rectangles));
    EXPECT_GT(sharedFraction(quartets), 0.5);
    uint32_t largest = 0;
    for (const qp::MacroFace& face : blocks.faces) {
        EXPECT_EQ(face.width, face.height);
        EXPECT_TRUE(std::has_single_bit(face.width));
        largest = std::max(largest, face.width);
    }
    EXPECT_GE(largest, 4u);
    // The regular torus: blocks of 16 wherever its size allows.
    const qp::Cage torus = qp::test::makeTorus(64, 32);
    const qp::MacroFaces torusBlocks = qp::blockMacroFaces(torus, qp::buildTopology(torus), 16);
    expectValidPartition(torus, torusBlocks, "torus, blocks");
    EXPECT_EQ(torusBlocks.facesInMacroFaces(), torus.faceCount());
    EXPECT_EQ(torusBlocks.faces.size(), 8u);
}
