// Culling (DrawView::cull, docs/culling.md): for every scheme that culls, on every path and from
// views around and inside the model, a culled frame draws exactly the pixels of the unculled one
// while drawing fewer patches; on an open cage, or one turned inside out, the back-patch tests
// stay off.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include <glm/gtc/matrix_transform.hpp>

#include "camera.h"
#include "displacement/displacement.h"
#include "id_pass.h"
#include "offscreen_target.h"
#include "plan_pass.h"
#include "plans/planned_cage.h"
#include "render_test_support.h"
#include "scheme_host.h"
#include "scheme_test_support.h"
#include "test_cages.h"
#include "vk_commands.h"

using namespace qp;

namespace {

const PluginCatalog& catalog() {
    static const PluginCatalog plugins = loadPlugins(QUADPLAN_PLUGIN_DIR);
    return plugins;
}

struct Frame {
    std::vector<uint8_t> pixels;
    uint64_t patches = 0;  // what the scheme drew: its patches, or its triangles when it draws no patches (uniform)
    CullCounts cull;
    std::vector<uint32_t> culledSubfaces;  // DrawView::culledSubfacesOut
    uint64_t triangles = 0, facingAway = 0;  // DrawStats::triangles, facingAwayTriangles
};

// A scheme with its options (e.g. plans with path=grid).
struct Variant {
    std::string scheme;
    std::vector<std::pair<std::string, std::string>> options;
    // On a closed cage the back-patch tests cull (on a coarse cage a scheme may cull nothing facing
    // away: only what lies a patch away from everything drawn goes, scheme_culling.h).
    bool backCulls = true;
    std::string name() const {
        std::string out = scheme;
        for (const auto& [key, value] : options) out += " " + key + "=" + value;
        return out;
    }
};

// Frames of `variant` through `cameras`, culled by `cull`, recorded into one command buffer by
// one instance: the cameras after the first as later objects of the same frame
// (DrawView::sameFrame), each into its own target.
std::vector<Frame> drawFrames(const VulkanContext& ctx, const PlannedCage& planned, const Variant& variant, CullMethod cull,
                              std::span<const RenderCamera> cameras, const Displacement* displacement = nullptr,
                              std::span<const uint32_t> hidden = {}, const glm::mat4& worldFromObject = glm::mat4(1.0f)) {
    constexpr uint32_t kSize = 160;
    std::vector<Frame> frames(cameras.size());
    std::vector<OffscreenTarget> targets;
    for (size_t k = 0; k < cameras.size(); ++k) {
        Result<OffscreenTarget> target = createOffscreenTarget(ctx, kSize, kSize, VK_FORMAT_R8G8B8A8_UNORM);
        EXPECT_TRUE(target.ok());
        if (target) targets.push_back(*target);
    }
    SchemeSettings settings;
    settings.tessFactor = 8;
    settings.options = variant.options;
    const GpuContext gpu{&ctx, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_D32_SFLOAT};
    Result<PreparedScheme> prepared = prepareScheme(catalog(), variant.scheme, planned, analyzeCage(planned.cage(), planned.topology()),
                                                    settings, gpu, "test cage", displacement);
    EXPECT_TRUE(prepared.ok()) << (prepared ? "" : prepared.error().message);
    if (prepared && targets.size() == cameras.size()) {
        EXPECT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) {
                        for (size_t k = 0; k < cameras.size(); ++k) {
                            DrawView view;
                            // Placed by worldFromObject, as a scene's object is (scheme_host.h objectView).
                            view.viewProjection = viewProjection(cameras[k]) * worldFromObject;
                            view.eye = glm::vec3(glm::inverse(worldFromObject) * glm::vec4(cameras[k].eye, 1.0f));
                            view.worldFromObject = glm::mat3(worldFromObject);
                            view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(cameras[k]), kSize);
                            view.cull = cull;
                            view.sameFrame = k > 0;
                            view.culledSubfacesOut = &frames[k].culledSubfaces;
                            view.hiddenSubfaces = hidden;
                            Result<DrawStats> drawn = prepared->instance.record(cmd, renderTarget(targets[k]), view);
                            if (drawn) {
                                frames[k].patches = drawn->patches ? drawn->patches : drawn->triangles;
                                frames[k].cull = drawn->cull;
                                frames[k].triangles = drawn->triangles;
                                frames[k].facingAway = drawn->facingAwayTriangles;
                            }
                        }
                    }).ok());
        for (size_t k = 0; k < cameras.size(); ++k) {
            Result<std::vector<uint8_t>> pixels = readPixels(ctx, targets[k]);
            if (pixels) frames[k].pixels = std::move(*pixels);
        }
        EXPECT_TRUE(prepared->instance.destroyGpu().ok());
    }
    for (OffscreenTarget& target : targets) destroyOffscreenTarget(ctx, target);
    return frames;
}

