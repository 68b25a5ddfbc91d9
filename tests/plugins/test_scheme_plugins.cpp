// The approximating scheme plugins (acc1, acc2, pn, stam): they load, say what they refuse and
// approximate, draw with the validation layer silent, draw the same picture through the
// tessellator as through the CPU grid, and their tessellation shaders evaluate what their CPU
// evaluation does (vertices captured in the evaluation stage; the shaders are compiled into
// this binary from the plugins' sources, with the same pass the plugins use).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <tuple>

#include "../../plugins/acc1/acc1.h"
#include "../../plugins/acc2/acc2.h"
#include "../../plugins/pn/pn.h"
#include "camera.h"
#include "edit/cage_delta.h"
#include "module_shader_code.h"
#include "offscreen_target.h"
#include "plan_pass.h"
#include "plans/planned_cage.h"
#include "render_test_support.h"
#include "scene/scene.h"
#include "scheme_host.h"
#include "scheme_support.h"
#include "scheme_test_support.h"
#include "tess_patch_pass.h"
#include "test_cages.h"
#include "test_support.h"
#include "vk_commands.h"

using namespace qp;

namespace {

const PluginCatalog& catalog() {
    static const PluginCatalog plugins = loadPlugins(QUADPLAN_PLUGIN_DIR);
    return plugins;
}

// The subdivided cube, nudged so no two patches are alike: closed, valence-3 corners.
Cage perturbedCube(uint32_t n) {
    Cage cage = test::makeSubdividedCube(n);
    for (size_t i = 0; i < cage.positions.size(); ++i)
        cage.positions[i] += 0.05f * glm::vec3(std::sin(1.3f * float(i)), std::cos(2.1f * float(i)), std::sin(0.7f * float(i)));
    return cage;
}

// Three quads around one edge.
Cage nonManifoldFan() {
    Cage cage;
    cage.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1, -1, 0.2f}, {0, -1, 0.2f}, {1, 0, 1}, {0, 0, 1}};
    const uint32_t faces[3][4] = {{0, 1, 2, 3}, {1, 0, 5, 4}, {0, 1, 6, 7}};
    for (const auto& f : faces) cage.addFace(f, 4);
    return cage;
}

SupportReport supportOf(const std::string& name, const Cage& cage, SchemeSettings settings = {}) {
    Result<SchemeInstance> scheme = SchemeInstance::create(catalog().find(name));
    EXPECT_TRUE(scheme.ok()) << name;
    if (!scheme) return {};
    Result<SupportReport> report = scheme->support(analyzeCage(cage, buildTopology(cage)), settings);
    EXPECT_TRUE(report.ok()) << name;
    return report ? *report : SupportReport{};
}

bool mentions(const std::vector<std::string>& texts, const std::string& part) {
    return std::any_of(texts.begin(), texts.end(), [&](const std::string& t) { return t.find(part) != std::string::npos; });
}

std::string joined(const std::vector<std::string>& texts) {
    std::string all;
    for (const std::string& t : texts) all += "\n  " + t;
    return all;
}

}  // namespace

TEST(SchemePlugins, ApproximatingSchemesLoad) {
    for (const PluginProblem& p : catalog().problems) ADD_FAILURE() << p.message;
    for (const char* name : {"acc1", "acc2", "pn", "stam"}) {
        ASSERT_TRUE(catalog().find(name)) << name << " in " << catalog().names();
        EXPECT_FALSE(catalog().find(name)->summary.empty());
    }
}

TEST(SchemePlugins, SayWhatTheyRefuseAndApproximate) {
    Result<Scene> creased = loadSceneOrCage(std::string(QUADPLAN_SCENES_DIR) + "/creased_box.json");
    ASSERT_TRUE(creased.ok());
    const Cage grid = test::makeGrid(4), fan = nonManifoldFan(), cube = perturbedCube(2);

    for (const char* name : {"acc1", "acc2"}) {
        SCOPED_TRACE(name);
        SupportReport r = supportOf(name, creased->objects[0].cage);
        EXPECT_TRUE(r.usable());
        EXPECT_TRUE(mentions(r.approximations, "draws semi-sharp creases smooth")) << joined(r.approximations);
        EXPECT_TRUE(mentions(r.approximations, "approximates the surface next to extraordinary vertices"));
        EXPECT_TRUE(supportOf(name, grid).usable());  // boundaries: exact on regular boundary patches
        SupportReport nonManifold = supportOf(name, fan);
        EXPECT_FALSE(nonManifold.usable());
        EXPECT_TRUE(mentions(nonManifold.refusals, "needs a manifold cage")) << joined(nonManifold.refusals);
        SupportReport mixed = supportOf(name, test::makeMixedGrid());
        EXPECT_TRUE(mentions(mixed.approximations, "refines cages with non-quad faces once first"));
        SchemeSettings badPath;
        badPath.options = {{"path", "bogus"}};
        EXPECT_TRUE(mentions(supportOf(name, cube, badPath).refusals, "unknown path 'bogus'"));
    }

    SupportReport pn = supportOf("pn", cube);
    EXPECT_TRUE(pn.usable());
    EXPECT_TRUE(mentions(pn.approximations, "does not approximate the Catmull-Clark limit surface anywhere"));
    EXPECT_TRUE(supportOf("pn", fan).usable());  // no neighbours needed
    EXPECT_TRUE(mentions(supportOf("pn", creased->objects[0].cage).approximations, "pn ignores creases"));

    SupportReport stamOpen = supportOf("stam", grid);
    EXPECT_FALSE(stamOpen.usable());
    EXPECT_TRUE(mentions(stamOpen.refusals, "stam evaluates closed surfaces only")) << joined(stamOpen.refusals);
    EXPECT_FALSE(supportOf("stam", fan).usable());
    SupportReport stamCreased = supportOf("stam", creased->objects[0].cage);
    EXPECT_TRUE(stamCreased.usable());
    EXPECT_TRUE(mentions(stamCreased.approximations, "honours creases only in its one or two isolation steps"));
    SchemeSettings tess;
    tess.options = {{"path", "tess"}};
    EXPECT_TRUE(mentions(supportOf("stam", cube, tess).refusals, "CPU grid only"));
}

