// SceneRenderer: the 3D part of an editor frame. Every viewport draws its limit surface through
// the viewport's own scheme plugin instance (plugins/scheme_api.h: `plans` is one of them, so
// renderer changes reach the editor through plugins/plans) with the scene's sculpted
// displacement (after a dab only the changed samples: Scheme::displacementChanged), or, in heat-map mode, the scheme's
// surface coloured by its distance from the exact limit surface (plugins/surface_error.h); then
// the ground grid, the cage (creased edges wider) and the selection (LinePass) over it. Drawn
// into sub-areas of any RenderTarget.
//
// GPU copies follow the Document by revision (document.h). syncScene brings them up to date
// once per frame: tag and topology edits go to Scheme::updatePlans (a scheme that cannot take
// one in place is rebuilt); an instance whose viewport switches scheme or closes is parked and
// reused when it is asked for again while the plans are as they were; vertex moves alone go
// to Scheme::updateMoved with the vertices that moved (a drag step's own list when the renderer
// is one step behind, Document::lastMove; else found by diffing positions), so a drag
// re-evaluates only what it touched; camera-only frames do no scheme work at all. Anything a
// frame in flight may read is rewritten only after the queue is idle, so a frame with changes
// drains the pipeline once; frames without keep the frames-in-flight overlap.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "cage_lines.h"
#include "document.h"
#include "line_pass.h"
#include "mesh_pass.h"
#include "scheme_host.h"
#include "scheme_loader.h"
#include "scheme_support.h"
#include "subface_index.h"
#include "swapchain_target.h"

