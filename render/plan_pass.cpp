// The plans renderer (plan_pass.h): buffers, the pass and its bindings, the tessellated path and
// the capture buffer; the grid paths are in plan_grid_path.cpp.
#include "plan_pass.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <iterator>
#include <type_traits>
#include <utility>

#include "cpu_grid.h"
#include "pipeline_builder.h"
#include "plan_pass_support.h"
#include "plan_pipelines.h"
#include "shared_pipelines.h"
#include "vk_check.h"
#include "vk_commands.h"

namespace qp {

namespace {

constexpr uint32_t kMaxGroupsPerRow = 65535;
constexpr uint32_t kCaptureHeaderBytes = 16;

// The pass's own descriptor set (one cage per pass).
Status allocateSet(const VulkanContext& ctx, PlanPass& pass) {
    const VkDescriptorPoolSize poolSize = pass.byAddress ? VkDescriptorPoolSize{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1}
                                                         : VkDescriptorPoolSize{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kPlanBufferCount};
    return createDescriptorSet(ctx, pass.setLayout, poolSize, pass.pool, pass.set);
}

constexpr VkPipelineStageFlags2 kShaderStagesReading =
    VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_TESSELLATION_CONTROL_SHADER_BIT |
    VK_PIPELINE_STAGE_2_TESSELLATION_EVALUATION_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT |
    VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;

}  // namespace

void dispatchPerSubface(VkCommandBuffer cmd, const PlanPass& pass, VkPipeline pipeline, PlanComputePush push) {
    const uint32_t count = push.subfaceCount;
    if (count == 0) return;
    push.groupsPerRow = std::min(count, kMaxGroupsPerRow);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pass.computeLayout, 0, 1, &pass.set, 0, nullptr);
    vkCmdPushConstants(cmd, pass.computeLayout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    vkCmdDispatch(cmd, push.groupsPerRow, (count + push.groupsPerRow - 1) / push.groupsPerRow, 1);
}

void computeWritesBeforeReads(VkCommandBuffer cmd) {
    memoryBarrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                  kShaderStagesReading | VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT,
                  VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT);
}

void recordStencils(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers, uint32_t level) {
    assert(!buffers.data.hostEvaluation && "these buffers hold no stencils: the CPU grid path evaluates on the host");
    // Displaced corners are shaded from derivatives kCornerNormalStep inside (cpu_grid.h): a
    // parameter of factor 64, which needs the deepest control points.
    if (buffers.displacement) level = std::max(level, stencilLevelFor(uint32_t(1.0f / kCornerNormalStep)));
    if (buffers.controlPointLevel != kNoControlPoints && buffers.controlPointLevel >= level) return;
    dispatchPerSubface(cmd, pass, pass.stencils, PlanComputePush{uint32_t(buffers.data.subfaces.size()), level, 0, kWholeCage});
    computeWritesBeforeReads(cmd);
    buffers.controlPointLevel = level;
}

PlanDrawPush planDrawPush(const PlanView& view, const TessellationSettings* settings) {
    PlanDrawPush push{};
    push.viewProjection = view.viewProjection;
    push.uniformFactor = settings ? float(settings->uniformFactor) : 0.0f;
    push.pixelsPerSegment = settings ? settings->pixelsPerSegment : 8.0f;
    push.pixelsPerUnit = view.pixelsPerUnit;
    // plan_lighting.glsl: bit 8 of the colour mode selects the matcap.
    push.colorMode = uint32_t(view.colorBy) | (view.shading == Shading::Matcap ? 0x100u : 0u);
    push.capture = view.capture ? 1u : 0u;
    push.keyLight = glm::vec4(view.keyLight, 0.0f);
    push.fillLight = glm::vec4(view.fillLight, 0.0f);
    return push;
}

