// Sample grids (sample_grids.h): the sub-faces' boundary layout every displacement's tiles are
// built from, and the bilinear evaluation of scene files of version 1 (which load by fitting).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <random>

#include <glm/geometric.hpp>

#include "displacement/sample_grids.h"
#include "displacement_test_support.h"
#include "mesh/generated_cage.h"
#include "plans/face_config.h"
#include "plans/planned_cage.h"
#include "test_cages.h"

using namespace qp;
using test::Planned;
using test::testCages;

namespace {

uint32_t bits(float x) { return std::bit_cast<uint32_t>(x); }

// Random power-of-two resolutions up to maxResolution and random values in [-1, 1].
SampleGrids randomDisplacement(const PlannedCage& planned, uint32_t maxResolution, uint32_t seed) {
    std::mt19937 rng(seed);
    SampleGrids d = makeSampleGrids(planned.cage(), planned.topology(), 1);
    std::vector<uint32_t> resolutions(d.layout.subfaces.size());
    uint32_t levels = uint32_t(std::countr_zero(maxResolution)) + 1;
    for (uint32_t& r : resolutions) r = 1u << (rng() % levels);
    d.layout = withResolutions(d.layout, resolutions);
    d.samples.assign(d.layout.sampleCount, 0.0f);
    std::uniform_real_distribution<float> value(-1.0f, 1.0f);
    for (float& s : d.samples) s = value(rng);
    return d;
}

struct EdgePoint {
    glm::vec3 limit;
    float value;
    uint32_t subface, edge, i, n;
};

// Every edge point of every sub-face at i / n, n = quad factor (n-gon sub-faces: n / 2), with
// its limit position and its displacement seen from that sub-face.
std::vector<EdgePoint> edgePoints(const PlannedCage& planned, const SampleGrids& d, uint32_t quadFactor) {
    std::vector<EdgePoint> points;
    for (uint32_t face = 0; face < planned.cage().faceCount(); ++face)
        for (uint32_t s = planned.firstSubface(face); s < planned.firstSubface(face + 1); ++s) {
            if (!planned.hasSurface(s)) continue;
            uint32_t n = planned.cage().faceSize(face) == 4 ? quadFactor : quadFactor / 2;
            for (uint32_t e = 0; e < 4; ++e)
                for (uint32_t i = 0; i <= n; ++i) {
                    glm::vec2 uv = edgePoint(e, float(i) / float(n));
                    points.push_back({planned.evaluate(s, uv.x, uv.y).position,
                                      evaluateSampleGrids(d, s, uv.x, uv.y).value, s, e, i, n});
                }
        }
    return points;
}

// Pairs of items at the same place (closer than `tolerance`) from different sub-faces.
template <class T, class Position>
std::vector<std::pair<size_t, size_t>> coincident(const std::vector<T>& items, Position position, float tolerance) {
    std::vector<size_t> order(items.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return position(items[a]).x < position(items[b]).x; });
    std::vector<std::pair<size_t, size_t>> pairs;
    for (size_t a = 0; a < order.size(); ++a)
        for (size_t b = a + 1; b < order.size() && position(items[order[b]]).x - position(items[order[a]]).x <= tolerance; ++b)
            if (glm::length(position(items[order[a]]) - position(items[order[b]])) <= tolerance)
                pairs.push_back({order[a], order[b]});
    return pairs;
}

}  // namespace

TEST(SampleGrids, CountsOnACube) {
    Cage cube = test::makeCube();
    Topology topology = buildTopology(cube);
    SampleGridLayout layout = buildSampleGridLayout(cube, topology, 4);
    EXPECT_EQ(layout.pointCount, 8u + 12u + 6u);
    ASSERT_EQ(layout.segments.size(), 12u);
    for (const DisplacementSegment& s : layout.segments) {
        EXPECT_LT(s.pointA, s.pointB);
        EXPECT_EQ(s.resolution, 4u);
    }
    EXPECT_EQ(layout.sampleCount, 26u + 12u * 3u + 6u * 9u);
    for (const DisplacementSubface& sf : layout.subfaces)
        for (const DisplacementEdge& e : sf.edges) EXPECT_EQ(e.flags & (kEdgeSplit | kEdgeFiner), 0u);
}



