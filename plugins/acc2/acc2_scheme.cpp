// `acc2`: Loop, Schaefer, Ni, Castano 2009 Gregory patches (acc2.h, README.md), one bicubic
// Gregory patch of 20 control points per quad of the (once refined, for non-quad cages) cage.
//
// Drawing: path=tess (default) draws one patch primitive per Gregory patch through the
// tessellator, the 20 points in a storage buffer and the rational interior blend evaluated in
// acc2.tese; path=cpu evaluates the patches on a sub-face grid on all cores and draws the
// triangles (grid_drawing.h). update() rebuilds the patches from the cage's positions.
#include "acc2.h"
#include "grid_drawing.h"
#include "module_shader_code.h"
#include "scheme_api.h"
#include "tess_patch_pass.h"

namespace qp {
namespace {

constexpr FeatureRule kRules[] = {
    {CageFeature::ExtraordinaryVertices, Handling::Approximated,
     "acc2 approximates the surface next to extraordinary vertices (Gregory patches: limit position at "
     "patch corners, G1 across edges; exact on regular quads)"},
    {CageFeature::SemiSharpCreases, Handling::Approximated, "acc2 draws semi-sharp creases smooth"},
    {CageFeature::InfinitelySharpCreases, Handling::Approximated, "acc2 draws infinitely sharp creases smooth"},
    {CageFeature::SemiSharpCorners, Handling::Approximated, "acc2 draws sharp corners smooth"},
    {CageFeature::InfinitelySharpCorners, Handling::Approximated, "acc2 draws sharp corners smooth"},
    {CageFeature::NonQuadFaces, Handling::Approximated,
     "acc2 refines cages with non-quad faces once first (tags act in that step only; 4 patches per quad)"},
    {CageFeature::NonManifold, Handling::Unsupported, "acc2 needs a manifold cage (a fan of quads around every vertex)"},
};

class Acc2Scheme final : public Scheme {
public:
    SupportReport support(const CageFeatures& features, const SchemeSettings& settings) const override {
        SupportReport report = assessSupport(kRules, features);
        checkPatchOptions(report, settings, "acc2");
        return report;
    }

    Status build(const PlannedCage& planned, const SchemeSettings& settings) override {
        planned_ = &planned;
        settings_ = settings;
        Result<PatchPath> path = patchPathOption(settings, "acc2");
        if (!path) return path.error();
        path_ = *path;
        if (Status built = rebuild(); !built) return built;
        prepareGridDrawing(grid_, planned, settings.adaptivePixels > 0.0f ? 16u : settings.tessFactor);
        return success();
    }

    Status createGpu(const GpuContext& gpu) override {
        ctx_ = gpu.vulkan;
        // The grid draws the CPU path, and the tessellated path while displaced.
        if (Status grid = createGridDrawing(grid_, gpu); !grid) return grid;
        if (path_ == PatchPath::Cpu) return success();
        Result<TessPatchPass> pass =
            createTessPatchPass(*ctx_, gpu.cache, gpu.colorFormat, gpu.depthFormat,
                                {moduleShaderCode("tess_patch.vert"), moduleShaderCode("acc2.tesc"), moduleShaderCode("acc2.tese")});
        if (!pass) return Error{"acc2: " + pass.error().message + " (use --option path=cpu)"};
        pass_ = *pass;
        havePass_ = true;
        return success();
    }

    Status update() override {
        if (Status built = rebuild(); !built) return built;
        if (onGrid()) return updateGridDrawing(grid_, *this);
        if (!havePass_) return success();
        const std::vector<glm::vec4> points = paddedPoints(patches_.controlPoints);
        return uploadTessPatches(*ctx_, pass_, points.data(), points.size() * sizeof(glm::vec4), patches_.stats.patches);
    }

    DrawStats record(VkCommandBuffer cmd, const RenderTarget& target, const DrawView& view) override {
        if (onGrid()) return recordGridDrawing(cmd, grid_, target, view, patches_.stats.patches);
        const uint32_t factor = patchFactor();
        recordTessPatches(cmd, pass_, target, view, {factor, settings_.adaptivePixels, false});
        return DrawStats{patches_.stats.patches, factor ? patches_.stats.patches * tessTriangles(factor, false) : 0};
    }

    // Sculpted displacement: this scheme's own surface moved along its own normal, drawn on the
    // CPU grid (grid_drawing.h) whichever path was chosen; evaluate() stays undisplaced.
    Status setDisplacement(const Displacement* displacement) override {
        setGridDisplacement(grid_, displacement);
        return success();
    }

    void evaluate(std::span<const SampleRequest> requests, std::span<SurfacePoint> out) const override {
        for (size_t i = 0; i < requests.size(); ++i) {
            const Acc2Sample s = evaluateAcc2(patches_, requests[i].subface, requests[i].u, requests[i].v);
            out[i] = SurfacePoint{s.position, s.normal, s.du, s.dv, s.valid};
        }
    }

    SchemeStats stats() const override {
        return SchemeStats{patches_.stats.patches, patches_.stats.controlPoints,
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
        Result<Acc2Patches> patches = buildAcc2(planned_->cage(), {}, "acc2");
        if (!patches) return patches.error();
        patches_ = std::move(*patches);
        return success();
    }

    // Segments per patch edge: a patch of a refined cage covers half a sub-face edge.
    uint32_t patchFactor() const {
        if (settings_.adaptivePixels > 0.0f) return 0;
        return patches_.source.steps.empty() ? settings_.tessFactor : std::max(1u, settings_.tessFactor / 2);
    }

    const PlannedCage* planned_ = nullptr;
    SchemeSettings settings_;
    PatchPath path_ = PatchPath::Tessellated;
    Acc2Patches patches_;
    const VulkanContext* ctx_ = nullptr;
    TessPatchPass pass_;
    bool havePass_ = false;
    GridDrawing grid_;
};

}  // namespace
}  // namespace qp

QUADPLAN_EXPORT_SCHEME("acc2",
                       "Loop et al. 2009 Gregory patches (ACC-2): 20 control points per quad, rational interior blend, "
                       "drawn through the tessellator",
                       qp::Acc2Scheme)
