// Sculpted displacement through the plans' three drawing paths (lavapipe, validation on) and
// through the CPU-mesh schemes: every vertex at s + D N of its own surface, shared boundary
// vertices bit-identical, and a brush dab's incremental update equal to a full evaluation.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <map>
#include <numeric>
#include <random>
#include <tuple>

#include <glm/geometric.hpp>
#include <opensubdiv/far/primvarRefiner.h>

#include "camera.h"
#include "cpu_grid.h"
#include "displaced_grid_factors.h"
#include "displacement/brush.h"
#include "displacement/displaced_mesh.h"
#include "displacement/displacement_users.h"
#include "displacement/sculpt_samples.h"
#include "grid_relayout.h"
#include "mesh/generated_cage.h"
#include "offscreen_target.h"
#include "plan_pass.h"
#include "plans/osd_refiner.h"
#include "plans/planned_cage.h"
#include "render_test_support.h"
#include "scheme_host.h"
#include "scheme_loader.h"
#include "scheme_support.h"
#include "test_cages.h"
#include "vk_commands.h"

using namespace qp;

namespace {

constexpr uint32_t kImageSize = 256;

// Tiles of `resolution` with random values in +-amplitude.
Displacement randomDisplacement(const PlannedCage& planned, uint32_t resolution, float amplitude, uint32_t seed) {
    std::mt19937 rng(seed);
    Displacement d = makeDisplacement(planned.cage(), planned.topology(), resolution);
    std::uniform_real_distribution<float> value(-amplitude, amplitude);
    for (float& s : d.samples) s = value(rng);
    return d;
}

std::vector<std::pair<std::string, Cage>> displacementCages() {
    Cage features = test::makeMixedGrid();  // EVs, a triangle and a pentagon beside quads, a boundary
    features.setEdgeSharpness(12, 13, kInfiniteSharpness);
    features.setHole(0, true);
    return {{"mixed grid", std::move(features)}, {"subdivided cube", test::makeSubdividedCube()}};
}

// The reference: s + D N of the limit surface at (sub-face, u, v), N the unit normal of
// du x dv, at sub-face corners where those vanish a step inside (the renderers' rule,
// cornerDerivativesVanish: at some extraordinary vertices the corner has none).
DisplacedPoint referencePoint(const PlannedCage& planned, const Displacement& d, uint32_t subface, float u, float v) {
    const LimitSample s = planned.evaluate(subface, u, v);
    const bool corner = (u == 0.0f || u == 1.0f) && (v == 0.0f || v == 1.0f);
    LimitSample at = s;
    if (corner) {
        const LimitSample inside = planned.evaluate(subface, u + (u < 0.5f ? kCornerNormalStep : -kCornerNormalStep),
                                                    v + (v < 0.5f ? kCornerNormalStep : -kCornerNormalStep));
        if (cornerDerivativesVanish(s.du, s.dv, inside.du, inside.dv)) at = inside;
    }
    const glm::vec3 n = glm::normalize(glm::cross(at.du, at.dv));
    return displacePoint(s.position, at.du, at.dv, n, evaluateDisplacement(d, subface, u, v));
}

// Where a boundary vertex of a sub-face lies, whichever sub-face names it: a point id, or a
// reduced fraction along a segment of the displacement layout (its canonical direction).
using Location = std::tuple<int, uint32_t, uint32_t, uint32_t>;
Location boundaryLocation(const SampleGridLayout& layout, uint32_t subface, uint32_t edge, uint32_t i, uint32_t n) {
    const DisplacementSubface& sf = layout.subfaces[subface];
    if (i == 0) return {0, sf.corners[kEdgeStart[edge]], 0, 0};
    if (i == n) return {0, sf.corners[kEdgeEnd[edge]], 0, 0};
    const EdgeSite site = edgeSite(sf, edge, i, n);
    const DisplacementSegment& seg = layout.segments[site.segment];
    if (site.k == 0) return {0, seg.pointA, 0, 0};
    if (site.k == site.intervals) return {0, seg.pointB, 0, 0};
    const uint32_t g = std::gcd(site.k, site.intervals);
    return {1, site.segment, site.k / g, site.intervals / g};
}

// Every vertex of an (n+1)^2 grid per sub-face on a boundary, checked against every other
// vertex at the same location: positions bit for bit (shading normals may differ: D is only
// C0 across edges). Returns how many coincided.
template <class Vertex>
uint32_t expectWatertight(const SampleGridLayout& layout, const std::vector<uint32_t>& gridSubface,
                          const std::vector<uint32_t>& gridFactor, const std::vector<uint32_t>& gridOffset,
                          const Vertex* vertices, const std::string& what) {
    std::map<Location, const Vertex*> seen;
    uint32_t shared = 0;
    for (size_t g = 0; g < gridSubface.size(); ++g) {
        const uint32_t n = gridFactor[g], side = n + 1;
        for (uint32_t k = 0; k < side * side; ++k) {
            const uint32_t x = k % side, y = k / side;
            const int edge = y == 0 ? 0 : x == n ? 1 : y == n ? 2 : x == 0 ? 3 : -1;
            if (edge < 0) continue;
            const uint32_t along = edge == 0 || edge == 2 ? x : y;
            const Vertex* v = vertices + gridOffset[g] + k;
            auto [it, inserted] = seen.emplace(boundaryLocation(layout, gridSubface[g], uint32_t(edge), along, n), v);
            if (!inserted) {
                ++shared;
                EXPECT_EQ(std::memcmp(&it->second->position, &v->position, sizeof(float[3])), 0)
                    << what << ": sub-face " << gridSubface[g] << " edge " << edge << " vertex " << along << " of " << n
                    << " differs from its neighbour's";
            }
        }
    }
    EXPECT_GT(shared, 0u) << what;
    return shared;
}

// OpenSubdiv's exact limit normal at every cage vertex (limit tangents after two uniform
// levels, so that the masks see quads only); zero where the tangents are degenerate.
std::vector<glm::dvec3> exactVertexNormals(const Cage& cage) {
    struct Point {
        glm::dvec3 p{0.0};
        void Clear() { p = glm::dvec3(0.0); }
        void AddWithWeight(const Point& s, float w) { p += double(w) * s.p; }
    };
    auto created = createRefiner(cage, "test cage");
    EXPECT_TRUE(created.ok());
    OpenSubdiv::Far::TopologyRefiner& refiner = **created;
    OpenSubdiv::Far::TopologyRefiner::UniformOptions options(2);
    options.fullTopologyInLastLevel = true;  // Limit needs the last level's full topology
    refiner.RefineUniform(options);
    std::vector<Point> base(cage.vertexCount()), one(refiner.GetLevel(1).GetNumVertices()),
        two(refiner.GetLevel(2).GetNumVertices()), limit(two.size()), tangent1(two.size()), tangent2(two.size());
    for (uint32_t v = 0; v < cage.vertexCount(); ++v) base[v].p = glm::dvec3(cage.positions[v]);
    OpenSubdiv::Far::PrimvarRefiner primvar(refiner);
    Point *b = base.data(), *o = one.data(), *t = two.data(), *l = limit.data(), *t1 = tangent1.data(), *t2 = tangent2.data();
    primvar.Interpolate(1, b, o);
    primvar.Interpolate(2, o, t);
    primvar.Limit(t, l, t1, t2);
    std::vector<glm::dvec3> normals(cage.vertexCount());
    for (uint32_t v = 0; v < cage.vertexCount(); ++v) {
        const int child = refiner.GetLevel(1).GetVertexChildVertex(refiner.GetLevel(0).GetVertexChildVertex(int(v)));
        const glm::dvec3 n = glm::cross(tangent1[child].p, tangent2[child].p);
        normals[v] = glm::length(n) > 0.0 ? glm::normalize(n) : glm::dvec3(0.0);
    }
    return normals;
}

struct DisplacementRender : test::PlanPassTest {
    using PlanPassTest::upload;
    PlanBuffers upload(const PlannedCage& planned, const Displacement& displacement) {
        PlanBuffers buffers = PlanPassTest::upload(planned);
        EXPECT_TRUE(setPlanDisplacement(ctx, pass, buffers, &displacement).ok());
        return buffers;
    }

