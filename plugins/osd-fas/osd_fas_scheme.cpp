// `osd-fas`: OpenSubdiv's feature-adaptive patches, the baseline B16 compares against
// (osd_fas_patches.h has the math). Two paths, chosen with path=auto|tess|cpu as for plans
// (auto: cpu on a CPU device, tess on a GPU):
//   - tess: OpenSubdiv's GPU path, one patch primitive per Far patch through the tessellator;
//     update() writes the cage's positions and the next record() applies Far's stencils in a
//     compute pass first (osd_fas_gpu.h); the CPU's copy of the points, which only evaluate()
//     reads, is brought up to date by the first evaluate() after a change, so a frame costs
//     what OpenSubdiv's GPU path costs;
//   - cpu: every patch tessellated on all cores at OpenSubdiv's uniform levels, drawn with
//     MeshPass; update() applies the stencils and tessellates, as a moving cage would need.
//
// Displacement: the patches' surface (evaluateFas) on a grid of at least the tessellation
// factor and the tiles' required factor, displaced along its own normal and made watertight
// through a DisplacedDrawing (displaced_drawing.h: a dab re-displaces only what it reached).
//
// Culling (DrawView::cull) is per Far patch on both paths while undisplaced (the tessellator
// draws the kept patches, the CPU path their index ranges), per sub-face on the displaced mesh
// (frustum only, boxes grown by the tile's largest |D|). The bounds come from the patches'
// control points on the CPU (Far's stencils applied there, also on the tess path, when a frame
// first needs them after an update): a B-spline patch, its phantoms beyond boundary or
// infinitely sharp edges made explicit, as its Bézier patch (box, tcone, ncone, pplane); a
// single-crease patch as the infinitely sharp patch plus up to half its second differences
// across the crease (a box, no cone, as the plans' semi-sharp leaves); a Gregory-basis end cap
// as a Gregory leaf (patch_cull_set.h). Back-patch tests only on a closed, outward cage.
#include <array>
#include <chrono>
#include <cmath>
#include <mutex>
#include <optional>

#include <glm/vec3.hpp>

#include "displaced_drawing.h"
#include "draw_path.h"
#include "mesh/closed_surface.h"
#include "mesh_pass.h"
#include "module_shader_code.h"
#include "osd_fas_gpu.h"
#include "osd_fas_patches.h"
#include "scheme_api.h"
#include "scheme_culling.h"
#include "scheme_support.h"
#include "tess_patch_pass.h"

namespace qp {
namespace {

enum class FasPath { Auto, Tessellated, Cpu };

Result<FasPath> fasPathOption(const SchemeSettings& settings) {
    const std::string* path = settings.option("path");
    if (!path || *path == "auto") return FasPath::Auto;
    if (*path == "tess") return FasPath::Tessellated;
    if (*path == "cpu") return FasPath::Cpu;
    return Error{"osd-fas: unknown path '" + *path + "'; use auto, tess (patches through the tessellator) or cpu"};
}

// Far patch `patch` as culling leaves relative to `origin` (the points in double, relative first).
void addFarPatchLeaves(const FasPatches& patches, uint32_t patch, const glm::vec3& origin, PatchCullLeaves& leaves) {
    using namespace OpenSubdiv;
    const Far::PatchTable& table = *patches.table;
    const Far::PatchTable::PatchHandle& handle = patches.layout[patch].handle;
    const Far::ConstIndexArray cvs = table.GetPatchVertices(handle);
    auto point = [&](int k) { return glm::vec3(patches.points[size_t(cvs[k])] - glm::dvec3(origin)); };
    switch (table.GetPatchArrayDescriptor(handle.arrayIndex).GetType()) {
    case Far::PatchDescriptor::REGULAR: {
        BicubicPoints bspline;  // Far's REGULAR order is patch_basis.h's
        for (int k = 0; k < 16; ++k) bspline[size_t(k)] = point(k);
        const uint32_t boundary = uint32_t(table.GetPatchParam(handle).GetBoundary());
        // A single-crease patch marks its crease edge as its boundary (osd_fas_patches.cpp).
        const float sharpness = table.GetSingleCreasePatchSharpnessValue(handle);
        if (sharpness > 0.0f && sharpness < 10.0f) addSemiSharpCreaseLeaf(leaves, bspline, 0, boundary);
        else addBezierLeaf(leaves, bsplineToBezier(withPhantoms(bspline, boundary)), false);
        break;
    }
    case Far::PatchDescriptor::GREGORY_BASIS: {
        std::array<glm::vec3, 20> gregory;  // GREGORY_BASIS order is patch_basis.h's
        for (int k = 0; k < 20; ++k) gregory[size_t(k)] = point(k);
        addGregoryLeaf(leaves, gregory, false);
        break;
    }
    default:  // buildFasPatches asks for the two above only; another kind is never culled
        addConelessBox(leaves, CullBox{glm::vec3(-INFINITY), glm::vec3(INFINITY)});
    }
}

class OsdFasScheme final : public Scheme {
public:
    SupportReport support(const CageFeatures&, const SchemeSettings& settings) const override {
        SupportReport report;
        Result<FasPath> path = fasPathOption(settings);
        if (!path) report.refusals.push_back(path.error().message);
        if (settings.adaptivePixels > 0.0f && path && *path == FasPath::Cpu)
            report.approximations.push_back("osd-fas path=cpu has no screen-adaptive tessellation: it uses factor 16");
        if (settings.adaptivePixels > 0.0f && path && *path == FasPath::Auto)
            report.approximations.push_back("osd-fas path=auto draws on the CPU on a CPU device, without screen-adaptive "
                                            "tessellation (factor 16 there); path=tess has it");
        for (const auto& [key, value] : settings.options)
            if (key != "path") report.approximations.push_back("osd-fas ignores the unknown option '" + key + "'");
        return report;
    }

