// Automation: a script of commands replayed into the running editor, one step per frame, for
// tests and measurements (`quadplan edit FILE --automation SCRIPT`, "-" reads stdin).
//
// Commands drive the code that real use drives: input commands set Dear ImGui's mouse and
// keyboard state (where the GLFW backend puts real events), `click-button` presses a widget
// through its own handler, `action` runs the actions table, edits go through applyEdit. One
// command per line, `#` starts a comment; indices are 0-based; coordinates are window pixels.
// The list with arguments is in docs/editor.md and kCommands in automation.cpp. A failing
// command stops the editor with exit status 3 and a message naming the line.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "automation_script.h"
#include "mesh/result.h"

namespace qp::editor {

struct EditorApp;

// parseAutomation (automation_script.h) with the editor's actions, colour modes and draw paths.
Result<std::vector<AutomationCommand>> parseAutomation(std::string_view text, const std::string& source);

class Automation {
public:
    explicit Automation(std::vector<AutomationCommand> commands) : commands_(std::move(commands)) {}

    // Runs commands until one needs frames to pass (waits, input, screenshots).
    void beforeFrame(EditorApp& app);
    // Puts the synthetic mouse and keyboard state into ImGui's IO (after the GLFW backend).
    void applySyntheticInput();
    void screenshotWritten(const std::string& path, const Status& status);

    bool failed() const { return failed_; }
    bool finished() const { return next_ >= commands_.size() && !busy(); }

private:
    struct Synthetic {
        bool active = false;
        float x = 0, y = 0, wheel = 0;
        bool buttons[3] = {};
        std::vector<int> keysDown, keysTouched;
        int framesSinceRelease = 0;
    };
    struct Measurement {
        int framesLeft = 0, settleFrames = 0;
        std::string mode;  // "": as it comes; "drag": move the selection every frame; "orbit": turn the camera
        std::string path;
        uint64_t firstFrame = 0;
        bool dragStarted = false;  // "drag": later steps extend the first one's history entry
    };

    // `time-frame FILE LABEL`: the frame the next command runs in, appended to FILE as a JSON
    // line (its CPU time, the interval to the frame after it) once that frame has passed.
    struct FrameTiming {
        std::string label, path;
        uint64_t frame = 0;
    };
    void writeFrameTimings(EditorApp& app);

    bool busy() const;
    bool execute(EditorApp& app, const AutomationCommand& command);  // false: yields for a frame
    void fail(const AutomationCommand& command, const std::string& message);
    void dumpState(EditorApp& app, const AutomationCommand& command);
    void measureStep(EditorApp& app);

    std::vector<AutomationCommand> commands_;
    size_t next_ = 0;
    bool failed_ = false;
    int waitFrames_ = 0;
    bool waitIdle_ = false;
    std::string waitFile_;
    std::chrono::steady_clock::time_point waitFileDeadline_;
    std::optional<std::chrono::steady_clock::time_point> waitUntil_;  // `wait-seconds`
    std::string pressLabel_;
    int pressFramesLeft_ = 0;
    int pressLine_ = 0;
    std::string screenshot_;
    int keyUpAfterFrame_ = 0;  // `key NAME`: release on the next frame
    Synthetic synthetic_;
    Measurement measurement_;
    std::vector<FrameTiming> frameTimings_;
};

Result<std::unique_ptr<Automation>> loadAutomation(const std::string& path);

}  // namespace qp::editor
