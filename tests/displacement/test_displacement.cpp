// Displacement tiles (displacement.h): C1 across every sub-face edge, a vanishing gradient at
// irregular corners, the same bits on shared edges, fitting and resampling, which tiles read a
// sample, and the watertight displaced mesh.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "displacement/displaced_mesh.h"
#include "displacement/displacement.h"
#include "displacement/displacement_users.h"
#include "displacement/sculpt_samples.h"
#include "displacement_test_support.h"
#include "mesh/generated_cage.h"
#include "plans/planned_cage.h"
#include "test_cages.h"

using namespace qp;
using test::Planned;
using test::testCages;
using test::SegmentSide;
using test::segmentSides;

namespace {

uint32_t bits(float x) { return std::bit_cast<uint32_t>(x); }

Displacement randomDisplacement(const Cage& cage, uint32_t resolution, uint32_t seed, float scale = 1.0f) {
    std::mt19937 rng(seed);
    Displacement d = makeDisplacement(cage, buildTopology(cage), resolution);
    std::uniform_real_distribution<float> value(-scale, scale);
    for (float& s : d.samples) s = value(rng);
    return d;
}

// D's derivative into the tile across edge e, per cell.
float inward(const DisplacementValue& d, uint32_t e, uint32_t cells) {
    const float perCell = 1.0f / float(cells);
    switch (e) {
    case 0: return d.dv * perCell;
    case 1: return -d.du * perCell;
    case 2: return -d.dv * perCell;
    default: return d.du * perCell;
    }
}

}  // namespace

TEST(DisplacementTiles, ValueAndCrossDerivativeAreContinuousAcrossEverySharedEdge) {
    for (const auto& [name, cage] : testCages())
        for (uint32_t resolution : {2u, 4u, 8u}) {
            const Displacement d = randomDisplacement(cage, resolution, 7 + resolution);
            uint32_t checked = 0;
            float worstValue = 0.0f, worstSlope = 0.0f;
            for (const std::vector<SegmentSide>& sides : segmentSides(d.layout)) {
                if (sides.size() != 2) continue;  // boundaries and non-manifold edges
                const SegmentSide& a = sides[0];
                const SegmentSide& b = sides[1];
                for (uint32_t q = 1; q < 40; ++q) {
                    const float s = float(q) / 40.0f;
                    const glm::vec2 pa = edgePoint(a.edge, a.along(d.layout, s)), pb = edgePoint(b.edge, b.along(d.layout, s));
                    const DisplacementValue da = evaluateDisplacement(d, a.tile, pa.x, pa.y);
                    const DisplacementValue db = evaluateDisplacement(d, b.tile, pb.x, pb.y);
                    worstValue = std::max(worstValue, std::abs(da.value - db.value));
                    worstSlope = std::max(worstSlope, std::abs(inward(da, a.edge, d.layout.tiles[a.tile].cells) +
                                                               inward(db, b.edge, d.layout.tiles[b.tile].cells)));
                    ++checked;
                }
            }
            EXPECT_GT(checked, 0u) << name;
            EXPECT_LT(worstValue, 2e-6f) << name << " R=" << resolution;
            EXPECT_LT(worstSlope, 2e-6f) << name << " R=" << resolution;
        }
}