// Pixels (RGB) that differ between two frames' pictures (all of them when the sizes differ).
size_t differingPixels(const Frame& a, const Frame& b) {
    if (a.pixels.size() != b.pixels.size()) return std::max(a.pixels.size(), b.pixels.size()) / 4;
    size_t differing = 0;
    for (size_t i = 0; i < a.pixels.size(); i += 4)
        differing += !std::equal(a.pixels.begin() + i, a.pixels.begin() + i + 3, b.pixels.begin() + i);
    return differing;
}

// One frame of `variant` through `camera`, culled by `cull`.
Frame drawFrame(const VulkanContext& ctx, const PlannedCage& planned, const Variant& variant, CullMethod cull,
                const RenderCamera& camera, const Displacement* displacement = nullptr, std::span<const uint32_t> hidden = {},
                const glm::mat4& worldFromObject = glm::mat4(1.0f)) {
    return drawFrames(ctx, planned, variant, cull, std::span<const RenderCamera>(&camera, 1), displacement, hidden,
                      worldFromObject)[0];
}

// Views: framing the model from six directions, one close up (part of the model off screen and
// the near plane through it: its back side shows through the cut), one orthographic.
std::vector<RenderCamera> views(const Cage& cage) {
    const Bounds bounds = computeBounds(cage);
    std::vector<RenderCamera> out;
    const glm::vec3 directions[] = {{1, 0.4f, 0.8f}, {-1, -0.5f, 0.6f}, {0.1f, 1, -0.2f}, {0.3f, -1, -0.9f}, {-0.7f, 0.2f, -1}, {0, 0.05f, 1}};
    for (const glm::vec3& d : directions) {
        RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
        camera.eye = camera.target + glm::length(camera.eye - camera.target) * glm::normalize(d);
        out.push_back(camera);
    }
    RenderCamera close = out[0];
    close.eye = close.target + 0.35f * (close.eye - close.target);
    close.target += 0.2f * (bounds.max - bounds.min);
    out.push_back(close);
    RenderCamera ortho = out[1];
    ortho.orthographic = true;
    ortho.orthoHeight = 0.8f * glm::length(bounds.max - bounds.min);
    out.push_back(ortho);
    return out;
}

