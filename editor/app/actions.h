// Actions: every command a menu item, a shortcut or the automation hook can run, with its
// keys, label and help text in one table, so the help panel, the menus and the key handler
// cannot disagree.
#pragma once

#include <span>
#include <string_view>

namespace qp::editor {

struct KeyChord {
    int key = 0;  // GLFW key code; 0: no shortcut
    bool ctrl = false, shift = false, alt = false;
};

struct ActionInfo {
    const char* id;        // "file.save"; automation: `action file.save`
    const char* label;     // menu text
    const char* shortcut;  // as shown to the user; "" when none
    KeyChord chord;
    const char* help;      // tooltip and help panel text
    KeyChord alternate{};  // a second binding (Ctrl+Y for redo, F9 for vertex mode, ...)
};

std::span<const ActionInfo> actions();
const ActionInfo* findAction(std::string_view id);

// Mouse gestures in a viewport, for the help panel.
struct MouseBinding {
    const char* gesture;
    const char* effect;
};
std::span<const MouseBinding> mouseBindings();

}  // namespace qp::editor
