#include "scene_renderer.h"

#include <algorithm>

#include "vk_check.h"

namespace qp::editor {

namespace {

constexpr VkQueryPipelineStatisticFlags kStatistics =
    VK_QUERY_PIPELINE_STATISTIC_INPUT_ASSEMBLY_PRIMITIVES_BIT | VK_QUERY_PIPELINE_STATISTIC_CLIPPING_INVOCATIONS_BIT;

const glm::vec3 kSelectedVertexColor(1.0f, 0.35f, 0.0f), kSelectedEdgeColor(0.0f, 0.85f, 1.0f);

// Writes `vertices` into `buffer`, growing it when needed (the caller made sure it is idle).
Status fillLineBuffer(const VulkanContext& ctx, Buffer& buffer, uint32_t& count, const std::vector<LineVertex>& vertices) {
    const VkDeviceSize bytes = std::max<VkDeviceSize>(vertices.size(), 2) * sizeof(LineVertex);
    if (buffer.size < bytes) {
        destroyBuffer(ctx, buffer);
        Result<Buffer> created = createBuffer(ctx, bytes * 2, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
        if (!created) return created.error();
        buffer = *created;
    }
    if (!vertices.empty()) uploadBuffer(buffer, vertices.data(), vertices.size() * sizeof(LineVertex));
    count = uint32_t(vertices.size());
    return success();
}

// A small 3D cross on each selected vertex and the selected edge, drawn over the cage.
std::vector<LineVertex> selectionLines(const Document& doc) {
    std::vector<LineVertex> lines;
    const Cage& cage = doc.planned->cage();
    const float size = 0.015f * std::max(computeBounds(cage).diagonal(), 1e-3f);
    for (uint32_t v : doc.selection.vertices) {
        if (v >= cage.vertexCount()) continue;
        for (int axis = 0; axis < 3; ++axis) {
            glm::vec3 offset(0.0f);
            offset[axis] = size;
            lines.push_back({cage.positions[v] - offset, kSelectedVertexColor});
            lines.push_back({cage.positions[v] + offset, kSelectedVertexColor});
        }
    }
    if (doc.selection.edge) {
        auto [a, b] = *doc.selection.edge;
        if (a < cage.vertexCount() && b < cage.vertexCount()) {
            lines.push_back({cage.positions[a], kSelectedEdgeColor});
            lines.push_back({cage.positions[b], kSelectedEdgeColor});
        }
    }
    return lines;
}

// The plan passes' compute stages rewrite buffers (control points, the grid) that the previous
// viewport's (or frame's) draws read: those reads must finish first.
void barrierBeforeEvaluation(VkCommandBuffer cmd) {
    VkMemoryBarrier2 barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
    barrier.srcStageMask = VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_TESSELLATION_CONTROL_SHADER_BIT |
                           VK_PIPELINE_STAGE_2_TESSELLATION_EVALUATION_SHADER_BIT |
                           VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT;
    barrier.srcAccessMask = VK_ACCESS_2_SHADER_STORAGE_READ_BIT;
    barrier.dstStageMask = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
    barrier.dstAccessMask = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT;
    VkDependencyInfo dependency{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    dependency.memoryBarrierCount = 1;
    dependency.pMemoryBarriers = &barrier;
    vkCmdPipelineBarrier2(cmd, &dependency);
}

bool sameSelection(const Selection& a, const Selection& b) { return a.vertices == b.vertices && a.edge == b.edge; }

}  // namespace

Result<SceneRenderer> createSceneRenderer(const VulkanContext& ctx, VkPipelineCache cache, VkFormat colorFormat) {
    SceneRenderer r;
    Result<PlanPass> plan = createPlanPass(ctx, cache, colorFormat);
    if (!plan) return plan.error();
    r.plan = *plan;
    Result<LinePass> lines = createLinePass(ctx, cache, colorFormat);
    if (!lines) {
        destroySceneRenderer(ctx, r);
        return lines.error();
    }
    r.lines = *lines;
    if (ctx.features.pipelineStatisticsQuery) {
        for (VkQueryPool& pool : r.statistics) {
            VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
            info.queryType = VK_QUERY_TYPE_PIPELINE_STATISTICS;
            info.queryCount = kMaxViewports;
            info.pipelineStatistics = kStatistics;
            if (VkResult result = vkCreateQueryPool(ctx.device, &info, nullptr, &pool); result != VK_SUCCESS) {
                destroySceneRenderer(ctx, r);
                return vkError("vkCreateQueryPool", result);
            }
        }
    }
    return r;
}

void destroySceneRenderer(const VulkanContext& ctx, SceneRenderer& r) {
    if (r.buffers) destroyPlanBuffers(ctx, *r.buffers);
    destroyBuffer(ctx, r.cageLines);
    destroyBuffer(ctx, r.overlayLines);
    for (VkQueryPool pool : r.statistics)
        if (pool) vkDestroyQueryPool(ctx.device, pool, nullptr);
    if (r.lines.pipeline) destroyLinePass(ctx, r.lines);
    if (r.plan.setLayout) destroyPlanPass(ctx, r.plan);
    r = SceneRenderer{};
}

void adoptDocument(const VulkanContext& ctx, SceneRenderer& r, const Document& doc, PlanBuffers buffers) {
    vkQueueWaitIdle(ctx.queue);
    if (r.buffers) destroyPlanBuffers(ctx, *r.buffers);
    r.buffers = std::move(buffers);
    bindPlanBuffers(ctx, r.plan, *r.buffers);
    r.document = &doc;
    r.planRevision = doc.planRevision;
    r.positionRevision = ~doc.positionRevision;  // lines still to build
    r.selection = Selection{{~0u}, std::nullopt};
    const Cage& cage = doc.planned->cage();
    r.hasNonQuads = false;
    for (uint32_t f = 0; f < cage.faceCount(); ++f) r.hasNonQuads |= cage.faceSize(f) != 4;
}

Status syncDocument(const VulkanContext& ctx, SceneRenderer& r, const Document& doc) {
    if (!doc.planned) return success();
    if (r.document != &doc || r.planRevision != doc.planRevision) {
        Result<PlanBuffers> uploaded = uploadPlans(ctx, *doc.planned);
        if (!uploaded) return uploaded.error();
        adoptDocument(ctx, r, doc, std::move(uploaded).value());
    }
    const bool positionsChanged = r.positionRevision != doc.positionRevision;
    const bool selectionChanged = positionsChanged || !sameSelection(r.selection, doc.selection);
    if (!positionsChanged && !selectionChanged) return success();
    VK_CHECK(vkQueueWaitIdle(ctx.queue));
    if (positionsChanged) {
        updatePositions(*r.buffers, *doc.planned);
        if (Status s = fillLineBuffer(ctx, r.cageLines, r.cageLineCount, cageLines(doc.planned->cage())); !s) return s;
        r.positionRevision = doc.positionRevision;
    }
    if (Status s = fillLineBuffer(ctx, r.overlayLines, r.overlayLineCount, selectionLines(doc)); !s) return s;
    r.selection = doc.selection;
    return success();
}

uint32_t effectiveGridFactor(const SceneRenderer& r, uint32_t factor) {
    factor = std::clamp(factor, 1u, 64u);
    return r.hasNonQuads && factor % 2 ? factor + 1 : factor;
}

Status prepareGridFactor(const VulkanContext& ctx, SceneRenderer& r, uint32_t factor) {
    if (!r.buffers) return success();
    factor = effectiveGridFactor(r, factor);
    GridFactors factors = uniformGridFactors(r.buffers->data, factor);
    if (!r.buffers->gridLayout.subfaceOffset.empty() && r.buffers->gridLayout.factors == factors) return success();
    VK_CHECK(vkQueueWaitIdle(ctx.queue));
    return prepareGrid(ctx, r.plan, *r.buffers, std::move(factors));
}

void recordScene(VkCommandBuffer cmd, SceneRenderer& r, uint32_t slot, const RenderTarget& target,
                 std::span<const ViewportDraw> viewports, const DisplayOptions& options) {
    const VkQueryPool pool = r.statistics[slot];
    const uint32_t count = std::min<uint32_t>(uint32_t(viewports.size()), kMaxViewports);
    if (pool) vkCmdResetQueryPool(cmd, pool, 0, kMaxViewports);
    r.recordedViewports[slot] = count;
    r.recordedWire[slot] = options.wireframe;
    r.recordedPath[slot] = options.path;
    for (uint32_t i = 0; i < count; ++i) {
        const ViewportDraw& v = viewports[i];
        const RenderTarget area = subArea(target, v.rect);
        const bool surface = v.drawSurface && r.buffers && r.buffers->data.subfaces.size() > 0;
        r.recordedSurface[slot][i] = surface && pool;
        if (!surface) {
            beginRendering(cmd, area, true, options.background);
            vkCmdEndRendering(cmd);
            continue;
        }
        PlanView view;
        view.viewProjection = v.viewProjection;
        view.pixelsPerUnit = v.pixelsPerUnit;
        view.background = options.background;
        view.colorBy = v.colorBy;
        view.wireframe = options.wireframe;
        barrierBeforeEvaluation(cmd);
        if (pool) vkCmdBeginQuery(cmd, pool, i, 0);
        if (options.path == DrawPath::Grid) recordGrid(cmd, r.plan, *r.buffers, area, view);
        else recordTessellated(cmd, r.plan, *r.buffers, area, view, options.tessellation);
        if (pool) vkCmdEndQuery(cmd, pool, i);
        if (options.cage && r.cageLineCount > 0)
            recordLines(cmd, r.lines, area, v.viewProjection, r.cageLines, r.cageLineCount);
        if (r.overlayLineCount > 0) recordLines(cmd, r.lines, area, v.viewProjection, r.overlayLines, r.overlayLineCount);
    }
}

std::vector<ViewportCounts> readViewportCounts(const VulkanContext& ctx, const SceneRenderer& r, uint32_t slot) {
    std::vector<ViewportCounts> counts;
    if (!r.statistics[slot]) return counts;
    const uint64_t passes = r.recordedWire[slot] ? 2 : 1;
    for (uint32_t i = 0; i < r.recordedViewports[slot]; ++i) {
        ViewportCounts c;
        uint64_t values[2] = {0, 0};
        if (r.recordedSurface[slot][i] &&
            vkGetQueryPoolResults(ctx.device, r.statistics[slot], i, 1, sizeof values, values, sizeof values,
                                  VK_QUERY_RESULT_64_BIT) == VK_SUCCESS) {
            c.triangles = values[1] / passes;
            c.patches = r.recordedPath[slot] == DrawPath::Grid ? r.buffers->data.subfaces.size() : values[0] / passes;
        }
        counts.push_back(c);
    }
    return counts;
}

}  // namespace qp::editor
