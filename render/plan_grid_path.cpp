// The plans renderer's grid paths (plan_pass.h): the grid's layout and buffers, evaluating it
// with the compute pass or on the CPU (cpu_grid.h), drawing it, refreshing what vertex moves and
// displacement changes touched.
#include <algorithm>
#include <cassert>
#include <iterator>
#include <tuple>
#include <utility>

#include "cpu_grid.h"
#include "displacement/brush.h"  // uploadRanges
#include "plan_pass.h"
#include "plan_pass_support.h"
#include "plan_pipelines.h"
#include "shared_pipelines.h"
#include "vk_check.h"
#include "vk_commands.h"

namespace qp {

namespace {

// A buffer of at least `bytes`: `buffer` itself when it is big enough, else a new one.
// Grown with an eighth to spare (within the largest buffer the device makes), so that the edits
// after the first that adds sub-faces keep the buffer and move the grid inside it (carryGrid).
Status ensureCapacity(const VulkanContext& ctx, Buffer& buffer, VkDeviceSize bytes, VkBufferUsageFlags usage) {
    bytes = std::max<VkDeviceSize>(bytes, 16);
    if (buffer.size >= bytes) return success();
    const VkDeviceSize largest = ctx.maxBufferBytes;
    const VkDeviceSize spare = bytes < largest ? std::min<VkDeviceSize>(bytes / 8, largest - bytes) : 0;
    Result<Buffer> bigger = createBuffer(ctx, bytes + spare, usage);
    if (!bigger) return bigger.error();
    destroyBuffer(ctx, buffer);
    buffer = *bigger;
    return success();
}

template <class T>
void uploadVector(const Buffer& buffer, const std::vector<T>& values) {
    if (!values.empty()) uploadBuffer(buffer, values.data(), values.size() * sizeof(T));
}

void dispatchGridPhase(VkCommandBuffer cmd, const PlanPass& pass, const PlanBuffers& buffers, uint32_t count, uint32_t phase,
                       uint32_t listOffset) {
    const VkPipeline grid = buffers.displacement ? pass.gridDisplaced : pass.grid;
    dispatchPerSubface(cmd, pass, grid, PlanComputePush{count, phase, 0, listOffset});
    computeWritesBeforeReads(cmd);
}

// Writes `list` into updateList at `offset` entries (vkCmdUpdateBuffer: at most 64 KiB a call).
void recordListUpload(VkCommandBuffer cmd, const PlanBuffers& buffers, const std::vector<uint32_t>& list, uint32_t offset) {
    assert(!buffers.data.hostEvaluation && "the list feeds the device's evaluation");
    constexpr size_t kChunk = 65536 / sizeof(uint32_t);
    for (size_t first = 0; first < list.size(); first += kChunk) {
        const size_t count = std::min(kChunk, list.size() - first);
        vkCmdUpdateBuffer(cmd, buffers.updateList.buffer, (offset + first) * sizeof(uint32_t), count * sizeof(uint32_t),
                          list.data() + first);
    }
}

}  // namespace

Status prepareGrid(const VulkanContext& ctx, PlanPass& pass, PlanBuffers& buffers, uint32_t factor) {
    if (Status s = prepareGrid(ctx, pass, buffers, uniformGridFactors(buffers.data, factor)); !s) return s;
    buffers.gridLayout.uniformRequest = factor;
    return success();
}

Status prepareGrid(const VulkanContext& ctx, PlanPass& pass, PlanBuffers& buffers, GridFactors factors) {
    buffers.adaptiveInputs = {};  // factors from elsewhere: the next adaptive frame chooses whole
    if (!buffers.gridLayout.subfaceOffset.empty() && buffers.gridLayout.factors == factors) return success();
    if (Status s = installGridLayout(ctx, pass, buffers, buildGridLayout(buffers.data, std::move(factors))); !s) return s;
    buffers.gridEvaluator = GridEvaluator::None;
    buffers.pendingGridSubfaces.clear();
    invalidateSampleCulling(buffers.sampleCulling);
    return success();
}

Status installGridLayout(const VulkanContext& ctx, PlanPass& pass, PlanBuffers& buffers, GridLayout layout) {
    const VkDeviceSize gridBytes = VkDeviceSize(layout.slotCount()) * sizeof(GridVertex);
    std::vector<glm::uvec2> subfaceGrid(buffers.data.subfaces.size());
    for (uint32_t d = 0; d < subfaceGrid.size(); ++d)
        subfaceGrid[d] = {layout.factors.subfaceFactor[d], layout.subfaceOffset[d]};
    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    const std::tuple<Buffer*, VkDeviceSize, VkBufferUsageFlags> sizes[] = {
        {&buffers.grid, gridBytes, storage | VK_BUFFER_USAGE_VERTEX_BUFFER_BIT},
        // Read by the device's grid evaluation only (not with hostEvaluation: a placeholder).
        {&buffers.gridSource, buffers.data.hostEvaluation ? 0 : layout.source.size() * sizeof(uint32_t), storage},
        {&buffers.slotSubface, layout.slotSubface.size() * sizeof(uint32_t), storage},
        {&buffers.subfaceGrid, subfaceGrid.size() * sizeof(glm::uvec2), storage},
        {&buffers.gridIndices, layout.indices.size() * sizeof(uint32_t), VkBufferUsageFlags(VK_BUFFER_USAGE_INDEX_BUFFER_BIT)},
        {&buffers.gridCulledIndices, buffers.data.hostEvaluation ? layout.indices.size() * sizeof(uint32_t) : 0,
         VkBufferUsageFlags(VK_BUFFER_USAGE_INDEX_BUFFER_BIT)}};
    for (auto [buffer, bytes, usage] : sizes)
        if (Status s = ensureCapacity(ctx, *buffer, bytes, usage); !s) return s;
    if (!buffers.data.hostEvaluation) uploadVector(buffers.gridSource, layout.source);
    uploadVector(buffers.slotSubface, layout.slotSubface);
    uploadVector(buffers.subfaceGrid, subfaceGrid);
    uploadVector(buffers.gridIndices, layout.indices);
    buffers.gridLayout = std::move(layout);
    return bindPlanBuffers(ctx, pass, buffers);
}

Status installGridIndices(const VulkanContext& ctx, PlanPass& pass, PlanBuffers& buffers) {
    const std::vector<uint32_t>& indices = buffers.gridLayout.indices;
    const VkBuffer before = buffers.gridIndices.buffer;
    if (Status s = ensureCapacity(ctx, buffers.gridIndices, indices.size() * sizeof(uint32_t), VK_BUFFER_USAGE_INDEX_BUFFER_BIT); !s)
        return s;
    if (buffers.data.hostEvaluation)
        if (Status s = ensureCapacity(ctx, buffers.gridCulledIndices, indices.size() * sizeof(uint32_t), VK_BUFFER_USAGE_INDEX_BUFFER_BIT); !s)
            return s;
    uploadVector(buffers.gridIndices, indices);
    invalidateSampleCulling(buffers.sampleCulling);
    return buffers.gridIndices.buffer == before ? success() : bindPlanBuffers(ctx, pass, buffers);
}

GridFactors adaptiveGridFactors(const PlanBuffers& buffers, const PlanView& view, const TessellationSettings& settings) {
    const AdaptiveView adaptive{view.viewProjection, view.pixelsPerUnit, settings.pixelsPerSegment};
    const bool laidOut = !buffers.gridLayout.subfaceOffset.empty();
    return adaptiveGridFactors(buffers.data, buffers.pointPositionsHost, adaptive,
                               laidOut ? &buffers.gridLayout.factors : nullptr);
}

void recordGridEvaluation(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers) {
    assert(!buffers.gridLayout.subfaceOffset.empty() && "prepareGrid first");
    recordStencils(cmd, pass, buffers, stencilLevelFor(buffers.gridLayout.maxFactor));
    const uint32_t count = uint32_t(buffers.data.subfaces.size());
    dispatchGridPhase(cmd, pass, buffers, count, 0, kWholeCage);
    dispatchGridPhase(cmd, pass, buffers, count, 1, kWholeCage);
    buffers.pendingGridSubfaces.clear();
    // Tests read the grid back on the host.
    memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                  VK_ACCESS_2_HOST_READ_BIT);
    buffers.gridEvaluator = GridEvaluator::Gpu;
}