    // The grid filled by the compute shader or the CPU evaluator; slots start as NaN.
    std::vector<GridVertex> fillGrid(const PlannedCage& planned, PlanBuffers& buffers, bool gpu) {
        std::memset(buffers.grid.data, 0xff, buffers.gridLayout.slotCount() * sizeof(GridVertex));
        buffers.gridEvaluator = GridEvaluator::None;
        if (gpu) {
            EXPECT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) { recordGridEvaluation(cmd, pass, buffers); }).ok());
        } else {
            buffers.controlPointLevel = kNoControlPoints;
            evaluateGridOnCpu(planned, buffers);
        }
        const GridVertex* grid = static_cast<const GridVertex*>(buffers.grid.data);
        return std::vector<GridVertex>(grid, grid + buffers.gridLayout.slotCount());
    }
};

glm::vec3 positionOf(const GridVertex& g) { return {g.position[0], g.position[1], g.position[2]}; }
glm::vec3 normalOf(const GridVertex& g) { return {g.normal[0], g.normal[1], g.normal[2]}; }

// Grid slots against the reference: a slot shows its owner's vertex (grid_layout.h), so it is
// compared with the reference at the owner's (sub-face, u, v) — across a crease, or at an
// extraordinary corner, the owner's normal is not this sub-face's. Shading normals of owned
// slots against displacePoint's; shared boundary vertices bit for bit.
void checkDisplacedGrid(const PlannedCage& planned, const Displacement& d, const PlanBuffers& buffers,
                        const std::vector<GridVertex>& grid, const std::string& what) {
    const GridLayout& layout = buffers.gridLayout;
    const float diagonal = computeBounds(planned.cage()).diagonal();
    double worstPosition = 0.0, worstNormal = 0.0, largestOffset = 0.0;
    std::vector<uint32_t> gridSubface, gridFactor;
    for (uint32_t drawn = 0; drawn < buffers.data.subfaces.size(); ++drawn) {
        gridSubface.push_back(buffers.data.subfaces[drawn].subface);
        gridFactor.push_back(layout.factors.subfaceFactor[drawn]);
    }
    for (uint32_t slot = 0; slot < layout.slotCount(); ++slot) {
        const uint32_t source = layout.source[slot], owner = layout.slotSubface[source];
        float u, v;
        slotParameter(source - layout.subfaceOffset[owner], gridFactor[owner], u, v);
        const DisplacedPoint ref = referencePoint(planned, d, gridSubface[owner], u, v);
        const double error = glm::length(positionOf(grid[slot]) - ref.position) / diagonal;
        ASSERT_TRUE(std::isfinite(error)) << what << ": slot " << slot << " never written";
        worstPosition = std::max(worstPosition, error);
        largestOffset = std::max(largestOffset, double(std::fabs(evaluateDisplacement(d, gridSubface[owner], u, v).value)) / diagonal);
        if (source == slot) worstNormal = std::max(worstNormal, 1.0 - double(glm::dot(normalOf(grid[slot]), ref.normal)));
    }
    EXPECT_LE(worstPosition, 1e-5) << what;
    EXPECT_LE(worstNormal, 1e-4) << what << " (1 - cos of the worst normal angle)";
    EXPECT_GT(largestOffset, 1e-3) << what << ": nothing was displaced";
    expectWatertight(d.layout.adjacency, gridSubface, gridFactor, layout.subfaceOffset, grid.data(), what);
}

}  // namespace

