// Sample culling (render/sample_culling.h): the CPU grid leaves out triangles that cover no
// pixel centre, and the picture stays the same pixel for pixel: from far and close views, in a
// viewport inside a larger image, with hidden faces, after vertex moves, after faces hidden
// and shown again and after topology edits, drawn incrementally.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "draw_path.h"
#include "edit/edit_history.h"
#include "mesh/generated_cage.h"
#include "mesh/topology_edits.h"
#include "offscreen_target.h"
#include "plan_pass.h"
#include "plan_update.h"
#include "plans/planned_cage.h"
#include "render_test_support.h"
#include "sample_culling.h"
#include "test_cages.h"
#include "vk_commands.h"

using namespace qp;

namespace {

// Object (x, y) in [0, width] x [0, height] onto the same framebuffer pixels, z = 0.5 in depth.
SampleView pixelView(uint32_t width, uint32_t height) {
    SampleView view;
    view.width = width, view.height = height;
    view.viewProjection = glm::translate(glm::mat4(1.0f), glm::vec3(-1.0f, -1.0f, 0.5f)) *
                          glm::scale(glm::mat4(1.0f), glm::vec3(2.0f / float(width), 2.0f / float(height), 0.0f));
    return view;
}

// Whether a pixel centre lies strictly inside the triangle (pixel coordinates): what must never
// be culled.
bool coversACentreStrictly(glm::vec2 a, glm::vec2 b, glm::vec2 c, uint32_t width, uint32_t height) {
    auto cross = [](glm::vec2 p, glm::vec2 q, glm::vec2 r) { return (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x); };
    for (uint32_t j = 0; j < height; ++j)
        for (uint32_t i = 0; i < width; ++i) {
            const glm::vec2 s{float(i) + 0.5f, float(j) + 0.5f};
            const float e0 = cross(a, b, s), e1 = cross(b, c, s), e2 = cross(c, a, s);
            if ((e0 > 0 && e1 > 0 && e2 > 0) || (e0 < 0 && e1 < 0 && e2 < 0)) return true;
        }
    return false;
}

}  // namespace

TEST(SampleCulling, KeepsEveryTriangleThatCoversAPixelCentre) {
    const uint32_t width = 24, height = 16;
    const SampleView view = pixelView(width, height);
    std::mt19937 random(7);
    std::uniform_real_distribution<float> corner(-2.0f, 26.0f), size(0.05f, 3.0f), unit(-1.0f, 1.0f);
    uint32_t culled = 0, covering = 0;
    for (int t = 0; t < 20000; ++t) {
        const glm::vec2 a{corner(random), corner(random) * float(height) / float(width)};
        const float s = size(random);
        const glm::vec2 b = a + s * glm::vec2(unit(random), unit(random)), c = a + s * glm::vec2(unit(random), unit(random));
        const bool covers = coversACentreStrictly(a, b, c, width, height);
        const bool kept = mayCoverPixelCentre({a, 0.0f}, {b, 0.0f}, {c, 0.0f}, view);
        covering += covers;
        culled += !kept;
        ASSERT_TRUE(kept || !covers) << "culled a triangle covering a pixel centre: (" << a.x << ", " << a.y << ") (" << b.x
                                     << ", " << b.y << ") (" << c.x << ", " << c.y << ")";
    }
    EXPECT_GT(culled, 20000u / 4) << "small triangles between pixel centres are left out";
    EXPECT_GT(covering, 20000u / 10);

    // Between four pixel centres: out. On a centre: in. Off the viewport: out.
    EXPECT_FALSE(mayCoverPixelCentre({1.6f, 1.6f, 0}, {2.4f, 1.6f, 0}, {2.0f, 2.4f, 0}, view));
    EXPECT_TRUE(mayCoverPixelCentre({2.2f, 2.2f, 0}, {2.8f, 2.2f, 0}, {2.5f, 2.8f, 0}, view));
    EXPECT_FALSE(mayCoverPixelCentre({30.2f, 2.2f, 0}, {30.8f, 2.2f, 0}, {30.5f, 2.8f, 0}, view));
    // A centre just outside an edge (by less than the margin) keeps the triangle: the device
    // snaps and rounds on its own.
    EXPECT_TRUE(mayCoverPixelCentre({2.0f, 2.51f, 0}, {3.0f, 2.51f, 0}, {2.5f, 3.3f, 0}, view));
    // Two corners at one position: zero area in any projection.
    EXPECT_FALSE(mayCoverPixelCentre({2.2f, 2.2f, 0}, {2.2f, 2.2f, 0}, {12.5f, 9.8f, 0}, view));
    // Not finite, behind the eye or outside the depth range: the clipper decides, the triangle stays.
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_TRUE(mayCoverPixelCentre({nan, 1.6f, 0}, {2.4f, 1.6f, 0}, {2.0f, 2.4f, 0}, view));
    SampleView behind = view;
    behind.viewProjection[3][3] = -1.0f;  // w < 0
    EXPECT_TRUE(mayCoverPixelCentre({1.6f, 1.6f, 0}, {2.4f, 1.6f, 0}, {2.0f, 2.4f, 0}, behind));
}