TEST(DisplacementTiles, GradientVanishesAtIrregularCornersAndTheyShareOneValue) {
    for (const auto& [name, cage] : testCages()) {
        const Displacement d = randomDisplacement(cage, 4, 3);
        const DisplacementLayout& layout = d.layout;
        uint32_t shared = 0;
        for (uint32_t s = 0; s < layout.sampleCount; ++s) {
            const SampleHome& home = layout.homes[s];
            if (home.corner < 0) continue;
            ++shared;
            // Every tile corner at this point: value = the shared sample, gradient zero.
            const uint32_t point = layout.adjacency.subfaces[home.tile].corners[home.corner];
            for (uint32_t tile = 0; tile < layout.tiles.size(); ++tile)
                for (uint32_t k = 0; k < 4; ++k) {
                    if (layout.adjacency.subfaces[tile].corners[k] != point) continue;
                    const DisplacementValue v = evaluateDisplacement(d, tile, kCornerU[k], kCornerV[k]);
                    EXPECT_FLOAT_EQ(v.value, d.samples[s]) << name;
                    EXPECT_EQ(v.du, 0.0f) << name;
                    EXPECT_EQ(v.dv, 0.0f) << name;
                }
        }
        if (name != "grid") {
            EXPECT_GT(shared, 0u) << name << ": has irregular corners";
        }
    }
    // The grid's interior vertices are regular: no shared sample there.
    const Displacement grid = randomDisplacement(test::makeGrid(3), 4, 11);
    for (const SampleHome& home : grid.layout.homes)
        if (home.corner >= 0) {
            const uint32_t point = grid.layout.adjacency.subfaces[home.tile].corners[home.corner];
            EXPECT_FALSE(point == 5 || point == 6 || point == 9 || point == 10) << point;  // the 4x4 grid's interior
        }
}

// Positions need the same bits from every tile that has the point: along every segment at
// canonical parameters on and between knots, and at every corner point from every tile around it.
TEST(DisplacementTiles, SharedEdgesAndCornersGiveTheSameBitsFromEverySide) {
    for (const auto& [name, cage] : testCages())
        for (uint32_t resolution : {2u, 4u, 8u}) {
            const Displacement d = randomDisplacement(cage, resolution, 11);
            uint32_t compared = 0;
            for (const std::vector<SegmentSide>& sides : segmentSides(d.layout)) {
                if (sides.size() < 2) continue;
                for (uint32_t q = 0; q <= 64; ++q) {
                    const float s = float(q) / 64.0f;
                    std::vector<uint32_t> seen;
                    for (const SegmentSide& side : sides) {
                        const glm::vec2 uv = edgePoint(side.edge, side.along(d.layout, s));
                        seen.push_back(bits(evaluateDisplacement(d, side.tile, uv.x, uv.y).value));
                    }
                    for (uint32_t b : seen) ASSERT_EQ(b, seen[0]) << name << " R " << resolution << " s " << s;
                    ++compared;
                }
            }
            EXPECT_GT(compared, 0u) << name;
            std::vector<std::vector<uint32_t>> cornerBits(d.layout.adjacency.pointCount);
            for (uint32_t tile = 0; tile < d.layout.tiles.size(); ++tile)
                for (uint32_t k = 0; k < 4; ++k)
                    cornerBits[d.layout.adjacency.subfaces[tile].corners[k]].push_back(
                        bits(evaluateDisplacement(d, tile, kCornerU[k], kCornerV[k]).value));
            for (uint32_t p = 0; p < cornerBits.size(); ++p)
                for (uint32_t b : cornerBits[p]) ASSERT_EQ(b, cornerBits[p][0]) << name << " R " << resolution << " point " << p;
            // SubfaceDisplacement has the same bits everywhere, edges included.
            for (uint32_t tile = 0; tile < d.layout.tiles.size(); tile += 3) {
                const SubfaceDisplacement fast(d, tile);
                for (uint32_t j = 0; j <= 8; ++j)
                    for (uint32_t i = 0; i <= 8; ++i) {
                        const float u = float(i) / 8.0f, v = float(j) / 8.0f;
                        const DisplacementValue a = evaluateDisplacement(d, tile, u, v), b = fast.evaluate(u, v);
                        ASSERT_EQ(bits(a.value), bits(b.value));
                        ASSERT_EQ(bits(a.du), bits(b.du));
                        ASSERT_EQ(bits(a.dv), bits(b.dv));
                        if (i > 0 && i < 8 && j > 0 && j < 8) {
                            ASSERT_EQ(bits(fast.inside(u, v).value), bits(a.value));
                        }
                    }
            }
        }
}

