// Plans on the GPU (lavapipe, validation on): positions from both drawing paths match the CPU
// evaluator, shared edges are bit-identical, draws are split under lavapipe's vertex limit,
// and the pictures look like surfaces.
#include <gtest/gtest.h>

#include <cstring>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <numeric>
#include <tuple>

#include <glm/geometric.hpp>

#include "camera.h"
#include "draw_path.h"
#include "extraordinary_corners.h"
#include "line_pass.h"
#include "mesh/obj_io.h"
#include "offscreen_target.h"
#include "plan_pass.h"
#include "plans/planned_cage.h"
#include "render_test_support.h"
#include "test_cages.h"
#include "test_support.h"
#include "vk_commands.h"

using namespace qp;

namespace {

constexpr uint32_t kImageSize = 320;

// Where a boundary vertex lies, independent of which sub-face produced it: a boundary point,
// or a position along a segment as a reduced fraction.
using BoundaryKey = std::tuple<int, uint32_t, uint32_t, uint32_t>;

BoundaryKey boundaryKey(const GpuPlanData& data, uint32_t drawn, uint32_t edge, uint32_t i, uint32_t n) {
    static const uint32_t startCorner[4] = {0, 1, 3, 0}, endCorner[4] = {1, 2, 2, 3};
    const GpuSubfaceBoundary& b = data.boundaries[drawn];
    const GpuEdgeRef& r = b.edges[edge];
    if (i == 0) return {0, b.corners[startCorner[edge]], 0, 0};
    if (i == n) return {0, b.corners[endCorner[edge]], 0, 0};
    uint32_t segment = r.segment, c = (r.flags & 1) ? n - i : i, k = n;
    if (r.flags & 2) {
        k = n / 2;
        if (i == k) return {0, r.midpoint, 0, 0};
        if (i > k) {
            segment = r.secondHalf;
            c = n - i;
        }
    }
    uint32_t g = std::gcd(c, k);
    return {1, segment, c / g, k / g};
}

struct Fixture : test::PlanPassTest {
    OffscreenTarget target;

    void SetUp() override {
        PlanPassTest::SetUp();
        if (HasFatalFailure()) return;
        Result<OffscreenTarget> t = createOffscreenTarget(ctx, kImageSize, kImageSize, VK_FORMAT_R8G8B8A8_UNORM);
        ASSERT_TRUE(t.ok()) << t.error().message;
        target = *t;
    }
    void TearDown() override {
        if (ctx.device) destroyOffscreenTarget(ctx, target);
        PlanPassTest::TearDown();
    }

    PlanView frame(const PlannedCage& planned) const {
        return test::framedPlanView(planned.cage(), kImageSize);
    }

    std::vector<uint8_t> pixels() {
        Result<std::vector<uint8_t>> read = readPixels(ctx, target);
        EXPECT_TRUE(read.ok());
        return std::move(read).value();
    }
};

std::vector<std::pair<std::string, Cage>> testCages() {
    // A hole where a triangle was: the quad beside it keeps its edge whole (no n-gon meets it).
    Cage holeNgon = test::makeMixedGrid();
    holeNgon.setHole(holeNgon.faceCount() - 2, true);
    std::vector<std::pair<std::string, Cage>> cages = {{"features", test::makeFeatureCage()},
                                                       {"subdivided cube", test::makeSubdividedCube()},
                                                       {"n-gon hole", std::move(holeNgon)}};
    if (test::haveSharedShapes())
        for (const char* name : {"catmark_nonquads", "catmark_cube_creases1", "catmark_pole8"}) {
            Result<Cage> cage = loadObj((test::sharedShapesDir() / (std::string(name) + ".obj")).string());
            if (cage) cages.push_back({name, std::move(cage).value()});
        }
    return cages;
}

double coverage(const std::vector<uint8_t>& rgba, const std::vector<uint8_t>& background) {
    size_t covered = 0;
    for (size_t i = 0; i < rgba.size(); i += 4) covered += std::memcmp(&rgba[i], &background[0], 3) != 0;
    return double(covered) / double(rgba.size() / 4);
}

}  // namespace