TEST_F(DisplacementRender, GridPathsDrawTheDisplacedSurfaceWatertight) {
    for (auto& [name, cage] : displacementCages()) {
        PlanDatabase db;
        PlannedCage planned = test::planCage(cage, db);
        const float diagonal = computeBounds(planned.cage()).diagonal();
        const Displacement d = randomDisplacement(planned, 8, 0.01f * diagonal, 17);
        PlanBuffers buffers = upload(planned, d);
        const uint32_t required = std::min(requiredMeshFactor(planned, d.layout), 64u);
        for (uint32_t factor : {required, std::min(2 * required, 64u)}) {
            ASSERT_TRUE(prepareGrid(ctx, pass, buffers, factor).ok());
            const std::string what = name + ", factor " + std::to_string(factor);
            const std::vector<GridVertex> gpu = fillGrid(planned, buffers, true);
            const std::vector<GridVertex> cpu = fillGrid(planned, buffers, false);
            checkDisplacedGrid(planned, d, buffers, gpu, what + ", compute shader");
            checkDisplacedGrid(planned, d, buffers, cpu, what + ", CPU evaluator");
            if (HasFatalFailure()) return;
        }
        destroyPlanBuffers(ctx, buffers);
    }
}

// A displacement sculpted in one place: the grid follows the tiles there (every non-zero
// sample a vertex) and keeps the asked-for factor where D is zero; still exact and watertight
// bit for bit across the change of factor, on both evaluators.
TEST_F(DisplacementRender, GridFactorsRiseOnlyWhereTheDisplacementIsNotZero) {
    for (auto& [name, cage] : displacementCages()) {
        PlanDatabase db;
        PlannedCage planned = test::planCage(cage, db);
        const float diagonal = computeBounds(planned.cage()).diagonal();
        Displacement d = makeDisplacement(planned.cage(), planned.topology(), 16);
        const SculptSamples samples = SculptSamples::build(planned, d.layout);
        uint32_t centre = samples.sampleCount() / 3;
        while (!samples.hasSite(centre)) ++centre;
        StrokeOptions options{{BrushKind::Raise, 0.12f * diagonal, 0.1f, Falloff::Smooth}};
        applyStroke(d, samples, options, std::vector<glm::vec3>{samples.position(centre)});
        PlanBuffers buffers = upload(planned, d);
        const GridFactors base = uniformGridFactors(buffers.data, 2);
        const GridFactors raised = displacedGridFactors(buffers.data, d, base);
        uint32_t fine = 0, kept = 0;
        for (uint32_t drawn = 0; drawn < buffers.data.subfaces.size(); ++drawn) {
            const uint32_t s = buffers.data.subfaces[drawn].subface;
            bool zero = true;
            const DisplacementTile& tile = d.layout.tiles[s];
            for (uint32_t k = 0; k < (tile.cells + 2) * (tile.cells + 2); ++k) zero &= d.samples[d.layout.padded[tile.offset + k]] == 0.0f;
            const uint32_t n = raised.subfaceFactor[drawn];
            EXPECT_TRUE(std::has_single_bit(n)) << name << ": sub-face " << s << " factor " << n;
            if (!zero) {
                EXPECT_GE(n, requiredTessellationFactor(d.layout, s)) << name << ": sub-face " << s << " is displaced";
            }
            fine += n >= 16;
            kept += n == base.subfaceFactor[drawn];
        }
        EXPECT_GT(fine, 0u) << name;
        EXPECT_GT(kept, 0u) << name << ": every sub-face was raised";
        ASSERT_TRUE(prepareGrid(ctx, pass, buffers, raised).ok());
        checkDisplacedGrid(planned, d, buffers, fillGrid(planned, buffers, true), name + ", compute shader");
        checkDisplacedGrid(planned, d, buffers, fillGrid(planned, buffers, false), name + ", CPU evaluator");
        destroyPlanBuffers(ctx, buffers);
        if (HasFatalFailure()) return;
    }
}