TEST(DisplacementTiles, DerivativesMatchFiniteDifferences) {
    const Displacement d = randomDisplacement(test::makeMixedGrid(), 4, 2);
    const float h = 1e-3f;
    for (uint32_t s = 0; s < d.layout.tiles.size(); ++s)
        for (float u : {0.2f, 0.52f, 0.8f})
            for (float v : {0.33f, 0.71f}) {
                const DisplacementValue at = evaluateDisplacement(d, s, u, v);
                EXPECT_NEAR(at.du, (evaluateDisplacement(d, s, u + h, v).value - evaluateDisplacement(d, s, u - h, v).value) / (2 * h), 2e-2f);
                EXPECT_NEAR(at.dv, (evaluateDisplacement(d, s, u, v + h).value - evaluateDisplacement(d, s, u, v - h).value) / (2 * h), 2e-2f);
            }
}

TEST(DisplacementTiles, FittingReproducesABiquadraticAndSamplesSitInTheirCells) {
    // On a flat grid's middle tile, f = a bi-quadratic of the world (x, y) continued across the
    // tiles: the fit reproduces it exactly there (its overlap is interior too).
    const Cage cage = test::makeGrid(3);
    const DisplacementLayout layout = buildDisplacementLayout(cage, buildTopology(cage), 4);
    auto world = [&](uint32_t tile, float u, float v) {
        const auto& c = layout.adjacency.subfaces[tile].corners;
        const glm::vec3 p0 = cage.positions[c[0]], p1 = cage.positions[c[1]], p3 = cage.positions[c[3]];
        return p0 + u * (p1 - p0) + v * (p3 - p0);
    };
    auto f = [&](uint32_t tile, float u, float v) {
        const glm::vec3 p = world(tile, u, v);
        return 0.3f * p.x * p.x - 0.2f * p.x * p.y + 0.1f * p.y * p.y + 0.5f * p.x - 0.25f;
    };
    Displacement d;
    d.layout = layout;
    d.samples = fitSamples(layout, f);
    uint32_t middle = UINT32_MAX;
    const glm::vec3 gridCentre = 0.5f * (cage.positions[0] + cage.positions[15]);
    for (uint32_t s = 0; s < layout.tiles.size(); ++s)
        if (glm::length(glm::vec2(world(s, 0.5f, 0.5f) - gridCentre)) < 1e-4f) middle = s;
    ASSERT_NE(middle, UINT32_MAX);
    for (float u : {0.0f, 0.1f, 0.5f, 0.77f, 1.0f})
        for (float v : {0.0f, 0.3f, 0.5f, 1.0f}) {
            // On an edge the parameter is snapped to 2^-14 (the shared-edge bits): D moves by the
            // slope along the edge times at most 2^-15.
            const DisplacementValue at = evaluateDisplacement(d, middle, u, v);
            const bool onEdge = u == 0.0f || u == 1.0f || v == 0.0f || v == 1.0f;
            const float snap = onEdge ? (std::abs(at.du) + std::abs(at.dv)) * std::ldexp(1.0f, -15) : 0.0f;
            EXPECT_NEAR(at.value, f(middle, u, v), 1e-5f + snap) << u << " " << v;
        }
    for (uint32_t s = 0; s < layout.sampleCount; ++s) {
        const SampleSite site = sampleSite(layout, s);
        EXPECT_EQ(site.subface, layout.homes[s].tile);
        EXPECT_TRUE(site.u >= 0.0f && site.u <= 1.0f && site.v >= 0.0f && site.v <= 1.0f);
        // The sample is a coefficient of its own tile's block.
        EXPECT_EQ(layout.sampleAt(site.subface, layout.homes[s].i, layout.homes[s].j), s);
    }
}