namespace {

// The grid as each evaluator fills it, for the layout in `buffers` (prepareGrid first). Slots
// start as NaN, so one that no phase writes cannot pass for a surface point.
std::vector<GridVertex> fillGrid(Fixture& f, const PlannedCage& planned, PlanBuffers& buffers, DrawPath evaluator) {
    std::memset(buffers.grid.data, 0xff, buffers.gridLayout.slotCount() * sizeof(GridVertex));
    buffers.gridEvaluator = GridEvaluator::None;
    if (evaluator == DrawPath::CpuGrid) {
        buffers.controlPointLevel = kNoControlPoints;  // the CPU path computes none on the device
        evaluateGridOnCpu(planned, buffers);
    } else {
        Status done = submitAndWait(f.ctx, [&](VkCommandBuffer cmd) { recordGridEvaluation(cmd, f.pass, buffers); });
        EXPECT_TRUE(done.ok());
    }
    const GridVertex* grid = static_cast<const GridVertex*>(buffers.grid.data);
    return std::vector<GridVertex>(grid, grid + buffers.gridLayout.slotCount());
}

// Checks a filled grid against the CPU evaluator and for watertightness: every slot lies on
// its own sub-face's limit surface (edge slots at the edge vertex they snap to), and every slot
// showing the same boundary vertex, whichever sub-face it belongs to, has the same bits.
// With `expectSnapped`, some edge must be coarser than its face (adaptive layouts).
void checkGrid(const PlannedCage& planned, const PlanBuffers& buffers, const std::vector<GridVertex>& grid,
               const std::string& what, bool expectSnapped = false) {
    const GridLayout& layout = buffers.gridLayout;
    const GpuPlanData& data = buffers.data;
    const float diagonal = computeBounds(planned.cage()).diagonal();
    double worst = 0.0;
    std::map<BoundaryKey, const GridVertex*> seen;
    uint32_t shared = 0, snapped = 0;
    for (uint32_t d = 0; d < data.subfaces.size(); ++d) {
        const uint32_t n = layout.factors.subfaceFactor[d], side = n + 1;
        for (uint32_t k = 0; k < side * side; ++k) {
            const uint32_t x = k % side, y = k / side;
            const GridVertex& g = grid[layout.subfaceOffset[d] + k];
            float u = float(x) / float(n), v = float(y) / float(n);
            const int edge = y == 0 ? 0 : x == n ? 1 : y == n ? 2 : x == 0 ? 3 : -1;
            uint32_t j = 0, pieces = 0;
            if (edge >= 0) {
                // The edge's pieces, from the segment(s) on it; slot i of n shows the nearest of them.
                const GpuEdgeRef& r = data.boundaries[d].edges[edge];
                pieces = layout.factors.segmentPieces[r.segment] * ((r.flags & 2) ? 2 : 1);
                const uint32_t i = (edge == 1 || edge == 3) ? y : x;
                const double t = double(i) * pieces / n;
                j = uint32_t(std::floor(t + 0.5));
                snapped += double(j) != t;
                (edge == 1 || edge == 3 ? v : u) = float(j) / float(pieces);
            }
            const LimitSample cpu = planned.evaluate(data.subfaces[d].subface, u, v);
            const glm::vec3 p(g.position[0], g.position[1], g.position[2]);
            const double error = double(glm::length(p - cpu.position)) / diagonal;
            ASSERT_TRUE(std::isfinite(error)) << what << ": slot " << k << " of drawn sub-face " << d << " was never written";
            worst = std::max(worst, error);
            if (edge < 0) continue;
            auto [it, inserted] = seen.emplace(boundaryKey(data, d, uint32_t(edge), j, pieces), &g);
            if (!inserted) {
                ++shared;
                ASSERT_EQ(std::memcmp(it->second, &g, sizeof(GridVertex)), 0)
                    << what << ": drawn sub-face " << d << " edge " << edge << " vertex " << j << " of " << pieces
                    << " differs from its neighbour's copy";
            }
        }
    }
    EXPECT_LE(worst, 1e-5) << what;
    EXPECT_GT(shared, 0u) << what;
    if (expectSnapped) {
        EXPECT_GT(snapped, 0u) << what << ": no edge is coarser than its face";
    }
}

}  // namespace

// The shaders keep the control points relative to each sub-face's first ring vertex, as the
// CPU does (core/plans/planned_cage.h): at depth 10 on a cube far from the origin the grid's normals
// at the valence-3 corners stay in the exact limit tangent plane (in the model's absolute
// coordinates float put them off by degrees there and flipped some).
TEST_F(Fixture, GridNormalsAtExtraordinaryCornersKeepTheirPrecisionOnTheDevice) {
    const Cage cage = test::makeFarOffCube();
    PlanDatabase db;
    PlanOptions options;
    options.maxDepth = 10;
    Result<PlannedCage> created = PlannedCage::create(cage, db, options, "far cube");
    ASSERT_TRUE(created.ok()) << created.error().message;
    const PlannedCage& planned = *created;
    PlanBuffers buffers = upload(planned);
    ASSERT_TRUE(prepareGrid(ctx, pass, buffers, 4u).ok());
    const std::vector<GridVertex> grid = fillGrid(*this, planned, buffers, DrawPath::Grid);
    const GridLayout& layout = buffers.gridLayout;
    uint32_t corners = 0;
    const double worst = test::worstValence3CornerDegrees(cage, [&](uint32_t f, uint32_t k) {
        const uint32_t d = buffers.drawnOfSubface[planned.firstSubface(f)], side = layout.factors.subfaceFactor[d] + 1;
        const uint32_t x = (k == 1 || k == 2) ? side - 1 : 0, y = (k == 2 || k == 3) ? side - 1 : 0;
        const GridVertex& g = grid[layout.subfaceOffset[d] + y * side + x];
        return glm::dvec3(g.normal[0], g.normal[1], g.normal[2]);
    }, corners);
    EXPECT_EQ(corners, 24u);
    EXPECT_LT(worst, 0.1) << "degrees from the exact limit tangent plane";
    destroyPlanBuffers(ctx, buffers);
}