// ---- Drawing through the plugins -----------------------------------------------------------

namespace {

struct Picture {
    std::vector<uint8_t> pixels;
    DrawStats stats;
};

// Renders `planned` through scheme `name` into a size x size image (lavapipe, validation on).
Picture render(const VulkanContext& ctx, const std::string& name, const PlannedCage& planned, SchemeSettings settings,
               bool wireframe = true, uint32_t size = 160) {
    Picture picture;
    Result<OffscreenTarget> target = createOffscreenTarget(ctx, size, size, VK_FORMAT_R8G8B8A8_UNORM);
    EXPECT_TRUE(target.ok());
    if (!target) return picture;
    const GpuContext gpu{&ctx, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_D32_SFLOAT};
    const CageFeatures features = analyzeCage(planned.cage(), planned.topology());
    Result<PreparedScheme> prepared = prepareScheme(catalog(), name, planned, features, settings, gpu, "test cage");
    EXPECT_TRUE(prepared.ok()) << name << ": " << (prepared ? "" : prepared.error().message);
    if (prepared) {
        const Bounds bounds = computeBounds(planned.cage());
        const RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
        DrawView view;
        view.viewProjection = viewProjection(camera);
        view.eye = camera.eye;
        view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(camera), size);
        view.wireframe = wireframe;
        Result<DrawStats> drawn = DrawStats{};
        Status ok = submitAndWait(ctx, [&](VkCommandBuffer cmd) { drawn = prepared->instance.record(cmd, renderTarget(*target), view); });
        EXPECT_TRUE(ok.ok() && drawn.ok()) << name;
        if (drawn) picture.stats = *drawn;
        Result<std::vector<uint8_t>> pixels = readPixels(ctx, *target);
        EXPECT_TRUE(pixels.ok());
        if (pixels) picture.pixels = std::move(*pixels);
        EXPECT_TRUE(prepared->instance.destroyGpu().ok());
    }
    destroyOffscreenTarget(ctx, *target);
    return picture;
}

double coverage(const Picture& p) {
    size_t covered = 0;
    for (size_t i = 0; i + 3 < p.pixels.size(); i += 4) covered += std::abs(int(p.pixels[i]) - int(p.pixels[i + 2])) < 10 && p.pixels[i] < 215;
    return p.pixels.empty() ? 0.0 : double(covered) / double(p.pixels.size() / 4);
}

// Fraction of pixels whose colour differs by more than `threshold` in some channel.
double differingPixels(const Picture& a, const Picture& b, int threshold) {
    if (a.pixels.size() != b.pixels.size() || a.pixels.empty()) return 1.0;
    size_t differing = 0;
    for (size_t i = 0; i < a.pixels.size(); i += 4) {
        int d = 0;
        for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(a.pixels[i + c]) - int(b.pixels[i + c])));
        differing += d > threshold;
    }
    return double(differing) / double(a.pixels.size() / 4);
}

}  // namespace

TEST(SchemePlugins, DrawWithValidationSilentAndTheSamePictureThroughBothPaths) {
    Result<VulkanContext> context = test::createTestContext();
    ASSERT_TRUE(context.ok()) << context.error().message;
    VulkanContext& ctx = *context;
    const Cage cube = perturbedCube(3);  // closed: every scheme draws it
    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(cube, database, PlanOptions{}, "cube");
    ASSERT_TRUE(planned.ok());
    SchemeSettings tess, cpu;
    tess.tessFactor = cpu.tessFactor = 8;
    cpu.options = {{"path", "cpu"}};
    const SchemeSettings defaults = tess;
    for (const char* name : {"acc1", "acc2", "pn", "osd-fas"}) {
        SCOPED_TRACE(name);
        // osd-fas's default (auto) is its cpu path on lavapipe; the others default to tess.
        tess.options = std::string(name) == "osd-fas" ? decltype(tess.options){{"path", "tess"}} : decltype(tess.options){};
        const Picture patches = render(ctx, name, *planned, tess), grid = render(ctx, name, *planned, cpu);
        EXPECT_GT(coverage(patches), 0.2);
        EXPECT_EQ(patches.stats.triangles, grid.stats.triangles) << "the same density through both paths";
        EXPECT_GT(patches.stats.patches, 0u);
        // Same surface, same shading, different triangulation of each patch (so without the
        // wireframe, which shows exactly that difference): the pictures differ only at
        // silhouettes.
        const Picture shadedPatches = render(ctx, name, *planned, tess, false), shadedGrid = render(ctx, name, *planned, cpu, false);
        const double differing = differingPixels(shadedPatches, shadedGrid, 40);
        EXPECT_LT(differing, 0.03) << name << ": " << differing * 100.0 << "% of the pixels differ";
    }
    const Picture stam = render(ctx, "stam", *planned, defaults);
    EXPECT_GT(coverage(stam), 0.2);
    // Screen-adaptive factors through the tessellator.
    SchemeSettings adaptive;
    adaptive.adaptivePixels = 6.0f;
    EXPECT_GT(coverage(render(ctx, "acc2", *planned, adaptive)), 0.2);
    adaptive.options = {{"path", "tess"}};
    EXPECT_GT(coverage(render(ctx, "osd-fas", *planned, adaptive)), 0.2);
    EXPECT_EQ(validationMessageCount(ctx), 0u) << test::describeMessages(ctx);
    destroyContext(ctx);
}