// A counter-clockwise triangle in the plane z = 1000 (its normal +z, far from the origin so the
// edges are small beside the coordinates) faces away from eyes below it, perspective (w = 1) or
// orthographic (w = 0: the direction toward the viewer); seen edge-on, or nearly, it does not.
TEST(SampleCulling, TrianglesFaceAwayOnlyFromEyesBehindTheirPlane) {
    const glm::vec3 a{1000.0f, 1000.0f, 1000.0f}, b{1000.01f, 1000.0f, 1000.0f}, c{1000.0f, 1000.01f, 1000.0f};
    EXPECT_FALSE(facesAwayFrom(a, b, c, {1000.0f, 1000.0f, 1005.0f, 1.0f}));
    EXPECT_TRUE(facesAwayFrom(a, b, c, {1000.0f, 1000.0f, 995.0f, 1.0f}));
    EXPECT_TRUE(facesAwayFrom(a, c, b, {1000.0f, 1000.0f, 1005.0f, 1.0f})) << "the other winding";
    EXPECT_FALSE(facesAwayFrom(a, b, c, {0.0f, 0.0f, 1.0f, 0.0f}));
    EXPECT_TRUE(facesAwayFrom(a, b, c, {0.0f, 0.3f, -1.0f, 0.0f}));
    EXPECT_FALSE(facesAwayFrom(a, b, c, {1.0f, 0.0f, 0.0f, 0.0f})) << "edge-on";
    EXPECT_FALSE(facesAwayFrom(a, b, c, {1.0f, 0.0f, -0.5f * float(kFacingMargin), 0.0f})) << "within the margin";
    EXPECT_TRUE(facesAwayFrom(a, b, c, {1.0f, 0.0f, -2.0f * float(kFacingMargin), 0.0f}));
    EXPECT_FALSE(facesAwayFrom(a, a, c, {0.0f, 0.0f, -1.0f, 0.0f})) << "a degenerate triangle faces nowhere";
}

namespace {

struct SampleCullingFixture : test::PlanPassTest {
    static constexpr uint32_t kSize = 256;
    OffscreenTarget image;  // kSize square, what the tests draw into
    PlanDatabase db;

    void SetUp() override {
        PlanPassTest::SetUp();
        if (HasFatalFailure()) return;
        Result<OffscreenTarget> created = createOffscreenTarget(ctx, kSize, kSize, VK_FORMAT_R8G8B8A8_UNORM);
        ASSERT_TRUE(created.ok()) << created.error().message;
        image = *created;
    }
    void TearDown() override {
        if (ctx.device) destroyOffscreenTarget(ctx, image);
        PlanPassTest::TearDown();
    }

    // The generated 20k-face torus cage every test draws.
    Result<PlannedCage> planGenerated() { return PlannedCage::create(makeBenchmarkCage(20000, 3), db, {}, "generated"); }

    // Planned for the CPU grid path only (PlanBuffers::gridCulledIndices exists then).
    PlanBuffers uploadForCpu(const PlannedCage& planned) {
        Result<PlanBuffers> buffers = uploadPlans(ctx, planned, MacroChoice::Auto, true);
        EXPECT_TRUE(buffers.ok()) << buffers.error().message;
        EXPECT_TRUE(bindPlanBuffers(ctx, pass, *buffers).ok());
        return std::move(buffers).value();
    }

