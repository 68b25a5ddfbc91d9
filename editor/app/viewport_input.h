// Mouse and keyboard in the viewports, read from Dear ImGui's input state (which the GLFW
// backend fills from real events and the automation hook from synthetic ones), so both drive
// the same code. Navigation follows Maya and Blender; see actions.cpp for the bindings.
#pragma once

#include <cstdint>
#include <optional>

#include <glm/vec2.hpp>

#include "gizmo.h"

namespace qp::editor {

struct EditorApp;

// Camera drags, wheel zoom, clicks and boxes that select, drags that move the selection, the
// transform handle, the loop tool. Ignores the mouse while ImGui wants it (over a panel)
// unless a drag is already under way.
void handleViewportInput(EditorApp& app);

// The mouse in framebuffer pixels, and the viewport under a point (-1: none).
glm::vec2 cursorInFramebuffer();
int viewportAt(const EditorApp& app, glm::vec2 p);

// Runs the actions whose shortcuts were pressed since the last frame (EditorApp::keyPresses),
// unless a text field has the keyboard or a dialog is open. Esc first cancels a drag or the
// loop tool.
void handleShortcuts(EditorApp& app);

// Left presses as GLFW delivers them, paired into double clicks by the events' own times, so
// that a double click still counts when both presses reach one slow frame (ImGui 1.86 keeps
// one mouse state per frame and merges them into a single click). Thresholds are ImGui's.
struct ClickPairing {
    double lastTime = -1.0;  // the unpaired press, or < 0
    glm::dvec2 lastAt{0.0};
};
// A press at `time` seconds, window position `at`: true when it completes a double click (a
// third press then starts a new pair).
bool pairPress(ClickPairing& pairing, double time, glm::dvec2 at, double maxInterval, double maxDistance);

// Ends a drag in progress; a cancelled move or transform puts the selection back.
void cancelDrag(EditorApp& app);

// The transform handle in a viewport (viewport pixels), when the tool shows one and something
// is selected.
std::optional<GizmoShape> gizmoIn(const EditorApp& app, uint32_t viewport);

}  // namespace qp::editor