void updateHoleDrawn(PlanBuffers& buffers, const PlannedCage& planned) {
    buffers.holeDrawn.clear();
    for (uint32_t face : planned.cage().holes)  // sorted faces: their sub-faces ascend, and so do drawn indices
        for (uint32_t s = planned.firstSubface(face); s < planned.firstSubface(face + 1); ++s)
            if (buffers.drawnOfSubface[s] != UINT32_MAX) buffers.holeDrawn.push_back(buffers.drawnOfSubface[s]);
}

std::vector<DrawnRun> drawnRuns(const PlanBuffers& buffers, std::span<const uint32_t> hidden) {
    std::vector<uint32_t> skipped;
    std::set_union(hidden.begin(), hidden.end(), buffers.holeDrawn.begin(), buffers.holeDrawn.end(), std::back_inserter(skipped));
    const uint32_t count = uint32_t(buffers.data.subfaces.size());
    std::vector<DrawnRun> runs;
    uint32_t begin = 0;
    for (uint32_t d : skipped) {
        if (d >= count) break;
        if (d > begin) runs.push_back({begin, d});
        begin = std::max(begin, d + 1);
    }
    if (begin < count) runs.push_back({begin, count});
    return runs;
}

std::vector<uint32_t> skippedDrawn(const PlanBuffers& buffers, const PlanView& view, bool gridMacros) {
    if (view.culledDrawn.empty()) return {view.hiddenDrawn.begin(), view.hiddenDrawn.end()};
    const std::vector<uint32_t> culled =
        gridMacros ? culledForDrawing(buffers.data.macros, buffers.gridLayout.factors, view.culledDrawn)
                   : std::vector<uint32_t>(view.culledDrawn.begin(), view.culledDrawn.end());
    std::vector<uint32_t> skipped;
    std::set_union(view.hiddenDrawn.begin(), view.hiddenDrawn.end(), culled.begin(), culled.end(), std::back_inserter(skipped));
    return skipped;
}