    // Single faces only (a coarse macro face's triangles are chosen again after a relayout,
    // which tests everything), small chunks, culled at any density.
    PlanBuffers uploadSingleFaces(const PlannedCage& planned) {
        Result<PlanBuffers> buffers = uploadPlans(ctx, planned, MacroChoice::Off, true);
        EXPECT_TRUE(buffers.ok()) << buffers.error().message;
        EXPECT_TRUE(bindPlanBuffers(ctx, pass, *buffers).ok());
        buffers->sampleCulling.chunkTriangles = 1024;
        buffers->sampleCulling.minTrianglesPerPixel = 0.0f;
        return std::move(buffers).value();
    }

    std::vector<uint8_t> draw(const OffscreenTarget& target, VkRect2D area, PlanBuffers& buffers, const PlannedCage& planned,
                              PlanView view, bool sampleCulling, bool expectCulled = true,
                              TessellationSettings settings = {0, 4.0f}) {
        view.sampleCulling = sampleCulling;
        EXPECT_TRUE(preparePlanFrame(ctx, pass, buffers, planned, DrawPath::CpuGrid, view, settings).ok());
        const Status drawn = submitAndWait(ctx, [&](VkCommandBuffer cmd) {
            recordPlanFrame(cmd, pass, buffers, DrawPath::CpuGrid, subArea(renderTarget(target), area), view, settings);
        });
        EXPECT_TRUE(drawn.ok()) << drawn.error().message;
        EXPECT_EQ(buffers.sampleCulling.inUse, sampleCulling && expectCulled);
        Result<std::vector<uint8_t>> rgba = readPixels(ctx, target);
        EXPECT_TRUE(rgba.ok());
        return rgba.ok() ? *rgba : std::vector<uint8_t>{};
    }
};

size_t differingBytes(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
    if (a.size() != b.size()) return std::max(a.size(), b.size());
    size_t count = 0;
    for (size_t i = 0; i < a.size(); ++i) count += a[i] != b[i];
    return count;
}

}  // namespace

