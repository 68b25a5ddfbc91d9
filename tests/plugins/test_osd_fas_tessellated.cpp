// osd-fas's tessellator path (plugins/osd-fas/osd_fas_gpu.h): Far's stencils in a compute pass,
// one patch primitive per Far patch. What the evaluation stage writes is checked against the
// CPU evaluation of the same patch, the edges of neighbouring patches against each other (no
// T-junctions, with OpenSubdiv's transition split), and the triangles the tessellator made
// (pipeline statistics) against the count the scheme reports.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <tuple>

#include "../../plugins/osd-fas/osd_fas_gpu.h"
#include "camera.h"
#include "mesh/obj_io.h"
#include "module_shader_code.h"
#include "offscreen_target.h"
#include "render_test_support.h"
#include "tess_patch_pass.h"
#include "test_cages.h"
#include "test_support.h"
#include "vk_check.h"
#include "vk_commands.h"

namespace qp {
namespace {

using namespace OpenSubdiv;

std::vector<std::pair<std::string, Cage>> closedCages() {
    std::vector<std::pair<std::string, Cage>> cages;
    Cage creased = test::makeSubdividedCube(3);
    const uint32_t* quad = creased.faceBegin(4);
    creased.setEdgeSharpness(quad[0], quad[1], 1.6f);
    creased.setEdgeSharpness(quad[1], quad[2], 0.7f);
    cages.push_back({"creased cube", creased});
    cages.push_back({"cube", test::makeCube()});
    for (const char* name : {"catmark_pyramid", "catmark_torus_creases0", "catmark_pawn"}) {
        const std::filesystem::path path = test::sharedShapesDir() / (std::string(name) + ".obj");
        if (!std::filesystem::exists(path)) continue;
        Result<Cage> cage = loadObj(path.string());
        if (cage) cages.push_back({name, std::move(*cage)});
    }
    return cages;
}

struct Drawn {
    std::vector<TessCaptureRecord> records;
    uint32_t overflow = 0;
    uint64_t triangles = 0;  // clipping invocations
};

// Uploads the patches, writes the cage, applies the stencils on the device and draws once with
// capture on.
Drawn drawPatches(const VulkanContext& ctx, const FasPatches& patches, const Cage& cage, TessPatchSettings settings) {
    Drawn out;
    Result<TessPatchPass> pass = createTessPatchPass(
        ctx, VK_NULL_HANDLE, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_D32_SFLOAT,
        {moduleShaderCode("tess_patch.vert"), moduleShaderCode("osd_fas.tesc"), moduleShaderCode("osd_fas.tese"),
         moduleShaderCode("osd_fas_stencils.comp")});
    EXPECT_TRUE(pass.ok()) << (pass ? "" : pass.error().message);
    if (!pass) return out;
    FasGpuData data = packFasPatches(patches, cage.vertexCount());
    EXPECT_TRUE(uploadTessPatches(ctx, *pass, data.words.data(), data.words.size() * 4, data.header.patchCount).ok());
    const std::vector<float> positions = fasCagePositions(cage.positions);
    writeTessPatchData(*pass, positions.data(), positions.size() * 4, size_t(data.header.cageOffset) * 4);
    EXPECT_TRUE(enableTessCapture(ctx, *pass, 3'000'000).ok());
    Result<OffscreenTarget> target = createOffscreenTarget(ctx, 256, 256, VK_FORMAT_R8G8B8A8_UNORM);
    EXPECT_TRUE(target.ok());

    VkQueryPoolCreateInfo queryInfo{};
    queryInfo.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
    queryInfo.queryType = VK_QUERY_TYPE_PIPELINE_STATISTICS;
    queryInfo.queryCount = 1;
    queryInfo.pipelineStatistics = VK_QUERY_PIPELINE_STATISTIC_CLIPPING_INVOCATIONS_BIT;
    VkQueryPool queries = VK_NULL_HANDLE;
    EXPECT_EQ(vkCreateQueryPool(ctx.device, &queryInfo, nullptr, &queries), VK_SUCCESS);

    const Bounds bounds = computeBounds(cage);
    const RenderCamera camera = frameBounds(bounds.min, bounds.max, 1.0f);
    DrawView view;
    view.viewProjection = viewProjection(camera);
    view.eye = camera.eye;
    view.pixelsPerUnit = 0.5f * 256.0f * std::abs(view.viewProjection[1][1]);
    settings.capture = true;
    EXPECT_TRUE(submitAndWait(ctx, [&](VkCommandBuffer cmd) {
                    vkCmdResetQueryPool(cmd, queries, 0, 1);
                    recordTessPrepare(cmd, *pass, data.header.pointCount);
                    vkCmdBeginQuery(cmd, queries, 0, 0);
                    recordTessPatches(cmd, *pass, renderTarget(*target), view, settings);
                    vkCmdEndQuery(cmd, queries, 0);
                }).ok());
    EXPECT_EQ(vkGetQueryPoolResults(ctx.device, queries, 0, 1, sizeof(out.triangles), &out.triangles, sizeof(out.triangles),
                                    VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
              VK_SUCCESS);
    out.records = readTessCapture(*pass, &out.overflow);
    vkDestroyQueryPool(ctx.device, queries, nullptr);
    destroyOffscreenTarget(ctx, *target);
    destroyTessPatchPass(ctx, *pass);
    return out;
}

bool onEdge(float t) { return t == 0.0f || t == 1.0f; }

// Far's edge e (0: v=0, 1: u=1, 2: v=1, 3: u=0) holds (u, v)?
bool onFarEdge(uint32_t e, float u, float v) {
    return e == 0 ? v == 0.0f : e == 1 ? u == 1.0f : e == 2 ? v == 1.0f : u == 0.0f;
}

// Crack-freeness, from the evaluated vertices alone: (1) every vertex inside a patch edge (not
// a corner, not on an edge without a neighbour) coincides with a vertex of another patch, so
// neither side cuts a shared edge where the other does not; (2) every transition edge has a
// vertex at its midpoint, where the finer neighbours' corner is. Returns the vertices checked.
size_t expectNoCracks(const FasPatches& patches, const std::vector<TessCaptureRecord>& records, double tolerance,
                      const std::string& what) {
    using Cell = std::tuple<long, long, long>;
    auto cellOf = [&](const float p[3]) {
        return Cell{std::lround(p[0] / tolerance), std::lround(p[1] / tolerance), std::lround(p[2] / tolerance)};
    };
    std::map<Cell, std::vector<const TessCaptureRecord*>> cells;
    for (const TessCaptureRecord& r : records)
        if (onEdge(r.u) || onEdge(r.v)) cells[cellOf(r.position)].push_back(&r);
    std::vector<uint8_t> midpointSeen(patches.layout.size() * 4, 0);
    size_t checked = 0;
    for (const TessCaptureRecord& r : records) {
        const Far::PatchParam param = patches.table->GetPatchParam(patches.layout[r.patch].handle);
        for (uint32_t e = 0; e < 4; ++e)
            if (onFarEdge(e, r.u, r.v) && (e % 2 == 0 ? r.u == 0.5f : r.v == 0.5f)) midpointSeen[4 * r.patch + e] = 1;
        if (onEdge(r.u) == onEdge(r.v)) continue;  // a corner, or inside
        const uint32_t e = r.v == 0.0f ? 0 : r.u == 1.0f ? 1 : r.v == 1.0f ? 2 : 3;
        // Boundary bits: a cage boundary, an infinitely sharp crease (it has a neighbour, but
        // leave it out with the boundaries) or a single-crease patch's crease (it has one too).
        if (param.GetBoundary() & (1u << e)) continue;
        const Cell c = cellOf(r.position);
        bool matched = false;
        for (long dx = -1; dx <= 1 && !matched; ++dx)
            for (long dy = -1; dy <= 1 && !matched; ++dy)
                for (long dz = -1; dz <= 1 && !matched; ++dz) {
                    auto it = cells.find({std::get<0>(c) + dx, std::get<1>(c) + dy, std::get<2>(c) + dz});
                    if (it == cells.end()) continue;
                    for (const TessCaptureRecord* other : it->second) {
                        const double d = glm::length(glm::dvec3(other->position[0] - r.position[0], other->position[1] - r.position[1],
                                                                other->position[2] - r.position[2]));
                        if (other->patch != r.patch && d <= tolerance) matched = true;
                    }
                }
        ++checked;
        if (!matched) {
            ADD_FAILURE() << what << ": patch " << r.patch << " edge " << e << " vertex (" << r.u << ", " << r.v
                          << ") meets no vertex of a neighbour";
            return checked;
        }
    }
    for (size_t i = 0; i < patches.layout.size(); ++i) {
        const uint32_t transitions = patches.table->GetPatchParam(patches.layout[i].handle).GetTransition();
        for (uint32_t e = 0; e < 4; ++e)
            if ((transitions & (1u << e)) && !midpointSeen[4 * i + e]) {
                ADD_FAILURE() << what << ": patch " << i << " has no vertex at the midpoint of its transition edge " << e;
                return checked;
            }
    }
    return checked;
}

}  // namespace

// The edge points are the refined vertices at the patch's corners: on a regular B-spline patch
// those are its control vertices 5, 6, 10 and 9.
TEST(OsdFasTessellated, EdgePointsAreThePatchCornersRefinedVertices) {
    std::vector<std::pair<std::string, Cage>> cages = closedCages();
    cages.push_back({"mixed grid", test::makeMixedGrid()});
    uint32_t totalTransitions = 0;
    for (const auto& [name, cage] : cages) {
        SCOPED_TRACE(name);
        Result<FasPatches> patches = buildFasPatches(cage, 6, 1);
        ASSERT_TRUE(patches.ok()) << patches.error().message;
        uint32_t regular = 0, transitions = 0;
        for (const FasPatchLayout& p : patches->layout) {
            const Far::PatchParam param = patches->table->GetPatchParam(p.handle);
            for (uint32_t e = 0; e < 4; ++e) {
                for (uint32_t k : {0u, 2u}) ASSERT_LT(p.edgePoints[e][k], uint32_t(patches->stencils->GetNumStencils()));
                if (!(param.GetTransition() & (3u << e)) && !(e == 3 && (param.GetTransition() & 9u))) {
                    EXPECT_EQ(p.edgePoints[e][2], p.edgePoints[(e + 1) % 4][0]) << "edges " << e << " and " << e + 1 << " share a corner";
                }
                if (param.GetTransition() & (1u << e)) {
                    ++transitions;
                    EXPECT_LT(p.edgePoints[e][1], uint32_t(patches->stencils->GetNumStencils()));
                } else {
                    EXPECT_EQ(p.edgePoints[e][1], kNoEdgeMidpoint);
                }
            }
            const bool bspline = patches->table->GetPatchArrayDescriptor(p.handle.arrayIndex).GetType() ==
                                 Far::PatchDescriptor::REGULAR;
            if (!bspline || param.GetBoundary() || param.GetTransition()) continue;
            ++regular;
            const Far::ConstIndexArray cvs = patches->table->GetPatchVertices(p.handle);
            const int corner[4] = {5, 6, 10, 9};
            for (uint32_t e = 0; e < 4; ++e) {
                EXPECT_EQ(p.edgePoints[e][0], uint32_t(cvs[corner[e]])) << "edge " << e;
                EXPECT_EQ(p.edgePoints[e][2], uint32_t(cvs[corner[(e + 1) % 4]])) << "edge " << e;
            }
        }
        EXPECT_GT(regular, 0u);
        totalTransitions += transitions;
    }
    EXPECT_GT(totalTransitions, 0u);
}

TEST(OsdFasTessellated, PatchesMatchTheCpuMeetWithoutCracksAndCountTheirTriangles) {
    Result<VulkanContext> context = test::createTestContext();
    ASSERT_TRUE(context.ok()) << context.error().message;
    VulkanContext& ctx = *context;
    ASSERT_TRUE(ctx.features.pipelineStatisticsQuery);
    for (const auto& [name, cage] : closedCages()) {
        Result<FasPatches> patches = buildFasPatches(cage, 6, 1);
        ASSERT_TRUE(patches.ok()) << patches.error().message;
        updateFasPoints(*patches, cage.positions);
        const double diagonal = computeBounds(cage).diagonal();
        size_t edgeVertices = 0;
        for (TessPatchSettings settings : {TessPatchSettings{1, 8.0f}, TessPatchSettings{3, 8.0f}, TessPatchSettings{8, 8.0f},
                                           TessPatchSettings{0, 6.0f}, TessPatchSettings{0, 1.5f}}) {
            const std::string what =
                name + (settings.uniformFactor ? " factor " + std::to_string(settings.uniformFactor)
                                               : " adaptive " + std::to_string(settings.pixelsPerSegment) + " px");
            settings.largestLevel = settings.uniformFactor ? settings.uniformFactor + 1 : 64;
            const Drawn drawn = drawPatches(ctx, *patches, cage, settings);
            ASSERT_EQ(drawn.overflow, 0u) << what;
            ASSERT_FALSE(drawn.records.empty()) << what;
            double worst = 0.0;
            for (const TessCaptureRecord& r : drawn.records) {
                const FasSample cpu = evaluateFasPatch(*patches, r.patch, r.u, r.v);
                worst = std::max(worst, double(glm::length(glm::vec3(r.position[0], r.position[1], r.position[2]) - cpu.position)) /
                                            diagonal);
            }
            EXPECT_LT(worst, 2e-6) << what << ": GPU against CPU";
            edgeVertices += expectNoCracks(*patches, drawn.records, 1e-5 * diagonal, what);
            if (settings.uniformFactor) {
                EXPECT_EQ(drawn.triangles, fasUniformTriangles(*patches, settings.uniformFactor)) << what;
            }
            if (HasFailure()) break;
        }
        EXPECT_GT(edgeVertices, 0u) << name;
    }
    EXPECT_EQ(validationMessageCount(ctx), 0u) << test::describeMessages(ctx);
    destroyContext(ctx);
}

}  // namespace qp