TEST_F(DisplacementRender, TessellatedPathDrawsTheDisplacedSurfaceWatertight) {
    for (auto& [name, cage] : displacementCages()) {
        PlanDatabase db;
        PlannedCage planned = test::planCage(cage, db);
        const float diagonal = computeBounds(planned.cage()).diagonal();
        const Displacement d = randomDisplacement(planned, 8, 0.01f * diagonal, 23);
        PlanBuffers buffers = upload(planned, d);
        ASSERT_TRUE(enableCapture(ctx, buffers, 1'000'000).ok());
        ASSERT_TRUE(bindPlanBuffers(ctx, pass, buffers).ok());
        Result<OffscreenTarget> target = createOffscreenTarget(ctx, kImageSize, kImageSize, VK_FORMAT_R8G8B8A8_UNORM);
        ASSERT_TRUE(target.ok());
        const Bounds bounds = computeBounds(planned.cage());
        const RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
        PlanView view;
        view.viewProjection = viewProjection(camera);
        view.capture = true;
        const TessellationSettings settings{std::min(requiredMeshFactor(planned, d.layout), 64u), 8.0f};
        ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) {
            recordTessellated(cmd, pass, buffers, renderTarget(*target), view, settings);
        }).ok());
        uint32_t overflow = 0;
        const std::vector<CaptureRecord> records = readCapture(buffers, &overflow);
        ASSERT_EQ(overflow, 0u);
        double worst = 0.0;
        std::map<Location, double> boundaryError;
        std::map<Location, const CaptureRecord*> seen;
        uint32_t shared = 0;
        for (const CaptureRecord& r : records) {
            const uint32_t edge = r.edgeAndFactor & 0xff, n = r.edgeAndFactor >> 8;
            const uint32_t s = buffers.data.subfaces[r.drawn].subface;
            float u = r.u, v = r.v;  // edge vertices are evaluated at i / n exactly
            if (edge == 0 || edge == 2) u = float(r.edgeIndex) / float(n);
            if (edge == 1 || edge == 3) v = float(r.edgeIndex) / float(n);
            const DisplacedPoint ref = referencePoint(planned, d, s, u, v);
            const double error =
                double(glm::length(glm::vec3(r.position[0], r.position[1], r.position[2]) - ref.position)) / diagonal;
            if (edge == 4) {
                worst = std::max(worst, error);
                continue;
            }
            // A boundary vertex is its owner's, one of the sub-faces that share it: the best
            // of their references (checkDisplacedGrid says why).
            const Location location = boundaryLocation(d.layout.adjacency, s, edge, r.edgeIndex, n);
            auto [best, fresh] = boundaryError.emplace(location, error);
            best->second = std::min(best->second, error);
            auto [it, inserted] = seen.emplace(location, &r);
            if (!inserted) {
                ++shared;
                EXPECT_EQ(std::memcmp(it->second->position, r.position, sizeof(r.position)), 0)
                    << name << ": sub-face " << s << " edge " << edge << " vertex " << r.edgeIndex << " of " << n;
            }
        }
        for (const auto& [location, error] : boundaryError) worst = std::max(worst, error);
        EXPECT_LE(worst, 1e-5) << name;
        EXPECT_GT(shared, 0u) << name;
        destroyOffscreenTarget(ctx, *target);
        destroyPlanBuffers(ctx, buffers);
    }
}

