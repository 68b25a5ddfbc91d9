#include "grid_relayout.h"

#include <cstring>

#include "cpu_grid.h"

namespace qp {

Status carryGrid(const VulkanContext& ctx, PlanPass& pass, PlanBuffers& buffers, GridFactors factors,
                 const std::vector<uint32_t>& oldOf, std::span<const char> ownersChanged) {
    GridLayout oldLayout = std::move(buffers.gridLayout);
    const std::vector<uint32_t>& oldOffset = oldLayout.subfaceOffset;
    // The new layout reads the old one's slot tables and writes into those the relayout before
    // left (PlanBuffers::spareSlotTables), and takes the old triangles' memory: nothing is
    // allocated or cleared afresh after each edit.
    GridLayout spare;
    spare.source = std::move(buffers.spareSlotTables.source);
    spare.slotSubface = std::move(buffers.spareSlotTables.slotSubface);
    spare.indices = std::move(oldLayout.indices);
    spare.dependents = std::move(oldLayout.dependents);
    GridLayout layout = carryGridLayout(buffers.data, std::move(factors), oldLayout, oldOf, ownersChanged, std::move(spare));
    buffers.spareSlotTables.source = std::move(oldLayout.source);
    buffers.spareSlotTables.slotSubface = std::move(oldLayout.slotSubface);
    layout.uniformRequest = oldLayout.uniformRequest;
    // The vertices move inside the grid buffer when the new layout fits it, else through a copy.
    const bool inPlace = VkDeviceSize(layout.slotCount()) * sizeof(GridVertex) <= buffers.grid.size;
    std::vector<GridVertex> before;
    if (!inPlace) {
        const GridVertex* grid = static_cast<const GridVertex*>(buffers.grid.data);
        before.assign(grid, grid + (oldOffset.empty() ? 0 : oldOffset.back()));
    }
    if (Status s = installGridLayout(ctx, pass, buffers, std::move(layout)); !s) {
        invalidateSampleCulling(buffers.sampleCulling);
        return s;
    }
    const GridLayout& now = buffers.gridLayout;
    const std::vector<uint32_t>& newOffset = now.subfaceOffset;
    auto* slots = static_cast<GridVertex*>(buffers.grid.data);
    const GridVertex* from = inPlace ? slots : before.data();
    auto move = [&](uint32_t d) {
        const uint32_t old = oldOf[d];
        if (!inPlace || newOffset[d] != oldOffset[old])
            std::memmove(slots + newOffset[d], from + oldOffset[old], (oldOffset[old + 1] - oldOffset[old]) * sizeof(GridVertex));
    };
    // Kept sub-faces keep their order (holes and topology edits renumber in order), so moving
    // those whose range goes down first, in ascending order, then those whose range goes up, in
    // descending order, never overwrites a range that has yet to move.
    const uint32_t count = uint32_t(oldOf.size());
    for (uint32_t d = 0; d < count; ++d)
        if (oldOf[d] != UINT32_MAX && newOffset[d] <= oldOffset[oldOf[d]]) move(d);
    for (uint32_t d = count; d-- > 0;)
        if (oldOf[d] != UINT32_MAX && newOffset[d] > oldOffset[oldOf[d]]) move(d);

    carrySampleCulling(buffers.sampleCulling, oldLayout, now, oldOf);

    // The CPU path's displacement frames follow their slots (a dab re-displaces from them).
    if (!buffers.gridFrames.components.empty()) {
        GridFrames frames;
        frames.resize(now);
        for (uint32_t d = 0; d < count; ++d) {
            const uint32_t old = oldOf[d];
            if (old == UINT32_MAX) continue;
            const size_t floats = size_t(kFrameComponents) * (oldOffset[old + 1] - oldOffset[old]);
            std::memcpy(frames.block(now, d), buffers.gridFrames.block(oldLayout, old), floats * sizeof(float));
        }
        buffers.gridFrames = std::move(frames);
    }
    return success();
}

namespace {

// Only the macro faces changed (which are drawn as one, and their spans' pieces): every slot
// keeps its meaning and its value; the triangles are written again and uploaded alone.
Result<bool> relayoutMacroFaces(const VulkanContext& ctx, PlanPass& pass, PlanBuffers& buffers, const GridFactors& factors) {
    GridLayout& layout = buffers.gridLayout;
    layout.factors.macroSpanPieces = factors.macroSpanPieces;
    layout.factors.macroResolution = factors.macroResolution;
    writeGridIndices(buffers.data, layout);
    if (Status s = installGridIndices(ctx, pass, buffers); !s) return s.error();
    return true;
}

}  // namespace

Result<bool> relayoutGridKeepingSlots(const VulkanContext& ctx, PlanPass& pass, PlanBuffers& buffers,
                                      const PlannedCage& planned, const GridFactors& factors) {
    const uint32_t count = uint32_t(buffers.data.subfaces.size());
    const GridLayout& current = buffers.gridLayout;
    if (buffers.gridEvaluator == GridEvaluator::None || current.subfaceOffset.size() != count + 1 ||
        factors.subfaceFactor.size() != count || !buffers.pendingGridSubfaces.empty())
        return false;
    if (current.factors == factors) return false;
    const std::vector<uint32_t> changed = subfacesWithNewFactors(buffers.data, current.factors, factors);
    if (changed.empty()) return relayoutMacroFaces(ctx, pass, buffers, factors);
    if (2 * changed.size() > count) return false;
    std::vector<uint32_t> oldOf(count);
    for (uint32_t d = 0; d < count; ++d) oldOf[d] = d;
    for (uint32_t d : changed) oldOf[d] = UINT32_MAX;
    const GridEvaluator evaluator = buffers.gridEvaluator;
    if (Status s = carryGrid(ctx, pass, buffers, factors, oldOf); !s) return s.error();
    buffers.gridEvaluator = evaluator;
    if (evaluator == GridEvaluator::Cpu) {
        const std::vector<uint32_t> copying = withDependents(buffers.gridLayout, changed);
        evaluateGridOnCpu(planned, buffers.data, buffers.gridLayout, changed, copying, static_cast<GridVertex*>(buffers.grid.data),
                          buffers.displacement, buffers.displacement ? &buffers.gridFrames : nullptr);
        markSlotsChanged(buffers.sampleCulling, buffers.gridLayout, copying);  // the carried culling tests them again
    } else {
        buffers.pendingGridSubfaces = changed;  // recordGrid evaluates them
    }
    return true;
}

}  // namespace qp
