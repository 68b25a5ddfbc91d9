// Playing the document's animation in the editor (issue 22): the wall clock says which frame is
// due at the timeline's rate, and that frame is shown (document_animation.h goToFrame: every
// animated cage moves, nothing is re-planned). A slow editor skips frames rather than slowing
// the animation down, so time stays true; playback loops at the end or stops there. The timeline
// strip, the shortcuts (Space, Left/Right, Shift+Left/Right, Up/Down, I, Alt+I) and automation's
// set-frame / play / pause / insert-key all come here.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "animation/cage_animation.h"

namespace qp::editor {

struct EditorApp;

struct PlaybackClock {
    std::chrono::steady_clock::time_point start;  // when `startFrame` was shown
    double startFrame = 1.0;
    std::deque<std::chrono::steady_clock::time_point> shown;  // frames shown in the last second
    double fpsAchieved = 0.0;  // distinct frames shown per second while playing (kept after a pause)
};

// Shows `frame` (any number: between keys the tracks interpolate); the status line says why not.
bool showFrameAt(EditorApp& app, double frame);
// Plays from the current frame (from the first when at or past the last); pauses.
void startPlayback(EditorApp& app);
void pausePlayback(EditorApp& app);
void togglePlayback(EditorApp& app);
// One frame back or forward (wrapping within the timeline when looping); the first or last
// frame; the previous or next keyed frame of the edited cage and the objects' transforms.
void stepFrame(EditorApp& app, int delta);
void jumpToEnd(EditorApp& app, bool last);
void jumpToKey(EditorApp& app, int direction);
// I and Alt+I: edit mode keys the selected vertices (all when none is selected) or deletes the
// cage's keys at the current frame; object mode does the same for the selected object's transform.
bool insertKeyTool(EditorApp& app);
bool deleteKeysTool(EditorApp& app);

// The interpolation of the object the timeline follows (keyMarks), none without one; setting it
// is one history entry (document_animation.h setInterpolation) and the frame is shown again.
// The timeline's combo, the Animation menu's toggle and automation's set-interpolation.
std::optional<Interpolation> timelineInterpolation(const EditorApp& app);
bool setInterpolationTool(EditorApp& app, Interpolation interpolation);
bool toggleInterpolationTool(EditorApp& app);

// The frames the timeline marks: the keys (of any vertex, or of the transform) of the object
// edit mode is on, or in object mode of the selected object.
std::vector<int32_t> keyMarks(const EditorApp& app);

// Each frame before the interface: shows the frame the clock says, when it changed.
void advancePlayback(EditorApp& app);
// Seconds until the next frame is due (the idle wait's bound); negative when not playing.
double secondsToNextFrame(const EditorApp& app);

}  // namespace qp::editor
