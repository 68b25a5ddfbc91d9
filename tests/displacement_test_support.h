// What the displacement tests share: a planned cage with its database, and the tile edges on
// each boundary segment, so that a test can visit both sides of every shared edge at the same
// point.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "displacement/displacement.h"
#include "mesh/generated_cage.h"
#include "plans/planned_cage.h"
#include "test_cages.h"

namespace qp::test {

// The test cages: a boundary, valence-3 EVs, non-quads with EVs, and a closed cage with
// triangles, valence-5 EVs, creases and corners.
inline std::vector<std::pair<std::string, Cage>> testCages() {
    return {{"grid", makeGrid(3)},
            {"subdivided cube", makeSubdividedCube(2)},
            {"mixed grid", makeMixedGrid()},
            {"benchmark cage", makeBenchmarkCage(120, 3)}};
}

// A cage planned with default options (the test fails when it cannot be).
struct Planned {
    PlanDatabase database;
    std::optional<PlannedCage> cage;
    explicit Planned(const Cage& c) {
        auto planned = PlannedCage::create(c, database, PlanOptions{}, "test cage");
        EXPECT_TRUE(planned) << planned.error().message;
        if (planned) cage.emplace(std::move(planned).value());
    }
};

// A tile edge on a segment: a whole sub-face edge, or one half of a split one.
struct SegmentSide {
    uint32_t tile, edge;
    int half;  // -1: a whole edge; 0, 1: the half of a split edge at its start or end corner
    // The parameter along the tile edge of canonical parameter s on the segment.
    float along(const DisplacementLayout& layout, float s) const {
        const DisplacementEdge& e = layout.adjacency.subfaces[tile].edges[edge];
        if (half < 0) return e.flags & kEdgeReversed ? 1.0f - s : s;
        return half == 0 ? 0.5f * s : 1.0f - 0.5f * s;
    }
};

// Per segment of the layout, the tile edges on it (of the tiles `keep` accepts).
template <class Keep>
std::vector<std::vector<SegmentSide>> segmentSides(const DisplacementLayout& layout, const Keep& keep) {
    std::vector<std::vector<SegmentSide>> sides(layout.adjacency.segments.size());
    for (uint32_t t = 0; t < layout.tiles.size(); ++t) {
        if (!keep(t)) continue;
        for (uint32_t e = 0; e < 4; ++e) {
            const DisplacementEdge& edge = layout.adjacency.subfaces[t].edges[e];
            if (edge.flags & kEdgeSplit) {
                sides[edge.segment].push_back({t, e, 0});
                sides[edge.secondHalf].push_back({t, e, 1});
            } else {
                sides[edge.segment].push_back({t, e, -1});
            }
        }
    }
    return sides;
}
inline std::vector<std::vector<SegmentSide>> segmentSides(const DisplacementLayout& layout) {
    return segmentSides(layout, [](uint32_t) { return true; });
}

}  // namespace qp::test
