// The interactive editor: a GLFW window, the Vulkan swapchain, Dear ImGui and the scene
// renderer around one Document. `runEditorApp` is what `quadplan` and `quadplan edit` call.
//
// Per frame (editor_app.cpp): events -> adopt a finished background load -> automation step ->
// ImGui frame (viewport input, shortcuts, panels) -> autosave -> draw (3D passes, then ImGui in
// its render pass) -> present. Every change to the cage goes through applyEdit (document.h).
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "document.h"
#include "document_loader.h"
#include "draw_path.h"
#include "frame_stats.h"
#include "gpu_timer.h"
#include "imgui_layer.h"
#include "pipeline_cache.h"
#include "scene_cache.h"
#include "scene_renderer.h"
#include "swapchain_target.h"
#include "view_camera.h"

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
    uint32_t width = 1280, height = 800;
    uint32_t planDepth = 6;
};

int runEditorApp(const LaunchOptions& options);

struct ViewportState {
    std::string scheme = "plans";
    std::string colorBy = "shading";
    bool linked = true;
    ViewCamera camera;  // used when not linked
    // This frame:
    VkRect2D rect{};    // framebuffer pixels
    glm::mat4 viewProjection{1.0f};
    RenderCamera renderCamera;
};

enum class DragKind { None, Orbit, Pan, Zoom, MoveSelection };

struct Drag {
    DragKind kind = DragKind::None;
    uint32_t viewport = 0;
    int button = 0;
    glm::vec2 start{0.0f};               // cursor at the start, framebuffer pixels
    glm::vec3 anchor{0.0f};              // MoveSelection: the grabbed vertex
    std::vector<uint32_t> vertices;      // MoveSelection: what moves, and from where
    std::vector<glm::vec3> startPositions;
    glm::mat4 viewProjection{1.0f};      // MoveSelection: the view at the start
    VkRect2D rect{};
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

struct UiState {
    bool showHelp = false;
    std::string openPath, saveAsPath;
    std::string requestPopup;  // opened at the top level of the next UI pass
    PendingAction pending;
    bool continuePendingAfterSave = false;
    std::string errorMessage;  // shown in the "Error" popup
    std::string status;        // last message, shown in the side panel
    std::optional<RecoveryOffer> recovery;
    float sharpness = 1.0f;    // the crease tool's value
    std::string title;         // window title last set
    // Automation's `click-button` and the widget rectangles for tests (window coordinates).
    std::string pressLabel;
    bool pressConsumed = false;
    std::vector<std::pair<std::string, std::array<float, 4>>> widgets;
    std::vector<std::string> openPopups;  // dialogs shown in the last frame
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
    SceneRenderer renderer;
    SceneCache sceneCache;
    bool sceneRecorded[kFramesInFlight] = {};  // the slot's last frame drew the 3D (its counts are fresh)
    uint64_t documentGeneration = 0;           // increases with every adopted document
    std::optional<GpuTimer> timers[kFramesInFlight];
    bool timerUsed[kFramesInFlight] = {};
    uint64_t timerFrame[kFramesInFlight] = {};

    std::unique_ptr<Document> doc;  // never null once started (an empty cage at worst)
    DocumentLoader loader;
    std::string recoveryDir;
    std::chrono::steady_clock::time_point lastAutosave;
    uint64_t autosavedPositionRevision = 0, autosavedPlanRevision = 0;
    bool autosavedOnce = false;

    ViewCamera sharedCamera;
    std::vector<ViewportState> viewports{ViewportState{}};
    uint32_t activeViewport = 0;
    Tessellation tessellation;       // display settings (saved into the scene)
    DrawPath requestedPath = DrawPath::Auto;
    DrawPath drawPath = DrawPath::Grid;  // resolved for this device
    uint32_t gridFactor = 8;         // used this frame
    float averageEdgeLength = 1.0f;  // for the adaptive grid factor
    uint64_t edgeLengthRevision = ~0ull;
    Drag drag;
    UiState ui;
    std::vector<KeyPress> keyPresses;  // since the last frame, from GLFW or automation

    FrameStats stats;
    uint64_t frame = 0;  // frames presented
    std::chrono::steady_clock::time_point lastFrameStart;
    std::unique_ptr<Automation> automation;
    std::string pendingScreenshot;  // read back the next frame into this PNG
    bool running = true;
    int exitCode = 0;
};

// Used by the panels, the input handler and the automation hook alike.
void runAction(EditorApp& app, std::string_view id);
ViewCamera& cameraOf(EditorApp& app, uint32_t viewport);
void setViewportCount(EditorApp& app, uint32_t count);
void requestOpen(EditorApp& app, const std::string& path);
void requestQuit(EditorApp& app);
bool saveTo(EditorApp& app, const std::string& path);  // false: failed (the error popup says why)
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

}  // namespace qp::editor
