// SceneRenderer: the 3D part of an editor frame — every viewport's limit surface (PlanPass),
// cage overlay and selection highlight (LinePass) — recorded into sub-areas of any
// RenderTarget, so the window and offscreen paths draw the same way.
//
// GPU copies follow the Document by revision. Anything a frame in flight may read (plan
// buffers, positions, the descriptor set, line buffers) is only rewritten after the queue is
// idle, so edits cost one pipeline drain; that keeps the frames-in-flight overlap for the
// common case, frames without edits.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "document.h"
#include "draw_path.h"
#include "line_pass.h"
#include "plan_pass.h"
#include "swapchain_target.h"

namespace qp::editor {

inline constexpr uint32_t kMaxViewports = 4;

struct ViewportDraw {
    VkRect2D rect{};
    glm::mat4 viewProjection{1.0f};
    float pixelsPerUnit = 1.0f;  // plan_pass.h pixelsPerUnit() for the rect's height
    ColorBy colorBy = ColorBy::Shading;
    bool drawSurface = true;     // false: the viewport's scheme is not available; clear only
};

struct DisplayOptions {
    DrawPath path = DrawPath::Grid;            // resolved (never Auto)
    TessellationSettings tessellation;         // tessellated path
    uint32_t gridFactor = 8;                   // grid path (see prepareGridFactor)
    bool wireframe = false, cage = true;
    glm::vec3 background{0.22f, 0.23f, 0.25f};
};

// What the GPU drew in one viewport, from pipeline-statistics queries: triangles rasterised
// for the surface (the wireframe overlay's second pass not counted) and patches (tessellated
// path: patch primitives; grid path: the sub-faces evaluated).
struct ViewportCounts {
    uint64_t triangles = 0, patches = 0;
};

struct SceneRenderer {
    PlanPass plan;
    LinePass lines;
    std::optional<PlanBuffers> buffers;
    Buffer cageLines, overlayLines;
    uint32_t cageLineCount = 0, overlayLineCount = 0;
    bool hasNonQuads = false;
    // What the GPU copies were made from.
    const Document* document = nullptr;
    uint64_t planRevision = 0, positionRevision = 0;
    Selection selection;
    // Per frame-in-flight slot: statistics queries and what they were recorded for.
    VkQueryPool statistics[kFramesInFlight] = {};
    uint32_t recordedViewports[kFramesInFlight] = {};
    bool recordedWire[kFramesInFlight] = {};
    bool recordedSurface[kFramesInFlight][kMaxViewports] = {};
    DrawPath recordedPath[kFramesInFlight] = {};
};

Result<SceneRenderer> createSceneRenderer(const VulkanContext& context, VkPipelineCache cache, VkFormat colorFormat);
void destroySceneRenderer(const VulkanContext& context, SceneRenderer& renderer);

// Takes over plan buffers uploaded elsewhere (the loading thread) for `document`.
void adoptDocument(const VulkanContext& context, SceneRenderer& renderer, const Document& document, PlanBuffers buffers);
// Brings the GPU copies up to date with `document` (uploads, position updates, line buffers).
Status syncDocument(const VulkanContext& context, SceneRenderer& renderer, const Document& document);

// The grid factor the grid path will really use for `factor` (n-gons need even factors).
uint32_t effectiveGridFactor(const SceneRenderer& renderer, uint32_t factor);
// Lays the grid out for `factor` (waiting for the device when it changes).
Status prepareGridFactor(const VulkanContext& context, SceneRenderer& renderer, uint32_t factor);

// Records every viewport into `target` (areas from ViewportDraw::rect), the statistics
// queries into `slot`'s pool. Areas outside the viewports are left as they are.
void recordScene(VkCommandBuffer cmd, SceneRenderer& renderer, uint32_t slot, const RenderTarget& target,
                 std::span<const ViewportDraw> viewports, const DisplayOptions& options);

// Counts of the frame last recorded in `slot`; call once the slot's fence has signalled.
// Empty when the device has no pipeline-statistics queries or the slot recorded nothing.
std::vector<ViewportCounts> readViewportCounts(const VulkanContext& context, const SceneRenderer& renderer,
                                               uint32_t slot);

}  // namespace qp::editor