// `closed`: the cage is closed and outward (back-patch tests apply), else only the frustum culls.
// Per variant: every culled frame equals the unculled one; what is drawn never grows, shrinks
// from tcone to ncone to pplane, and on a closed cage pplane draws less than 90%. Plans' CPU grid
// also leaves out facing-away triangles there (sample_culling.h): with pplane it draws less than
// two thirds of the triangles, and none is left out as facing away elsewhere.
// `displacement` > 0: drawn with random displacement of that amplitude (times the cage's
// diagonal; then only the frustum culls, with boxes grown by each tile's largest |D|).
void expectSamePixelsFewerPatches(const Cage& cage, const std::string& name, bool closed, const std::vector<Variant>& variants,
                                  float displacement = 0.0f) {
    Result<VulkanContext> context = test::createTestContext();
    ASSERT_TRUE(context.ok()) << context.error().message;
    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(cage, database, PlanOptions{}, name);
    ASSERT_TRUE(planned.ok());
    Displacement displaced = makeDisplacement(planned->cage(), planned->topology(), 4);
    std::mt19937 rng(29);
    const Bounds bounds = computeBounds(cage);
    std::uniform_real_distribution<float> value(-displacement, displacement);
    for (float& sample : displaced.samples) sample = value(rng) * glm::length(bounds.max - bounds.min);
    const Displacement* d = displacement > 0.0f ? &displaced : nullptr;
    const std::vector<RenderCamera> cameras = views(cage);
    for (const Variant& variant : variants) {
        uint64_t drawn[5] = {};
        uint64_t trianglesPlain = 0, trianglesPPlane = 0, facingAway = 0;
        for (size_t v = 0; v < cameras.size(); ++v) {
            const RenderCamera& camera = cameras[v];
            const Frame plain = drawFrame(*context, *planned, variant, CullMethod::None, camera, d);
            EXPECT_EQ(plain.cull.tested, 0u) << variant.name();
            EXPECT_TRUE(plain.culledSubfaces.empty()) << variant.name();
            drawn[0] += plain.patches;
            trianglesPlain += plain.triangles;
            EXPECT_EQ(plain.facingAway, 0u) << variant.name();
            int k = 1;
            for (CullMethod method : {CullMethod::Frustum, CullMethod::TCone, CullMethod::NCone, CullMethod::PPlane}) {
                const Frame culled = drawFrame(*context, *planned, variant, method, camera, d);
                ASSERT_EQ(culled.pixels, plain.pixels) << name << ", " << variant.name() << ", view " << v << ", "
                                                       << cullMethodName(method) << ": a culled frame differs in "
                                                       << differingPixels(plain, culled) << " pixels";
                EXPECT_LE(culled.patches, plain.patches);
                EXPECT_GT(culled.cull.tested, 0u) << variant.name();
                EXPECT_LE(culled.cull.frustum + culled.cull.backFacing, culled.cull.tested) << variant.name();
                EXPECT_TRUE(std::is_sorted(culled.culledSubfaces.begin(), culled.culledSubfaces.end())) << variant.name();
                EXPECT_TRUE(culled.culledSubfaces.empty() || culled.culledSubfaces.back() < planned->subfaceCount());
                drawn[k++] += culled.patches;
                facingAway += culled.facingAway;
                if (method == CullMethod::PPlane) trianglesPPlane += culled.triangles - culled.facingAway;
            }
        }
        EXPECT_LE(drawn[1], drawn[0]) << variant.name();
        EXPECT_LE(drawn[2], drawn[1]) << variant.name();
        EXPECT_LE(drawn[3], drawn[2]) << variant.name();
        EXPECT_LE(drawn[4], drawn[3]) << variant.name();
        if (d) {
            EXPECT_LT(drawn[1], drawn[0]) << name << ", " << variant.name() << ": the frustum culls the close-up's hidden part";
        }
        const bool cpuPlans = variant.scheme == "plans" && variant.name().find("path=cpu") != std::string::npos;
        if (closed && cpuPlans && !d) {
            EXPECT_LT(trianglesPPlane, trianglesPlain * 2 / 3) << name << ": facing-away triangles are left out";
        } else {
            EXPECT_EQ(facingAway, 0u) << name << ", " << variant.name() << ": no triangle is left out as facing away";
        }
        if (closed && variant.backCulls) {
            EXPECT_LT(drawn[4], drawn[0] * 9 / 10) << name << ", " << variant.name() << ": pplane culls";
        } else if (!closed) {
            EXPECT_EQ(drawn[4], drawn[1]) << name << ", " << variant.name()
                                          << ": back sides show on an open, inside-out or displaced cage; only the frustum culls";
        }
        ::testing::Test::RecordProperty(name + " " + variant.name(),
                                        std::to_string(drawn[0]) + " " + std::to_string(drawn[1]) + " " + std::to_string(drawn[2]) +
                                            " " + std::to_string(drawn[3]) + " " + std::to_string(drawn[4]) + " drawn over " +
                                            std::to_string(cameras.size()) + " frames (none, frustum, tcone, ncone, pplane)");
    }
    EXPECT_EQ(test::describeMessages(*context), "");
    destroyContext(*context);
}

