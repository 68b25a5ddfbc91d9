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
#include <mutex>

#include "displaced_drawing.h"
#include "draw_path.h"
#include "mesh_pass.h"
#include "module_shader_code.h"
#include "osd_fas_gpu.h"
#include "osd_fas_patches.h"
#include "scheme_api.h"
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
        return success();
    }

    Status createGpu(const GpuContext& gpu) override {
        ctx_ = gpu.vulkan;
        tessellated_ = requestedPath_ == FasPath::Tessellated ||
                       (requestedPath_ == FasPath::Auto && resolveDrawPath(DrawPath::Auto, *ctx_) == DrawPath::Tessellated);
        Result<MeshPass> pass = createMeshPass(*ctx_, gpu.cache, gpu.colorFormat, gpu.depthFormat);
        if (!pass) return pass.error();
        pass_ = *pass;
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
        if (settings_.adaptivePixels <= 0.0f) uniformTriangles_ = fasUniformTriangles(patches_, std::min(settings_.tessFactor, 64u));
        return success();
    }

    Status update() override {
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
            if (mesh_.indexCount) destroyMesh(*ctx_, mesh_);
            mesh_ = GpuMesh{};
            const uint32_t factor = displacedGridFactor(*planned_, *displacement_, factor_);
            if (Status built = buildDisplacedDrawing(displaced_, *ctx_, *this, *planned_, *displacement_, factor); !built)
                return built;
            triangles_ = displaced_.gpu.indexCount / 3;
            return success();
        }
        destroyDisplacedDrawing(displaced_);
        triangles_ = patches_.indices.size() / 3;
        std::vector<glm::vec3> positions, normals;
        tessellateFas(patches_, positions, normals);
        if (mesh_.indexCount) destroyMesh(*ctx_, mesh_);
        if (positions.empty()) return success();
        std::vector<MeshVertex> vertices(positions.size());
        for (size_t i = 0; i < positions.size(); ++i) vertices[i] = {positions[i], normals[i]};
        Result<GpuMesh> mesh = uploadMesh(*ctx_, vertices, patches_.indices);
        if (!mesh) return mesh.error();
        mesh_ = *mesh;
        return success();
    }

    DrawStats record(VkCommandBuffer cmd, const RenderTarget& target, const DrawView& view) override {
        if (haveTess_ && !displacement_) {
            if (stencilsPending_) recordTessPrepare(cmd, tess_, gpuData_.header.pointCount);
            stencilsPending_ = false;
            const bool adaptive = settings_.adaptivePixels > 0.0f;
            const uint32_t factor = adaptive ? 0u : std::min(settings_.tessFactor, 64u);
            // A transition edge at factor F may get 2 ceil(F / 2) segments.
            recordTessPatches(cmd, tess_, target, view, {factor, settings_.adaptivePixels, capture_, adaptive ? 64u : factor + 1});
            return DrawStats{patches_.layout.size(), adaptive ? 0 : uniformTriangles_, DrawnBy::Tessellator};
        }
        MeshDraw draw{displacement_ ? &displaced_.gpu : &mesh_, glm::vec3(0.8f), true, view.wireframe};
        recordMeshPass(cmd, pass_, target, MeshView{view.viewProjection, view.eye, view.background, view.shading, view.clear},
                       draw.mesh->indexCount ? std::span<const MeshDraw>(&draw, 1) : std::span<const MeshDraw>());
        return DrawStats{patches_.layout.size(), triangles_, DrawnBy::CpuMesh};
    }

    Status setDisplacement(const Displacement* displacement) override {
        displacement_ = displacement && !displacement->empty() ? displacement : nullptr;
        return success();
    }

    Status displacementChanged(std::span<const uint32_t> samples) override {
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
    const PlannedCage* planned_ = nullptr;
    SchemeSettings settings_;
    FasPath requestedPath_ = FasPath::Auto;
    bool tessellated_ = false;  // resolved in createGpu
    mutable FasPatches patches_;     // mutable: evaluate() refreshes the CPU points on the tess path
    mutable std::mutex cpuPointsMutex_;
    mutable bool cpuPointsStale_ = true;
    uint32_t factor_ = 8;
    uint64_t triangles_ = 0;          // path=cpu: the mesh's
    uint64_t uniformTriangles_ = 0;   // path=tess at a uniform factor
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