Result<PlanBuffers> uploadPlans(const VulkanContext& ctx, const PlannedCage& planned, MacroChoice macros,
                                bool hostEvaluation) {
    PlanBuffers b;
    b.data = packPlans(planned, hostEvaluation);
    b.data.macros.choice = macros;
    rebuildMacroGrid(planned, b.data);
    b.pointPositionsHost = boundaryPointPositions(planned);
    const GpuPlanData& d = b.data;
    const std::vector<uint32_t> placeholder(4, 0);
    // What only the device's evaluation and tessellator read: nothing with hostEvaluation.
    auto forDevice = [hostEvaluation](const auto& table) -> const std::decay_t<decltype(table)>& {
        static const std::decay_t<decltype(table)> none;
        return hostEvaluation ? none : table;
    };
    struct Item {
        Buffer& buffer;
        Result<Buffer> result;
    };
    Item items[] = {
        {b.planHeaders, createFilled(ctx, d.plans)},
        {b.nodes, createFilled(ctx, d.nodes)},
        {b.points, createFilled(ctx, d.points)},  // empty with hostEvaluation, as are the weights
        {b.weights, createFilled(ctx, d.weights)},
        {b.subfaces, createFilled(ctx, d.subfaces)},
        {b.rings, createFilled(ctx, forDevice(d.rings))},
        {b.positions, createFilled(ctx, hostEvaluation ? std::vector<float>{} : cagePositions(planned))},
        // Written by the stencil pass before anything reads them (967 MiB at a million faces);
        // none with hostEvaluation (an edit that relocated a sub-face's range once grew and
        // copied it whole: 3.3 s and 2.4 GB touched at the first crease of a million faces).
        {b.controlPoints,
         createBuffer(ctx, std::max<VkDeviceSize>(hostEvaluation ? 0 : VkDeviceSize(d.controlPointCount) * sizeof(glm::vec4), 16),
                      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT)},
        {b.boundaries, createFilled(ctx, forDevice(d.boundaries))},
        {b.segments, createFilled(ctx, forDevice(d.segments))},
        {b.boundaryPoints, createFilled(ctx, forDevice(d.boundaryPoints))},
        {b.pointPositions, createFilled(ctx, forDevice(b.pointPositionsHost))},
        {b.capture, createFilled(ctx, placeholder, VK_BUFFER_USAGE_TRANSFER_DST_BIT)},
        // The grid's buffers get their sizes from prepareGrid.
        {b.subfaceGrid, createFilled(ctx, placeholder)},
        {b.grid, createFilled(ctx, placeholder, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT)},
        {b.gridSource, createFilled(ctx, placeholder)},
        {b.slotSubface, createFilled(ctx, placeholder)},
        {b.gridIndices, createFilled(ctx, placeholder, VK_BUFFER_USAGE_INDEX_BUFFER_BIT)},
        {b.gridCulledIndices, createFilled(ctx, placeholder, VK_BUFFER_USAGE_INDEX_BUFFER_BIT)},
        // A partial update of the device's evaluation lists its sub-faces twice at most (phase 1,
        // then phase 2).
        {b.updateList, createFilled(ctx, std::vector<uint32_t>(hostEvaluation ? 4 : 2 * d.subfaces.size() + 4),
                                    VK_BUFFER_USAGE_TRANSFER_DST_BIT)},
        // No displacement until setPlanDisplacement: placeholders smaller than one record.
        {b.displacementTiles, createFilled(ctx, std::vector<uint32_t>{})},
        {b.displacementPadded, createFilled(ctx, std::vector<uint32_t>{})},
        {b.displacementSamples, createFilled(ctx, std::vector<uint32_t>{})},
        {b.addresses, createBuffer(ctx, sizeof(PlanAddresses), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT)},
    };
    b.drawnOfSubface.assign(planned.subfaceCount(), UINT32_MAX);
    for (uint32_t drawn = 0; drawn < d.subfaces.size(); ++drawn) b.drawnOfSubface[d.subfaces[drawn].subface] = drawn;
    updateHoleDrawn(b, planned);
    for (Item& item : items) {
        if (!item.result) {
            Error error = item.result.error();
            for (Item& other : items)
                if (other.result) destroyBuffer(ctx, *other.result);
            return error;
        }
        item.buffer = *item.result;
    }
    return b;
}

void updatePositions(PlanBuffers& buffers, const PlannedCage& planned) {
    buffers.pointPositionsHost = boundaryPointPositions(planned);
    if (!buffers.data.hostEvaluation) {
        std::vector<float> positions = cagePositions(planned);
        assert(positions.size() * sizeof(float) <= buffers.positions.size);
        uploadBuffer(buffers.positions, positions.data(), positions.size() * sizeof(float));
        uploadBuffer(buffers.pointPositions, buffers.pointPositionsHost.data(),
                     buffers.pointPositionsHost.size() * sizeof(glm::vec4));
    }
    buffers.controlPointLevel = kNoControlPoints;
    buffers.gridEvaluator = GridEvaluator::None;
    buffers.adaptiveInputs = {};  // every point may have moved
}

void destroyPlanBuffers(const VulkanContext& ctx, PlanBuffers& b) {
    for (Buffer* buffer : {&b.planHeaders, &b.nodes, &b.points, &b.weights, &b.subfaces, &b.rings, &b.positions,
                           &b.controlPoints, &b.boundaries, &b.segments, &b.boundaryPoints, &b.pointPositions, &b.capture,
                           &b.subfaceGrid, &b.grid, &b.gridSource, &b.slotSubface, &b.gridIndices, &b.gridCulledIndices, &b.updateList,
                           &b.displacementTiles, &b.displacementPadded, &b.displacementSamples, &b.addresses})
        destroyBuffer(ctx, *buffer);
    b = PlanBuffers{};
}