const std::vector<Variant> kPlanPaths = {{"plans", {{"path", "cpu"}}}, {"plans", {{"path", "grid"}}}, {"plans", {{"path", "tess"}}}};
// The other schemes that cull: per patch through the tessellator, per sub-face on the CPU grid
// (osd-fas: per patch on its CPU mesh), uniform per face.
const std::vector<Variant> kPatchSchemes = {
    {"acc1", {{"path", "tess"}}}, {"acc1", {{"path", "cpu"}}}, {"acc2", {{"path", "tess"}}}, {"acc2", {{"path", "cpu"}}},
    {"pn", {{"path", "tess"}}},   {"pn", {{"path", "cpu"}}},   {"osd-fas", {{"path", "tess"}}}, {"osd-fas", {{"path", "cpu"}}},
    {"uniform", {}}};
// The same on the 3 x 3 subdivided cube, where acc2 and pn find nothing a patch away from the outline.
const std::vector<Variant> kPatchSchemesOnTheCube = {
    {"acc1", {{"path", "tess"}}},      {"acc1", {{"path", "cpu"}}},      {"acc2", {{"path", "tess"}}, false},
    {"acc2", {{"path", "cpu"}}, false}, {"pn", {{"path", "tess"}}, false}, {"pn", {{"path", "cpu"}}, false},
    {"osd-fas", {{"path", "tess"}}},   {"osd-fas", {{"path", "cpu"}}},   {"uniform", {}}};
// A torus fine enough that some of its back lies a patch away from every outline.
Cage fineTorus() { return test::makeTorus(36, 18); }

// The torus with every face's winding reversed: closed, but its normals point inward.
Cage insideOutTorus() {
    Cage cage = test::makeTorus(24, 12);
    for (uint32_t f = 0; f < cage.faceCount(); ++f)
        std::reverse(cage.faceVertices.begin() + cage.faceOffsets[f], cage.faceVertices.begin() + cage.faceOffsets[f + 1]);
    return cage;
}

}  // namespace

TEST(PlanCulling, ClosedTorusDrawsTheSamePixelsWithFewerSubfaces) {
    expectSamePixelsFewerPatches(test::makeTorus(24, 12), "torus", true, kPlanPaths);
}

TEST(PlanCulling, ClosedCubeWithExtraordinaryVerticesDrawsTheSamePixels) {
    expectSamePixelsFewerPatches(test::makeSubdividedCube(3), "subdivided cube", true, kPlanPaths);
}

TEST(PlanCulling, OpenGridCullsOnlyByTheFrustum) {
    expectSamePixelsFewerPatches(test::makeGrid(4), "grid", false, kPlanPaths);
}

TEST(PlanCulling, InsideOutTorusCullsOnlyByTheFrustum) {
    expectSamePixelsFewerPatches(insideOutTorus(), "inside-out torus", false, kPlanPaths);
}

// Faces the editor hides open the surface: the back side shows through them, so nothing is culled
// as facing away (patches or triangles) while any is hidden, and the pictures stay the unculled ones.
TEST(PlanCulling, HiddenFacesShowTheBackSideBehindThem) {
    Result<VulkanContext> context = test::createTestContext();
    ASSERT_TRUE(context.ok()) << context.error().message;
    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(fineTorus(), database, PlanOptions{}, "torus");
    ASSERT_TRUE(planned.ok());
    // Two bands around the tube (sub-faces are faces here, 36 to a ring): the views look into them.
    std::vector<uint32_t> hidden;
    for (uint32_t s = 0; s < planned->subfaceCount(); ++s)
        if (s % 18 < 6) hidden.push_back(s);
    const std::vector<RenderCamera> cameras = views(planned->cage());
    for (const Variant& variant : kPlanPaths)
        for (size_t v = 0; v < cameras.size(); ++v) {
            const Frame plain = drawFrame(*context, *planned, variant, CullMethod::None, cameras[v], nullptr, hidden);
            const Frame culled = drawFrame(*context, *planned, variant, CullMethod::PPlane, cameras[v], nullptr, hidden);
            EXPECT_TRUE(culled.pixels == plain.pixels)
                << variant.name() << ", view " << v << ": " << differingPixels(plain, culled) << " pixels differ";
            EXPECT_EQ(culled.cull.backFacing, 0u) << variant.name() << ", view " << v;
            EXPECT_EQ(culled.facingAway, 0u) << variant.name() << ", view " << v;
        }
    EXPECT_EQ(test::describeMessages(*context), "");
    destroyContext(*context);
}

