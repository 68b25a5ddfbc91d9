// A scheme whose surface is a set of patches built from the cage on the CPU, drawn one patch
// primitive per patch through the tessellator (path=tess, the default: the control points in a
// storage buffer, the surface evaluated in the module's .tese) or on a sub-face grid evaluated
// on all cores (path=cpu, and whenever displaced: grid_drawing.h). update() rebuilds the patches
// from the cage's positions. acc1, acc2 and pn differ only in their patches, given by `Traits`
// (acc1 and acc2 take most of theirs from QuadPatchTraits below):
//
//   struct Traits {
//       static constexpr const char* kName;              // the scheme's name, e.g. "acc1"
//       static constexpr const char* kTessControl, *kTessEvaluation;  // its shaders (module files)
//       static constexpr const char* kApproximates;      // said whatever the cage (or nullptr)
//       static constexpr bool kTriangles;                 // triangle patches (else quads)
//       static std::span<const FeatureRule> rules();     // what it does with each cage feature
//       using Data = ...;
//       static Result<Data> build(const Cage& cage);
//       static uint32_t patchCount(const Data& data), controlPoints(const Data& data);
//       static std::vector<glm::vec4> packPatches(const Data& data);  // what the .tese reads
//       // Segments per patch edge for `factor` per quad sub-face edge.
//       static uint32_t edgeFactor(const Data& data, uint32_t factor);
//       static SurfacePoint evaluate(const Data& data, uint32_t subface, float u, float v);
//       // Culling (scheme_culling.h): which sub-faces each patch covers, which patches touch, a
//       // point near patch p, and patch p's geometry as culling leaves relative to `origin`.
//       static PatchCover cover(const Data& data);
//       static CullAdjacency adjacency(const Data& data, const PlannedCage& planned);
//       static glm::vec3 anchor(const Data& data, uint32_t p);
//       static void addCullLeaves(const Data& data, uint32_t p, const glm::vec3& origin, PatchCullLeaves& leaves);
//   };
//
// Culling (DrawView::cull): per patch on the tessellated path (its geometry patch's bounds), per
// sub-face on the grid (the leaves of the patches covering it); the bounds are built on the CPU
// when a frame first needs them after update(). Back-patch tests only on a closed, outward cage.
#pragma once

#include <algorithm>
#include <array>
#include <vector>

#include "grid_drawing.h"
#include "mesh/closed_surface.h"
#include "module_shader_code.h"
#include "scheme_api.h"
#include "scheme_culling.h"
#include "tess_patch_pass.h"

namespace qp {

// N points from `first` on, relative to `origin`: a patch's geometry as its culling leaf takes it.
template <size_t N>
std::array<glm::vec3, N> pointsRelativeTo(const glm::vec3* first, const glm::vec3& origin) {
    std::array<glm::vec3, N> points;
    for (size_t k = 0; k < N; ++k) points[k] = first[k] - origin;
    return points;
}

// The Traits acc1 and acc2 share: one quad patch per face of data.source that has one,
// Data::kControlPointsPerPatch points each, uploaded as they are.
template <class Patches>
struct QuadPatchTraits {
    using Data = Patches;
    static constexpr const char* kApproximates = nullptr;
    static constexpr bool kTriangles = false;
    static uint32_t patchCount(const Data& data) { return data.stats.patches; }
    static uint32_t controlPoints(const Data& data) { return data.stats.controlPoints; }
    static std::vector<glm::vec4> packPatches(const Data& data) { return paddedPoints(data.controlPoints); }
    // A patch of a refined cage covers half a sub-face edge.
    static uint32_t edgeFactor(const Data& data, uint32_t factor) {
        return data.source.steps.empty() ? factor : std::max(1u, factor / 2);
    }
    static PatchCover cover(const Data& data) { return quadPatchCover(data.source, data.stats.patches); }
    static CullAdjacency adjacency(const Data& data, const PlannedCage&) {
        return quadPatchAdjacency(data.source, data.stats.patches);
    }
    static glm::vec3 anchor(const Data& data, uint32_t p) {
        return data.controlPoints[size_t(p) * Data::kControlPointsPerPatch];
    }
};

template <class Traits>
class TessPatchScheme final : public Scheme {
public:
    SupportReport support(const CageFeatures& features, const SchemeSettings& settings) const override {
        SupportReport report = assessSupport(Traits::rules(), features);
        if constexpr (Traits::kApproximates != nullptr)
            report.approximations.insert(report.approximations.begin(), Traits::kApproximates);
        checkPatchOptions(report, settings, Traits::kName);
        return report;
    }

    Status build(const PlannedCage& planned, const SchemeSettings& settings) override {
        planned_ = &planned;
        settings_ = settings;
        Result<PatchPath> path = patchPathOption(settings, Traits::kName);
        if (!path) return path.error();
        path_ = *path;
        if (Status built = rebuild(); !built) return built;
        prepareGridDrawing(grid_, planned, settings.adaptivePixels > 0.0f ? 16u : settings.tessFactor);
        culling_ = PatchCulling{Traits::cover(data_), closedOutwardSurface(planned.cage(), planned.topology()),
                                Traits::adjacency(data_, planned), subfaceAdjacency(planned)};
        return success();
    }

