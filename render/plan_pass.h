// PlanPass: draws planned limit surfaces (Brainerd et al. 2016 §5-§6) with Vulkan.
//
// Three paths share one set of buffers (render/gpu_plans.h) and one evaluator design
// (shaders/plan_eval.glsl, the GLSL twin of core/plans/plan_eval.cpp); draw_path.h picks one:
//   - Tessellated: a compute pass applies each sub-face's stencil prefix for the level the
//     largest factor needs (a compute pass rather than B16's tessellation-control stage: on
//     lavapipe compute runs on every core, tessellation on one), then one patch per drawn
//     sub-face goes through the tessellator; the control stage picks the factors (uniform, or
//     adaptive by the screen size of a sphere around each edge, equal from both sides; 2k/k
//     where a split n-gon meets a quad), the evaluation stage walks the quadtree. Boundary
//     vertices are evaluated by their owner (gpu_plans.h), so shared edges are bit-identical.
//     Draws are split so that no single draw makes the tessellator emit more than 65,535
//     vertices (lavapipe corrupts larger ones; platform notes).
//   - Grid: a compute pass evaluates every sub-face on a grid (grid_layout.h: uniform or
//     adaptive factors, the same ownership) into a vertex buffer drawn as indexed triangles,
//     what a CPU rasteriser likes best.
//   - CPU grid: the same grid filled by the multithreaded CPU evaluator (cpu_grid.h).
// The grid is cached: frames that only move the camera just draw it, and vertex moves
// re-evaluate only the sub-faces they touch (recordMovedVertices).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>

#include "cpu_grid.h"  // GridFrames
#include "displacement/displacement.h"
#include "displacement/displacement_users.h"
#include "gpu_plans.h"
#include "grid_layout.h"
#include "sample_culling.h"
#include "render_target.h"
#include "scene/shading.h"
#include "vk_buffer.h"
#include "vk_context.h"

namespace qp {

enum class ColorBy : uint32_t { Shading = 0, NodeKind = 1, PlanDepth = 2, Sharpness = 3 };

struct TessellationSettings {
    uint32_t uniformFactor = 8;     // 1..64; 0 selects adaptive
    float pixelsPerSegment = 8.0f;  // adaptive: target screen length of one segment
    // Grid paths with a displacement: > 0 draws displaced tiles no finer than this many pixels per
    // segment on screen (an editor's level of detail); 0 makes every non-zero sample a vertex.
    float displacementPixels = 0.0f;
    // Grid paths at uniform factor 1: macro faces (macro_grid.h) drawn at per-face factor
    // 1 / minify (1: single faces). Adaptive factors choose macro faces by screen size instead.
    uint32_t minify = 1;
    // Uniform factors: macro faces whose members share one factor drawn as one grid even at their
    // members' full resolution (the same triangles over shared vertices instead of each face's
    // copies; `quadplan bench macro` compares the two).
    bool wholeMacroFaces = false;
};

// GPU copies of one planned cage.
//
// Caching. What the paths compute from positions is kept until something it depends on
// changes: the control points (for the highest level asked for so far) and the grid (for its
// layout). updatePositions and a new layout drop them; recordMovedVertices refreshes just the
// sub-faces a vertex move touches. A view-only frame of the grid paths therefore only draws.
// Edits that re-plan faces (sharpness, holes, topology) change the buffers' layout: upload the
// cage again.
// The flags describe recorded work: submit what was recorded before relying on them.
//
// Host writes. Positions, the CPU grid and the layout buffers are written through their
// mapping: call those functions only while no submitted work uses the buffers (after the
// fence of the last frame that drew them).
enum class GridEvaluator : uint8_t { None, Gpu, Cpu };  // who filled the cached grid

inline constexpr uint32_t kNoControlPoints = UINT32_MAX;

struct PlanBuffers {
    GpuPlanData data;               // what was uploaded, kept for sizes, updates and tests
    Buffer planHeaders, nodes, points, weights, subfaces, rings, positions, controlPoints;
    Buffer boundaries, segments, boundaryPoints, pointPositions, capture;
    Buffer addresses;               // PlanAddresses (plan_pipelines.h): where the shaders find the others
    uint32_t captureCapacity = 0;   // records the capture buffer holds
    std::vector<glm::vec4> pointPositionsHost;  // what pointPositions holds (adaptive grid factors)