// A brush dab re-evaluates only the sub-faces that read its samples, with the bits of a full
// evaluation, on both grid evaluators.
TEST_F(DisplacementRender, DabUpdatesExactlyWhatAFullEvaluationWould) {
    for (auto& [name, cage] : displacementCages()) {
        PlanDatabase db;
        PlannedCage planned = test::planCage(cage, db);
        const float diagonal = computeBounds(planned.cage()).diagonal();
        Displacement d = randomDisplacement(planned, 8, 0.002f * diagonal, 5);
        const SculptSamples samples = SculptSamples::build(planned, d.layout);
        PlanBuffers buffers = upload(planned, d);
        ASSERT_TRUE(prepareGrid(ctx, pass, buffers, std::min(requiredMeshFactor(planned, d.layout), 64u)).ok());
        for (bool gpu : {true, false}) {
            const std::string what = name + (gpu ? ", compute shader" : ", CPU evaluator");
            fillGrid(planned, buffers, gpu);
            Sculptor sculptor(d, samples);
            sculptor.beginStroke();
            const Brush brush{BrushKind::Raise, 0.15f * diagonal, 0.05f, Falloff::Smooth};
            uint32_t centre = samples.sampleCount() / 2;
            while (!samples.hasSite(centre)) ++centre;
            ASSERT_GT(sculptor.dab(brush, MirrorAxis::None, samples.position(centre)), 0u) << what;
            const std::vector<uint32_t> reached(sculptor.lastDabSamples().begin(), sculptor.lastDabSamples().end());
            sculptor.endStroke();
            DisplacementUpdate update;
            ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) {
                update = recordDisplacementChange(cmd, pass, buffers, planned, reached);
            }).ok());
            EXPECT_GT(update.uploadedSamples, 0u) << what;
            EXPECT_GT(update.evaluatedSubfaces, 0u) << what;
            EXPECT_LT(update.evaluatedSubfaces, buffers.data.subfaces.size()) << what << ": the whole cage was re-evaluated";
            EXPECT_EQ(std::memcmp(buffers.displacementSamples.data, d.samples.data(), d.samples.size() * sizeof(float)), 0)
                << what << ": the device's samples differ";
            const GridVertex* grid = static_cast<const GridVertex*>(buffers.grid.data);
            const std::vector<GridVertex> updated(grid, grid + buffers.gridLayout.slotCount());
            const std::vector<GridVertex> full = fillGrid(planned, buffers, gpu);
            EXPECT_EQ(std::memcmp(updated.data(), full.data(), full.size() * sizeof(GridVertex)), 0)
                << what << ": the updated grid differs from a full evaluation";
        }
        destroyPlanBuffers(ctx, buffers);
    }
}

// A stroke that reaches tiles that were zero raises their factors: the grid is laid out again
// keeping every sub-face whose slots mean the same (their factor and edges' pieces unchanged)
// and evaluates only the others and the neighbours that copy from them, on both evaluators,
// with the same bits as laying out and evaluating the whole grid.
TEST_F(DisplacementRender, AStrokeReachingNewTilesRelaysTheGridKeepingWhatIsEvaluated) {
    for (auto& [name, cage] : displacementCages()) {
        for (bool gpu : {true, false}) {
            const std::string what = name + (gpu ? ", compute shader" : ", CPU evaluator");
            PlanDatabase db;
            PlannedCage planned = test::planCage(cage, db);
            const float diagonal = computeBounds(planned.cage()).diagonal();
            Displacement d = makeDisplacement(planned.cage(), planned.topology(), 8);
            const SculptSamples samples = SculptSamples::build(planned, d.layout);
            std::vector<uint32_t> sited;
            for (uint32_t i = 0; i < samples.sampleCount(); ++i)
                if (samples.hasSite(i)) sited.push_back(i);
            const Brush brush{BrushKind::Raise, 0.08f * diagonal, 0.05f, Falloff::Smooth};
            applyStroke(d, samples, StrokeOptions{brush}, std::vector<glm::vec3>{samples.position(sited[sited.size() / 5])});
            PlanBuffers buffers = upload(planned, d);
            const GridFactors base = uniformGridFactors(buffers.data, 2);
            ASSERT_TRUE(prepareGrid(ctx, pass, buffers, displacedGridFactors(buffers.data, d, base)).ok());
            fillGrid(planned, buffers, gpu);
            const uint32_t slotsBefore = buffers.gridLayout.slotCount();

            // A dab far from the first: its samples are sent and re-displaced in the old layout
            // (as the editor does after each dab), then the next frame's factors differ.
            Sculptor sculptor(d, samples);
            sculptor.beginStroke();
            ASSERT_GT(sculptor.dab(brush, MirrorAxis::None, samples.position(sited[4 * sited.size() / 5])), 0u) << what;
            const std::vector<uint32_t> reached(sculptor.lastDabSamples().begin(), sculptor.lastDabSamples().end());
            sculptor.endStroke();
            ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) { recordDisplacementChange(cmd, pass, buffers, planned, reached); }).ok());
            const GridFactors raised = displacedGridFactors(buffers.data, d, base);
            const std::vector<uint32_t> changed = subfacesWithNewFactors(buffers.data, buffers.gridLayout.factors, raised);
            ASSERT_GT(changed.size(), 0u) << what << ": the dab raised no factor";
            ASSERT_LT(2 * changed.size(), buffers.data.subfaces.size()) << what;
            Result<bool> kept = relayoutGridKeepingSlots(ctx, pass, buffers, planned, raised);
            ASSERT_TRUE(kept.ok()) << kept.error().message;
            ASSERT_TRUE(*kept) << what << ": laid out whole";
            EXPECT_EQ(buffers.gridLayout.factors, raised) << what;
            EXPECT_GT(buffers.gridLayout.slotCount(), slotsBefore) << what;
            EXPECT_EQ(buffers.pendingGridSubfaces.empty(), !gpu) << what;
            ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) { recordPendingGridRefresh(cmd, pass, buffers); }).ok());
            EXPECT_TRUE(buffers.pendingGridSubfaces.empty()) << what;
            const GridVertex* grid = static_cast<const GridVertex*>(buffers.grid.data);
            const std::vector<GridVertex> updated(grid, grid + buffers.gridLayout.slotCount());
            const std::vector<float> frames = buffers.gridFrames.components;
            const std::vector<GridVertex> full = fillGrid(planned, buffers, gpu);
            EXPECT_EQ(std::memcmp(updated.data(), full.data(), full.size() * sizeof(GridVertex)), 0)
                << what << ": the relaid grid differs from a whole evaluation";
            if (!gpu) {
                ASSERT_EQ(frames.size(), buffers.gridFrames.components.size()) << what;
                // Padding past the last slot is never written by either.
                EXPECT_EQ(std::memcmp(frames.data(), buffers.gridFrames.components.data(),
                                      size_t(kFrameComponents) * buffers.gridLayout.slotCount() * sizeof(float)), 0)
                    << what << ": the carried displacement frames differ";
            }
            destroyPlanBuffers(ctx, buffers);
            if (HasFatalFailure()) return;
        }
    }
}