// Raising R refines the B-spline: the fit reproduces a spline of the coarser space exactly, away
// from irregular corners (whose shared samples are not in the finer space); the mask follows.
TEST(DisplacementTiles, RaisingTheResolutionKeepsTheSurface) {
    for (const auto& [name, cage] : testCages()) {
        Displacement d = randomDisplacement(cage, 2, 4);
        d.mask.assign(d.samples.size(), 0.0f);
        for (uint32_t s = 0; s < d.mask.size(); s += 3) d.mask[s] = 1.0f;
        const Displacement raised = resampleDisplacement(d, 8);
        EXPECT_EQ(raised.resolution(), 8u);
        ASSERT_EQ(raised.mask.size(), raised.samples.size());
        for (float m : raised.mask) EXPECT_TRUE(m >= 0.0f && m <= 1.0f);
        float worst = 0.0f;
        for (uint32_t s = 0; s < d.layout.tiles.size(); ++s)
            for (float u : {0.3f, 0.5f, 0.7f})
                for (float v : {0.3f, 0.45f, 0.6f})
                    worst = std::max(worst, std::abs(evaluateDisplacement(raised, s, u, v).value -
                                                     evaluateDisplacement(d, s, u, v).value));
        // Random samples of +-1: the inner part of a 2-cell tile reads corner cells, so irregular
        // corners reach it; regular cages (the grid) are exact.
        if (name == "grid") EXPECT_LT(worst, 1e-5f) << name;
        else EXPECT_LT(worst, 0.5f) << name;
        EXPECT_EQ(resampleDisplacement(d, 2), d);
    }
}

// The sub-faces reading a sample are exactly those whose D changes when it changes.
TEST(DisplacementTiles, UsersAreTheSubfacesASampleChanges) {
    for (const auto& [name, cage] : testCages()) {
        const Displacement d = randomDisplacement(cage, 4, 3);
        const DisplacementUsers users = buildDisplacementUsers(d.layout);
        for (uint32_t sample = 0; sample < d.layout.sampleCount; sample += 37) {
            Displacement changed = d;
            changed.samples[sample] += 1.0f;
            std::vector<uint32_t> expected;
            for (uint32_t tile = 0; tile < d.layout.tiles.size(); ++tile) {
                bool differs = false;
                for (uint32_t j = 0; j <= 8 && !differs; ++j)
                    for (uint32_t i = 0; i <= 8 && !differs; ++i)
                        differs = evaluateDisplacement(changed, tile, i / 8.0f, j / 8.0f).value !=
                                  evaluateDisplacement(d, tile, i / 8.0f, j / 8.0f).value;
                if (differs) expected.push_back(tile);
            }
            EXPECT_EQ(subfacesReadingSamples(d.layout, users, std::span(&sample, 1)), expected) << name << " sample " << sample;
        }
    }
}

// Converting the sample grids of file version 1: the fitted tiles stay close to the grids'
// bilinear D. Grids of 16 samples per side sampled from a smooth D (tiles of the fewest cells),
// fitted at the R the file reader picks: within 3% of the relief (the smoothing of the bilinear
// kinks).
TEST(DisplacementTiles, SampleGridsFitCloseToTheirBilinearD) {
    for (const auto& [name, cage] : testCages()) {
        const Displacement smooth = randomDisplacement(cage, 2, 21);
        Planned p(cage);
        SampleGrids grids = makeSampleGrids(cage, p.cage->topology(), 16);
        // Every grid sample takes the smooth D at its place (points and segments at their owner).
        for (uint32_t s = 0; s < grids.layout.subfaces.size(); ++s)
            for (uint32_t j = 0; j <= 16; ++j)
                for (uint32_t i = 0; i <= 16; ++i)
                    grids.samples[gridSample(grids.layout, s, i, j)] =
                        evaluateDisplacement(smooth, s, float(i) / 16.0f, float(j) / 16.0f).value;
        // At the R the reader picks: the grids' 16 samples per side in quad cells (an n-gon's
        // sub-face spans half a quad side: 32).
        const uint32_t resolution = minimumDisplacementResolution(cage) == 4 ? 32 : 16;
        const Displacement fitted = fitSampleGrids(buildDisplacementLayout(cage, p.cage->topology(), resolution), grids);
        float worst = 0.0f, range = 0.0f;
        for (uint32_t s = 0; s < fitted.layout.tiles.size(); ++s)
            for (uint32_t j = 0; j <= 12; ++j)
                for (uint32_t i = 0; i <= 12; ++i) {
                    const float u = float(i) / 12.0f, v = float(j) / 12.0f;
                    const float had = evaluateSampleGrids(grids, s, u, v).value;
                    worst = std::max(worst, std::abs(evaluateDisplacement(fitted, s, u, v).value - had));
                    range = std::max(range, std::abs(had));
                }
        EXPECT_LT(worst, 0.03f * range) << name;
        RecordProperty(name + "_fit_error_of_relief", std::to_string(worst / range));
    }
}

