// `uniform`: table-driven uniform Catmull-Clark refinement (Loop 2010 §3) drawn as triangles
// (uniform_refinement.h). Every base quad becomes (2^L)^2 quads, two triangles each, with
// L = round(log2 of the tessellation factor), so the triangle density matches the plans' grid
// at the same factor. The refined vertices are not pushed to the limit: the surface is the
// refined mesh, and its error shrinks about fourfold per level.
//
// Options: level=L (1..8) overrides the level derived from the factor.
//
// Tag edits (sharpness, corners, holes) update in place: the refinement tables are rewritten
// around the re-planned faces from a local refinement (updateUniformTags), and the refined mesh
// is applied again as after a vertex move; topology edits rebuild.
//
// Displacement: the refined surface (sampleRefined, its own normals) on a grid of at least
// 2^L and at least the tiles' required factor, displaced and made watertight through
// a DisplacedDrawing (displaced_drawing.h: a dab re-displaces only what it reached).
#include <algorithm>
#include <cmath>
#include <string>

#include "displaced_drawing.h"
#include "mesh_pass.h"
#include "scheme_api.h"
#include "scheme_support.h"
#include "uniform_refinement.h"

namespace qp {
namespace {

constexpr FeatureRule kRules[] = {
    {CageFeature::SmoothTriangleRule, Handling::Approximated,
     "uniform refines triangles with the Catmark rule, not the smooth triangle rule"},
};

class UniformScheme final : public Scheme {
public:
    SupportReport support(const CageFeatures& features, const SchemeSettings& settings) const override {
        SupportReport report = assessSupport(kRules, features);
        if (settings.adaptivePixels > 0.0f)
            report.approximations.push_back("uniform has no screen-adaptive mode: it refines to level 4");
        for (const auto& [key, value] : settings.options) {
            if (key != "level") report.approximations.push_back("uniform ignores the unknown option '" + key + "'");
            else if (parseLevel(value) == 0) report.refusals.push_back("uniform: level must be 1..8, got '" + value + "'");
        }
        return report;
    }

    Status build(const PlannedCage& planned, const SchemeSettings& settings) override {
        planned_ = &planned;
        uint32_t level = settings.adaptivePixels > 0.0f
                             ? 4u
                             : uint32_t(std::clamp(std::lround(std::log2(double(std::max(1u, settings.tessFactor)))), 1l, 8l));
        if (const std::string* text = settings.option("level")) level = parseLevel(*text);
        if (level == 0) return Error{"uniform: level must be 1..8"};
        Result<UniformRefinement> refinement = buildUniformRefinement(planned, level);
        if (!refinement) return refinement.error();
        refinement_ = std::move(*refinement);
        level_ = level;
        fillIndices();
        return success();
    }

    // Tag edits keep the refined topology: the tables are rewritten around the re-planned
    // sub-faces (updateUniformTags), then everything is applied again as after a move.
    Result<PlanUpdate> updatePlans(const PlanChange& change) override {
        if (change.topologyChanged) return PlanUpdate::Rebuild;
        if (Status s = updateUniformTags(refinement_, *planned_, change.subfaces); !s) return s.error();
        fillIndices();
        if (Status s = update(); !s) return s.error();
        return PlanUpdate::Updated;
    }
    bool updatesPlansInPlace() const override { return true; }

    Status createGpu(const GpuContext& gpu) override {
        ctx_ = gpu.vulkan;
        Result<MeshPass> pass = createMeshPass(*ctx_, gpu.cache, gpu.colorFormat, gpu.depthFormat);
        if (!pass) return pass.error();
        pass_ = *pass;
        return success();
    }

    Status update() override {
        applyUniformRefinement(refinement_, planned_->cage().positions, buffer_);
        const uint32_t first = refinement_.levelOffset[refinement_.levels];
        finest_ = std::span<const glm::vec3>(buffer_).subspan(first, refinement_.finestVertexCount());
        normals_ = refinedNormals(refinement_, finest_);
        if (!ctx_) return success();
        if (mesh_.indexCount) destroyMesh(*ctx_, mesh_);
        triangles_ = indices_.size() / 3;
        if (indices_.empty()) return success();
        if (displacement_) {
            const uint32_t factor = displacedGridFactor(*planned_, *displacement_, 1u << level_);
            if (Status built = buildDisplacedDrawing(displaced_, *ctx_, *this, *planned_, *displacement_, factor); !built)
                return built;
            triangles_ = displaced_.gpu.indexCount / 3;
            return success();
        }
        destroyDisplacedDrawing(displaced_);
        std::vector<MeshVertex> vertices(finest_.size());
        for (size_t i = 0; i < vertices.size(); ++i) vertices[i] = {finest_[i], normals_[i]};
        Result<GpuMesh> mesh = uploadMesh(*ctx_, vertices, indices_);
        if (!mesh) return mesh.error();
        mesh_ = *mesh;
        return success();
    }

    DrawStats record(VkCommandBuffer cmd, const RenderTarget& target, const DrawView& view) override {
        const MeshView meshView{view.viewProjection, view.eye, view.background, view.shading, view.clear};
        const GpuMesh& mesh = displacement_ ? displaced_.gpu : mesh_;
        MeshDraw draw{&mesh, glm::vec3(0.8f), true, view.wireframe};
        recordMeshPass(cmd, pass_, target, meshView,
                       mesh.indexCount ? std::span<const MeshDraw>(&draw, 1) : std::span<const MeshDraw>());
        return DrawStats{0, triangles_, DrawnBy::CpuMesh};
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
            const RefinedSample s = sampleRefined(refinement_, finest_, normals_, requests[i].subface, requests[i].u, requests[i].v);
            out[i] = SurfacePoint{s.position, s.normal, s.du, s.dv, true};
        }
    }

    SchemeStats stats() const override {
        SchemeStats stats;
        stats.controlPoints = refinement_.levelOffset.empty() ? 0 : refinement_.levelOffset.back() - refinement_.levelOffset[1];
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
    void fillIndices() {
        indices_.clear();
        indices_.reserve(6 * refinement_.drawnQuads.size());
        for (uint32_t i : refinement_.drawnQuads) {
            const uint32_t* v = refinement_.quads[i].vertices;
            indices_.insert(indices_.end(), {v[0], v[1], v[2], v[0], v[2], v[3]});
        }
    }

    static uint32_t parseLevel(const std::string& text) {
        char* end = nullptr;
        const long level = std::strtol(text.c_str(), &end, 10);
        return (!text.empty() && *end == '\0' && level >= 1 && level <= 8) ? uint32_t(level) : 0u;
    }

    const PlannedCage* planned_ = nullptr;
    UniformRefinement refinement_;
    uint32_t level_ = 1;
    std::vector<uint32_t> indices_;
    uint64_t triangles_ = 0;
    const Displacement* displacement_ = nullptr;
    std::vector<glm::vec3> buffer_, normals_;
    std::span<const glm::vec3> finest_;

    const VulkanContext* ctx_ = nullptr;
    MeshPass pass_;
    GpuMesh mesh_;                // undisplaced
    DisplacedDrawing displaced_;  // with a displacement
};

}  // namespace
}  // namespace qp

QUADPLAN_EXPORT_SCHEME("uniform",
                       "table-driven uniform Catmull-Clark refinement (Loop 2010 section 3) drawn as triangles",
                       qp::UniformScheme)