namespace qp::editor {

inline constexpr uint32_t kMaxViewports = 4;

// What a viewport asks to be drawn with this frame.
struct SchemeRequest {
    std::string name = "plans";
    SchemeSettings settings;
    bool heatMap = false;
    uint32_t heatFactor = 8;  // error samples per sub-face edge
};

// The scheme's error against the exact limit on a sample grid, drawn as a coloured mesh.
struct HeatMap {
    SubfaceGrid grid;
    VertexSubfaceIndex index;   // vertex -> grid sub-faces, for updates after moves
    std::vector<float> relError;
    GpuMesh mesh;               // positions of the scheme's surface, colours of its error
    double maxRelError = 0.0, rmsRelError = 0.0;
    double lastMs = 0.0;        // the last (re)computation
    uint32_t lastSubfaces = 0;  // sub-faces it re-evaluated
    bool valid = false;
};

// The error heat map of `instance` drawing `planned`, sampled `factor` times per sub-face edge:
// the whole grid, or after a move only the sub-faces the `moved` vertices touch (rewritten in
// place: the caller waited for the device).
Status updateHeatMap(const VulkanContext& context, const PlannedCage& planned, SchemeInstance& instance, uint32_t factor,
                     HeatMap& heat, const std::vector<uint32_t>* moved);
void destroyHeat(const VulkanContext& context, HeatMap& heat);

// One viewport's scheme instance and what it was made from.
struct SchemeView {
    SchemeRequest built;                     // what the instance (or the failure) is for
    std::optional<SchemeInstance> instance;  // empty: nothing drawn (see problem)
    SupportReport support;                   // approximations: warnings shown in the viewport
    std::string problem;                     // why nothing is drawn: unknown, refused, failed
    std::string drawProblem;                 // why the last frame's draw failed (empty: it did not)
    std::vector<std::string> colorModes{"shading"};
    uint64_t generation = ~0ull, planRevision = ~0ull;
    double setupMs = 0.0;   // build + GPU + first update, the last time it was made
    // The last tag or topology edit reached this viewport in planUpdateMs, in place
    // (Scheme::updatePlans) or by a new instance; planUpdateNote says which (and why a rebuild).
    double planUpdateMs = 0.0;
    bool planUpdateInPlace = false;
    std::string planUpdateNote;
    double updateMs = 0.0;  // the last update after a move
    uint32_t updatedVertices = 0;
    double displacementMs = 0.0;  // the last displacement update (a dab, a new displacement)
    uint32_t updatedSamples = 0;
    HeatMap heat;
    uint64_t drawRevision = 0;  // changes whenever what this viewport draws may have changed
};

// An instance no viewport shows any more (its viewport switched to another scheme or was
// closed), kept while the document's plans and displacement stay as they were, so that switching
// back or showing the viewport again reuses it instead of building a new one.
struct ParkedInstance {
    SchemeView view;  // without its heat map
    uint64_t positionRevision = 0, displacementRevision = 0, sampleRevision = 0;
};
inline constexpr size_t kMaxParkedInstances = 4;

// One viewport of a frame.
// viewProjection, eye and pixelsPerUnit are in the active object's coordinates (the camera's
// times the object's matrix: picking, the cage and every tool work there); the world ones are
// the camera's (the ground grid and the other objects).
struct ViewportDraw {
    VkRect2D rect{};
    glm::mat4 viewProjection{1.0f};
    glm::vec3 eye{0.0f};
    float pixelsPerUnit = 1.0f;  // plan_pass.h pixelsPerUnit() for the rect's height
    glm::mat4 worldViewProjection{1.0f};
    glm::vec3 worldEye{0.0f};
    float worldPixelsPerUnit = 1.0f;
    std::string colorBy = "shading";
    CullMethod cull = CullMethod::None;
    bool navigating = false;  // the camera is moving: a coarse frame (DrawView::navigating)
};

// The objects a viewport draws besides the active one (scene_objects_draw.cpp): the active
// cage's instances through the viewport's own instance, the other cages through instances of the
// viewport's scheme made for them (read-only: made once per document and scheme request).
struct OtherObjectsView {
    std::vector<PreparedScheme> cages;  // parallel to Document::otherCages
    std::vector<HeatMap> heat;          // likewise, in heat-map mode
    std::string scheme;
    uint32_t factor = 0, heatFactor = 0;
    float adaptivePixels = 0.0f;
    bool heatMap = false;
    uint64_t generation = ~0ull;
    uint64_t drawRevision = 0;  // changes whenever the instances or heat maps change
    std::string problem;  // why they are not drawn (a scheme that refuses one of them)
    // What the instances were last brought to (Document::otherPositionRevision): animated cages
    // move, and their instances take the moved vertices (Scheme::updateMoved).
    uint64_t positionRevision = ~0ull;
    std::vector<std::vector<glm::vec3>> positions;  // per cage, as last synced
};
struct ObjectDraw {
    ObjectTransform transform;
    uint32_t cage = kActiveCage;  // Document::otherCageOfObject
    bool active = false, visible = true;
};

struct DisplayOptions {
    bool wireframe = false, cage = true, grid = true;
    bool denseCage = false;  // plain cage lines however short they draw (cage_lines.h plainLinesReadable)
    bool selection = true;   // the edited cage's selection (edit mode)
    Shading shading = Shading::Studio;
    UpAxis up = UpAxis::Y;  // the ground grid lies across it
    glm::vec3 background{0.22f, 0.23f, 0.25f};
};

// Line widths in pixels (LinePass clamps them to the device's range): creases stand out at a
// glance, plain cage edges and the grid stay light.
inline constexpr float kCageLineWidth = 2.0f, kCreaseLineWidth = 5.0f, kGridLineWidth = 1.0f, kOverlayLineWidth = 2.0f;

// What the GPU drew in one viewport, from pipeline-statistics queries (triangles rasterised
// for the surface), and what the scheme said it submitted.
struct ViewportCounts {
    uint64_t triangles = 0, patches = 0;
    CullCounts cull;              // every object the viewport drew (DrawStats::cull)
    double cullMilliseconds = 0.0;
    uint64_t sampleCulled = 0;    // of `triangles`: covering no pixel centre, left out (DrawStats::sampleCulledTriangles)
    uint64_t facingAway = 0;      // of `triangles`: facing away behind the front, left out (DrawStats::facingAwayTriangles)
};

// Adds a draw's culling (DrawStats::cull, cullMilliseconds, sampleCulledTriangles,
// facingAwayTriangles) to a viewport's.
void addCullStats(ViewportCounts& counts, const DrawStats& drawn);

struct SceneRenderer {
    GpuContext gpu;
    LinePass lines;
    MeshPass heatPass;
    CageLines cageLineCache;  // what cageLines and creaseLines hold
    Bounds cageBounds;        // the edited cage's as last synced (plainLinesReadable)
    Buffer cageLines, creaseLines, overlayLines, gridLines;
    uint32_t cageLineCount = 0, creaseLineCount = 0, overlayLineCount = 0, gridLineCount = 0;
    std::optional<UpAxis> gridUp;  // what the grid was made for (with gridBounds); empty: not made
    Bounds gridBounds;
    std::vector<SchemeView> views;  // one per viewport
    std::vector<OtherObjectsView> others;  // one per viewport
    std::vector<ObjectDraw> objects;       // the document's objects as last synced
    std::vector<ParkedInstance> parked;  // oldest first, at most kMaxParkedInstances
    // What the copies were made from.
    uint64_t generation = ~0ull, planRevision = ~0ull, positionRevision = ~0ull;
    uint64_t displacementRevision = ~0ull, sampleRevision = ~0ull, hiddenRevision = ~0ull;
    std::vector<uint32_t> hiddenSubfaces;  // of the document's hidden faces, sorted: DrawView::hiddenSubfaces
    std::vector<glm::vec3> positions;  // as last synced, to find the vertices an edit moved
    std::string overlayKey;
    CageFeatures features;     // of the cage the last build saw (analyzeCage)
    bool featuresStale = true;  // the plans changed since: analysed again before the next build
    double lastSyncMs = 0.0;  // scheme updates, heat maps and line buffers of the last change
    // The last sync's wait for the device to finish earlier frames before it changed their
    // buffers (0 when nothing changed): idle time, left out of the frame's CPU time.
    double lastDeviceWaitMs = 0.0;
    // Per frame-in-flight slot: statistics queries and what they were recorded for.
    VkQueryPool statistics[kFramesInFlight] = {};
    uint32_t recordedViewports[kFramesInFlight] = {};
    bool recordedWire[kFramesInFlight] = {};
    bool recordedSurface[kFramesInFlight][kMaxViewports] = {};
    uint64_t recordedPatches[kFramesInFlight][kMaxViewports] = {};
    ViewportCounts recordedCull[kFramesInFlight][kMaxViewports] = {};  // its cull and cullMilliseconds
    // Per viewport, as last recorded: the cage shown but its plain lines left out (too dense there).
    bool plainLinesHidden[kMaxViewports] = {};
};

Result<SceneRenderer> createSceneRenderer(const VulkanContext& context, VkPipelineCache cache, VkFormat colorFormat);
void destroySceneRenderer(const VulkanContext& context, SceneRenderer& renderer);

// Destroys every scheme instance and heat map (after waiting for the device): before the
// document they point at goes away.
void releaseSchemes(const VulkanContext& context, SceneRenderer& renderer);

// Brings instances, heat maps and line buffers up to date with `document` (adopted as
// `generation`) and the viewports' requests; `changedSamples` are the displacement samples
// changed in place since the last call (takeUnsyncedSamples), `planChange` what edits re-planned
// since then (takeUnsyncedPlanChange): instances whose scheme updates plans in place get just
// those sub-faces, the others (and any whose update fails or asks for it) are rebuilt. The
// ground grid follows the cage's bounds when its plans change (not while vertices move) and
// `display.up`. Scheme failures become SchemeView::problem; an error here is a Vulkan failure
// of the editor's own buffers.
Status syncScene(const VulkanContext& context, SceneRenderer& renderer, const PluginCatalog& catalog,
                 const Document& document, uint64_t generation, std::span<const SchemeRequest> requests,
                 std::span<const uint32_t> changedSamples, const EditReport& planChange, const DisplayOptions& display);

// The other objects' instances and draws, brought up to date (scene_objects_draw.cpp).
void syncOtherObjects(const VulkanContext& context, SceneRenderer& renderer, const PluginCatalog& catalog,
                      const Document& document, uint64_t generation, std::span<const SchemeRequest> requests);
void releaseOtherObjects(const VulkanContext& context, SceneRenderer& renderer);
// Records viewport `i`'s other objects into `area` over what is there: through the schemes
// (their culling added to `counts`), or their heat maps (heat-map mode).
void recordOtherObjects(VkCommandBuffer cmd, SceneRenderer& renderer, uint32_t i, const RenderTarget& area,
                        const ViewportDraw& viewport, DrawView view, ViewportCounts& counts);
void recordOtherHeatMaps(VkCommandBuffer cmd, SceneRenderer& renderer, uint32_t i, const RenderTarget& area,
                         const ViewportDraw& viewport, const DisplayOptions& options);

// The error of viewport `i`'s scheme over every cage of the scene (the edited one and the
// others; instances share their cage's samples, as `quadplan compare` counts them).
struct SceneHeat {
    double maxRelError = 0.0, rmsRelError = 0.0;
    size_t samples = 0;
    uint32_t cages = 0;
    bool valid = false;
};
SceneHeat sceneHeat(const SceneRenderer& renderer, uint32_t i);

// Records every viewport into `target` (areas from ViewportDraw::rect), the statistics
// queries into `slot`'s pool. Areas outside the viewports are left as they are.
void recordScene(VkCommandBuffer cmd, SceneRenderer& renderer, uint32_t slot, const RenderTarget& target,
                 std::span<const ViewportDraw> viewports, const DisplayOptions& options);

// Counts of the frame last recorded in `slot`; call once the slot's fence has signalled.
std::vector<ViewportCounts> readViewportCounts(const VulkanContext& context, const SceneRenderer& renderer,
                                               uint32_t slot);

// Colour of a crease or corner of this sharpness (LinePass's ramp: yellow soft, red infinite).
glm::vec3 sharpnessRampColor(float sharpness);

}  // namespace qp::editor
