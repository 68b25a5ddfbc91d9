// Analytic displacement tiles: C1 across every sub-face edge, a vanishing gradient at irregular
// corners, copies that follow their homes, and fitting that reproduces bi-quadratics.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <random>

#include "displacement_tiles.h"
#include "generated_cage.h"
#include "planned_cage.h"
#include "sculpt_samples.h"
#include "test_cages.h"
#include "topology.h"

using namespace qp;

namespace {

struct Tiled {
    Cage cage;
    Topology topology;
    DisplacementLayout adjacency;
    TileLayout tiles;
    std::vector<float> coefficients;
};

Tiled randomTiles(Cage cage, uint32_t resolution, uint32_t seed) {
    Tiled t{std::move(cage), {}, {}, {}, {}};
    t.topology = buildTopology(t.cage);
    t.adjacency = buildDisplacementLayout(t.cage, t.topology, 1);
    t.tiles = buildTileLayout(t.adjacency, std::max(resolution, minimumTileResolution(t.adjacency)));
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> value(-1.0f, 1.0f);
    t.coefficients.assign(t.tiles.coefficientCount(), 0.0f);
    for (uint32_t x = 0; x < t.tiles.coefficientCount(); ++x)
        if (t.tiles.home[x] == x) t.coefficients[x] = value(rng);
    propagateAllCopies(t.tiles, t.coefficients);
    return t;
}

std::vector<std::pair<std::string, Cage>> testCages() {
    return {{"grid (boundary)", test::makeGrid(3)},
            {"subdivided cube (valence 3)", test::makeSubdividedCube(2)},
            {"mixed grid (triangle, pentagon)", test::makeMixedGrid()},
            {"benchmark cage (valence 5, triangles)", makeBenchmarkCage(120, 3)}};
}

// D's derivative into the tile, across edge e, per cell.
float inward(const DisplacementValue& d, uint32_t e, uint32_t cells) {
    const float perCell = 1.0f / float(cells);
    switch (e) {
    case 0: return d.dv * perCell;
    case 1: return -d.du * perCell;
    case 2: return -d.dv * perCell;
    default: return d.du * perCell;
    }
}

bool sameDirection(const DisplacementLayout& adjacency, uint32_t t, uint32_t e, uint32_t t2, uint32_t e2) {
    const auto& a = adjacency.subfaces[t].corners;
    const auto& b = adjacency.subfaces[t2].corners;
    return a[kEdgeStart[e]] == b[kEdgeStart[e2]] || a[kEdgeEnd[e]] == b[kEdgeEnd[e2]];
}

}  // namespace

TEST(DisplacementTiles, ValueAndCrossDerivativeAreContinuousAcrossEverySharedEdge) {
    for (const auto& [name, cage] : testCages()) {
        for (uint32_t resolution : {2u, 4u, 8u}) {
            const Tiled t = randomTiles(cage, resolution, 7 + resolution);
            const TileAdjacency adjacency(t.adjacency, t.tiles);
            uint32_t checked = 0;
            float worstValue = 0.0f, worstSlope = 0.0f;
            for (uint32_t tile = 0; tile < t.tiles.tiles.size(); ++tile) {
                const uint32_t n = t.tiles.tiles[tile].cells;
                for (uint32_t e = 0; e < 4; ++e)
                    for (int m = 0; m < int(n); ++m) {
                        const std::optional<TileEdgeCell> other = adjacency.across(tile, e, m);
                        if (!other) continue;
                        const uint32_t n2 = t.tiles.tiles[other->tile].cells;
                        const bool same = sameDirection(t.adjacency, tile, e, other->tile, other->edge);
                        for (float s : {0.0f, 0.25f, 0.5f, 0.9f, 1.0f}) {
                            const float s2 = same ? s : 1.0f - s;
                            const glm::vec2 a = edgePoint(e, (float(m) + s) / float(n));
                            const glm::vec2 b = edgePoint(other->edge, (float(other->along) + s2) / float(n2));
                            const DisplacementValue da = evaluateTile(t.tiles, t.coefficients, tile, a.x, a.y);
                            const DisplacementValue db = evaluateTile(t.tiles, t.coefficients, other->tile, b.x, b.y);
                            worstValue = std::max(worstValue, std::abs(da.value - db.value));
                            worstSlope = std::max(worstSlope, std::abs(inward(da, e, n) + inward(db, other->edge, n2)));
                            ++checked;
                        }
                    }
            }
            EXPECT_GT(checked, 0u) << name;
            EXPECT_LT(worstValue, 2e-6f) << name << " R=" << resolution;
            EXPECT_LT(worstSlope, 2e-6f) << name << " R=" << resolution;
        }
    }
}

