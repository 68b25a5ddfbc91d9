#include "actions.h"

#include <algorithm>

#include <GLFW/glfw3.h>

namespace qp::editor {

namespace {

const ActionInfo kActions[] = {
    {"file.open", "Open...", "Ctrl+O", {GLFW_KEY_O, true}, "Open a scene (.json) or a cage (.obj)"},
    {"file.save", "Save", "Ctrl+S", {GLFW_KEY_S, true}, "Save to the current file (asks for a name when untitled)"},
    {"file.save_as", "Save As...", "Ctrl+Shift+S", {GLFW_KEY_S, true, true}, "Save to a new file (.json scene or .obj cage)"},
    {"file.quit", "Quit", "Ctrl+Q", {GLFW_KEY_Q, true}, "Close the editor (asks before losing unsaved changes)"},
    {"edit.undo", "Undo", "Ctrl+Z", {GLFW_KEY_Z, true}, "Undo the last edit (not available yet: comes with the editing core)"},
    {"edit.redo", "Redo", "Ctrl+Shift+Z", {GLFW_KEY_Z, true, true}, "Redo (not available yet: comes with the editing core)"},
    {"select.none", "Deselect all", "Esc", {GLFW_KEY_ESCAPE}, "Clear the selection"},
    {"view.frame", "Frame selection", "F", {GLFW_KEY_F}, "Frame the selection, or the whole model when nothing is selected"},
    {"view.frame_all", "Frame all", "Home", {GLFW_KEY_HOME}, "Frame the whole model"},
    {"view.front", "Front", "Numpad 1", {GLFW_KEY_KP_1}, "Look at the front (from +Z)"},
    {"view.back", "Back", "Ctrl+Numpad 1", {GLFW_KEY_KP_1, true}, "Look at the back (from -Z)"},
    {"view.right", "Right", "Numpad 3", {GLFW_KEY_KP_3}, "Look at the right side (from +X)"},
    {"view.left", "Left", "Ctrl+Numpad 3", {GLFW_KEY_KP_3, true}, "Look at the left side (from -X)"},
    {"view.top", "Top", "Numpad 7", {GLFW_KEY_KP_7}, "Look down from above (from +Y)"},
    {"view.bottom", "Bottom", "Ctrl+Numpad 7", {GLFW_KEY_KP_7, true}, "Look up from below (from -Y)"},
    {"view.projection", "Perspective / orthographic", "Numpad 5", {GLFW_KEY_KP_5}, "Toggle the projection of the active viewport"},
    {"layout.one", "One viewport", "Ctrl+1", {GLFW_KEY_1, true}, "Show one viewport"},
    {"layout.two", "Two viewports", "Ctrl+2", {GLFW_KEY_2, true}, "Show two viewports side by side"},
    {"layout.four", "Four viewports", "Ctrl+4", {GLFW_KEY_4, true}, "Show four viewports in a 2x2 grid"},
    {"display.cage", "Cage overlay", "C", {GLFW_KEY_C}, "Show or hide the cage (creases coloured yellow to red by sharpness)"},
    {"display.wireframe", "Tessellation wireframe", "W", {GLFW_KEY_W}, "Show or hide the tessellation wireframe"},
    {"help.toggle", "Help", "F1", {GLFW_KEY_F1}, "Show or hide this help"},
};

const MouseBinding kMouse[] = {
    {"Left click", "Select the vertex nearest the cursor, else the edge; empty space clears"},
    {"Shift + left click", "Add or remove a vertex from the selection"},
    {"Left drag on a selected vertex", "Move the selected vertices in the view plane"},
    {"Alt + left drag, or middle drag", "Orbit"},
    {"Alt + middle drag, or Shift + middle drag", "Pan"},
    {"Alt + right drag, Ctrl + middle drag, or wheel", "Zoom (dolly)"},
};

}  // namespace

std::span<const ActionInfo> actions() { return kActions; }

const ActionInfo* findAction(std::string_view id) {
    auto it = std::find_if(std::begin(kActions), std::end(kActions), [&](const ActionInfo& a) { return id == a.id; });
    return it == std::end(kActions) ? nullptr : &*it;
}

std::span<const MouseBinding> mouseBindings() { return kMouse; }

}  // namespace qp::editor
