// `plans`: the exact subdivision plans (Brainerd et al. 2016) through the renderer's PlanPass.
//
// The scheme is the reference itself: its CPU evaluation is PlannedCage::evaluate, so its error
// in `quadplan compare` is zero by construction; the GPU evaluation behind its pictures is
// checked against the CPU one in tests/test_render_plans.cpp. It draws every cage the plans
// accept (creases of any sharpness, corners, boundaries, holes, non-quads, non-manifold).
//
// Options: path=auto|tess|grid|cpu. auto, tess and grid are the renderer's GPU paths
// (render/draw_path.h: auto is grid on a CPU device); cpu evaluates the plans on a grid with
// the CPU evaluator (all cores) in update() and draws triangles with MeshPass, the fast path on
// lavapipe, where compute and tessellation shaders are slow. A frame that only moves the
// camera draws the triangles as they are; after a vertex move, updateMoved re-evaluates only
// the sub-faces whose 1-ring holds a moved vertex.
#include <algorithm>
#include <cstdio>

#include "draw_path.h"
#include "mesh_pass.h"
#include "plan_evaluator.h"
#include "plan_pass.h"
#include "scheme_api.h"
#include "scheme_support.h"

namespace qp {
namespace {

uint32_t levelOf(uint32_t factor) {
    uint32_t level = 0;
    while ((1u << level) < factor) ++level;
    return level;
}

class PlansScheme final : public Scheme {
public:
    SupportReport support(const CageFeatures&, const SchemeSettings& settings) const override {
        SupportReport report;
        for (const auto& [key, value] : settings.options)
            if (key != "path") report.approximations.push_back("plans ignores the unknown option '" + key + "'");
        return report;
    }

    Status build(const PlannedCage& planned, const SchemeSettings& settings) override {
        planned_ = &planned;
        settings_ = settings;
        requestedPath_ = DrawPath::Auto;
        cpuPath_ = false;
        if (const std::string* path = settings.option("path")) {
            std::optional<DrawPath> parsed = parseDrawPath(*path);
            cpuPath_ = *path == "cpu";
            if (!parsed && !cpuPath_) return Error{"plans: unknown path '" + *path + "'; use auto, tess, grid or cpu"};
            if (parsed) requestedPath_ = *parsed;
        }
        if (cpuPath_) {
            grid_ = buildSubfaceGrid(planned, gridFactor());
            indexRings();
        }
        return success();
    }

    Status createGpu(const GpuContext& gpu) override {
        ctx_ = gpu.vulkan;
        if (cpuPath_) {
            Result<MeshPass> pass = createMeshPass(*ctx_, gpu.cache, gpu.colorFormat, gpu.depthFormat);
            if (!pass) return pass.error();
            meshPass_ = *pass;
            return success();
        }
        path_ = resolveDrawPath(requestedPath_, *ctx_);
        Result<PlanPass> pass = createPlanPass(*ctx_, gpu.cache, gpu.colorFormat, gpu.depthFormat);
        if (!pass) return pass.error();
        pass_ = *pass;
        Result<PlanBuffers> buffers = uploadPlans(*ctx_, *planned_);
        if (!buffers) return buffers.error();
        buffers_ = *buffers;
        haveBuffers_ = true;
        bindPlanBuffers(*ctx_, pass_, buffers_);
        if (path_ == DrawPath::Grid) {
            if (Status s = prepareGrid(*ctx_, pass_, buffers_, gridFactor()); !s) return s;
            bindPlanBuffers(*ctx_, pass_, buffers_);
        }
        return success();
    }

