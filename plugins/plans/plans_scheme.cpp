// `plans`: the exact subdivision plans (Brainerd et al. 2016) through the renderer's PlanPass.
//
// The scheme is the reference itself: its CPU evaluation is PlannedCage::evaluate, so its error
// in `quadplan compare` is zero by construction; the GPU evaluation behind its pictures is
// checked against the CPU one in tests/render/test_render_plans.cpp. It draws every cage the plans
// accept (creases of any sharpness, corners, boundaries, holes, non-quads, non-manifold).
//
// Options: path=auto|tess|grid|cpu, the renderer's paths (render/draw_path.h: auto is cpu on a
// CPU device, tess on a GPU). Culling (DrawView::cull) is per sub-face and frame
// (core/culling/subface_cull_bounds.h: conservative; back-patch tests only on closed, outward cages seen
// from outside, and only the frustum with a displacement; culled sub-faces are left out as
// hidden ones are, on every path). The grid paths keep their evaluated grid between frames, so a
// frame whose camera moved but whose cage did not only draws, and after updateMoved (the
// editor's drags) the next frame re-evaluates only the sub-faces whose 1-ring holds a moved
// vertex (recordMovedVertices).
//
// Displacement: all three paths draw it (render/plan_pass.h, setPlanDisplacement). The grid
// paths keep the requested (uniform or screen-adaptive) factors where the displacement is zero
// and raise them to the tiles' resolutions where it is not (render/displaced_grid_factors.h),
// so a sculpted patch costs triangles only where it is; the tessellated path draws uniformly at
// the tiles' required factor (displacedGridFactor, at most 64). After a dab only the sub-faces
// that read the changed samples are re-evaluated (recordDisplacementChange), unless the dab
// reached zero tiles, whose factors then grow (a new grid layout, evaluated whole).
//
// Tag edits (sharpness, corners, the crease method, holes) update in place (updatePlans,
// render/plan_update.h): the re-planned sub-faces' records are rewritten, new plans appended,
// control-point ranges re-allocated (holes: the sub-face tables packed again, the grid kept),
// and the next record() re-evaluates just those sub-faces and the neighbours whose edges
// changed owner. Topology edits (extrude, delete, their undo) do the same through the edit's
// renumbering: kept sub-faces keep their control points and grid vertices, and only new,
// re-planned and re-owned sub-faces are evaluated (with a displacement set they rebuild).
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iterator>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "culling/subface_cull_bounds.h"
#include "draw_path.h"
#include "mesh/closed_surface.h"
#include "plan_pass.h"
#include "plan_update.h"
#include "plans/memory_estimate.h"
#include "scheme_api.h"
#include "scheme_culling.h"
#include "scheme_support.h"
#include "vk_commands.h"

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
            if (key != "path" && key != "displacement-pixels" && key != "macro" && key != "minify" &&
                key != "macro-whole" && key != "sample-culling")
                report.approximations.push_back("plans ignores the unknown option '" + key + "'");
        return report;
    }

    Status build(const PlannedCage& planned, const SchemeSettings& settings) override {
        planned_ = &planned;
        settings_ = settings;
        requestedPath_ = DrawPath::Auto;
        if (const std::string* path = settings.option("path")) {
            std::optional<DrawPath> parsed = parseDrawPath(*path);
            if (!parsed) return Error{"plans: unknown --path '" + *path + "'; use auto, tess, grid or cpu"};
            requestedPath_ = *parsed;
        }
        macroChoice_ = MacroChoice::Auto;
        if (const std::string* macro = settings.option("macro")) {
            bool known = false;
            for (MacroChoice choice :
                 {MacroChoice::Auto, MacroChoice::Rectangles, MacroChoice::Quartets, MacroChoice::Blocks, MacroChoice::Off})
                if (*macro == macroChoiceName(choice)) macroChoice_ = choice, known = true;
            if (!known) return Error{"plans: --option macro=" + *macro + ": use auto, rectangles, quartets, blocks or off"};
        }
        minify_ = 1;
        if (const std::string* minify = settings.option("minify")) {
            char* end = nullptr;
            const long value = std::strtol(minify->c_str(), &end, 10);
            if (minify->empty() || *end != '\0' || value < 1 || value > 64)
                return Error{"plans: --option minify=" + *minify + " is not a whole number from 1 to 64 (at --tess 1, "
                             "macro faces drawn at per-face factor 1 / minify)"};
            minify_ = uint32_t(value);
        }
        wholeMacroFaces_ = false;
        if (const std::string* whole = settings.option("macro-whole")) {
            if (*whole != "on" && *whole != "off") return Error{"plans: --option macro-whole=" + *whole + ": use on or off"};
            wholeMacroFaces_ = *whole == "on";
        }
        sampleCulling_ = true;
        if (const std::string* culling = settings.option("sample-culling")) {
            if (*culling != "on" && *culling != "off")
                return Error{"plans: --option sample-culling=" + *culling + ": use on or off"};
            sampleCulling_ = *culling == "on";
        }
        cullBounds_.reset();
        displacementPixels_ = 0.0f;
        if (const std::string* pixels = settings.option("displacement-pixels")) {
            char* end = nullptr;
            const float value = std::strtof(pixels->c_str(), &end);
            if (pixels->empty() || *end != '\0' || !(value >= 0.0f && value <= 1000.0f))
                return Error{"plans: --option displacement-pixels=" + *pixels + " is not a number of pixels from 0 to 1000 "
                             "(0: every displacement sample a vertex)"};
            displacementPixels_ = value;
        }
        return success();
    }

    Status createGpu(const GpuContext& gpu) override {
        ctx_ = gpu.vulkan;
        path_ = resolveDrawPath(requestedPath_, *ctx_);
        Result<PlanPass> pass = createPlanPass(*ctx_, gpu.cache, gpu.colorFormat, gpu.depthFormat);
        if (!pass) return pass.error();
        pass_ = *pass;
        Result<PlanBuffers> buffers = uploadPlans(*ctx_, *planned_, macroChoice_, path_ == DrawPath::CpuGrid);
        if (!buffers) return buffers.error();
        buffers_ = std::move(*buffers);
        haveBuffers_ = true;
        if (Status s = bindPlanBuffers(*ctx_, pass_, buffers_); !s) return s;
        return setPlanDisplacement(*ctx_, pass_, buffers_, displacement_);
    }

    Status setDisplacement(const Displacement* displacement) override {
        cullBounds_.reset();
        cullMargins_.clear();
        displacement_ = displacement && !displacement->empty() ? displacement : nullptr;
        if (displacement_ && displacement_->layout.tiles.size() != planned_->subfaceCount())
            return Error{"plans: the displacement does not match the cage's sub-faces"};
        return haveBuffers_ ? setPlanDisplacement(*ctx_, pass_, buffers_, displacement_) : success();
    }

    Status displacementChanged(std::span<const uint32_t> samples) override {
        cullMargins_.clear();  // they follow |D|
        if (!haveBuffers_ || !displacement_) return success();
        // Device work (the GPU grid path) goes through one short submission; the CPU grid and
        // the tessellated path need none.
        if (buffers_.gridEvaluator == GridEvaluator::Gpu)
            return submitAndWait(*ctx_, [&](VkCommandBuffer cmd) {
                recordDisplacementChange(cmd, pass_, buffers_, *planned_, samples);
            });
        recordDisplacementChange(VK_NULL_HANDLE, pass_, buffers_, *planned_, samples);
        return success();
    }

    Result<PlanUpdate> updatePlans(const PlanChange& change) override {
        if (change.topologyChanged) renumberCullBounds(change);
        else staleCullBounds(change.subfaces);
        if (!haveBuffers_ || (change.topologyChanged && change.previousSubfaceOf.empty())) return PlanUpdate::Rebuild;
        std::span<const uint32_t> changed = change.subfaces;
        std::vector<uint32_t> withPending;
        if (change.topologyChanged && (!pendingMoves_.empty() || !pendingRefresh_.empty())) {
            // Refreshes not drawn yet name vertices and drawn sub-faces of the numbering before
            // the edit: they join the change as sub-faces of the new numbering.
            withPending = renumberedPending(change);
            changed = withPending;
        }
        Result<PlanTableUpdate> updated = updatePlanTables(*ctx_, pass_, buffers_, *planned_, changed,
                                                           change.topologyChanged ? change.previousSubfaceOf
                                                                                  : std::span<const uint32_t>());
        if (!updated) return updated.error();
        if (!updated->applied) return PlanUpdate::Rebuild;
        if (displacement_) {  // as updateMoved: the partial refresh draws the undisplaced surface
            if (Status s = update(); !s) return s.error();
            return PlanUpdate::Updated;
        }
        std::vector<uint32_t> merged;
        std::set_union(pendingRefresh_.begin(), pendingRefresh_.end(), updated->refresh.begin(), updated->refresh.end(),
                       std::back_inserter(merged));
        pendingRefresh_ = std::move(merged);
        return PlanUpdate::Updated;
    }

    // change.subfaces with the pending refreshes (moves, earlier updates) in the new numbering.
    std::vector<uint32_t> renumberedPending(const PlanChange& change) {
        std::vector<uint32_t> drawn = subfacesAround(buffers_.data, pendingMoves_);
        drawn.insert(drawn.end(), pendingRefresh_.begin(), pendingRefresh_.end());
        std::vector<char> stale(buffers_.drawnOfSubface.size(), 0);
        for (uint32_t d : drawn) stale[buffers_.data.subfaces[d].subface] = 1;
        std::vector<uint32_t> out(change.subfaces.begin(), change.subfaces.end());
        for (uint32_t s = 0; s < change.previousSubfaceOf.size(); ++s) {
            const uint32_t previous = change.previousSubfaceOf[s];
            if (previous < stale.size() && stale[previous]) out.push_back(s);
        }
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        pendingMoves_.clear();
        pendingRefresh_.clear();
        return out;
    }

    bool updatesPlansInPlace() const override { return true; }
    bool updatesTopologyInPlace() const override { return true; }
    bool hidesSubfaces() const override { return true; }

    Status update() override {
        cullBounds_.reset();
        pendingMoves_.clear();
        pendingRefresh_.clear();
        if (haveBuffers_) updatePositions(buffers_, *planned_);  // drops the cached grid
        return success();
    }

    // Only these vertices moved: the next record() refreshes just the sub-faces around them,
    // recording the device part into its command buffer (evaluate() reads planned_ directly).
    Status updateMoved(std::span<const uint32_t> vertices) override {
        if (!haveBuffers_) return success();
        if (cullBounds_) {
            std::vector<uint32_t> around;
            for (uint32_t d : subfacesAround(buffers_.data, vertices)) around.push_back(buffers_.data.subfaces[d].subface);
            std::sort(around.begin(), around.end());
            staleCullBounds(around);
        }
        // The partial refresh re-evaluates the undisplaced surface only; with a displacement the
        // whole grid is evaluated again.
        if (displacement_) return update();
        std::vector<uint32_t> merged;
        std::set_union(pendingMoves_.begin(), pendingMoves_.end(), vertices.begin(), vertices.end(),
                       std::back_inserter(merged));
        pendingMoves_ = std::move(merged);
        return success();
    }

    Result<DrawStats> record(VkCommandBuffer cmd, const RenderTarget& target, const DrawView& view) override {
        PlanView planView;
        planView.viewProjection = view.viewProjection;
        planView.pixelsPerUnit = view.pixelsPerUnit;
        planView.background = view.background;
        planView.wireframe = view.wireframe;
        // A later draw of the same frame (another instance of the cage) must not rewrite the culled
        // triangles an earlier draw of the command buffer reads: it draws every triangle.
        planView.sampleCulling = sampleCulling_ && view.sampleCulling && !view.sameFrame;
        planView.clear = view.clear;
        // Lights fixed in the world: toward them in the cage's coordinates (normals go by the
        // inverse transpose, so dot(n, l) keeps its sign and, for rotations and uniform scales, its value).
        const glm::mat3 objectFromWorld = glm::inverse(view.worldFromObject);
        planView.keyLight = glm::normalize(objectFromWorld * kPlanKeyLight);
        planView.fillLight = glm::normalize(objectFromWorld * kPlanFillLight);
        planView.colorBy = colorBy(view.colorBy);
        hiddenDrawn_.clear();
        for (uint32_t subface : view.hiddenSubfaces)
            if (subface < buffers_.drawnOfSubface.size() && buffers_.drawnOfSubface[subface] != UINT32_MAX)
                hiddenDrawn_.push_back(buffers_.drawnOfSubface[subface]);
        std::sort(hiddenDrawn_.begin(), hiddenDrawn_.end());
        // Holes are in the tables but never drawn; counted here so the statistics leave them out.
        std::vector<uint32_t> hiddenOrHole;
        std::set_union(hiddenDrawn_.begin(), hiddenDrawn_.end(), buffers_.holeDrawn.begin(), buffers_.holeDrawn.end(),
                       std::back_inserter(hiddenOrHole));
        hiddenDrawn_ = std::move(hiddenOrHole);
        DrawStats stats;
        culledDrawn_ = culledDrawnSubfaces(view, stats);
        planView.hiddenDrawn = hiddenDrawn_;
        planView.culledDrawn = culledDrawn_;
        planView.backFacesHidden = backFacesHidden_;
        planView.eye = homogeneousEye(view.viewProjection, view.eye);
        planView.shading = view.shading;
        planView.keepFactors = view.navigating;
        TessellationSettings tessellation{settings_.tessFactor, 8.0f};
        if (settings_.adaptivePixels > 0.0f) tessellation = {0, settings_.adaptivePixels};
        tessellation.displacementPixels = displacementPixels_;
        tessellation.minify = minify_;
        tessellation.wholeMacroFaces = wholeMacroFaces_;
        // Every stored sample a vertex: the grid paths raise the factors where the displacement
        // is not zero (displaced_grid_factors.h); the tessellator takes one uniform factor.
        if (displacement_ && path_ == DrawPath::Tessellated)
            tessellation = {std::min(displacedGridFactor(*planned_, *displacement_,
                                                         tessellation.uniformFactor ? tessellation.uniformFactor : 1u),
                                     64u),
                            8.0f};

        // The host side of the frame (grid layout, the CPU-evaluated grid). The callers submit
        // and wait between frames, so no earlier frame still reads what it writes.
        if (!pendingMoves_.empty()) {
            recordMovedVertices(cmd, pass_, buffers_, *planned_, pendingMoves_);
            pendingMoves_.clear();
        }
        if (!pendingRefresh_.empty()) {
            recordSubfaceRefresh(cmd, pass_, buffers_, *planned_, pendingRefresh_);
            pendingRefresh_.clear();
        }
        if (Status prepared = view.sameFrame ? success()
                                             : preparePlanFrame(*ctx_, pass_, buffers_, *planned_, path_, planView, tessellation);
            !prepared) {
            beginRendering(cmd, target, view.clear, view.background);  // a defined picture all the same
            vkCmdEndRendering(cmd);
            return Error{"plans: " + prepared.error().message};
        }
        recordPlanFrame(cmd, pass_, buffers_, path_, target, planView, tessellation);
        const std::vector<uint32_t> skipped = skippedDrawn(buffers_, planView, path_ != DrawPath::Tessellated);
        std::vector<uint32_t> skippedOrHole;
        std::set_union(skipped.begin(), skipped.end(), buffers_.holeDrawn.begin(), buffers_.holeDrawn.end(),
                       std::back_inserter(skippedOrHole));
        stats.patches = buffers_.data.subfaces.size() - skippedOrHole.size();
        stats.drawnBy = path_ == DrawPath::Tessellated ? DrawnBy::Tessellator
                        : path_ == DrawPath::Grid      ? DrawnBy::GpuGrid
                                                       : DrawnBy::CpuMesh;
        if (path_ != DrawPath::Tessellated) {
            // The index ranges drawn (a coarse macro face's triangles are its head's).
            const std::vector<uint32_t>& indexOffset = buffers_.gridLayout.indexOffset;
            for (const DrawnRun& run : drawnRuns(buffers_, skipped))
                stats.triangles += (indexOffset[run.end] - indexOffset[run.begin]) / 3;
            if (buffers_.sampleCulling.inUse) {
                stats.facingAwayTriangles = buffers_.sampleCulling.facingAwayTriangles;
                stats.sampleCulledTriangles = stats.triangles - buffers_.sampleCulling.keptTriangles - stats.facingAwayTriangles;
            }
        } else if (tessellation.uniformFactor > 0) {  // the tessellator's count at a uniform factor
            const std::vector<uint32_t> factors = uniformGridFactors(buffers_.data, tessellation.uniformFactor).subfaceFactor;
            for (uint32_t n : factors) stats.triangles += 2ull * n * n;
            for (uint32_t d : skippedOrHole) stats.triangles -= 2ull * factors[d] * factors[d];
        }
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
        const uint32_t level = levelOf(settings_.adaptivePixels > 0.0f ? 64u : std::max(1u, settings_.tessFactor));
        if (haveBuffers_) {
            stats.patches = buffers_.data.subfaces.size();
            for (const GpuSubface& s : buffers_.data.subfaces)
                stats.controlPoints += buffers_.data.plans[s.plan].stencilCountByLevel[std::min(level, kMaxPlanDepth)];
            for (const Buffer* b : {&buffers_.planHeaders, &buffers_.nodes, &buffers_.points, &buffers_.weights,
                                    &buffers_.subfaces, &buffers_.rings, &buffers_.positions, &buffers_.controlPoints,
                                    &buffers_.boundaries, &buffers_.segments, &buffers_.boundaryPoints,
                                    &buffers_.pointPositions, &buffers_.subfaceGrid, &buffers_.grid,
                                    &buffers_.gridSource, &buffers_.slotSubface, &buffers_.gridIndices, &buffers_.gridCulledIndices,
                                    &buffers_.displacementTiles, &buffers_.displacementPadded,
                                    &buffers_.displacementSamples})
                stats.gpuBytes += b->size;
        }
        return stats;
    }

    std::vector<std::string> colorModes() const override { return {"shading", "node-kind", "depth", "sharpness"}; }

    void destroyGpu() override {
        if (!ctx_) return;
        if (haveBuffers_) destroyPlanBuffers(*ctx_, buffers_);
        haveBuffers_ = false;
        destroyPlanPass(*ctx_, pass_);
        ctx_ = nullptr;
    }