    Status build(const PlannedCage& planned, const SchemeSettings& settings) override {
        planned_ = &planned;
        settings_ = settings;
        Result<FasPath> path = fasPathOption(settings);
        if (!path) return path.error();
        requestedPath_ = *path;
        factor_ = settings.adaptivePixels > 0.0f ? 16u : settings.tessFactor;
        // The CPU layout only where it may be drawn: at factor 64 it holds 4,225 points a patch.
        Result<FasPatches> patches =
            buildFasPatches(planned.cage(), settings.planDepth, requestedPath_ == FasPath::Tessellated ? 1u : factor_);
        if (!patches) return patches.error();
        patches_ = std::move(*patches);
        std::vector<std::pair<uint32_t, uint32_t>> pairs;  // a Far patch lies in its ptex face, our sub-face
        std::vector<std::vector<uint32_t>> atPoint;        // per refined vertex: the patches with it on an edge
        patchFirstIndex_.assign(1, 0);
        for (uint32_t p = 0; p < patches_.layout.size(); ++p) {
            pairs.push_back({uint32_t(patches_.table->GetPatchParam(patches_.layout[p].handle).GetFaceId()), p});
            patchFirstIndex_.push_back(patches_.layout[p].firstIndex + patches_.layout[p].indexCount);
            for (const auto& edge : patches_.layout[p].edgePoints)
                for (uint32_t point : edge)
                    if (point != kNoEdgeMidpoint) {
                        if (point >= atPoint.size()) atPoint.resize(point + 1);
                        atPoint[point].push_back(p);
                    }
        }
        // Neighbours (scheme_culling.h) meet through shared refined vertices (a transition edge
        // lists the finer neighbours' corners). The displaced mesh culls by the frustum only.
        culling_ = PatchCulling{patchCover(planned.subfaceCount(), uint32_t(patches_.layout.size()), std::move(pairs)),
                                closedOutwardSurface(planned.cage(), planned.topology()),
                                adjacencyOfGroups(uint32_t(patches_.layout.size()), atPoint), {}};
        return success();
    }

    Status createGpu(const GpuContext& gpu) override {
        ctx_ = gpu.vulkan;
        tessellated_ = requestedPath_ == FasPath::Tessellated ||
                       (requestedPath_ == FasPath::Auto && resolveDrawPath(DrawPath::Auto, *ctx_) == DrawPath::Tessellated);
        if (Status pass = createSchemeMeshPass(pass_, gpu); !pass) return pass;
        if (!tessellated_) return success();
        Result<TessPatchPass> tess = createTessPatchPass(
            *ctx_, gpu.cache, gpu.colorFormat, gpu.depthFormat,
            {moduleShaderCode("tess_patch.vert"), moduleShaderCode("osd_fas.tesc"), moduleShaderCode("osd_fas.tese"),
             moduleShaderCode("osd_fas_stencils.comp")});
        if (!tess) return Error{"osd-fas: " + tess.error().message + " (use --option path=cpu)"};
        tess_ = *tess;
        haveTess_ = true;
        gpuData_ = packFasPatches(patches_, planned_->cage().vertexCount());
        if (Status uploaded = uploadTessPatches(*ctx_, tess_, gpuData_.words.data(), gpuData_.words.size() * 4,
                                                gpuData_.header.patchCount);
            !uploaded)
            return uploaded;
        gpuData_.words = {};  // on the device now
        // What record() reports at a uniform factor: the levels depend on the patches only.
        patchTriangles_.clear();
        if (settings_.adaptivePixels <= 0.0f)
            for (const FasPatchLayout& p : patches_.layout) {
                float outer[4];
                fasUniformLevels(patches_.table->GetPatchParam(p.handle), std::min(settings_.tessFactor, 64u), outer);
                patchTriangles_.push_back(quadTessTriangles(outer));
            }
        return success();
    }