// An object mirrored and stretched by its transform (a scene's object): the facing is judged in
// the cage's own coordinates, where a mirror leaves sides as they are, so its facing-away
// triangles still go and nothing visible with them.
TEST(PlanCulling, MirroredAndStretchedObjectsLeaveOutTheirFacingAwayTriangles) {
    Result<VulkanContext> context = test::createTestContext();
    ASSERT_TRUE(context.ok()) << context.error().message;
    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(fineTorus(), database, PlanOptions{}, "torus");
    ASSERT_TRUE(planned.ok());
    const glm::mat4 mirrored = glm::scale(glm::rotate(glm::mat4(1.0f), 0.4f, glm::vec3(1, 0, 0)), glm::vec3(1.3f, -1.0f, 0.6f));
    // The cameras frame the placed torus (its cage's corners through the transform).
    Cage placed = planned->cage();
    for (glm::vec3& p : placed.positions) p = glm::vec3(mirrored * glm::vec4(p, 1.0f));
    const std::vector<RenderCamera> cameras = views(placed);
    uint64_t facingAway = 0;
    for (size_t v = 0; v < cameras.size(); ++v) {
        const Variant cpu{"plans", {{"path", "cpu"}}};
        const Frame plain = drawFrame(*context, *planned, cpu, CullMethod::None, cameras[v], nullptr, {}, mirrored);
        const Frame culled = drawFrame(*context, *planned, cpu, CullMethod::PPlane, cameras[v], nullptr, {}, mirrored);
        EXPECT_TRUE(!plain.pixels.empty() && culled.pixels == plain.pixels)
            << "view " << v << ": " << differingPixels(plain, culled) << " pixels differ";
        facingAway += culled.facingAway;
        if (v < 6) {
            EXPECT_GT(culled.facingAway, culled.triangles / 4) << "view " << v << " frames the whole torus";
        }
    }
    EXPECT_GT(facingAway, 0u);
    EXPECT_EQ(test::describeMessages(*context), "");
    destroyContext(*context);
}

TEST(SchemeCulling, ClosedTorusDrawsTheSamePixelsWithFewerPatches) {
    expectSamePixelsFewerPatches(fineTorus(), "torus 36 x 18", true, kPatchSchemes);
}

TEST(SchemeCulling, ClosedCubeWithExtraordinaryVerticesDrawsTheSamePixels) {
    expectSamePixelsFewerPatches(test::makeSubdividedCube(3), "subdivided cube", true, kPatchSchemesOnTheCube);
}

TEST(SchemeCulling, OpenGridCullsOnlyByTheFrustum) {
    expectSamePixelsFewerPatches(test::makeGrid(4), "grid", false, kPatchSchemes);
}

// Displaced (every path draws a displaced mesh): only the frustum culls, each box grown by its
// tile's largest |D|, and the pictures stay the unculled ones.
TEST(SchemeCulling, DisplacedSurfacesCullOnlyByTheFrustum) {
    expectSamePixelsFewerPatches(test::makeTorus(), "displaced torus", false,
                                 {{"acc1", {{"path", "tess"}}}, {"pn", {{"path", "cpu"}}}, {"osd-fas", {{"path", "tess"}}},
                                  {"uniform", {}}},
                                 0.02f);
}

// stam does not cull: asked to, it draws everything and reports no culling.
TEST(SchemeCulling, StamDrawsEverythingAndReportsNoCulling) {
    Result<VulkanContext> context = test::createTestContext();
    ASSERT_TRUE(context.ok()) << context.error().message;
    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(test::makeTorus(), database, PlanOptions{}, "torus");
    ASSERT_TRUE(planned.ok());
    const RenderCamera camera = views(planned->cage())[0];
    const Frame plain = drawFrame(*context, *planned, {"stam", {}}, CullMethod::None, camera);
    const Frame asked = drawFrame(*context, *planned, {"stam", {}}, CullMethod::PPlane, camera);
    EXPECT_EQ(asked.pixels, plain.pixels);
    EXPECT_EQ(asked.patches, plain.patches);
    EXPECT_EQ(asked.cull.tested, 0u);
    EXPECT_EQ(asked.cull.frustum + asked.cull.backFacing + asked.cull.frustumOnly, 0u);
    EXPECT_EQ(test::describeMessages(*context), "");
    destroyContext(*context);
}

