// The editor's cage lines kept per edge (editor/app/cage_lines.h): after moves and tag edits
// they draw exactly what lines made anew would, whatever order the lines ended up in.
#include <gtest/gtest.h>

#include <algorithm>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>

#include "cage_lines.h"
#include "test_cages.h"

namespace qp::editor {
namespace {

// A set's lines as sorted tuples (both ends, colour), so equal sets compare equal in any order.
using Line = std::tuple<float, float, float, float, float, float, float, float, float>;
std::vector<Line> sorted(const std::vector<LineVertex>& set) {
    std::vector<Line> out;
    for (size_t i = 0; i + 1 < set.size(); i += 2) {
        const LineVertex &a = set[i], &b = set[i + 1];
        out.push_back({a.position.x, a.position.y, a.position.z, b.position.x, b.position.y, b.position.z, a.color.r,
                       a.color.g, a.color.b});
    }
    std::sort(out.begin(), out.end());
    return out;
}

void expectSameAsRebuilt(const CageLines& lines, const Cage& cage, const Topology& topology) {
    CageLines fresh;
    rebuildCageLines(fresh, cage, topology, {});
    EXPECT_EQ(sorted(lines.plain), sorted(fresh.plain));
    EXPECT_EQ(sorted(lines.creased), sorted(fresh.creased));
    for (uint32_t e = 0; e < topology.edgeCount(); ++e) {  // every line knows its edge
        const uint32_t line = lines.lineOf[e] & ~CageLines::kCreased;
        const bool creased = lines.lineOf[e] & CageLines::kCreased;
        ASSERT_EQ((creased ? lines.creasedEdge : lines.plainEdge)[line], e);
    }
}

TEST(CageLines, MovesAndTagEditsRewriteOnlyWhatTheyTouchAndMatchARebuild) {
    Cage cage = test::makeGrid(6);
    const Topology topology = buildTopology(cage);
    CageLines lines;
    rebuildCageLines(lines, cage, topology, {});
    EXPECT_TRUE(lines.wholePlain && lines.wholeCreased);
    EXPECT_TRUE(lines.creased.empty());
    lines.wholePlain = lines.wholeCreased = false;

    // A move: only the lines at the vertex change.
    const uint32_t v = 20;
    cage.positions[v].z += 0.5f;
    moveCageLines(lines, cage, topology, {&v, 1});
    EXPECT_EQ(lines.changedPlain.size(), topology.vertexEdgeCount(v));
    expectSameAsRebuilt(lines, cage, topology);

    // Creases on, a sharpness change, then off again: the edges move between the sets.
    auto faces = [&](uint32_t a, uint32_t b) {
        std::vector<uint32_t> out;
        for (uint32_t vertex : {a, b})
            for (uint32_t k = topology.vertexFaceOffsets[vertex]; k < topology.vertexFaceOffsets[vertex + 1]; ++k)
                out.push_back(topology.vertexFaces[k]);
        return out;
    };
    const uint32_t a = topology.edgeVertices[0], b = topology.edgeVertices[1];
    const uint32_t c = topology.edgeVertices[2 * 30], d = topology.edgeVertices[2 * 30 + 1];
    for (float sharpness : {2.0f, 10.0f, 0.0f}) {
        cage.setEdgeSharpness(a, b, sharpness);
        cage.setEdgeSharpness(c, d, sharpness > 0.0f ? 1.0f : 0.0f);
        std::vector<uint32_t> touched = faces(a, b), more = faces(c, d);
        touched.insert(touched.end(), more.begin(), more.end());
        retagCageLines(lines, cage, topology, touched);
        SCOPED_TRACE("sharpness " + std::to_string(sharpness));
        EXPECT_EQ(lines.creased.size(), sharpness > 0.0f ? 4u : 0u);
        expectSameAsRebuilt(lines, cage, topology);
    }
}

TEST(CageLines, EdgesNotShownStayOutThroughMovesAndTags) {
    Cage cage = test::makeGrid(4);
    const Topology topology = buildTopology(cage);
    CageLines lines;
    rebuildCageLines(lines, cage, topology, [](uint32_t e) { return e % 3 != 0; });
    const size_t shown = lines.plain.size();
    std::vector<uint32_t> all(cage.vertexCount()), faces(cage.faceCount());
    for (uint32_t i = 0; i < all.size(); ++i) all[i] = i, cage.positions[i].z = 0.1f * float(i);
    for (uint32_t f = 0; f < faces.size(); ++f) faces[f] = f;
    moveCageLines(lines, cage, topology, all);
    cage.setEdgeSharpness(topology.edgeVertices[0], topology.edgeVertices[1], 3.0f);  // edge 0: not shown
    retagCageLines(lines, cage, topology, faces);
    EXPECT_EQ(lines.plain.size(), shown);
    EXPECT_TRUE(lines.creased.empty());
}

// Plain lines are drawn while the cage's longer edges draw 8 px or more where the cage comes
// nearest the eye: a grid of unit edges seen from near, from far, from inside its box, head-on
// orthographic; creased lines are not the rule's business.
TEST(CageLines, PlainLinesAreReadableOnlyWhereTheEdgesDrawLongEnough) {
    const Cage cage = test::makeGrid(10);  // unit edges, in 0..10 x 0..10
    const Topology topology = buildTopology(cage);
    CageLines lines;
    rebuildCageLines(lines, cage, topology, {});
    EXPECT_NEAR(lines.longPlainEdge, 1.0f, 0.05f);
    const Bounds box = computeBounds(cage);
    const float pixelsPerUnit = 600.0f;  // a 600-pixel-high view, 90 degrees vertically
    auto perspective = [&](glm::vec3 eye) {
        glm::mat4 projection = glm::perspective(glm::radians(90.0f), 1.0f, 0.01f, 1000.0f);
        return projection * glm::lookAt(eye, glm::vec3(5, 5, 0), glm::vec3(0, 1, 0));
    };
    const glm::vec3 near(5, 5, 20), far(5, 5, 200);  // 30 px an edge, 3 px
    EXPECT_TRUE(plainLinesReadable(lines, box, perspective(near), near, pixelsPerUnit));
    EXPECT_FALSE(plainLinesReadable(lines, box, perspective(far), far, pixelsPerUnit));
    // Far from the middle, but the box's corner is near the eye: its edges draw long.
    const glm::vec3 besideCorner(11, 11, 5);
    EXPECT_TRUE(plainLinesReadable(lines, box, perspective(besideCorner), besideCorner, pixelsPerUnit));
    const glm::vec3 inside(5, 5, 0.1f);  // in the (flat, bumped) box
    EXPECT_TRUE(plainLinesReadable(lines, box, perspective(inside), inside, pixelsPerUnit));
    // Orthographic: w is 1 everywhere, so the scale alone decides.
    const glm::mat4 ortho = glm::ortho(-5.0f, 5.0f, -5.0f, 5.0f, 0.1f, 100.0f) *
                            glm::lookAt(glm::vec3(5, 5, 50), glm::vec3(5, 5, 0), glm::vec3(0, 1, 0));
    EXPECT_TRUE(plainLinesReadable(lines, box, ortho, glm::vec3(5, 5, 50), 60.0f));
    EXPECT_FALSE(plainLinesReadable(lines, box, ortho, glm::vec3(5, 5, 50), 6.0f));
}

}  // namespace
}  // namespace qp::editor