    Status update() override {
        culling_.bounds.reset();
        if (haveTess_ && !displacement_) {
            cpuPointsStale_ = true;
            destroyDisplacedDrawing(displaced_);
            const std::vector<float> packed = fasCagePositions(planned_->cage().positions);
            writeTessPatchData(tess_, packed.data(), packed.size() * sizeof(float),
                               size_t(gpuData_.header.cageOffset) * 4);
            stencilsPending_ = true;
            return success();
        }
        updateFasPoints(patches_, planned_->cage().positions);
        cpuPointsStale_ = false;
        if (!ctx_) return success();
        if (displacement_) {
            if (Status cleared = replaceMesh(*ctx_, mesh_, {}, {}); !cleared) return cleared;  // drawn instead
            const uint32_t factor = displacedGridFactor(*planned_, *displacement_, factor_);
            return buildDisplacedDrawing(displaced_, *ctx_, *this, *planned_, *displacement_, factor);
        }
        destroyDisplacedDrawing(displaced_);
        std::vector<glm::vec3> positions, normals;
        tessellateFas(patches_, positions, normals);
        return replaceMesh(*ctx_, mesh_, meshVertices(positions, normals), patches_.indices);
    }

    Result<DrawStats> record(VkCommandBuffer cmd, const RenderTarget& target, const DrawView& view) override {
        DrawStats stats;
        const uint32_t patchCount = uint32_t(patches_.layout.size());
        if (view.cull != CullMethod::None && !culling_.bounds) refreshCpuPoints(stats);
        const PatchBounds bounds{patchCount, [this](uint32_t p) { return patchAnchor(p); },
                                 [this](uint32_t p, const glm::vec3& origin, PatchCullLeaves& leaves) {
                                     addFarPatchLeaves(patches_, p, origin, leaves);
                                 }};
        if (displacement_) {
            const std::vector<uint32_t> culled = cullSubfacesForView(culling_, bounds, displacement_, view, stats);
            recordDisplacedParts(cmd, pass_, target, view, displaced_, culled, stats);
            return stats;
        }
        const std::vector<uint32_t> culled = cullPatchesForView(culling_, bounds, view, stats);
        stats.patches = patchCount - culled.size();
        if (haveTess_) {
            if (stencilsPending_) recordTessPrepare(cmd, tess_, gpuData_.header.pointCount);
            stencilsPending_ = false;
            const bool adaptive = settings_.adaptivePixels > 0.0f;
            const uint32_t factor = adaptive ? 0u : std::min(settings_.tessFactor, 64u);
            // A transition edge at factor F may get 2 ceil(F / 2) segments.
            recordTessPatches(cmd, tess_, target, view, {factor, settings_.adaptivePixels, capture_, adaptive ? 64u : factor + 1},
                              culled);
            for (uint64_t triangles : patchTriangles_) stats.triangles += triangles;
            for (uint32_t p : culled)
                if (p < patchTriangles_.size()) stats.triangles -= patchTriangles_[p];
            stats.drawnBy = DrawnBy::Tessellator;
            return stats;
        }
        const std::vector<IndexRange> parts = keptIndexRanges(patchFirstIndex_, culled);
        recordMeshParts(cmd, pass_, target, view, mesh_, culled.empty() ? nullptr : &parts, stats);
        return stats;
    }

    Status setDisplacement(const Displacement* displacement) override {
        culling_.bounds.reset();
        displacement_ = displacementToDraw(displacement);
        return success();
    }

    Status displacementChanged(std::span<const uint32_t> samples) override {
        culling_.bounds.reset();  // the margins follow |D|
        return updateDisplacedDrawing(displaced_, samples);
    }

    void evaluate(std::span<const SampleRequest> requests, std::span<SurfacePoint> out) const override {
        {
            // Called from several threads at once (scheme_support.h): the first brings the
            // points up to date (all cores), the others wait for it.
            std::lock_guard<std::mutex> lock(cpuPointsMutex_);
            if (cpuPointsStale_) {
                updateFasPoints(patches_, planned_->cage().positions);
                cpuPointsStale_ = false;
            }
        }
        for (size_t i = 0; i < requests.size(); ++i) {
            const FasSample s = evaluateFas(patches_, requests[i].subface, requests[i].u, requests[i].v);
            out[i] = surfacePoint(s.position, s.du, s.dv);
        }
    }