// Later objects of a frame that share an instance (DrawView::sameFrame) each draw their own
// culled patches: the tessellated paths write each draw's patch list in the command buffer, so a
// later draw's list does not replace an earlier one's before it ran. Two views in one command
// buffer equal each view drawn alone without culling.
TEST(SchemeCulling, ObjectsOfOneFrameEachDrawTheirOwnCulledPatches) {
    Result<VulkanContext> context = test::createTestContext();
    ASSERT_TRUE(context.ok()) << context.error().message;
    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(fineTorus(), database, PlanOptions{}, "torus");
    ASSERT_TRUE(planned.ok());
    const std::vector<RenderCamera> all = views(planned->cage());
    const RenderCamera cameras[2] = {all[0], all[3]};  // opposite sides: different patches culled
    for (const Variant& variant : std::vector<Variant>{{"acc2", {{"path", "tess"}}}, {"osd-fas", {{"path", "tess"}}}}) {
        const std::vector<Frame> culled = drawFrames(*context, *planned, variant, CullMethod::PPlane, cameras);
        for (size_t k = 0; k < 2; ++k) {
            const Frame plain = drawFrame(*context, *planned, variant, CullMethod::None, cameras[k]);
            EXPECT_EQ(culled[k].pixels, plain.pixels) << variant.name() << ", object " << k;
            EXPECT_LT(culled[k].patches, plain.patches) << variant.name() << ", object " << k;
        }
        EXPECT_NE(culled[0].culledSubfaces, culled[1].culledSubfaces) << variant.name();
    }
    EXPECT_EQ(test::describeMessages(*context), "");
    destroyContext(*context);
}

