// Actions: every command a menu item, a shortcut or the automation hook can run, with its
// keys, label and help text in one table, so the help panel, the menus and the key handler
// cannot disagree.
#pragma once

#include <cstdint>
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

// Where an action works: edit mode's act on the edited cage ("select.", "mesh.", "crease.",
// "sculpt." and the sculpt tool), object mode's on whole objects ("object."), the rest in both.
// One key may serve one action of each mode (H hides faces in edit mode, objects in object mode).
// The sculpt tool's ("brush.") work in edit mode too; their keys act only while the sculpt tool
// is active, where they win over an edit-mode action on the same key (M masks, not merges).
enum class ActionScope : uint8_t { Both, EditMode, ObjectMode, SculptTool };
ActionScope scopeOf(std::string_view id);

// Mouse gestures in a viewport, for the help panel.
struct MouseBinding {
    const char* gesture;
    const char* effect;
};
std::span<const MouseBinding> mouseBindings();

}  // namespace qp::editor