TEST(SampleGrids, NonQuadsSplitTheirEdgesAtMidpoints) {
    Cage cage = test::makeMixedGrid();
    Topology topology = buildTopology(cage);
    SampleGridLayout layout = buildSampleGridLayout(cage, topology, 4);
    uint32_t splitQuadEdges = 0;
    for (uint32_t f = 0, s = 0; f < cage.faceCount(); s += subfaceCount(cage.faceSize(f)), ++f) {
        if (cage.faceSize(f) == 4) {
            for (const DisplacementEdge& e : layout.subfaces[s].edges)
                if (e.flags & kEdgeSplit) {
                    ++splitQuadEdges;
                    // Halves of R = 4 need 2 intervals each: the quad's grid lands on them.
                    EXPECT_EQ(layout.segments[e.segment].resolution, 4u);  // the n-gon side needs 4
                    EXPECT_TRUE(e.flags & kEdgeFiner);
                }
        } else {
            for (uint32_t k = 0; k < cage.faceSize(f); ++k) {
                const DisplacementSubface& sf = layout.subfaces[s + k];
                EXPECT_EQ(sf.corners[2], layout.vertexCount + layout.edgeCount + f);  // the centre
                for (const DisplacementEdge& e : sf.edges) EXPECT_EQ(e.flags, 0u);  // canonical, same resolution
            }
        }
    }
    EXPECT_GT(splitQuadEdges, 0u);
}



TEST(SampleGrids, GridPointsReadTheirSamples) {
    Planned p(test::makeMixedGrid());
    SampleGrids d = randomDisplacement(*p.cage, 8, 11);
    for (uint32_t s = 0; s < d.layout.subfaces.size(); ++s) {
        const uint32_t R = d.layout.subfaces[s].resolution;
        for (uint32_t j = 0; j <= R; ++j)
            for (uint32_t i = 0; i <= R; ++i) {
                float value = evaluateSampleGrids(d, s, float(i) / float(R), float(j) / float(R)).value;
                ASSERT_EQ(bits(value), bits(d.samples[gridSample(d.layout, s, i, j)])) << s << " " << i << " " << j;
            }
    }
}

// The renderers' per-sub-face evaluator (gathered grid, inline bilinear inside) returns
// evaluateSampleGrids's bits: on grid lines and edges, in the strips of edges finer than the
// grid, at random points, and clamped outside [0, 1].


// The storage promise: the same point of a shared edge reads the same bits from every side,
// at any tessellation, whatever the resolutions on either side, across n-gon sub-faces and
// extraordinary vertices.
TEST(SampleGrids, SharedEdgePointsAreBitIdenticalFromEverySide) {
    for (auto& [name, cage] : testCages()) {
        Planned p(cage);
        const float diagonal = computeBounds(cage).diagonal();
        for (uint32_t seed : {1u, 2u}) {
            SampleGrids d = randomDisplacement(*p.cage, 16, seed);
            for (uint32_t factor : {2u, 4u, 6u, 10u, 14u, 16u, 22u, 32u, 46u, 64u}) {
                std::vector<EdgePoint> points = edgePoints(*p.cage, d, factor);
                auto pairs = coincident(points, [](const EdgePoint& e) { return e.limit; }, 1e-5f * diagonal);
                uint32_t compared = 0;
                for (auto [a, b] : pairs) {
                    if (points[a].subface == points[b].subface && points[a].edge == points[b].edge) continue;
                    ++compared;
                    ASSERT_EQ(bits(points[a].value), bits(points[b].value))
                        << name << ", factor " << factor << ": sub-face " << points[a].subface << " edge "
                        << points[a].edge << " point " << points[a].i << "/" << points[a].n << " reads " << points[a].value
                        << ", sub-face " << points[b].subface << " edge " << points[b].edge << " point " << points[b].i
                        << "/" << points[b].n << " reads " << points[b].value;
                }
                EXPECT_GT(compared, points.size() / 4) << name << ", factor " << factor;
            }
        }
    }
}

// Parameters that are not exact complements (i/n from both ends, n not a power of two) still
// agree thanks to the snap; the pair (t, 1 - t) computed in float is the hard case.