TEST(DisplacementTiles, GradientVanishesAtIrregularCornersAndTheyShareOneValue) {
    for (const auto& [name, cage] : testCages()) {
        const Tiled t = randomTiles(cage, 4, 3);
        uint32_t shared = 0;
        for (uint32_t x = 0; x < t.tiles.coefficientCount(); ++x) {
            if (t.tiles.sharedCorner[x] == kNoTileCorner) continue;
            ++shared;
            // Every tile corner at this point: value = the shared coefficient, gradient zero.
            const uint32_t point = t.adjacency.subfaces[t.tiles.sharedCorner[x] >> 2].corners[t.tiles.sharedCorner[x] & 3];
            for (uint32_t tile = 0; tile < t.adjacency.subfaces.size(); ++tile)
                for (uint32_t k = 0; k < 4; ++k) {
                    if (t.adjacency.subfaces[tile].corners[k] != point) continue;
                    const DisplacementValue d = evaluateTile(t.tiles, t.coefficients, tile, kCornerU[k], kCornerV[k]);
                    EXPECT_FLOAT_EQ(d.value, t.coefficients[x]) << name;
                    EXPECT_EQ(d.du, 0.0f) << name;
                    EXPECT_EQ(d.dv, 0.0f) << name;
                }
        }
        if (name.find("grid (boundary)") == std::string::npos) EXPECT_GT(shared, 0u) << name << ": has irregular corners";
    }
}

TEST(DisplacementTiles, RegularCornersKeepTheirGradient) {
    // A regular interior vertex of the grid: no shared value, and a random D has a gradient there.
    const Tiled t = randomTiles(test::makeGrid(3), 4, 11);
    uint32_t sharedInside = 0;
    for (uint32_t x = 0; x < t.tiles.coefficientCount(); ++x)
        if (t.tiles.sharedCorner[x] != kNoTileCorner) {
            const uint32_t point = t.adjacency.subfaces[t.tiles.sharedCorner[x] >> 2].corners[t.tiles.sharedCorner[x] & 3];
            sharedInside += point == 5 || point == 6 || point == 9 || point == 10;  // the 4x4 grid's interior vertices
        }
    EXPECT_EQ(sharedInside, 0u);
}

TEST(DisplacementTiles, CopiesFollowTheirHomes) {
    Tiled t = randomTiles(test::makeMixedGrid(), 4, 5);
    std::vector<uint32_t> changed;
    for (uint32_t x = 0; x < t.tiles.coefficientCount(); x += 7)
        if (t.tiles.home[x] == x) {
            t.coefficients[x] += 1.0f;
            changed.push_back(x);
        }
    propagateCopies(t.tiles, t.coefficients, changed);
    for (uint32_t x = 0; x < t.tiles.coefficientCount(); ++x)
        EXPECT_EQ(t.coefficients[x], t.coefficients[t.tiles.home[x]]) << x;
    // Every own cell is a home or a copy of one; every copy is listed under its home.
    uint32_t listed = 0;
    for (uint32_t x = 0; x < t.tiles.coefficientCount(); ++x) {
        EXPECT_EQ(t.tiles.home[t.tiles.home[x]], t.tiles.home[x]);
        listed += t.tiles.copyOffsets[x + 1] - t.tiles.copyOffsets[x];
    }
    uint32_t copies = 0;
    for (uint32_t x = 0; x < t.tiles.coefficientCount(); ++x) copies += t.tiles.home[x] != x;
    EXPECT_EQ(listed, copies);
}