TEST_F(Fixture, GridPathsMatchCpuAndAreWatertight) {
    for (auto& [name, cage] : testCages()) {
        PlanDatabase db;
        PlannedCage planned = test::planCage(cage, db);
        PlanBuffers buffers = upload(planned);
        PlanView view = frame(planned);
        std::vector<std::pair<std::string, GridFactors>> layouts;
        for (uint32_t factor : {2u, 7u, 16u})
            layouts.push_back({"uniform " + std::to_string(factor), uniformGridFactors(buffers.data, factor)});
        // Adaptive: the camera close to the cage, so that near and far edges get different
        // factors; the target segment length grows until no edge is clamped at 64.
        Bounds bounds = computeBounds(planned.cage());
        RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
        camera.eye = camera.target + 0.45f * (camera.eye - camera.target);
        PlanView close = view;
        close.viewProjection = viewProjection(camera);
        float pixels = 3.0f;
        auto adaptive = [&](float p) { return adaptiveGridFactors(buffers, close, TessellationSettings{0, p}); };
        while (pixels < 200.0f && std::ranges::max(adaptive(pixels).subfaceFactor) == 64) pixels *= 2.0f;
        for (float p : {pixels, 3.0f * pixels}) {
            GridFactors factors = adaptive(p);
            std::set<uint32_t> distinct(factors.subfaceFactor.begin(), factors.subfaceFactor.end());
            EXPECT_GT(distinct.size(), 1u) << name << ": adaptive factors are all " << *distinct.begin();
            layouts.push_back({"adaptive " + std::to_string(p) + " px", std::move(factors)});
        }
        for (auto& [what, factors] : layouts) {
            ASSERT_TRUE(prepareGrid(ctx, pass, buffers, factors).ok());
            std::vector<GridVertex> gpu = fillGrid(*this, planned, buffers, DrawPath::Grid);
            std::vector<GridVertex> cpu = fillGrid(*this, planned, buffers, DrawPath::CpuGrid);
            const bool adaptive = what.rfind("adaptive", 0) == 0;
            checkGrid(planned, buffers, gpu, name + ", compute shader, " + what, adaptive);
            checkGrid(planned, buffers, cpu, name + ", CPU evaluator, " + what, adaptive);
            if (HasFatalFailure()) return;
        }
        destroyPlanBuffers(ctx, buffers);
    }
}