    Status update() override {
        if (haveBuffers_) updatePositions(buffers_, *planned_);  // the CPU evaluation reads planned_ itself
        if (!cpuPath_ || !ctx_ || grid_.samples.empty()) return success();
        std::vector<LimitSample> samples(grid_.samples.size());
        evaluateBatch(*planned_, grid_.samples, samples);
        std::vector<MeshVertex> vertices(samples.size());
        for (size_t i = 0; i < samples.size(); ++i) vertices[i] = {samples[i].position, normalOf(samples[i].du, samples[i].dv)};
        if (mesh_.indexCount) {  // same grid: rewrite the vertices in place (the host waited for the device)
            uploadBuffer(mesh_.vertices, vertices.data(), vertices.size() * sizeof(MeshVertex));
            return success();
        }
        Result<GpuMesh> mesh = uploadMesh(*ctx_, vertices, grid_.indices);
        if (!mesh) return mesh.error();
        mesh_ = *mesh;
        return success();
    }

    // path=cpu: re-evaluates only the grid samples of sub-faces whose 1-ring holds a moved
    // vertex (PlannedCage::moveVertices refreshed exactly those sub-faces' control points).
    Status updateMoved(std::span<const uint32_t> vertices) override {
        if (!cpuPath_ || !mesh_.indexCount) return update();
        std::vector<uint32_t> touched;  // indices into grid_.subfaces
        for (uint32_t v : vertices)
            if (v + 1 < ringOffsets_.size())
                touched.insert(touched.end(), ringSubfaces_.begin() + ringOffsets_[v], ringSubfaces_.begin() + ringOffsets_[v + 1]);
        std::sort(touched.begin(), touched.end());
        touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
        std::vector<SampleRequest> requests;
        for (uint32_t i : touched)
            requests.insert(requests.end(), grid_.samples.begin() + grid_.firstSample[i],
                            grid_.samples.begin() + grid_.firstSample[i + 1]);
        std::vector<LimitSample> samples(requests.size());
        evaluateBatch(*planned_, requests, samples);
        auto* mapped = static_cast<MeshVertex*>(mesh_.vertices.data);
        size_t k = 0;
        for (uint32_t i : touched)
            for (uint32_t j = grid_.firstSample[i]; j < grid_.firstSample[i + 1]; ++j, ++k)
                mapped[j] = {samples[k].position, normalOf(samples[k].du, samples[k].dv)};
        return success();
    }

    DrawStats record(VkCommandBuffer cmd, const RenderTarget& target, const DrawView& view) override {
        if (cpuPath_) {
            MeshDraw draw{&mesh_, glm::vec3(0.8f), true, view.wireframe};
            recordMeshPass(cmd, meshPass_, target, MeshView{view.viewProjection, view.eye, view.background},
                           mesh_.indexCount ? std::span<const MeshDraw>(&draw, 1) : std::span<const MeshDraw>());
            return DrawStats{grid_.subfaces.size(), grid_.indices.size() / 3};
        }
        PlanView planView;
        planView.viewProjection = view.viewProjection;
        planView.pixelsPerUnit = view.pixelsPerUnit;
        planView.background = view.background;
        planView.wireframe = view.wireframe;
        planView.colorBy = colorBy(view.colorBy);
        TessellationSettings tessellation{settings_.tessFactor, 8.0f};
        if (settings_.adaptivePixels > 0.0f) tessellation = {0, settings_.adaptivePixels};

        DrawStats stats;
        stats.patches = buffers_.data.subfaces.size();
        const bool adaptive = path_ == DrawPath::Tessellated && tessellation.uniformFactor == 0;
        const uint32_t factor = path_ == DrawPath::Grid ? buffers_.gridFactor : tessellation.uniformFactor;
        if (!adaptive)
            for (uint32_t i = 0; i < buffers_.data.subfaces.size(); ++i) {
                const uint32_t n = gridFactorOf(buffers_.data, i, factor);
                stats.triangles += 2ull * n * n;
            }
        if (path_ == DrawPath::Grid) recordGrid(cmd, pass_, buffers_, target, planView);
        else recordTessellated(cmd, pass_, buffers_, target, planView, tessellation);
        return stats;
    }

    void evaluate(std::span<const SampleRequest> requests, std::span<SurfacePoint> out) const override {
        for (size_t i = 0; i < requests.size(); ++i) {
            const LimitSample s = planned_->evaluate(requests[i].subface, requests[i].u, requests[i].v);
            out[i] = surfacePoint(s.position, s.du, s.dv);
        }
    }

