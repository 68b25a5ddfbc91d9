// Mouse and keyboard in the viewports, read from Dear ImGui's input state (which the GLFW
// backend fills from real events and the automation hook from synthetic ones), so both drive
// the same code. Navigation follows Maya and Blender; see actions.h for the bindings.
#pragma once

namespace qp::editor {

struct EditorApp;

// Camera drags, wheel zoom, click to select, drag a selected vertex to move the selection.
// Ignores the mouse while ImGui wants it (over a panel) unless a drag is already under way.
void handleViewportInput(EditorApp& app);

// Runs the actions whose shortcuts were pressed since the last frame (EditorApp::keyPresses),
// unless a text field has the keyboard or a dialog is open.
void handleShortcuts(EditorApp& app);

}  // namespace qp::editor