void evaluateGridOnCpu(const PlannedCage& planned, PlanBuffers& buffers) {
    assert(!buffers.gridLayout.subfaceOffset.empty() && "prepareGrid first");
    if (buffers.displacement) buffers.gridFrames.resize(buffers.gridLayout);
    else buffers.gridFrames = {};
    evaluateWholeGridOnCpu(planned, buffers.data, buffers.gridLayout, static_cast<GridVertex*>(buffers.grid.data),
                           buffers.displacement, buffers.displacement ? &buffers.gridFrames : nullptr);
    buffers.gridEvaluator = GridEvaluator::Cpu;
    buffers.pendingGridSubfaces.clear();
    invalidateSampleCulling(buffers.sampleCulling);
}

namespace {

// Index ranges (first, count) of one indexed draw; every index of the buffer when `ranges` is empty.
struct TriangleDraw {
    VkBuffer indices = VK_NULL_HANDLE;
    uint32_t indexCount = 0;
    std::span<const std::pair<uint32_t, uint32_t>> ranges;
};

// Indexed GridVertex triangles into `target` (cleared), shaded as the view asks: the surface
// from `surface`, the wireframe over it (when the view asks for one) from `wire`.
void recordTriangles(VkCommandBuffer cmd, const PlanPass& pass, VkBuffer vertices, const TriangleDraw& surface,
                     const TriangleDraw& wire, const RenderTarget& target, const PlanView& view) {
    assert(pass.colorFormat == target.colorFormat && pass.depthFormat == target.depthFormat);
    beginRendering(cmd, target, view.clear, view.background);
    PlanDrawPush push = planDrawPush(view, nullptr);
    push.capture = 0;
    const VkPipeline surfacePipeline = view.colorBy == ColorBy::Shading ? pass.gridTriangles : pass.gridColored;
    for (VkPipeline pipeline : {surfacePipeline, view.wireframe ? pass.gridWire : VkPipeline(VK_NULL_HANDLE)}) {
        const TriangleDraw& draw = pipeline == surfacePipeline ? surface : wire;
        if (!pipeline || draw.indexCount == 0) continue;
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pass.drawLayout, 0, 1, &pass.set, 0, nullptr);
        vkCmdBindIndexBuffer(cmd, draw.indices, 0, VK_INDEX_TYPE_UINT32);
        const VkDeviceSize offset = 0;
        vkCmdBindVertexBuffers(cmd, 0, 1, &vertices, &offset);
        PlanDrawPush p = push;
        if (pipeline == pass.gridWire) p.colorMode = 0xffffffffu;
        vkCmdPushConstants(cmd, pass.drawLayout, kPlanDrawStages, 0, sizeof(p), &p);
        if (draw.ranges.empty()) vkCmdDrawIndexed(cmd, draw.indexCount, 1, 0, 0, 0);
        for (const auto& [first, count] : draw.ranges)
            if (count) vkCmdDrawIndexed(cmd, count, 1, first, 0, 0);
    }
    vkCmdEndRendering(cmd);
}

