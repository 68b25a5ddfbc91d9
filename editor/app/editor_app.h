// The interactive editor: a GLFW window, the Vulkan swapchain, Dear ImGui and the scene
// renderer around one Document. `runEditorApp` is what `quadplan` and `quadplan edit` call.
//
// Per frame (editor_app.cpp): events -> adopt a finished background load -> automation step ->
// ImGui frame (viewport input, shortcuts, panels, gizmo) -> autosave -> draw (each viewport's
// scheme plugin, the cage overlay, then ImGui in its render pass) -> present. Every change to
// the cage goes through applyEdit (document.h), so it lands in the undo history.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "background_job.h"
#include "displacement_bake.h"
#include "document.h"
#include "document_export.h"
#include "document_loader.h"
#include "extrude_tool.h"
#include "frame_stats.h"
#include "gizmo.h"
#include "gpu_timer.h"
#include "imgui_layer.h"
#include "mask_overlay.h"
#include "object_mode.h"
#include "pick_cache.h"
#include "pipeline_cache.h"
#include "playback.h"
#include "scene_cache.h"
#include "scene_renderer.h"
#include "scheme_loader.h"
#include "sculpt_tool.h"
#include "swapchain_target.h"
#include "view_camera.h"
#include "viewport_input.h"

struct GLFWwindow;

