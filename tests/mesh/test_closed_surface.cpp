// closedOutwardSurface (core/mesh/closed_surface.h): back-patch culling is allowed only on a closed,
// consistently oriented cage whose every piece encloses a positive volume.
#include <gtest/gtest.h>

#include <algorithm>

#include "mesh/closed_surface.h"
#include "scheme_test_support.h"
#include "test_cages.h"

using namespace qp;

namespace {

bool cullable(const Cage& cage) { return closedOutwardSurface(cage, buildTopology(cage)); }

void reverseFace(Cage& cage, uint32_t f) {
    std::reverse(cage.faceVertices.begin() + cage.faceOffsets[f], cage.faceVertices.begin() + cage.faceOffsets[f + 1]);
}

Cage reversed(Cage cage) {
    for (uint32_t f = 0; f < cage.faceCount(); ++f) reverseFace(cage, f);
    return cage;
}

// Two copies of `cage`, the second moved by `offset` (two pieces).
Cage twoPieces(const Cage& first, const Cage& second, const glm::vec3& offset) {
    Cage out = first;
    const uint32_t base = out.vertexCount();
    for (const glm::vec3& p : second.positions) out.positions.push_back(p + offset);
    for (uint32_t f = 0; f < second.faceCount(); ++f) {
        std::vector<uint32_t> face(second.faceBegin(f), second.faceBegin(f) + second.faceSize(f));
        for (uint32_t& v : face) v += base;
        out.addFace(face.data(), uint32_t(face.size()));
    }
    return out;
}

}  // namespace

TEST(ClosedSurface, OutwardClosedCagesAreCullable) {
    EXPECT_TRUE(cullable(test::makeTorus()));
    EXPECT_TRUE(cullable(test::makeSubdividedCube(2)));
    EXPECT_TRUE(cullable(twoPieces(test::makeTorus(), test::makeSubdividedCube(2), glm::vec3(10, 0, 0))));
}

TEST(ClosedSurface, OpenHoledInsideOutOrMixedCagesAreNot) {
    EXPECT_FALSE(cullable(test::makeGrid(3))) << "open";
    Cage holed = test::makeTorus();
    holed.setHole(0, true);
    EXPECT_FALSE(cullable(holed)) << "a hole opens it";
    EXPECT_FALSE(cullable(reversed(test::makeTorus()))) << "inside out";
    Cage mixed = test::makeSubdividedCube(2);
    reverseFace(mixed, 3);
    EXPECT_FALSE(cullable(mixed)) << "one face turned";
    EXPECT_FALSE(cullable(twoPieces(test::makeTorus(), reversed(test::makeSubdividedCube(2)), glm::vec3(10, 0, 0))))
        << "one piece inside out";
}

TEST(ClosedSurface, AFlatClosedSheetIsNot) {
    // Two squares back to back: closed and consistently oriented, but enclosing nothing.
    Cage sheet;
    sheet.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const uint32_t front[4] = {0, 1, 2, 3}, back[4] = {3, 2, 1, 0};
    sheet.addFace(front, 4);
    sheet.addFace(back, 4);
    EXPECT_FALSE(cullable(sheet));
}