namespace {

// Draws the tessellated path with capture on (enableCapture first) and checks what the
// evaluation stage wrote against the CPU evaluator, the factors of shared segments (equal from
// both sides; a quad edge split by an n-gon gets 2k, each n-gon sub-face k) and watertightness.
void checkTessellated(Fixture& f, const PlannedCage& planned, PlanBuffers& buffers, const TessellationSettings& settings,
                      const std::string& what) {
    PlanView view = f.frame(planned);
    view.capture = true;
    ASSERT_TRUE(submitAndWait(f.ctx, [&](VkCommandBuffer cmd) {
        recordTessellated(cmd, f.pass, buffers, renderTarget(f.target), view, settings);
    }).ok()) << what;
    uint32_t overflow = 0;
    std::vector<CaptureRecord> records = readCapture(buffers, &overflow);
    ASSERT_EQ(overflow, 0u) << what;
    ASSERT_GT(records.size(), buffers.data.subfaces.size()) << what;

    const float diagonal = computeBounds(planned.cage()).diagonal();
    double worst = 0.0;
    std::map<BoundaryKey, const CaptureRecord*> seen;
    std::map<uint32_t, uint32_t> segmentFactor;
    uint32_t shared = 0, factorsAbove1 = 0;
    for (const CaptureRecord& r : records) {
        const uint32_t edge = r.edgeAndFactor & 0xff, n = r.edgeAndFactor >> 8;
        // Edge vertices are evaluated at i/n exactly, not at the tessellator's approximation of it.
        float u = r.u, v = r.v;
        if (edge == 0 || edge == 2) u = float(r.edgeIndex) / float(n);
        if (edge == 1 || edge == 3) v = float(r.edgeIndex) / float(n);
        LimitSample cpu = planned.evaluate(buffers.data.subfaces[r.drawn].subface, u, v);
        worst = std::max(worst, double(glm::length(glm::vec3(r.position[0], r.position[1], r.position[2]) - cpu.position)) /
                                    diagonal);
        if (edge == 4) continue;
        factorsAbove1 += n > 1;
        const GpuEdgeRef& ref = buffers.data.boundaries[r.drawn].edges[edge];
        if (ref.flags & 2) {
            ASSERT_EQ(n % 2, 0u) << what << ": a quad edge split by an n-gon needs an even factor";
        }
        // Both sides of a segment must cut it into the same number of pieces.
        const uint32_t pieces = (ref.flags & 2) ? n / 2 : n;
        auto [it0, fresh] = segmentFactor.emplace(ref.segment, pieces);
        ASSERT_EQ(it0->second, pieces) << what << ": segment " << ref.segment << " split differently by two faces";
        auto [it, inserted] = seen.emplace(boundaryKey(buffers.data, r.drawn, edge, r.edgeIndex, n), &r);
        if (!inserted) {
            ++shared;
            ASSERT_EQ(std::memcmp(it->second->position, r.position, sizeof(r.position)), 0)
                << what << ": drawn sub-face " << r.drawn << " edge " << edge << " vertex " << r.edgeIndex << " of " << n;
        }
    }
    EXPECT_LE(worst, 1e-5) << what;
    EXPECT_GT(shared, 0u) << what;
    EXPECT_GT(factorsAbove1, 0u) << what;
}

}  // namespace

TEST_F(Fixture, TessellatedPathMatchesCpuAndIsWatertight) {
    for (auto& [name, cage] : testCages()) {
        PlanDatabase db;
        PlannedCage planned = test::planCage(cage, db);
        PlanBuffers buffers = upload(planned);
        ASSERT_TRUE(enableCapture(ctx, buffers, 2'000'000).ok());
        ASSERT_TRUE(bindPlanBuffers(ctx, pass, buffers).ok());
        for (TessellationSettings settings : {TessellationSettings{3, 0}, TessellationSettings{8, 0},
                                              TessellationSettings{0, 6.0f}, TessellationSettings{0, 2.5f}}) {
            checkTessellated(*this, planned, buffers, settings,
                             name + (settings.uniformFactor ? " uniform " + std::to_string(settings.uniformFactor)
                                                            : " adaptive " + std::to_string(settings.pixelsPerSegment)));
            if (HasFatalFailure()) return;
        }
        destroyPlanBuffers(ctx, buffers);
    }
}

// Every Catmull-Clark cage OpenSubdiv ships for its regression, through all three paths at one
// uniform and one adaptive setting: positions against the CPU evaluator, watertight edges.
TEST_F(Fixture, EverySharedCageOnEveryPath) {
    QP_REQUIRE_SHARED_SHAPES();
    uint32_t cages = 0;
    for (const std::filesystem::path& path : test::sharedShapes("catmark_")) {
        const std::string name = path.stem().string();
        Result<Cage> cage = loadObj(path.string());
        ASSERT_TRUE(cage.ok()) << name << ": " << cage.error().message;
        PlanDatabase db;
        Result<PlannedCage> planned = PlannedCage::create(std::move(cage).value(), db, {}, name);
        ASSERT_TRUE(planned.ok()) << name << ": " << planned.error().message;
        PlanBuffers buffers = upload(*planned);
        if (buffers.data.subfaces.empty()) {  // e.g. every face a hole: nothing to draw
            destroyPlanBuffers(ctx, buffers);
            continue;
        }
        ++cages;
        ASSERT_TRUE(enableCapture(ctx, buffers, 4'000'000).ok());
        ASSERT_TRUE(bindPlanBuffers(ctx, pass, buffers).ok());
        checkTessellated(*this, *planned, buffers, TessellationSettings{5, 0}, name + ", tess uniform 5");
        checkTessellated(*this, *planned, buffers, TessellationSettings{0, 4.0f}, name + ", tess adaptive 4 px");
        const TessellationSettings adaptive{0, 4.0f};
        for (const auto& [what, factors] : {std::pair{std::string("uniform 5"), uniformGridFactors(buffers.data, 5)},
                                            std::pair{std::string("adaptive 4 px"),
                                                      adaptiveGridFactors(buffers, frame(*planned), adaptive)}}) {
            ASSERT_TRUE(prepareGrid(ctx, pass, buffers, factors).ok()) << name;
            checkGrid(*planned, buffers, fillGrid(*this, *planned, buffers, DrawPath::Grid), name + ", grid " + what);
            checkGrid(*planned, buffers, fillGrid(*this, *planned, buffers, DrawPath::CpuGrid), name + ", cpu " + what);
        }
        destroyPlanBuffers(ctx, buffers);
        if (HasFatalFailure()) return;
    }
    EXPECT_GT(cages, 50u);
}