// A frame the device cannot hold (its grid larger than the largest buffer the device makes, here
// lowered to 1 MiB) is an error of record(), naming the buffer, not an empty picture with success:
// `quadplan render` wrote such a PNG and exited 0. A factor that fits draws again afterwards.
TEST(SchemePlugins, PlansSaysWhenAFrameDoesNotFitTheDevice) {
    Result<VulkanContext> context = test::createTestContext();
    ASSERT_TRUE(context.ok()) << context.error().message;
    VulkanContext& ctx = *context;
    ctx.maxBufferBytes = 1 << 20;
    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(perturbedCube(3), database, PlanOptions{}, "cube");
    ASSERT_TRUE(planned.ok());
    const CageFeatures features = analyzeCage(planned->cage(), planned->topology());
    const GpuContext gpu{&ctx, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_D32_SFLOAT};
    Result<OffscreenTarget> target = createOffscreenTarget(ctx, 64, 64, VK_FORMAT_R8G8B8A8_UNORM);
    ASSERT_TRUE(target.ok());
    const Bounds bounds = computeBounds(planned->cage());
    const RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
    DrawView view;
    view.viewProjection = viewProjection(camera);
    view.eye = camera.eye;
    view.pixelsPerUnit = pixelsPerUnit(projectionMatrix(camera), 64);
    for (uint32_t factor : {64u, 2u}) {  // 54 sub-faces x 65^2 slots x 24 bytes = 5.2 MiB; then 0.01 MiB
        SchemeSettings settings;
        settings.tessFactor = factor;
        settings.options = {{"path", "cpu"}};
        Result<PreparedScheme> prepared = prepareScheme(catalog(), "plans", *planned, features, settings, gpu, "cube");
        ASSERT_TRUE(prepared.ok()) << prepared.error().message;
        Result<DrawStats> drawn = DrawStats{};
        ASSERT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) { drawn = prepared->instance.record(cmd, renderTarget(*target), view); }).ok());
        if (factor == 64) {
            ASSERT_FALSE(drawn.ok()) << "a 5 MiB grid on a device whose buffers stop at 1 MiB";
            EXPECT_NE(drawn.error().message.find("is larger than"), std::string::npos) << drawn.error().message;
        } else {
            ASSERT_TRUE(drawn.ok()) << drawn.error().message;
            EXPECT_GT(drawn->triangles, 0u);
        }
        ASSERT_TRUE(prepared->instance.destroyGpu().ok());
    }
    destroyOffscreenTarget(ctx, *target);
    EXPECT_EQ(validationMessageCount(ctx), 0u) << test::describeMessages(ctx);
    destroyContext(ctx);
}

// osd-fas's tess path applies its stencils on the device and refreshes its CPU points only when
// evaluate() asks: after a vertex move both paths must still evaluate the same surface.
TEST(SchemePlugins, OsdFasTessPathEvaluatesTheMovedCage) {
    Result<VulkanContext> context = test::createTestContext();
    ASSERT_TRUE(context.ok()) << context.error().message;
    VulkanContext& ctx = *context;
    PlanDatabase database;
    Result<PlannedCage> planned = PlannedCage::create(perturbedCube(3), database, PlanOptions{}, "cube");
    ASSERT_TRUE(planned.ok());
    const CageFeatures features = analyzeCage(planned->cage(), planned->topology());
    const GpuContext gpu{&ctx, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_D32_SFLOAT};
    SchemeSettings tess, cpu;
    tess.options = {{"path", "tess"}};
    cpu.options = {{"path", "cpu"}};
    Result<PreparedScheme> onDevice = prepareScheme(catalog(), "osd-fas", *planned, features, tess, gpu, "cube");
    Result<PreparedScheme> onCpu = prepareScheme(catalog(), "osd-fas", *planned, features, cpu, gpu, "cube");
    ASSERT_TRUE(onDevice.ok() && onCpu.ok());
    std::vector<SampleRequest> requests;
    for (uint32_t s = 0; s < planned->subfaceCount(); ++s) requests.push_back({s, 0.3f, 0.6f});
    std::vector<SurfacePoint> a(requests.size()), b(requests.size());
    ASSERT_TRUE(onDevice->instance.evaluate(requests, a).ok());  // the CPU points, before the move
    const uint32_t moved[1] = {5};
    const glm::vec3 to[1] = {planned->cage().positions[5] + glm::vec3(0.2f, -0.1f, 0.3f)};
    ASSERT_TRUE(planned->moveVertices(moved, to).ok());
    ASSERT_TRUE(onDevice->instance.update().ok());
    ASSERT_TRUE(onCpu->instance.update().ok());
    ASSERT_TRUE(onDevice->instance.evaluate(requests, a).ok());
    ASSERT_TRUE(onCpu->instance.evaluate(requests, b).ok());
    double moving = 0.0;
    for (size_t i = 0; i < requests.size(); ++i) {
        EXPECT_EQ(a[i].position, b[i].position) << "sub-face " << requests[i].subface;
        moving = std::max(moving, double(glm::length(a[i].position - planned->evaluate(requests[i].subface, 0.3f, 0.6f).position)));
    }
    EXPECT_LT(moving, 1e-5) << "osd-fas follows the moved cage";
    EXPECT_TRUE(onDevice->instance.destroyGpu().ok());
    EXPECT_TRUE(onCpu->instance.destroyGpu().ok());
    destroyContext(ctx);
}

