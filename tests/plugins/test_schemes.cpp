// The scheme plugins: the loader and its failure modes (with deliberately broken modules from
// tests/plugins/), each built-in scheme's CPU evaluation against the exact limit surface, the
// cage analysis behind support reports, and the heat-map scale.
#include <gtest/gtest.h>

#include <functional>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <unordered_map>

#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/primvarRefiner.h>

#include "../../plugins/osd-fas/osd_fas_patches.h"
#include "../../plugins/uniform/uniform_refinement.h"
#include "plans/osd_refiner.h"
#include "scene/scene.h"
#include "scheme_host.h"
#include "scheme_support.h"
#include "surface_error.h"
#include "test_cages.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace qp;

namespace {

const PluginCatalog& builtIn() {
    static const PluginCatalog catalog = loadPlugins(QUADPLAN_PLUGIN_DIR);
    return catalog;
}

struct Planned {
    PlanDatabase database;
    std::optional<PlannedCage> planned;
};

std::unique_ptr<Planned> plan(const Cage& cage, uint32_t depth = 6) {
    auto p = std::make_unique<Planned>();
    Result<PlannedCage> planned = PlannedCage::create(cage, p->database, PlanOptions{depth, true}, "test cage");
    EXPECT_TRUE(planned.ok()) << planned.error().message;
    if (planned) p->planned.emplace(std::move(*planned));
    return p;
}

Cage loadCage(const fs::path& path) {
    Result<Scene> scene = loadSceneOrCage(path.string());
    EXPECT_TRUE(scene.ok()) << path << ": " << (scene ? "" : scene.error().message);
    return scene ? scene->objects[0].cage : Cage{};
}

// A built scheme without GPU (build + update only: the CPU evaluation needs no device).
SchemeInstance buildScheme(const std::string& name, const PlannedCage& planned, SchemeSettings settings = {}) {
    std::shared_ptr<SchemePlugin> plugin = builtIn().find(name);
    EXPECT_TRUE(plugin) << name << " not found in " << builtIn().directory;
    Result<SchemeInstance> instance = SchemeInstance::create(plugin);
    EXPECT_TRUE(instance.ok());
    Status built = instance->build(planned, settings);
    EXPECT_TRUE(built.ok()) << built.error().message;
    Status updated = instance->update();
    EXPECT_TRUE(updated.ok()) << updated.error().message;
    return std::move(*instance);
}

ErrorStats errorOf(const SchemeInstance& scheme, const PlannedCage& planned, uint32_t samplesPerEdge = 8) {
    const SubfaceGrid grid = buildSubfaceGrid(planned, samplesPerEdge);
    std::vector<SurfacePoint> points(grid.samples.size());
    Status evaluated = scheme.evaluate(grid.samples, points);
    EXPECT_TRUE(evaluated.ok()) << evaluated.error().message;
    return measureSurfaceError(planned, grid.samples, points, computeBounds(planned.cage()).diagonal()).stats;
}

// The shared cages the comparison in docs/schemes.md uses (when ../shared is present).
std::vector<fs::path> comparisonShapes() {
    std::vector<fs::path> shapes;
    for (const char* name : {"catmark_cube_creases1", "catmark_nonquads", "catmark_pawn", "catmark_hole_test1",
                             "catmark_torus_creases0", "catmark_chaikin1", "catmark_dart_edgeonly", "catmark_fan"})
        if (fs::exists(test::sharedShapesDir() / (std::string(name) + ".obj")))
            shapes.push_back(test::sharedShapesDir() / (std::string(name) + ".obj"));
    return shapes;
}

}  // namespace

// ---- Loader ------------------------------------------------------------------------------

TEST(SchemeLoader, FindsTheBuiltInSchemes) {
    const PluginCatalog& catalog = builtIn();
    for (const PluginProblem& p : catalog.problems) ADD_FAILURE() << p.message;
    for (const char* name : {"plans", "osd-fas", "uniform"}) {
        ASSERT_TRUE(catalog.find(name)) << name << " in " << catalog.names();
        EXPECT_FALSE(catalog.find(name)->summary.empty());
    }
    EXPECT_FALSE(catalog.find("acc9"));
    EXPECT_NE(unknownSchemeMessage(catalog, "acc9").find("plans"), std::string::npos);
}