TEST(DisplacedMesh, SharedBoundaryVerticesAreBitIdentical) {
    for (auto& [name, cage] : testCages()) {
        Planned p(cage);
        const float diagonal = computeBounds(cage).diagonal();
        const Displacement d = randomDisplacement(cage, 8, 21, 0.02f * diagonal);
        const uint32_t required = requiredMeshFactor(*p.cage, d.layout);
        EXPECT_GE(required, 8u);
        for (uint32_t factor : {required, 6u, 2u * required}) {
            if (factor > 2 * kMaxDisplacementResolution) continue;
            Result<DisplacedMesh> mesh = buildDisplacedMesh(*p.cage, d, factor);
            ASSERT_TRUE(mesh) << mesh.error().message;
            // The same point: vertices whose undisplaced positions coincide (the owners make them
            // exactly equal; distinct points are far apart).
            Result<DisplacedMesh> flat = buildDisplacedMesh(*p.cage, Displacement{}, factor);
            ASSERT_TRUE(flat) << flat.error().message;
            std::vector<std::pair<glm::vec3, size_t>> boundary;  // (limit, vertex)
            std::vector<size_t> gridOf;
            for (size_t g = 0; g < mesh->gridSubface.size(); ++g) {
                const uint32_t n = mesh->gridFactor[g];
                for (uint32_t j = 0; j <= n; ++j)
                    for (uint32_t i = 0; i <= n; ++i)
                        if (i == 0 || j == 0 || i == n || j == n) {
                            const size_t k = mesh->gridOffset[g] + j * (n + 1) + i;
                            boundary.push_back({flat->positions[k], k});
                            gridOf.push_back(g);
                        }
            }
            std::vector<size_t> order(boundary.size());
            for (size_t i = 0; i < order.size(); ++i) order[i] = i;
            std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return boundary[a].first.x < boundary[b].first.x; });
            std::vector<bool> matched(boundary.size(), false);
            const float tolerance = 1e-6f * diagonal;
            for (size_t a = 0; a < order.size(); ++a)
                for (size_t b = a + 1; b < order.size() && boundary[order[b]].first.x - boundary[order[a]].first.x <= tolerance; ++b) {
                    const size_t x = order[a], y = order[b];
                    if (gridOf[x] == gridOf[y] || glm::length(boundary[x].first - boundary[y].first) > tolerance) continue;
                    ASSERT_EQ(boundary[x].first, boundary[y].first);
                    for (int axis = 0; axis < 3; ++axis)
                        ASSERT_EQ(bits(mesh->positions[boundary[x].second][axis]), bits(mesh->positions[boundary[y].second][axis]))
                            << name << " factor " << factor;
                    matched[x] = matched[y] = true;
                }
            if (name == "subdivided cube" || name == "benchmark cage")
                EXPECT_EQ(std::count(matched.begin(), matched.end(), false), 0) << name << " factor " << factor;
            else
                EXPECT_GT(std::count(matched.begin(), matched.end(), true), 0) << name;
        }
    }
}

