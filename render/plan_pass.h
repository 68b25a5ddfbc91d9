// PlanPass: draws planned limit surfaces (Brainerd et al. 2016 §5-§6) on the GPU.
//
// Two paths share one set of buffers (render/gpu_plans.h) and one evaluator
// (shaders/plan_eval.glsl):
//   - Tessellated: a compute pass applies each sub-face's stencil prefix for the level the
//     largest factor needs (a compute pass rather than B16's tessellation-control stage: on
//     lavapipe compute runs on every core, tessellation on one), then one patch per drawn
//     sub-face goes through the tessellator; the control stage picks the factors (uniform, or
//     adaptive by the screen size of a sphere around each edge, equal from both sides; 2k/k
//     where a split n-gon meets a quad), the evaluation stage walks the quadtree.
//   - Grid: a compute pass evaluates every sub-face on a uniform grid into a vertex buffer that
//     is drawn as triangles (what a CPU rasteriser likes best).
// Boundary vertices are evaluated by their owner in both paths, so shared edges are
// bit-identical (watertight). Draws are split so that no single draw makes the tessellator
// emit more than 65,535 vertices (lavapipe corrupts larger ones; platform notes).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>

#include "gpu_plans.h"
#include "render_target.h"
#include "vk_buffer.h"
#include "vk_context.h"

namespace qp {

enum class ColorBy : uint32_t { Shading = 0, NodeKind = 1, PlanDepth = 2, Sharpness = 3 };

struct TessellationSettings {
    uint32_t uniformFactor = 8;     // 1..64; 0 selects adaptive
    float pixelsPerSegment = 8.0f;  // adaptive: target screen length of one segment
};

// GPU copies of one planned cage. Positions can be refreshed without re-uploading plans.
struct PlanBuffers {
    GpuPlanData data;               // what was uploaded, kept for sizes and tests
    Buffer planHeaders, nodes, points, weights, subfaces, rings, positions, controlPoints;
    Buffer boundaries, segments, boundaryPoints, pointPositions, subfaceFactors, grid, capture;
    uint32_t gridFactor = 0;        // grid path: factor the grid buffer is laid out for
    uint32_t captureCapacity = 0;   // records the capture buffer holds
};

Result<PlanBuffers> uploadPlans(const VulkanContext& context, const PlannedCage& planned);
// After vertex moves: new positions (and boundary point positions) for the same topology.
void updatePositions(const PlanBuffers& buffers, const PlannedCage& planned);
void destroyPlanBuffers(const VulkanContext& context, PlanBuffers& buffers);

struct PlanPass {
    VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
    VkPipelineLayout computeLayout = VK_NULL_HANDLE, drawLayout = VK_NULL_HANDLE;
    VkPipeline stencils = VK_NULL_HANDLE, grid = VK_NULL_HANDLE;
    VkPipeline tessellated = VK_NULL_HANDLE, tessellatedWire = VK_NULL_HANDLE;
    VkPipeline gridTriangles = VK_NULL_HANDLE, gridWire = VK_NULL_HANDLE;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    VkDescriptorSet set = VK_NULL_HANDLE;
    VkFormat colorFormat = VK_FORMAT_UNDEFINED, depthFormat = VK_FORMAT_UNDEFINED;
    Buffer gridIndices;             // triangle indices of one sub-face grid, per factor in use
    uint32_t gridIndexFactor = 0;
};

Result<PlanPass> createPlanPass(const VulkanContext& context, VkPipelineCache cache, VkFormat colorFormat,
                                VkFormat depthFormat = VK_FORMAT_D32_SFLOAT);
void destroyPlanPass(const VulkanContext& context, PlanPass& pass);

// Points the pass's descriptor set at `buffers` (call after uploadPlans / a grid resize).
void bindPlanBuffers(const VulkanContext& context, PlanPass& pass, const PlanBuffers& buffers);

struct PlanView {
    glm::mat4 viewProjection{1.0f};
    float pixelsPerUnit = 1.0f;        // see pixelsPerUnit()
    glm::vec3 background{0.9f, 0.92f, 0.95f};
    ColorBy colorBy = ColorBy::Shading;
    bool wireframe = false;            // tessellation wireframe over the shaded surface
    bool capture = false;              // tessellated path: record every evaluated vertex
};

// Pixels per world unit at clip w = 1, for adaptive factors: viewport height / 2 * |P[1][1]|
// (Vulkan projections flip Y, so P[1][1] is negative).
float pixelsPerUnit(const glm::mat4& projection, uint32_t viewportHeight);

// Highest tessellation level (factor <= 2^level) the settings can ask for.
uint32_t maxTessellationLevel(const TessellationSettings& settings);

// Patches per draw so the tessellator emits at most 65,535 vertices per draw at `maxFactor`.
uint32_t patchesPerDraw(uint32_t maxFactor);

// Tessellated path: stencils for the needed level, then the patches, into `target` (cleared).
void recordTessellated(VkCommandBuffer cmd, const PlanPass& pass, const PlanBuffers& buffers,
                       const RenderTarget& target, const PlanView& view, const TessellationSettings& settings);

// Grid path: makes sure the grid buffer and indices fit `factor`, then evaluates and draws.
Status prepareGrid(const VulkanContext& context, PlanPass& pass, PlanBuffers& buffers, uint32_t factor);
void recordGrid(VkCommandBuffer cmd, const PlanPass& pass, const PlanBuffers& buffers, const RenderTarget& target,
                const PlanView& view);
// Only the evaluation part of the grid path (for tests and read-backs).
void recordGridEvaluation(VkCommandBuffer cmd, const PlanPass& pass, const PlanBuffers& buffers);

// Grid vertex layout in PlanBuffers::grid: position and normal, 6 floats.
struct GridVertex {
    float position[3];
    float normal[3];
};
// Vertices reserved per drawn sub-face in the grid buffer, and the factor a drawn sub-face uses
// (quads `factor`, n-gon sub-faces half of it: they are half the size).
uint32_t gridVerticesPerSubface(uint32_t factor);
uint32_t gridFactorOf(const GpuPlanData& data, uint32_t drawn, uint32_t factor);

// Capture record written by the tessellated path when PlanView::capture is set.
struct CaptureRecord {
    float u, v;
    uint32_t drawn;
    uint32_t edgeAndFactor;  // sub-face edge (0..3, 4 inside) | segments along it << 8
    float position[3];
    uint32_t edgeIndex;      // index along that edge
};
Status enableCapture(const VulkanContext& context, PlanBuffers& buffers, uint32_t capacity);
// Records written by the last captured draw (the count is clamped to the capacity).
std::vector<CaptureRecord> readCapture(const PlanBuffers& buffers, uint32_t* overflowed = nullptr);

}  // namespace qp