namespace qp::editor {

class Automation;

struct LaunchOptions {
    std::string path;                 // scene or cage to open
    bool untitled = false;            // the bundled default scene: Save asks for a name
    std::string automationScript;     // file of automation commands, "-" for stdin; empty: none
    bool validate = false;            // Vulkan validation; any message makes the exit status 4
    bool vsync = true;
    double autosaveSeconds = 30.0;
    double coarseAboveMs = 100.0;     // progressive refinement when full frames take longer (editor_app.cpp navigating())
    uint32_t width = 1280, height = 800;
    uint32_t planDepth = 6;
    std::string pluginDir;            // scheme plugins (scheme_loader.h: flag, $QUADPLAN_PLUGIN_DIR, default)
};

int runEditorApp(const LaunchOptions& options);

struct ViewportState {
    std::string scheme = "plans";
    std::string colorBy = "shading";
    CullMethod cull = CullMethod::None;  // patches skipped in this view (docs/culling.md)
    bool heatMap = false;  // the scheme's error against the exact limit instead of its shading
    bool linked = true;
    ViewCamera camera;  // used when not linked
    // This frame:
    VkRect2D rect{};    // framebuffer pixels
    glm::mat4 viewProjection{1.0f};       // into the active object's coordinates (picking, tools)
    glm::mat4 worldViewProjection{1.0f};  // the camera's (grid, axes, the other objects)
    RenderCamera renderCamera;
    uint32_t factor = 8;  // tessellation factor asked of the scheme (uniform, or adaptive for this view)
};

// The tool of the left mouse button in the viewports (Maya's Q, W, E, R; B for the brush).
enum class Tool : uint8_t { Select, Move, Rotate, Scale, Sculpt };

// Blender's modes (Tab toggles): object mode picks and places whole objects; edit mode edits the
// cage of one of them (document_objects.h), with every tool of the Mesh, Creases and Sculpt panels.
enum class EditorMode : uint8_t { Object, Edit };

enum class DragKind { None, Orbit, Pan, Zoom, Press, MoveSelection, BoxSelect, Gizmo, Sculpt };

struct Drag {
    DragKind kind = DragKind::None;
    uint32_t viewport = 0;
    int button = 0;
    glm::vec2 start{0.0f};               // cursor at the start, framebuffer pixels
    glm::vec2 cursor{0.0f};              // now
    SelectOp op = SelectOp::Replace;     // BoxSelect, Press
    // MoveSelection and Gizmo: what moves, from where, in the view at the start.
    std::vector<uint32_t> vertices;
    std::vector<glm::vec3> startPositions;
    glm::vec3 anchor{0.0f};
    glm::mat4 viewProjection{1.0f};
    VkRect2D rect{};
    bool applied = false;                // an edit was made (later steps extend its history entry)
    GizmoShape shape;                    // Gizmo: the handle at the start
    GizmoHandle handle = GizmoHandle::None;
    std::string readout;                 // what the drag amounts to, shown beside the cursor
    StrokeOptions stroke;                // Sculpt: the brush, with the modifiers held at the start
    uint32_t strokeDabs = 0;
    bool loopClick = false;              // Orbit from Alt+left: released in place, it selects a loop
    bool ring = false;                   // ... an edge ring (Ctrl held)
    // Object mode's handle: the object and its transform at the start (shown live, one history
    // entry when the drag ends).
    uint32_t objectId = 0;
    ObjectTransform objectStart;
};

// What happens once the user has answered "unsaved changes".
struct PendingAction {
    enum Kind { None, Open, Quit } kind = None;
    std::string path;
};

struct RecoveryOffer {
    std::string source, savedAt;
    bool restoreWhenIdle = false;  // chosen while another load was running
};

// Settings of the editing tools (the side panel shows and changes them).
struct ToolSettings {
    Tool tool = Tool::Select;
    TransformSpace space = TransformSpace::World;
    bool visibleOnly = true;           // clicks and boxes skip what the limit surface hides
    bool facesOnSurface = true;        // face clicks pick the face whose limit patch is under the cursor
    float extrudeDistance = 0.0f;      // set to half the average edge length when a cage is adopted
    float loopFraction = 0.5f;         // where a loop from the panel cuts the selected edge
    bool loopTool = false;             // Ctrl+R: the next click on an edge inserts a loop there
    MergeTarget mergeTarget = MergeTarget::Centroid;
    float edgeSharpness = 2.0f, cornerSharpness = 2.0f;
    // Numeric transform entry, in the tool's space, about the selection's centroid.
    glm::vec3 moveBy{0.0f};
    glm::vec3 rotateAxis{0.0f, 0.0f, 1.0f};
    float rotateDegrees = 90.0f;
    glm::vec3 scaleBy{1.0f};
    SculptSettings sculpt;
};

// A key answering the dialog on top (Enter: its first button; Esc: Cancel), from the GLFW
// key queue, so a quick tap during a slow frame still counts.
enum class DialogKey : uint8_t { None, Confirm, Cancel };

struct UiState {
    DialogKey dialogKey = DialogKey::None;  // taken by the modal dialog drawn this frame
    bool showHelp = false;
    bool showHistory = true;
    std::string openPath, saveAsPath, exportPath, importPath, bakePath, bakeNormalMapPath;
    ExportOptions exportOptions;  // File > Export's settings
    BakeOptions bakeOptions;      // File > Bake's
    std::string selectTab;      // the side panel's tab to bring forward in the next frame
    std::string addObjectPath;  // the Scene tab's "Add from file"
    std::string renameText;     // the Scene tab's name field, for the object with renameObjectId
    uint32_t renameObjectId = 0;
    std::string requestPopup;  // opened at the top level of the next UI pass
    PendingAction pending;
    bool continuePendingAfterSave = false;
    std::string errorMessage;  // shown in the "Error" popup
    std::string status;        // last message, shown in the side panel
    std::optional<RecoveryOffer> recovery;
    std::string title;         // window title last set
    // Automation's `click-button` and the widget rectangles for tests (window coordinates).
    std::string pressLabel;
    bool pressConsumed = false;
    std::vector<std::pair<std::string, std::array<float, 4>>> widgets;
    std::vector<std::string> openPopups;  // dialogs shown in the last frame
    std::vector<std::string> tooltips;    // labels of widgets drawn with a tooltip this frame
    // Hover feedback in the viewports (drawn by the overlay, no 3D redraw needed):
    GizmoHandle gizmoHover = GizmoHandle::None;
    std::vector<glm::vec3> loopPreview;   // the loop the loop tool would cut, as segment pairs
    std::string loopPreviewKey;
    std::optional<SurfaceHit> brushHover;  // the sculpt tool: the surface under the cursor
    bool showMask = true;                  // the sculpt tool: masked samples as dark dots
    MaskDots maskDots;
    uint32_t brushViewport = 0;
    // A live slider's drag (creases, corners): the history position just after its entry,
    // which later changes of the same drag replace.
    std::optional<size_t> liveEditEntry;
};

// A key press as GLFW reported it. Shortcuts read these rather than ImGui 1.86's per-frame key
// state, which loses a press and release that both land between two (slow) frames.
struct KeyPress {
    int key = 0;
    bool ctrl = false, shift = false, alt = false;
};

struct EditorApp {
    LaunchOptions options;
    GLFWwindow* window = nullptr;
    VulkanContext ctx;
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    SwapchainTarget swapchain;
    std::optional<PipelineCache> pipelineCache;
    ImGuiLayer imgui;
    PluginCatalog catalog;             // the scheme plugins (viewports draw through them)
    SceneRenderer renderer;
    SceneCache sceneCache;
    bool sceneRecorded[kFramesInFlight] = {};  // the slot's last frame drew the 3D (its counts are fresh)
    uint64_t documentGeneration = 0;           // increases with every adopted document
    // Document::objectsRevision and editedCageRevision the renderer last started from.
    uint64_t syncedObjectsRevision = 0, syncedEditedCageRevision = 0;
    std::optional<GpuTimer> timers[kFramesInFlight];
    bool timerUsed[kFramesInFlight] = {};
    uint64_t timerFrame[kFramesInFlight] = {};