// After samples change in place, re-displacing the grids of the sub-faces that read them gives
// the bits of a full rebuild: no other grid needs to change.
TEST(DisplacedMesh, RedisplacingTheReadersOfChangedSamplesEqualsARebuild) {
    for (auto& [name, cage] : testCages()) {
        Planned p(cage);
        const float diagonal = computeBounds(cage).diagonal();
        Displacement d = randomDisplacement(cage, 4, 5, 0.01f * diagonal);
        const uint32_t factor = requiredMeshFactor(*p.cage, d.layout);
        Result<DisplacedMesh> mesh = buildDisplacedMesh(*p.cage, d, factor);
        ASSERT_TRUE(mesh) << mesh.error().message;
        std::vector<uint32_t> changed;
        for (uint32_t k = 3; k < d.samples.size(); k += 7) changed.push_back(k), d.samples[k] += 0.005f * diagonal;
        std::vector<uint32_t> gridOf(p.cage->subfaceCount(), UINT32_MAX), grids;
        for (uint32_t g = 0; g < mesh->gridSubface.size(); ++g) gridOf[mesh->gridSubface[g]] = g;
        const DisplacementUsers users = buildDisplacementUsers(d.layout);
        SampleBits changedSet;
        changedSet.assign(d.layout.sampleCount, changed);
        EXPECT_EQ(subfacesReadingSamples(d.layout, users, changedSet), subfacesReadingSamples(d.layout, users, changed));
        for (uint32_t s : subfacesReadingSamples(d.layout, users, changed))
            if (gridOf[s] != UINT32_MAX) grids.push_back(gridOf[s]);
        EXPECT_GT(grids.size(), 0u);
        redisplaceGrids(*mesh, d, grids);
        Result<DisplacedMesh> rebuilt = buildDisplacedMesh(*p.cage, d, factor);
        ASSERT_TRUE(rebuilt) << rebuilt.error().message;
        ASSERT_EQ(mesh->positions.size(), rebuilt->positions.size());
        for (size_t v = 0; v < mesh->positions.size(); ++v)
            for (int axis = 0; axis < 3; ++axis) {
                ASSERT_EQ(bits(mesh->positions[v][axis]), bits(rebuilt->positions[v][axis])) << name << " vertex " << v;
                ASSERT_EQ(bits(mesh->normals[v][axis]), bits(rebuilt->normals[v][axis])) << name << " vertex " << v;
            }
    }
}

TEST(DisplacedMesh, VerticesAreDisplacedAlongTheLimitNormal) {
    Planned p(test::makeSubdividedCube(2));
    const Displacement d = randomDisplacement(p.cage->cage(), 4, 8);
    Result<DisplacedMesh> mesh = buildDisplacedMesh(*p.cage, d, 4);
    ASSERT_TRUE(mesh);
    for (size_t g = 0; g < mesh->gridSubface.size(); ++g) {
        const uint32_t s = mesh->gridSubface[g];
        const LimitSample limit = p.cage->evaluate(s, 0.5f, 0.25f);
        const glm::vec3 normal = limitNormal(*p.cage, s, 0.5f, 0.25f, limit);
        const glm::vec3 expected = limit.position + evaluateDisplacement(d, s, 0.5f, 0.25f).value * normal;
        EXPECT_EQ(mesh->positions[mesh->gridOffset[g] + 1 * 5 + 2], expected);
    }
    EXPECT_TRUE(buildDisplacedMesh(*p.cage, d, 3));  // all quads: any factor
    Planned mixed(test::makeMixedGrid());
    Result<DisplacedMesh> refused = buildDisplacedMesh(*mixed.cage, Displacement{}, 3);
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.error().message.find("even"), std::string::npos);
}