    SchemeStats stats() const override {
        SchemeStats stats;
        if (cpuPath_) return SchemeStats{grid_.subfaces.size(), 0, mesh_.vertices.size + mesh_.indices.size};
        const uint32_t level = levelOf(settings_.adaptivePixels > 0.0f ? 64u : std::max(1u, settings_.tessFactor));
        if (haveBuffers_) {
            stats.patches = buffers_.data.subfaces.size();
            for (const GpuSubface& s : buffers_.data.subfaces)
                stats.controlPoints += buffers_.data.plans[s.plan].stencilCountByLevel[std::min(level, 11u)];
            for (const Buffer* b : {&buffers_.planHeaders, &buffers_.nodes, &buffers_.points, &buffers_.weights,
                                    &buffers_.subfaces, &buffers_.rings, &buffers_.positions, &buffers_.controlPoints,
                                    &buffers_.boundaries, &buffers_.segments, &buffers_.boundaryPoints,
                                    &buffers_.pointPositions, &buffers_.subfaceFactors, &buffers_.grid})
                stats.gpuBytes += b->size;
        }
        return stats;
    }

    std::vector<std::string> colorModes() const override {
        if (cpuPath_) return {"shading"};
        return {"shading", "node-kind", "depth", "sharpness"};
    }

    void destroyGpu() override {
        if (!ctx_) return;
        if (mesh_.indexCount) destroyMesh(*ctx_, mesh_);
        if (meshPass_.layout) destroyMeshPass(*ctx_, meshPass_);
        if (haveBuffers_) destroyPlanBuffers(*ctx_, buffers_);
        haveBuffers_ = false;
        destroyPlanPass(*ctx_, pass_);
        ctx_ = nullptr;
    }

private:
    // Per vertex, the gridded sub-faces (indices into grid_.subfaces) whose 1-ring holds it.
    void indexRings() {
        const uint32_t vertexCount = planned_->cage().vertexCount();
        ringOffsets_.assign(vertexCount + 1, 0);
        for (uint32_t s : grid_.subfaces)
            for (uint32_t v : planned_->subfaceRing(s)) ++ringOffsets_[v + 1];
        for (uint32_t v = 0; v < vertexCount; ++v) ringOffsets_[v + 1] += ringOffsets_[v];
        ringSubfaces_.resize(ringOffsets_.back());
        std::vector<uint32_t> next(ringOffsets_.begin(), ringOffsets_.end() - 1);
        for (uint32_t i = 0; i < grid_.subfaces.size(); ++i)
            for (uint32_t v : planned_->subfaceRing(grid_.subfaces[i])) ringSubfaces_[next[v]++] = i;
    }

    // The grid paths have no screen-adaptive mode: a fixed factor for adaptive requests.
    uint32_t gridFactor() const { return settings_.adaptivePixels > 0.0f ? 16u : settings_.tessFactor; }

    static ColorBy colorBy(const std::string& name) {
        if (name == "node-kind") return ColorBy::NodeKind;
        if (name == "depth") return ColorBy::PlanDepth;
        if (name == "sharpness") return ColorBy::Sharpness;
        return ColorBy::Shading;
    }

    const PlannedCage* planned_ = nullptr;
    SchemeSettings settings_;
    DrawPath requestedPath_ = DrawPath::Auto, path_ = DrawPath::Grid;
    const VulkanContext* ctx_ = nullptr;
    PlanPass pass_;
    PlanBuffers buffers_;
    bool haveBuffers_ = false;
    // path=cpu
    bool cpuPath_ = false;
    SubfaceGrid grid_;
    std::vector<uint32_t> ringOffsets_, ringSubfaces_;  // CSR: vertex -> gridded sub-faces seeing it
    MeshPass meshPass_;
    GpuMesh mesh_;
};

}  // namespace
}  // namespace qp

QUADPLAN_EXPORT_SCHEME("plans", "exact subdivision plans (Brainerd et al. 2016): one primitive per sub-face, the reference",
                       qp::PlansScheme)