    // The CPU path's own mesh: the triangles it draws, bit for bit. The tess path keeps no host
    // tessellation at its factor, so the same patches are laid out again at it (F / 2^d segments
    // at depth d, as fasUniformLevels gives the tessellator): the same lattice points, the
    // triangles of a transition edge and of the tessellator's outer ring joined differently.
    Result<PatchTriangles> drawnPatches() const override {
        // Displaced, culling is per sub-face; the tessellator's screen-adaptive levels follow the view.
        if (displacement_ || (haveTess_ && settings_.adaptivePixels > 0.0f)) return PatchTriangles{};
        std::optional<FasPatches> laidOut;
        if (haveTess_) {
            Result<FasPatches> built = buildFasPatches(planned_->cage(), settings_.planDepth, std::min(settings_.tessFactor, 64u));
            if (!built) return built.error();
            laidOut = std::move(*built);
            updateFasPoints(*laidOut, planned_->cage().positions);
        }
        const FasPatches& drawn = laidOut ? *laidOut : patches_;
        PatchTriangles out;
        std::vector<glm::vec3> normals;
        tessellateFas(drawn, out.positions, normals);
        out.patchOfVertex.resize(out.positions.size());
        for (uint32_t p = 0; p < drawn.layout.size(); ++p)
            std::fill_n(out.patchOfVertex.begin() + drawn.layout[p].firstVertex, drawn.layout[p].vertexCount, p);
        out.indices = drawn.indices;
        out.patchCount = uint32_t(drawn.layout.size());
        return out;
    }

    SchemeStats stats() const override {
        SchemeStats stats;
        stats.patches = patches_.layout.size();
        stats.singleCreasePatches = patches_.singleCreasePatches;
        stats.controlPoints = uint64_t(patches_.stencils->GetNumStencils()) - planned_->cage().vertexCount();
        stats.gpuBytes = mesh_.vertices.size + mesh_.indices.size + displaced_.gpu.vertices.size + displaced_.gpu.indices.size +
                         tess_.patchData.size;
        return stats;
    }

    void destroyGpu() override {
        if (!ctx_) return;
        if (mesh_.indexCount) destroyMesh(*ctx_, mesh_);
        destroyDisplacedDrawing(displaced_);
        destroyMeshPass(*ctx_, pass_);
        if (haveTess_) destroyTessPatchPass(*ctx_, tess_);
        haveTess_ = false;
        ctx_ = nullptr;
    }

private:
    // The CPU's points for the culling bounds: on the tess path only the device has them after
    // update(); their time counts as the frame's culling.
    void refreshCpuPoints(DrawStats& stats) const {
        const auto start = std::chrono::steady_clock::now();
        std::lock_guard<std::mutex> lock(cpuPointsMutex_);
        if (!cpuPointsStale_) return;
        updateFasPoints(patches_, planned_->cage().positions);
        cpuPointsStale_ = false;
        stats.cullMilliseconds += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }

    glm::vec3 patchAnchor(uint32_t patch) const {
        const OpenSubdiv::Far::ConstIndexArray cvs = patches_.table->GetPatchVertices(patches_.layout[patch].handle);
        return glm::vec3(patches_.points[size_t(cvs[0])]);
    }

    const PlannedCage* planned_ = nullptr;
    SchemeSettings settings_;
    FasPath requestedPath_ = FasPath::Auto;
    bool tessellated_ = false;  // resolved in createGpu
    mutable FasPatches patches_;     // mutable: evaluate() refreshes the CPU points on the tess path
    mutable std::mutex cpuPointsMutex_;
    mutable bool cpuPointsStale_ = true;
    uint32_t factor_ = 8;
    std::vector<uint64_t> patchTriangles_;   // path=tess at a uniform factor: per patch
    std::vector<uint32_t> patchFirstIndex_;  // path=cpu: per patch its first index in the mesh; the total last
    PatchCulling culling_;
    const Displacement* displacement_ = nullptr;
    const VulkanContext* ctx_ = nullptr;
    MeshPass pass_;
    GpuMesh mesh_;                // undisplaced, path=cpu
    DisplacedDrawing displaced_;  // with a displacement, either path
    TessPatchPass tess_;          // path=tess
    bool haveTess_ = false;
    FasGpuData gpuData_;          // its header (the words are uploaded and dropped)
    bool stencilsPending_ = false;
    bool capture_ = false;
};

}  // namespace
}  // namespace qp

QUADPLAN_EXPORT_SCHEME("osd-fas",
                       "OpenSubdiv feature-adaptive patches: B-spline and single-crease patches, Gregory-basis end "
                       "caps, one primitive per patch",
                       qp::OsdFasScheme)