TEST_F(Fixture, SplitDrawsMatchTheGridPathOnALargeCage) {
    QP_REQUIRE_SHARED_SHAPES();
    Result<Cage> car = loadObj((test::sharedShapesDir() / "catmark_car.obj").string());
    ASSERT_TRUE(car.ok());
    PlanDatabase db;
    PlannedCage planned = test::planCage(*car, db);
    PlanBuffers buffers = upload(planned);
    // 1,575 patches at factor 16 are 7 draws of at most 226 (lavapipe corrupts 228 and more).
    EXPECT_EQ(patchesPerDraw(16), 226u);
    ASSERT_GT(buffers.data.subfaces.size(), patchesPerDraw(16));
    PlanView view = frame(planned);
    TessellationSettings settings{16, 0};
    ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) { recordTessellated(cmd, pass, buffers, renderTarget(target), view, settings); }).ok());
    std::vector<uint8_t> tessellated = pixels();
    ASSERT_TRUE(prepareGrid(ctx, pass, buffers, 16).ok());
    ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) { recordGrid(cmd, pass, buffers, renderTarget(target), view); }).ok());
    std::vector<uint8_t> grid = pixels();
    std::vector<uint8_t> background(tessellated.begin(), tessellated.begin() + 4);  // corner pixel
    // Same surface, same camera: the silhouettes agree; stray triangles would not.
    size_t differ = 0;
    for (size_t i = 0; i < grid.size(); i += 4) {
        bool a = std::memcmp(&tessellated[i], background.data(), 3) != 0, b = std::memcmp(&grid[i], background.data(), 3) != 0;
        differ += a != b;
    }
    EXPECT_GT(coverage(grid, background), 0.15);
    EXPECT_LT(double(differ) / double(grid.size() / 4), 0.003);
    EXPECT_TRUE(writePng((test::testOutputDir() / "plans_car_tessellated.png").string(), kImageSize, kImageSize, tessellated).ok());
    EXPECT_TRUE(writePng((test::testOutputDir() / "plans_car_grid.png").string(), kImageSize, kImageSize, grid).ok());
    destroyPlanBuffers(ctx, buffers);
}

// Every colour mode on the tessellated path and on the grid (whose plain shading and colour
// modes use different pipelines): each differs from plain shading, and both paths cover the
// same pixels.
TEST_F(Fixture, ColourModesAndWireframeDraw) {
    PlanDatabase db;
    PlannedCage planned = test::planCage(test::makeFeatureCage(), db);
    PlanBuffers buffers = upload(planned);
    PlanView view = frame(planned);
    const TessellationSettings settings{0, 6.0f};
    std::map<ColorBy, double> tessCoverage;
    for (DrawPath path : {DrawPath::Tessellated, DrawPath::CpuGrid}) {
        std::vector<uint8_t> shaded;
        for (ColorBy mode : {ColorBy::Shading, ColorBy::NodeKind, ColorBy::PlanDepth, ColorBy::Sharpness}) {
            const std::string what = std::string(drawPathName(path)) + " mode " + std::to_string(uint32_t(mode));
            view.colorBy = mode;
            view.wireframe = mode == ColorBy::NodeKind;
            ASSERT_TRUE(preparePlanFrame(ctx, pass, buffers, planned, path, view, settings).ok());
            ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) {
                recordPlanFrame(cmd, pass, buffers, path, renderTarget(target), view, settings);
            }).ok());
            std::vector<uint8_t> image = pixels();
            std::vector<uint8_t> background(image.begin(), image.begin() + 4);
            const double covered = coverage(image, background);
            EXPECT_GT(covered, 0.1) << what;
            if (path == DrawPath::Tessellated) tessCoverage[mode] = covered;
            else EXPECT_NEAR(covered, tessCoverage[mode], 0.01) << what << ": the paths cover different pixels";
            if (mode == ColorBy::Shading) shaded = image;
            else EXPECT_NE(image, shaded) << what << " looks like plain shading";
            EXPECT_TRUE(writePng((test::testOutputDir() / ("plans_features_" + std::string(drawPathName(path)) + "_mode" +
                                                           std::to_string(uint32_t(mode)) + ".png")).string(),
                                 kImageSize, kImageSize, image).ok());
        }
    }
    destroyPlanBuffers(ctx, buffers);
}