    // Grid paths (prepareGrid): the layout and its buffers.
    GridLayout gridLayout;
    // The slot tables (source, slotSubface) of the layout before the last relayout kept slots
    // (grid_relayout.h carryGrid): the next one writes into them while it reads the current ones.
    GridLayout spareSlotTables;
    Buffer subfaceGrid;             // per drawn sub-face: grid factor n, first slot
    Buffer grid, gridSource, slotSubface, gridIndices;
    // The CPU grid's triangles that may cover a pixel centre, chunk by chunk (sample_culling.h;
    // with hostEvaluation only, else a placeholder), and what they were chosen for.
    Buffer gridCulledIndices;
    SampleCulling sampleCulling;
    Buffer updateList;              // drawn sub-faces of partial updates (written by commands)

    uint32_t controlPointLevel = kNoControlPoints;  // the control points serve factors <= 2^level
    // Control points each drawn sub-face's range holds (plan_update.h; empty until the first
    // update in place: then the stencil counts packPlans gave them).
    std::vector<uint32_t> controlPointCapacity;
    GridEvaluator gridEvaluator = GridEvaluator::None;
    // Drawn sub-faces the compute shader evaluates at the next recordGrid (and their neighbours'
    // copies): a relayout kept the rest (grid_relayout.h).
    std::vector<uint32_t> pendingGridSubfaces;
    GridFactors displacementScreen;  // the last screen caps of displaced tiles (kept while close enough)
    // Adaptive factors (draw_path.cpp): the view the layout's were chosen for (valid only while the
    // points moved just by recordMovedVertices since), and the drawn sub-faces around the vertices
    // moved since (sorted): while the view stays, only those are chosen again.
    struct AdaptiveInputs {
        bool valid = false;
        glm::mat4 viewProjection{0.0f};
        float pixelsPerUnit = 0.0f, pixelsPerSegment = 0.0f;
        bool operator==(const AdaptiveInputs&) const = default;
    } adaptiveInputs;
    std::vector<uint32_t> movedSinceFactors;
    bool factorsKept = false;  // the layout's factors were chosen for a PlanView::keepFactors frame
    // What the layout's macro faces were chosen for (draw_path.cpp): while the view, the request
    // and every other factor stay, they are kept instead of chosen again.
    struct MacroChoiceInputs {
        glm::mat4 viewProjection{0.0f};
        float pixelsPerUnit = 0.0f, pixelsPerSegment = 0.0f;
        uint32_t uniformFactor = 0, minify = 0;
        bool whole = false;
        std::vector<uint32_t> blocked;
        bool operator==(const MacroChoiceInputs&) const = default;
    } macroInputs;