// The ranges (first index, count) of the layout's indices a draw of `view` covers: empty for
// every index, {0, 0} for none.
std::vector<std::pair<uint32_t, uint32_t>> drawnIndexRanges(const PlanBuffers& buffers, const PlanView& view) {
    std::vector<std::pair<uint32_t, uint32_t>> ranges;
    if (!view.hiddenDrawn.empty() || !view.culledDrawn.empty() || !buffers.holeDrawn.empty()) {
        const std::vector<uint32_t>& indexOffset = buffers.gridLayout.indexOffset;
        for (const DrawnRun& run : drawnRuns(buffers, skippedDrawn(buffers, view, true)))
            ranges.push_back({indexOffset[run.begin], indexOffset[run.end] - indexOffset[run.begin]});
        if (ranges.empty()) ranges.push_back({0, 0});  // everything hidden
    }
    return ranges;
}

TriangleDraw wholeGrid(const PlanBuffers& buffers, std::span<const std::pair<uint32_t, uint32_t>> ranges) {
    return {buffers.gridIndices.buffer, uint32_t(buffers.gridLayout.indices.size()), ranges};
}

}  // namespace

void recordGridDraw(VkCommandBuffer cmd, const PlanPass& pass, const PlanBuffers& buffers, const RenderTarget& target,
                    const PlanView& view) {
    assert(buffers.gridEvaluator != GridEvaluator::None && "fill the grid first");
    const std::vector<std::pair<uint32_t, uint32_t>> ranges = drawnIndexRanges(buffers, view);
    recordTriangles(cmd, pass, buffers.grid.buffer, wholeGrid(buffers, ranges), wholeGrid(buffers, ranges), target, view);
}

void recordShadedTriangles(VkCommandBuffer cmd, const PlanPass& pass, VkBuffer vertices, VkBuffer indices,
                           uint32_t indexCount, const RenderTarget& target, const PlanView& view) {
    PlanView shaded = view;
    shaded.colorBy = ColorBy::Shading;
    const TriangleDraw all{indices, indexCount, {}};
    recordTriangles(cmd, pass, vertices, all, all, target, shaded);
}