// Every shader and the clear encode colour the same way: one picture (plans, tessellation
// wireframe, cage lines, background) stores the same bytes in an _SRGB target, where the
// hardware encodes, and in a UNORM target, where the shaders do.
TEST_F(Fixture, SrgbAndUnormTargetsStoreTheSamePicture) {
    PlanDatabase db;
    PlannedCage planned = test::planCage(test::makeFeatureCage(), db);
    PlanView view = frame(planned);
    view.wireframe = true;
    const std::vector<LineVertex> cage = cageLines(planned.cage());
    std::vector<std::vector<uint8_t>> images;
    for (VkFormat format : {VK_FORMAT_R8G8B8A8_SRGB, VK_FORMAT_R8G8B8A8_UNORM}) {
        Result<OffscreenTarget> t = createOffscreenTarget(ctx, kImageSize, kImageSize, format);
        Result<PlanPass> plans = createPlanPass(ctx, VK_NULL_HANDLE, format);
        Result<LinePass> lines = createLinePass(ctx, VK_NULL_HANDLE, format);
        Result<PlanBuffers> buffers = uploadPlans(ctx, planned);
        Result<Buffer> lineBuffer = createBuffer(ctx, cage.size() * sizeof(LineVertex), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
        ASSERT_TRUE(t && plans && lines && buffers && lineBuffer);
        uploadBuffer(*lineBuffer, cage.data(), cage.size() * sizeof(LineVertex));
        ASSERT_TRUE(bindPlanBuffers(ctx, *plans, *buffers).ok());
        ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) {
            recordTessellated(cmd, *plans, *buffers, renderTarget(*t), view, TessellationSettings{6, 0});
            recordLines(cmd, *lines, renderTarget(*t), view.viewProjection, *lineBuffer, uint32_t(cage.size()));
        }).ok());
        Result<std::vector<uint8_t>> read = readPixels(ctx, *t);
        ASSERT_TRUE(read.ok());
        images.push_back(std::move(read).value());
        destroyBuffer(ctx, *lineBuffer);
        destroyPlanBuffers(ctx, *buffers);
        destroyLinePass(ctx, *lines);
        destroyPlanPass(ctx, *plans);
        destroyOffscreenTarget(ctx, *t);
    }
    int worst = 0;
    size_t differing = 0;
    for (size_t i = 0; i < images[0].size(); ++i) {
        const int d = std::abs(int(images[0][i]) - int(images[1][i]));
        worst = std::max(worst, d);
        differing += d > 1;
    }
    // Rounding differs by one level at most between the hardware's and the shader's encoding.
    EXPECT_LE(worst, 1) << differing << " bytes differ by more than one level";
    std::vector<uint8_t> background(images[1].begin(), images[1].begin() + 4);
    EXPECT_GT(coverage(images[1], background), 0.1);
}