    // Sculpted displacement (setPlanDisplacement): DisplacementLayout's tiles and padded blocks
    // and the samples; 16-byte placeholders (shorter than any padded block: the shaders'
    // hasDisplacement) when there is none.
    Buffer displacementTiles, displacementPadded, displacementSamples;
    const Displacement* displacement = nullptr;  // what the buffers hold; null: none
    GridFrames gridFrames;                       // CPU grid with displacement: frames of evaluated slots
    DisplacementUsers displacementUsers;         // which sub-faces read each sample
    std::vector<uint32_t> drawnOfSubface;        // PlannedCage sub-face -> drawn index (or UINT32_MAX)
    std::vector<uint32_t> holeDrawn;             // drawn sub-faces that are holes (sorted): never drawn
    SampleBits changedSamples;                   // the samples of the last dab (reused)
};

// `macros`: which macro faces the grid paths may draw (macro_grid.h). `hostEvaluation`: only
// the CPU grid path will draw (GpuPlanData::hostEvaluation); the stencil pass, the compute
// grid and the tessellated path must not be recorded with these buffers (recordStencils asserts).
Result<PlanBuffers> uploadPlans(const VulkanContext& context, const PlannedCage& planned,
                                MacroChoice macros = MacroChoice::Auto, bool hostEvaluation = false);
// holeDrawn from the cage's holes (O(holes)): after uploadPlans does it, for updates.
void updateHoleDrawn(PlanBuffers& buffers, const PlannedCage& planned);

// The runs [begin, end) of drawn sub-faces a draw covers: all but `hidden` (sorted) and holes.
struct DrawnRun {
    uint32_t begin, end;
};
std::vector<DrawnRun> drawnRuns(const PlanBuffers& buffers, std::span<const uint32_t> hidden);
struct PlanView;
// What a draw of `view` skips besides holes (sorted): hidden and culled sub-faces; with
// `gridMacros`, a coarse macro face's head (macro_grid.h) only when all its members are culled.
std::vector<uint32_t> skippedDrawn(const PlanBuffers& buffers, const PlanView& view, bool gridMacros);
// New positions for every vertex (same topology); drops what was cached.
void updatePositions(PlanBuffers& buffers, const PlannedCage& planned);
void destroyPlanBuffers(const VulkanContext& context, PlanBuffers& buffers);

struct PlanPass {
    VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
    VkPipelineLayout computeLayout = VK_NULL_HANDLE, drawLayout = VK_NULL_HANDLE;
    VkPipeline stencils = VK_NULL_HANDLE, grid = VK_NULL_HANDLE;
    VkPipeline tessellated = VK_NULL_HANDLE, tessellatedWire = VK_NULL_HANDLE;
    // The same with the displacement code compiled in (plan_pipelines.h): for buffers with a
    // displacement set.
    VkPipeline gridDisplaced = VK_NULL_HANDLE, tessellatedDisplaced = VK_NULL_HANDLE, tessellatedDisplacedWire = VK_NULL_HANDLE;
    VkPipeline gridTriangles = VK_NULL_HANDLE, gridColored = VK_NULL_HANDLE, gridWire = VK_NULL_HANDLE;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    VkDescriptorSet set = VK_NULL_HANDLE;
    VkFormat colorFormat = VK_FORMAT_UNDEFINED, depthFormat = VK_FORMAT_UNDEFINED;
    // The shaders reach the buffers by device address (shaders/plan_buffers.glsl) instead of
    // through storage-buffer descriptors: bindPlanBuffers switches when a buffer is larger than
    // the device's storage buffer range, so no cage is refused for its size.
    bool byAddress = false;
    bool alwaysByAddress = false;            // made by address (createPlanPass): never switches back
    VkPipelineCache cache = VK_NULL_HANDLE;  // what the pipelines of the other variant are made through
};

// The layouts and pipelines are made once per device, formats and variant and shared by every
// pass (shared_pipelines.h: a new pass, for a rebuild or another viewport, compiles nothing); the
// descriptor pool and set are the pass's own. `byAddress`: always the by-address variant (else
// bindPlanBuffers picks it when the buffers need it).
Result<PlanPass> createPlanPass(const VulkanContext& context, VkPipelineCache cache, VkFormat colorFormat,
                                VkFormat depthFormat = VK_FORMAT_D32_SFLOAT, bool byAddress = false);
// Frees the pass's descriptor pool; the shared pipelines stay with the device.
void destroyPlanPass(const VulkanContext& context, PlanPass& pass);

// Points the pass's descriptor set at `buffers`: after uploadPlans and enableCapture
// (prepareGrid rebinds itself when it replaces buffers). One set per pass: a pass draws one
// cage. When a buffer is larger than the device's storage buffer range the pass becomes its
// by-address variant (and back when none is); fails only when those pipelines cannot be made.
// Call while no submitted work uses the pass.
Status bindPlanBuffers(const VulkanContext& context, PlanPass& pass, const PlanBuffers& buffers);

// Where the plans' studio lights are in the world (toward the light; normalised in use).
inline constexpr glm::vec3 kPlanKeyLight{0.3f, 0.5f, 1.0f}, kPlanFillLight{-0.6f, 0.8f, -0.2f};

struct PlanView {
    glm::mat4 viewProjection{1.0f};
    float pixelsPerUnit = 1.0f;        // see pixelsPerUnit()
    glm::vec3 background{0.9f, 0.92f, 0.95f};
    ColorBy colorBy = ColorBy::Shading;
    Shading shading = Shading::Studio;
    bool wireframe = false;            // tessellation wireframe over the shaded surface
    // The CPU grid path leaves out the triangles that cover no pixel centre (sample_culling.h);
    // the picture is the same either way.
    bool sampleCulling = true;
    // The surface hides its back side from this view (closed, outward, seen from outside, the
    // near plane clear of it; the scheme's culling decides): the CPU grid path then also leaves
    // out triangles facing away from `eye` (object space, homogeneous) behind facing ones
    // (sample_culling.h). The picture is the same either way.
    bool backFacesHidden = false;
    glm::vec4 eye{0.0f};
    bool capture = false;              // tessellated path: record every evaluated vertex
    bool clear = true;                 // false: draw over what target.area holds (later objects of a scene)
    // The studio lights (plan_lighting.glsl), unit vectors toward them in the cage's coordinates:
    // fixed in the world, so an object of a scene turned by its transform gets them turned back.
    glm::vec3 keyLight = kPlanKeyLight, fillLight = kPlanFillLight;
    std::span<const uint32_t> hiddenDrawn;  // drawn sub-faces not to draw (sorted; the editor's hidden
                                            // faces); holes (PlanBuffers::holeDrawn) are never drawn
    // Drawn sub-faces culled for this view (sorted): not drawn either, but unlike hidden ones they
    // do not keep a macro face from being coarse (its triangles go when all its members are culled).
    std::span<const uint32_t> culledDrawn;
    // The camera is moving (progressive refinement): the grid paths choose screen-adaptive
    // factors and macro faces for the first such frame's view (the caller may coarsen it through
    // pixelsPerUnit) and keep that layout, drawn under each later view's matrix, while the flag
    // stays; the first frame without it chooses them for its own view again.
    bool keepFactors = false;
};

// Pixels per world unit at clip w = 1, for adaptive factors: viewport height / 2 * |P[1][1]|
// (Vulkan projections flip Y, so P[1][1] is negative).
float pixelsPerUnit(const glm::mat4& projection, uint32_t viewportHeight);

// Highest tessellation level (factor <= 2^level) the settings can ask for.
uint32_t maxTessellationLevel(const TessellationSettings& settings);

// Patches per draw so the tessellator emits at most 65,535 vertices per draw at `maxFactor`.
uint32_t patchesPerDraw(uint32_t maxFactor);

// Tessellated path: the stencils for the needed level (unless cached), then the patches, into
// `target` (cleared).
void recordTessellated(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers, const RenderTarget& target,
                       const PlanView& view, const TessellationSettings& settings);

// ---- grid paths --------------------------------------------------------------------------
// Every drawn sub-face evaluated on a grid (grid_layout.h) into a vertex buffer that is drawn
// as indexed triangles; evaluated by a compute shader (DrawPath::Grid) or by the CPU
// (DrawPath::CpuGrid), then cached until positions or the layout change.

// Lays the grid out for uniform `factor` (1..64) or for `factors` (adaptiveGridFactors),
// growing buffers when needed. Does nothing when the layout is already that one; otherwise
// the cached grid is dropped. May replace buffers: the device must be done with them.
Status prepareGrid(const VulkanContext& context, PlanPass& pass, PlanBuffers& buffers, uint32_t factor);
Status prepareGrid(const VulkanContext& context, PlanPass& pass, PlanBuffers& buffers, GridFactors factors);

// Makes `layout` (built for buffers.data) the grid's, growing and filling the layout buffers,
// and leaves the grid's vertices and the sample culling as they are (the caller brings both up
// to date: prepareGrid drops them, carryGrid carries them). May replace buffers: the device must
// be done with them.
Status installGridLayout(const VulkanContext& context, PlanPass& pass, PlanBuffers& buffers, GridLayout layout);
// Uploads buffers.gridLayout's triangles alone (after writeGridIndices: the slots unchanged),
// growing the index buffer when needed. The device must be done with it.
Status installGridIndices(const VulkanContext& context, PlanPass& pass, PlanBuffers& buffers);

// Adaptive factors for `view` and `settings` (uniformFactor 0), keeping the current layout's
// where they still fit (grid_layout.h); pass them to prepareGrid.
GridFactors adaptiveGridFactors(const PlanBuffers& buffers, const PlanView& view, const TessellationSettings& settings);

// Fills the whole grid with the compute shader (stencils first unless cached).
void recordGridEvaluation(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers);
// Fills the whole grid on the CPU (cpu_grid.h), now.
void evaluateGridOnCpu(const PlannedCage& planned, PlanBuffers& buffers);
// Draws the grid as it is (it must have been filled), every triangle of it.
void recordGridDraw(VkCommandBuffer cmd, const PlanPass& pass, const PlanBuffers& buffers, const RenderTarget& target,
                    const PlanView& view);
// Any triangle mesh of GridVertex (a vertex buffer, uint32 indices) drawn as recordGridDraw
// draws the grid with plain shading: the benchmark's pre-tessellated baseline, so that it
// differs from a view frame only in where its vertices came from.
void recordShadedTriangles(VkCommandBuffer cmd, const PlanPass& pass, VkBuffer vertices, VkBuffer indices,
                           uint32_t indexCount, const RenderTarget& target, const PlanView& view);
// The sub-faces a relayout left to the compute shader (PlanBuffers::pendingGridSubfaces) and
// their neighbours' copies; nothing when none are pending.
void recordPendingGridRefresh(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers);
// recordGridEvaluation unless the grid is cached (then the pending refresh), then the draw: as
// recordGridDraw, except that a CPU grid denser than one triangle a pixel leaves out the triangles
// that cover no pixel centre (view.sampleCulling; sample_culling.h).
void recordGrid(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers, const RenderTarget& target,
                const PlanView& view);

// ---- incremental updates ----------------------------------------------------------------
struct MoveUpdate {
    uint32_t movedVertices = 0;
    uint32_t controlPointSubfaces = 0;  // new control points (device)
    uint32_t evaluatedSubfaces = 0;     // grid phase 1 (device or CPU)
    uint32_t copiedSubfaces = 0;        // grid phase 2
};

// After planned.moveVertices(vertices, ...): writes the moved positions (and the boundary
// points around them), then brings what is cached up to date for just the sub-faces whose
// 1-ring holds a moved vertex: their control points and grid slots, plus the neighbours' copies
// of their edge vertices. Device work is recorded into `cmd` (outside rendering); a CPU grid is
// updated now. The result has the same bits as updatePositions and a full evaluation.
MoveUpdate recordMovedVertices(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers,
                               const PlannedCage& planned, std::span<const uint32_t> vertices);

// Brings what is cached up to date for the drawn sub-faces `drawn` (sorted, unique) whose
// control points or plans changed: their control points (when cached), their grid slots and
// the neighbours' copies of their edge vertices, as recordMovedVertices does after a move.
// Device work is recorded into `cmd` (outside rendering); a CPU grid is updated now.
MoveUpdate recordSubfaceRefresh(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers,
                                const PlannedCage& planned, const std::vector<uint32_t>& drawn);

// ---- sculpted displacement (docs/displacement.md) ------------------------------------------
// Every path draws s + D N with displacePoint's shading normal: the grid paths in the slots
// they evaluate (copies carry them to the neighbours), the tessellated path at each vertex's
// owner. `displacement` (or null / empty: none) must match the planned cage and outlive its
// use; it is read, never written. Uploads it and drops the cached grid; the device must be
// done with the buffers. Choose factors of at least requiredMeshFactor (displaced_mesh.h) so
// that no sample is skipped.
Status setPlanDisplacement(const VulkanContext& context, PlanPass& pass, PlanBuffers& buffers,
                           const Displacement* displacement);

struct DisplacementUpdate {
    uint32_t uploadedSamples = 0;
    uint32_t evaluatedSubfaces = 0;  // grid slots re-evaluated (device or CPU)
    uint32_t copiedSubfaces = 0;
    uint32_t displacedSlots = 0;     // CPU grid: slots re-displaced (those reading a changed sample)
};
// After a dab changed `samples` in place (same layout; any order, repeats allowed): copies
// their blocks (uploadRanges, core/displacement/brush.h) into the device's samples and brings a cached grid
// up to date for just the sub-faces that read them (device work recorded into `cmd`, outside
// rendering; a CPU grid now, re-displacing only the slots whose D reads one of `samples`).
// The result equals setPlanDisplacement and a full evaluation.
DisplacementUpdate recordDisplacementChange(VkCommandBuffer cmd, const PlanPass& pass, PlanBuffers& buffers,
                                            const PlannedCage& planned, std::span<const uint32_t> samples);

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