// Big brushes on the CPU grid re-displace only the slots whose D reads a changed sample, from
// the kept frames, a few at a time on SIMD lanes or one by one: strokes of every brush kind, with
// mirror symmetry, over resolutions that differ between neighbours (edges finer than their
// grid), leave the grid bit for bit as a full evaluation does, while re-displacing fewer slots
// than the sub-faces they touch hold.
TEST_F(DisplacementRender, LargeBrushStrokesOnTheCpuGridEqualAFullEvaluationBitForBit) {
    struct Stroke {
        BrushKind kind;
        float radius, strength;  // radius in bounding-box diagonals
        MirrorAxis mirror;
    };
    const Stroke strokes[] = {{BrushKind::Raise, 0.12f, 0.05f, MirrorAxis::None},  {BrushKind::Raise, 0.2f, 0.05f, MirrorAxis::X},
                              {BrushKind::Smooth, 0.2f, 0.5f, MirrorAxis::None},   {BrushKind::Flatten, 0.2f, 0.5f, MirrorAxis::None},
                              {BrushKind::Lower, 0.12f, 0.05f, MirrorAxis::Y},     {BrushKind::Erase, 0.2f, 0.3f, MirrorAxis::None}};
    for (auto& [name, cage] : displacementCages()) {
        PlanDatabase db;
        PlannedCage planned = test::planCage(cage, db);
        const float diagonal = computeBounds(planned.cage()).diagonal();
        Displacement d = randomDisplacement(planned, 8, 0.002f * diagonal, 9);
        const SculptSamples samples = SculptSamples::build(planned, d.layout);
        PlanBuffers buffers = upload(planned, d);
        ASSERT_TRUE(prepareGrid(ctx, pass, buffers, std::min(requiredMeshFactor(planned, d.layout), 64u)).ok());
        fillGrid(planned, buffers, false);
        std::vector<uint32_t> sited;
        for (uint32_t i = 0; i < samples.sampleCount(); ++i)
            if (samples.hasSite(i)) sited.push_back(i);
        std::mt19937 rng(3);
        uint64_t displaced = 0, slotsOfTouched = 0;
        for (const Stroke& stroke : strokes) {
            const std::string what = name + ", " + brushKindName(stroke.kind) + " " + std::to_string(stroke.radius);
            const Brush brush{stroke.kind, stroke.radius * diagonal, stroke.strength, Falloff::Smooth};
            Sculptor sculptor(d, samples);
            sculptor.beginStroke();
            for (int dab = 0; dab < 4; ++dab) {
                sculptor.dab(brush, stroke.mirror, samples.position(sited[rng() % sited.size()]));
                const DisplacementUpdate update =
                    recordDisplacementChange(VK_NULL_HANDLE, pass, buffers, planned, sculptor.lastDabSamples());
                displaced += update.displacedSlots;
                for (uint32_t s : subfacesReadingSamples(d.layout, buffers.displacementUsers, sculptor.lastDabSamples())) {
                    const uint32_t drawn = buffers.drawnOfSubface[s];
                    if (drawn == UINT32_MAX) continue;
                    for (uint32_t slot = buffers.gridLayout.subfaceOffset[drawn]; slot < buffers.gridLayout.subfaceOffset[drawn + 1]; ++slot)
                        slotsOfTouched += buffers.gridLayout.source[slot] == slot;
                }
            }
            ASSERT_FALSE(sculptor.endStroke().changes.empty()) << what;
            const GridVertex* grid = static_cast<const GridVertex*>(buffers.grid.data);
            const std::vector<GridVertex> updated(grid, grid + buffers.gridLayout.slotCount());
            const std::vector<GridVertex> full = fillGrid(planned, buffers, false);
            ASSERT_EQ(std::memcmp(updated.data(), full.data(), full.size() * sizeof(GridVertex)), 0)
                << what << ": the updated grid differs from a full evaluation";
        }
        EXPECT_GT(displaced, 0u) << name;
        EXPECT_LT(displaced, slotsOfTouched) << name << ": every slot of the touched sub-faces was re-displaced";
        destroyPlanBuffers(ctx, buffers);
    }
}