// Dragging vertices updates only the sub-faces around them, with the same bits as a full
// re-evaluation: control points, both grid evaluators, uniform and adaptive (snapped) layouts,
// and the boundary points the adaptive factors read.
TEST_F(Fixture, MovedVerticesUpdateExactlyWhatAFullEvaluationWould) {
    std::vector<std::pair<std::string, Cage>> cages = testCages();
    if (test::haveSharedShapes()) {
        Result<Cage> car = loadObj((test::sharedShapesDir() / "catmark_car.obj").string());
        ASSERT_TRUE(car.ok());
        cages.push_back({"catmark_car", std::move(car).value()});
    }
    for (auto& [name, cage] : cages) {
        PlanDatabase db;
        PlannedCage planned = test::planCage(cage, db);
        PlanBuffers buffers = upload(planned);
        const PlanView view = frame(planned);
        const float step = 0.03f * computeBounds(planned.cage()).diagonal();
        // One vertex, then three: on a crease, at an n-gon, at an extraordinary vertex when the
        // cage has them (the feature cage does).
        const uint32_t vertexCount = planned.cage().vertexCount();
        std::vector<uint32_t> three = {7 % vertexCount, 16 % vertexCount, vertexCount - 1};
        std::sort(three.begin(), three.end());
        three.erase(std::unique(three.begin(), three.end()), three.end());
        const std::vector<std::vector<uint32_t>> moves = {{vertexCount / 2}, three};
        for (DrawPath evaluator : {DrawPath::Grid, DrawPath::CpuGrid})
            for (bool adaptive : {false, true}) {
                const std::string what = name + (evaluator == DrawPath::Grid ? ", compute shader" : ", CPU evaluator") +
                                         (adaptive ? ", adaptive" : ", uniform 8");
                SCOPED_TRACE(what);
                const TessellationSettings settings{adaptive ? 0u : 8u, 6.0f};
                ASSERT_TRUE(preparePlanFrame(ctx, pass, buffers, planned, DrawPath::CpuGrid, view, settings).ok());
                fillGrid(*this, planned, buffers, evaluator);
                for (const std::vector<uint32_t>& moved : moves) {
                    std::vector<glm::vec3> to;
                    for (uint32_t v : moved) to.push_back(planned.cage().positions[v] + step * glm::vec3(0.2f, -0.5f, 0.7f));
                    ASSERT_TRUE(planned.moveVertices(moved, to).ok());
                    MoveUpdate update;
                    ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) {
                        update = recordMovedVertices(cmd, pass, buffers, planned, moved);
                    }).ok());
                    EXPECT_GT(update.evaluatedSubfaces, 0u);
                    EXPECT_GE(update.copiedSubfaces, update.evaluatedSubfaces);
                    if (buffers.data.subfaces.size() > 100) {
                        EXPECT_LT(update.copiedSubfaces, buffers.data.subfaces.size() / 4);
                    }
                    EXPECT_EQ(update.controlPointSubfaces, evaluator == DrawPath::Grid ? update.evaluatedSubfaces : 0u);
                    const GridVertex* grid = static_cast<const GridVertex*>(buffers.grid.data);
                    const std::vector<GridVertex> updated(grid, grid + buffers.gridLayout.slotCount());
                    const auto* cp = static_cast<const glm::vec4*>(buffers.controlPoints.data);
                    const std::vector<glm::vec4> updatedControlPoints(cp, cp + buffers.data.controlPointCount);
                    const uint32_t level = buffers.controlPointLevel;
                    const std::vector<glm::vec4> points(buffers.pointPositionsHost);

                    updatePositions(buffers, planned);
                    EXPECT_EQ(std::memcmp(points.data(), buffers.pointPositionsHost.data(), points.size() * sizeof(glm::vec4)), 0);
                    EXPECT_EQ(std::memcmp(points.data(), buffers.pointPositions.data, points.size() * sizeof(glm::vec4)), 0);
                    const std::vector<GridVertex> full = fillGrid(*this, planned, buffers, evaluator);
                    ASSERT_EQ(updated.size(), full.size());
                    EXPECT_EQ(std::memcmp(updated.data(), full.data(), full.size() * sizeof(GridVertex)), 0)
                        << "the updated grid differs from a full evaluation";
                    if (evaluator == DrawPath::Grid) {
                        EXPECT_EQ(buffers.controlPointLevel, level);
                        EXPECT_EQ(std::memcmp(updatedControlPoints.data(), cp, updatedControlPoints.size() * sizeof(glm::vec4)), 0)
                            << "updated control points differ from a full stencil pass";
                    }
                }
            }
        destroyPlanBuffers(ctx, buffers);
    }
}

// Ownership as gpu_plans.h defines it, checked against the tables packSubfaces builds on all
// cores: segments are numbered in the order of their first use (non-quad sub-faces first, then
// quads, each in drawing order, edges 0-3, a split edge's first half before its second) and
// owned by that first user; a boundary point is owned by the first sub-face with it as a corner.
TEST(GpuPlans, SegmentsAndPointsBelongToTheirFirstUser) {
    PlanDatabase db;
    for (const Cage& cage : {test::makeFeatureCage(), test::makeSubdividedCube()}) {
        PlannedCage planned = test::planCage(cage, db);
        const GpuPlanData data = packPlans(planned);
        auto isQuad = [&](uint32_t d) {
            const uint32_t subface = data.subfaces[d].subface;
            uint32_t face = 0;
            while (planned.firstSubface(face + 1) <= subface) ++face;
            return planned.cage().faceSize(face) == 4;
        };
        std::vector<uint32_t> seenSegments;
        std::set<uint32_t> seenPoints;
        for (bool quads : {false, true})
            for (uint32_t d = 0; d < data.subfaces.size(); ++d) {
                if (isQuad(d) != quads) continue;
                const GpuSubfaceBoundary& b = data.boundaries[d];
                auto use = [&](uint32_t segment, uint32_t edge) {
                    if (std::find(seenSegments.begin(), seenSegments.end(), segment) != seenSegments.end()) return;
                    EXPECT_EQ(segment, seenSegments.size()) << "segments are numbered by first use";
                    seenSegments.push_back(segment);
                    EXPECT_EQ(data.segments[segment].owner, d);
                    EXPECT_EQ(data.segments[segment].ownerEdge & 3, edge);
                };
                for (uint32_t e = 0; e < 4; ++e) {
                    use(b.edges[e].segment, e);
                    if (b.edges[e].flags & kEdgeRefSplit) use(b.edges[e].secondHalf, e);
                }
                for (uint32_t c = 0; c < 4; ++c)
                    if (seenPoints.insert(b.corners[c]).second) {
                        EXPECT_EQ(data.boundaryPoints[b.corners[c]].owner, d);
                        EXPECT_EQ(data.boundaryPoints[b.corners[c]].ownerCorner, c);
                    }
            }
        EXPECT_EQ(seenSegments.size(), data.segments.size());
    }
}