TEST_F(SampleCullingFixture, CulledFramesEqualEveryTriangleDrawnPixelForPixel) {
    Result<PlannedCage> created = planGenerated();
    ASSERT_TRUE(created.ok()) << created.error().message;
    PlannedCage& planned = *created;
    PlanBuffers buffers = uploadForCpu(planned);
    buffers.sampleCulling.chunkTriangles = 1024;  // so that a move's chunks are a small part of the grid
    buffers.sampleCulling.minTrianglesPerPixel = 0.0f;  // culled at any density (the gate is tested below)

    const PlanView framed = test::framedPlanView(planned.cage(), kSize);
    const VkRect2D whole{{0, 0}, {kSize, kSize}};
    struct Case {
        std::string name;
        PlanView view;
        VkRect2D area;
    };
    std::vector<Case> cases;
    cases.push_back({"framed", framed, whole});
    // A viewport inside the image, off its origin and not square (the editor's split views).
    cases.push_back({"sub-viewport", framed, VkRect2D{{37, 21}, {150, 201}}});
    // Close up, the near plane through the model: triangles behind the eye and crossing it.
    const Bounds bounds = computeBounds(planned.cage());
    RenderCamera close = frameBounds(bounds.min, bounds.max, 1.0f);
    close.eye = close.target + 0.4f * (close.eye - close.target);  // the planes stay: the near one cuts the cage
    PlanView inside = framed;
    inside.viewProjection = viewProjection(close);
    inside.pixelsPerUnit = pixelsPerUnit(projectionMatrix(close), kSize);
    cases.push_back({"close up", inside, whole});
    // Hidden faces: the drawn ranges are gaps in the index buffer.
    PlanView hidden = framed;
    std::vector<uint32_t> hiddenDrawn;
    for (uint32_t d = 0; d < buffers.data.subfaces.size(); d += 3) hiddenDrawn.push_back(d);
    hidden.hiddenDrawn = hiddenDrawn;
    cases.push_back({"hidden faces", hidden, whole});

    for (const Case& c : cases) {
        const std::vector<uint8_t> all = draw(image, c.area, buffers, planned, c.view, false);
        const std::vector<uint8_t> culled = draw(image, c.area, buffers, planned, c.view, true);
        EXPECT_EQ(differingBytes(all, culled), 0u) << c.name;
        const uint64_t triangles = buffers.gridLayout.indices.size() / 3;
        EXPECT_LT(buffers.sampleCulling.keptTriangles, triangles) << c.name;
        if (c.name == "framed") {
            EXPECT_LT(buffers.sampleCulling.keptTriangles, 3 * triangles / 4) << "many of a far cage's triangles cover no centre";
            ASSERT_TRUE(writePng((test::testOutputDir() / "sample_culling_framed.png").string(), kSize, kSize, culled).ok());
        }
    }

    // Vertex moves: only the chunks that read a moved slot are tested again, and the picture is
    // still the one with every triangle drawn.
    draw(image, whole, buffers, planned, framed, true);
    std::mt19937 random(11);
    std::uniform_int_distribution<uint32_t> pick(0, planned.cage().vertexCount() - 1);
    for (int round = 0; round < 4; ++round) {
        std::vector<uint32_t> moved = {pick(random), pick(random)};
        std::vector<glm::vec3> to;
        for (uint32_t v : moved) to.push_back(planned.cage().positions[v] + 0.002f * bounds.diagonal() * glm::vec3(0.3f, 1.0f, -0.5f));
        ASSERT_TRUE(planned.moveVertices(moved, to).ok());
        ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) { recordMovedVertices(cmd, pass, buffers, planned, moved); }).ok());
        const std::vector<uint8_t> culled = draw(image, whole, buffers, planned, framed, true);
        EXPECT_LT(buffers.sampleCulling.testedTriangles, buffers.gridLayout.indices.size() / 3 / 4)
            << "round " << round << ": a move tests the chunks around it, not the whole grid";
        const std::vector<uint8_t> all = draw(image, whole, buffers, planned, framed, false);
        EXPECT_EQ(differingBytes(all, culled), 0u) << "after move " << round;
    }

    // Faces hidden and shown again (a hole made and undone): the chunks whose drawn triangles
    // changed are written again from the results kept for every triangle, none is tested, and
    // the picture is still the one with every drawn triangle drawn. Faces drawn alone: hiding a
    // member of a coarse macro face breaks it up (a new layout, everything tested again).
    const uint32_t drawnCount = uint32_t(buffers.data.subfaces.size());
    const GridFactors& factors = buffers.gridLayout.factors;
    auto drawnAlone = [&](uint32_t d) {
        const uint32_t m = buffers.data.macros.macroOfDrawn.empty() ? UINT32_MAX : buffers.data.macros.macroOfDrawn[d];
        return m == UINT32_MAX || factors.macroResolution.empty() || factors.macroResolution[2 * m] == 0;
    };
    std::vector<uint32_t> holes;  // one in each quarter of the drawn sub-faces
    for (uint32_t quarter = 0; quarter < 4; ++quarter)
        for (uint32_t d = quarter * drawnCount / 4 + drawnCount / 8; d < (quarter + 1) * drawnCount / 4; ++d)
            if (drawnAlone(d)) {
                holes.push_back(d);
                break;
            }
    ASSERT_EQ(holes.size(), 4u);
    const size_t layoutTriangles = buffers.gridLayout.indices.size() / 3;
    PlanView holed = framed;
    holed.hiddenDrawn = holes;
    for (const PlanView& v : {holed, framed}) {
        const std::vector<uint8_t> culled = draw(image, whole, buffers, planned, v, true);
        const uint64_t tested = buffers.sampleCulling.testedTriangles;
        ASSERT_EQ(buffers.gridLayout.indices.size() / 3, layoutTriangles) << "the same layout";
        EXPECT_EQ(tested, 0u) << (v.hiddenDrawn.empty() ? "showing" : "hiding") << " four faces tests no triangle again";
        const std::vector<uint8_t> all = draw(image, whole, buffers, planned, v, false);
        EXPECT_EQ(differingBytes(all, culled), 0u) << (v.hiddenDrawn.empty() ? "shown again" : "hidden");
    }
    EXPECT_NE(differingBytes(draw(image, whole, buffers, planned, holed, true), draw(image, whole, buffers, planned, framed, true)),
              0u)
        << "the hidden faces are visible in the framed view";

    // With fewer triangles than pixels the renderer does not test them (kMinTrianglesPerPixel).
    buffers.sampleCulling.minTrianglesPerPixel = kMinTrianglesPerPixel;
    const uint32_t large = 512;
    Result<OffscreenTarget> largeImage = createOffscreenTarget(ctx, large, large, VK_FORMAT_R8G8B8A8_UNORM);
    ASSERT_TRUE(largeImage.ok()) << largeImage.error().message;
    draw(*largeImage, VkRect2D{{0, 0}, {large, large}}, buffers, planned, framed, true, false);
    EXPECT_LT(buffers.gridLayout.indices.size() / 3, size_t(large) * large);
    destroyOffscreenTarget(ctx, *largeImage);
    destroyPlanBuffers(ctx, buffers);
}