    std::unique_ptr<Document> doc;  // never null once started (an empty cage at worst)
    DocumentLoader loader;
    BackgroundJob job;  // File > Export and Bake, off the UI thread
    PickCache picking;
    std::string recoveryDir;
    std::chrono::steady_clock::time_point lastAutosave;
    uint64_t autosavedPositionRevision = 0, autosavedPlanRevision = 0, autosavedDisplacementRevision = 0;
    bool autosavedOnce = false;
    // Writes the autosave off the UI thread (formatting and writing a 100k-face scene took 0.7 s
    // there): it holds its own copy of the scene. Whatever removes or writes the recovery files
    // waits for it first (finishAutosave).
    BackgroundWork<std::string> autosaver;

    ViewCamera sharedCamera;
    std::vector<ViewportState> viewports{ViewportState{}};
    uint32_t activeViewport = 0;
    Tessellation tessellation;       // display settings (saved into the scene)
    DisplaySettings display;         // shading, grid, up axis (always set once a document is adopted)
    bool frameAfterLayout = false;   // Ctrl+1/2/4: frame the model in the new viewports once they are laid out
    std::string plansPath = "auto";  // the plans scheme's path option (auto: the fastest here)
    Drag drag;
    std::optional<ExtrudeSession> extrude;  // the interactive extrude in progress (extrude_tool.h)
    ToolSettings tools;
    PlaybackClock playback;  // the animation's clock while Document::playing
    EditorMode mode = EditorMode::Edit;
    ObjectPickCache objectPicking;
    UiState ui;
    std::vector<KeyPress> keyPresses;  // since the last frame, from GLFW or automation
    ClickPairing leftPresses;      // from GLFW (viewport_input.h)
    bool leftDoubleClick = false;  // since the last frame

    FrameStats stats;
    // The frame that showed the last edit (the one it was applied in): its CPU time, which holds
    // the plan engine's work and every viewport's update, and the interval until the next frame.
    struct EditFrame {
        uint64_t frame = ~0ull;
        double cpuMs = 0.0, intervalMs = -1.0;  // interval < 0 until the next frame starts
        double syncMs = 0.0;                    // scheme updates in it (SceneRenderer::lastSyncMs)
    } lastEditFrame;
    uint64_t frame = 0;  // frames presented
    std::chrono::steady_clock::time_point lastFrameStart;
    std::chrono::steady_clock::time_point cameraMovedAt;  // the last orbit, pan or zoom step
    std::unique_ptr<Automation> automation;
    std::string pendingScreenshot;  // read back the next frame into this PNG
    bool running = true;
    int exitCode = 0;
};

// Used by the panels, the input handler and the automation hook alike.
void runAction(EditorApp& app, std::string_view id);
ViewCamera& cameraOf(EditorApp& app, uint32_t viewport);
// Progressive refinement: a camera step (orbit, pan, zoom, wheel) notes the time; while steps
// keep coming and full frames are slow, frames are coarse (see navigating() in editor_app.cpp).
void noteCameraMoved(EditorApp& app);
void setViewportCount(EditorApp& app, uint32_t count);
void requestOpen(EditorApp& app, const std::string& path);
void requestQuit(EditorApp& app);
bool saveTo(EditorApp& app, const std::string& path);  // false: failed (the error popup says why)
bool exportTo(EditorApp& app, const std::string& path);  // File > Export with ui.exportOptions: starts the job
bool bakeTo(EditorApp& app, const std::string& path);    // File > Bake with ui.bakeOptions: starts the job
void adoptFinishedJob(EditorApp& app);                   // shows a finished job's outcome
void finishAutosave(EditorApp& app);  // waits for an autosave being written (before the recovery files change)
// A fault the editor cannot continue after (a lost Vulkan device): writes unsaved changes to
// the recovery directory at once, prints the message and what happened to them, and stops
// with exit status 1.
void stopOnFatalError(EditorApp& app, const std::string& message);
void continuePending(EditorApp& app);
void restoreRecovery(EditorApp& app);
void discardRecovery(EditorApp& app);
// Applies an edit and reports a failure in the UI; returns whether it was applied.
bool edit(EditorApp& app, const Edit& edit);
void showError(EditorApp& app, const std::string& message);
// Bounds of the selection (or of the model when nothing is selected).
Bounds selectionBounds(const EditorApp& app);
void frameSelection(EditorApp& app, uint32_t viewport, bool wholeModel);
UpAxis upAxisOf(const EditorApp& app);
// A new up axis: every camera orbits about it from a 3/4 view that frames the model.
void setUpAxis(EditorApp& app, UpAxis up);

}  // namespace qp::editor