namespace {

// Writes the lists a partial update dispatches over: `evaluate` at 0, `copy` after it. The lists
// are recorded into the command buffer, so updates in flight never see another's.
void recordUpdateLists(VkCommandBuffer cmd, const PlanBuffers& buffers, const std::vector<uint32_t>& evaluate,
                       const std::vector<uint32_t>& copy) {
    memoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                  VK_ACCESS_2_TRANSFER_WRITE_BIT);
    recordListUpload(cmd, buffers, evaluate, 0);
    if (!copy.empty()) recordListUpload(cmd, buffers, copy, uint32_t(evaluate.size()));
    memoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                  VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
}

// Phase 1 over the first `evaluated` entries of the update list, phase 2 over the `copied` after them.
void dispatchGridPhases(VkCommandBuffer cmd, const PlanPass& pass, const PlanBuffers& buffers, uint32_t evaluated,
                        uint32_t copied) {
    dispatchGridPhase(cmd, pass, buffers, evaluated, 0, 0);
    dispatchGridPhase(cmd, pass, buffers, copied, 1, evaluated);
}

// The compute shader's part of a partial grid update.
void recordGpuGridRefresh(VkCommandBuffer cmd, const PlanPass& pass, const PlanBuffers& buffers,
                          const std::vector<uint32_t>& evaluate, const std::vector<uint32_t>& copy) {
    recordUpdateLists(cmd, buffers, evaluate, copy);
    dispatchGridPhases(cmd, pass, buffers, uint32_t(evaluate.size()), uint32_t(copy.size()));
}

struct GridRefresh {
    uint32_t controlPointSubfaces = 0, evaluatedSubfaces = 0, copiedSubfaces = 0;
};

MoveUpdate withRefresh(MoveUpdate update, const GridRefresh& refresh) {
    update.controlPointSubfaces = refresh.controlPointSubfaces;
    update.evaluatedSubfaces = refresh.evaluatedSubfaces;
    update.copiedSubfaces = refresh.copiedSubfaces;
    return update;
}

// Brings what is cached up to date for the drawn sub-faces `touched`: their control points
// (when `controlPoints`), their grid slots and the neighbours' copies of their edge vertices.
GridRefresh recordGridRefresh(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers, const PlannedCage& planned,
                              const std::vector<uint32_t>& touched, bool controlPoints) {
    GridRefresh update;
    const std::vector<uint32_t> copying =
        buffers.gridEvaluator == GridEvaluator::None ? std::vector<uint32_t>{} : withDependents(buffers.gridLayout, touched);
    if (touched.empty()) return update;

    const uint32_t touchedCount = uint32_t(touched.size());
    if (controlPoints || buffers.gridEvaluator == GridEvaluator::Gpu)
        recordUpdateLists(cmd, buffers, touched, buffers.gridEvaluator == GridEvaluator::Gpu ? copying : std::vector<uint32_t>{});
    if (controlPoints) {
        dispatchPerSubface(cmd, pass, pass.stencils, PlanComputePush{touchedCount, buffers.controlPointLevel, 0, 0});
        computeWritesBeforeReads(cmd);
        update.controlPointSubfaces = touchedCount;
    }
    if (buffers.gridEvaluator == GridEvaluator::Gpu) {
        dispatchGridPhases(cmd, pass, buffers, touchedCount, uint32_t(copying.size()));
    } else if (buffers.gridEvaluator == GridEvaluator::Cpu) {
        evaluateGridOnCpu(planned, buffers.data, buffers.gridLayout, touched, copying,
                          static_cast<GridVertex*>(buffers.grid.data), buffers.displacement,
                          buffers.displacement ? &buffers.gridFrames : nullptr);
        markSlotsChanged(buffers.sampleCulling, buffers.gridLayout, touched);
        markSlotsChanged(buffers.sampleCulling, buffers.gridLayout, copying);
    }
    if (buffers.gridEvaluator != GridEvaluator::None) {
        update.evaluatedSubfaces = touchedCount;
        update.copiedSubfaces = uint32_t(copying.size());
    }
    return update;
}

}  // namespace