// Displaced, every path draws the scheme's own surface moved along its own normal on the CPU
// grid: the tessellated and grid paths give the same picture, different from the undisplaced
// one, with the displaced mesh's triangles; removing the displacement restores the patches.
// A cube with sculpted bumps, an offscreen target and a camera: what the displacement tests of
// the schemes draw.
class DisplacedSchemes : public ::testing::Test {
protected:
    void SetUp() override {
        Result<VulkanContext> context = test::createTestContext();
        ASSERT_TRUE(context.ok()) << context.error().message;
        ctx = std::move(*context);
        haveContext = true;
        const Cage cube = perturbedCube(3);
        Result<PlannedCage> created = PlannedCage::create(cube, database, PlanOptions{}, "cube");
        ASSERT_TRUE(created.ok());
        planned.emplace(std::move(created).value());
        bumps = makeDisplacement(planned->cage(), planned->topology(), 8);
        const float amplitude = 0.04f * computeBounds(cube).diagonal();
        for (size_t i = 0; i < bumps.samples.size(); ++i) bumps.samples[i] = amplitude * std::sin(0.37f * float(i));
        gpu = GpuContext{&ctx, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_D32_SFLOAT};
        features = analyzeCage(planned->cage(), planned->topology());
        const Bounds bounds = computeBounds(cube);
        const RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
        view.viewProjection = viewProjection(camera);
        view.eye = camera.eye;
        Result<OffscreenTarget> created2 = createOffscreenTarget(ctx, kSize, kSize, VK_FORMAT_R8G8B8A8_UNORM);
        ASSERT_TRUE(created2.ok());
        target.emplace(*created2);
    }

    void TearDown() override {
        if (!haveContext) return;
        if (target) destroyOffscreenTarget(ctx, *target);
        EXPECT_EQ(validationMessageCount(ctx), 0u) << test::describeMessages(ctx);
        destroyContext(ctx);
    }

    Picture draw(SchemeInstance& instance) {
        Picture picture;
        Result<DrawStats> drawn = DrawStats{};
        EXPECT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) { drawn = instance.record(cmd, renderTarget(*target), view); }).ok());
        if (drawn) picture.stats = *drawn;
        Result<std::vector<uint8_t>> pixels = readPixels(ctx, *target);
        if (pixels) picture.pixels = std::move(*pixels);
        return picture;
    }

    static constexpr uint32_t kSize = 160;
    VulkanContext ctx;
    bool haveContext = false;
    PlanDatabase database;
    std::optional<PlannedCage> planned;
    Displacement bumps;
    GpuContext gpu;
    CageFeatures features;
    DrawView view;
    std::optional<OffscreenTarget> target;
};

// Displaced, every path draws the scheme's own surface moved along its own normal on the CPU
// grid: the tessellated and grid paths give the same picture, different from the undisplaced
// one, with the displaced mesh's triangles; removing the displacement restores the patches.
TEST_F(DisplacedSchemes, DrawTheDisplacementOnTheirOwnSurface) {
    for (const char* name : {"acc1", "acc2", "pn", "stam"}) {
        SCOPED_TRACE(name);
        std::vector<Picture> displaced;
        for (const char* path : {"tess", "cpu"}) {
            if (std::string(name) == "stam" && std::string(path) == "tess") continue;
            SchemeSettings settings;
            settings.tessFactor = 8;
            settings.options = {{"path", path}};
            Result<PreparedScheme> plain = prepareScheme(catalog(), name, *planned, features, settings, gpu, "cube");
            Result<PreparedScheme> bumped = prepareScheme(catalog(), name, *planned, features, settings, gpu, "cube", &bumps);
            ASSERT_TRUE(plain.ok() && bumped.ok()) << path;
            EXPECT_FALSE(mentions(bumped->support.approximations, "drawn without the sculpted displacement"));
            const Picture flat = draw(plain->instance);
            displaced.push_back(draw(bumped->instance));
            Result<DisplacedMesh> mesh = displacedSchemeMesh(bumped->instance.scheme(), *planned, bumps,
                                                          displacedGridFactor(*planned, bumps, settings.tessFactor));
            ASSERT_TRUE(mesh.ok());
            EXPECT_EQ(displaced.back().stats.triangles, mesh->indices.size() / 3) << path;
            EXPECT_GT(differingPixels(flat, displaced.back(), 40), 0.02) << path << ": the bumps do not show";
            // Displacement removed: back to the undisplaced picture.
            ASSERT_TRUE(bumped->instance.setDisplacement(nullptr).ok());
            ASSERT_TRUE(bumped->instance.update().ok());
            EXPECT_LT(differingPixels(flat, draw(bumped->instance), 40), 0.001) << path;
            EXPECT_TRUE(plain->instance.destroyGpu().ok());
            EXPECT_TRUE(bumped->instance.destroyGpu().ok());
        }
        if (displaced.size() == 2) {
            EXPECT_LT(differingPixels(displaced[0], displaced[1], 40), 0.001) << "tess and cpu paths differ when displaced";
        }
    }
}