// Topology edits lay the grid out anew (grid_relayout.h carryGrid): the kept sub-faces' results
// follow their triangles, only the new and re-evaluated ones are tested, and the picture stays
// the one with every triangle drawn.
TEST_F(SampleCullingFixture, TopologyEditsCarryTheResultsOfKeptFaces) {
    Result<PlannedCage> created = planGenerated();
    ASSERT_TRUE(created.ok()) << created.error().message;
    PlannedCage& planned = *created;
    PlanBuffers buffers = uploadSingleFaces(planned);
    const PlanView framed = test::framedPlanView(planned.cage(), kSize);
    const VkRect2D whole{{0, 0}, {kSize, kSize}};
    // Uniform factors: the next frame's factors are known, and the grid is carried (adaptive
    // factors choose new sub-faces' segments by the view: the grid is laid out whole).
    const TessellationSettings uniform{2, 4.0f};
    draw(image, whole, buffers, planned, framed, true, true, uniform);

    EditHistory history;
    auto extrude = [&](uint32_t face) -> Result<EditReport> {
        Result<TopologyEdit> edit = extrudeFaces(planned.cage(), planned.topology(), std::vector<uint32_t>{face}, 0.05f);
        if (!edit) return edit.error();
        return history.applyTopologyEdit(planned, "extrude", std::move(edit).value());
    };
    auto remove = [&](uint32_t face) -> Result<EditReport> {
        Result<TopologyEdit> edit = deleteFaces(planned.cage(), planned.topology(), std::vector<uint32_t>{face}, true);
        if (!edit) return edit.error();
        return history.applyTopologyEdit(planned, "delete", std::move(edit).value());
    };
    const uint32_t faces = planned.cage().faceCount();
    const std::vector<std::pair<std::string, std::function<Result<EditReport>()>>> edits = {
        {"extrude a face", [&] { return extrude(faces / 3); }},
        {"extrude another", [&] { return extrude(2 * faces / 3); }},
        {"undo", [&] { return history.undo(planned); }},
        {"delete a face and its vertices", [&] { return remove(faces / 2); }},
        {"undo the delete", [&] { return history.undo(planned); }},
        {"redo the delete", [&] { return history.redo(planned); }},
    };
    for (const auto& [label, edit] : edits) {
        Result<EditReport> report = edit();
        ASSERT_TRUE(report.ok()) << label << ": " << report.error().message;
        std::vector<uint32_t> subfaces = report->updatedSubfaceList;
        for (uint32_t f : report->replannedFaceList)
            for (uint32_t s = planned.firstSubface(f); s < planned.firstSubface(f + 1); ++s) subfaces.push_back(s);
        Result<PlanTableUpdate> updated = updatePlanTables(ctx, pass, buffers, planned, subfaces, report->previousSubfaceOf);
        ASSERT_TRUE(updated.ok()) << label << ": " << updated.error().message;
        ASSERT_TRUE(updated->applied) << label << ": " << updated->reason;
        ASSERT_FALSE(updated->gridDropped) << label;
        ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) {
                        recordSubfaceRefresh(cmd, pass, buffers, planned, updated->refresh);
                    }).ok());
        const std::vector<uint8_t> culled = draw(image, whole, buffers, planned, framed, true, true, uniform);
        const uint64_t triangles = buffers.gridLayout.indices.size() / 3;
        EXPECT_GT(buffers.sampleCulling.testedTriangles, 0u) << label << ": the new triangles are tested";
        EXPECT_LT(buffers.sampleCulling.testedTriangles, triangles / 4) << label << ": the kept faces' results are carried";
        EXPECT_LT(buffers.sampleCulling.keptTriangles, triangles) << label;
        const std::vector<uint8_t> all = draw(image, whole, buffers, planned, framed, false, true, uniform);
        EXPECT_EQ(differingBytes(all, culled), 0u) << label;
    }
    destroyPlanBuffers(ctx, buffers);
}