TEST(SchemeLoader, BrokenModulesAreReportedAndTheRestLoads) {
    // A copy of the test modules plus files that are not modules at all.
    const fs::path dir = fs::path(::testing::TempDir()) / ("qp-plugins-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (const auto& entry : fs::directory_iterator(QUADPLAN_TEST_PLUGIN_DIR))
        if (entry.path().extension() == ".so") fs::copy_file(entry.path(), dir / entry.path().filename());
    std::ofstream(dir / "quadplan-scheme-garbage.so") << "this is not an ELF file\n";
    std::ofstream(dir / "README.txt") << "ignored: not named quadplan-scheme-*.so\n";

    const PluginCatalog catalog = loadPlugins(dir.string());
    ASSERT_TRUE(catalog.find("test-flat")) << catalog.names();
    EXPECT_TRUE(catalog.find("test-throws"));
    EXPECT_TRUE(catalog.find("test-null"));
    auto problem = [&](const std::string& file) -> std::string {
        for (const PluginProblem& p : catalog.problems)
            if (fs::path(p.path).filename() == file) return p.message;
        return "";
    };
    EXPECT_NE(problem("quadplan-scheme-garbage.so").find("cannot load scheme plugin"), std::string::npos);
    EXPECT_NE(problem("quadplan-scheme-test-undefined.so").find("quadplan_test_symbol_nobody_defines"), std::string::npos)
        << problem("quadplan-scheme-test-undefined.so");
    EXPECT_NE(problem("quadplan-scheme-test-noentry.so").find("no entry point"), std::string::npos);
    EXPECT_NE(problem("quadplan-scheme-test-version.so").find("interface version"), std::string::npos);
    EXPECT_NE(problem("quadplan-scheme-test-version.so").find("rebuild"), std::string::npos);
    EXPECT_NE(problem("quadplan-scheme-test-abi.so").find("another compiler"), std::string::npos);
    // Two modules naming themselves test-flat: the second is refused, the first kept.
    const std::string duplicate = problem("quadplan-scheme-test-flat.so") + problem("quadplan-scheme-test-duplicate.so");
    EXPECT_NE(duplicate.find("already provides"), std::string::npos) << duplicate;
    EXPECT_EQ(catalog.problems.size(), 6u);
    for (const PluginProblem& p : catalog.problems) EXPECT_NE(p.message.find(p.path), std::string::npos) << p.message;
    fs::remove_all(dir);

    const PluginCatalog missing = loadPlugins((dir / "nowhere").string());
    EXPECT_TRUE(missing.plugins.empty());
    ASSERT_EQ(missing.problems.size(), 1u);
    EXPECT_NE(missing.problems[0].message.find("does not exist"), std::string::npos);
}

TEST(SchemeLoader, ThrowingAndEmptySchemesFailWithAMessage) {
    const PluginCatalog catalog = loadPlugins(QUADPLAN_TEST_PLUGIN_DIR);
    auto planned = plan(test::makeCube());
    const CageFeatures features = analyzeCage(planned->planned->cage(), planned->planned->topology());
    const GpuContext noGpu{};
    Result<PreparedScheme> throws = prepareScheme(catalog, "test-throws", *planned->planned, features, {}, noGpu, "cube");
    ASSERT_FALSE(throws.ok());
    EXPECT_NE(throws.error().message.find("scheme 'test-throws' threw during build: deliberate failure in build"),
              std::string::npos)
        << throws.error().message;
    Result<PreparedScheme> empty = prepareScheme(catalog, "test-null", *planned->planned, features, {}, noGpu, "cube");
    ASSERT_FALSE(empty.ok());
    EXPECT_NE(empty.error().message.find("created no instance"), std::string::npos) << empty.error().message;
    Result<PreparedScheme> unknown = prepareScheme(catalog, "nope", *planned->planned, features, {}, noGpu, "cube");
    ASSERT_FALSE(unknown.ok());
    EXPECT_NE(unknown.error().message.find("unknown scheme 'nope'"), std::string::npos);
    // The good one still works after all that, and is the bilinear cage.
    Result<SchemeInstance> flat = SchemeInstance::create(catalog.find("test-flat"));
    ASSERT_TRUE(flat.ok());
    ASSERT_TRUE(flat->build(*planned->planned, {}).ok());
    SurfacePoint point;
    const SampleRequest corner{0, 0.0f, 0.0f};
    ASSERT_TRUE(flat->evaluate({&corner, 1}, {&point, 1}).ok());
    EXPECT_EQ(point.position, planned->planned->cage().positions[planned->planned->cage().faceBegin(0)[0]]);
}

// ---- Support reports ---------------------------------------------------------------------

TEST(SchemeSupport, AnalyzeCageCountsFeatures) {
    Cage cage = test::makeMixedGrid();
    cage.setEdgeSharpness(0, 1, 2.5f);
    cage.setEdgeSharpness(1, 2, kInfiniteSharpness);
    cage.setVertexSharpness(3, 1.0f);
    const CageFeatures f = analyzeCage(cage, buildTopology(cage));
    EXPECT_EQ(f[CageFeature::NonQuadFaces], 2u);
    EXPECT_EQ(f[CageFeature::Triangles], 1u);
    EXPECT_EQ(f[CageFeature::SemiSharpCreases], 1u);
    EXPECT_EQ(f[CageFeature::InfinitelySharpCreases], 1u);
    EXPECT_EQ(f[CageFeature::SemiSharpCorners], 1u);
    EXPECT_EQ(f[CageFeature::Boundaries], 16u);
    EXPECT_FALSE(f.has(CageFeature::Holes));
    EXPECT_FALSE(f.has(CageFeature::NonManifold));
    EXPECT_TRUE(f.has(CageFeature::ExtraordinaryVertices));

    const CageFeatures cube = analyzeCage(test::makeCube(), buildTopology(test::makeCube()));
    EXPECT_EQ(cube[CageFeature::ExtraordinaryVertices], 8u);
    EXPECT_EQ(cube[CageFeature::AdjacentExtraordinary], 6u);  // every face has four valence-3 corners
    EXPECT_FALSE(cube.has(CageFeature::Boundaries));
    EXPECT_EQ(cube.maxValence, 3u);

    const FeatureRule rules[] = {{CageFeature::SemiSharpCreases, Handling::Approximated, "semi-sharp creases are drawn smooth"},
                                 {CageFeature::NonQuadFaces, Handling::Unsupported, "needs quads"},
                                 {CageFeature::Holes, Handling::Unsupported, "no holes"}};
    const SupportReport report = assessSupport(rules, f);
    ASSERT_EQ(report.approximations.size(), 1u);
    EXPECT_EQ(report.approximations[0], "semi-sharp creases are drawn smooth (the cage has 1 semi-sharp creases)");
    ASSERT_EQ(report.refusals.size(), 1u);  // no holes in the cage: that rule stays silent
    EXPECT_FALSE(report.usable());
}

TEST(SchemeSupport, BuiltInSchemesSayWhatTheyApproximate) {
    Cage triangles = test::makeMixedGrid();
    triangles.options.triangleSubdivision = TriangleSubdivision::Smooth;
    const CageFeatures f = analyzeCage(triangles, buildTopology(triangles));
    ASSERT_TRUE(f.has(CageFeature::SmoothTriangleRule));
    for (const char* name : {"plans", "osd-fas", "uniform"}) {
        Result<SchemeInstance> scheme = SchemeInstance::create(builtIn().find(name));
        ASSERT_TRUE(scheme.ok());
        Result<SupportReport> report = scheme->support(f, {});
        ASSERT_TRUE(report.ok());
        EXPECT_TRUE(report->usable()) << name;
        const bool saysTriangleRule = std::any_of(report->approximations.begin(), report->approximations.end(),
                                                  [](const std::string& s) { return s.find("smooth triangle") != std::string::npos; });
        EXPECT_EQ(saysTriangleRule, std::string(name) == "uniform") << name;
    }
    SchemeSettings badLevel;
    badLevel.options = {{"level", "12"}};
    Result<SchemeInstance> uniform = SchemeInstance::create(builtIn().find("uniform"));
    EXPECT_FALSE(uniform->support(f, badLevel)->usable());
}

// ---- CPU evaluation against the exact limit surface ----------------------------------------

TEST(SchemeEvaluation, PlansIsTheReference) {
    auto planned = plan(test::makeMixedGrid());
    SchemeInstance scheme = buildScheme("plans", *planned->planned);
    const ErrorStats e = errorOf(scheme, *planned->planned);
    EXPECT_EQ(e.maxRelError, 0.0);
    // The same du and dv; the scheme's normal is normalised in float, the reference's in double.
    EXPECT_LT(e.maxNormalDegrees, 1e-4);
    EXPECT_GT(e.samples, 1000u);
}

TEST(SchemeEvaluation, OsdFasMatchesTheExactSurface) {
    std::vector<std::pair<std::string, Cage>> cages = {{"subdivided cube", test::makeSubdividedCube()},
                                                       {"mixed grid", test::makeMixedGrid()},
                                                       {"cube", test::makeCube()}};
    Cage creased = test::makeSubdividedCube();
    creased.setEdgeSharpness(creased.faceBegin(0)[0], creased.faceBegin(0)[1], 2.5f);
    cages.push_back({"creased cube", creased});
    for (const fs::path& shape : comparisonShapes()) cages.push_back({shape.filename().string(), loadCage(shape)});
    for (const auto& [name, cage] : cages) {
        SCOPED_TRACE(name);
        auto planned = plan(cage);
        SchemeInstance scheme = buildScheme("osd-fas", *planned->planned);
        const ErrorStats e = errorOf(scheme, *planned->planned);
        EXPECT_LT(e.maxRelError, 5e-5);
        EXPECT_LT(e.rmsRelError, 1e-6);
        EXPECT_GT(e.normalSamples, e.samples / 2);
    }
}

// osd-fas is OpenSubdiv's method as its GPU path ships it: its patch table is the one Far builds
// with single-crease patches, inf-sharp patches and Gregory-basis end caps at the plan depth,
// and every semi-sharp crease a regular face carries alone is a single-crease patch.
TEST(SchemeEvaluation, OsdFasBuildsFarsOwnPatchTable) {
    if (!test::haveSharedShapes()) GTEST_SKIP() << "needs ../shared/shapes (OpenSubdiv's regression cages)";
    using namespace OpenSubdiv;
    // Far's counts at depth 6 with these options, measured with OpenSubdiv 3.5 (platform notes).
    const std::map<std::string, int> measured = {{"catmark_car", 22767}, {"catmark_pawn", 1488}};
    for (const char* name : {"catmark_car", "catmark_pawn", "catmark_cube_creases1", "catmark_creases2",
                             "catmark_dart_edgeonly", "catmark_nonquads"}) {
        const fs::path path = test::sharedShapesDir() / (std::string(name) + ".obj");
        if (!fs::exists(path)) continue;
        SCOPED_TRACE(name);
        const Cage cage = loadCage(path);
        auto refiner = createRefiner(cage, name);
        ASSERT_TRUE(refiner.ok()) << refiner.error().message;
        Far::PatchTableFactory::Options options(6);
        options.useSingleCreasePatch = true;
        options.useInfSharpPatch = true;
        options.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
        (*refiner)->RefineAdaptive(options.GetRefineAdaptiveOptions());
        std::unique_ptr<Far::PatchTable> far(Far::PatchTableFactory::Create(**refiner, options));
        Result<FasPatches> patches = buildFasPatches(cage, 6, 8);
        ASSERT_TRUE(patches.ok()) << patches.error().message;
        EXPECT_EQ(int(patches->layout.size()), far->GetNumPatchesTotal());
        if (auto it = measured.find(name); it != measured.end()) {
            EXPECT_EQ(int(patches->layout.size()), it->second);
            EXPECT_GT(patches->singleCreasePatches, 0u) << "no semi-sharp crease became a single-crease patch";
        }
    }
}

// Welds the triangles' corners by position and counts edges used by one triangle only: a closed
// cage must give none, or the tessellation has cracks.
size_t openEdges(const std::vector<glm::vec3>& positions, const std::vector<uint32_t>& indices, float tolerance) {
    std::unordered_map<int64_t, std::vector<uint32_t>> cells;
    auto key = [&](glm::ivec3 c) { return (int64_t(c.x) * 73856093) ^ (int64_t(c.y) * 19349663) ^ (int64_t(c.z) * 83492791); };
    std::vector<uint32_t> weld(positions.size());
    for (uint32_t i = 0; i < positions.size(); ++i) {
        const glm::ivec3 c(glm::floor(positions[i] / tolerance));
        weld[i] = i;
        for (int dx = -1; dx <= 1 && weld[i] == i; ++dx)
            for (int dy = -1; dy <= 1 && weld[i] == i; ++dy)
                for (int dz = -1; dz <= 1 && weld[i] == i; ++dz) {
                    auto it = cells.find(key(c + glm::ivec3(dx, dy, dz)));
                    if (it == cells.end()) continue;
                    for (uint32_t j : it->second)
                        if (glm::length(positions[j] - positions[i]) < tolerance) {
                            weld[i] = j;
                            break;
                        }
                }
        if (weld[i] == i) cells[key(c)].push_back(i);
    }
    std::map<std::pair<uint32_t, uint32_t>, int> uses;
    for (size_t t = 0; t < indices.size(); t += 3)
        for (int k = 0; k < 3; ++k) {
            uint32_t a = weld[indices[t + k]], b = weld[indices[t + (k + 1) % 3]];
            if (a == b) continue;
            ++uses[{std::min(a, b), std::max(a, b)}];
        }
    return size_t(std::count_if(uses.begin(), uses.end(), [](const auto& u) { return u.second == 1; }));
}

TEST(SchemeEvaluation, OsdFasPatchTessellationIsWatertight) {
    // What osd-fas draws: every patch tessellated at its own factor, one-segment patches next to
    // finer ones carrying their midpoints. A closed cage must weld into a closed mesh at every
    // factor, the low ones (where transitions matter) included.
    std::vector<std::pair<std::string, Cage>> cages;
    Cage cube = test::makeSubdividedCube(2);
    cube.setEdgeSharpness(cube.faceBegin(0)[0], cube.faceBegin(0)[1], 1.5f);
    cages.push_back({"creased cube", cube});
    cages.push_back({"cube", test::makeCube()});
    for (const char* name : {"catmark_cube_creases1", "catmark_pyramid", "catmark_torus_creases0"})
        if (fs::exists(test::sharedShapesDir() / (std::string(name) + ".obj")))
            cages.push_back({name, loadCage(test::sharedShapesDir() / (std::string(name) + ".obj"))});
    for (const auto& [name, cage] : cages)
        for (uint32_t factor : {1u, 2u, 4u, 16u}) {
            SCOPED_TRACE(name + " factor " + std::to_string(factor));
            Result<FasPatches> patches = buildFasPatches(cage, 6, factor);
            ASSERT_TRUE(patches.ok()) << patches.error().message;
            updateFasPoints(*patches, cage.positions);
            std::vector<glm::vec3> positions, normals;
            tessellateFas(*patches, positions, normals);
            EXPECT_EQ(openEdges(positions, patches->indices, 1e-5f * computeBounds(cage).diagonal()), 0u);
        }
}

TEST(SchemeEvaluation, UniformTablesReproduceOpenSubdivRefinement) {
    struct Point {
        glm::vec3 p{0.0f};
        void Clear(void* = nullptr) { p = glm::vec3(0.0f); }
        void AddWithWeight(const Point& s, float w) { p += w * s.p; }
    };
    std::vector<std::pair<std::string, Cage>> cages = {{"mixed grid", test::makeMixedGrid()}};
    Cage creased = test::makeSubdividedCube();
    const uint32_t* quad = creased.faceBegin(4);
    creased.setEdgeSharpness(quad[0], quad[1], 1.7f);
    creased.setEdgeSharpness(quad[1], quad[2], 0.4f);
    creased.setVertexSharpness(quad[3], 2.2f);
    cages.push_back({"creased cube", creased});
    for (const fs::path& shape : comparisonShapes()) cages.push_back({shape.filename().string(), loadCage(shape)});
    for (const char* extra : {"catmark_nonman_edges", "catmark_chaikin0", "catmark_cube_corner2"})
        if (fs::exists(test::sharedShapesDir() / (std::string(extra) + ".obj")))
            cages.push_back({extra, loadCage(test::sharedShapesDir() / (std::string(extra) + ".obj"))});
    for (const auto& [name, cage] : cages) {
        SCOPED_TRACE(name);
        auto planned = plan(cage, 2);
        const uint32_t levels = 3;
        Result<UniformRefinement> refinement = buildUniformRefinement(*planned->planned, levels);
        ASSERT_TRUE(refinement.ok()) << refinement.error().message;
        std::vector<glm::vec3> ours;
        applyUniformRefinement(*refinement, planned->planned->cage().positions, ours);

        auto refiner = createRefiner(planned->planned->cage(), name);
        ASSERT_TRUE(refiner.ok());
        (*refiner)->RefineUniform(OpenSubdiv::Far::TopologyRefiner::UniformOptions(int(levels)));
        std::vector<Point> theirs((*refiner)->GetNumVerticesTotal());
        for (size_t i = 0; i < cage.positions.size(); ++i) theirs[i].p = planned->planned->cage().positions[i];
        OpenSubdiv::Far::PrimvarRefiner primvar(**refiner);
        Point* source = theirs.data();
        for (int level = 1; level <= int(levels); ++level) {
            Point* destination = source + (*refiner)->GetLevel(level - 1).GetNumVertices();
            primvar.Interpolate(level, source, destination);
            source = destination;
        }
        ASSERT_EQ(ours.size(), theirs.size());
        const float scale = computeBounds(cage).diagonal();
        float worst = 0.0f;
        for (size_t i = 0; i < ours.size(); ++i) worst = std::max(worst, glm::length(ours[i] - theirs[i].p));
        EXPECT_LT(worst / scale, 5e-6f);  // float sums in another order
        // Every drawable sub-face is covered by refined quads in its own frame.
        for (uint32_t s = 0; s < planned->planned->subfaceCount(); ++s) {
            if (!planned->planned->hasSurface(s)) continue;
            const uint32_t side = refinement->subfaceSide[s];
            ASSERT_GT(side, 0u) << "sub-face " << s;
            for (uint32_t c = 0; c < side * side; ++c)
                ASSERT_NE(refinement->cellQuad[refinement->subfaceCellBase[s] + c], UINT32_MAX) << "sub-face " << s;
        }
    }
}

// Tag edits rewrite the uniform tables in place (updateUniformTags): the refined points equal
// those of tables built from scratch for the edited cage, and the drawn quads follow the holes.
TEST(SchemeEvaluation, UniformTagEditsInPlaceMatchNewTables) {
    std::vector<std::pair<std::string, Cage>> cages = {{"mixed grid", test::makeMixedGrid()},
                                                       {"subdivided cube", test::makeSubdividedCube(4)}};
    for (const char* extra : {"catmark_nonman_edges", "catmark_chaikin0", "catmark_car"})
        if (fs::exists(test::sharedShapesDir() / (std::string(extra) + ".obj")))
            cages.push_back({extra, loadCage(test::sharedShapesDir() / (std::string(extra) + ".obj"))});
    for (const auto& [name, cage] : cages) {
        SCOPED_TRACE(name);
        auto planned = plan(cage, 2);
        PlannedCage& p = *planned->planned;
        const uint32_t levels = 3;
        Result<UniformRefinement> refinement = buildUniformRefinement(p, levels);
        ASSERT_TRUE(refinement.ok()) << refinement.error().message;
        std::vector<glm::vec3> original;
        applyUniformRefinement(*refinement, p.cage().positions, original);
        bool changedSome = false;
        const Topology& topology = p.topology();
        // An edge between two interior vertices (a crease there changes the surface), from a third in.
        auto interior = [&](uint32_t v) { return topology.vertexFaceCount(v) == topology.vertexEdgeCount(v); };
        uint32_t e = topology.edgeCount() / 3;
        while (e + 1 < topology.edgeCount() &&
               !(topology.edgeFaceCount(e) == 2 && interior(topology.edgeVertices[2 * e]) && interior(topology.edgeVertices[2 * e + 1])))
            ++e;
        const uint32_t v = topology.edgeVertices[2 * e + 1], f = p.cage().faceCount() / 2;
        const uint32_t a = topology.edgeVertices[2 * e], b = topology.edgeVertices[2 * e + 1];
        std::vector<std::pair<std::string, std::function<Result<EditReport>()>>> edits = {
            {"semi-sharp crease", [&] { return p.setEdgeSharpness(a, b, 1.6f); }},
            {"infinitely sharp", [&] { return p.setEdgeSharpness(a, b, kInfiniteSharpness); }},
            {"corner", [&] { return p.setVertexSharpness(v, 0.7f); }},
            {"hole", [&] { return p.setHole(f, true); }},
            {"crease cleared", [&] { return p.setEdgeSharpness(a, b, 0.0f); }},
            {"hole filled", [&] { return p.setHole(f, false); }},
            {"chaikin", [&] { return p.setCreaseMethod(CreaseMethod::Chaikin); }},
        };
        for (auto& [label, edit] : edits) {
            SCOPED_TRACE(label);
            Result<EditReport> report = edit();
            ASSERT_TRUE(report.ok()) << report.error().message;
            std::vector<uint32_t> subfaces = report->updatedSubfaceList;
            for (uint32_t face : report->replannedFaceList)
                for (uint32_t s = p.firstSubface(face); s < p.firstSubface(face + 1); ++s) subfaces.push_back(s);
            ASSERT_TRUE(updateUniformTags(*refinement, p, subfaces).ok());
            Result<UniformRefinement> fresh = buildUniformRefinement(p, levels);
            ASSERT_TRUE(fresh.ok());
            std::vector<glm::vec3> inPlace, rebuilt;
            applyUniformRefinement(*refinement, p.cage().positions, inPlace);
            applyUniformRefinement(*fresh, p.cage().positions, rebuilt);
            ASSERT_EQ(inPlace.size(), rebuilt.size());
            float worst = 0.0f;
            for (size_t i = 0; i < inPlace.size(); ++i) worst = std::max(worst, glm::length(inPlace[i] - rebuilt[i]));
            EXPECT_LT(worst / computeBounds(cage).diagonal(), 1e-6f) << "the tables updated in place refine differently";
            EXPECT_EQ(refinement->drawnQuads, fresh->drawnQuads);
            changedSome |= inPlace != original;
        }
        EXPECT_TRUE(changedSome) << "the edits changed nothing";
    }
}

TEST(SchemeEvaluation, UniformConvergesAsTheLevelGrows) {
    std::vector<std::pair<std::string, Cage>> cages = {{"subdivided cube", test::makeSubdividedCube()},
                                                       {"mixed grid", test::makeMixedGrid()}};
    Cage creased = test::makeSubdividedCube();
    creased.setEdgeSharpness(creased.faceBegin(0)[0], creased.faceBegin(0)[1], kInfiniteSharpness);
    creased.setEdgeSharpness(creased.faceBegin(0)[1], creased.faceBegin(0)[2], kInfiniteSharpness);
    cages.push_back({"infinitely creased cube", creased});
    for (const auto& [name, cage] : cages) {
        SCOPED_TRACE(name);
        auto planned = plan(cage);
        double previousMax = 1e30, previousRms = 1e30, firstMax = 0.0;
        for (uint32_t level = 1; level <= 5; ++level) {
            SchemeSettings settings;
            settings.options = {{"level", std::to_string(level)}};
            SchemeInstance scheme = buildScheme("uniform", *planned->planned, settings);
            const ErrorStats e = errorOf(scheme, *planned->planned, 40);  // not a multiple of 2^level
            std::printf("[ uniform ] %s level %u: max %.3e rms %.3e normal %.2f deg\n", name.c_str(), level, e.maxRelError,
                        e.rmsRelError, e.maxNormalDegrees);
            // A refined mesh approaches its limit about fourfold per level where the surface is
            // regular (the RMS); near extraordinary vertices, crease ends included, the
            // parameterisation converges more slowly (the subdominant eigenvalue), and that is
            // where the maximum sits.
            EXPECT_LT(e.maxRelError, previousMax / 1.5) << "level " << level;
            EXPECT_LT(e.rmsRelError, previousRms / 2.5) << "level " << level;
            if (level == 1) firstMax = e.maxRelError;
            previousMax = e.maxRelError;
            previousRms = e.rmsRelError;
        }
        EXPECT_LT(previousMax, firstMax / 15);
        EXPECT_LT(previousMax, 1e-3);
    }
}

// ---- The heat-map scale -------------------------------------------------------------------

TEST(SchemeHeatMap, FixedLogarithmicScaleClampsAtBothEnds) {
    EXPECT_EQ(heatColorSrgb(0.0), heatColorSrgb(kHeatLow));
    EXPECT_EQ(heatColorSrgb(kHeatLow / 100), heatColorSrgb(kHeatLow));
    EXPECT_EQ(heatColorSrgb(1.0), heatColorSrgb(kHeatHigh));
    EXPECT_NE(heatColorSrgb(1e-5), heatColorSrgb(1e-4));
    // Red grows with the error across the upper half of the scale; blue dominates the bottom.
    EXPECT_GT(heatColorSrgb(kHeatHigh).r, 0.8f);
    EXPECT_GT(heatColorSrgb(kHeatLow).b, heatColorSrgb(kHeatLow).r);
    float previousRed = 0.0f;
    for (double e = 1e-4; e <= 1e-3; e *= 1.2) {
        EXPECT_GE(heatColorSrgb(e).r, previousRed);
        previousRed = heatColorSrgb(e).r;
    }
}