// osd-fas culls Far patches, which next to an extraordinary vertex are smaller than a sub-face,
// so `cull-stats` checks them against an ID buffer of the triangles it draws per patch
// (Scheme::drawnPatches). On the CPU path those are the drawn triangles themselves: their ID
// buffer covers exactly the pixels the unculled frame covers, and no patch that owns a pixel of it
// is culled, while more patches are culled than make up whole sub-faces. On the tess path the
// same patches are laid out on the host (one triangle list a patch, every patch numbered).
TEST(SchemeCulling, OsdFasGivesTheTrianglesItDrawsPerPatch) {
    Result<VulkanContext> context = test::createTestContext();
    ASSERT_TRUE(context.ok()) << context.error().message;
    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(test::makeSubdividedCube(3), database, PlanOptions{}, "subdivided cube");
    ASSERT_TRUE(planned.ok());
    constexpr uint32_t kSize = 160;
    Result<IdPass> idPass = createIdPass(*context, VK_NULL_HANDLE);
    ASSERT_TRUE(idPass.ok()) << idPass.error().message;
    for (const char* path : {"cpu", "tess"}) {
        SchemeSettings settings;
        settings.tessFactor = 8;
        settings.options = {{"path", path}};
        const GpuContext gpu{&*context, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_D32_SFLOAT};
        Result<PreparedScheme> prepared = prepareScheme(catalog(), "osd-fas", *planned,
                                                        analyzeCage(planned->cage(), planned->topology()), settings, gpu, "cube");
        ASSERT_TRUE(prepared.ok()) << prepared.error().message;
        Result<PatchTriangles> patches = prepared->instance.drawnPatches();
        ASSERT_TRUE(patches.ok()) << patches.error().message;
        Result<SchemeStats> stats = prepared->instance.stats();
        ASSERT_TRUE(stats.ok());
        EXPECT_EQ(patches->patchCount, stats->patches) << path;
        EXPECT_GT(patches->patchCount, planned->subfaceCount()) << path << ": Far patches halve toward each corner";
        ASSERT_EQ(patches->patchOfVertex.size(), patches->positions.size());
        ASSERT_FALSE(patches->indices.empty());
        for (size_t i = 0; i < patches->indices.size(); i += 3) {
            const uint32_t a = patches->indices[i], b = patches->indices[i + 1], c = patches->indices[i + 2];
            ASSERT_TRUE(a < patches->positions.size() && b < patches->positions.size() && c < patches->positions.size());
            EXPECT_TRUE(patches->patchOfVertex[a] == patches->patchOfVertex[b] && patches->patchOfVertex[a] == patches->patchOfVertex[c])
                << path << ": triangle " << i / 3 << " joins two patches";
        }
        std::vector<IdVertex> vertices(patches->positions.size());
        for (size_t i = 0; i < vertices.size(); ++i) vertices[i] = {patches->positions[i], patches->patchOfVertex[i]};
        Result<IdMesh> mesh = uploadIdMesh(*context, vertices, patches->indices);
        ASSERT_TRUE(mesh.ok()) << mesh.error().message;
        Result<OffscreenTarget> target = createOffscreenTarget(*context, kSize, kSize, VK_FORMAT_R8G8B8A8_UNORM);
        ASSERT_TRUE(target.ok());
        uint64_t culledPatches = 0, culledWholeSubfaces = 0;
        for (const RenderCamera& camera : views(planned->cage())) {
            DrawView view;
            view.viewProjection = viewProjection(camera);
            view.eye = camera.eye;
            view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(camera), kSize);
            auto draw = [&](CullMethod cull, std::vector<uint32_t>* culled, std::vector<uint32_t>* culledSubfaces) {
                view.cull = cull;
                view.culledPatchesOut = culled;
                view.culledSubfacesOut = culledSubfaces;
                EXPECT_TRUE(submitAndWait(*context, [&](VkCommandBuffer cmd) {
                                EXPECT_TRUE(prepared->instance.record(cmd, renderTarget(*target), view).ok());
                            }).ok());
                Result<std::vector<uint8_t>> pixels = readPixels(*context, *target);
                return pixels ? *pixels : std::vector<uint8_t>{};
            };
            const std::vector<uint8_t> picture = draw(CullMethod::None, nullptr, nullptr);
            std::vector<uint32_t> culled, culledSubfaces;
            EXPECT_EQ(draw(CullMethod::PPlane, &culled, &culledSubfaces), picture) << path;
            culledPatches += culled.size();
            culledWholeSubfaces += culledSubfaces.size();
            EXPECT_TRUE(std::is_sorted(culled.begin(), culled.end()));
            ASSERT_TRUE(submitAndWait(*context, [&](VkCommandBuffer cmd) {
                            recordIdPass(cmd, *idPass, renderTarget(*target), view.viewProjection, true, *mesh);
                        }).ok());
            Result<std::vector<uint8_t>> ids = readPixels(*context, *target);
            ASSERT_TRUE(ids.ok() && ids->size() == picture.size());
            std::vector<uint32_t> owns(patches->patchCount, 0);
            // The background is the colour of a corner the model leaves free (every view frames it).
            ASSERT_EQ(decodeId(ids->data()), kNoId);
            size_t coverageDiffers = 0;
            for (size_t i = 0; i < ids->size(); i += 4) {
                const uint32_t id = decodeId(ids->data() + i);
                if (id != kNoId) ++owns[id];
                const bool surface = !std::equal(picture.begin() + i, picture.begin() + i + 3, picture.begin());
                coverageDiffers += surface != (id != kNoId);
            }
            if (std::string(path) == "cpu") {
                EXPECT_EQ(coverageDiffers, 0u) << "the ID buffer covers what the scheme draws, pixel for pixel";
            }
            for (uint32_t p : culled) EXPECT_EQ(owns[p], 0u) << path << ": culled patch " << p << " shows";
        }
        EXPECT_GT(culledPatches, 4 * culledWholeSubfaces) << path << ": most culled patches lie in sub-faces partly drawn";
        destroyIdMesh(*context, *mesh);
        destroyOffscreenTarget(*context, *target);
        EXPECT_TRUE(prepared->instance.destroyGpu().ok());
    }
    destroyIdPass(*context, *idPass);
    EXPECT_EQ(test::describeMessages(*context), "");
    destroyContext(*context);
}