private:
    // The drawn sub-faces culled for this view (sorted); the bounds are built when first needed
    // after a change of the cage or the displacement (their time counts in this frame's).
    // after a change of the cage, or brought up to date for the sub-faces a move or a tag edit
    // changed (their time counts in this frame's).
    std::vector<uint32_t> culledDrawnSubfaces(const DrawView& view, DrawStats& stats) {
        if (view.culledSubfacesOut) view.culledSubfacesOut->clear();
        backFacesHidden_ = false;
        if (view.cull == CullMethod::None) return {};
        const auto start = std::chrono::steady_clock::now();
        // A displaced surface is tested against the frustum only: boxes are all it needs.
        CullMethod detail = displacement_ ? CullMethod::Frustum : view.cull;
        if (detail == CullMethod::PPlane && planesTooLarge_) detail = CullMethod::NCone;
        if (cullBounds_ && cullDetail_ < detail) cullBounds_.reset();
        if (!cullBounds_) {
            // pplane's tangent planes (1.3 KB a leaf) may not fit beside a very large cage: then
            // it takes ncone's answers, which are conservative too and cull less.
            if (view.cull == CullMethod::PPlane && !displacement_) {
                const uint64_t available = availableMemoryBytes();
                planesTooLarge_ = available > 0 && tangentPlaneBytes(*planned_) > available / 2;
                detail = planesTooLarge_ ? CullMethod::NCone : CullMethod::PPlane;
            }
            cullBounds_ = buildSubfaceCullBounds(*planned_, detail);
            cullNeighbours_ = subfaceAdjacency(*planned_);
            cullDetail_ = detail;
            cullStale_.clear();
            cullRenumbered_ = false;
            closed_ = closedOutwardSurface(planned_->cage(), planned_->topology());
            cullMargins_.clear();
            cullBox_ = cullBounds_->bounds();
        } else if (!cullStale_.empty() || cullRenumbered_) {
            updateSubfaceCullBounds(*cullBounds_, *planned_, cullStale_, cullDetail_);
            cullStale_.clear();
            if (cullRenumbered_) cullNeighbours_ = subfaceAdjacency(*planned_);
            cullRenumbered_ = false;
            // Moves can turn a piece inside out, and holes open the surface.
            closed_ = closedOutwardSurface(planned_->cage(), planned_->topology());
            cullBox_ = cullBounds_->bounds();
        }
        if (displacement_ && cullMargins_.empty()) {  // every box grows by its tile's largest |D|
            cullMargins_.assign(planned_->subfaceCount(), 0.0f);
            const DisplacementLayout& layout = displacement_->layout;
            for (uint32_t s = 0; s < layout.tiles.size(); ++s) {
                const DisplacementTile& tile = layout.tiles[s];
                for (uint32_t k = 0; k < (tile.cells + 2) * (tile.cells + 2); ++k)
                    cullMargins_[s] = std::max(cullMargins_[s], std::abs(displacement_->samples[layout.padded[tile.offset + k]]));
            }
        }
        // The grid's facing-away triangles go too where the back side cannot show (as for the
        // back-patch tests: scheme_support.h cullForView).
        backFacesHidden_ = view.cull >= CullMethod::TCone && closed_ && !displacement_ && view.hiddenSubfaces.empty() &&
                           backSideHidden(cullBox_, view.viewProjection, homogeneousEye(view.viewProjection, view.eye));
        stats.cullMilliseconds += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        std::vector<uint32_t> drawn;
        // Outlines (scheme_culling.h): the bounds hold the limit surface, the rasteriser draws its
        // triangles, and cull-stats found a facing-away sub-face beside a drawn one owning an
        // outline pixel at factor 8 (the chord error); so only those a sub-face away from every
        // drawn one are culled.
        const std::vector<uint32_t> culled =
            keepBesideDrawn(cullForView(*cullBounds_, closed_, cullMargins_, view, stats), cullNeighbours_, *cullBounds_, view, stats);
        for (uint32_t s : culled)
            if (s < buffers_.drawnOfSubface.size() && buffers_.drawnOfSubface[s] != UINT32_MAX)
                drawn.push_back(buffers_.drawnOfSubface[s]);
        if (view.culledSubfacesOut) *view.culledSubfacesOut = culled;
        std::sort(drawn.begin(), drawn.end());
        return drawn;
    }

    // A topology edit renumbered the sub-faces: the kept ones keep their bounds (unless a move
    // or tag edit had left them stale), the next culled frame builds the re-planned and new ones
    // and the neighbours again (at 100,000 faces the bounds take seconds to build whole).
    void renumberCullBounds(const PlanChange& change) {
        if (!cullBounds_ || change.previousSubfaceOf.size() != planned_->subfaceCount()) {
            cullBounds_.reset();
            return;
        }
        std::vector<uint32_t> previousOf(change.previousSubfaceOf.begin(), change.previousSubfaceOf.end());
        std::vector<uint32_t> stale(change.subfaces.begin(), change.subfaces.end());
        for (uint32_t s = 0; s < previousOf.size(); ++s) {
            if (std::binary_search(cullStale_.begin(), cullStale_.end(), previousOf[s])) previousOf[s] = UINT32_MAX;
            if (previousOf[s] == UINT32_MAX) stale.push_back(s);
        }
        std::sort(stale.begin(), stale.end());
        stale.erase(std::unique(stale.begin(), stale.end()), stale.end());
        renumberPatches(*cullBounds_, previousOf);
        cullStale_ = std::move(stale);
        cullRenumbered_ = true;
    }

    // Sub-faces (sorted) whose bounds the next culled frame rebuilds.
    void staleCullBounds(std::span<const uint32_t> subfaces) {
        if (!cullBounds_) return;
        std::vector<uint32_t> merged;
        std::set_union(cullStale_.begin(), cullStale_.end(), subfaces.begin(), subfaces.end(), std::back_inserter(merged));
        cullStale_ = std::move(merged);
    }

    static ColorBy colorBy(const std::string& name) {
        if (name == "node-kind") return ColorBy::NodeKind;
        if (name == "depth") return ColorBy::PlanDepth;
        if (name == "sharpness") return ColorBy::Sharpness;
        return ColorBy::Shading;
    }

    const PlannedCage* planned_ = nullptr;
    SchemeSettings settings_;
    MacroChoice macroChoice_ = MacroChoice::Auto;  // --option macro=
    uint32_t minify_ = 1;                          // --option minify=
    bool wholeMacroFaces_ = false;                 // --option macro-whole=
    bool sampleCulling_ = true;                    // --option sample-culling=
    float displacementPixels_ = 0.0f;  // grid paths: displaced tiles no finer than this on screen (0: off)
    DrawPath requestedPath_ = DrawPath::Auto, path_ = DrawPath::Grid;
    const Displacement* displacement_ = nullptr;
    const VulkanContext* ctx_ = nullptr;
    PlanPass pass_;
    PlanBuffers buffers_;
    bool haveBuffers_ = false;
    std::vector<uint32_t> pendingMoves_;    // sorted: vertices moved since the last frame (updateMoved)
    std::vector<uint32_t> pendingRefresh_;  // sorted drawn sub-faces re-planned since the last frame
    std::vector<uint32_t> hiddenDrawn_;     // this draw's DrawView::hiddenSubfaces as drawn indices, and holes
    std::vector<uint32_t> culledDrawn_;     // this draw's culled sub-faces as drawn indices
    bool backFacesHidden_ = false;          // this draw's view cannot see the back side (PlanView::backFacesHidden)
    std::optional<PatchCullSet> cullBounds_;  // built when first needed after a change
    bool cullRenumbered_ = false;             // a topology edit renumbered cullBounds_: neighbours anew
    bool planesTooLarge_ = false;             // pplane culls as ncone: its planes would not fit in memory
    CullBox cullBox_;                       // the box of every entry of cullBounds_
    CullAdjacency cullNeighbours_;          // sub-faces sharing a cage vertex (keepBesideDrawn)
    CullMethod cullDetail_ = CullMethod::None;  // what cullBounds_ serves (PatchCullLeaves::detail)
    std::vector<uint32_t> cullStale_;       // sorted sub-faces whose bounds changed since
    bool closed_ = false;                   // back-patch tests apply (closedOutwardSurface)
    std::vector<float> cullMargins_;        // per sub-face: its tile's largest |D| (displaced; empty: to compute)
};

}  // namespace
}  // namespace qp

QUADPLAN_EXPORT_SCHEME("plans", "exact subdivision plans (Brainerd et al. 2016): one primitive per sub-face, the reference",
                       qp::PlansScheme)
