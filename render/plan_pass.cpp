#include "plan_pass.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <utility>
#include <iterator>
#include <tuple>

#include "cpu_grid.h"
#include "displacement/brush.h"  // uploadRanges
#include "plan_pipelines.h"
#include "shared_pipelines.h"
#include "vk_check.h"

namespace qp {

namespace {

constexpr uint32_t kWholeCage = UINT32_MAX;
constexpr uint32_t kMaxGroupsPerRow = 65535;
constexpr uint32_t kCaptureHeaderBytes = 16;

// The pass's own descriptor set (one cage per pass).
Status allocateSet(const VulkanContext& ctx, PlanPass& pass) {
    const VkDescriptorPoolSize poolSize = pass.byAddress ? VkDescriptorPoolSize{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1}
                                                         : VkDescriptorPoolSize{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kPlanBufferCount};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = 1;
    poolInfo.poolSizeCount = 1;
    poolInfo.pPoolSizes = &poolSize;
    VK_CHECK(vkCreateDescriptorPool(ctx.device, &poolInfo, nullptr, &pass.pool));
    VkDescriptorSetAllocateInfo allocInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    allocInfo.descriptorPool = pass.pool;
    allocInfo.descriptorSetCount = 1;
    allocInfo.pSetLayouts = &pass.setLayout;
    VK_CHECK(vkAllocateDescriptorSets(ctx.device, &allocInfo, &pass.set));
    return success();
}

template <class T>
Result<Buffer> createFilled(const VulkanContext& ctx, const std::vector<T>& values, VkBufferUsageFlags extra = 0) {
    // Vulkan buffers cannot be empty; a 16-byte placeholder keeps the descriptor valid.
    VkDeviceSize size = std::max<VkDeviceSize>(values.size() * sizeof(T), 16);
    Result<Buffer> buffer = createBuffer(ctx, size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | extra);
    if (buffer && !values.empty()) uploadBuffer(*buffer, values.data(), values.size() * sizeof(T));
    return buffer;
}

void barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess, VkPipelineStageFlags2 dstStage,
             VkAccessFlags2 dstAccess) {
    VkMemoryBarrier2 memory{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
    memory.srcStageMask = srcStage;
    memory.srcAccessMask = srcAccess;
    memory.dstStageMask = dstStage;
    memory.dstAccessMask = dstAccess;
    VkDependencyInfo dependency{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dependency.memoryBarrierCount = 1;
    dependency.pMemoryBarriers = &memory;
    vkCmdPipelineBarrier2(cmd, &dependency);
}

constexpr VkPipelineStageFlags2 kShaderStagesReading =
    VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_TESSELLATION_CONTROL_SHADER_BIT |
    VK_PIPELINE_STAGE_2_TESSELLATION_EVALUATION_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT |
    VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;

void dispatchPerSubface(VkCommandBuffer cmd, const PlanPass& pass, VkPipeline pipeline, PlanComputePush push) {
    const uint32_t count = push.subfaceCount;
    if (count == 0) return;
    push.groupsPerRow = std::min(count, kMaxGroupsPerRow);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pass.computeLayout, 0, 1, &pass.set, 0, nullptr);
    vkCmdPushConstants(cmd, pass.computeLayout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    vkCmdDispatch(cmd, push.groupsPerRow, (count + push.groupsPerRow - 1) / push.groupsPerRow, 1);
}

// Compute results (control points, grid vertices) before any later shader or vertex fetch.
void computeWritesBeforeReads(VkCommandBuffer cmd) {
    barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
            kShaderStagesReading | VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT,
            VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT);
}

uint32_t levelFor(uint32_t factor) {
    uint32_t level = 0;
    while ((1u << level) < factor) ++level;
    return level;
}

// Control points for factors up to 2^level, visible to every later shader stage; nothing when
// they are cached for that level or a higher one.
void recordStencils(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers, uint32_t level) {
    // Displaced corners are shaded from derivatives kCornerNormalStep inside (cpu_grid.h): a
    // parameter of factor 64, which needs the deepest control points.
    if (buffers.displacement) level = std::max(level, levelFor(uint32_t(1.0f / kCornerNormalStep)));
    if (buffers.controlPointLevel != kNoControlPoints && buffers.controlPointLevel >= level) return;
    dispatchPerSubface(cmd, pass, pass.stencils, PlanComputePush{uint32_t(buffers.data.subfaces.size()), level, 0, kWholeCage});
    computeWritesBeforeReads(cmd);
    buffers.controlPointLevel = level;
}

}  // namespace

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

Result<PlanBuffers> uploadPlans(const VulkanContext& ctx, const PlannedCage& planned, MacroChoice macros) {
    PlanBuffers b;
    b.data = packPlans(planned);
    b.data.macros.choice = macros;
    rebuildMacroGrid(planned, b.data);
    b.pointPositionsHost = boundaryPointPositions(planned);
    const GpuPlanData& d = b.data;
    const std::vector<uint32_t> placeholder(4, 0);
    struct Item {
        Buffer& buffer;
        Result<Buffer> result;
    };
    Item items[] = {
        {b.planHeaders, createFilled(ctx, d.plans)},
        {b.nodes, createFilled(ctx, d.nodes)},
        {b.points, createFilled(ctx, d.points)},
        {b.weights, createFilled(ctx, d.weights)},
        {b.subfaces, createFilled(ctx, d.subfaces)},
        {b.rings, createFilled(ctx, d.rings)},
        {b.positions, createFilled(ctx, cagePositions(planned))},
        // Written by the stencil pass before anything reads them; left untouched, the CPU grid
        // path never makes the pages resident (967 MiB at a million faces).
        {b.controlPoints, createBuffer(ctx, std::max<VkDeviceSize>(VkDeviceSize(d.controlPointCount) * sizeof(glm::vec4), 16),
                                       VK_BUFFER_USAGE_STORAGE_BUFFER_BIT)},
        {b.boundaries, createFilled(ctx, d.boundaries)},
        {b.segments, createFilled(ctx, d.segments)},
        {b.boundaryPoints, createFilled(ctx, d.boundaryPoints)},
        {b.pointPositions, createFilled(ctx, b.pointPositionsHost)},
        {b.capture, createFilled(ctx, placeholder, VK_BUFFER_USAGE_TRANSFER_DST_BIT)},
        // The grid's buffers get their sizes from prepareGrid.
        {b.subfaceGrid, createFilled(ctx, placeholder)},
        {b.grid, createFilled(ctx, placeholder, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT)},
        {b.gridSource, createFilled(ctx, placeholder)},
        {b.slotSubface, createFilled(ctx, placeholder)},
        {b.gridIndices, createFilled(ctx, placeholder, VK_BUFFER_USAGE_INDEX_BUFFER_BIT)},
        // A partial update lists its sub-faces twice at most (phase 1, then phase 2).
        {b.updateList, createFilled(ctx, std::vector<uint32_t>(2 * d.subfaces.size() + 4), VK_BUFFER_USAGE_TRANSFER_DST_BIT)},
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
    std::vector<float> positions = cagePositions(planned);
    assert(positions.size() * sizeof(float) <= buffers.positions.size);
    uploadBuffer(buffers.positions, positions.data(), positions.size() * sizeof(float));
    buffers.pointPositionsHost = boundaryPointPositions(planned);
    uploadBuffer(buffers.pointPositions, buffers.pointPositionsHost.data(), buffers.pointPositionsHost.size() * sizeof(glm::vec4));
    buffers.controlPointLevel = kNoControlPoints;
    buffers.gridEvaluator = GridEvaluator::None;
    buffers.adaptiveInputs = {};  // every point may have moved
}

void destroyPlanBuffers(const VulkanContext& ctx, PlanBuffers& b) {
    for (Buffer* buffer : {&b.planHeaders, &b.nodes, &b.points, &b.weights, &b.subfaces, &b.rings, &b.positions,
                           &b.controlPoints, &b.boundaries, &b.segments, &b.boundaryPoints, &b.pointPositions, &b.capture,
                           &b.subfaceGrid, &b.grid, &b.gridSource, &b.slotSubface, &b.gridIndices, &b.updateList,
                           &b.displacementTiles, &b.displacementPadded, &b.displacementSamples, &b.addresses})
        destroyBuffer(ctx, *buffer);
    b = PlanBuffers{};
}

Result<PlanPass> createPlanPass(const VulkanContext& ctx, VkPipelineCache cache, VkFormat colorFormat,
                                VkFormat depthFormat, bool byAddress) {
    Result<PlanPass> shared = sharedDeviceObject<PlanPass>(
        ctx, sharedPassKey(byAddress ? "plan-by-address" : "plan", colorFormat, depthFormat),
        [&]() -> Result<PlanPass> {
            PlanPass pipelines;
            pipelines.colorFormat = colorFormat;
            pipelines.depthFormat = depthFormat;
            pipelines.byAddress = byAddress;
            if (Status s = createPlanPipelines(ctx, cache, pipelines); !s) {
                destroyPlanPipelines(ctx, pipelines);
                return s.error();
            }
            return pipelines;
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
    return levelFor(settings.uniformFactor == 0 ? 64 : std::min(settings.uniformFactor, 64u));
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
        barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
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
                barrier(cmd, VK_PIPELINE_STAGE_2_TESSELLATION_EVALUATION_SHADER_BIT,
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
        {&buffers.gridSource, layout.source.size() * sizeof(uint32_t), storage},
        {&buffers.slotSubface, layout.slotSubface.size() * sizeof(uint32_t), storage},
        {&buffers.subfaceGrid, subfaceGrid.size() * sizeof(glm::uvec2), storage},
        {&buffers.gridIndices, layout.indices.size() * sizeof(uint32_t), VkBufferUsageFlags(VK_BUFFER_USAGE_INDEX_BUFFER_BIT)}};
    for (auto [buffer, bytes, usage] : sizes)
        if (Status s = ensureCapacity(ctx, *buffer, bytes, usage); !s) return s;
    uploadVector(buffers.gridSource, layout.source);
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
    uploadVector(buffers.gridIndices, indices);
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
    recordStencils(cmd, pass, buffers, levelFor(buffers.gridLayout.maxFactor));
    const uint32_t count = uint32_t(buffers.data.subfaces.size());
    dispatchGridPhase(cmd, pass, buffers, count, 0, kWholeCage);
    dispatchGridPhase(cmd, pass, buffers, count, 1, kWholeCage);
    buffers.pendingGridSubfaces.clear();
    // Tests read the grid back on the host.
    barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
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
}

namespace {

// Indexed GridVertex triangles into `target` (cleared), shaded as the view asks.
// `ranges`: (first index, count) pairs to draw; one covering every index when empty.
void recordTriangles(VkCommandBuffer cmd, const PlanPass& pass, VkBuffer vertices, VkBuffer indices, uint32_t indexCount,
                     const RenderTarget& target, const PlanView& view,
                     std::span<const std::pair<uint32_t, uint32_t>> ranges = {}) {
    assert(pass.colorFormat == target.colorFormat && pass.depthFormat == target.depthFormat);
    beginRendering(cmd, target, view.clear, view.background);
    PlanDrawPush push = planDrawPush(view, nullptr);
    push.capture = 0;
    const VkPipeline surface = view.colorBy == ColorBy::Shading ? pass.gridTriangles : pass.gridColored;
    for (VkPipeline pipeline : {surface, view.wireframe ? pass.gridWire : VkPipeline(VK_NULL_HANDLE)}) {
        if (!pipeline || indexCount == 0) continue;
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pass.drawLayout, 0, 1, &pass.set, 0, nullptr);
        vkCmdBindIndexBuffer(cmd, indices, 0, VK_INDEX_TYPE_UINT32);
        const VkDeviceSize offset = 0;
        vkCmdBindVertexBuffers(cmd, 0, 1, &vertices, &offset);
        PlanDrawPush p = push;
        if (pipeline == pass.gridWire) p.colorMode = 0xffffffffu;
        vkCmdPushConstants(cmd, pass.drawLayout, kPlanDrawStages, 0, sizeof(p), &p);
        if (ranges.empty()) vkCmdDrawIndexed(cmd, indexCount, 1, 0, 0, 0);
        for (const auto& [first, count] : ranges)
            if (count) vkCmdDrawIndexed(cmd, count, 1, first, 0, 0);
    }
    vkCmdEndRendering(cmd);
}

}  // namespace

void recordGridDraw(VkCommandBuffer cmd, const PlanPass& pass, const PlanBuffers& buffers, const RenderTarget& target,
                    const PlanView& view) {
    assert(buffers.gridEvaluator != GridEvaluator::None && "fill the grid first");
    std::vector<std::pair<uint32_t, uint32_t>> ranges;
    if (!view.hiddenDrawn.empty() || !view.culledDrawn.empty() || !buffers.holeDrawn.empty()) {
        const std::vector<uint32_t>& indexOffset = buffers.gridLayout.indexOffset;
        for (const DrawnRun& run : drawnRuns(buffers, skippedDrawn(buffers, view, true)))
            ranges.push_back({indexOffset[run.begin], indexOffset[run.end] - indexOffset[run.begin]});
        if (ranges.empty()) ranges.push_back({0, 0});  // everything hidden
    }
    recordTriangles(cmd, pass, buffers.grid.buffer, buffers.gridIndices.buffer, uint32_t(buffers.gridLayout.indices.size()),
                    target, view, ranges);
}

void recordShadedTriangles(VkCommandBuffer cmd, const PlanPass& pass, VkBuffer vertices, VkBuffer indices,
                           uint32_t indexCount, const RenderTarget& target, const PlanView& view) {
    PlanView shaded = view;
    shaded.colorBy = ColorBy::Shading;
    recordTriangles(cmd, pass, vertices, indices, indexCount, target, shaded);
}


namespace {

// Writes the lists a partial update dispatches over: `evaluate` at 0, `copy` after it. The lists
// are recorded into the command buffer, so updates in flight never see another's.
void recordUpdateLists(VkCommandBuffer cmd, const PlanBuffers& buffers, const std::vector<uint32_t>& evaluate,
                       const std::vector<uint32_t>& copy) {
    barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
            VK_ACCESS_2_TRANSFER_WRITE_BIT);
    recordListUpload(cmd, buffers, evaluate, 0);
    if (!copy.empty()) recordListUpload(cmd, buffers, copy, uint32_t(evaluate.size()));
    barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
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
    recordGridDraw(cmd, pass, buffers, target, view);
}

void recordPendingGridRefresh(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers) {
    if (buffers.pendingGridSubfaces.empty()) return;
    const std::vector<uint32_t> pending = std::exchange(buffers.pendingGridSubfaces, {});
    recordStencils(cmd, pass, buffers, levelFor(buffers.gridLayout.maxFactor));  // raised factors may go deeper
    recordGpuGridRefresh(cmd, pass, buffers, pending, withDependents(buffers.gridLayout, pending));
}

MoveUpdate recordMovedVertices(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers,
                               const PlannedCage& planned, std::span<const uint32_t> vertices) {
    MoveUpdate update;
    update.movedVertices = uint32_t(vertices.size());
    for (uint32_t v : vertices) {
        const glm::vec3& p = planned.cage().positions[v];
        const float xyz[3] = {p.x, p.y, p.z};
        uploadBuffer(buffers.positions, xyz, sizeof xyz, size_t(v) * sizeof xyz);
    }
    for (uint32_t id : boundaryPointsAround(planned, vertices)) {
        buffers.pointPositionsHost[id] = boundaryPointPosition(planned, id);
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
    const GridRefresh refresh = recordGridRefresh(cmd, pass, buffers, planned, touched, controlPoints);
    update.controlPointSubfaces = refresh.controlPointSubfaces;
    update.evaluatedSubfaces = refresh.evaluatedSubfaces;
    update.copiedSubfaces = refresh.copiedSubfaces;
    return update;
}

MoveUpdate recordSubfaceRefresh(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers,
                                const PlannedCage& planned, const std::vector<uint32_t>& drawn) {
    MoveUpdate update;
    const bool controlPoints = buffers.controlPointLevel != kNoControlPoints;
    if (!controlPoints && buffers.gridEvaluator == GridEvaluator::Gpu) {
        buffers.gridEvaluator = GridEvaluator::None;  // re-evaluated whole, control points first
        return update;
    }
    const GridRefresh refresh = recordGridRefresh(cmd, pass, buffers, planned, drawn, controlPoints);
    update.controlPointSubfaces = refresh.controlPointSubfaces;
    update.evaluatedSubfaces = refresh.evaluatedSubfaces;
    update.copiedSubfaces = refresh.copiedSubfaces;
    return update;
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
        update.evaluatedSubfaces = uint32_t(touched.size());
        update.copiedSubfaces = uint32_t(copying.size());
        return update;
    }
    const GridRefresh refresh = recordGridRefresh(cmd, pass, buffers, planned, touched, false);
    update.evaluatedSubfaces = refresh.evaluatedSubfaces;
    update.copiedSubfaces = refresh.copiedSubfaces;
    return update;
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