Result<PlanPass> createPlanPass(const VulkanContext& ctx, VkPipelineCache cache, VkFormat colorFormat,
                                VkFormat depthFormat, bool byAddress) {
    Result<PlanPass> shared = sharedPass<PlanPass>(
        ctx, sharedPassKey(byAddress ? "plan-by-address" : "plan", colorFormat, depthFormat), colorFormat, depthFormat,
        [&](PlanPass& pipelines) {
            pipelines.byAddress = byAddress;
            return createPlanPipelines(ctx, cache, pipelines);
        },
        destroyPlanPipelines);
    if (!shared) return shared.error();
    PlanPass pass = *shared;
    pass.cache = cache;
    pass.alwaysByAddress = byAddress;
    if (Status s = allocateSet(ctx, pass); !s) {
        destroyPlanPass(ctx, pass);
        return s.error();
    }
    return pass;
}

void destroyPlanPass(const VulkanContext& ctx, PlanPass& pass) {
    if (pass.pool) vkDestroyDescriptorPool(ctx.device, pass.pool, nullptr);
    pass = PlanPass{};  // the pipelines and layouts are the device's (shared_pipelines.h)
}

Status bindPlanBuffers(const VulkanContext& ctx, PlanPass& pass, const PlanBuffers& b) {
    // In the order of the shaders' bindings (shaders/plan_buffers.glsl).
    const Buffer* order[kPlanBufferCount] = {&b.planHeaders, &b.nodes,      &b.points,       &b.weights,     &b.subfaces,
                                          &b.rings,       &b.positions,  &b.controlPoints, &b.grid,       &b.boundaries,
                                          &b.segments,    &b.boundaryPoints, &b.subfaceGrid, &b.pointPositions,
                                          &b.capture,     &b.updateList, &b.gridSource,   &b.slotSubface,
                                          &b.displacementTiles, &b.displacementPadded, &b.displacementSamples};
    const bool byAddress = pass.alwaysByAddress || std::any_of(std::begin(order), std::end(order), [&](const Buffer* buffer) {
        return buffer->size > ctx.properties.limits.maxStorageBufferRange;
    });
    if (byAddress != pass.byAddress) {
        Result<PlanPass> other = createPlanPass(ctx, pass.cache, pass.colorFormat, pass.depthFormat, byAddress);
        if (!other) return other.error();
        destroyPlanPass(ctx, pass);
        pass = *other;
    }
    if (!byAddress) {
        VkDescriptorBufferInfo infos[kPlanBufferCount];
        VkWriteDescriptorSet writes[kPlanBufferCount];
        for (uint32_t i = 0; i < kPlanBufferCount; ++i) {
            infos[i] = {order[i]->buffer, 0, VK_WHOLE_SIZE};
            writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, nullptr, pass.set, i, 0, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                         nullptr, &infos[i], nullptr};
        }
        vkUpdateDescriptorSets(ctx.device, kPlanBufferCount, writes, 0, nullptr);
        return success();
    }
    PlanAddresses addresses{};
    for (uint32_t i = 0; i < kPlanBufferCount; ++i) {
        assert(order[i]->address && "a storage buffer");
        addresses.buffers[i] = order[i]->address;
    }
    addresses.controlPointCount = uint32_t(b.controlPoints.size / sizeof(glm::vec4));
    addresses.dispPaddedCount = uint32_t(b.displacementPadded.size / sizeof(uint32_t));
    uploadBuffer(b.addresses, &addresses, sizeof addresses);
    const VkDescriptorBufferInfo info{b.addresses.buffer, 0, sizeof(PlanAddresses)};
    const VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, nullptr, pass.set, 0, 0, 1,
                                     VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, nullptr, &info, nullptr};
    vkUpdateDescriptorSets(ctx.device, 1, &write, 0, nullptr);
    return success();
}

float pixelsPerUnit(const glm::mat4& projection, uint32_t viewportHeight) {
    return 0.5f * float(viewportHeight) * std::fabs(projection[1][1]);
}

uint32_t maxTessellationLevel(const TessellationSettings& settings) {
    return stencilLevelFor(settings.uniformFactor == 0 ? 64 : std::min(settings.uniformFactor, 64u));
}