void recordGrid(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers, const RenderTarget& target,
                const PlanView& view) {
    if (buffers.gridEvaluator == GridEvaluator::None) recordGridEvaluation(cmd, pass, buffers);
    else recordPendingGridRefresh(cmd, pass, buffers);
    const std::vector<std::pair<uint32_t, uint32_t>> ranges = drawnIndexRanges(buffers, view);
    const TriangleDraw whole = wholeGrid(buffers, ranges);
    SampleCulling& culling = buffers.sampleCulling;
    const size_t indexBytes = buffers.gridLayout.indices.size() * sizeof(uint32_t);
    const double pixels = double(target.area.extent.width) * double(target.area.extent.height);
    // Not with a displacement: sculpting dabs all over a dense grid re-test many chunks a frame,
    // and the editor's sculpt frames were slower with it (docs/renderer.md).
    const bool dense = double(buffers.gridLayout.indices.size() / 3) > culling.minTrianglesPerPixel * pixels;
    culling.inUse = view.sampleCulling && buffers.gridEvaluator == GridEvaluator::Cpu && !buffers.displacement &&
                    indexBytes > 0 && buffers.gridCulledIndices.size >= indexBytes && buffers.gridCulledIndices.data &&
                    (dense || view.backFacesHidden);
    if (!culling.inUse) return recordTriangles(cmd, pass, buffers.grid.buffer, whole, whole, target, view);
    const SampleView sampleView{view.viewProjection,
                                target.area.offset.x,
                                target.area.offset.y,
                                target.area.extent.width,
                                target.area.extent.height,
                                dense,
                                view.backFacesHidden,
                                view.backFacesHidden ? view.eye : glm::vec4(0.0f)};
    std::vector<std::pair<uint32_t, uint32_t>> draws =
        updateSampleCulling(culling, buffers.gridLayout, static_cast<const GridVertex*>(buffers.grid.data), sampleView, ranges,
                            static_cast<uint32_t*>(buffers.gridCulledIndices.data));
    if (draws.empty()) draws.push_back({0, 0});  // nothing covers a pixel centre
    const TriangleDraw kept{buffers.gridCulledIndices.buffer, uint32_t(buffers.gridLayout.indices.size()), draws};
    recordTriangles(cmd, pass, buffers.grid.buffer, kept, whole, target, view);
}

void recordPendingGridRefresh(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers) {
    if (buffers.pendingGridSubfaces.empty()) return;
    const std::vector<uint32_t> pending = std::exchange(buffers.pendingGridSubfaces, {});
    recordStencils(cmd, pass, buffers, stencilLevelFor(buffers.gridLayout.maxFactor));  // raised factors may go deeper
    recordGpuGridRefresh(cmd, pass, buffers, pending, withDependents(buffers.gridLayout, pending));
}

MoveUpdate recordMovedVertices(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers,
                               const PlannedCage& planned, std::span<const uint32_t> vertices) {
    MoveUpdate update;
    update.movedVertices = uint32_t(vertices.size());
    const bool onDevice = !buffers.data.hostEvaluation;  // the device's copies (uploadPlans)
    for (uint32_t v : vertices) {
        const glm::vec3& p = planned.cage().positions[v];
        const float xyz[3] = {p.x, p.y, p.z};
        if (onDevice) uploadBuffer(buffers.positions, xyz, sizeof xyz, size_t(v) * sizeof xyz);
    }
    for (uint32_t id : boundaryPointsAround(planned, vertices)) {
        buffers.pointPositionsHost[id] = boundaryPointPosition(planned, id);
        if (onDevice)
            uploadBuffer(buffers.pointPositions, &buffers.pointPositionsHost[id], sizeof(glm::vec4), size_t(id) * sizeof(glm::vec4));
    }
    const std::vector<uint32_t> touched = subfacesAround(buffers.data, vertices);
    if (buffers.adaptiveInputs.valid) {  // their edges' factors are chosen again at the next frame
        std::vector<uint32_t> merged;
        std::set_union(buffers.movedSinceFactors.begin(), buffers.movedSinceFactors.end(), touched.begin(), touched.end(),
                       std::back_inserter(merged));
        buffers.movedSinceFactors = std::move(merged);
    }
    const bool controlPoints = buffers.controlPointLevel != kNoControlPoints;
    if (!controlPoints && buffers.gridEvaluator != GridEvaluator::Cpu) {
        buffers.gridEvaluator = GridEvaluator::None;  // re-evaluated whole, control points first
        return update;
    }
    return withRefresh(update, recordGridRefresh(cmd, pass, buffers, planned, touched, controlPoints));
}