TEST(DisplacementTiles, FittingReproducesABiquadraticInsideAndAHomeSitsInItsCell) {
    // On a flat grid's interior tile, f = a bi-quadratic of (u, v) continued across the tiles
    // (the grid's tiles are unit squares side by side): the fit reproduces it exactly there.
    const Cage cage = test::makeGrid(3);
    const Topology topology = buildTopology(cage);
    const DisplacementLayout adjacency = buildDisplacementLayout(cage, topology, 1);
    const TileLayout tiles = buildTileLayout(adjacency, 4);
    // Tile t of the 3 x 3 grid covers [t % 3, t % 3 + 1] x [t / 3, t / 3 + 1] with its corner 0 at
    // cage vertex corners[0]; the world (x, y) of (u, v) from the cage's own positions.
    auto world = [&](uint32_t tile, float u, float v) {
        const auto& c = adjacency.subfaces[tile].corners;
        const glm::vec3 p0 = cage.positions[c[0]], p1 = cage.positions[c[1]], p3 = cage.positions[c[3]];
        return p0 + u * (p1 - p0) + v * (p3 - p0);
    };
    auto f = [&](uint32_t tile, float u, float v) {
        const glm::vec3 p = world(tile, u, v);
        return 0.3f * p.x * p.x - 0.2f * p.x * p.y + 0.1f * p.y * p.y + 0.5f * p.x - 0.25f;
    };
    const std::vector<float> c = fitTiles(tiles, f);
    // The middle tile (its overlap is all interior): exact at any point.
    uint32_t middle = UINT32_MAX;
    for (uint32_t s = 0; s < adjacency.subfaces.size(); ++s) {
        const glm::vec3 centre = world(s, 0.5f, 0.5f);
        const glm::vec3 gridCentre = 0.5f * (cage.positions[0] + cage.positions[15]);
        if (glm::length(glm::vec2(centre - gridCentre)) < 1e-4f) middle = s;
    }
    ASSERT_NE(middle, UINT32_MAX);
    for (float u : {0.0f, 0.1f, 0.5f, 0.77f, 1.0f})
        for (float v : {0.0f, 0.3f, 0.5f, 1.0f})
            EXPECT_NEAR(evaluateTile(tiles, c, middle, u, v).value, f(middle, u, v), 1e-5f) << u << " " << v;
    // Sites: inside their tile, at a cell centre.
    for (uint32_t x = 0; x < tiles.coefficientCount(); ++x) {
        if (tiles.home[x] != x) continue;
        const CoefficientSite site = homeSite(tiles, x);
        EXPECT_GE(site.u, 0.0f);
        EXPECT_LE(site.u, 1.0f);
        EXPECT_GE(site.v, 0.0f);
        EXPECT_LE(site.v, 1.0f);
    }
}

// Positions need the same bits from every tile that has the point: along every segment (whole
// edges and the halves of split ones) at canonical parameters on and between knots, and at
// every corner point from every tile around it.
TEST(DisplacementTiles, SharedEdgesAndCornersGiveTheSameBitsFromEverySide) {
    for (const auto& [name, cage] : testCages())
        for (uint32_t resolution : {2u, 4u, 8u}) {
            const Tiled t = randomTiles(cage, resolution, 11);
            // Segment -> the tile edges on it, with how a canonical parameter s maps to theirs.
            struct Side {
                uint32_t tile, edge;
                int half;  // -1: a whole edge; 0, 1: the half of a split edge
            };
            std::vector<std::vector<Side>> sides(t.adjacency.segments.size());
            for (uint32_t tile = 0; tile < t.adjacency.subfaces.size(); ++tile)
                for (uint32_t e = 0; e < 4; ++e) {
                    const DisplacementEdge& edge = t.adjacency.subfaces[tile].edges[e];
                    if (edge.flags & kEdgeSplit) {
                        sides[edge.segment].push_back({tile, e, 0});
                        sides[edge.secondHalf].push_back({tile, e, 1});
                    } else {
                        sides[edge.segment].push_back({tile, e, -1});
                    }
                }
            uint32_t compared = 0;
            for (uint32_t segment = 0; segment < sides.size(); ++segment) {
                if (sides[segment].size() < 2) continue;
                for (uint32_t q = 0; q <= 64; ++q) {
                    const float s = float(q) / 64.0f;  // canonical: from the segment's lower point
                    std::vector<uint32_t> bits;
                    for (const Side& side : sides[segment]) {
                        const DisplacementEdge& edge = t.adjacency.subfaces[side.tile].edges[side.edge];
                        const float along = side.half < 0 ? (edge.flags & kEdgeReversed ? 1.0f - s : s)
                                                          : (side.half == 0 ? 0.5f * s : 1.0f - 0.5f * s);
                        const glm::vec2 uv = edgePoint(side.edge, along);
                        bits.push_back(std::bit_cast<uint32_t>(
                            evaluateTileValue(t.tiles, t.adjacency, t.coefficients, side.tile, uv.x, uv.y)));
                    }
                    for (uint32_t b : bits) ASSERT_EQ(b, bits[0]) << name << " R " << resolution << " segment " << segment << " s " << s;
                    ++compared;
                }
            }
            EXPECT_GT(compared, 0u) << name;
            // Corner points from every tile around them.
            std::vector<std::vector<uint32_t>> cornerBits(t.adjacency.pointCount);
            for (uint32_t tile = 0; tile < t.adjacency.subfaces.size(); ++tile)
                for (uint32_t k = 0; k < 4; ++k)
                    cornerBits[t.adjacency.subfaces[tile].corners[k]].push_back(std::bit_cast<uint32_t>(
                        evaluateTileValue(t.tiles, t.adjacency, t.coefficients, tile, kCornerU[k], kCornerV[k])));
            for (uint32_t p = 0; p < cornerBits.size(); ++p)
                for (uint32_t b : cornerBits[p]) ASSERT_EQ(b, cornerBits[p][0]) << name << " R " << resolution << " point " << p;
            // On an edge between knots the value is the B-spline's, up to rounding, at parameters
            // on the 2^-14 grid the canonical parameter is snapped to.
            const float u = 0.3125f;
            const DisplacementValue spline = evaluateTile(t.tiles, t.coefficients, 0, u, 0.0f);
            EXPECT_NEAR(evaluateTileValue(t.tiles, t.adjacency, t.coefficients, 0, u, 0.0f), spline.value, 1e-5f) << name;
        }
}

