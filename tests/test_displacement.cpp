// Displacement storage: layout, sharing exactness across edges, resampling, tessellation
// factors, and the watertight displaced mesh.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <random>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "displaced_mesh.h"
#include "displacement.h"
#include "displacement_users.h"
#include "generated_cage.h"
#include "planned_cage.h"
#include "sculpt_samples.h"
#include "test_cages.h"

using namespace qp;

namespace {

struct Planned {
    PlanDatabase database;
    std::optional<PlannedCage> cage;
    explicit Planned(const Cage& c) {
        auto planned = PlannedCage::create(c, database, PlanOptions{}, "test cage");
        EXPECT_TRUE(planned) << planned.error().message;
        cage.emplace(std::move(planned).value());
    }
};

uint32_t bits(float x) { return std::bit_cast<uint32_t>(x); }

// Random power-of-two resolutions up to maxResolution and random values in [-1, 1].
Displacement randomDisplacement(const PlannedCage& planned, uint32_t maxResolution, uint32_t seed) {
    std::mt19937 rng(seed);
    Displacement d = makeDisplacement(planned.cage(), planned.topology(), 1);
    std::vector<uint32_t> resolutions(d.layout.subfaces.size());
    uint32_t levels = uint32_t(std::countr_zero(maxResolution)) + 1;
    for (uint32_t& r : resolutions) r = 1u << (rng() % levels);
    d = resampleDisplacement(d, resolutions);
    std::uniform_real_distribution<float> value(-1.0f, 1.0f);
    for (float& s : d.samples) s = value(rng);
    return d;
}

// The test cages: a boundary, valence-3 EVs, non-quads with EVs, and a closed cage with
// triangles, valence-5 EVs, creases and corners.
std::vector<std::pair<std::string, Cage>> testCages() {
    return {{"grid", test::makeGrid(3)},
            {"subdivided cube", test::makeSubdividedCube(2)},
            {"mixed grid", test::makeMixedGrid()},
            {"benchmark cage", makeBenchmarkCage(120, 3)}};
}

struct EdgePoint {
    glm::vec3 limit;
    float value;
    uint32_t subface, edge, i, n;
};

// Every edge point of every sub-face at i / n, n = quad factor (n-gon sub-faces: n / 2), with
// its limit position and its displacement seen from that sub-face.
std::vector<EdgePoint> edgePoints(const PlannedCage& planned, const Displacement& d, uint32_t quadFactor) {
    std::vector<EdgePoint> points;
    for (uint32_t face = 0; face < planned.cage().faceCount(); ++face)
        for (uint32_t s = planned.firstSubface(face); s < planned.firstSubface(face + 1); ++s) {
            if (!planned.hasSurface(s)) continue;
            uint32_t n = planned.cage().faceSize(face) == 4 ? quadFactor : quadFactor / 2;
            for (uint32_t e = 0; e < 4; ++e)
                for (uint32_t i = 0; i <= n; ++i) {
                    glm::vec2 uv = edgePoint(e, float(i) / float(n));
                    points.push_back({planned.evaluate(s, uv.x, uv.y).position,
                                      evaluateDisplacement(d, s, uv.x, uv.y).value, s, e, i, n});
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

TEST(DisplacementLayout, CountsOnACube) {
    Cage cube = test::makeCube();
    Topology topology = buildTopology(cube);
    DisplacementLayout layout = buildDisplacementLayout(cube, topology, 4);
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

TEST(DisplacementLayout, SegmentsTakeTheFinestNeedOfTheirFaces) {
    Cage cube = test::makeCube();
    Topology topology = buildTopology(cube);
    DisplacementLayout layout = buildDisplacementLayout(cube, topology, 2);
    std::vector<uint32_t> resolutions(6, 2);
    resolutions[0] = 16;
    layout = withResolutions(layout, resolutions);
    uint32_t finerEdges = 0;
    for (uint32_t s = 0; s < 6; ++s)
        for (const DisplacementEdge& e : layout.subfaces[s].edges) {
            bool sharedWithFace0 = s == 0 || std::any_of(std::begin(layout.subfaces[0].edges), std::end(layout.subfaces[0].edges),
                                                         [&](const DisplacementEdge& o) { return o.segment == e.segment; });
            EXPECT_EQ(layout.segments[e.segment].resolution, sharedWithFace0 ? 16u : 2u);
            EXPECT_EQ((e.flags & kEdgeFiner) != 0, s != 0 && sharedWithFace0);
            finerEdges += (e.flags & kEdgeFiner) != 0;
        }
    EXPECT_EQ(finerEdges, 4u);
    EXPECT_EQ(requiredTessellationFactor(layout, 0), 16u);
    EXPECT_EQ(requiredTessellationFactor(layout, 1), 2u);  // the opposite face shares nothing
    for (uint32_t s = 2; s < 6; ++s) {  // the neighbours: their shared edge needs 16
        EXPECT_EQ(requiredTessellationFactor(layout, s), 16u);
        uint32_t sixteen = 0;
        for (uint32_t e = 0; e < 4; ++e) sixteen += requiredEdgeFactor(layout, s, e) == 16;
        EXPECT_EQ(sixteen, 1u);
    }
}

TEST(DisplacementLayout, NonQuadsSplitTheirEdgesAtMidpoints) {
    Cage cage = test::makeMixedGrid();
    Topology topology = buildTopology(cage);
    DisplacementLayout layout = buildDisplacementLayout(cage, topology, 4);
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

    // Both sides of a split edge ask for matching factors: 2k on the quad, k on each half.
    std::vector<uint32_t> resolutions(layout.subfaces.size(), 2);
    for (uint32_t s = 15; s < resolutions.size(); ++s) resolutions[s] = s % 2 ? 8 : 16;  // the n-gon sub-faces
    layout = withResolutions(layout, resolutions);
    uint32_t checked = 0;
    for (uint32_t q = 0; q < 15; ++q)
        for (uint32_t e = 0; e < 4; ++e) {
            const DisplacementEdge& edge = layout.subfaces[q].edges[e];
            if (!(edge.flags & kEdgeSplit)) continue;
            for (uint32_t s = 15; s < layout.subfaces.size(); ++s)
                for (uint32_t f : {0u, 3u})
                    if (layout.subfaces[s].edges[f].segment == edge.segment ||
                        layout.subfaces[s].edges[f].segment == edge.secondHalf) {
                        EXPECT_EQ(requiredEdgeFactor(layout, q, e), 2 * requiredEdgeFactor(layout, s, f));
                        ++checked;
                    }
        }
    EXPECT_GT(checked, 0u);
}

TEST(DisplacementEval, GridPointsReadTheirSamples) {
    Planned p(test::makeMixedGrid());
    Displacement d = randomDisplacement(*p.cage, 8, 11);
    for (uint32_t s = 0; s < d.layout.subfaces.size(); ++s) {
        const uint32_t R = d.layout.subfaces[s].resolution;
        for (uint32_t j = 0; j <= R; ++j)
            for (uint32_t i = 0; i <= R; ++i) {
                float value = evaluateDisplacement(d, s, float(i) / float(R), float(j) / float(R)).value;
                ASSERT_EQ(bits(value), bits(d.samples[gridSample(d.layout, s, i, j)])) << s << " " << i << " " << j;
            }
    }
}

// The renderers' per-sub-face evaluator (gathered grid, inline bilinear inside) returns
// evaluateDisplacement's bits: on grid lines and edges, in the strips of edges finer than the
// grid, at random points, and clamped outside [0, 1].
TEST(DisplacementEval, SubfaceDisplacementHasEvaluateDisplacementsBits) {
    for (auto& [name, cage] : testCages()) {
        Planned p(cage);
        Displacement d = randomDisplacement(*p.cage, 16, 13);
        std::mt19937 rng(4);
        std::uniform_real_distribution<float> param(-0.05f, 1.05f);
        uint32_t strips = 0;
        for (uint32_t s = 0; s < d.layout.subfaces.size(); ++s) {
            const SubfaceDisplacement D(d, s);
            for (uint32_t e = 0; e < 4; ++e) strips += (d.layout.subfaces[s].edges[e].flags & kEdgeFiner) != 0;
            std::vector<glm::vec2> points;
            for (uint32_t n : {1u, 3u, 32u, 64u})
                for (uint32_t y = 0; y <= n; ++y)
                    for (uint32_t x = 0; x <= n; ++x) points.push_back({float(x) / float(n), float(y) / float(n)});
            for (int k = 0; k < 200; ++k) points.push_back({param(rng), param(rng)});
            for (const glm::vec2& uv : points) {
                const DisplacementValue a = evaluateDisplacement(d, s, uv.x, uv.y), b = D.evaluate(uv.x, uv.y);
                ASSERT_EQ(bits(a.value), bits(b.value)) << name << " sub-face " << s << " at " << uv.x << ", " << uv.y;
                ASSERT_EQ(bits(a.du), bits(b.du)) << name << " sub-face " << s << " at " << uv.x << ", " << uv.y;
                ASSERT_EQ(bits(a.dv), bits(b.dv)) << name << " sub-face " << s << " at " << uv.x << ", " << uv.y;
            }
        }
        EXPECT_GT(strips, 0u) << name << ": no edge finer than its grid was tried";
    }
}

TEST(DisplacementEval, DerivativesMatchFiniteDifferences) {
    Planned p(test::makeMixedGrid());
    Displacement d = randomDisplacement(*p.cage, 8, 5);
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> param(0.02f, 0.98f);
    for (uint32_t s = 0; s < d.layout.subfaces.size(); ++s)
        for (int k = 0; k < 20; ++k) {
            float u = param(rng), v = param(rng);
            const float h = 1e-3f / float(kMaxDisplacementResolution);
            DisplacementValue at = evaluateDisplacement(d, s, u, v);
            // Skip points whose difference stencil crosses a cell line (D is piecewise smooth).
            const float R = float(requiredTessellationFactor(d.layout, s)) * 2.0f;
            auto nearLine = [&](float x) { return std::abs(x * R - std::round(x * R)) < 2.0f * h * R; };
            if (nearLine(u) || nearLine(v)) continue;
            float du = (evaluateDisplacement(d, s, u + h, v).value - evaluateDisplacement(d, s, u - h, v).value) / (2 * h);
            float dv = (evaluateDisplacement(d, s, u, v + h).value - evaluateDisplacement(d, s, u, v - h).value) / (2 * h);
            float scale = 1.0f + std::abs(at.du) + std::abs(at.dv);
            EXPECT_NEAR(at.du, du, 2e-2f * scale) << "sub-face " << s << " at " << u << ", " << v;
            EXPECT_NEAR(at.dv, dv, 2e-2f * scale) << "sub-face " << s << " at " << u << ", " << v;
        }
}

TEST(DisplacementEval, CoarseFaceMeetsItsFinerEdgeContinuously) {
    Planned p(test::makeSubdividedCube(2));
    Displacement d = randomDisplacement(*p.cage, 16, 7);
    for (uint32_t s = 0; s < d.layout.subfaces.size(); ++s)
        for (float t : {0.1f, 0.37f, 0.5f, 0.81f}) {
            for (uint32_t e = 0; e < 4; ++e) {
                glm::vec2 on = edgePoint(e, t);
                glm::vec2 inward = glm::vec2(0.5f) - on;
                glm::vec2 near = on + 1e-5f * inward / glm::length(inward);
                float a = evaluateDisplacement(d, s, on.x, on.y).value;
                float b = evaluateDisplacement(d, s, near.x, near.y).value;
                // |D'| is at most about 2 * 64 * 2 here; the snap moves t by at most 2^-15.
                EXPECT_NEAR(a, b, 1e-2f) << "sub-face " << s << " edge " << e << " t " << t;
            }
        }
}

// The storage promise: the same point of a shared edge reads the same bits from every side,
// at any tessellation, whatever the resolutions on either side, across n-gon sub-faces and
// extraordinary vertices.
TEST(DisplacementSharing, SharedEdgePointsAreBitIdenticalFromEverySide) {
    for (auto& [name, cage] : testCages()) {
        Planned p(cage);
        const float diagonal = computeBounds(cage).diagonal();
        for (uint32_t seed : {1u, 2u}) {
            Displacement d = randomDisplacement(*p.cage, 16, seed);
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
TEST(DisplacementSharing, ReversedParametersAgreeForEveryFactorUpTo64) {
    Planned p(test::makeCube());
    Displacement d = randomDisplacement(*p.cage, 16, 3);
    const DisplacementLayout& layout = d.layout;
    uint32_t checked = 0;
    for (uint32_t a = 0; a < layout.subfaces.size(); ++a)
        for (uint32_t ea = 0; ea < 4; ++ea)
            for (uint32_t b = a + 1; b < layout.subfaces.size(); ++b)
                for (uint32_t eb = 0; eb < 4; ++eb) {
                    const DisplacementEdge& x = layout.subfaces[a].edges[ea];
                    const DisplacementEdge& y = layout.subfaces[b].edges[eb];
                    if (x.segment != y.segment) continue;
                    bool opposite = (x.flags & kEdgeReversed) != (y.flags & kEdgeReversed);
                    for (uint32_t n = 1; n <= 64; ++n)
                        for (uint32_t i = 0; i <= n; ++i) {
                            glm::vec2 pa = edgePoint(ea, float(i) / float(n));
                            glm::vec2 pb = edgePoint(eb, opposite ? 1.0f - float(i) / float(n) : float(i) / float(n));
                            ASSERT_EQ(bits(evaluateDisplacement(d, a, pa.x, pa.y).value),
                                      bits(evaluateDisplacement(d, b, pb.x, pb.y).value))
                                << "n " << n << " i " << i;
                            ++checked;
                        }
                }
    EXPECT_EQ(checked, 12u * (64u * 67u / 2u));  // 12 shared edges, sum over n of (n + 1)
}

TEST(DisplacementResample, RaisingUniformResolutionReproducesTheSurface) {
    Planned p(test::makeSubdividedCube(2));
    Displacement d = randomDisplacement(*p.cage, 1, 4);  // all at 1, then:
    d = resampleDisplacement(d, std::vector<uint32_t>(d.layout.subfaces.size(), 4));
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> value(-1.0f, 1.0f);
    for (float& s : d.samples) s = value(rng);
    Displacement raised = resampleDisplacement(d, std::vector<uint32_t>(d.layout.subfaces.size(), 16));
    std::uniform_real_distribution<float> param(0.0f, 1.0f);
    float worst = 0.0f;
    for (uint32_t s = 0; s < d.layout.subfaces.size(); ++s)
        for (int k = 0; k < 200; ++k) {
            float u = param(rng), v = param(rng);
            worst = std::max(worst, std::abs(evaluateDisplacement(d, s, u, v).value -
                                             evaluateDisplacement(raised, s, u, v).value));
        }
    EXPECT_LT(worst, 1e-6f);
}

// Raising ONE sub-face (the editor's per-face resolution) keeps the shape everywhere: on the
// raised face, and on its neighbours, whose shared edges become finer than their grids.
TEST(DisplacementResample, RaisingOneFaceKeepsTheSurfaceOfEveryFace) {
    Planned p(test::makeMixedGrid());  // quads, a triangle and a pentagon: whole and split edges
    Displacement d = randomDisplacement(*p.cage, 1, 6);
    d = resampleDisplacement(d, std::vector<uint32_t>(d.layout.subfaces.size(), 4));
    std::mt19937 rng(8);
    std::uniform_real_distribution<float> value(-1.0f, 1.0f), param(0.0f, 1.0f);
    for (float& s : d.samples) s = value(rng);
    const uint32_t count = uint32_t(d.layout.subfaces.size());
    for (uint32_t raisedSubface : {0u, count / 2, count - 1}) {
        std::vector<uint32_t> resolutions(count, 4);
        resolutions[raisedSubface] = 16;
        Displacement raised = resampleDisplacement(d, resolutions);
        EXPECT_GT(raised.layout.sampleCount, d.layout.sampleCount);
        float worst = 0.0f;
        for (uint32_t s = 0; s < count; ++s)
            for (int k = 0; k < 200; ++k) {
                // Interior points, and points on the edges (where neighbours meet).
                float u = param(rng), v = k % 4 == 0 ? 0.0f : k % 4 == 1 ? 1.0f : param(rng);
                worst = std::max(worst, std::abs(evaluateDisplacement(d, s, u, v).value -
                                                 evaluateDisplacement(raised, s, u, v).value));
            }
        EXPECT_LT(worst, 1e-5f) << "raised sub-face " << raisedSubface;
    }
}

// Smooth data sampled from f(p): lowering keeps exactly the coarse samples, so it equals
// sampling f at the coarse resolution directly; raising stays within the interpolation error.
TEST(DisplacementResample, LoweringIsInjectionAndRaisingStaysWithinInterpolationError) {
    Planned p(test::makeMixedGrid());
    auto f = [](const glm::vec3& q) { return 0.05f * std::sin(2.0f * q.x) * std::cos(1.5f * q.y) + 0.02f * q.z; };
    auto sampled = [&](std::vector<uint32_t> resolutions) {
        Displacement d = makeDisplacement(p.cage->cage(), p.cage->topology(), 1);
        d = resampleDisplacement(d, resolutions);
        std::vector<SampleSite> sites = computeSampleSites(d.layout, *p.cage);
        for (uint32_t i = 0; i < sites.size(); ++i)
            if (sites[i].subface != kNoSite) d.samples[i] = f(p.cage->evaluate(sites[i].subface, sites[i].u, sites[i].v).position);
        return d;
    };
    const uint32_t count = p.cage->subfaceCount();
    std::vector<uint32_t> mixed(count);
    for (uint32_t s = 0; s < count; ++s) mixed[s] = 1u << (s % 4);  // 1, 2, 4, 8
    Displacement fine = sampled(std::vector<uint32_t>(count, 16));
    Displacement lowered = resampleDisplacement(fine, mixed);
    Displacement direct = sampled(mixed);
    ASSERT_EQ(lowered.layout, direct.layout);
    for (uint32_t i = 0; i < lowered.samples.size(); ++i) ASSERT_EQ(bits(lowered.samples[i]), bits(direct.samples[i])) << i;

    // Raise-then-lower gives back the original bit for bit.
    Displacement raised = resampleDisplacement(direct, std::vector<uint32_t>(count, 16));
    Displacement back = resampleDisplacement(raised, mixed);
    for (uint32_t i = 0; i < back.samples.size(); ++i) ASSERT_EQ(bits(back.samples[i]), bits(direct.samples[i])) << i;

    // The raised surface differs from the coarse one by no more than their interpolation errors.
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> param(0.0f, 1.0f);
    float coarseError = 0.0f, change = 0.0f;
    for (uint32_t s = 0; s < count; ++s)
        for (int k = 0; k < 100; ++k) {
            float u = param(rng), v = param(rng);
            float exact = f(p.cage->evaluate(s, u, v).position);
            float coarse = evaluateDisplacement(direct, s, u, v).value;
            coarseError = std::max(coarseError, std::abs(coarse - exact));
            change = std::max(change, std::abs(evaluateDisplacement(raised, s, u, v).value - coarse));
        }
    EXPECT_GT(coarseError, 0.0f);
    EXPECT_LE(change, coarseError + 1e-6f) << "coarse interpolation error " << coarseError;
}

TEST(DisplacedMesh, SharedBoundaryVerticesAreBitIdentical) {
    for (auto& [name, cage] : testCages()) {
        Planned p(cage);
        const float diagonal = computeBounds(cage).diagonal();
        Displacement d = randomDisplacement(*p.cage, 8, 21);
        for (float& s : d.samples) s *= 0.02f * diagonal;
        const uint32_t required = requiredMeshFactor(*p.cage, d.layout);
        EXPECT_GE(required, 8u);
        for (uint32_t factor : {required, 6u, 2u * required}) {
            if (factor > 2 * kMaxDisplacementResolution) continue;
            Result<DisplacedMesh> mesh = buildDisplacedMesh(*p.cage, d, factor);
            ASSERT_TRUE(mesh) << mesh.error().message;
            // Which vertices are the same point: those whose undisplaced positions coincide
            // (the owners make them exactly equal; distinct points are far apart).
            Result<DisplacedMesh> flat = buildDisplacedMesh(*p.cage, Displacement{}, factor);
            ASSERT_TRUE(flat) << flat.error().message;
            struct Vertex {
                glm::vec3 limit, position;
                size_t grid;
                uint32_t i, j;
            };
            std::vector<Vertex> boundary;
            for (size_t g = 0; g < mesh->gridSubface.size(); ++g) {
                uint32_t n = mesh->gridFactor[g];
                for (uint32_t j = 0; j <= n; ++j)
                    for (uint32_t i = 0; i <= n; ++i)
                        if (i == 0 || j == 0 || i == n || j == n) {
                            uint32_t k = mesh->gridOffset[g] + j * (n + 1) + i;
                            boundary.push_back({flat->positions[k], mesh->positions[k], g, i, j});
                        }
            }
            auto pairs = coincident(boundary, [](const Vertex& v) { return v.limit; }, 1e-6f * diagonal);
            std::vector<bool> matched(boundary.size(), false);
            for (auto [a, b] : pairs) {
                if (boundary[a].grid == boundary[b].grid) continue;
                ASSERT_EQ(boundary[a].limit, boundary[b].limit);
                for (int axis = 0; axis < 3; ++axis)
                    ASSERT_EQ(bits(boundary[a].position[axis]), bits(boundary[b].position[axis]))
                        << name << " factor " << factor << ": sub-face " << mesh->gridSubface[boundary[a].grid] << " ("
                        << boundary[a].i << ", " << boundary[a].j << ") and sub-face " << mesh->gridSubface[boundary[b].grid]
                        << " (" << boundary[b].i << ", " << boundary[b].j << ")";
                EXPECT_NE(boundary[a].position, boundary[a].limit);  // displaced, not zero
                matched[a] = matched[b] = true;
            }
            // Closed cages: every boundary vertex has a partner (no T-junctions, no cracks).
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
        Displacement d = randomDisplacement(*p.cage, 4, 5);
        for (float& s : d.samples) s *= 0.01f * diagonal;
        const uint32_t factor = requiredMeshFactor(*p.cage, d.layout);
        Result<DisplacedMesh> mesh = buildDisplacedMesh(*p.cage, d, factor);
        ASSERT_TRUE(mesh) << mesh.error().message;
        // Change every 7th sample: tiles, segments and points alike.
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
    Displacement d = randomDisplacement(*p.cage, 4, 8);
    Result<DisplacedMesh> mesh = buildDisplacedMesh(*p.cage, d, 4);
    ASSERT_TRUE(mesh);
    for (size_t g = 0; g < mesh->gridSubface.size(); ++g) {
        uint32_t s = mesh->gridSubface[g];
        // An interior vertex: evaluated by its own sub-face.
        LimitSample limit = p.cage->evaluate(s, 0.5f, 0.25f);
        glm::vec3 normal = limitNormal(*p.cage, s, 0.5f, 0.25f, limit);
        float value = evaluateDisplacement(d, s, 0.5f, 0.25f).value;
        glm::vec3 expected = limit.position + value * normal;
        EXPECT_EQ(mesh->positions[mesh->gridOffset[g] + 1 * 5 + 2], expected);
    }
    Result<DisplacedMesh> odd = buildDisplacedMesh(*p.cage, d, 3);
    EXPECT_TRUE(odd);  // all quads: any factor
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
    std::vector<SampleSite> sites = computeSampleSites(d.layout, *p.cage);
    for (uint32_t i = 0; i < sites.size(); ++i) {
        if (sites[i].subface == kNoSite) continue;  // midpoints and centres of quads: unused
        glm::vec3 q = p.cage->evaluate(sites[i].subface, sites[i].u, sites[i].v).position;
        d.samples[i] = 0.01f * diagonal * std::sin(3.0f * q.x) * std::cos(2.0f * q.y);
    }
    auto displaced = [&](uint32_t s, float u, float v) {
        LimitSample l = p.cage->evaluate(s, u, v);
        return l.position + evaluateDisplacement(d, s, u, v).value * limitNormal(*p.cage, s, u, v, l);
    };
    float worstDegrees = 0.0f;
    for (uint32_t s = 0; s < d.layout.subfaces.size(); ++s) {
        for (float u : {0.3f, 0.55f}) {
            const float v = 0.45f, h = 1e-3f;
            LimitSample l = p.cage->evaluate(s, u, v);
            DisplacedPoint shading = displacePoint(l.position, l.du, l.dv, limitNormal(*p.cage, s, u, v, l),
                                                   evaluateDisplacement(d, s, u, v));
            glm::vec3 fu = (displaced(s, u + h, v) - displaced(s, u - h, v)) / (2 * h);
            glm::vec3 fv = (displaced(s, u, v + h) - displaced(s, u, v - h)) / (2 * h);
            glm::vec3 truth = glm::normalize(glm::cross(fu, fv));
            float degrees = glm::degrees(std::acos(std::clamp(glm::dot(truth, shading.normal), -1.0f, 1.0f)));
            worstDegrees = std::max(worstDegrees, degrees);
        }
    }
    // Displacement 1% of the diagonal on a surface of curvature radius ~1: a degree or two.
    EXPECT_LT(worstDegrees, 3.0f);
    RecordProperty("worst_degrees", std::to_string(worstDegrees));
}