// At an extraordinary vertex the grid paths move the surface along the limit normal there,
// like every other vertex: a sub-face corner is displaced along the normal of its own
// derivatives, which at smooth EVs is OpenSubdiv's exact limit normal; only where they vanish
// do the paths take them a step inside. (Taking them a step inside everywhere tilted the
// EV's normal by 0.9 degrees at the cube's valence-3 corners, 1.6-1.8 at valence 5 and up to
// 10 at catmark_car's valence 6: a strong raise pushed the EV sideways by D sin(tilt), a
// spike at the corner.)
TEST_F(DisplacementRender, ExtraordinaryCornersAreDisplacedAlongTheLimitNormal) {
    const std::pair<std::string, Cage> cages[] = {{"subdivided cube", test::makeSubdividedCube()},
                                                  {"benchmark cage", makeBenchmarkCage(300, 3)}};
    for (const auto& [name, cage] : cages) {
        PlanDatabase db;
        PlannedCage planned = test::planCage(cage, db);
        const std::vector<glm::dvec3> exact = exactVertexNormals(planned.cage());
        const Topology& topology = planned.topology();
        const float diagonal = computeBounds(planned.cage()).diagonal();
        Displacement d = makeDisplacement(planned.cage(), topology, 4);
        const float D = 0.05f * diagonal;
        std::fill(d.samples.begin(), d.samples.end(), D);
        PlanBuffers buffers = upload(planned, d);
        ASSERT_TRUE(prepareGrid(ctx, pass, buffers, std::min(requiredMeshFactor(planned, d.layout), 64u)).ok());
        for (bool gpu : {false, true}) {
            const std::string what = name + (gpu ? ", compute shader" : ", CPU evaluator");
            const std::vector<GridVertex> grid = fillGrid(planned, buffers, gpu);
            const GridLayout& layout = buffers.gridLayout;
            double worst = 0.0;
            uint32_t corners = 0;
            for (uint32_t drawn = 0; drawn < buffers.data.subfaces.size(); ++drawn) {
                const uint32_t s = buffers.data.subfaces[drawn].subface, n = layout.factors.subfaceFactor[drawn];
                for (uint32_t c = 0; c < 4; ++c) {
                    // Owned corners at cage vertices of valence other than 4, off boundaries and creases.
                    const uint32_t vertex = d.layout.adjacency.subfaces[s].corners[c];
                    if (vertex >= planned.cage().vertexCount()) continue;
                    const uint32_t valence = topology.vertexEdgeCount(vertex);
                    bool sharp = planned.cage().vertexSharpness(vertex) > 0.0f;
                    for (uint32_t k = topology.vertexEdgeOffsets[vertex]; k < topology.vertexEdgeOffsets[vertex + 1]; ++k) {
                        const uint32_t e = topology.vertexEdges[k];
                        sharp = sharp || planned.cage().edgeSharpness(topology.edgeVertices[2 * e], topology.edgeVertices[2 * e + 1]) > 0.0f;
                    }
                    if (valence == 4 || sharp || topology.vertexFaceCount(vertex) != valence) continue;
                    const uint32_t x = c == 1 || c == 2 ? n : 0, y = c >= 2 ? n : 0;
                    const uint32_t slot = layout.subfaceOffset[drawn] + y * (n + 1) + x;
                    if (layout.source[slot] != slot) continue;
                    const LimitSample at = planned.evaluate(s, kCornerU[c], kCornerV[c]);
                    const glm::dvec3 moved = (glm::dvec3(positionOf(grid[slot])) - glm::dvec3(at.position)) / double(D);
                    worst = std::max(worst, std::min(glm::length(moved - exact[vertex]), glm::length(moved + exact[vertex])));
                    ++corners;
                }
            }
            EXPECT_GT(corners, 0u) << what;
            // |moved - N| is the tilt in radians: 0.1 degrees.
            EXPECT_LE(worst, 0.1 * 3.14159265 / 180.0) << what << ": an extraordinary corner was displaced "
                                                        << worst * 180.0 / 3.14159265 << " degrees off the limit normal";
        }
        destroyPlanBuffers(ctx, buffers);
    }
}