// The tiles a home's change reaches are exactly those whose D changes: change one home, compare
// every tile's values before and after.
TEST(DisplacementTiles, TilesReadingAHomeAreTheTilesItChanges) {
    for (const auto& [name, cage] : testCages()) {
        Tiled t = randomTiles(cage, 4, 3);
        for (uint32_t x = 0; x < t.tiles.coefficientCount(); x += 37) {
            const uint32_t home = t.tiles.home[x];
            std::vector<float> changed = t.coefficients;
            changed[home] += 1.0f;
            propagateCopies(t.tiles, changed, std::span(&home, 1));
            std::vector<uint32_t> expected;
            for (uint32_t tile = 0; tile < t.tiles.tiles.size(); ++tile) {
                const DisplacementTile& d = t.tiles.tiles[tile];
                const uint32_t size = (d.cells + 2) * (d.cells + 2);
                if (!std::equal(changed.begin() + d.offset, changed.begin() + d.offset + size, t.coefficients.begin() + d.offset))
                    expected.push_back(tile);
            }
            EXPECT_EQ(tilesReadingHomes(t.tiles, std::span(&home, 1)), expected) << name << " coefficient " << x;
        }
    }
}

// Converting today's sample grids (file version 1): the fitted tiles stay close to the grids'
// bilinear D they replace. Grids of 16 samples per side sampled from tiles of 2 random cells
// (relief varying over half a face), fitted with 16 cells: 1.3-2.3% of the relief, the
// smoothing of the bilinear kinks. (At 4 samples per side it is 10-14%: the quasi-interpolant
// does not pass through the samples; an interpolating fit would.)
TEST(DisplacementTiles, SampleGridsFitCloseToTheirBilinearD) {
    for (const auto& [name, cage] : testCages()) {
        Tiled smooth = randomTiles(cage, 2, 21);
        PlanDatabase database;
        Result<PlannedCage> planned = PlannedCage::create(smooth.cage, database, PlanOptions{}, name);
        ASSERT_TRUE(planned) << planned.error().message;
        Displacement grids = makeDisplacement(smooth.cage, smooth.topology, 16);
        const std::vector<SampleSite> sites = computeSampleSites(grids.layout, *planned);
        for (uint32_t i = 0; i < grids.samples.size(); ++i)
            if (sites[i].subface != kNoSite)
                grids.samples[i] =
                    evaluateTileValue(smooth.tiles, smooth.adjacency, smooth.coefficients, sites[i].subface, sites[i].u, sites[i].v);
        const TileLayout fine = buildTileLayout(smooth.adjacency, 16);
        const std::vector<float> fitted = fitSampleGrids(fine, grids);
        float worst = 0.0f, range = 0.0f;
        for (uint32_t s = 0; s < fine.tiles.size(); ++s)
            for (uint32_t j = 0; j <= 12; ++j)
                for (uint32_t i = 0; i <= 12; ++i) {
                    const float u = float(i) / 12.0f, v = float(j) / 12.0f;
                    const float had = evaluateDisplacement(grids, s, u, v).value;
                    worst = std::max(worst, std::abs(evaluateTile(fine, fitted, s, u, v).value - had));
                    range = std::max(range, std::abs(had));
                }
        std::printf("%s: the fit within %.4f of the bilinear D (relief %.3f)\n", name.c_str(), worst, range);
        EXPECT_LT(worst, 0.03f * range) << name;
    }
}