// After a dab (samples changed in place) displacementChanged re-displaces only what the dab
// reached, and the picture is exactly the one a full update draws, for every scheme that draws
// a CPU mesh.
TEST_F(DisplacedSchemes, ADabUpdatesThePictureExactlyAsAFullUpdate) {
    for (const char* name : {"uniform", "osd-fas", "acc1", "acc2", "pn", "stam"}) {
        SCOPED_TRACE(name);
        SchemeSettings settings;
        settings.tessFactor = 8;
        Result<PreparedScheme> prepared = prepareScheme(catalog(), name, *planned, features, settings, gpu, "cube", &bumps);
        ASSERT_TRUE(prepared.ok()) << prepared.error().message;
        const Picture before = draw(prepared->instance);
        // A dab's worth of change (60 samples, spread so that the view sees some) and a shared
        // corner sample.
        std::vector<uint32_t> changed;
        for (uint32_t k = 40; k < 40 + 60 * 7 && k < bumps.layout.sampleCount; k += 7) changed.push_back(k);
        for (uint32_t k = 0; k < bumps.layout.sampleCount; ++k)
            if (bumps.layout.homes[k].corner >= 0) {
                changed.push_back(k);
                break;
            }
        const std::vector<float> saved = bumps.samples;
        for (uint32_t k : changed) bumps.samples[k] += 0.05f * computeBounds(planned->cage()).diagonal();
        ASSERT_TRUE(prepared->instance.displacementChanged(changed).ok());
        const Picture updated = draw(prepared->instance);
        ASSERT_TRUE(prepared->instance.update().ok());
        const Picture rebuilt = draw(prepared->instance);
        EXPECT_GT(differingPixels(before, updated, 40), 0.0005) << "the change did not show";
        EXPECT_EQ(updated.pixels, rebuilt.pixels) << "the incremental update differs from a full update";
        EXPECT_EQ(updated.stats.triangles, rebuilt.stats.triangles);
        bumps.samples = saved;
        EXPECT_TRUE(prepared->instance.destroyGpu().ok());
    }
}