uint32_t patchesPerDraw(uint32_t maxFactor) {
    uint32_t side = maxFactor + 1;
    return std::max(1u, 65535u / (side * side));
}

void recordTessellated(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers, const RenderTarget& target,
                       const PlanView& view, const TessellationSettings& settings) {
    assert(pass.colorFormat == target.colorFormat && pass.depthFormat == target.depthFormat);
    if (view.capture) {
        vkCmdFillBuffer(cmd, buffers.capture.buffer, 0, 4, 0);
        memoryBarrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_2_TESSELLATION_EVALUATION_SHADER_BIT,
                      VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    }
    recordStencils(cmd, pass, buffers, maxTessellationLevel(settings));
    beginRendering(cmd, target, view.clear, view.background);
    const PlanDrawPush push = planDrawPush(view, &settings);
    const uint32_t perDraw = patchesPerDraw(settings.uniformFactor == 0 ? 64 : std::min(settings.uniformFactor, 64u));
    const std::vector<DrawnRun> runs = drawnRuns(buffers, skippedDrawn(buffers, view, false));
    const bool displaced = buffers.displacement != nullptr;
    const VkPipeline solid = displaced ? pass.tessellatedDisplaced : pass.tessellated;
    const VkPipeline wire = displaced ? pass.tessellatedDisplacedWire : pass.tessellatedWire;
    for (VkPipeline pipeline : {solid, view.wireframe ? wire : VkPipeline(VK_NULL_HANDLE)}) {
        if (!pipeline) continue;
        PlanDrawPush p = push;
        if (pipeline == wire) {
            p.colorMode = 0xffffffffu;  // plan.frag: flat wire colour
            p.capture = 0;
        }
        bool firstDraw = true;
        for (const DrawnRun& run : runs)
        for (uint32_t first = run.begin; first < run.end; first += perDraw, firstDraw = false) {
            // Captured draws all append to one buffer: order them (barriers may not sit inside
            // a rendering instance at these stages, so each chunk gets its own).
            if (p.capture && !firstDraw) {
                vkCmdEndRendering(cmd);
                memoryBarrier(cmd, VK_PIPELINE_STAGE_2_TESSELLATION_EVALUATION_SHADER_BIT,
                              VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                              VK_PIPELINE_STAGE_2_TESSELLATION_EVALUATION_SHADER_BIT,
                              VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
                beginRendering(cmd, target, false, view.background);
            }
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pass.drawLayout, 0, 1, &pass.set, 0, nullptr);
            vkCmdPushConstants(cmd, pass.drawLayout, kPlanDrawStages, 0, sizeof(p), &p);
            vkCmdDraw(cmd, std::min(perDraw, run.end - first), 1, first, 0);
        }
    }
    vkCmdEndRendering(cmd);
}


Status enableCapture(const VulkanContext& ctx, PlanBuffers& buffers, uint32_t capacity) {
    Result<Buffer> capture = createBuffer(ctx, kCaptureHeaderBytes + VkDeviceSize(capacity) * sizeof(CaptureRecord),
                                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT);
    if (!capture) return capture.error();
    destroyBuffer(ctx, buffers.capture);
    buffers.capture = *capture;
    buffers.captureCapacity = capacity;
    const uint32_t header[4] = {0, capacity, 0, 0};
    uploadBuffer(buffers.capture, header, sizeof(header));
    return success();
}

std::vector<CaptureRecord> readCapture(const PlanBuffers& buffers, uint32_t* overflowed) {
    uint32_t header[2];
    std::memcpy(header, buffers.capture.data, sizeof(header));
    uint32_t count = std::min(header[0], buffers.captureCapacity);
    if (overflowed) *overflowed = header[0] - count;
    std::vector<CaptureRecord> records(count);
    std::memcpy(records.data(), static_cast<const char*>(buffers.capture.data) + kCaptureHeaderBytes,
                count * sizeof(CaptureRecord));
    return records;
}

}  // namespace qp