    Status createGpu(const GpuContext& gpu) override {
        ctx_ = gpu.vulkan;
        // The grid draws the CPU path, and the tessellated path while displaced.
        if (Status grid = createGridDrawing(grid_, gpu); !grid) return grid;
        if (path_ == PatchPath::Cpu) return success();
        Result<TessPatchPass> pass = createTessPatchPass(
            *ctx_, gpu.cache, gpu.colorFormat, gpu.depthFormat,
            {moduleShaderCode("tess_patch.vert"), moduleShaderCode(Traits::kTessControl), moduleShaderCode(Traits::kTessEvaluation), {}});
        if (!pass) return Error{std::string(Traits::kName) + ": " + pass.error().message + " (use --option path=cpu)"};
        pass_ = *pass;
        havePass_ = true;
        return success();
    }

    Status update() override {
        culling_.bounds.reset();
        if (Status built = rebuild(); !built) return built;
        if (onGrid()) return updateGridDrawing(grid_, *this);
        if (!havePass_) return success();
        const std::vector<glm::vec4> points = Traits::packPatches(data_);
        return uploadTessPatches(*ctx_, pass_, points.data(), points.size() * sizeof(glm::vec4), Traits::patchCount(data_));
    }

    Result<DrawStats> record(VkCommandBuffer cmd, const RenderTarget& target, const DrawView& view) override {
        DrawStats stats;
        const PatchBounds bounds = patchBounds();
        if (onGrid()) {
            const std::vector<uint32_t> culled = cullSubfacesForView(culling_, bounds, grid_.displacement, view, stats);
            return recordGridDrawing(cmd, grid_, target, view, stats, culled);
        }
        const std::vector<uint32_t> culled = cullPatchesForView(culling_, bounds, view, stats);
        const uint32_t factor = patchFactor();
        recordTessPatches(cmd, pass_, target, view, {factor, settings_.adaptivePixels, false}, culled);
        stats.patches = Traits::patchCount(data_) - culled.size();
        stats.triangles = factor ? stats.patches * tessTriangles(factor, Traits::kTriangles) : 0;
        stats.drawnBy = DrawnBy::Tessellator;
        return stats;
    }

    // Sculpted displacement: this scheme's own surface moved along its own normal, drawn on the
    // CPU grid whichever path was chosen; evaluate() stays undisplaced.
    Status setDisplacement(const Displacement* displacement) override {
        culling_.bounds.reset();
        return setGridDisplacement(grid_, displacement);
    }
    Status displacementChanged(std::span<const uint32_t> samples) override {
        culling_.bounds.reset();  // the margins follow |D|
        return gridDisplacementChanged(grid_, samples);
    }

    void evaluate(std::span<const SampleRequest> requests, std::span<SurfacePoint> out) const override {
        for (size_t i = 0; i < requests.size(); ++i)
            out[i] = Traits::evaluate(data_, requests[i].subface, requests[i].u, requests[i].v);
    }

    SchemeStats stats() const override {
        return SchemeStats{Traits::patchCount(data_), Traits::controlPoints(data_),
                           onGrid() ? gridDrawingBytes(grid_) : pass_.patchData.size};
    }

    void destroyGpu() override {
        if (!ctx_) return;
        destroyGridDrawing(grid_);
        if (havePass_) destroyTessPatchPass(*ctx_, pass_);
        havePass_ = false;
        ctx_ = nullptr;
    }

private:
    bool onGrid() const { return path_ == PatchPath::Cpu || grid_.displacement; }

    Status rebuild() {
        Result<typename Traits::Data> built = Traits::build(planned_->cage());
        if (!built) return built.error();
        data_ = std::move(*built);
        return success();
    }

    PatchBounds patchBounds() const {
        return PatchBounds{Traits::patchCount(data_), [this](uint32_t p) { return Traits::anchor(data_, p); },
                           [this](uint32_t p, const glm::vec3& origin, PatchCullLeaves& leaves) {
                               Traits::addCullLeaves(data_, p, origin, leaves);
                           }};
    }

    // Segments per patch edge; 0: screen-adaptive.
    uint32_t patchFactor() const {
        return settings_.adaptivePixels > 0.0f ? 0u : Traits::edgeFactor(data_, settings_.tessFactor);
    }

    const PlannedCage* planned_ = nullptr;
    SchemeSettings settings_;
    PatchPath path_ = PatchPath::Tessellated;
    typename Traits::Data data_;
    const VulkanContext* ctx_ = nullptr;
    TessPatchPass pass_;
    bool havePass_ = false;
    GridDrawing grid_;
    PatchCulling culling_;
};

}  // namespace qp