// A tag edit, a hole and a topology edit reach `plans` in place on every path, and tag edits
// reach `uniform` in place, with the picture of a new instance; every other scheme asks for a
// rebuild (issue 15).
TEST_F(DisplacedSchemes, PlansTakesTagEditsInPlaceOthersAskForARebuild) {
    // The edge nearest the camera, so that the crease shows.
    const Topology& topology = planned->topology();
    const Cage& cage = planned->cage();
    uint32_t a = 0, b = 0;
    float nearest = INFINITY;
    for (uint32_t e = 0; e < topology.edgeCount(); ++e) {
        const uint32_t v0 = topology.edgeVertices[2 * e], v1 = topology.edgeVertices[2 * e + 1];
        const float distance = glm::length(0.5f * (cage.positions[v0] + cage.positions[v1]) - view.eye);
        if (distance < nearest) nearest = distance, a = v0, b = v1;
    }
    for (const char* path : {"tess", "grid", "cpu"}) {
        SCOPED_TRACE(path);
        SchemeSettings settings;
        settings.tessFactor = 8;
        settings.options = {{"path", path}};
        Result<PreparedScheme> prepared = prepareScheme(catalog(), "plans", *planned, features, settings, gpu, "cube");
        ASSERT_TRUE(prepared.ok()) << prepared.error().message;
        EXPECT_TRUE(prepared->instance.updatesPlansInPlace());
        EXPECT_TRUE(prepared->instance.updatesTopologyInPlace());
        const Picture before = draw(prepared->instance);
        Result<EditReport> crease = planned->setEdgeSharpness(a, b, kInfiniteSharpness);
        ASSERT_TRUE(crease.ok());
        const std::vector<uint32_t> subfaces = changedSubfaces(*planned, *crease);
        Result<PlanUpdate> updated = prepared->instance.updatePlans(PlanChange{subfaces, false, {}});
        ASSERT_TRUE(updated.ok()) << updated.error().message;
        EXPECT_EQ(*updated, PlanUpdate::Updated);
        const Picture inPlace = draw(prepared->instance);
        Result<PreparedScheme> fresh = prepareScheme(catalog(), "plans", *planned, features, settings, gpu, "cube");
        ASSERT_TRUE(fresh.ok());
        EXPECT_GT(differingPixels(before, inPlace, 8), 0.004) << "the crease does not show";
        EXPECT_EQ(inPlace.pixels, draw(fresh->instance).pixels) << "in place differs from a new instance";
        EXPECT_TRUE(fresh->instance.destroyGpu().ok());
        // A hole next to the crease, then filled: the drawn set changes, still in place.
        const uint32_t face = topology.edgeFaces[topology.edgeFaceOffsets[topology.findEdge(a, b)]];
        for (bool hole : {true, false}) {
            ASSERT_TRUE(planned->setHole(face, hole).ok());
            Result<PlanUpdate> holeUpdate = prepared->instance.updatePlans(PlanChange{std::vector<uint32_t>{face}, false, {}});
            ASSERT_TRUE(holeUpdate.ok()) << holeUpdate.error().message;
            EXPECT_EQ(*holeUpdate, PlanUpdate::Updated);
            const Picture holed = draw(prepared->instance);
            Result<PreparedScheme> again = prepareScheme(catalog(), "plans", *planned, features, settings, gpu, "cube");
            ASSERT_TRUE(again.ok());
            EXPECT_EQ(holed.pixels, draw(again->instance).pixels) << (hole ? "hole" : "filled") << ": differs from a new instance";
            EXPECT_TRUE(again->instance.destroyGpu().ok());
        }
        ASSERT_TRUE(planned->setEdgeSharpness(a, b, 0.0f).ok());
        // A topology edit (extrude the face, then its undo) through its renumbering, in place too.
        const Cage original = planned->cage();
        Result<TopologyEdit> extrude = extrudeFaces(planned->cage(), planned->topology(), std::vector<uint32_t>{face}, 0.3f);
        ASSERT_TRUE(extrude.ok()) << extrude.error().message;
        const TopologyDelta delta = makeTopologyDelta(planned->cage(), *extrude);
        // A crease taken in place but not drawn yet: its refresh is pending when the extrude comes.
        auto creaseInPlace = [&](float sharpness) {
            Result<EditReport> crease = planned->setEdgeSharpness(a, b, sharpness);
            ASSERT_TRUE(crease.ok());
            const std::vector<uint32_t> replanned = changedSubfaces(*planned, *crease);
            Result<PlanUpdate> tagUpdate = prepared->instance.updatePlans(PlanChange{replanned, false, {}});
            ASSERT_TRUE(tagUpdate.ok());
            EXPECT_EQ(*tagUpdate, PlanUpdate::Updated);
        };
        creaseInPlace(2.0f);
        for (DeltaDirection direction : {DeltaDirection::Forward, DeltaDirection::Backward}) {
            Result<TopologyEdit> edit = applyTopologyDelta(planned->cage(), delta, direction);
            ASSERT_TRUE(edit.ok()) << edit.error().message;
            Result<EditReport> report = planned->applyTopologyEdit(std::move(edit).value());
            ASSERT_TRUE(report.ok()) << report.error().message;
            const std::vector<uint32_t> changed = changedSubfaces(*planned, *report);
            Result<PlanUpdate> topologyUpdate =
                prepared->instance.updatePlans(PlanChange{changed, true, report->previousSubfaceOf});
            ASSERT_TRUE(topologyUpdate.ok()) << topologyUpdate.error().message;
            EXPECT_EQ(*topologyUpdate, PlanUpdate::Updated);
            const CageFeatures now = analyzeCage(planned->cage(), planned->topology());
            Result<PreparedScheme> again = prepareScheme(catalog(), "plans", *planned, now, settings, gpu, "cube");
            ASSERT_TRUE(again.ok());
            EXPECT_EQ(draw(prepared->instance).pixels, draw(again->instance).pixels) << "topology edit: differs from a new instance";
            EXPECT_TRUE(again->instance.destroyGpu().ok());
        }
        EXPECT_EQ(planned->cage().faceVertices, original.faceVertices);
        creaseInPlace(0.0f);
        EXPECT_TRUE(prepared->instance.destroyGpu().ok());
    }
    {  // uniform rewrites its refinement tables around the edit
        SCOPED_TRACE("uniform");
        SchemeSettings settings;
        settings.tessFactor = 8;
        Result<PreparedScheme> prepared = prepareScheme(catalog(), "uniform", *planned, features, settings, gpu, "cube");
        ASSERT_TRUE(prepared.ok()) << prepared.error().message;
        EXPECT_TRUE(prepared->instance.updatesPlansInPlace());
        EXPECT_FALSE(prepared->instance.updatesTopologyInPlace());
        const Picture before = draw(prepared->instance);
        const uint32_t face = topology.edgeFaces[topology.edgeFaceOffsets[topology.findEdge(a, b)]];
        std::vector<std::function<Result<EditReport>()>> edits = {
            [&] { return planned->setEdgeSharpness(a, b, kInfiniteSharpness); },
            [&] { return planned->setHole(face, true); },
            [&] { return planned->setHole(face, false); },
            [&] { return planned->setEdgeSharpness(a, b, 0.0f); },
        };
        for (size_t k = 0; k < edits.size(); ++k) {
            SCOPED_TRACE("edit " + std::to_string(k));
            Result<EditReport> report = edits[k]();
            ASSERT_TRUE(report.ok());
            const std::vector<uint32_t> changed = changedSubfaces(*planned, *report);
            Result<PlanUpdate> updated = prepared->instance.updatePlans(PlanChange{changed, false, {}});
            ASSERT_TRUE(updated.ok()) << updated.error().message;
            EXPECT_EQ(*updated, PlanUpdate::Updated);
            const Picture inPlace = draw(prepared->instance);
            if (k == 0) {
                EXPECT_GT(differingPixels(before, inPlace, 8), 0.004) << "the crease does not show";
            }
            Result<PreparedScheme> fresh = prepareScheme(catalog(), "uniform", *planned, features, settings, gpu, "cube");
            ASSERT_TRUE(fresh.ok());
            EXPECT_LT(differingPixels(inPlace, draw(fresh->instance), 8), 0.0005) << "in place differs from a new instance";
            EXPECT_TRUE(fresh->instance.destroyGpu().ok());
        }
        Result<PlanUpdate> topologyUpdate = prepared->instance.updatePlans(PlanChange{{}, true, {}});
        ASSERT_TRUE(topologyUpdate.ok());
        EXPECT_EQ(*topologyUpdate, PlanUpdate::Rebuild) << "uniform rebuilds after topology edits";
        EXPECT_TRUE(prepared->instance.destroyGpu().ok());
    }
    for (const char* name : {"osd-fas", "acc1", "acc2", "pn", "stam"}) {
        SCOPED_TRACE(name);
        Result<PreparedScheme> prepared = prepareScheme(catalog(), name, *planned, features, SchemeSettings{}, gpu, "cube");
        ASSERT_TRUE(prepared.ok()) << prepared.error().message;
        EXPECT_FALSE(prepared->instance.updatesPlansInPlace());
        Result<PlanUpdate> updated = prepared->instance.updatePlans(PlanChange{std::vector<uint32_t>{0}, false, {}});
        ASSERT_TRUE(updated.ok());
        EXPECT_EQ(*updated, PlanUpdate::Rebuild);
        EXPECT_TRUE(prepared->instance.destroyGpu().ok());
    }
}

