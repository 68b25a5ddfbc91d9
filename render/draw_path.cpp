#include "draw_path.h"

#include "displaced_grid_factors.h"
#include "grid_relayout.h"

#include <algorithm>
#include <cassert>
#include <iterator>

namespace qp {

DrawPath resolveDrawPath(DrawPath requested, const VulkanContext& context) {
    if (requested != DrawPath::Auto) return requested;
    return context.isSoftware ? DrawPath::CpuGrid : DrawPath::Tessellated;
}

const char* drawPathName(DrawPath path) {
    switch (path) {
    case DrawPath::Auto: return "auto";
    case DrawPath::Tessellated: return "tess";
    case DrawPath::Grid: return "grid";
    case DrawPath::CpuGrid: return "cpu";
    }
    return "?";
}

std::optional<DrawPath> parseDrawPath(std::string_view name) {
    for (DrawPath path : {DrawPath::Auto, DrawPath::Tessellated, DrawPath::Grid, DrawPath::CpuGrid})
        if (name == drawPathName(path)) return path;
    return std::nullopt;
}

Status preparePlanFrame(const VulkanContext& ctx, PlanPass& pass, PlanBuffers& buffers, const PlannedCage& planned,
                        DrawPath path, const PlanView& drawnView, const TessellationSettings& settings) {
    assert(path != DrawPath::Auto && "resolveDrawPath first");
    if (path == DrawPath::Tessellated) return success();
    // The view the factors are chosen for: this one, or while the camera keeps moving the one
    // the layout's factors were chosen for (then every choice below finds its inputs unchanged).
    PlanView view = drawnView;
    if (drawnView.keepFactors && buffers.factorsKept && !settings.uniformFactor && buffers.adaptiveInputs.valid &&
        buffers.adaptiveInputs.pixelsPerSegment == settings.pixelsPerSegment) {
        view.viewProjection = buffers.adaptiveInputs.viewProjection;
        view.pixelsPerUnit = buffers.adaptiveInputs.pixelsPerUnit;
    }
    GridFactors factors;
    const PlanBuffers::AdaptiveInputs adaptiveInputs{true, view.viewProjection, view.pixelsPerUnit, settings.pixelsPerSegment};
    if (settings.uniformFactor) {
        factors = uniformGridFactors(buffers.data, settings.uniformFactor);
    } else {
        // While the view stays and points moved only by vertex drags, just the sub-faces around
        // the moved vertices are chosen again (a pass over every segment costs tens of ms at a
        // million faces). With a displacement the layout's factors are raised: always a full pass.
        const GridFactors& current = buffers.gridLayout.factors;
        if (!buffers.displacement && adaptiveInputs == buffers.adaptiveInputs && !buffers.gridLayout.subfaceOffset.empty() &&
            current.segmentPieces.size() == buffers.data.segments.size() &&
            current.subfaceFactor.size() == buffers.data.subfaces.size()) {
            factors.segmentPieces = current.segmentPieces;
            factors.subfaceFactor = current.subfaceFactor;
            const AdaptiveView adaptive{view.viewProjection, view.pixelsPerUnit, settings.pixelsPerSegment};
            updateAdaptiveGridFactors(buffers.data, buffers.pointPositionsHost, adaptive, factors, buffers.movedSinceFactors);
        } else {
            factors = adaptiveGridFactors(buffers, view, settings);
        }
        buffers.movedSinceFactors.clear();
    }
    if (buffers.displacement && settings.displacementPixels > 0.0f) {
        const AdaptiveView fine{view.viewProjection, view.pixelsPerUnit, settings.displacementPixels};
        // Kept caps only for the same sub-face tables (a topology edit renumbers them).
        const bool laidOut = buffers.displacementScreen.segmentPieces.size() == buffers.data.segments.size() &&
                             buffers.displacementScreen.subfaceFactor.size() == buffers.data.subfaces.size();
        buffers.displacementScreen = adaptiveGridFactors(buffers.data, buffers.pointPositionsHost, fine,
                                                         laidOut ? &buffers.displacementScreen : nullptr);
        factors = displacedGridFactors(buffers.data, *buffers.displacement, std::move(factors), &buffers.displacementScreen);
    } else if (buffers.displacement) {
        factors = displacedGridFactors(buffers.data, *buffers.displacement, std::move(factors));
    }
    // Macro faces last: they need every member's final factor. Hidden faces and holes keep theirs
    // single. Kept as they are while nothing they are chosen from changed (a vertex drag, an edit
    // in place): choosing them again is a pass over every macro face.
    PlanBuffers::MacroChoiceInputs inputs{view.viewProjection, view.pixelsPerUnit, settings.pixelsPerSegment,
                                          settings.uniformFactor, settings.minify, settings.wholeMacroFaces, {}};
    std::set_union(view.hiddenDrawn.begin(), view.hiddenDrawn.end(), buffers.holeDrawn.begin(), buffers.holeDrawn.end(),
                   std::back_inserter(inputs.blocked));
    const uint32_t macroMinify = settings.uniformFactor == 1 ? settings.minify : 1;
    const bool wholeMacros = settings.uniformFactor && settings.wholeMacroFaces;
    if (buffers.data.macros.stale && (!settings.uniformFactor || macroMinify > 1 || wholeMacros))
        rebuildMacroGrid(planned, buffers.data);  // the first frame since a repack that can draw them
    const GridFactors& current = buffers.gridLayout.factors;
    const bool macrosLaidOut = current.macroSpanPieces.size() == buffers.data.macros.spanCount() &&
                               current.macroResolution.size() == 2 * buffers.data.macros.faces.size();
    if (macrosLaidOut && inputs == buffers.macroInputs && factors.subfaceFactor == current.subfaceFactor &&
        factors.segmentPieces == current.segmentPieces) {
        factors.macroSpanPieces = current.macroSpanPieces;
        factors.macroResolution = current.macroResolution;
    } else {
        const AdaptiveView adaptive{view.viewProjection, view.pixelsPerUnit, settings.pixelsPerSegment};
        chooseMacroPieces(buffers.data, factors, buffers.pointPositionsHost, settings.uniformFactor ? nullptr : &adaptive,
                          macroMinify, inputs.blocked, macrosLaidOut ? &current : nullptr, wholeMacros);
        buffers.macroInputs = std::move(inputs);
    }
    // The compute shader's pending sub-faces are not for the CPU path: it evaluates whole instead.
    if (path == DrawPath::CpuGrid && !buffers.pendingGridSubfaces.empty()) buffers.gridEvaluator = GridEvaluator::None;
    Result<bool> kept = relayoutGridKeepingSlots(ctx, pass, buffers, planned, factors);
    if (!kept) return kept.error();
    Status laidOut = *kept ? success() : prepareGrid(ctx, pass, buffers, std::move(factors));
    if (!laidOut) return laidOut;
    buffers.gridLayout.uniformRequest = buffers.displacement ? 0 : settings.uniformFactor;
    // What the layout's factors now are for: the next frame's incremental adaptive factors.
    buffers.adaptiveInputs = settings.uniformFactor || buffers.displacement ? PlanBuffers::AdaptiveInputs{} : adaptiveInputs;
    buffers.factorsKept = drawnView.keepFactors;
    // A grid filled by the other evaluator is equally good; only a missing one is filled.
    if (path == DrawPath::CpuGrid && buffers.gridEvaluator == GridEvaluator::None) evaluateGridOnCpu(planned, buffers);
    return success();
}

void recordPlanFrame(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers, DrawPath path,
                     const RenderTarget& target, const PlanView& view, const TessellationSettings& settings) {
    assert(path != DrawPath::Auto && "resolveDrawPath first");
    if (path == DrawPath::Tessellated) recordTessellated(cmd, pass, buffers, target, view, settings);
    else recordGrid(cmd, pass, buffers, target, view);
}

}  // namespace qp