// The schemes that draw a displaced CPU mesh (uniform, osd-fas; acc1, acc2, pn and stam on
// their grid) displace their own surface along their own normal; the mesh is watertight bit
// for bit (boundary vertices come from their owner).
TEST(DisplacementSchemes, CpuMeshSchemesAreDisplacedAndWatertight) {
    const PluginCatalog catalog = loadPlugins(QUADPLAN_PLUGIN_DIR);
    for (auto& [name, cage] : displacementCages()) {
        PlanDatabase db;
        PlannedCage planned = test::planCage(cage, db);
        const float diagonal = computeBounds(planned.cage()).diagonal();
        const Displacement d = randomDisplacement(planned, 8, 0.01f * diagonal, 31);
        for (const char* schemeName : {"uniform", "osd-fas", "acc1", "acc2", "pn", "stam"}) {
            const std::string what = name + ", " + schemeName;
            if (std::string(schemeName) == "stam" && name != "subdivided cube") continue;  // stam: closed cages only
            std::shared_ptr<SchemePlugin> plugin = catalog.find(schemeName);
            ASSERT_TRUE(plugin) << schemeName << " not found in " << catalog.directory;
            Result<SchemeInstance> instance = SchemeInstance::create(plugin);
            ASSERT_TRUE(instance.ok());
            ASSERT_TRUE(instance->build(planned, SchemeSettings{}).ok()) << what;
            ASSERT_TRUE(instance->setDisplacement(&d).ok()) << what;
            ASSERT_TRUE(instance->update().ok()) << what;
            const uint32_t factor = displacedGridFactor(planned, d, 8);
            EXPECT_GE(factor, requiredMeshFactor(planned, d.layout)) << what;
            Result<DisplacedMesh> displaced = displacedSchemeMesh(instance->scheme(), planned, d, factor);
            ASSERT_TRUE(displaced.ok()) << what;
            std::vector<MeshVertex> vertices(displaced->positions.size());
            for (size_t i = 0; i < vertices.size(); ++i) vertices[i] = {displaced->positions[i], displaced->normals[i]};
            // The grids, as buildDisplacedMesh lays them out.
            std::vector<uint32_t> gridSubface, gridFactor, gridOffset;
            uint32_t offset = 0;
            for (uint32_t face = 0; face < planned.cage().faceCount(); ++face)
                for (uint32_t s = planned.firstSubface(face); s < planned.firstSubface(face + 1); ++s) {
                    if (!planned.hasSurface(s)) continue;
                    const uint32_t n = planned.cage().faceSize(face) == 4 ? factor : factor / 2;
                    gridSubface.push_back(s);
                    gridFactor.push_back(n);
                    gridOffset.push_back(offset);
                    offset += (n + 1) * (n + 1);
                }
            ASSERT_EQ(offset, vertices.size());
            // Inside each grid: the scheme's own point moved by D along the scheme's own normal.
            double worst = 0.0, largest = 0.0;
            for (size_t g = 0; g < gridSubface.size(); ++g) {
                const uint32_t n = gridFactor[g];
                for (uint32_t y = 1; y < n; ++y)
                    for (uint32_t x = 1; x < n; ++x) {
                        const SampleRequest request{gridSubface[g], float(x) / float(n), float(y) / float(n)};
                        SurfacePoint p;
                        instance->scheme().evaluate(std::span<const SampleRequest>(&request, 1), std::span<SurfacePoint>(&p, 1));
                        const float D = evaluateDisplacement(d, request.subface, request.u, request.v).value;
                        const glm::vec3 expected = p.position + D * p.normal;
                        const MeshVertex& b = vertices[gridOffset[g] + y * (n + 1) + x];
                        worst = std::max(worst, double(glm::length(b.position - expected)) / diagonal);
                        largest = std::max(largest, double(std::fabs(D)) / diagonal);
                    }
            }
            EXPECT_LE(worst, 1e-5) << what;
            EXPECT_GT(largest, 1e-3) << what;
            expectWatertight(d.layout.adjacency, gridSubface, gridFactor, gridOffset, vertices.data(), what);
        }
    }
}

// A scheme that does not draw displacement says so: the host draws it without and warns.
TEST_F(DisplacementRender, ASchemeWithoutDisplacementIsDrawnWithoutItAndWarns) {
    const PluginCatalog catalog = loadPlugins(QUADPLAN_TEST_PLUGIN_DIR);
    PlanDatabase db;
    PlannedCage planned = test::planCage(test::makeSubdividedCube(), db);
    const Displacement d = randomDisplacement(planned, 4, 0.01f, 3);
    const GpuContext gpu{&ctx, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_D32_SFLOAT};
    const CageFeatures features = analyzeCage(planned.cage(), planned.topology());
    Result<PreparedScheme> prepared = prepareScheme(catalog, "test-flat", planned, features, {}, gpu, "cube", &d);
    ASSERT_TRUE(prepared.ok()) << prepared.error().message;
    ASSERT_FALSE(prepared->support.approximations.empty());
    EXPECT_NE(prepared->support.approximations.back().find("drawn without the sculpted displacement"), std::string::npos)
        << prepared->support.approximations.back();
    EXPECT_TRUE(prepared->instance.destroyGpu().ok());
}