// Hidden faces (DrawView::hiddenSubfaces) leave `plans`'s picture exactly as holes there would,
// on every path; the other schemes say they draw them anyway.
TEST_F(DisplacedSchemes, PlansLeavesHiddenFacesOutAsHolesWould) {
    // The three faces nearest the camera (quads: one sub-face each), sorted.
    const Cage& cage = planned->cage();
    std::vector<std::pair<float, uint32_t>> byDistance;
    for (uint32_t f = 0; f < cage.faceCount(); ++f) {
        glm::vec3 centre(0.0f);
        for (uint32_t k = 0; k < 4; ++k) centre += 0.25f * cage.positions[cage.faceBegin(f)[k]];
        byDistance.push_back({glm::length(centre - view.eye), f});
    }
    std::sort(byDistance.begin(), byDistance.end());
    std::vector<uint32_t> hidden = {byDistance[0].second, byDistance[1].second, byDistance[2].second};
    std::sort(hidden.begin(), hidden.end());
    for (const char* path : {"tess", "grid", "cpu"}) {
        SCOPED_TRACE(path);
        SchemeSettings settings;
        settings.tessFactor = 8;
        settings.options = {{"path", path}};
        Result<PreparedScheme> prepared = prepareScheme(catalog(), "plans", *planned, features, settings, gpu, "cube");
        ASSERT_TRUE(prepared.ok()) << prepared.error().message;
        EXPECT_TRUE(prepared->instance.hidesSubfaces());
        const Picture whole = draw(prepared->instance);
        view.hiddenSubfaces = hidden;
        const Picture withHidden = draw(prepared->instance);
        view.hiddenSubfaces = {};
        for (uint32_t f : hidden) ASSERT_TRUE(planned->setHole(f, true).ok());
        Result<PreparedScheme> holes = prepareScheme(catalog(), "plans", *planned, features, settings, gpu, "cube");
        ASSERT_TRUE(holes.ok());
        const Picture withHoles = draw(holes->instance);
        for (uint32_t f : hidden) ASSERT_TRUE(planned->setHole(f, false).ok());
        EXPECT_GT(differingPixels(whole, withHidden, 8), 0.01) << "hiding shows nothing";
        EXPECT_EQ(withHidden.pixels, withHoles.pixels) << "hidden faces differ from holes";
        EXPECT_EQ(withHidden.stats.patches, whole.stats.patches - hidden.size());
        EXPECT_EQ(withHidden.stats.triangles, withHoles.stats.triangles);
        EXPECT_TRUE(prepared->instance.destroyGpu().ok());
        EXPECT_TRUE(holes->instance.destroyGpu().ok());
    }
    Result<PreparedScheme> uniform = prepareScheme(catalog(), "uniform", *planned, features, SchemeSettings{}, gpu, "cube");
    ASSERT_TRUE(uniform.ok());
    EXPECT_FALSE(uniform->instance.hidesSubfaces());
    EXPECT_TRUE(uniform->instance.destroyGpu().ok());
}

// ---- The tessellation shaders against the CPU evaluation -----------------------------------

namespace {

struct Captured {
    std::vector<TessCaptureRecord> records;
    uint32_t overflow = 0;
};

// Draws `patchCount` patches of `data` through the shaders `control`/`evaluation` at a uniform
// factor, capturing every evaluated vertex.
Captured drawAndCapture(const VulkanContext& ctx, const char* control, const char* evaluation,
                        const std::vector<glm::vec4>& data, uint32_t patchCount, uint32_t factor, const Bounds& bounds) {
    Captured out;
    Result<TessPatchPass> pass = createTessPatchPass(
        ctx, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_D32_SFLOAT,
        {moduleShaderCode("tess_patch.vert"), moduleShaderCode(control), moduleShaderCode(evaluation), {}});
    EXPECT_TRUE(pass.ok()) << (pass ? "" : pass.error().message);
    if (!pass) return out;
    Result<OffscreenTarget> target = createOffscreenTarget(ctx, 128, 128, VK_FORMAT_R8G8B8A8_UNORM);
    EXPECT_TRUE(target.ok());
    EXPECT_TRUE(uploadTessPatches(ctx, *pass, data.data(), data.size() * sizeof(glm::vec4), patchCount).ok());
    const uint32_t perPatch = (factor + 1) * (factor + 2);  // room for any vertex order
    EXPECT_TRUE(enableTessCapture(ctx, *pass, patchCount * perPatch).ok());
    const RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
    DrawView view;
    view.viewProjection = viewProjection(camera);
    view.eye = camera.eye;
    EXPECT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) {
                    recordTessPatches(cmd, *pass, renderTarget(*target), view, {factor, 8.0f, true});
                }).ok());
    out.records = readTessCapture(*pass, &out.overflow);
    destroyOffscreenTarget(ctx, *target);
    destroyTessPatchPass(ctx, *pass);
    return out;
}

struct GpuCpuGap {
    double position = 0.0, normalDegrees = 0.0;
    size_t distinctVertices = 0;  // distinct (patch, lattice point) pairs
};

