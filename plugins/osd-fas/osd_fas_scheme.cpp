// `osd-fas`: OpenSubdiv's feature-adaptive patches, the baseline B16 compares against: one
// primitive per patch, tessellated on the CPU (all cores) and drawn with MeshPass
// (osd_fas_patches.h has the math). The refinement stencils and the patch evaluation run on
// every update(), as they would when the cage's vertices move.
//
// Displacement: the patches' surface (evaluateFas) on a grid of at least the tessellation
// factor and the tiles' required factor, displaced along its own normal and made watertight
// through a DisplacedDrawing (displaced_drawing.h: a dab re-displaces only what it reached).
#include "displaced_drawing.h"
#include "mesh_pass.h"
#include "osd_fas_patches.h"
#include "scheme_api.h"
#include "scheme_support.h"

namespace qp {
namespace {

class OsdFasScheme final : public Scheme {
public:
    SupportReport support(const CageFeatures&, const SchemeSettings& settings) const override {
        SupportReport report;
        if (settings.adaptivePixels > 0.0f)
            report.approximations.push_back("osd-fas has no screen-adaptive tessellation: it uses factor 16");
        for (const auto& [key, value] : settings.options)
            report.approximations.push_back("osd-fas ignores the unknown option '" + key + "'");
        return report;
    }

    Status build(const PlannedCage& planned, const SchemeSettings& settings) override {
        planned_ = &planned;
        factor_ = settings.adaptivePixels > 0.0f ? 16u : settings.tessFactor;
        Result<FasPatches> patches =
            buildFasPatches(planned.cage(), settings.planDepth, settings.adaptivePixels > 0.0f ? 16u : settings.tessFactor);
        if (!patches) return patches.error();
        patches_ = std::move(*patches);
        return success();
    }

    Status createGpu(const GpuContext& gpu) override {
        ctx_ = gpu.vulkan;
        Result<MeshPass> pass = createMeshPass(*ctx_, gpu.cache, gpu.colorFormat, gpu.depthFormat);
        if (!pass) return pass.error();
        pass_ = *pass;
        return success();
    }

    Status update() override {
        updateFasPoints(patches_, planned_->cage().positions);
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
        MeshDraw draw{displacement_ ? &displaced_.gpu : &mesh_, glm::vec3(0.8f), true, view.wireframe};
        recordMeshPass(cmd, pass_, target, MeshView{view.viewProjection, view.eye, view.background, view.shading},
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
        for (size_t i = 0; i < requests.size(); ++i) {
            const FasSample s = evaluateFas(patches_, requests[i].subface, requests[i].u, requests[i].v);
            out[i] = surfacePoint(s.position, s.du, s.dv);
        }
    }

    SchemeStats stats() const override {
        SchemeStats stats;
        stats.patches = patches_.layout.size();
        stats.singleCreasePatches = patches_.singleCreasePatches;
        stats.controlPoints = patches_.points.size() - planned_->cage().vertexCount();
        stats.gpuBytes = mesh_.vertices.size + mesh_.indices.size + displaced_.gpu.vertices.size + displaced_.gpu.indices.size;
        return stats;
    }

    void destroyGpu() override {
        if (!ctx_) return;
        if (mesh_.indexCount) destroyMesh(*ctx_, mesh_);
        destroyDisplacedDrawing(displaced_);
        destroyMeshPass(*ctx_, pass_);
        ctx_ = nullptr;
    }

private:
    const PlannedCage* planned_ = nullptr;
    FasPatches patches_;
    uint32_t factor_ = 8;
    uint64_t triangles_ = 0;
    const Displacement* displacement_ = nullptr;
    const VulkanContext* ctx_ = nullptr;
    MeshPass pass_;
    GpuMesh mesh_;                // undisplaced
    DisplacedDrawing displaced_;  // with a displacement
};

}  // namespace
}  // namespace qp

QUADPLAN_EXPORT_SCHEME("osd-fas",
                       "OpenSubdiv feature-adaptive patches: B-spline and single-crease patches, Gregory-basis end "
                       "caps, one primitive per patch",
                       qp::OsdFasScheme)