// Host evaluation packs no 1-rings; the ring users are the same as with them, and tell an
// unchanged ring (in any order) from a changed one.
TEST(GpuPlans, RingUsersWithoutPackedRings) {
    PlanDatabase db;
    for (const Cage& cage : {test::makeFeatureCage(), test::makeSubdividedCube()}) {
        PlannedCage planned = test::planCage(cage, db);
        const GpuPlanData packed = packPlans(planned), host = packPlans(planned, true);
        EXPECT_TRUE(host.rings.empty());
        EXPECT_EQ(host.ringEntries, packed.rings.size());
        EXPECT_EQ(host.vertexSubfaceOffsets, packed.vertexSubfaceOffsets);
        EXPECT_EQ(host.vertexSubfaces, packed.vertexSubfaces);
        const uint32_t vertexCount = planned.cage().vertexCount();
        for (uint32_t d = 0; d < host.subfaces.size(); ++d) {
            const std::span<const uint32_t> ring = planned.subfaceRing(host.subfaces[d].subface);
            ASSERT_TRUE(ringUsersMatch(host, d, ring)) << "drawn sub-face " << d;
            std::vector<uint32_t> other(ring.begin(), ring.end());
            std::reverse(other.begin(), other.end());
            EXPECT_TRUE(ringUsersMatch(host, d, other)) << "the same vertices in another order";
            other.back() = other.front();  // one vertex twice, one missing
            EXPECT_FALSE(ringUsersMatch(host, d, other));
            other.back() = (ring.front() + 1) % vertexCount;
            if (std::find(ring.begin(), ring.end(), other.back()) == ring.end()) {
                EXPECT_FALSE(ringUsersMatch(host, d, other));
            }
            other.pop_back();
            EXPECT_FALSE(ringUsersMatch(host, d, other)) << "a shorter ring";
        }
    }
}

// Pixels, not just vertices: from inside a closed surface every pixel must show the surface.
// A crack between sub-faces (a T-junction, an unsnapped edge, a wrong owner) would show the
// pure red background. Adaptive factors from an off-centre eye, so neighbours differ.
TEST_F(Fixture, ClosedSurfaceSeenFromInsideHasNoCracks) {
    PlanDatabase db;
    PlannedCage planned = test::planCage(test::makeSubdividedCube(), db);
    PlanBuffers buffers = upload(planned);
    RenderCamera camera;
    camera.eye = {0.45f, 0.35f, 0.3f};
    camera.fovY = glm::radians(110.0f);
    camera.nearZ = 0.005f;
    camera.farZ = 10.0f;
    for (glm::vec3 lookAt : {glm::vec3(1.0f, 1.0f, 1.0f), glm::vec3(-1.0f, 0.2f, -0.5f)}) {
        camera.target = lookAt;
        PlanView view;
        view.viewProjection = viewProjection(camera);
        view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(camera), kImageSize);
        view.background = {1.0f, 0.0f, 0.0f};
        for (DrawPath path : {DrawPath::Tessellated, DrawPath::CpuGrid, DrawPath::Grid})
            for (TessellationSettings settings : {TessellationSettings{0, 12.0f}, TessellationSettings{0, 40.0f},
                                                  TessellationSettings{5, 0}}) {
                const std::string what = std::string(drawPathName(path)) +
                                         (settings.uniformFactor ? " uniform" : " adaptive " + std::to_string(settings.pixelsPerSegment));
                ASSERT_TRUE(preparePlanFrame(ctx, pass, buffers, planned, path, view, settings).ok()) << what;
                ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) {
                    recordPlanFrame(cmd, pass, buffers, path, renderTarget(target), view, settings);
                }).ok());
                const std::vector<uint8_t> image = pixels();
                size_t background = 0;
                for (size_t i = 0; i < image.size(); i += 4)
                    background += image[i] == 255 && image[i + 1] == 0 && image[i + 2] == 0;
                EXPECT_EQ(background, 0u) << what << ": background shows through";
                if (path == DrawPath::CpuGrid && !settings.uniformFactor) {
                    std::set<uint32_t> factors(buffers.gridLayout.factors.subfaceFactor.begin(),
                                               buffers.gridLayout.factors.subfaceFactor.end());
                    EXPECT_GT(factors.size(), 1u) << what << ": every sub-face got the same factor";
                }
            }
    }
    destroyPlanBuffers(ctx, buffers);
}