MoveUpdate recordSubfaceRefresh(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers,
                                const PlannedCage& planned, const std::vector<uint32_t>& drawn) {
    MoveUpdate update;
    const bool controlPoints = buffers.controlPointLevel != kNoControlPoints;
    if (!controlPoints && buffers.gridEvaluator == GridEvaluator::Gpu) {
        buffers.gridEvaluator = GridEvaluator::None;  // re-evaluated whole, control points first
        return update;
    }
    return withRefresh(update, recordGridRefresh(cmd, pass, buffers, planned, drawn, controlPoints));
}

Status setPlanDisplacement(const VulkanContext& ctx, PlanPass& pass, PlanBuffers& buffers,
                           const Displacement* displacement) {
    if (displacement && displacement->empty()) displacement = nullptr;
    if (displacement && displacement->layout.tiles.size() != buffers.drawnOfSubface.size() &&
        !buffers.drawnOfSubface.empty())
        return Error{"the displacement does not match the cage (" + std::to_string(displacement->layout.tiles.size()) +
                     " sub-faces, the cage has " + std::to_string(buffers.drawnOfSubface.size()) + ")"};
    const std::vector<uint32_t> none;
    Result<Buffer> tiles = displacement ? createFilled(ctx, displacement->layout.tiles) : createFilled(ctx, none);
    Result<Buffer> padded = displacement ? createFilled(ctx, displacement->layout.padded) : createFilled(ctx, none);
    Result<Buffer> samples = displacement ? createFilled(ctx, displacement->samples) : createFilled(ctx, none);
    if (!tiles || !padded || !samples) {
        for (Result<Buffer>* r : {&tiles, &padded, &samples})
            if (*r) destroyBuffer(ctx, **r);
        return !tiles ? tiles.error() : !padded ? padded.error() : samples.error();
    }
    destroyBuffer(ctx, buffers.displacementTiles);
    destroyBuffer(ctx, buffers.displacementPadded);
    destroyBuffer(ctx, buffers.displacementSamples);
    buffers.displacementTiles = *tiles;
    buffers.displacementPadded = *padded;
    buffers.displacementSamples = *samples;
    buffers.displacement = displacement;
    buffers.displacementUsers = displacement ? buildDisplacementUsers(displacement->layout) : DisplacementUsers{};
    buffers.gridEvaluator = GridEvaluator::None;
    buffers.adaptiveInputs = {};  // the factors were (or will be) raised for the tiles
    return bindPlanBuffers(ctx, pass, buffers);
}

DisplacementUpdate recordDisplacementChange(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers,
                                            const PlannedCage& planned, std::span<const uint32_t> samples) {
    DisplacementUpdate update;
    if (!buffers.displacement) return update;
    const std::vector<float>& values = buffers.displacement->samples;
    // One bit per sample, marked once and read in sample order by everything below (a big
    // dab's list is in spatial order: scattered over the samples).
    SampleBits& changed = buffers.changedSamples;
    changed.assign(uint32_t(values.size()), samples);
    for (const SampleRange& range : uploadRanges(changed)) {
        uploadBuffer(buffers.displacementSamples, values.data() + range.first, range.count * sizeof(float),
                     size_t(range.first) * sizeof(float));
        update.uploadedSamples += range.count;
    }
    if (buffers.gridEvaluator == GridEvaluator::None) return update;  // evaluated whole when drawn
    std::vector<uint32_t> touched;
    for (uint32_t s : subfacesReadingSamples(buffers.displacement->layout, buffers.displacementUsers, changed))
        if (buffers.drawnOfSubface[s] != UINT32_MAX) touched.push_back(buffers.drawnOfSubface[s]);
    std::sort(touched.begin(), touched.end());
    if (buffers.gridEvaluator == GridEvaluator::Cpu) {
        // The surface did not move: re-displace the kept frames where D changed, no evaluation.
        const std::vector<uint32_t> copying = withDependents(buffers.gridLayout, touched);
        update.displacedSlots = redisplaceGridOnCpu(buffers.data, buffers.gridLayout, touched, copying, *buffers.displacement,
                                                    changed, buffers.gridFrames, static_cast<GridVertex*>(buffers.grid.data));
        markSlotsChanged(buffers.sampleCulling, buffers.gridLayout, touched);
        markSlotsChanged(buffers.sampleCulling, buffers.gridLayout, copying);
        update.evaluatedSubfaces = uint32_t(touched.size());
        update.copiedSubfaces = uint32_t(copying.size());
        return update;
    }
    const GridRefresh refresh = recordGridRefresh(cmd, pass, buffers, planned, touched, false);
    update.evaluatedSubfaces = refresh.evaluatedSubfaces;
    update.copiedSubfaces = refresh.copiedSubfaces;
    return update;
}

}  // namespace qp