// Blinn's approximation (dropping D N_u) against the true normal of s + D N by differences.
TEST(DisplacedMesh, ShadingNormalCloseToTheDisplacedSurfaceNormal) {
    Planned p(test::makeSubdividedCube(3));
    const float diagonal = computeBounds(p.cage->cage()).diagonal();
    Displacement d = makeDisplacement(p.cage->cage(), p.cage->topology(), 8);
    d.samples = fitSamples(d.layout, [&](uint32_t s, float u, float v) {
        const glm::vec3 q = p.cage->evaluate(s, u, v).position;
        return 0.01f * diagonal * std::sin(3.0f * q.x) * std::cos(2.0f * q.y);
    });
    auto displaced = [&](uint32_t s, float u, float v) {
        const LimitSample l = p.cage->evaluate(s, u, v);
        return l.position + evaluateDisplacement(d, s, u, v).value * limitNormal(*p.cage, s, u, v, l);
    };
    float worstDegrees = 0.0f;
    for (uint32_t s = 0; s < d.layout.tiles.size(); ++s)
        for (float u : {0.3f, 0.55f}) {
            const float v = 0.45f, h = 1e-3f;
            const LimitSample l = p.cage->evaluate(s, u, v);
            const DisplacedPoint shading =
                displacePoint(l.position, l.du, l.dv, limitNormal(*p.cage, s, u, v, l), evaluateDisplacement(d, s, u, v));
            const glm::vec3 fu = (displaced(s, u + h, v) - displaced(s, u - h, v)) / (2 * h);
            const glm::vec3 fv = (displaced(s, u, v + h) - displaced(s, u, v - h)) / (2 * h);
            const glm::vec3 truth = glm::normalize(glm::cross(fu, fv));
            worstDegrees = std::max(worstDegrees, glm::degrees(std::acos(std::clamp(glm::dot(truth, shading.normal), -1.0f, 1.0f))));
        }
    // Displacement 1% of the diagonal on a surface of curvature radius ~1: a degree or two.
    EXPECT_LT(worstDegrees, 3.0f);
    RecordProperty("worst_degrees", std::to_string(worstDegrees));
}

// Parameters that are not exact complements (i/n from both ends, n not a power of two) still
// agree thanks to the snap; the pair (t, 1 - t) computed in float is the hard case.
TEST(DisplacementTiles, ReversedParametersAgreeForEveryFactorUpTo64) {
    const Displacement d = randomDisplacement(test::makeCube(), 16, 3);
    const DisplacementLayout& layout = d.layout;
    uint32_t checked = 0;
    for (uint32_t a = 0; a < layout.tiles.size(); ++a)
        for (uint32_t ea = 0; ea < 4; ++ea)
            for (uint32_t b = a + 1; b < layout.tiles.size(); ++b)
                for (uint32_t eb = 0; eb < 4; ++eb) {
                    const DisplacementEdge& x = layout.adjacency.subfaces[a].edges[ea];
                    const DisplacementEdge& y = layout.adjacency.subfaces[b].edges[eb];
                    if (x.segment != y.segment) continue;
                    const bool opposite = (x.flags & kEdgeReversed) != (y.flags & kEdgeReversed);
                    for (uint32_t n = 1; n <= 64; ++n)
                        for (uint32_t i = 0; i <= n; ++i) {
                            const glm::vec2 pa = edgePoint(ea, float(i) / float(n));
                            const glm::vec2 pb = edgePoint(eb, opposite ? 1.0f - float(i) / float(n) : float(i) / float(n));
                            ASSERT_EQ(bits(evaluateDisplacement(d, a, pa.x, pa.y).value), bits(evaluateDisplacement(d, b, pb.x, pb.y).value))
                                << "n " << n << " i " << i;
                            ++checked;
                        }
                }
    EXPECT_EQ(checked, 12u * (64u * 67u / 2u));  // 12 shared edges, sum over n of (n + 1)
}