// Compares every captured vertex with the CPU evaluation at its (u, v[, w]). The tessellator
// emits shared vertices more than once, not always with bit-identical coordinates, so vertices
// are counted by their coordinates rounded to 1e-5.
template <typename Evaluate>  // Evaluate(record) -> pair<position, normal> on the CPU
GpuCpuGap compare(const Captured& captured, double diagonal, Evaluate evaluate) {
    GpuCpuGap gap;
    std::set<std::tuple<uint32_t, long, long, long>> seen;
    const auto rounded = [](float c) { return std::lround(double(c) * 1e5); };
    for (const TessCaptureRecord& r : captured.records) {
        seen.insert({r.patch, rounded(r.u), rounded(r.v), rounded(r.w)});
        const auto [position, normal] = evaluate(r);
        const glm::dvec3 p(r.position[0], r.position[1], r.position[2]), n(r.normal[0], r.normal[1], r.normal[2]);
        gap.position = std::max(gap.position, glm::length(p - glm::dvec3(position)) / diagonal);
        if (glm::length(glm::dvec3(normal)) > 0.0) gap.normalDegrees = std::max(gap.normalDegrees, test::angleDegrees(n, glm::dvec3(normal)));
    }
    gap.distinctVertices = seen.size();
    return gap;
}

}  // namespace

// 384 patches at factor 16: more than one draw (patchesPerDraw(16) = 226), so the split draws
// are covered too.
TEST(SchemePlugins, TessellationShadersMatchTheCpuEvaluation) {
    Result<VulkanContext> context = test::createTestContext();
    ASSERT_TRUE(context.ok()) << context.error().message;
    VulkanContext& ctx = *context;
    const Cage cube = perturbedCube(8);
    const Bounds bounds = computeBounds(cube);
    constexpr uint32_t kFactor = 16;
    // Equal spacing, even factor n: a quad is an (n+1)^2 lattice; a triangle is n/2 concentric
    // rings of 3n, 3(n-2), ... 6 vertices around its centre (not a barycentric lattice).
    const size_t quadVertices = (kFactor + 1) * (kFactor + 1), triangleVertices = 1 + 3 * kFactor * (kFactor + 2) / 4;

    // Draws `patches` patches of `data` through the scheme's shaders, captures every vertex and
    // compares it with `evaluate` (position and normal at the captured parameter).
    auto expectShadersMatch = [&](const char* scheme, const std::vector<glm::vec4>& data, uint32_t patches,
                                  const Bounds& b, size_t verticesPerPatch, const auto& evaluate) {
        const std::string name = scheme;
        Captured c = drawAndCapture(ctx, (name + ".tesc").c_str(), (name + ".tese").c_str(), data, patches, kFactor, b);
        EXPECT_EQ(c.overflow, 0u);
        GpuCpuGap gap = compare(c, b.diagonal(), evaluate);
        std::printf("%s: %zu vertices, GPU - CPU: position %.2e of the diagonal, normal %.2e deg\n", scheme,
                    gap.distinctVertices, gap.position, gap.normalDegrees);
        EXPECT_EQ(gap.distinctVertices, patches * verticesPerPatch) << scheme;
        EXPECT_LT(gap.position, 1e-5) << scheme;
        EXPECT_LT(gap.normalDegrees, 0.01) << scheme;
    };
    {
        Result<Acc2Patches> acc2 = buildAcc2(cube, {}, "cube");
        ASSERT_TRUE(acc2.ok());
        ASSERT_GT(acc2->stats.patches, patchesPerDraw(kFactor));
        expectShadersMatch("acc2", paddedPoints(acc2->controlPoints), acc2->stats.patches, bounds, quadVertices,
                           [&](const TessCaptureRecord& r) {
                               Acc2Sample s = evaluateAcc2Patch(*acc2, r.patch, r.u, r.v);
                               return std::pair(s.position, s.normal);
                           });
    }
    {
        Result<Acc1Patches> acc1 = buildAcc1(cube, {}, "cube");
        ASSERT_TRUE(acc1.ok());
        expectShadersMatch("acc1", paddedPoints(acc1->controlPoints), acc1->stats.patches, bounds, quadVertices,
                           [&](const TessCaptureRecord& r) {
                               Acc1Sample s = evaluateAcc1Patch(*acc1, r.patch, r.u, r.v);
                               return std::pair(s.position, s.normal);
                           });
    }
    for (const Cage& cage : {cube, test::makeMixedGrid()}) {  // split quads; a triangle and a fanned pentagon
        Result<PnPatches> pn = buildPn(cage, "pn cage");
        ASSERT_TRUE(pn.ok());
        std::vector<glm::vec4> data;
        for (uint32_t t = 0; t < pn->stats.triangles; ++t) {
            for (uint32_t i = 0; i < PnPatches::kPositionPoints; ++i) data.push_back(glm::vec4(pn->positions[t * 10 + i], 1.0f));
            for (uint32_t i = 0; i < PnPatches::kNormalPoints; ++i) data.push_back(glm::vec4(pn->normals[t * 6 + i], 0.0f));
        }
        expectShadersMatch("pn", data, pn->stats.triangles, computeBounds(cage), triangleVertices,
                           [&](const TessCaptureRecord& r) {
                               PnSample s = evaluatePnTriangle(*pn, r.patch, glm::vec3(r.u, r.v, r.w));
                               return std::pair(s.position, s.normal);
                           });
    }
    EXPECT_EQ(validationMessageCount(ctx), 0u) << test::describeMessages(ctx);
    destroyContext(ctx);
}