// Screen-adaptive factors: a vertex pulled toward the camera raises its sub-faces' factors, and
// the grid is laid out again keeping the others (relayoutGridKeepingSlots): their results are
// carried, the re-evaluated sub-faces tested, and the picture stays the one with every triangle
// drawn. A second vertex, elsewhere, moves a few pixels across the view in the same frame: its
// sub-faces keep their factors, and their slots, written before the relayout, are tested again.
TEST_F(SampleCullingFixture, AdaptiveRelayoutsCarryTheResultsOfKeptFaces) {
    Result<PlannedCage> created = planGenerated();
    ASSERT_TRUE(created.ok()) << created.error().message;
    PlannedCage& planned = *created;
    PlanBuffers buffers = uploadSingleFaces(planned);
    const PlanView framed = test::framedPlanView(planned.cage(), kSize);
    const VkRect2D whole{{0, 0}, {kSize, kSize}};
    draw(image, whole, buffers, planned, framed, true);

    const Bounds bounds = computeBounds(planned.cage());
    const glm::vec3 eye = glm::vec3(glm::inverse(framed.viewProjection) * glm::vec4(0.0f, 0.0f, 0.0f, 1.0f) /
                                    (glm::inverse(framed.viewProjection) * glm::vec4(0.0f, 0.0f, 0.0f, 1.0f)).w);
    uint32_t relayouts = 0;
    const uint32_t vertices = planned.cage().vertexCount();
    const glm::vec3 across = glm::normalize(glm::vec3(glm::inverse(framed.viewProjection) * glm::vec4(1.0f, 0.0f, 0.0f, 0.0f)));
    for (uint32_t v : {vertices / 3, vertices / 2, 2 * vertices / 3}) {
        const GridFactors before = buffers.gridLayout.factors;
        // Facing the camera (a vertex on the far side could hide what a stale result leaves out):
        // the one nearest the eye among the sixth of the vertices after v.
        uint32_t aside = (v + vertices / 6) % vertices;
        for (uint32_t k = 1; k < vertices / 6; ++k) {
            const uint32_t w = (v + vertices / 6 + k) % vertices;
            if (glm::length(planned.cage().positions[w] - eye) < glm::length(planned.cage().positions[aside] - eye)) aside = w;
        }
        const glm::vec3 from = planned.cage().positions[v];
        const std::vector<glm::vec3> to = {from + 0.08f * bounds.diagonal() * glm::normalize(eye - from),
                                           planned.cage().positions[aside] + 0.01f * bounds.diagonal() * across};
        const std::vector<uint32_t> moved{v, aside};
        ASSERT_TRUE(planned.moveVertices(moved, to).ok());
        ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) { recordMovedVertices(cmd, pass, buffers, planned, moved); }).ok());
        const std::vector<uint8_t> culled = draw(image, whole, buffers, planned, framed, true);
        const uint64_t triangles = buffers.gridLayout.indices.size() / 3;
        if (buffers.gridLayout.factors.subfaceFactor != before.subfaceFactor) {
            ++relayouts;
            EXPECT_LT(buffers.sampleCulling.testedTriangles, triangles / 4) << "vertex " << v << ": the kept faces' results are carried";
        }
        const std::vector<uint8_t> all = draw(image, whole, buffers, planned, framed, false);
        EXPECT_EQ(differingBytes(all, culled), 0u) << "vertex " << v;
    }
    EXPECT_GT(relayouts, 0u) << "a vertex pulled toward the camera raises some factors";
    destroyPlanBuffers(ctx, buffers);
}
