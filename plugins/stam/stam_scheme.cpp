// `stam`: Stam 1998 exact evaluation (stam.h, README.md) after one or two Catmull-Clark steps
// that isolate the extraordinary vertices: B-spline patches on regular quads, the eigenbasis
// evaluation on quads with one extraordinary corner.
//
// Drawing: the CPU grid only (grid_drawing.h): the surface is evaluated on a sub-face grid on
// all cores in update() and drawn as triangles. A tessellation path would need the eigenbasis
// tables per valence and the log2 level search in the evaluation stage; it is not written.
#include <string>

#include "grid_drawing.h"
#include "scheme_api.h"
#include "scheme_support.h"
#include "stam.h"

namespace qp {
namespace {

constexpr FeatureRule kRules[] = {
    {CageFeature::Boundaries, Handling::Unsupported,
     "stam evaluates closed surfaces only: Stam's construction has no boundary rules"},
    {CageFeature::NonManifold, Handling::Unsupported, "stam needs a manifold cage"},
    {CageFeature::SemiSharpCreases, Handling::Approximated,
     "stam honours creases only in its one or two isolation steps and draws them smooth after"},
    {CageFeature::InfinitelySharpCreases, Handling::Approximated,
     "stam honours creases only in its one or two isolation steps and draws them smooth after"},
    {CageFeature::SemiSharpCorners, Handling::Approximated,
     "stam honours corner tags only in its one or two isolation steps"},
    {CageFeature::InfinitelySharpCorners, Handling::Approximated,
     "stam honours corner tags only in its one or two isolation steps"},
};

class StamScheme final : public Scheme {
public:
    SupportReport support(const CageFeatures& features, const SchemeSettings& settings) const override {
        SupportReport report = assessSupport(kRules, features);
        for (const auto& [key, value] : settings.options) {
            if (key == "path" && value != "cpu")
                report.refusals.push_back("stam draws on the CPU grid only (path=cpu), not '" + value + "'");
            else if (key != "path")
                report.approximations.push_back("stam ignores the unknown option '" + key + "'");
        }
        if (settings.adaptivePixels > 0.0f)
            report.approximations.push_back("stam has no screen-adaptive mode: it uses factor 16");
        return report;
    }

    Status build(const PlannedCage& planned, const SchemeSettings& settings) override {
        planned_ = &planned;
        if (Status built = rebuild(); !built) return built;
        prepareGridDrawing(grid_, planned, settings.adaptivePixels > 0.0f ? 16u : settings.tessFactor);
        return success();
    }

    Status createGpu(const GpuContext& gpu) override { return createGridDrawing(grid_, gpu); }

    Status update() override {
        if (Status built = rebuild(); !built) return built;
        return updateGridDrawing(grid_, *this);
    }

    Result<DrawStats> record(VkCommandBuffer cmd, const RenderTarget& target, const DrawView& view) override {
        DrawStats stats;  // no culling (DrawView::cull): everything is drawn, the culling counts stay zero
        stats.patches = patches_.stats.patches;
        return recordGridDrawing(cmd, grid_, target, view, stats);
    }

    // Sculpted displacement: Stam's surface moved along its own normal (grid_drawing.h);
    // evaluate() stays undisplaced.
    Status setDisplacement(const Displacement* displacement) override { return setGridDisplacement(grid_, displacement); }
    Status displacementChanged(std::span<const uint32_t> samples) override { return gridDisplacementChanged(grid_, samples); }

    void evaluate(std::span<const SampleRequest> requests, std::span<SurfacePoint> out) const override {
        for (size_t i = 0; i < requests.size(); ++i)
            out[i] = surfacePointOf(evaluateStam(patches_, requests[i].subface, requests[i].u, requests[i].v));
    }

    SchemeStats stats() const override {
        return SchemeStats{patches_.stats.patches, patches_.stats.controlPoints, gridDrawingBytes(grid_)};
    }

    void destroyGpu() override { destroyGridDrawing(grid_); }

private:
    Status rebuild() {
        Result<StamPatches> patches = buildStam(planned_->cage(), "stam");
        if (!patches) return patches.error();
        patches_ = std::move(*patches);
        return success();
    }

    const PlannedCage* planned_ = nullptr;
    StamPatches patches_;
    GridDrawing grid_;
};

}  // namespace
}  // namespace qp

QUADPLAN_EXPORT_SCHEME("stam",
                       "Stam 1998 exact evaluation at isolated extraordinary vertices (after 1-2 refinement steps), "
                       "closed cages, drawn on the CPU grid",
                       qp::StamScheme)
